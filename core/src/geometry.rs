//! Measurement geometry (docs/conventions.md §1–§2): the angles of one measurement and
//! the terms derived from them, computed once per scene and reused for every
//! parameter set.

use crate::error::{check_range, InputError};
use crate::fresnel::refract_cos;
use crate::lane::Lane;
use crate::param::{Angle, Input};
use crate::trig::{sin_cos, P1, P2};
use core::f64::consts::{FRAC_PI_2, PI};

/// The angles of one measurement in the paper's Beckmann geometry (radians):
/// incident azimuth π, forward specular direction at `phi_s = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Angles {
    theta_i: f64,
    theta_s: f64,
    phi_s: f64,
}

impl Angles {
    /// Validates `θi, θs ∈ [0, π/2]` and a finite `φs` (any value; it is
    /// periodic). Returns [`InputError`] naming the offending angle otherwise.
    ///
    /// # Errors
    /// [`InputError::OutOfRange`] naming `theta_i`, `theta_s` or `phi_s`.
    pub fn new(theta_i: f64, theta_s: f64, phi_s: f64) -> Result<Self, InputError> {
        let zenith = |a, v| check_range(Input::Angle(a), v, 0.0, FRAC_PI_2, "[0, π/2]");
        if !phi_s.is_finite() {
            return Err(InputError::OutOfRange {
                input: Input::Angle(Angle::PhiS),
                value: phi_s,
                allowed: "a finite angle",
            });
        }
        Ok(Self {
            theta_i: zenith(Angle::ThetaI, theta_i)?,
            theta_s: zenith(Angle::ThetaS, theta_s)?,
            phi_s,
        })
    }

    /// Maps a CUReT row (`θv φv θi φi`, docs/conventions.md §1) to the Beckmann
    /// geometry: `θs = θv`, `φs = φv − φi − π` wrapped to `(−π, π]`.
    ///
    /// # Errors
    /// [`InputError::OutOfRange`] as [`Angles::new`] (θv is named `theta_s`).
    pub fn from_curet(
        theta_v: f64,
        phi_v: f64,
        theta_i: f64,
        phi_i: f64,
    ) -> Result<Self, InputError> {
        Self::new(theta_i, theta_v, wrap_pi(phi_v - phi_i - PI))
    }

    /// Incident zenith angle θi.
    #[must_use]
    pub fn theta_i(&self) -> f64 {
        self.theta_i
    }
    /// Scattering zenith angle θs.
    #[must_use]
    pub fn theta_s(&self) -> f64 {
        self.theta_s
    }
    /// Scattering azimuth φs.
    #[must_use]
    pub fn phi_s(&self) -> f64 {
        self.phi_s
    }
    /// The same measurement with `φs` negated (the model is symmetric in φs).
    #[must_use]
    pub fn mirrored(&self) -> Self {
        Self {
            phi_s: -self.phi_s,
            ..*self
        }
    }
}

/// Wraps an angle to `(−π, π]`.
#[must_use]
pub fn wrap_pi(phi: f64) -> f64 {
    let two_pi = 2.0 * PI;
    let mut p = phi - two_pi * libm::floor(phi / two_pi);
    // p in [0, 2π)
    if p > PI {
        p -= two_pi;
    }
    p
}

/// `π/2 − FRAC_PI_2`: the part of π/2 that `f64` cannot hold.
const FRAC_PI_2_LO: f64 = 6.123_233_995_736_766e-17;

/// `v_xy² = (sin θi − sin θs cos φs)² + (sin θs sin φs)²` (docs/conventions.md §2)
/// in `f64`, free of cancellation: the x component is evaluated as
/// `sin θi − sin θs + sin θs (1 − cos φs)
///  = 2 cos((θi+θs)/2) sin((θi−θs)/2) + 2 sin θs sin²(φs/2)`,
/// whose first term takes the exact difference `θi − θs` (Sterbenz) and
/// whose second is never negative.
fn vxy2(a: &Angles) -> f64 {
    let sin_s = libm::sin(a.theta_s);
    let half_phi = libm::sin(0.5 * a.phi_s);
    // cos((θi + θs)/2) = sin((ci + cs)/2) with the complements c = π/2 − θ,
    // which are exact (Sterbenz, plus the low part of π/2) where the
    // half-sum nears π/2: there the rounding of θi + θs would dominate.
    let complement = |t: f64| (FRAC_PI_2 - t) + FRAC_PI_2_LO;
    let cos_half_sum = libm::sin(0.5 * (complement(a.theta_i) + complement(a.theta_s)));
    let dx = 2.0 * cos_half_sum * libm::sin(0.5 * (a.theta_i - a.theta_s))
        + 2.0 * sin_s * half_phi * half_phi;
    let dy = sin_s * libm::sin(a.phi_s);
    dx * dx + dy * dy
}

/// The zenith cosines of one measurement per lane, with the surface-term
/// quantities of eqs. 1–2 derived from the angles (docs/conventions.md §2, k = 1).
#[derive(Clone, Copy, Debug)]
pub struct Geometry<L> {
    /// cos θi (clamped to `[0, 1]`).
    pub cos_i: L,
    /// cos θs (clamped to `[0, 1]`).
    pub cos_s: L,
    /// sin²θi, from the angle (accurate where `1 − cos²θi` would cancel).
    pub sin2_i: L,
    /// sin²θs, from the angle.
    pub sin2_s: L,
    /// `v_xy² = (sin θi − sin θs cos φs)² + (sin θs sin φs)²`.
    pub vxy2: L,
    /// `v_z² = (cos θi + cos θs)²` (docs/conventions.md §2: `v_z = −(cos θi + cos θs)`).
    pub vz2: L,
    /// `cos θi / v_z²`, the leading factor of eqs. 1–2; 0 where `v_z = 0`
    /// (both angles grazing: no irradiance).
    pub lead: L,
    /// `v_xy² / v_z²`, so that eqs. 1–2 use `x = ratio · (T/σ)²`; +∞ where `v_z = 0`.
    pub ratio: L,
}

impl<L: Copy> Geometry<L> {
    /// Every field set to `v` (`const`: a scratch memory's zeroed
    /// geometry, not a geometry of any direction).
    pub const fn filled(v: L) -> Self {
        Self {
            cos_i: v,
            cos_s: v,
            sin2_i: v,
            sin2_s: v,
            vxy2: v,
            vz2: v,
            lead: v,
            ratio: v,
        }
    }

    /// Every field through `f` (a kernel's load of stored lanes into its
    /// own, [`crate::simd`]).
    #[inline(always)]
    pub fn map<M>(&self, f: impl Fn(L) -> M) -> Geometry<M> {
        Geometry {
            cos_i: f(self.cos_i),
            cos_s: f(self.cos_s),
            sin2_i: f(self.sin2_i),
            sin2_s: f(self.sin2_s),
            vxy2: f(self.vxy2),
            vz2: f(self.vz2),
            lead: f(self.lead),
            ratio: f(self.ratio),
        }
    }
}

/// One measurement's directions as a sensor gives them: the sines and
/// cosines of θi, θs (each in `[0, 1]`) and of φs (each in `[−1, 1]`), in the
/// paper's frame (docs/conventions.md §1). Input of
/// [`Geometry::from_directions`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Directions {
    /// cos θi.
    pub cos_i: f32,
    /// sin θi.
    pub sin_i: f32,
    /// cos θs.
    pub cos_s: f32,
    /// sin θs.
    pub sin_s: f32,
    /// cos φs.
    pub cos_phi: f32,
    /// sin φs.
    pub sin_phi: f32,
}

impl Directions {
    /// Checks the ranges and that each pair is on the unit circle (within
    /// [`UNIT_TOLERANCE`]), as [`Geometry::from_directions`] does.
    ///
    /// # Errors
    /// [`InputError::OutOfRange`] naming `theta_i`, `theta_s` or `phi_s`
    /// (a sine or cosine out of range, or a pair off the unit circle).
    #[inline(always)] // as `Geometry::from_directions`
    pub fn check(&self) -> Result<(), InputError> {
        let pair = |name, c: f32, s: f32, lo: f32| {
            let unit = c * c + s * s - 1.0;
            if c >= lo && s >= lo && c <= 1.0 && s <= 1.0 && unit.abs() <= UNIT_TOLERANCE {
                Ok(())
            } else if unit.abs() <= UNIT_TOLERANCE {
                Err(out_of_range(
                    name,
                    if c < lo || c > 1.0 { c } else { s },
                    "cosine and sine in range",
                ))
            } else {
                Err(out_of_range(name, unit, "cos² + sin² − 1 within 1e-4"))
            }
        };
        pair(Angle::ThetaI, self.cos_i, self.sin_i, 0.0)?;
        pair(Angle::ThetaS, self.cos_s, self.sin_s, 0.0)?;
        pair(Angle::PhiS, self.cos_phi, self.sin_phi, -1.0)
    }
}

/// How far `cos² + sin²` of a [`Directions`] pair may be from 1.
pub const UNIT_TOLERANCE: f32 = 1e-4;

/// The largest `f32` not above π/2 (the `f32` π/2 itself is above it).
const F32_FRAC_PI_2: f32 = 1.570_796_2;
/// The largest `f32` not above π.
const F32_PI: f32 = 3.141_592_5;

#[inline(always)]
fn out_of_range(angle: Angle, value: f32, allowed: &'static str) -> InputError {
    InputError::OutOfRange {
        input: Input::Angle(angle),
        value: value as f64,
        allowed,
    }
}

/// The geometry of one measurement in `f32` arithmetic alone (no `f64`
/// operation: on a single-precision FPU such as the Cortex-M4F's, each
/// would be a software call). Error budget against the `f64` constructor
/// ([`Geometry::from_lanes`]), measured by `core/tests/geometry_f32.rs`:
/// the table in docs/conventions.md §2.
impl Geometry<f32> {
    /// Checks angles for [`Geometry::from_angles_f32`] (a caller that must
    /// check a batch before building any of it need not build twice).
    ///
    /// # Errors
    /// [`InputError::OutOfRange`] naming `theta_i`, `theta_s` or `phi_s`.
    #[inline(always)] // as `from_angles_f32`
    pub fn check_angles_f32(theta_i: f32, theta_s: f32, phi_s: f32) -> Result<(), InputError> {
        let zenith = |a, v| check_range(Input::Angle(a), v, 0.0, F32_FRAC_PI_2 as f64, "[0, π/2]");
        zenith(Angle::ThetaI, theta_i)?;
        zenith(Angle::ThetaS, theta_s)?;
        let phi = Input::Angle(Angle::PhiS);
        check_range(phi, phi_s, -F32_PI as f64, F32_PI as f64, "[−π, π]")?;
        Ok(())
    }

    /// From the angles in `f32` radians: `θi, θs ∈ [0, π/2]`, `φs ∈ [−π, π]`.
    /// `v_xy²` by the same cancellation-free form as the `f64` constructor,
    /// with five [`crate::trig::sin_cos`] calls.
    ///
    /// # Errors
    /// [`InputError::OutOfRange`] naming `theta_i`, `theta_s` or `phi_s`.
    #[inline(always)] // so that a caller mapping the error to a code drops its strings
    pub fn from_angles_f32(theta_i: f32, theta_s: f32, phi_s: f32) -> Result<Self, InputError> {
        Self::check_angles_f32(theta_i, theta_s, phi_s)?;
        let (ti, ts) = (theta_i, theta_s);
        let (sin_i, cos_i) = sin_cos(ti);
        let (sin_s, cos_s) = sin_cos(ts);
        let (sin_half_phi, cos_half_phi) = sin_cos(0.5 * phi_s);
        // cos((θi + θs)/2) as the sine of the half-sum of the complements
        // π/2 − θ, exact where the half-sum nears π/2 (see `vxy2`).
        let complement = |t: f32| (P1 - t) + P2;
        let (cos_half_sum, _) = sin_cos(0.5 * (complement(ti) + complement(ts)));
        let (sin_half_diff, _) = sin_cos(0.5 * (ti - ts));
        let dx = 2.0 * cos_half_sum * sin_half_diff + 2.0 * sin_s * sin_half_phi * sin_half_phi;
        let dy = sin_s * (2.0 * sin_half_phi * cos_half_phi);
        Ok(Self::from_parts(
            [cos_i.clamp(0.0, 1.0), cos_s.clamp(0.0, 1.0)],
            [(sin_i * sin_i).min(1.0), (sin_s * sin_s).min(1.0)],
            dx * dx + dy * dy,
        ))
    }

    /// From sines and cosines as a sensor gives them (each pair's
    /// `cos² + sin²` within [`UNIT_TOLERANCE`] of 1). `v_xy²` is formed as
    /// `(sin θi − sin θs) + sin θs (1 − cos φs)` and `sin θs sin φs`, with
    /// `1 − cos φs = sin²φs / (1 + cos φs)` where `cos φs > 0`: nothing
    /// cancels but the difference of the two given sines, which is exact
    /// where they are close (Sterbenz).
    ///
    /// # Errors
    /// [`InputError::OutOfRange`] naming `theta_i`, `theta_s` or `phi_s`
    /// (a sine or cosine out of range, or a pair off the unit circle).
    #[inline(always)] // as `from_angles_f32`
    pub fn from_directions(d: &Directions) -> Result<Self, InputError> {
        d.check()?;
        let one_minus_cos_phi = if d.cos_phi > 0.0 {
            d.sin_phi * d.sin_phi / (1.0 + d.cos_phi)
        } else {
            1.0 - d.cos_phi
        };
        let dx = (d.sin_i - d.sin_s) + d.sin_s * one_minus_cos_phi;
        let dy = d.sin_s * d.sin_phi;
        Ok(Self::from_parts(
            [d.cos_i, d.cos_s],
            [(d.sin_i * d.sin_i).min(1.0), (d.sin_s * d.sin_s).min(1.0)],
            dx * dx + dy * dy,
        ))
    }
}

impl<L: Lane> Geometry<L> {
    /// Geometry of lane `i` taken from `angles(i)`; trigonometry in `f64`
    /// (libm), rounded once to the lane precision.
    pub fn from_lanes(mut angles: impl FnMut(usize) -> Angles) -> Self {
        let mut a = [Angles {
            theta_i: 0.0,
            theta_s: 0.0,
            phi_s: 0.0,
        }; 8];
        for (i, slot) in a.iter_mut().enumerate().take(L::LANES) {
            *slot = angles(i);
        }
        let cos01 = |v: f64| libm::cos(v).clamp(0.0, 1.0);
        let sin2 = |v: f64| {
            let s = libm::sin(v);
            (s * s).min(1.0)
        };
        Self::from_parts(
            [
                L::from_f64_lanes(|i| cos01(a[i].theta_i)),
                L::from_f64_lanes(|i| cos01(a[i].theta_s)),
            ],
            [
                L::from_f64_lanes(|i| sin2(a[i].theta_i)),
                L::from_f64_lanes(|i| sin2(a[i].theta_s)),
            ],
            L::from_f64_lanes(|i| vxy2(&a[i])),
        )
    }

    /// The same measurement in every lane.
    pub fn splat(angles: &Angles) -> Self {
        Self::from_lanes(|_| *angles)
    }

    /// Derives `v_z²`, the leading factor and the ratio from the cosines and
    /// `v_xy²` (all in lane precision). `v_xy²` comes in precomputed because
    /// it cancels near the forward-specular direction: from rounded sines
    /// its relative error grows without bound there.
    #[must_use]
    fn from_parts([cos_i, cos_s]: [L; 2], [sin2_i, sin2_s]: [L; 2], vxy2: L) -> Self {
        let sz = cos_i + cos_s;
        let vz2 = sz * sz;
        let zero = L::c(0.0);
        let lit = zero.lt(vz2);
        // Guarded denominators: the unselected lanes never divide by zero.
        let safe_vz2 = L::select(lit, vz2, L::c(1.0));
        Self {
            cos_i,
            cos_s,
            sin2_i,
            sin2_s,
            vxy2,
            vz2,
            lead: L::select(lit, cos_i / safe_vz2, zero),
            ratio: L::select(lit, vxy2 / safe_vz2, L::c(f64::INFINITY)),
        }
    }

    /// The geometry below the upper boundary for refractive index `n ≥ 1`
    /// (docs/conventions.md §3): Snell `sin θ′ = sin θ / n` for both zenith angles,
    /// `φs` unchanged; the cosines come from [`refract_cos`], accurate near
    /// grazing and for `n` close to 1. Both sines shrink by `1/n`, so
    /// `v_xy′ = v_xy / n` exactly: `v_xy′²` is scaled, not recomputed from
    /// sines (which would cancel near the specular direction).
    #[must_use]
    pub fn refracted(&self, n: L) -> Self {
        let (ci, _) = refract_cos(self.cos_i, n);
        let (cs, _) = refract_cos(self.cos_s, n);
        let n2 = n * n;
        Self::from_parts(
            [ci, cs],
            [self.sin2_i / n2, self.sin2_s / n2],
            self.vxy2 / n2,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_pi_range() {
        assert_eq!(wrap_pi(PI), PI);
        assert!((wrap_pi(-PI) - PI).abs() < 1e-15);
        assert!((wrap_pi(3.0 * PI / 2.0) + PI / 2.0).abs() < 1e-15);
        assert_eq!(wrap_pi(0.25), 0.25);
    }

    #[test]
    fn curet_mirror_row_maps_to_forward_specular() {
        // θv = θi, φv − φi = π: the mirror configuration has φs = 0.
        let a = Angles::from_curet(0.5, PI, 0.5, 0.0).unwrap();
        assert_eq!(a.phi_s(), 0.0);
        let g = Geometry::<f64>::splat(&a);
        assert!(g.vxy2.abs() < 1e-30);
    }

    #[test]
    fn invalid_angles_are_rejected() {
        assert!(Angles::new(-0.1, 0.0, 0.0).is_err());
        assert!(Angles::new(0.0, 1.6, 0.0).is_err());
        assert!(Angles::new(0.0, 0.0, f64::NAN).is_err());
        assert!(Angles::new(f64::NAN, 0.0, 0.0).is_err());
    }

    #[test]
    fn both_grazing_is_finite() {
        let g = Geometry::<f32>::splat(&Angles::new(FRAC_PI_2, FRAC_PI_2, 0.0).unwrap());
        assert!(g.lead.is_finite() && g.ratio.is_finite());
        // Exactly zero cosines (v_z = 0): no irradiance, no division by zero.
        let g = Geometry::<f32>::from_parts([0.0, 0.0], [1.0, 1.0], 0.0);
        assert_eq!(g.lead, 0.0);
        assert_eq!(g.ratio, f32::INFINITY);
    }
}
