//! Jensen et al. 2001 BRDF approximation: dipole diffusion plus single
//! scattering (docs/conventions.md §7).
//!
//! `f = (1/π) Ft(θi) R_d Ft(θs) + α′ Ft(θi) Ft(θs) p / (cos θi′ + cos θs′)`,
//! isotropic phase `p = 1/(4π)`, `η = 1.3`, `Ft = 1 − f(·, η)`; radiance `f cos θi`.

use crate::error::{check_param, InputError};
use crate::exp::exp;
use crate::fresnel::{refract_cos, transmittance_from_cosines};
use crate::geometry::Angles;
use crate::lane::{Lane, Real};
use crate::param::Param;
use core::f64::consts::PI;

/// Relative refractive index η of the Jensen baseline (docs/conventions.md §7).
pub const JENSEN_ETA: f64 = 1.3;

/// Per-geometry terms of the Jensen model, computed once per scene.
#[derive(Clone, Copy, Debug)]
pub struct JensenGeometry<L> {
    /// `cos θi · Ft(θi) · Ft(θs)`.
    pub weight: L,
    /// `1 / (cos θi′ + cos θs′)` (refracted cosines, η = 1.3).
    pub inv_cos_sum: L,
}

impl<L: Lane> JensenGeometry<L> {
    /// Lane `i` from `angles(i)`; cosines in `f64` (libm), rounded once.
    pub fn from_lanes(mut angles: impl FnMut(usize) -> Angles) -> Self {
        let mut a = [(0.0f64, 0.0f64); 8];
        for (i, slot) in a.iter_mut().enumerate().take(L::LANES) {
            let g = angles(i);
            *slot = (
                libm::cos(g.theta_i()).clamp(0.0, 1.0),
                libm::cos(g.theta_s()).clamp(0.0, 1.0),
            );
        }
        let ci = L::from_f64_lanes(|i| a[i].0);
        let cs = L::from_f64_lanes(|i| a[i].1);
        let eta = L::c(JENSEN_ETA);
        let one = L::c(1.0);
        let (ti, _) = refract_cos(ci, eta);
        let (ts, _) = refract_cos(cs, eta);
        let ft_i = transmittance_from_cosines(ci, ti, eta);
        let ft_s = transmittance_from_cosines(cs, ts, eta);
        Self {
            weight: ci * ft_i * ft_s,
            inv_cos_sum: one / (ti + ts),
        }
    }
}

/// Parameter-only coefficients of the Jensen model for `(σa, σs′)`, in the
/// scalar precision of the lanes; computed once per parameter pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JensenCoefficients<S> {
    /// `R_d / π` (diffusion term).
    pub diffuse: S,
    /// `α′ p = α′ / (4π)` (single scattering).
    pub single: S,
}

impl<S: Real> JensenCoefficients<S> {
    /// Validates `σa, σs′ ∈ (0, 100]` (mm⁻¹ in the paper's grid 0.01…1) and
    /// computes `α′ = σs′/(σa + σs′)`,
    /// `R_d = (α′/2)(1 + e^{−(4/3) A √(3(1−α′))}) e^{−√(3(1−α′))}`,
    /// `A = (1 + F_dr)/(1 − F_dr)`, `F_dr = −1.440/η² + 0.710/η + 0.668 + 0.0636 η`.
    ///
    /// # Errors
    /// [`InputError::OutOfRange`] naming `sigma_a` or `sigma_s` when it is
    /// outside `(0, 100]` or NaN.
    pub fn new(sigma_a: f64, sigma_s_prime: f64) -> Result<Self, InputError> {
        check_param(Param::SigmaA, sigma_a)?;
        check_param(Param::SigmaS, sigma_s_prime)?;
        let (sa, ss) = (S::from_f64(sigma_a), S::from_f64(sigma_s_prime));
        let eta = S::from_f64(JENSEN_ETA);
        let c = S::c;
        let f_dr = c(-1.440) / (eta * eta) + c(0.710) / eta + c(0.668) + c(0.0636) * eta;
        let big_a = (c(1.0) + f_dr) / (c(1.0) - f_dr);
        let alpha = ss / (sa + ss);
        let root = (c(3.0) * (c(1.0) - alpha)).sqrt();
        let rd = c(0.5)
            * alpha
            * (c(1.0) + exp(c(0.0) - c(4.0 / 3.0) * big_a * root))
            * exp(c(0.0) - root);
        Ok(Self {
            diffuse: rd / c(PI),
            single: alpha / c(4.0 * PI),
        })
    }
}

/// Jensen radiance `f · cos θi` (docs/conventions.md §7), un-normalised.
#[inline]
#[must_use]
pub fn jensen_radiance<L: Lane>(g: &JensenGeometry<L>, k: &JensenCoefficients<L::Scalar>) -> L {
    g.weight * (L::splat(k.diffuse) + L::splat(k.single) * g.inv_cos_sum)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_non_positive_coefficients() {
        assert!(JensenCoefficients::<f64>::new(0.0, 0.5).is_err());
        assert!(JensenCoefficients::<f64>::new(0.5, f64::NAN).is_err());
    }

    #[test]
    fn normal_incidence_value() {
        let g = JensenGeometry::<f64>::from_lanes(|_| Angles::new(0.0, 0.0, 0.0).unwrap());
        let k = JensenCoefficients::<f64>::new(0.1, 0.9).unwrap();
        let ft = 1.0 - (0.3f64 / 2.3).powi(2);
        let alpha: f64 = 0.9;
        let f_dr = -1.44 / 1.69 + 0.71 / 1.3 + 0.668 + 0.0636 * 1.3;
        let big_a = (1.0 + f_dr) / (1.0 - f_dr);
        let root = (3.0 * (1.0 - alpha)).sqrt();
        let rd = 0.5 * alpha * (1.0 + (-4.0 / 3.0 * big_a * root).exp()) * (-root).exp();
        let want = ft * ft * (rd / PI + alpha / (4.0 * PI) / 2.0);
        let got = jensen_radiance(&g, &k);
        assert!((got - want).abs() < 1e-14 * want, "{got} vs {want}");
    }
}
