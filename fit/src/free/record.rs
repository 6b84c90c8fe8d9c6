//! The record of a free-amplitude fit: each reported parameter
//! ([`Parameter`]: grid and refined value, box, flags, intervals) and the
//! correlations of the Jacobian's covariance.

use super::driver::Analysed;
use super::intervals::JacobianCovariance;
use super::layout::{domain_of, Layout};
use super::problem::{Point, Problem};
use crate::analysis::Uncertainty;
use crate::covariance::Covariance;
use crate::edges::Edge;
use crate::profile::Interval;
use crate::report::{Parameter, Source};

/// The covariance of the parameters that have one (the amplitude left out).
pub(super) fn correlations(layout: &Layout, c: &JacobianCovariance) -> Option<Covariance> {
    let kept: Vec<usize> = (0..layout.names.len())
        .filter(|&i| c.matrix[i][i].is_some())
        .collect();
    if kept.len() < 2 {
        return None;
    }
    Some(Covariance {
        names: kept.iter().map(|&i| layout.names[i]).collect(),
        matrix: kept
            .iter()
            .map(|&i| {
                kept.iter()
                    .map(|&j| c.matrix[i][j].unwrap_or(0.0))
                    .collect()
            })
            .collect(),
    })
}

/// The reported parameters.
pub(super) fn parameters(
    layout: &Layout,
    problem: &Problem,
    grid: &[f64],
    analysed: Option<&Analysed>,
    at: &Point,
    uncertainty: Option<Uncertainty>,
) -> Vec<Parameter> {
    layout
        .coordinates
        .iter()
        .enumerate()
        .map(|(i, &c)| {
            let (lo, hi) = c.bounds(problem);
            let (dlo, dhi) = domain_of(layout, i);
            let value = c.value(at, problem);
            let mut p = Parameter::new(layout.names[i], grid[i]);
            p.bounds = Some((lo, hi));
            if analysed.is_some() {
                p.refined = Some(value);
            }
            if value <= lo || value >= hi {
                p.flags.push(Edge::RangeEdge);
            }
            if value <= dlo || value >= dhi {
                p.flags.push(Edge::DomainBound);
            }
            let Some(analysed) = analysed else {
                return p;
            };
            let sd = analysed.covariance.as_ref().and_then(|cov| cov.sd(i));
            if matches!(uncertainty, Some(Uncertainty::Jacobian | Uncertainty::Both)) {
                p.sd = sd;
            }
            if let Some(profile) = &analysed.profile {
                let [below, above] = profile[i];
                let closed = |(end, at_face): (f64, bool), face: f64| {
                    if end.is_nan() {
                        (face, true)
                    } else {
                        (end, at_face)
                    }
                };
                let interval = |level: usize| {
                    let (l, l_face) = closed(below[level], lo);
                    let (h, h_face) = closed(above[level], hi);
                    Interval {
                        lo: l.clamp(lo, value),
                        hi: h.clamp(value, hi),
                        open_below: l_face && lo > dlo,
                        open_above: h_face && hi < dhi,
                    }
                };
                p.set_intervals([interval(0), interval(1)], Source::Profile);
                if below[1].1 && above[1].1 && hi > lo {
                    p.flags.push(Edge::NotIdentified);
                }
            } else if let (Some(sd), Some(levels)) = (sd, analysed.levels) {
                let around = |level: usize| {
                    let d = (levels.heights[level] / levels.s2).sqrt() * sd;
                    Interval {
                        lo: (value - d).max(lo),
                        hi: (value + d).min(hi),
                        open_below: false,
                        open_above: false,
                    }
                };
                p.set_intervals([around(0), around(1)], Source::Jacobian);
            }
            p
        })
        .collect()
}
