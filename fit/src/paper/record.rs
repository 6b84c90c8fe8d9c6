//! What a paper-objective fit reports after its grid search
//! (docs/conventions.md §11): the refined estimate ([`super::refine`]),
//! then each searched parameter's refined value, intervals and flags
//! ([`super::intervals`], [`crate::edges`]).

use super::intervals::{
    grid_profile, jacobian_covariance, jacobian_intervals, noise_variance, Probe,
};
use super::objective::SumOfSquares;
use super::refine::{grid_steps, refine, starts};
use crate::analysis::{Analysis, Uncertainty};
use crate::covariance::Covariance;
use crate::edges::{flags, Edge};
use crate::estimate::Estimate;
use crate::model::{at_bound, Model, Param};
use crate::paper::search::{GridProfile, Searched};
use crate::report::{Parameter, Source};
use crate::scene::Scene;
use rayon::prelude::*;

/// What [`analyse`] adds to a fit.
pub(crate) struct Analysed {
    pub refined: Option<Estimate>,
    pub parameters: Vec<Parameter>,
    pub covariance: Option<Covariance>,
}

/// Refines and measures the uncertainty of `model`'s grid best `best` on
/// `scene` (refining also from `rh`, the best of the a = 0 slice).
/// `searched` lists the searched axes; `profile` is the grid's profile
/// (over all the grid's axes, of lengths `lens`) when
/// [`Analysis::needs_profile`], computed with
/// [`super::intervals::cutoffs`].
pub(crate) fn analyse(
    scene: &Scene,
    model: Model,
    (best, rh): (&Estimate, Option<&Estimate>),
    searched: &[Searched],
    profile: Option<(&GridProfile, &[usize])>,
    analysis: Analysis,
) -> Analysed {
    if analysis == Analysis::NONE {
        // The grid search alone: the grid values' flags, and no model
        // evaluation (batches of pixels take this path).
        let parameters = model
            .free_params()
            .iter()
            .filter_map(|&name| axis_of(searched, name).map(grid_parameter))
            .collect();
        return Analysed {
            refined: None,
            parameters,
            covariance: None,
        };
    }
    let objective = SumOfSquares::new(scene, model);
    let steps = grid_steps(&objective, searched);
    let x_grid = objective.values(best.params());
    let (x, sse, refined) = if analysis.refine {
        let rh = rh.map(|rh| objective.values(rh.params()));
        let starts = starts(&x_grid, profile, searched, (&objective, rh));
        let r = refine(&objective, &starts, &steps);
        let estimate = Estimate::new(scene, model, objective.params(&r.x))
            .expect("refined values are projected onto the domain");
        // Never worse than the grid (the refinement starts there; a tie in
        // the last bit keeps the grid's point).
        if estimate.rms <= best.rms {
            (r.x, r.sse, Some(estimate))
        } else {
            let sse = objective.sse(&x_grid);
            (x_grid, sse, Some(best.clone()))
        }
    } else {
        let sse = objective.sse(&x_grid);
        (x_grid, sse, None)
    };

    let s2 = noise_variance(scene, sse, x.len());
    // The covariance also guides the profile's probes, so it is computed
    // for either kind of uncertainty and reported for the Jacobian's.
    let covariance = s2
        .filter(|_| analysis.uncertainty != Uncertainty::Off)
        .and_then(|s2| jacobian_covariance(&objective, &x, s2));
    let probe = s2.map(|s2| Probe {
        objective: &objective,
        covariance: covariance.as_ref(),
        x: &x,
        sse,
        s2,
        steps: &steps,
    });
    // Each parameter's interval is independent of the others': they run in
    // parallel, collected in parameter order.
    let parameters: Vec<Parameter> = objective
        .names()
        .par_iter()
        .enumerate()
        .filter_map(|(i, &name)| {
            let s = axis_of(searched, name)?;
            let mut p = grid_parameter(s);
            if analysis.refine {
                // domain_bound describes the value reported: the refined one.
                p.refined = Some(x[i]);
                p.flags.retain(|&f| f != Edge::DomainBound);
                if at_bound(name, x[i]) {
                    p.flags.push(Edge::DomainBound);
                }
            }
            if analysis.uncertainty.jacobian() {
                p.sd = covariance.as_ref().map(|c| c.sd(i));
            }
            let intervals = match &probe {
                Some(probe) if analysis.uncertainty.profile() => {
                    let grid = profile.map(|(g, _)| grid_profile(s, g));
                    Some((probe.intervals(i, range(s), grid), Source::Profile))
                }
                _ => p.sd.map(|sd| {
                    let domain = objective.bounds()[i];
                    (jacobian_intervals(x[i], sd, domain), Source::Jacobian)
                }),
            };
            if let Some((intervals, source)) = intervals {
                p.set_intervals(intervals, source);
            }
            Some(p)
        })
        .collect();
    Analysed {
        refined,
        parameters,
        covariance: covariance.filter(|_| analysis.uncertainty.jacobian()),
    }
}

/// The searched axis of parameter `name`.
fn axis_of<'s, 'a>(searched: &'s [Searched<'a>], name: Param) -> Option<&'s Searched<'a>> {
    searched.iter().find(|s| s.name == name)
}

/// The first and last values of a searched axis, in increasing order.
fn range(s: &Searched) -> (f64, f64) {
    s.values
        .values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        })
}

/// A searched parameter with its grid value and that value's flags.
fn grid_parameter(s: &Searched) -> Parameter {
    Parameter {
        flags: flags(s.name, s.value, s.values),
        ..Parameter::new(s.name, s.value)
    }
}
