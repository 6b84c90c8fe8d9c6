//! The record of a free-amplitude fit: each reported parameter
//! ([`Parameter`]: grid and refined value, box, flags, intervals) from the
//! statistics of its [`Solution`], and the correlations of the Jacobian's
//! covariance.

use super::model::FreeModel;
use super::statistics::bootstrap::Bootstrapped;
use super::statistics::covariance::JacobianCovariance;
use super::statistics::intervals::Analysed;
use super::statistics::levels::Levels;
use super::statistics::Solution;
use crate::analysis::Uncertainty;
use crate::covariance::Covariance;
use crate::edges::{Edge, MISFIT_SENSITIVE};
use crate::model::Param;
use crate::profile::Interval;
use crate::report::{Alternative, Parameter, Source};

/// Both levels' intervals (68.27%, 95%).
type Pair = [Interval; 2];

/// The statistics a refined fit's record is made from.
pub struct Statistics<'a> {
    /// The intervals and covariance.
    pub analysed: &'a Analysed,
    /// The uncertainty asked for.
    pub uncertainty: Uncertainty,
    /// The bootstrap, when one ran.
    pub bootstrap: Option<&'a Bootstrapped>,
}

/// The covariance of the parameters that have one (the amplitude left out).
pub fn correlations(names: &[Param], c: &JacobianCovariance) -> Option<Covariance> {
    let kept: Vec<usize> = (0..names.len())
        .filter(|&i| c.matrix[i][i].is_some())
        .collect();
    if kept.len() < 2 {
        return None;
    }
    Some(Covariance {
        names: kept.iter().map(|&i| names[i]).collect(),
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

/// The reported parameters at `solution`'s minimum (the grid's best point
/// when the fit is not refined), with their grid values `grid`, and with
/// `statistics` when refined.
pub fn parameters<M: FreeModel>(
    solution: &Solution<'_, M>,
    grid: &[f64],
    statistics: Option<&Statistics<'_>>,
) -> Vec<Parameter> {
    (0..solution.layout.coordinates.len())
        .map(|i| {
            let mut p = placed(solution, i, grid[i], statistics.is_some());
            if let Some(statistics) = statistics {
                let value = solution.value(i);
                intervals(&mut p, solution, (i, value), statistics);
            }
            p
        })
        .collect()
}

/// Parameter `i` with its grid value, its value at the minimum when
/// `refined`, its box and the flags of where it lies.
fn placed<M: FreeModel>(
    solution: &Solution<'_, M>,
    i: usize,
    grid: f64,
    refined: bool,
) -> Parameter {
    let (lo, hi) = solution.bounds(i);
    let (dlo, dhi) = solution.domain(i);
    let value = solution.value(i);
    let mut p = Parameter::new(solution.layout.names[i], grid);
    p.bounds = Some((lo, hi));
    if refined {
        p.refined = Some(value);
    }
    if value <= lo || value >= hi {
        p.flags.push(Edge::RangeEdge);
    }
    if value <= dlo || value >= dhi {
        p.flags.push(Edge::DomainBound);
    }
    p
}

/// Parameter `i`'s intervals at `value`: every one computed, the headline
/// chosen by the uncertainty asked for, and the flags of what they found.
fn intervals<M: FreeModel>(
    p: &mut Parameter,
    solution: &Solution<'_, M>,
    (i, value): (usize, f64),
    statistics: &Statistics<'_>,
) {
    let analysed = statistics.analysed;
    let covariance = analysed.covariance.as_ref();
    let sd = covariance.and_then(|cov| cov.sd(i));
    if statistics.uncertainty.jacobian() {
        p.sd = sd;
    }
    // Flags of what the intervals found, after the open ends'.
    let mut found = Vec::new();
    let profile = analysed
        .profile
        .as_ref()
        .map(|profile| profile_intervals(solution, (i, value), profile[i], &mut found));
    let jacobian = sd
        .zip(analysed.levels)
        .map(|(sd, levels)| jacobian_intervals(solution.bounds(i), value, sd, levels));
    // The robust interval: the profile's (else the Jacobian's), its
    // distances from the estimate scaled by the sandwich to model-based sd
    // ratio (docs/estimation.md).
    let ratio = covariance
        .and_then(|cov| cov.misfit_ratio(i))
        .filter(|_| !analysed.rounding);
    p.misfit_ratio = ratio;
    if ratio.is_some_and(|r| !(1.0 / MISFIT_SENSITIVE..=MISFIT_SENSITIVE).contains(&r)) {
        found.push(Edge::MisfitSensitive);
    }
    let robust = ratio
        .zip(profile.or(jacobian))
        .map(|(r, base)| robust_intervals(solution, (i, value), r, base));
    let resampled = statistics.bootstrap.map(|b| b.intervals[i]);
    p.bootstrap_error = resampled.map(|b| b.1);
    let computed = [
        (Source::Bootstrap, resampled.map(|b| b.0)),
        (Source::Robust, robust),
        (Source::Profile, profile),
        (Source::Jacobian, jacobian),
    ];
    headline(p, statistics.uncertainty, &computed);
    p.flags.extend(found);
}

/// The profile's intervals of parameter `i` at `value` from its walks'
/// `[below, above]` ends (an unknown end closed at the face); the flags of
/// an interval that reaches both faces go to `found`.
fn profile_intervals<M: FreeModel>(
    solution: &Solution<'_, M>,
    (i, value): (usize, f64),
    [below, above]: [[(f64, bool); 2]; 2],
    found: &mut Vec<Edge>,
) -> Pair {
    let (lo, hi) = solution.bounds(i);
    let (dlo, dhi) = solution.domain(i);
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
}

/// The Jacobian's intervals `value ± √(Δ/s²) sd` in the box `(lo, hi)`.
fn jacobian_intervals((lo, hi): (f64, f64), value: f64, sd: f64, levels: Levels) -> Pair {
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
}

/// `base`'s distances from `value` scaled by the misfit ratio `r`, in
/// parameter `i`'s box (open where the scaled end passes a face that is
/// not a bound of its domain).
fn robust_intervals<M: FreeModel>(
    solution: &Solution<'_, M>,
    (i, value): (usize, f64),
    r: f64,
    base: Pair,
) -> Pair {
    let (lo, hi) = solution.bounds(i);
    let (dlo, dhi) = solution.domain(i);
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
}

/// The headline intervals of `p`: the robust ones by default (`both`),
/// the model-based ones asked for otherwise, the bootstrap's with
/// `bootstrap`; the others computed kept as alternatives.
fn headline(p: &mut Parameter, uncertainty: Uncertainty, computed: &[(Source, Option<Pair>)]) {
    let preference: &[Source] = match uncertainty {
        Uncertainty::Bootstrap => &[
            Source::Bootstrap,
            Source::Robust,
            Source::Profile,
            Source::Jacobian,
        ],
        Uncertainty::Both => &[Source::Robust, Source::Profile, Source::Jacobian],
        Uncertainty::Profile => &[Source::Profile, Source::Jacobian],
        Uncertainty::Jacobian => &[Source::Jacobian],
        Uncertainty::Off => &[],
    };
    let chosen = preference
        .iter()
        .find_map(|s| computed.iter().find(|(c, i)| c == s && i.is_some()))
        .and_then(|&(source, i)| i.map(|i| (source, i)));
    let Some((source, intervals)) = chosen else {
        return;
    };
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
