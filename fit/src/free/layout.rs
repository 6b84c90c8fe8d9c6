//! How a model's reported parameters map onto the free objective
//! (docs/conventions.md §4b): the box and grid of each nonlinear parameter
//! (in its internal coordinate, ln σ/T for the slope), β's box, and the
//! model's parameters and estimate at a point of the objective.

use super::basis::Columns;
use super::intervals::Coordinate;
use super::problem::{Point, Problem};
use super::search::GridAxes;
use crate::estimate::Estimate;
use crate::fitted::{FittedModel, ModelParams};
use crate::grid::{Axis, Grid};
use crate::model::{attainable_domain, baseline_grid, Family, Model, Param};
use crate::scene::Scene;

/// A model's reported parameters and how each maps onto the objective.
pub(super) struct Layout {
    pub(super) names: &'static [Param],
    pub(super) coordinates: Vec<Coordinate>,
    /// Grid axes of the nonlinear parameters (model units).
    pub(super) axes: GridAxes,
    /// Box of the nonlinear parameters (internal coordinates).
    pub(super) bounds: Vec<(f64, f64)>,
    /// The same box in the parameters' units.
    pub(super) reported: Vec<(f64, f64)>,
    /// Domain of the nonlinear parameters (internal coordinates).
    pub(super) domain: Vec<(f64, f64)>,
    /// β's box.
    pub(super) beta: (f64, f64),
}

impl Layout {
    pub(super) fn new(model: Model, grid: &Grid) -> Self {
        let log = |(lo, hi): (f64, f64)| (libm::log(lo), libm::log(hi));
        // The nonlinear parameters and the axes they are searched on.
        let nonlinear: Vec<(Param, Axis)> = match model.family() {
            Family::Baseline(b) => {
                let (x, y) = baseline_grid(b);
                let names = b.params();
                vec![(names[0], x), (names[1], y)]
            }
            Family::Layered { absorption, .. } => {
                let mut axes = vec![
                    (Param::Slope, grid.slope.clone()),
                    (Param::N, grid.n.clone()),
                ];
                if absorption {
                    axes.push((Param::A, grid.a.clone()));
                }
                axes
            }
        };
        // σ/T is searched and refined in its logarithm.
        let in_log = |name: Param| name == Param::Slope;
        let internal =
            |name: Param, range: (f64, f64)| if in_log(name) { log(range) } else { range };
        let names = model.free_params();
        let coordinates = names
            .iter()
            .map(
                |&name| match nonlinear.iter().position(|(n, _)| *n == name) {
                    Some(j) => Coordinate::Nonlinear {
                        j,
                        log: in_log(name),
                    },
                    None => Coordinate::Beta,
                },
            )
            .collect();
        Self {
            names,
            coordinates,
            bounds: nonlinear
                .iter()
                .map(|(name, axis)| internal(*name, axis.range()))
                .collect(),
            reported: nonlinear.iter().map(|(_, axis)| axis.range()).collect(),
            domain: nonlinear
                .iter()
                .map(|&(name, _)| internal(name, attainable_domain(name)))
                .collect(),
            beta: if model.correlation().is_some() {
                grid.beta.range()
            } else {
                (0.0, 0.0)
            },
            axes: GridAxes {
                axes: nonlinear.into_iter().map(|(_, axis)| axis.values).collect(),
            },
        }
    }

    /// The nonlinear parameters (internal coordinates) of grid indices.
    pub(super) fn theta(&self, indices: &[usize]) -> Vec<f64> {
        let logarithmic = |j: usize| {
            self.coordinates
                .contains(&Coordinate::Nonlinear { j, log: true })
        };
        indices
            .iter()
            .enumerate()
            .map(|(j, &i)| {
                let v = self.axes.axes[j][i];
                if logarithmic(j) {
                    libm::log(v)
                } else {
                    v
                }
            })
            .collect()
    }
}

/// The model's parameters at `point`.
pub(super) fn params_of(problem: &Problem, model: Model, point: &Point) -> ModelParams {
    match model.family() {
        Family::Baseline(b) => ModelParams::baseline(b, [point.theta[0], point.theta[1]]),
        Family::Layered { .. } => {
            let (_, n, a) = problem.basis.slope_n_a(&point.theta);
            ModelParams::Layered {
                // In the box exactly (exp(ln x) can miss x by an ulp).
                slope: Coordinate::Nonlinear { j: 0, log: true }.value(point, problem),
                beta: point.linear.beta(problem.beta.0),
                n,
                a,
            }
        }
    }
}

/// The estimate of `model` at `point`, whose columns are `columns`.
pub(super) fn estimate(
    scene: &Scene,
    problem: &Problem,
    model: Model,
    point: &Point,
    columns: &Columns,
) -> Estimate {
    let fitted = FittedModel::with_amplitude(
        model,
        params_of(problem, model, point),
        point.linear.amplitude(),
        scene.data_scale(),
    );
    Estimate::of_raw(
        scene,
        fitted,
        &raw_terms(columns),
        problem.parameter_count(),
    )
    .expect("the box lies inside the model's domain")
}

/// The model's raw terms (`[S, U]`, or `[L, 0]` for a baseline) from its
/// columns at a point: an [`Estimate`] without evaluating the model again.
pub(super) fn raw_terms(Columns { s, u }: &Columns) -> Vec<[f64; 2]> {
    (0..s.len())
        .map(|k| [s[k], u.get(k).copied().unwrap_or(0.0)])
        .collect()
}

/// The model's domain of reported parameter `i` (an open lower end at the
/// smallest value a fit takes), exactly: not through σ/T's logarithm.
pub(super) fn domain_of(layout: &Layout, i: usize) -> (f64, f64) {
    attainable_domain(layout.names[i])
}
