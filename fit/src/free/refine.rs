//! Refinement of the free-amplitude objective: Levenberg–Marquardt over the
//! nonlinear parameters inside the box, on the variable-projection residual
//! ([`Problem::jacobian`]), the linear part solved in closed form at every
//! point. The objective is smooth in the nonlinear parameters (no max
//! enters it), so a derivative-based method converges in a few steps.
//!
//! Bounds: a parameter on a face of the box whose gradient points out of
//! the box is held there for the step (a projected active set), and every
//! trial point is clamped into the box, so nothing leaves it. A step is
//! taken only when it lowers the objective, so the result is never worse
//! than the start; a step that does not is cut back once along itself
//! (to the parabola's minimum) before the damping is raised.

use super::problem::{Point, Problem};
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// Most Levenberg–Marquardt iterations per start.
pub const MAX_ITERATIONS: usize = 100;

/// The refinement's iterations stop when a step lowers the objective by
/// less than this fraction of it.
pub const TOLERANCE: f64 = 1e-10;

/// The tolerance of the first pass from every start: enough to tell the
/// basins apart; only the best is then taken to [`TOLERANCE`].
pub const SCREENING: f64 = 1e-6;

/// A minimisation's result.
#[derive(Debug, Clone, PartialEq)]
pub struct Minimum {
    /// The point.
    pub point: Point,
    /// Points whose columns were evaluated (the start and every trial; the
    /// derivatives' own passes, analytic for the layered models, are not
    /// counted).
    pub evaluations: usize,
}

/// Minimises `problem` from `start` over the parameters marked in `free`
/// (the others stay at their start values), with β in `beta`, until a step
/// gains less than `tolerance` of the objective.
pub fn minimise(
    problem: &Problem,
    start: &[f64],
    free: &[bool],
    beta: (f64, f64),
    tolerance: f64,
) -> Minimum {
    let bounds = &problem.bounds;
    let clamp = |x: &[f64]| -> Vec<f64> {
        x.iter()
            .zip(bounds)
            .map(|(&v, &(lo, hi))| v.clamp(lo, hi))
            .collect()
    };
    let mut x = clamp(start);
    let held = problem.basis.held(&x, free);
    let (mut point, mut normal) = problem.jacobian(&x, beta, &held, free);
    let mut evaluations = 1;
    let mut lambda = 1e-3;
    // Nielsen's factor for consecutive failures.
    let mut nu = 2.0;
    'outer: for _ in 0..MAX_ITERATIONS {
        let m = x.len();
        let gradient = &normal.jtr;
        let moving: Vec<usize> = (0..m)
            .filter(|&j| {
                let (lo, hi) = bounds[j];
                free[j] && !(x[j] <= lo && gradient[j] > 0.0) && !(x[j] >= hi && gradient[j] < 0.0)
            })
            .collect();
        if moving.is_empty() {
            break;
        }
        let f = moving.len();
        let mut h = DMatrix::<f64>::zeros(f, f);
        for (a, &i) in moving.iter().enumerate() {
            for (b, &j) in moving.iter().enumerate() {
                h[(a, b)] = normal.jtj[(i, j)];
            }
        }
        let g = DVector::from_iterator(f, moving.iter().map(|&j| -gradient[j]));
        if g.norm() == 0.0 {
            break;
        }
        loop {
            let mut a = h.clone();
            for i in 0..f {
                a[(i, i)] += lambda * h[(i, i)].max(1e-30);
            }
            let Some(step) = a.cholesky().map(|c| c.solve(&g)) else {
                lambda *= 10.0;
                if lambda > 1e12 {
                    break 'outer;
                }
                continue;
            };
            // The Gauss–Newton model's decrease of the objective along the
            // step: below the tolerance, the point is the minimum to it.
            let predicted = 2.0 * step.dot(&g) - (&h * &step).dot(&step);
            if predicted < tolerance * point.sse && lambda <= 1e-3 {
                break 'outer;
            }
            // The full step; when it fails, once more cut back to the minimum
            // of the parabola through the objective at both ends and its
            // slope at the start: one evaluation, where raising the damping
            // alone takes several rejections to shorten a step that
            // overshoots a curved valley.
            let slope_at_start = -2.0 * step.dot(&g);
            let mut fraction = 1.0;
            let mut accepted = None;
            for attempt in 0..2 {
                let mut trial = x.clone();
                for (a, &j) in moving.iter().enumerate() {
                    trial[j] += fraction * step[a];
                }
                let trial = clamp(&trial);
                let (candidate, evaluated) = problem.evaluate_keeping(&trial, beta, &held);
                evaluations += 1;
                if candidate.sse < point.sse {
                    accepted = Some((trial, candidate, evaluated));
                    break;
                }
                let slope = fraction * slope_at_start;
                let rise = candidate.sse - point.sse - slope;
                if attempt == 1 || !(slope < 0.0 && rise > 0.0) {
                    break;
                }
                fraction *= (-slope / (2.0 * rise)).clamp(0.1, 0.5);
            }
            if let Some((trial, candidate, evaluated)) = accepted {
                let gain = (point.sse - candidate.sse) / point.sse.max(1e-300);
                let moved = trial
                    .iter()
                    .zip(&x)
                    .any(|(a, b)| (a - b).abs() > 1e-14 * b.abs().max(1.0));
                x = trial;
                // A full, barely damped step whose decrease the Gauss–Newton
                // model predicted to within the tolerance ends at the
                // model's minimum: what is left to gain is at most about
                // that disagreement (the residuals' own curvature, which
                // the model leaves out, shrinks each step's remainder by
                // its ratio to JᵀJ's), so no Jacobian is formed to confirm.
                let agreed = fraction == 1.0
                    && lambda <= 1e-3
                    && (point.sse - candidate.sse - predicted).abs() < tolerance * point.sse;
                if gain < tolerance || !moved || agreed {
                    point = candidate;
                    break 'outer;
                }
                lambda = if fraction < 1.0 {
                    // The full step overshot: the next one damped to about
                    // the length that succeeded.
                    (2.0 * lambda).max(1.0 / fraction - 1.0)
                } else {
                    // Nielsen's update from the gain ratio: the damping
                    // follows how well the Gauss–Newton model predicted the
                    // decrease (no see-saw between two values in a curved
                    // valley).
                    let rho = (point.sse - candidate.sse) / predicted.max(1e-300);
                    (lambda * (1.0 / 3.0f64).max(1.0 - (2.0 * rho - 1.0).powi(3))).max(1e-12)
                };
                nu = 2.0;
                normal = problem.jacobian_at(&candidate, evaluated, beta, free);
                point = candidate;
                break;
            }
            lambda *= nu;
            nu *= 2.0;
            if lambda > 1e12 {
                break 'outer;
            }
        }
    }
    Minimum { point, evaluations }
}

/// Minimises from every start (all parameters free, β in the box) to the
/// [`SCREENING`] tolerance, then takes the lowest (the first on ties, so the
/// result does not depend on the thread count) on to [`TOLERANCE`].
pub fn refine(problem: &Problem, starts: &[Vec<f64>]) -> Minimum {
    let free = vec![true; problem.dim()];
    let runs: Vec<Minimum> = starts
        .par_iter()
        .map(|s| minimise(problem, s, &free, problem.beta, SCREENING))
        .collect();
    let mut evaluations: usize = runs.iter().map(|r| r.evaluations).sum();
    let best = runs
        .into_iter()
        .reduce(|a, b| if b.point.sse < a.point.sse { b } else { a })
        .expect("at least one start");
    let polished = minimise(problem, &best.point.theta, &free, problem.beta, TOLERANCE);
    evaluations += polished.evaluations;
    Minimum {
        evaluations,
        ..polished
    }
}
