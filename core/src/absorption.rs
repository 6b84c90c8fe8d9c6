//! Absorption in the subsurface layer (eqs. 9–11, 14; docs/conventions.md §3).
//!
//! `A = a cos²θ (1 − f)`, so the transmission left after reflection and
//! absorption is `1 − f − A = (1 − f)(1 − a cos²θ)`: at `a = 0` the
//! attenuation factor is exactly 1 and the model is exactly Ragheb–Hancock.

use crate::fresnel::{fresnel_pair, refract_cos};
use crate::lane::Lane;

/// Absorbed fraction `A(a, θ) = a cos²θ (1 − f)` (eq. 10 with `θ = θi`,
/// `f = f(θi, n)`; eq. 11 with `θ = θs2 = θs` by eq. 14, `f = f(θs′, 1/n)`),
/// from the transmittance `1 − f` ([`crate::fresnel::fresnel_pair`]).
/// Accuracy (crate docs, Accuracy): within 4.8 ulps (f64) and 4.9 (f32).
#[inline]
#[must_use]
pub fn absorbed<L: Lane>(a: L, cos: L, transmittance: L) -> L {
    a * (cos * cos) * transmittance
}

/// Attenuation `1 − a cos²θ`: the factor that absorption multiplies the
/// Fresnel transmission `1 − f` by, evaluated as `(1 − a) + a sin²θ` from
/// `sin²θ`: a sum of two non-negative terms, so it keeps its relative
/// accuracy as `a → 1` at normal incidence (where `1 − a cos²θ` cancels).
/// Depends on geometry and `a` only, so a search computes it once per `a`.
#[inline]
#[must_use]
pub fn attenuation<L: Lane>(a: L, sin2: L) -> L {
    (L::c(1.0) - a) + a * sin2
}

/// Transmitted fraction `T = 1 − f − A = (1 − f)(1 − a cos²θ)` (eq. 9).
#[inline]
#[must_use]
pub fn transmitted<L: Lane>(a: L, sin2: L, transmittance: L) -> L {
    transmittance * attenuation(a, sin2)
}

/// Energy budget of light entering from air (the curves of Fig. 2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergyBudget<L> {
    /// Reflected fraction `R = f(θ, n)`.
    pub reflected: L,
    /// Transmitted fraction `T = (1 − R)(1 − a cos²θ)`.
    pub transmitted: L,
    /// Absorbed fraction `A = a cos²θ (1 − R)`.
    pub absorbed: L,
}

/// `R`, `T` and `A` at incidence `cos θ` for index `n ≥ 1` and absorption
/// `a` (eq. 9, `R + T + A = 1`; Fig. 2 plots `T` and `A` against θ for
/// n = 1.7). `sin²θ` is formed as `(1 − cos θ)(1 + cos θ)` here, so `T`
/// loses relative accuracy near normal incidence as `a → 1`; the model
/// itself uses `sin²θ` from the angle ([`crate::Geometry`]).
#[inline]
#[must_use]
pub fn energy_budget<L: Lane>(cos: L, n: L, a: L) -> EnergyBudget<L> {
    let (cos_t, _) = refract_cos(cos, n);
    let (reflected, transmittance) = fresnel_pair(cos, cos_t, n);
    let one = L::c(1.0);
    let sin2 = (one - cos) * (one + cos);
    EnergyBudget {
        reflected,
        transmitted: transmitted(a, sin2, transmittance),
        absorbed: absorbed(a, cos, transmittance),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn full_absorption_at_normal_incidence_transmits_nothing() {
        let b = energy_budget(1.0f64, 1.5, 1.0);
        assert_eq!(b.transmitted, 0.0);
        assert!((b.absorbed - 0.96).abs() < 1e-15);
    }

    #[test]
    fn zero_absorption_is_exactly_fresnel_transmission() {
        for &c in &[0.0f32, 0.2, 0.9, 1.0] {
            let b = energy_budget(c, 1.4, 0.0);
            let (cos_t, _) = refract_cos(c, 1.4);
            // Exactly the transmittance (attenuation 1), which is 1 − f up
            // to its rounding (computed without the subtraction).
            assert_eq!(b.transmitted, fresnel_pair(c, cos_t, 1.4).1);
            assert!((b.transmitted - (1.0 - b.reflected)).abs() <= 2.0 * f32::EPSILON);
            assert_eq!(b.absorbed, 0.0);
        }
    }
}
