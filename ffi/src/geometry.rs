//! The `f32` geometry of the C ABI: [`LaminarGeometry`] holds what the
//! core's `Geometry<f32>` holds, built once per measurement by one of three
//! constructors and then evaluated at any number of parameter sets.

use crate::{angles, status_of, LaminarAngles, Status};
use laminar_brdf_core::{Directions, Geometry};

/// One measurement's geometry, ready to evaluate (the core's
/// `Geometry<f32>`: the model's terms that depend on the angles only).
/// Build it with a `laminar_geometry_*` function; its fields are not
/// meant to be set by hand.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LaminarGeometry {
    /// cos θi.
    pub cos_i: f32,
    /// cos θs.
    pub cos_s: f32,
    /// sin²θi.
    pub sin2_i: f32,
    /// sin²θs.
    pub sin2_s: f32,
    /// `v_xy²` (docs/conventions.md §2).
    pub vxy2: f32,
    /// `v_z²`.
    pub vz2: f32,
    /// `cos θi / v_z²`.
    pub lead: f32,
    /// `v_xy² / v_z²`.
    pub ratio: f32,
}

impl From<Geometry<f32>> for LaminarGeometry {
    fn from(g: Geometry<f32>) -> Self {
        Self {
            cos_i: g.cos_i,
            cos_s: g.cos_s,
            sin2_i: g.sin2_i,
            sin2_s: g.sin2_s,
            vxy2: g.vxy2,
            vz2: g.vz2,
            lead: g.lead,
            ratio: g.ratio,
        }
    }
}

impl From<LaminarGeometry> for Geometry<f32> {
    fn from(g: LaminarGeometry) -> Self {
        Self {
            cos_i: g.cos_i,
            cos_s: g.cos_s,
            sin2_i: g.sin2_i,
            sin2_s: g.sin2_s,
            vxy2: g.vxy2,
            vz2: g.vz2,
            lead: g.lead,
            ratio: g.ratio,
        }
    }
}

/// A geometry in `f32` radians: θi, θs ∈ [0, π/2], φs ∈ [−π, π].
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaminarAnglesF32 {
    /// Incidence angle θi.
    pub theta_i: f32,
    /// Scattering angle θs.
    pub theta_s: f32,
    /// Scattering azimuth φs.
    pub phi_s: f32,
}

/// A geometry as a sensor gives it: the cosine and sine of θi, θs (each in
/// [0, 1]) and φs (each in [−1, 1]); each pair's `cos² + sin²` within 1e-4
/// of 1.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaminarDirections {
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

/// Geometry from `f64` angles with `f64` trigonometry, rounded once to
/// `f32`: bitwise what the fitting library packs for its `f32` paths.
pub fn from_angles(a: &LaminarAngles) -> Result<LaminarGeometry, Status> {
    Ok(Geometry::<f32>::splat(&angles(a)?).into())
}

/// Geometry from `f32` angles in `f32` arithmetic alone.
pub fn from_angles_f32(a: &LaminarAnglesF32) -> Result<LaminarGeometry, Status> {
    Geometry::from_angles_f32(a.theta_i, a.theta_s, a.phi_s)
        .map(Into::into)
        .map_err(status_of)
}

/// The core's [`Directions`] of a C one.
fn directions(d: &LaminarDirections) -> Directions {
    Directions {
        cos_i: d.cos_i,
        sin_i: d.sin_i,
        cos_s: d.cos_s,
        sin_s: d.sin_s,
        cos_phi: d.cos_phi,
        sin_phi: d.sin_phi,
    }
}

/// Checks sines and cosines as [`from_directions`] does.
pub fn check_directions(d: &LaminarDirections) -> Result<(), Status> {
    directions(d).check().map_err(status_of)
}

/// Geometry from sines and cosines in `f32` arithmetic alone.
pub fn from_directions(d: &LaminarDirections) -> Result<LaminarGeometry, Status> {
    Geometry::from_directions(&directions(d))
        .map(Into::into)
        .map_err(status_of)
}
