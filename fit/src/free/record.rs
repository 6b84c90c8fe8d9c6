//! The record of a free-amplitude fit: each reported parameter
//! ([`Parameter`]: grid and refined value, box, flags, intervals) and the
//! correlations of the Jacobian's covariance.

use super::bootstrap::Bootstrapped;
use super::driver::Analysed;
use super::intervals::JacobianCovariance;
use super::layout::{domain_of, Layout};
use super::problem::{Point, Problem};
use crate::analysis::Uncertainty;
use crate::covariance::Covariance;
use crate::edges::{Edge, MISFIT_SENSITIVE};
use crate::profile::Interval;
use crate::report::{Alternative, Parameter, Source};

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
    bootstrap: Option<&Bootstrapped>,
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
            let covariance = analysed.covariance.as_ref();
            let sd = covariance.and_then(|cov| cov.sd(i));
            if uncertainty.is_some_and(Uncertainty::jacobian) {
                p.sd = sd;
            }
            // Flags of what the intervals found, after the open ends'.
            let mut found = Vec::new();
            // The model-based intervals: the profile's, and the Jacobian's.
            let profile = analysed.profile.as_ref().map(|profile| {
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
                if below[1].1 && above[1].1 && hi > lo {
                    found.push(Edge::NotIdentified);
                }
                if below[0].1 && above[0].1 && hi > lo {
                    found.push(Edge::NotDetermined);
                }
                [interval(0), interval(1)]
            });
            let jacobian = sd.zip(analysed.levels).map(|(sd, levels)| {
                let around = |level: usize| {
                    let d = (levels.heights[level] / levels.s2).sqrt() * sd;
                    Interval {
                        lo: (value - d).max(lo),
                        hi: (value + d).min(hi),
                        open_below: false,
                        open_above: false,
                    }
                };
                [around(0), around(1)]
            });
            // The robust interval: the profile's (else the Jacobian's), its
            // distances from the estimate scaled by the sandwich to
            // model-based sd ratio (docs/estimation.md).
            let ratio = covariance
                .and_then(|cov| cov.misfit_ratio(i))
                .filter(|_| !analysed.rounding);
            p.misfit_ratio = ratio;
            if ratio.is_some_and(|r| !(1.0 / MISFIT_SENSITIVE..=MISFIT_SENSITIVE).contains(&r)) {
                found.push(Edge::MisfitSensitive);
            }
            let robust = ratio.zip(profile.or(jacobian)).map(|(r, base)| {
                base.map(|i| {
                    let down = value - r * (value - i.lo);
                    let up = value + r * (i.hi - value);
                    Interval {
                        lo: down.clamp(lo, value),
                        hi: up.clamp(value, hi),
                        open_below: i.open_below || (down < lo && lo > dlo),
                        open_above: i.open_above || (up > hi && hi < dhi),
                    }
                })
            });
            // The headline: the robust interval by default (`both`), the
            // model-based one asked for otherwise; the others kept.
            let resampled = bootstrap.map(|b| b.intervals[i]);
            p.bootstrap_error = resampled.map(|b| b.1);
            let computed = [
                (Source::Bootstrap, resampled.map(|b| b.0)),
                (Source::Robust, robust),
                (Source::Profile, profile),
                (Source::Jacobian, jacobian),
            ];
            let preference: &[Source] = match uncertainty {
                Some(Uncertainty::Bootstrap) => &[
                    Source::Bootstrap,
                    Source::Robust,
                    Source::Profile,
                    Source::Jacobian,
                ],
                Some(Uncertainty::Both) => &[Source::Robust, Source::Profile, Source::Jacobian],
                Some(Uncertainty::Profile) => &[Source::Profile, Source::Jacobian],
                Some(Uncertainty::Jacobian) => &[Source::Jacobian],
                Some(Uncertainty::Off) | None => &[],
            };
            let headline = preference
                .iter()
                .find_map(|s| computed.iter().find(|(c, i)| c == s && i.is_some()))
                .and_then(|&(source, i)| i.map(|i| (source, i)));
            if let Some((source, intervals)) = headline {
                p.set_intervals(intervals, source);
                p.alternatives = computed
                    .iter()
                    .filter(|(s, _)| *s != source)
                    .filter_map(|&(s, i)| {
                        i.map(|[interval68, interval95]| Alternative {
                            source: s,
                            interval68,
                            interval95,
                        })
                    })
                    .collect();
            }
            p.flags.extend(found);
            p
        })
        .collect()
}
