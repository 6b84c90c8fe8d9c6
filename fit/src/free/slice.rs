//! The Ragheb–Hancock best of an absorptive model's box (a = 0), reported
//! beside its fit: the a = 0 slice's best grid point, refined with a held
//! at 0.

use super::estimate::estimate_at;
use super::layout::Layout;
use super::model::FreeModel;
use super::problem::Problem;
use super::refine::{minimise, SCREENING};
use super::search::GridValues;
use crate::estimate::Estimate;
use crate::model::Param;
use crate::scene::Scene;

/// The Ragheb–Hancock best of the box when the model has a
/// Ragheb–Hancock variant and 0 is on its a axis: the a = 0 slice's best
/// grid point (the first on ties), refined with a held at 0 when `refine`.
pub fn ragheb_hancock<M: FreeModel>(
    scene: &Scene,
    (problem, layout): (&Problem<M>, &Layout),
    values: &GridValues,
    refine: bool,
) -> Option<Estimate> {
    let rh_model = problem.model.model().ragheb_hancock()?;
    let a_at = layout.axes.position(Param::A)?;
    let zero_a = layout.axes.axes[a_at].iter().position(|&v| v == 0.0)?;
    let slice = values
        .slice(a_at, zero_a)
        .fold(None, |b: Option<usize>, f| match b {
            Some(g) if values.sse[g] <= values.sse[f] => Some(g),
            _ => Some(f),
        })?;
    let theta = layout.axes.theta(&values.indices(slice));
    let (mut point, mut columns) = problem.evaluate(&theta, problem.beta);
    if refine {
        // A side result reported by its rms: the screening tolerance (10⁻⁶
        // of the objective) fixes that to about 5·10⁻⁷ of itself.
        let free = problem.model.table().hold(Param::A);
        point = minimise(problem, &point.theta, &free, problem.beta, SCREENING).point;
        columns = problem.model.columns(&point.theta);
    }
    let parameters = problem.parameter_count() - 1;
    Some(estimate_at(
        scene,
        (problem, layout),
        (rh_model, parameters),
        &point,
        &columns,
    ))
}
