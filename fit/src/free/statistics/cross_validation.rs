//! K-fold cross-validation of a free-amplitude fit (docs/estimation.md,
//! "Choosing a model"): the measurements dealt into `F` folds by a seeded
//! shuffle; each fold held out in turn while the others are refitted from
//! the full fit's minimum, and its held-out residuals predicted. The
//! held-out weighted squared errors of all `K` measurements give the
//! cross-validated error `sqrt(Σ w r²/K)`, which over-fitting cannot
//! lower: a model that bends to its training noise predicts the held-out
//! measurements worse.
//!
//! A held-out measurement is a weight of 0 ([`super::bootstrap::reweighted`]),
//! so no basis is rebuilt; the folds run in parallel, summed in order, so
//! the error does not depend on the thread count.

use super::bootstrap::reweighted;
use super::Solution;
use crate::choice::CrossValidation;
use crate::free::model::FreeModel;
use crate::free::refine::{minimise, SCREENING};
use crate::synthetic::Noise;
use rayon::prelude::*;

/// The fold of each of `k` measurements: a shuffle seeded by `seed` dealt
/// round the `folds` folds, so the folds' sizes differ by at most one.
pub(crate) fn assignment(k: usize, folds: usize, seed: u64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..k).collect();
    let mut rng = Noise::new(seed ^ 0x9E37_79B9_7F4A_7C15);
    for i in (1..k).rev() {
        let j = ((rng.uniform() * (i + 1) as f64) as usize).min(i);
        order.swap(i, j);
    }
    let mut fold = vec![0; k];
    for (position, &measurement) in order.iter().enumerate() {
        fold[measurement] = position % folds;
    }
    fold
}

/// The `folds`-fold cross-validation of `solution`'s problem around its
/// minimum, the folds dealt by `seed`. `None` with fewer than two folds,
/// or when a training set would not outnumber the fitted parameters.
pub fn cross_validate<M: FreeModel>(
    solution: &Solution<'_, M>,
    (folds, seed): (usize, u64),
) -> Option<CrossValidation> {
    let Solution {
        problem, minimum, ..
    } = solution;
    let k = problem.data.len();
    let training = k - k.div_ceil(folds.max(1));
    if folds < 2 || training <= problem.parameter_count() {
        return None;
    }
    let fold = assignment(k, folds, seed);
    let free = problem.all_free();
    let held_out: Vec<f64> = (0..folds)
        .into_par_iter()
        .map(|f| {
            let keep: Vec<f64> = fold.iter().map(|&g| f64::from(g != f)).collect();
            let train = reweighted(problem, &keep);
            let point = minimise(&train, &minimum.theta, &free, train.beta, SCREENING).point;
            let columns = problem.model.columns(&point.theta);
            let r = problem.residuals(&columns, &point.linear);
            (0..k).filter(|&i| fold[i] == f).map(|i| r[i] * r[i]).sum()
        })
        .collect();
    let sse: f64 = held_out.iter().sum();
    sse.is_finite().then(|| CrossValidation {
        folds,
        rms: (sse / k as f64).sqrt(),
        in_sample: (minimum.sse / k as f64).sqrt(),
    })
}

#[cfg(test)]
mod tests {
    use super::assignment;

    /// Every measurement in one fold, the folds within one of each other's
    /// size, the same seed the same folds and another seed others.
    #[test]
    fn folds_partition_the_measurements_by_the_seed() {
        let a = assignment(198, 5, 7);
        let mut sizes = [0; 5];
        for &f in &a {
            sizes[f] += 1;
        }
        assert_eq!(sizes.iter().sum::<usize>(), 198);
        assert!(sizes.iter().max().unwrap() - sizes.iter().min().unwrap() <= 1);
        assert_eq!(a, assignment(198, 5, 7));
        assert_ne!(a, assignment(198, 5, 8));
    }
}
