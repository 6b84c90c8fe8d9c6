//! Energy of a fitted model: its directional albedo
//! `ρ(θv) = ∫ f(ωi, ωv) cos θi dωi` over the light's hemisphere
//! (docs/conventions.md §12).
//!
//! A fitted model predicts radiance `f · cos θi` in the input's units
//! ([`FittedModel::predict_radiance`]), so `ρ(θv)` is the integral of the
//! prediction over the solid angle of the light, `∫₀¹ dμ ∫₋π^π dφs` with
//! `μ = cos θi`. The model is even in φs (eqs. 1–14 see φs through
//! `cos φs` and `sin² φs`), so the φs integral is twice that over [0, π].
//! Both are Gauss–Legendre rules (the `gauss-quad` crate) of `n` nodes,
//! with `n` doubled from 16 until two successive values agree to the
//! tolerance; the error stated is that last difference (a bound on the
//! coarser rule's error, and in practice far above the finer one's).
//!
//! `ρ ≤ 1` is energy conservation only for a BRDF in absolute units
//! (sr⁻¹); for data on an arbitrary scale (a camera's counts, CUReT's
//! relative BRDF) `ρ` has the data's units and no bound.

use crate::error::ModelError;
use crate::fitted::FittedModel;
use gauss_quad::legendre::GaussLegendre;
use laminar_brdf_core::Angles;
use thiserror::Error;

/// The relative tolerance of the quadrature: two successive rules must
/// agree within it. Checked once here, for every front end: from
/// [`Tolerance::FINEST`] up to (not including) 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance(f64);

/// A tolerance outside `[Tolerance::FINEST, 1)`.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[error("tolerance {0:?}: give a relative tolerance from 1e-12 up to (not including) 1")]
pub struct ToleranceError(pub f64);

impl Tolerance {
    /// The finest tolerance: two rules of up to a million terms each,
    /// summed in f64, round at about 10⁻¹³ of their value, so a finer
    /// target could only run to [`MOST_NODES`] and stop unmet.
    pub const FINEST: f64 = 1e-12;

    /// Every front end's default, 10⁻⁶.
    pub const DEFAULT: Tolerance = Tolerance(1e-6);

    /// `tolerance`, checked.
    ///
    /// # Errors
    /// [`ToleranceError`] for a value outside `[FINEST, 1)` or NaN.
    pub fn new(tolerance: f64) -> Result<Self, ToleranceError> {
        if (Self::FINEST..1.0).contains(&tolerance) {
            Ok(Self(tolerance))
        } else {
            Err(ToleranceError(tolerance))
        }
    }

    /// Its value.
    pub fn get(self) -> f64 {
        self.0
    }
}

/// The directional albedo at one view angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Albedo {
    /// View polar angle θv (radians).
    pub theta_v: f64,
    /// `ρ(θv)`, in the input's units (see the module docs).
    pub albedo: f64,
    /// The estimated quadrature error: `|ρ_n − ρ_{n/2}|`.
    pub error: f64,
    /// Nodes per dimension of the rule `ρ` comes from (`n²/…` evaluations:
    /// `n` in μ times `n` in φs).
    pub nodes: usize,
}

/// Nodes of the first rule; each refinement doubles them.
const FIRST_NODES: usize = 16;

/// Most nodes per dimension (a rule of `MOST_NODES²` evaluations).
pub const MOST_NODES: usize = 1024;

/// `ρ(θv)` of `model` (module docs), refined until two successive rules
/// agree within `tolerance · ρ` (relative; at most [`MOST_NODES`] nodes
/// per dimension, after which the error says how far it got).
///
/// ```
/// use laminar_brdf_fit::albedo::{directional_albedo, Tolerance};
/// use laminar_brdf_fit::{Baseline, FittedModel, Model, ModelParams};
/// // Oren–Nayar at σ = 0 is Lambertian, ρ/π · cos θi: its albedo is ρ
/// // (here times the amplitude 1.5 and the data's scale 2).
/// let params = ModelParams::baseline(Baseline::OrenNayar, [0.0, 0.8]);
/// let lambert = FittedModel::with_amplitude(Model::OrenNayar, params, 1.5, 2.0);
/// let a = directional_albedo(&lambert, 0.7, Tolerance::new(1e-10)?)?;
/// assert!((a.albedo - 2.4).abs() < 1e-12 && a.error < 1e-10);
/// assert!(Tolerance::new(0.0).is_err() && Tolerance::new(1e-300).is_err());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`ModelError`] when θv is outside `[0, π/2]`, or the model cannot
/// predict (its parameters or constants; a prediction that is not finite).
pub fn directional_albedo(
    model: &FittedModel,
    theta_v: f64,
    tolerance: Tolerance,
) -> Result<Albedo, ModelError> {
    let tolerance = tolerance.get();
    let mut nodes = FIRST_NODES;
    let mut previous = rule(model, theta_v, nodes)?;
    loop {
        let next = rule(model, theta_v, 2 * nodes)?;
        nodes *= 2;
        let error = (next - previous).abs();
        if error <= tolerance * next.abs() || nodes >= MOST_NODES {
            return Ok(Albedo {
                theta_v,
                albedo: next,
                error,
                nodes,
            });
        }
        previous = next;
    }
}

/// The `n × n` Gauss–Legendre rule of `ρ(θv)`.
fn rule(model: &FittedModel, theta_v: f64, n: usize) -> Result<f64, ModelError> {
    let quadrature =
        GaussLegendre::new(core::num::NonZeroUsize::new(n).unwrap_or(core::num::NonZeroUsize::MIN));
    // Nodes and weights on [0, 1] (μ) and [0, π] (φs), from [−1, 1].
    let on = |lo: f64, hi: f64| -> Vec<(f64, f64)> {
        let half = 0.5 * (hi - lo);
        quadrature
            .as_node_weight_pairs()
            .iter()
            .map(|&(x, w)| (lo + half * (x + 1.0), half * w))
            .collect()
    };
    let (mu, phi) = (on(0.0, 1.0), on(0.0, core::f64::consts::PI));
    let mut angles = Vec::with_capacity(n * n);
    for &(m, _) in &mu {
        for &(p, _) in &phi {
            angles.push(Angles::new(libm::acos(m), theta_v, p).map_err(ModelError::OutOfDomain)?);
        }
    }
    let values = model.predict_radiance(&angles)?;
    let mut sum = 0.0;
    for (i, &(_, wm)) in mu.iter().enumerate() {
        for (j, &(_, wp)) in phi.iter().enumerate() {
            sum += wm * wp * values[i * n + j];
        }
    }
    Ok(2.0 * sum)
}

/// [`directional_albedo`] at each of `theta_v`.
///
/// # Errors
/// As [`directional_albedo`], for the first angle that fails.
pub fn albedo_table(
    model: &FittedModel,
    theta_v: &[f64],
    tolerance: Tolerance,
) -> Result<Vec<Albedo>, ModelError> {
    theta_v
        .iter()
        .map(|&t| directional_albedo(model, t, tolerance))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Baseline, Model, ModelParams};

    /// Against an independent rule: a midpoint sum in (θi, φs) of the
    /// solid angle (`sin θi dθi dφs`), fine enough for 1e-4, on the
    /// layered models and both baselines, sharp and broad lobes.
    #[test]
    fn albedo_agrees_with_a_midpoint_sum_and_states_its_error() {
        let layered = |slope, beta, n, a| ModelParams::Layered {
            slope,
            beta,
            n,
            a,
            sub_slope: None,
        };
        let cases = [
            (Model::Exp, layered(1.2, 0.4, 1.45, 0.2)),
            (Model::Gauss, layered(0.6, 0.3, 1.3, 0.5)),
            (Model::Exp, layered(0.25, 0.2, 1.5, 0.0)),
            (
                Model::Jensen,
                ModelParams::baseline(Baseline::Jensen, [0.3, 2.0]),
            ),
            (
                Model::OrenNayar,
                ModelParams::baseline(Baseline::OrenNayar, [0.4, 0.7]),
            ),
        ];
        for (model, params) in cases {
            let fitted = FittedModel::with_amplitude(model, params, 0.8, 1.0);
            for theta_v in [0.0, 0.6, 1.3] {
                let got =
                    directional_albedo(&fitted, theta_v, Tolerance::new(1e-9).unwrap()).unwrap();
                let steps = 1000;
                let (dt, dp) = (
                    core::f64::consts::FRAC_PI_2 / steps as f64,
                    core::f64::consts::PI / steps as f64,
                );
                let mut angles = Vec::new();
                let mut weights = Vec::new();
                for i in 0..steps {
                    let t = (i as f64 + 0.5) * dt;
                    for j in 0..steps {
                        let p = (j as f64 + 0.5) * dp;
                        angles.push(Angles::new(t, theta_v, p).unwrap());
                        weights.push(2.0 * libm::sin(t) * dt * dp);
                    }
                }
                let values = fitted.predict_radiance(&angles).unwrap();
                let want: f64 = values.iter().zip(&weights).map(|(v, w)| v * w).sum();
                let rel = (got.albedo - want).abs() / want;
                assert!(
                    rel < 1e-4,
                    "{model:?} θv {theta_v}: {} against {want} ({rel:e})",
                    got.albedo
                );
                assert!(got.error <= 1e-9 * got.albedo || got.nodes == MOST_NODES);
            }
        }
    }

    #[test]
    fn a_view_angle_out_of_range_is_an_error() {
        let params = ModelParams::baseline(Baseline::OrenNayar, [0.0, 0.5]);
        let fitted = FittedModel::with_amplitude(Model::OrenNayar, params, 1.0, 1.0);
        assert!(directional_albedo(&fitted, 2.0, Tolerance::new(1e-6).unwrap()).is_err());
        assert!(directional_albedo(&fitted, f64::NAN, Tolerance::new(1e-6).unwrap()).is_err());
    }
}
