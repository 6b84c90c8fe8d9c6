//! What releasing a face of the box gives (docs/estimation.md): for a
//! reported parameter on a face of the box that is not a bound of its
//! domain, one local fit from the minimum with that bound moved out to
//! the domain's, a diagnostic beside the estimate.

use super::Solution;
use crate::free::coordinate::Coordinate;
use crate::free::estimate::estimate_at;
use crate::free::model::FreeModel;
use crate::free::refine::{minimise, SCREENING};
use crate::report::Released;
use crate::scene::Scene;

/// Which face of its box reported parameter `i` is on, when that face is
/// not a bound of its domain: `Some(true)` the upper, `Some(false)` the
/// lower.
pub fn releasable_face<M: FreeModel>(solution: &Solution<'_, M>, i: usize) -> Option<bool> {
    let (lo, hi) = solution.bounds(i);
    let (dlo, dhi) = solution.domain(i);
    let v = solution.value(i);
    if v <= lo && lo > dlo {
        Some(false)
    } else if v >= hi && hi < dhi {
        Some(true)
    } else {
        None
    }
}

/// The fit of `scene` from `solution`'s minimum with reported parameter
/// `i`'s bound on the upper (`at_upper`) or lower face released to its
/// domain's; `rms_in_box` is the fit's own Δ_RMS, to compare.
pub fn release<M: FreeModel>(
    solution: &Solution<'_, M>,
    scene: &Scene,
    (i, at_upper): (usize, bool),
    rms_in_box: f64,
) -> Released {
    let Solution {
        problem,
        layout,
        minimum,
    } = solution;
    let coordinate = layout.coordinates[i];
    let mut wider = (*problem).clone();
    match coordinate {
        Coordinate::Nonlinear { j, .. } => {
            let (dlo, dhi) = layout.domain[j];
            let (rlo, rhi) = solution.domain(i);
            if at_upper {
                wider.bounds[j].1 = dhi;
                wider.reported[j].1 = rhi;
            } else {
                wider.bounds[j].0 = dlo;
                wider.reported[j].0 = rlo;
            }
        }
        Coordinate::Beta => {
            if at_upper {
                wider.beta.1 = 1.0;
            } else {
                wider.beta.0 = 0.0;
            }
        }
    }
    let free = wider.all_free();
    let point = minimise(&wider, &minimum.theta, &free, wider.beta, SCREENING).point;
    let model = (wider.model.model(), wider.parameter_count());
    let columns = wider.model.columns(&point.theta);
    let e = estimate_at(scene, (&wider, layout), model, &point, &columns);
    Released {
        value: coordinate.value(&point, &wider),
        rms: e.rms,
        rms_in_box,
    }
}
