//! The pairs (case-resampling) bootstrap of a free-amplitude fit
//! (docs/estimation.md, "When the model does not fit"): `B` resamples of
//! the measurements with replacement, each refitted from the full fit's
//! minimum, and each parameter's percentile intervals with their own Monte
//! Carlo error. Like the sandwich it assumes nothing of the residuals but
//! their independence; unlike it, it sees the estimate's nonlinearity.
//!
//! A resample with counts `c_k` (multinomial, `Σ c_k = K`) is the same
//! objective as the duplicated rows: the weights become `c_k w_k`, so no
//! basis is rebuilt. Resample `b` draws from its own generator seeded by
//! `(seed, b)`, and the resamples run in parallel, collected in order: the
//! intervals do not depend on the thread count.

use super::Solution;
use crate::free::model::FreeModel;
use crate::free::problem::Problem;
use crate::free::refine::{minimise, SCREENING};
use crate::profile::Interval;
use crate::synthetic::Noise;
use rayon::prelude::*;

/// The two-sided levels' lower quantiles (68.27%, 95%).
const LOWER: [f64; 2] = [0.158_655_253_931_457, 0.025];

/// Each reported parameter's bootstrap intervals (68.27%, 95%) and the
/// largest Monte Carlo standard deviation of their four ends.
#[derive(Debug, Clone, PartialEq)]
pub struct Bootstrapped {
    /// Per reported parameter, in the layout's order.
    pub intervals: Vec<([Interval; 2], f64)>,
}

/// The generator of resample `b` of a bootstrap seeded `seed`.
fn generator(seed: u64, b: usize) -> Noise {
    Noise::new(seed ^ (b as u64).wrapping_mul(0xD605_BBB5_8C8A_BBAD))
}

/// Each of `k` measurements' count in resample `b` of a bootstrap seeded
/// `seed` (multinomial, the counts sum to `k`).
pub(crate) fn resample_counts(k: usize, seed: u64, b: usize) -> Vec<f64> {
    let mut rng = generator(seed, b);
    let mut counts = vec![0.0; k];
    for _ in 0..k {
        let i = ((rng.uniform() * k as f64) as usize).min(k - 1);
        counts[i] += 1.0;
    }
    counts
}

/// `problem` with measurement `k`'s weight times `counts[k]` (a resample's
/// count, or 0 for a measurement held out of a fold).
pub fn reweighted<M>(problem: &Problem<M>, counts: &[f64]) -> Problem<M> {
    let mut out = problem.clone();
    for (i, &c) in counts.iter().enumerate() {
        out.weight[i] *= c;
        out.root_weight[i] *= c.sqrt();
        out.weighted_data[i] *= c;
    }
    out.dd = out
        .weighted_data
        .iter()
        .zip(&out.data)
        .map(|(w, d)| w * d)
        .sum();
    out
}

/// The `q` quantile of sorted `values` (linear between order statistics).
fn quantile(sorted: &[f64], q: f64) -> f64 {
    let h = q * (sorted.len() - 1) as f64;
    let (i, f) = (h.floor() as usize, h - h.floor());
    let j = (i + 1).min(sorted.len() - 1);
    sorted[i] + f * (sorted[j] - sorted[i])
}

/// The Monte Carlo standard deviation of the `q` quantile of sorted
/// `values`: half the spread of the order statistics one binomial standard
/// deviation `√(B q (1 − q))` either side of it.
fn quantile_error(sorted: &[f64], q: f64) -> f64 {
    let b = sorted.len() as f64;
    let spread = (b * q * (1.0 - q)).sqrt() / b;
    0.5 * (quantile(sorted, (q + spread).min(1.0)) - quantile(sorted, (q - spread).max(0.0)))
}

/// The bootstrap of `solution`'s problem around its minimum: `resamples`
/// refits seeded by `seed` (a face of the box that is not a bound of the
/// parameter's domain leaves an end open). `None` with fewer than two
/// resamples, or without degrees of freedom (no more measurements than
/// fitted parameters: every resample is fitted exactly, and its intervals
/// would be of zero width whatever the noise; the other intervals are
/// absent there too).
pub fn bootstrap<M: FreeModel>(
    solution: &Solution<'_, M>,
    (resamples, seed): (usize, u64),
) -> Option<Bootstrapped> {
    let problem = solution.problem;
    if resamples < 2 || problem.data.len() <= problem.parameter_count() {
        return None;
    }
    let Solution {
        layout, minimum, ..
    } = solution;
    let free = problem.all_free();
    let values: Vec<Vec<f64>> = (0..resamples)
        .into_par_iter()
        .map(|b| {
            let p = reweighted(problem, &resample_counts(problem.data.len(), seed, b));
            let point = minimise(&p, &minimum.theta, &free, p.beta, SCREENING).point;
            layout
                .coordinates
                .iter()
                .map(|c| c.value(&point, &p))
                .collect()
        })
        .collect();
    let intervals = (0..layout.coordinates.len())
        .map(|i| {
            let mut sorted: Vec<f64> = values.iter().map(|v| v[i]).collect();
            sorted.sort_by(f64::total_cmp);
            percentile_intervals(
                &sorted,
                solution.value(i),
                solution.bounds(i),
                solution.domain(i),
            )
        })
        .collect();
    Some(Bootstrapped { intervals })
}

/// The percentile intervals (68.27%, 95%) of one parameter's `sorted`
/// resampled values around its estimate `value`, in its box, and the
/// largest Monte Carlo standard deviation of their four ends.
pub(crate) fn percentile_intervals(
    sorted: &[f64],
    value: f64,
    (lo, hi): (f64, f64),
    (dlo, dhi): (f64, f64),
) -> ([Interval; 2], f64) {
    let mut error = 0.0f64;
    let levels = LOWER.map(|q| {
        let (a, b) = (quantile(sorted, q), quantile(sorted, 1.0 - q));
        error = error
            .max(quantile_error(sorted, q))
            .max(quantile_error(sorted, 1.0 - q));
        Interval {
            lo: a.min(value).max(lo),
            hi: b.max(value).min(hi),
            open_below: a <= lo && lo > dlo,
            open_above: b >= hi && hi < dhi,
        }
    });
    (levels, error)
}
