//! Levenberg–Marquardt on the joint objective `J` from a nearby start (a
//! bootstrap resample's or a cross-validation fold's, from the estimate):
//! the shared values' step from the channels' Gauss–Newton normal
//! equations ([`Problem::jacobian`]: Golub and Pereyra's, analytic), each
//! channel's a eliminated from its own (the Schur complement
//! `H_xx − H_xa H_aa⁻¹ H_ax`, `g_x − H_xa H_aa⁻¹ g_a`: a moves with the
//! shared values to first order), then each a found again exactly at the
//! trial point ([`Joint::at`]), so every value of `J` compared is the
//! minimum over the a's. The damping, the box and the stopping rule are
//! the single fit's ([`crate::free::refine`]): a parameter on a face whose
//! gradient points out is held for the step, a trial is clamped into the
//! box and taken only when it lowers `J`, and the refinement stops when a
//! step gains less than [`TOLERANCE`] of `J`.

use super::Joint;
use crate::free::model::{FreeModel, LayeredModel};
use crate::free::problem::Problem;
use crate::free::refine::TOLERANCE;
use nalgebra::{DMatrix, DVector};

/// The damping at the start (a Gauss–Newton step, barely damped).
const UNDAMPED: f64 = 1e-3;

/// Above this damping no step lowers `J`: the start is the minimum.
const MOST_DAMPING: f64 = 1e12;

/// The most iterations.
const MOST_ITERATIONS: usize = 100;

/// `J`'s minimum near `start` (the shared values): the shared values, each
/// channel's a and `J` there.
pub(super) fn refine(
    joint: &Joint<'_>,
    problems: &[Problem<LayeredModel>],
    start: &[f64],
) -> (Vec<f64>, Vec<f64>, f64) {
    let bounds = joint.bounds(problems);
    let mut x: Vec<f64> = (start.iter().zip(&bounds))
        .map(|(&v, &(lo, hi))| v.clamp(lo, hi))
        .collect();
    let (mut objective, mut a) = joint.at(problems, &x);
    let (mut lambda, mut nu) = (UNDAMPED, 2.0);
    for _ in 0..MOST_ITERATIONS {
        let (h, gradient) = reduced_normal(joint, problems, &x, &a);
        let moving: Vec<usize> = (0..x.len())
            .filter(|&i| {
                let (lo, hi) = bounds[i];
                let held = (x[i] <= lo && gradient[i] > 0.0) || (x[i] >= hi && gradient[i] < 0.0);
                !held
            })
            .collect();
        let m = moving.len();
        let g = DVector::from_iterator(m, moving.iter().map(|&i| -gradient[i]));
        if m == 0 || g.norm() == 0.0 || !g.iter().all(|v| v.is_finite()) {
            break;
        }
        let h = DMatrix::from_fn(m, m, |p, q| h[(moving[p], moving[q])]);
        // Damped until a step lowers J, or no step does.
        let accepted = loop {
            let mut damped = h.clone();
            for i in 0..m {
                damped[(i, i)] += lambda * h[(i, i)].max(1e-30);
            }
            let Some(step) = damped.cholesky().map(|c| c.solve(&g)) else {
                lambda *= 10.0;
                if lambda > MOST_DAMPING {
                    break None;
                }
                continue;
            };
            let predicted = 2.0 * step.dot(&g) - (&h * &step).dot(&step);
            if predicted < TOLERANCE * objective && lambda <= UNDAMPED {
                break None;
            }
            let mut trial = x.clone();
            for (p, &i) in moving.iter().enumerate() {
                let (lo, hi) = bounds[i];
                trial[i] = (trial[i] + step[p]).clamp(lo, hi);
            }
            let (value, trial_a) = joint.at(problems, &trial);
            if value < objective {
                let rho = (objective - value) / predicted.max(1e-300);
                lambda = (lambda * (1.0 / 3.0f64).max(1.0 - (2.0 * rho - 1.0).powi(3))).max(1e-12);
                nu = 2.0;
                break Some((trial, trial_a, value));
            }
            lambda *= nu;
            nu *= 2.0;
            if lambda > MOST_DAMPING {
                break None;
            }
        };
        let Some((trial, trial_a, value)) = accepted else {
            break;
        };
        let gain = (objective - value) / objective.max(1e-300);
        (x, a, objective) = (trial, trial_a, value);
        if gain < TOLERANCE {
            break;
        }
    }
    (x, a, objective)
}

/// The Gauss–Newton normal equations of `J` in the shared values `x`, each
/// channel's a (at `a`, its minimum there) eliminated: `JᵀJ` and `Jᵀr`
/// summed over the channels.
fn reduced_normal(
    joint: &Joint<'_>,
    problems: &[Problem<LayeredModel>],
    x: &[f64],
    a: &[f64],
) -> (DMatrix<f64>, Vec<f64>) {
    let m = x.len();
    let mut h = DMatrix::<f64>::zeros(m, m);
    let mut g = vec![0.0; m];
    for (c, problem) in problems.iter().enumerate() {
        let theta = joint.theta_of(x, c, a[c]);
        // a on a face of its box stays there: not eliminated.
        let a_free = joint
            .a_at
            .filter(|_| a[c] > joint.a_box.0 && a[c] < joint.a_box.1);
        let free: Vec<bool> = (0..theta.len())
            .map(|j| joint.x_index(c, j).is_some() || Some(j) == a_free)
            .collect();
        let held = problem.model.held(&theta, &free);
        let (_, normal) = problem.jacobian(&theta, problem.beta, &held, &free);
        let (jtj, jtr) = (&normal.jtj, &normal.jtr);
        // Channel c's rows of the shared values: (x index, θ position).
        let rows: Vec<(usize, usize)> = (0..theta.len())
            .filter_map(|j| joint.x_index(c, j).map(|i| (i, j)))
            .collect();
        let eliminated = a_free.filter(|&k| jtj[(k, k)] > 0.0);
        for &(p, j) in &rows {
            let (coupling_j, gradient_a) = match eliminated {
                Some(k) => (jtj[(j, k)] / jtj[(k, k)], jtr[k]),
                None => (0.0, 0.0),
            };
            g[p] += jtr[j] - coupling_j * gradient_a;
            for &(q, l) in &rows {
                let coupling_l = eliminated.map_or(0.0, |k| jtj[(k, l)]);
                h[(p, q)] += jtj[(j, l)] - coupling_j * coupling_l;
            }
        }
    }
    (h, g)
}

#[cfg(test)]
mod tests {
    use super::super::{channel_grid_starts, channel_grids, channel_problems, refine_all};
    use super::super::{refine as nelder_mead, ESTIMATE_STEPS};
    use super::*;
    use crate::free::layout::Layout;
    use crate::free::statistics::bootstrap::{resample_counts, reweighted};
    use crate::grid::Grid;
    use crate::model::Model;
    use crate::settings::Precision;
    use crate::synthetic;
    use laminar_brdf_core::{Correlation, Params};
    use std::sync::Arc;

    /// From the estimate, on bootstrap resamples of three channels of an
    /// untied surface, Levenberg–Marquardt ends where two Nelder–Mead
    /// passes do, and no higher.
    #[test]
    fn resamples_reach_nelder_meads_minimum() {
        let scenes: Vec<_> = [0.05, 0.3, 0.6]
            .into_iter()
            .enumerate()
            .map(|(c, a)| {
                let truth = Params::untied(0.3, 1.5, 0.39, 1.44, a).unwrap();
                synthetic::scene(Correlation::Exponential, &truth, 0.01, 11 + c as u64)
            })
            .collect();
        let model = Model::Exp2;
        let built = Arc::new(LayeredModel::new(model, scenes[0].angles()));
        let layout = Layout::new(&*built, &Grid::user());
        let problems = channel_problems(&scenes, model, &built, &layout);
        let joint = Joint::all_shared(&built, &layout);
        let grids = channel_grids(&problems, &layout, Precision::F64);
        let starts = channel_grid_starts(&grids, &layout, &[joint.a_at.unwrap()], |thetas| {
            joint.shared.iter().map(|&j| thetas[0][j]).collect()
        });
        let x = refine_all(
            &joint,
            &problems,
            (&starts, super::super::Method::NelderMead),
            0,
        )
        .x;
        for b in 0..8 {
            let counts = resample_counts(problems[0].data.len(), 5, b);
            let resampled: Vec<_> = problems.iter().map(|p| reweighted(p, &counts)).collect();
            let (xn, an, jn) = refine(&joint, &resampled, &x);
            let (xm, am, jm) = nelder_mead(&joint, &resampled, &x, &ESTIMATE_STEPS);
            assert!(jn <= jm * (1.0 + 1e-9), "resample {b}: J {jn} against {jm}");
            for (u, v) in xn.iter().zip(&xm).chain(an.iter().zip(&am)) {
                assert!(
                    (u - v).abs() < 1e-3,
                    "resample {b}: {xn:?} {an:?} against {xm:?} {am:?}"
                );
            }
        }
    }
}
