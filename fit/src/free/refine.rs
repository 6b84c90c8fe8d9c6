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
//!
//! The method is a stepper ([`LevenbergMarquardt::next_iter`], argmin's
//! shape) with its knobs in [`LevenbergMarquardt`]; [`minimise`] runs it.

use super::jacobian::Normal;
use super::model::FreeModel;
use super::problem::{Point, Problem};
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// The refinement's iterations stop when a step lowers the objective by
/// less than this fraction of it.
pub const TOLERANCE: f64 = 1e-10;

/// The tolerance of the first pass from every start: enough to tell the
/// basins apart; only the best is then taken to [`TOLERANCE`].
pub const SCREENING: f64 = 1e-6;

/// The damping at the start, and the most a step keeps to count as an
/// undamped (Gauss–Newton) step.
const UNDAMPED: f64 = 1e-3;

/// Above this damping a minimisation stops: no step lowers the objective.
const MOST_DAMPING: f64 = 1e12;

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

/// Levenberg–Marquardt's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LevenbergMarquardt {
    tolerance: f64,
    max_iterations: usize,
}

impl Default for LevenbergMarquardt {
    /// To [`TOLERANCE`], at most 100 iterations.
    fn default() -> Self {
        Self {
            tolerance: TOLERANCE,
            max_iterations: 100,
        }
    }
}

/// Where a minimisation is: the point, its normal equations and the
/// damping.
struct State<M: FreeModel> {
    x: Vec<f64>,
    point: Point,
    normal: Normal,
    held: M::Held,
    lambda: f64,
    /// Nielsen's factor for consecutive failures.
    nu: f64,
    evaluations: usize,
}

/// What one iteration did.
enum Step {
    /// Moved to a lower point; the next iteration goes on from there.
    Moved,
    /// The minimum, to the tolerance (or nothing lowers the objective).
    Converged,
}

/// A trial accepted: its parameters, point and evaluation.
type Accepted<M> = (
    Vec<f64>,
    Point,
    super::model::Evaluated<<M as FreeModel>::Kept>,
);

impl LevenbergMarquardt {
    /// Stops when a step gains less than `tolerance` of the objective (a
    /// fraction of it; a negative or NaN tolerance is 0: it stops only
    /// where no step lowers the objective, or after the most iterations).
    pub fn with_tolerance(self, tolerance: f64) -> Self {
        Self {
            tolerance: tolerance.max(0.0),
            ..self
        }
    }

    /// Minimises `problem` from `start` over the parameters marked in
    /// `free` (the others stay at their start values), with β in `beta`.
    pub fn minimise<M: FreeModel>(
        &self,
        problem: &Problem<M>,
        start: &[f64],
        free: &[bool],
        beta: (f64, f64),
    ) -> Minimum {
        let x = clamp(problem, start);
        let held = problem.model.held(&x, free);
        let (point, normal) = problem.jacobian(&x, beta, &held, free);
        let mut state = State {
            x,
            point,
            normal,
            held,
            lambda: UNDAMPED,
            nu: 2.0,
            evaluations: 1,
        };
        for _ in 0..self.max_iterations {
            if let Step::Converged = self.next_iter(problem, &mut state, free, beta) {
                break;
            }
        }
        Minimum {
            point: state.point,
            evaluations: state.evaluations,
        }
    }

    /// One iteration: steps damped more until one lowers the objective.
    fn next_iter<M: FreeModel>(
        &self,
        problem: &Problem<M>,
        state: &mut State<M>,
        free: &[bool],
        beta: (f64, f64),
    ) -> Step {
        let gradient = &state.normal.jtr;
        let moving: Vec<usize> = (0..state.x.len())
            .filter(|&j| {
                let (lo, hi) = problem.bounds[j];
                let x = state.x[j];
                free[j] && !(x <= lo && gradient[j] > 0.0) && !(x >= hi && gradient[j] < 0.0)
            })
            .collect();
        if moving.is_empty() {
            return Step::Converged;
        }
        let f = moving.len();
        let h = DMatrix::from_fn(f, f, |a, b| state.normal.jtj[(moving[a], moving[b])]);
        let g = DVector::from_iterator(f, moving.iter().map(|&j| -gradient[j]));
        if g.norm() == 0.0 {
            return Step::Converged;
        }
        loop {
            let mut a = h.clone();
            for i in 0..f {
                a[(i, i)] += state.lambda * h[(i, i)].max(1e-30);
            }
            let Some(step) = a.cholesky().map(|c| c.solve(&g)) else {
                state.lambda *= 10.0;
                if state.lambda > MOST_DAMPING {
                    return Step::Converged;
                }
                continue;
            };
            // The Gauss–Newton model's decrease of the objective along the
            // step: below the tolerance, the point is the minimum to it.
            let predicted = 2.0 * step.dot(&g) - (&h * &step).dot(&step);
            if predicted < self.tolerance * state.point.sse && state.lambda <= UNDAMPED {
                return Step::Converged;
            }
            let slope_at_start = -2.0 * step.dot(&g);
            if let Some((accepted, fraction)) =
                trial(problem, state, (&moving, &step), slope_at_start, beta)
            {
                return self.accept(
                    problem,
                    state,
                    accepted,
                    (fraction, predicted),
                    (free, beta),
                );
            }
            state.lambda *= state.nu;
            state.nu *= 2.0;
            if state.lambda > MOST_DAMPING {
                return Step::Converged;
            }
        }
    }

    /// Moves `state` to the accepted trial, taken `fraction` of its step
    /// along, whose decrease the Gauss–Newton model `predicted`; the
    /// minimum when it gains less than the tolerance.
    fn accept<M: FreeModel>(
        &self,
        problem: &Problem<M>,
        state: &mut State<M>,
        (trial, candidate, evaluated): Accepted<M>,
        (fraction, predicted): (f64, f64),
        (free, beta): (&[bool], (f64, f64)),
    ) -> Step {
        let sse = state.point.sse;
        let gain = (sse - candidate.sse) / sse.max(1e-300);
        let moved = trial
            .iter()
            .zip(&state.x)
            .any(|(a, b)| (a - b).abs() > 1e-14 * b.abs().max(1.0));
        state.x = trial;
        // A full, barely damped step whose decrease the Gauss–Newton model
        // predicted to within the tolerance ends at the model's minimum:
        // what is left to gain is at most about that disagreement (the
        // residuals' own curvature, which the model leaves out, shrinks each
        // step's remainder by its ratio to JᵀJ's), so no Jacobian is formed
        // to confirm.
        let agreed = fraction == 1.0
            && state.lambda <= UNDAMPED
            && (sse - candidate.sse - predicted).abs() < self.tolerance * sse;
        if gain < self.tolerance || !moved || agreed {
            state.point = candidate;
            return Step::Converged;
        }
        state.lambda = if fraction < 1.0 {
            // The full step overshot: the next one damped to about the
            // length that succeeded.
            (2.0 * state.lambda).max(1.0 / fraction - 1.0)
        } else {
            // Nielsen's update from the gain ratio: the damping follows how
            // well the Gauss–Newton model predicted the decrease (no see-saw
            // between two values in a curved valley).
            let rho = (sse - candidate.sse) / predicted.max(1e-300);
            (state.lambda * (1.0 / 3.0f64).max(1.0 - (2.0 * rho - 1.0).powi(3))).max(1e-12)
        };
        state.nu = 2.0;
        state.normal = problem.jacobian_at(&candidate, evaluated, beta, free);
        state.point = candidate;
        Step::Moved
    }
}

/// `x` clamped into `problem`'s box.
fn clamp<M>(problem: &Problem<M>, x: &[f64]) -> Vec<f64> {
    x.iter()
        .zip(&problem.bounds)
        .map(|(&v, &(lo, hi))| v.clamp(lo, hi))
        .collect()
}

/// The full step of the parameters `moving`; when it fails, once more cut
/// back to the minimum of the parabola through the objective at both ends
/// and its slope at the start (one evaluation, where raising the damping
/// alone takes several rejections to shorten a step that overshoots a
/// curved valley). The trial that lowers the objective, and the fraction
/// of the step it took.
fn trial<M: FreeModel>(
    problem: &Problem<M>,
    state: &mut State<M>,
    (moving, step): (&[usize], &DVector<f64>),
    slope_at_start: f64,
    beta: (f64, f64),
) -> Option<(Accepted<M>, f64)> {
    let mut fraction = 1.0;
    for attempt in 0..2 {
        let mut trial = state.x.clone();
        for (a, &j) in moving.iter().enumerate() {
            trial[j] += fraction * step[a];
        }
        let trial = clamp(problem, &trial);
        let (candidate, evaluated) = problem.evaluate_keeping(&trial, beta, &state.held);
        state.evaluations += 1;
        if candidate.sse < state.point.sse {
            return Some(((trial, candidate, evaluated), fraction));
        }
        let slope = fraction * slope_at_start;
        let rise = candidate.sse - state.point.sse - slope;
        if attempt == 1 || !(slope < 0.0 && rise > 0.0) {
            return None;
        }
        fraction *= (-slope / (2.0 * rise)).clamp(0.1, 0.5);
    }
    None
}

/// Minimises `problem` from `start` over the parameters marked in `free`
/// (the others stay at their start values), with β in `beta`, until a step
/// gains less than `tolerance` of the objective
/// ([`LevenbergMarquardt::minimise`]).
pub fn minimise<M: FreeModel>(
    problem: &Problem<M>,
    start: &[f64],
    free: &[bool],
    beta: (f64, f64),
    tolerance: f64,
) -> Minimum {
    LevenbergMarquardt::default()
        .with_tolerance(tolerance)
        .minimise(problem, start, free, beta)
}

/// Minimises from every start (all parameters free, β in the box) to the
/// [`SCREENING`] tolerance, then takes the lowest (the first on ties, so the
/// result does not depend on the thread count) on to [`TOLERANCE`].
pub fn refine<M: FreeModel>(problem: &Problem<M>, starts: &[Vec<f64>]) -> Minimum {
    let free = problem.all_free();
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

/// The refinement of a fit: [`refine`] from the grid's basins `starts`
/// and, side by side, a minimisation from the model's `corner` start
/// ([`super::model::FreeModel::corner_start`]), whose minimum is taken
/// only when lower by more than the [`SCREENING`] tolerance (so a fit whose
/// corner leads back to its own basin is unchanged), then polished to
/// [`TOLERANCE`].
pub fn refinement<M: FreeModel>(
    problem: &Problem<M>,
    starts: &[Vec<f64>],
    corner: Option<Vec<f64>>,
) -> Point {
    let free = problem.all_free();
    let (refined, corner) = rayon::join(
        || refine(problem, starts).point,
        || corner.map(|start| minimise(problem, &start, &free, problem.beta, SCREENING).point),
    );
    match corner {
        Some(c) if c.sse < refined.sse * (1.0 - SCREENING) => {
            minimise(problem, &c.theta, &free, problem.beta, TOLERANCE).point
        }
        _ => refined,
    }
}
