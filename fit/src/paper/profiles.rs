//! The profiles of a reported paper-objective fit, for figures
//! (`laminar report`): the grid's and the continuous profile of each
//! parameter on the `Δχ²` scale.

use super::intervals::{
    grid_profile as grid_profile_of, jacobian_covariance, noise_variance, path_start,
};
use super::objective::SumOfSquares;
use super::refine::{grid_steps, profile_at};
use crate::paper::search::{GridProfile, Searched};
use crate::report::Fit;
use crate::scene::Scene;

/// A parameter's profile for a figure, on the `Δχ²` scale
/// `(Σ (D − P)² − min) / s²` ([`crate::Fitter::profiles`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ProfileCurve {
    /// The parameter's name.
    pub name: String,
    /// The grid's profile (the smallest objective over the grid values of
    /// the other parameters) at each axis value in the plotted range whose
    /// profile was computed, as (value, Δχ²).
    pub grid: Vec<(f64, f64)>,
    /// The continuous profile (minimised over the other parameters by
    /// Nelder–Mead) at evenly spaced values, as (value, Δχ²).
    pub refined: Vec<(f64, f64)>,
    /// The estimate (refined value).
    pub estimate: f64,
}

/// The profiles of every parameter of `fit` with a 95% interval, over its
/// interval widened by half its width each side (within the domain), with
/// `points` values on the refined curve. `profile` is the grid's
/// profile over axes `searched`.
pub(crate) fn profile_curves(
    scene: &Scene,
    fit: &Fit,
    searched: &[Searched],
    profile: &GridProfile,
    points: usize,
) -> Vec<ProfileCurve> {
    let objective = SumOfSquares::new(scene, fit.model);
    let names = objective.names().to_vec();
    let x = objective.values(fit.estimate().params());
    let sse = objective.sse(&x);
    let Some(s2) = noise_variance(scene, sse, names.len()).filter(|&s2| s2 > 0.0) else {
        return Vec::new();
    };
    let covariance = jacobian_covariance(&objective, &x, s2);
    let steps = grid_steps(&objective, searched);
    let mut out = Vec::new();
    for (i, &name) in names.iter().enumerate() {
        let (Some(s), Some(p)) = (
            searched.iter().find(|s| s.name == name),
            fit.parameters.iter().find(|p| p.name == name),
        ) else {
            continue;
        };
        let Some(i95) = p.interval95 else { continue };
        let (lo_d, hi_d) = objective.bounds()[i];
        let width = (i95.hi - i95.lo).max(steps[i]);
        let (lo, hi) = (
            (i95.lo - width / 2.0).max(lo_d),
            (i95.hi + width / 2.0).min(hi_d),
        );
        let scale = |e: f64| (e - sse) / s2;
        let grid = grid_profile_of(s, profile)
            .points
            .into_iter()
            .filter(|&(v, e)| v >= lo && v <= hi && e.is_finite())
            .map(|(v, e)| (v, scale(e)))
            .collect();
        let refined = (0..points)
            .map(|k| {
                let v = lo + (hi - lo) * k as f64 / (points - 1).max(1) as f64;
                let start = path_start(&x, covariance.as_ref(), i, v);
                (v, scale(profile_at(&objective, i, v, &start, &steps).sse))
            })
            .collect();
        out.push(ProfileCurve {
            name: name.to_string(),
            grid,
            refined,
            estimate: x[i],
        });
    }
    out
}
