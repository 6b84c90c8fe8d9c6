//! The layered models' start of the refinement beside the grid's basins:
//! just above the face n = 1 (docs/conventions.md §11b).

use super::{GridAxes, GridValues};
use crate::free::model::{FreeModel, LayeredModel};
use crate::free::problem::Problem;
use crate::model::Param;

/// How far above the face n = 1 [`corner_start`] starts, as a fraction of
/// the least `cos²` of the measurements' directions: the refracted cosine
/// `√(n² − 1 + cos²θ)/n` of that direction has moved by about 1% of itself
/// there. The lower points found in the valley lay at 0.5% to 2.6% of it
/// (docs/conventions.md §11b).
const CORNER: f64 = 0.01;

/// A start just above the face n = 1 (docs/conventions.md §11b), on a box
/// whose n reaches 1. At n = 1 and a = 0 the layer's term is the surface's
/// own; just above, it moves fastest near grazing, so a narrow valley with
/// β near 1 runs from that face between the grid's columns, and a
/// minimisation that reaches the face stays there. The start is the σ/T of
/// the grid's best point on that face (a at its lower face), a at its
/// lower face and n at [`CORNER`] of the least `cos²` above 1 (and the
/// untied models' σ′/T′ that point's).
pub fn corner_start(
    problem: &Problem<LayeredModel>,
    axes: &GridAxes,
    values: &GridValues,
) -> Option<Vec<f64>> {
    let table = problem.model.table();
    let place = |p: Param| table.position(p).expect("a layered model's parameter");
    let (slope_at, sub_at, n_at, a_at) = (
        place(Param::Slope),
        table.position(Param::SubSlope),
        place(Param::N),
        table.position(Param::A),
    );
    let (lo, hi) = problem.bounds[n_at];
    let (cos2_i, cos2_s) = problem.model.cosines();
    let least = cos2_i
        .iter()
        .chain(cos2_s)
        .filter(|c| **c > 0.0)
        .fold(f64::INFINITY, |m, &c| m.min(c));
    if lo != 1.0 || !least.is_finite() {
        return None;
    }
    // The grid indices of the face: n at 1, a (when fitted) at its lower face.
    let mut face = vec![0; axes.axes.len()];
    face[n_at] = axes.axes[n_at].iter().position(|&v| v == lo)?;
    if let Some(j) = a_at {
        let a_lo = problem.bounds[j].0;
        face[j] = axes.axes[j].iter().position(|&v| v == a_lo)?;
    }
    // The best grid point on that face over σ/T (and σ′/T′ for the untied
    // models), in the grid's order.
    let subs = sub_at.map_or(1, |j| axes.axes[j].len());
    let best = (0..axes.axes[slope_at].len())
        .flat_map(|s| (0..subs).map(move |t| (s, t)))
        .map(|(s, t)| {
            let mut point = face.clone();
            point[slope_at] = s;
            if let Some(j) = sub_at {
                point[j] = t;
            }
            values.flat(&point)
        })
        .min_by(|&f, &g| values.sse[f].total_cmp(&values.sse[g]))?;
    let mut start = axes.theta(&values.indices(best));
    start[n_at] = (1.0 + CORNER * least).min(hi);
    Some(start)
}
