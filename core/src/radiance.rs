//! Validated parameters, the per-component breakdown and the total radiance
//! of eq. 8.

use crate::absorption::absorbed;
use crate::error::{check_range, InputError};
use crate::geometry::Geometry;
use crate::lane::Lane;
use crate::subsurface::{absorption_factor, subsurface_base, Interface};
use crate::surface::{inverse_slope_squared, surface_radiance, Correlation};

/// Smallest accepted RMS slope σ/T. Below it `(T/σ)²` leaves the `f32` range.
pub const SLOPE_MIN: f64 = 1.0e-3;
/// Largest accepted RMS slope σ/T.
pub const SLOPE_MAX: f64 = 1.0e3;
/// Largest accepted refractive index.
pub const INDEX_MAX: f64 = 10.0;

/// Parameters of the absorptive model, validated once by [`Params::new`]:
/// RMS slope `σ/T = σ′/T′ ∈ [1e-3, 1e3]`, balance `β ∈ [0, 1]`, refractive
/// index `n ∈ [1, 10]`, absorption `a ∈ [0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    slope: f64,
    beta: f64,
    n: f64,
    a: f64,
}

impl Params {
    /// Validates and builds a parameter set; the error names the first
    /// parameter out of its domain (NaN is always out).
    ///
    /// # Errors
    /// [`InputError::OutOfRange`] naming the first parameter outside its domain.
    pub fn new(slope: f64, beta: f64, n: f64, a: f64) -> Result<Self, InputError> {
        Ok(Self {
            slope: check_range("slope", slope, SLOPE_MIN, SLOPE_MAX, "[1e-3, 1e3]")?,
            beta: check_range("beta", beta, 0.0, 1.0, "[0, 1]")?,
            n: check_range("n", n, 1.0, INDEX_MAX, "[1, 10]")?,
            a: check_range("a", a, 0.0, 1.0, "[0, 1]")?,
        })
    }
    /// RMS slope σ/T (also σ′/T′).
    #[must_use]
    pub fn slope(&self) -> f64 {
        self.slope
    }
    /// Balance β between subsurface and surface radiance.
    #[must_use]
    pub fn beta(&self) -> f64 {
        self.beta
    }
    /// Refractive index n of the upper layer.
    #[must_use]
    pub fn n(&self) -> f64 {
        self.n
    }
    /// Fractional absorption a (0: Ragheb–Hancock).
    #[must_use]
    pub fn a(&self) -> f64 {
        self.a
    }
}

/// Every term of the model at one geometry per lane (un-normalised, K = k = 1).
#[derive(Clone, Copy, Debug)]
pub struct Components<L> {
    /// `f(θi, n)` (eq. 6).
    pub fresnel_in: L,
    /// `f(θs′, 1/n)` (eq. 6).
    pub fresnel_out: L,
    /// `A1 = a cos²θi (1 − f(θi, n))` (eq. 10).
    pub absorb_in: L,
    /// `A2 = a cos²θs2 (1 − f(θs′, 1/n))` (eqs. 11, 14).
    pub absorb_out: L,
    /// Surface radiance `L^sf` (eq. 1 or 2).
    pub surface: L,
    /// Subsurface radiance `L^sb` (eq. 12 or 13).
    pub subsurface: L,
    /// Total radiance `β L^sb + (1 − β) L^sf` (eq. 8).
    pub total: L,
}

impl<L: Copy> Components<L> {
    /// Field names in [`Components::to_array`] order (the `laminar eval` CSV columns).
    pub const NAMES: [&'static str; 7] = [
        "fresnel_in",
        "fresnel_out",
        "absorb_in",
        "absorb_out",
        "surface",
        "subsurface",
        "total",
    ];

    /// The seven fields in [`Components::NAMES`] order.
    #[must_use]
    pub fn to_array(&self) -> [L; 7] {
        [
            self.fresnel_in,
            self.fresnel_out,
            self.absorb_in,
            self.absorb_out,
            self.surface,
            self.subsurface,
            self.total,
        ]
    }
}

/// Total radiance `β L^sb + (1 − β) L^sf` (eq. 8) from its two components.
#[inline]
#[must_use]
pub fn mix<L: Lane>(beta: L, subsurface: L, surface: L) -> L {
    beta * subsurface + (L::c(1.0) - beta) * surface
}

/// Evaluates every component of the model (eqs. 1–14) at `g`.
/// Accuracy per field: the table in the crate docs (Accuracy); `total`
/// within 9.9 ulps (f64) and 6.2 (f32), plus the Gaussian-tail allowance.
#[must_use]
pub fn components<L: Lane>(g: &Geometry<L>, corr: Correlation, p: &Params) -> Components<L> {
    let inv_slope2 = inverse_slope_squared(L::c(p.slope));
    let iface = Interface::new(g, L::c(p.n));
    let a = L::c(p.a);
    let surface = surface_radiance(g, corr, inv_slope2);
    let subsurface = subsurface_base(&iface, corr, inv_slope2) * absorption_factor(g, a);
    Components {
        fresnel_in: iface.fresnel_in,
        fresnel_out: iface.fresnel_out,
        absorb_in: absorbed(a, g.cos_i, iface.transmit_in),
        absorb_out: absorbed(a, g.cos_s, iface.transmit_out),
        surface,
        subsurface,
        total: mix(L::c(p.beta), subsurface, surface),
    }
}

/// Total radiance (eq. 8), computing only the terms with non-zero weight:
///
/// ```
/// use laminar_core::{components, total_radiance, Angles, Correlation, Geometry, Params};
/// let g = Geometry::<f64>::splat(&Angles::new(0.3, 0.9, 2.1)?);
/// let p = Params::new(0.5, 0.0, 1.45, 0.3)?; // β = 0: the surface term only
/// let t = total_radiance(&g, Correlation::Gaussian, &p);
/// assert_eq!(t.to_bits(), components(&g, Correlation::Gaussian, &p).total.to_bits());
/// # Ok::<(), laminar_core::InputError>(())
/// ```
///
/// no subsurface work at β = 0, no surface work at β = 1, no absorption
/// work at a = 0. Bitwise equal to [`components`]`.total`.
#[must_use]
pub fn total_radiance<L: Lane>(g: &Geometry<L>, corr: Correlation, p: &Params) -> L {
    let inv_slope2 = inverse_slope_squared(L::c(p.slope));
    let zero = L::c(0.0);
    let surface = if p.beta < 1.0 {
        surface_radiance(g, corr, inv_slope2)
    } else {
        zero
    };
    let subsurface = if p.beta > 0.0 {
        let base = subsurface_base(&Interface::new(g, L::c(p.n)), corr, inv_slope2);
        if p.a > 0.0 {
            base * absorption_factor(g, L::c(p.a))
        } else {
            base
        }
    } else {
        zero
    };
    mix(L::c(p.beta), subsurface, surface)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invalid_parameters_are_rejected_by_name() {
        let e = Params::new(0.5, 0.5, 0.9, 0.0).unwrap_err();
        assert!(matches!(e, InputError::OutOfRange { name: "n", .. }));
        assert!(Params::new(0.0, 0.5, 1.3, 0.0).is_err());
        assert!(Params::new(-1.0, 0.5, 1.3, 0.0).is_err());
        assert!(Params::new(0.5, 1.5, 1.3, 0.0).is_err());
        assert!(Params::new(0.5, 0.5, 1.3, -0.1).is_err());
        assert!(Params::new(0.5, 0.5, 1.3, 1.1).is_err());
        assert!(Params::new(f64::NAN, 0.5, 1.3, 0.0).is_err());
        assert!(Params::new(0.5, 0.5, f64::INFINITY, 0.0).is_err());
        assert!(Params::new(0.12, 0.01, 1.3, 0.0).is_ok());
    }
}
