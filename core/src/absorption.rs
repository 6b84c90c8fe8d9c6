//! Absorption in the subsurface layer (eqs. 9–11, 14; docs/conventions.md §3).
//!
//! `A = a cos²θ (1 − f)`, so the transmission left after reflection and
//! absorption is `1 − f − A = (1 − f)(1 − a cos²θ)`: at `a = 0` the
//! attenuation factor is exactly 1 and the model is exactly Ragheb–Hancock.

use crate::fresnel::fresnel;
use crate::lane::Lane;

/// Absorbed fraction `A(a, θ) = a cos²θ (1 − f)` (eq. 10 with `θ = θi`,
/// `f = f(θi, n)`; eq. 11 with `θ = θs2 = θs` by eq. 14, `f = f(θs′, 1/n)`).
#[inline]
#[must_use]
pub fn absorbed<L: Lane>(a: L, cos: L, fresnel: L) -> L {
    a * (cos * cos) * (L::c(1.0) - fresnel)
}

/// Attenuation `1 − a cos²θ`: the factor that absorption multiplies the
/// Fresnel transmission `1 − f` by. Depends on geometry and `a` only, so a
/// search computes it once per `a`.
#[inline]
#[must_use]
pub fn attenuation<L: Lane>(a: L, cos: L) -> L {
    L::c(1.0) - a * (cos * cos)
}

/// Transmitted fraction `T = 1 − f − A = (1 − f)(1 − a cos²θ)` (eq. 9).
#[inline]
#[must_use]
pub fn transmitted<L: Lane>(a: L, cos: L, fresnel: L) -> L {
    (L::c(1.0) - fresnel) * attenuation(a, cos)
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

/// `R`, `T` and `A` at incidence `cos θ` for index `n` and absorption `a`
/// (eq. 9, `R + T + A = 1`; Fig. 2 plots `T` and `A` against θ for n = 1.7).
#[inline]
#[must_use]
pub fn energy_budget<L: Lane>(cos: L, n: L, a: L) -> EnergyBudget<L> {
    let reflected = fresnel(cos, n);
    EnergyBudget {
        reflected,
        transmitted: transmitted(a, cos, reflected),
        absorbed: absorbed(a, cos, reflected),
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
            assert_eq!(b.transmitted, 1.0 - b.reflected);
            assert_eq!(b.absorbed, 0.0);
        }
    }
}
