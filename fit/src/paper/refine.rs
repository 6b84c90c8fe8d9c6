//! Local refinement beyond the grid (docs/conventions.md §11): a bounded
//! Nelder–Mead search in f64 over a model's continuous parameters, within
//! the model's domain (not the grid's range), from the best grid point and
//! from the best point of each other basin the grid shows.
//!
//! Why Nelder–Mead ([`argmin`]'s): the paper normalisation divides the
//! prediction by its max over the measurements, so the objective has kinks
//! where the measurement holding the max changes, and a derivative-based
//! method (Levenberg–Marquardt) would step on a Jacobian that is wrong
//! there. The simplex method needs only values. Bounds are kept by
//! evaluating every vertex at its projection onto the domain (so the
//! objective is continuous and flat outside it), and the answer is the
//! projection of the best vertex. The start is a vertex, and Nelder–Mead
//! never replaces its best vertex by a worse one, so the refined objective
//! is never above the start's.

use super::objective::SumOfSquares;
use crate::grid::Axis;
use crate::model::Param;
use crate::paper::search::{GridProfile, Searched};
use crate::profile::basins;
use argmin::core::{CostFunction, Executor, State};
use argmin::solver::neldermead::NelderMead;
use rayon::prelude::*;

/// Most starts of the refinement from the grid (the best grid point and
/// the best points of other basins within `DELTA_68 · s²` of it); the
/// Ragheb–Hancock best is one more.
pub const MOST_STARTS: usize = 4;

/// A refined point: free values (inside the domain) and objective.
#[derive(Debug, Clone, PartialEq)]
pub struct Refined {
    /// The free values, in [`SumOfSquares::names`] order.
    pub x: Vec<f64>,
    /// `Σ (D − P)²` there.
    pub sse: f64,
    /// Objective evaluations used.
    pub evaluations: usize,
}

/// `v` without its `j`-th element.
fn without<T: Clone>(v: &[T], j: usize) -> Vec<T> {
    let mut v = v.to_vec();
    v.remove(j);
    v
}

/// A cost function for [`argmin`] from a closure.
struct Cost<F>(F);

impl<F: Fn(&[f64]) -> f64> CostFunction for Cost<F> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, x: &Vec<f64>) -> Result<f64, argmin::core::Error> {
        Ok((self.0)(x))
    }
}

/// Refinement stops when the standard deviation of the objective over the
/// simplex falls below this fraction of the start's objective.
pub const TOLERANCE: f64 = 1e-9;

/// A profile probe ([`profile_at`]) stops at this fraction: about 10⁻⁴ of
/// the noise variance `s² ≈ objective/(K − p)` at K ≈ 200, far below what
/// moves an interval end.
pub const PROFILE_TOLERANCE: f64 = 5e-7;

/// Most Nelder–Mead iterations per start.
pub const MAX_ITERATIONS: u64 = 400;

/// Nelder–Mead on `cost` (evaluated at its argument projected onto
/// `bounds`) from `start` with a first simplex of `steps` along each axis
/// (turned back into the domain at an upper end), stopping when the
/// objective's spread over the simplex is below `tolerance` times the
/// start's; the best vertex, projected, and its cost. Never worse than
/// `start`.
pub(crate) fn nelder_mead(
    cost: impl Fn(&[f64]) -> f64,
    bounds: &[(f64, f64)],
    (start, steps): (&[f64], &[f64]),
    tolerance: f64,
) -> Refined {
    let project = |x: &[f64]| -> Vec<f64> {
        x.iter()
            .zip(bounds)
            .map(|(&v, &(lo, hi))| v.clamp(lo, hi))
            .collect()
    };
    let start = project(start);
    let mut simplex = vec![start.clone()];
    for (i, (&step, &(_, hi))) in steps.iter().zip(bounds).enumerate() {
        let mut v = start.clone();
        v[i] = if start[i] + step <= hi {
            start[i] + step
        } else {
            start[i] - step
        };
        simplex.push(v);
    }
    let fallback = Refined {
        sse: cost(&start),
        x: start,
        evaluations: 1,
    };
    if simplex.len() < 2 {
        return fallback;
    }
    let run = NelderMead::new(simplex)
        .with_sd_tolerance(tolerance * fallback.sse + 1e-300)
        .and_then(|solver| {
            Executor::new(Cost(|x: &[f64]| cost(&project(x))), solver)
                .configure(|state| state.max_iters(MAX_ITERATIONS).counting(true))
                .run()
        });
    match run {
        Ok(result) => {
            let state = result.state();
            let evaluations = state
                .get_func_counts()
                .get("cost_count")
                .copied()
                .unwrap_or(0) as usize;
            match state.get_best_param() {
                Some(x) if state.get_best_cost() <= fallback.sse => {
                    let x = project(x);
                    Refined {
                        sse: cost(&x),
                        x,
                        evaluations,
                    }
                }
                _ => fallback,
            }
        }
        Err(_) => fallback,
    }
}

/// Refines from each of `starts` (free values; the first is the best grid
/// point) with first steps `steps` (one grid step per parameter), then
/// restarts once from the best with steps a tenth as long (a simplex can
/// collapse before it reaches the minimum). The best point found; never
/// worse than the first start.
pub fn refine(objective: &SumOfSquares, starts: &[Vec<f64>], steps: &[f64]) -> Refined {
    let cost = |x: &[f64]| objective.sse(x);
    let bounds = objective.bounds();
    // The starts run in parallel; the best is chosen in start order (the
    // first on ties), so the result does not depend on the thread count.
    let runs: Vec<Refined> = starts
        .par_iter()
        .map(|start| nelder_mead(cost, bounds, (start, steps), TOLERANCE))
        .collect();
    let mut evaluations = 0;
    let mut best: Option<Refined> = None;
    for r in runs {
        evaluations += r.evaluations;
        if best.as_ref().is_none_or(|b| r.sse < b.sse) {
            best = Some(r);
        }
    }
    let best = best.expect("at least one start");
    let fine: Vec<f64> = steps.iter().map(|s| s / 10.0).collect();
    let again = nelder_mead(cost, bounds, (&best.x, &fine), TOLERANCE);
    evaluations += again.evaluations;
    let best = if again.sse < best.sse { again } else { best };
    Refined {
        evaluations,
        ..best
    }
}

/// The profile of free parameter `j` at `value`: the smallest objective
/// over the other free parameters with parameter `j` held at `value`
/// (Nelder–Mead from `start`, whose `j`-th value is ignored, with first
/// `steps`). The point found is returned whole, `x[j] = value`.
pub fn profile_at(
    objective: &SumOfSquares,
    j: usize,
    value: f64,
    start: &[f64],
    steps: &[f64],
) -> Refined {
    let full = |others: &[f64]| -> Vec<f64> {
        let mut x = others.to_vec();
        x.insert(j, value);
        x
    };
    let r = nelder_mead(
        |others: &[f64]| objective.sse(&full(others)),
        &without(objective.bounds(), j),
        (&without(start, j), &without(steps, j)),
        PROFILE_TOLERANCE,
    );
    Refined { x: full(&r.x), ..r }
}

/// The first simplex steps of each free parameter of `objective`: one
/// grid step of its searched axis (0.01 when it was not searched or its
/// axis has one value).
pub(crate) fn grid_steps(objective: &SumOfSquares, searched: &[Searched]) -> Vec<f64> {
    objective
        .names()
        .iter()
        .map(|&n| {
            searched
                .iter()
                .find(|s| s.name == n)
                .map_or(0.01, |s| step(s.values))
        })
        .collect()
}

/// The spacing of an axis near its values (the first step; 0.01 for an axis
/// of one value).
fn step(axis: &Axis) -> f64 {
    match axis.values.as_slice() {
        [a, b, ..] => (b - a).abs(),
        _ => 0.01,
    }
}

/// The starts of the refinement, as free values of `objective`: the best
/// grid point `x_grid`, the best point of each other basin of the grid's
/// `profile` (over all the grid's axes, of lengths `lens`), at most
/// [`MOST_STARTS`] in all, then `rh` (the Ragheb–Hancock best, a point of
/// this model too and often in another basin). No start twice.
pub(crate) fn starts(
    x_grid: &[f64],
    profile: Option<(&GridProfile, &[usize])>,
    searched: &[Searched],
    (objective, rh): (&SumOfSquares, Option<Vec<f64>>),
) -> Vec<Vec<f64>> {
    let mut starts = vec![x_grid.to_vec()];
    if let Some((grid_profile, lens)) = profile {
        for (flat, _) in basins(&grid_profile.near, lens, MOST_STARTS) {
            let start = point_of(flat, lens, searched, objective.names(), x_grid);
            if !starts.contains(&start) {
                starts.push(start);
            }
        }
        starts.truncate(MOST_STARTS);
    }
    if let Some(start) = rh {
        if !starts.contains(&start) {
            starts.push(start);
        }
    }
    starts
}

/// The free values of the grid point `flat` (row-major over `lens`),
/// taking parameters not searched from `fallback`.
fn point_of(
    flat: usize,
    lens: &[usize],
    searched: &[Searched],
    names: &[Param],
    fallback: &[f64],
) -> Vec<f64> {
    names
        .iter()
        .zip(fallback)
        .map(|(&name, &f)| {
            searched.iter().find(|s| s.name == name).map_or(f, |s| {
                let stride: usize = lens[s.axis + 1..].iter().product();
                s.values.values[(flat / stride) % lens[s.axis]]
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fitted::ModelParams;
    use crate::model::Model;
    use crate::synthetic;
    use laminar_brdf_core::{Correlation, Params};

    #[test]
    fn refinement_finds_an_off_grid_truth_without_noise() {
        let truth = Params::new(1.234, 0.456, 1.417, 0.321).unwrap();
        let scene = synthetic::scene(Correlation::Exponential, &truth, 0.0, 1);
        let objective = SumOfSquares::new(&scene, Model::Exp);
        assert_eq!(objective.names(), Model::Exp.params());
        let start = vec![1.24, 0.46, 1.42, 0.32];
        let r = refine(
            &objective,
            std::slice::from_ref(&start),
            &[0.08, 0.01, 0.02, 0.01],
        );
        assert!(r.sse < objective.sse(&start));
        for (got, want) in r.x.iter().zip([1.234, 0.456, 1.417, 0.321]) {
            assert!((got - want).abs() < 1e-6, "{:?}", r.x);
        }
    }

    #[test]
    fn bounds_hold_and_ragheb_hancock_keeps_a_at_zero() {
        let truth = Params::new(0.8, 0.3, 1.05, 0.0).unwrap();
        let scene = synthetic::scene(Correlation::Gaussian, &truth, 0.0, 1);
        let objective = SumOfSquares::new(&scene, Model::RhGauss);
        assert_eq!(objective.names(), [Param::Slope, Param::Beta, Param::N]);
        // Starts pushed against n = 1: the answer stays in the domain.
        let r = refine(&objective, &[vec![0.9, 0.35, 1.0]], &[0.08, 0.01, 0.02]);
        assert!(r.x[2] >= 1.0 && r.x[1] >= 0.0 && r.x[1] <= 1.0);
        assert!((r.x[2] - 1.05).abs() < 1e-5, "{:?}", r.x);
        assert!(matches!(
            objective.params(&r.x),
            ModelParams::Layered { a, .. } if a == 0.0
        ));
    }
}
