//! Subsurface radiance of the layered surface (eqs. 3–5 and, with
//! absorption, eqs. 12–14; docs/conventions.md §3).

use crate::absorption::attenuation;
use crate::fresnel::{fresnel_pair, solid_angle};
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
    /// `1 − f(θi, n)`, without cancellation ([`fresnel_pair`]).
    pub transmit_in: L,
    /// `1 − f(θs′, 1/n)`, without cancellation.
    pub transmit_out: L,
    /// `dω′ = cos θi / (n² cos θi′)` (eq. 5).
    pub solid_angle: L,
}

impl<L: Lane> Interface<L> {
    /// Refracts `g` into a layer of index `n ≥ 1` (Snell, docs/conventions.md §3).
    #[must_use]
    pub fn new(g: &Geometry<L>, n: L) -> Self {
        let refracted = g.refracted(n);
        let (fresnel_in, transmit_in) = fresnel_pair(g.cos_i, refracted.cos_i, n);
        let (fresnel_out, transmit_out) = fresnel_pair(g.cos_s, refracted.cos_s, n);
        Self {
            fresnel_in,
            fresnel_out,
            transmit_in,
            transmit_out,
            solid_angle: solid_angle(g.cos_i, refracted.cos_i, n),
            refracted,
        }
    }
}

/// Ragheb–Hancock subsurface radiance (eqs. 3–4):
/// `L^sf(θi′, θs′, φs; σ′/T′) · (1 − f(θi, n)) · (1 − f(θs′, 1/n)) · dω′`,
/// at the lower boundary's `inv_slope2 = (T′/σ′)²` (equal to the upper
/// boundary's when tied, as the paper's search ties them).
#[inline]
#[must_use]
pub fn subsurface_base<L: Lane>(iface: &Interface<L>, corr: Correlation, inv_slope2: L) -> L {
    surface_radiance(&iface.refracted, corr, inv_slope2)
        * iface.transmit_in
        * iface.transmit_out
        * iface.solid_angle
}

/// The absorption factor of eqs. 12–13, `(1 − a cos²θi)(1 − a cos²θs2)` with
/// `θs2 = θs` (eq. 14); geometry and `a` only, so computed once per `a`.
/// Exactly 1 at `a = 0`.
#[inline]
#[must_use]
pub fn absorption_factor<L: Lane>(g: &Geometry<L>, a: L) -> L {
    attenuation(a, g.sin2_i) * attenuation(a, g.sin2_s)
}

/// Absorptive subsurface radiance (eq. 12 Gaussian, eq. 13 Exponential):
/// `L^sf(θi′, θs′) · (1 − f1 − A1)(1 − f2 − A2) · dω′`, evaluated as
/// [`subsurface_base`] × [`absorption_factor`]; at `a = 0` this is bit for
/// bit the Ragheb–Hancock value.
/// Accuracy (crate docs, Accuracy): within 8.4 ulps (f64) and 6.8 (f32),
/// plus up to `2x′` ulps in the Gaussian tail.
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
