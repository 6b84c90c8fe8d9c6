//! A point of the free objective as a fitted model: its parameters
//! ([`ModelParams`]), and its estimate (Δ_RMS and the normalised fitted
//! model) from the columns there, without evaluating the model again.

use super::layout::Layout;
use super::model::{Columns, FreeModel};
use super::problem::{Point, Problem};
use crate::estimate::Estimate;
use crate::fitted::{FittedModel, ModelParams};
use crate::model::Model;
use crate::scene::Scene;

/// `model`'s parameters at `point` of `problem`: each reported one at its
/// place in the objective (σ/T kept in the box exactly: exp(ln x) can miss
/// x by an ulp), the ones a fit holds (Ragheb–Hancock's a) at 0.
pub fn params_at<M: FreeModel>(
    problem: &Problem<M>,
    layout: &Layout,
    model: Model,
    point: &Point,
) -> ModelParams {
    ModelParams::from_values(model, |p| {
        layout
            .names
            .iter()
            .position(|&name| name == p)
            .map_or(0.0, |i| layout.coordinates[i].value(point, problem))
    })
}

/// The estimate of `model` at `point`, whose columns are `columns`, with
/// `parameters` fitted parameters.
pub fn estimate_at<M: FreeModel>(
    scene: &Scene,
    (problem, layout): (&Problem<M>, &Layout),
    (model, parameters): (Model, usize),
    point: &Point,
    columns: &Columns,
) -> Estimate {
    let fitted = FittedModel::with_amplitude(
        model,
        params_at(problem, layout, model, point),
        point.linear.amplitude(),
        scene.data_scale(),
    );
    Estimate::of_raw(scene, fitted, &raw_terms(columns), parameters)
        .expect("the box lies inside the model's domain")
}

/// The model's raw terms (`[S, U]`, or `[L, 0]` for a one-column model)
/// from its columns at a point: an [`Estimate`] without evaluating the
/// model again.
fn raw_terms(Columns { s, u }: &Columns) -> Vec<[f64; 2]> {
    (0..s.len())
        .map(|k| [s[k], u.get(k).copied().unwrap_or(0.0)])
        .collect()
}
