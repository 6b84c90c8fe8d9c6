//! Subsurface radiance of the layered surface (eqs. 3–5 and, with
//! absorption, eqs. 12–14; docs/conventions.md §3).

use crate::absorption::attenuation;
use crate::fresnel::{fresnel_from_cosines, solid_angle};
use crate::geometry::Geometry;
use crate::lane::Lane;
use crate::surface::{surface_radiance, Correlation};

/// Everything below the upper boundary that depends on geometry and the
/// refractive index `n` only; a search computes it once per `(scene, n)`.
#[derive(Clone, Copy, Debug)]
pub struct Interface<L> {
    /// The refracted geometry (θi′, θs′, φs) of the lower boundary.
    pub refracted: Geometry<L>,
    /// `f(θi, n)`, air to dielectric (eq. 6).
    pub fresnel_in: L,
    /// `f(θs′, 1/n)`, dielectric to air at the internal angle (eq. 6;
    /// evaluated as the equal `f(θs, n)` from the same two cosines).
    pub fresnel_out: L,
    /// `dω′ = cos θi / (n² cos θi′)` (eq. 5).
    pub solid_angle: L,
}

impl<L: Lane> Interface<L> {
    /// Refracts `g` into a layer of index `n ≥ 1` (Snell, docs/conventions.md §3).
    #[must_use]
    pub fn new(g: &Geometry<L>, n: L) -> Self {
        let refracted = g.refracted(n);
        Self {
            fresnel_in: fresnel_from_cosines(g.cos_i, refracted.cos_i, n),
            fresnel_out: fresnel_from_cosines(g.cos_s, refracted.cos_s, n),
            solid_angle: solid_angle(g.cos_i, refracted.cos_i, n),
            refracted,
        }
    }
}

/// Ragheb–Hancock subsurface radiance (eqs. 3–4):
/// `L^sf(θi′, θs′, φs; σ/T) · (1 − f(θi, n)) · (1 − f(θs′, 1/n)) · dω′`,
/// with σ′/T′ = σ/T (the paper's search ties them).
#[inline]
#[must_use]
pub fn subsurface_base<L: Lane>(iface: &Interface<L>, corr: Correlation, inv_slope2: L) -> L {
    let one = L::c(1.0);
    surface_radiance(&iface.refracted, corr, inv_slope2)
        * (one - iface.fresnel_in)
        * (one - iface.fresnel_out)
        * iface.solid_angle
}

/// The absorption factor of eqs. 12–13, `(1 − a cos²θi)(1 − a cos²θs2)` with
/// `θs2 = θs` (eq. 14); geometry and `a` only, so computed once per `a`.
/// Exactly 1 at `a = 0`.
#[inline]
#[must_use]
pub fn absorption_factor<L: Lane>(g: &Geometry<L>, a: L) -> L {
    attenuation(a, g.cos_i) * attenuation(a, g.cos_s)
}

/// Absorptive subsurface radiance (eq. 12 Gaussian, eq. 13 Exponential):
/// `L^sf(θi′, θs′) · (1 − f1 − A1)(1 − f2 − A2) · dω′`, evaluated as
/// [`subsurface_base`] × [`absorption_factor`]; at `a = 0` this is bit for
/// bit the Ragheb–Hancock value.
#[inline]
#[must_use]
pub fn subsurface_radiance<L: Lane>(
    g: &Geometry<L>,
    iface: &Interface<L>,
    corr: Correlation,
    inv_slope2: L,
    a: L,
) -> L {
    subsurface_base(iface, corr, inv_slope2) * absorption_factor(g, a)
}
