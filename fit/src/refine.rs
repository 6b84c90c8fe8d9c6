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

use crate::edges::attainable_domain;
use crate::error::ModelError;
use crate::fitted::{FittedModel, Geometries, ModelParams};
use crate::model::Model;
use crate::scene::Scene;
use argmin::core::{CostFunction, Executor, State};
use argmin::solver::neldermead::NelderMead;
use rayon::prelude::*;

/// The objective of one (scene, model): the sum of squared residuals
/// `Σ (D − P)²` (eq. 15 before the root) as a function of the model's free
/// parameters, in f64, with the geometry built once.
#[derive(Debug, Clone)]
pub struct Objective<'a> {
    scene: &'a Scene,
    model: Model,
    geometries: Geometries,
    names: Vec<&'static str>,
    bounds: Vec<(f64, f64)>,
}

impl<'a> Objective<'a> {
    /// The objective of `model` on `scene`. Its free parameters are the
    /// model's parameters in output order, without a of the Ragheb–Hancock
    /// variants (fixed at 0).
    pub fn new(scene: &'a Scene, model: Model) -> Self {
        let names = free_names(model);
        let bounds = names
            .iter()
            .map(|&name| attainable_domain(model, name))
            .collect();
        Self {
            scene,
            model,
            geometries: Geometries::new(model, &scene.angles),
            names,
            bounds,
        }
    }

    /// The free parameters' names.
    pub fn names(&self) -> &[&'static str] {
        &self.names
    }

    /// The closed domain `[lo, hi]` of each free parameter.
    pub fn bounds(&self) -> &[(f64, f64)] {
        &self.bounds
    }

    /// `x` moved onto the domain, coordinate by coordinate.
    pub fn project(&self, x: &[f64]) -> Vec<f64> {
        x.iter()
            .zip(&self.bounds)
            .map(|(&v, &(lo, hi))| v.clamp(lo, hi))
            .collect()
    }

    /// The model's parameters at free values `x` (taken as they are).
    pub fn params(&self, x: &[f64]) -> ModelParams {
        let value = |name: &str| {
            self.names
                .iter()
                .position(|&n| n == name)
                .map_or(0.0, |i| x[i])
        };
        match template(self.model) {
            ModelParams::Layered { .. } => ModelParams::Layered {
                slope: value("slope"),
                beta: value("beta"),
                n: value("n"),
                a: value("a"),
            },
            ModelParams::Jensen { .. } => ModelParams::Jensen {
                sigma_a: value("sigma_a"),
                sigma_s: value("sigma_s"),
            },
            ModelParams::OrenNayar { .. } => ModelParams::OrenNayar {
                sigma: value("sigma"),
                rho: value("rho"),
            },
        }
    }

    /// The free values of `params`, in [`Objective::names`] order.
    pub fn values(&self, params: &ModelParams) -> Vec<f64> {
        self.names
            .iter()
            .map(|&n| params.get(n).unwrap_or(f64::NAN))
            .collect()
    }

    /// The normalised prediction `P` at every measurement at free values
    /// `x` (inside the domain).
    ///
    /// # Errors
    /// [`ModelError`] for values outside the domain.
    pub fn prediction(&self, x: &[f64]) -> Result<Vec<f64>, ModelError> {
        let params = self.params(x);
        let raw = self.geometries.raw(self.model, &params)?;
        FittedModel::from_raw(self.model, params, &raw, self.scene.data_scale).predict_raw(&raw)
    }

    /// `Σ (D − P)²` at `x` projected onto the domain (+∞ if the model
    /// cannot be evaluated there).
    pub fn sse(&self, x: &[f64]) -> f64 {
        match self.prediction(&self.project(x)) {
            Ok(p) => self
                .scene
                .data
                .iter()
                .zip(&p)
                .map(|(d, p)| (d - p) * (d - p))
                .sum(),
            Err(_) => f64::INFINITY,
        }
    }
}

/// The free parameters of `model` in output order: its parameters, without
/// a of the Ragheb–Hancock variants (fixed at 0).
pub fn free_names(model: Model) -> Vec<&'static str> {
    template(model)
        .pairs()
        .into_iter()
        .map(|(name, _)| name)
        .filter(|&name| !(model.is_ragheb_hancock() && name == "a"))
        .collect()
}

/// A model's parameters (values unused) to read names and kind from.
fn template(model: Model) -> ModelParams {
    match model {
        Model::Jensen => ModelParams::Jensen {
            sigma_a: 0.0,
            sigma_s: 0.0,
        },
        Model::OrenNayar => ModelParams::OrenNayar {
            sigma: 0.0,
            rho: 0.0,
        },
        _ => ModelParams::Layered {
            slope: 0.0,
            beta: 0.0,
            n: 0.0,
            a: 0.0,
        },
    }
}

/// A refined point: free values (inside the domain) and objective.
#[derive(Debug, Clone, PartialEq)]
pub struct Refined {
    /// The free values, in [`Objective::names`] order.
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
fn nelder_mead(
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
pub fn refine(objective: &Objective, starts: &[Vec<f64>], steps: &[f64]) -> Refined {
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
    objective: &Objective,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synthetic;
    use laminar_core::{Correlation, Params};

    #[test]
    fn refinement_finds_an_off_grid_truth_without_noise() {
        let truth = Params::new(1.234, 0.456, 1.417, 0.321).unwrap();
        let scene = synthetic::scene(Correlation::Exponential, &truth, 0.0, 1);
        let objective = Objective::new(&scene, Model::Exp);
        assert_eq!(objective.names(), ["slope", "beta", "n", "a"]);
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
        let objective = Objective::new(&scene, Model::RhGauss);
        assert_eq!(objective.names(), ["slope", "beta", "n"]);
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
