//! A measurement set ("scene"): kept geometries and normalised measured
//! radiance (conventions §1, §4, §8).

use crate::data::TableRow;
use laminar_core::{normalise_by_max, wrap_pi, Angles};
use std::f64::consts::PI;

/// Tolerance of the specular test (conventions §1), radians.
pub const SPECULAR_TOLERANCE: f64 = 1e-4;

/// True for a mirror configuration: `θv = θi` and `|φv − φi| = π` (conventions §1).
pub fn is_specular(row: &TableRow) -> bool {
    (row.theta_v - row.theta_i).abs() <= SPECULAR_TOLERANCE
        && (wrap_pi(row.phi_v - row.phi_i).abs() - PI).abs() <= SPECULAR_TOLERANCE
}

/// Kept geometries with their normalised measured radiance.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Geometry of each kept measurement, in the Beckmann frame.
    pub angles: Vec<Angles>,
    /// Normalised measured radiance `D_k` (max 1, or all 0 when no value is positive).
    pub data: Vec<f64>,
    /// 1-based table index of each kept measurement.
    pub rows: Vec<usize>,
    /// Kept measurements whose BRDF value is zero or negative (conventions §8).
    pub nonpositive: usize,
}

impl Scene {
    /// Builds the scene of one BRDF row: drops the specular rows, converts
    /// BRDF to radiance `D = v cos θi` and divides by the max (conventions §4).
    pub fn from_curet(table: &[TableRow], brdf: &[f64]) -> Self {
        let mut angles = Vec::new();
        let mut radiance = Vec::new();
        let mut rows = Vec::new();
        let mut nonpositive = 0;
        for (row, &v) in table.iter().zip(brdf) {
            if is_specular(row) {
                continue;
            }
            // The table reader has validated the angles.
            let a = Angles::from_curet(row.theta_v, row.phi_v, row.theta_i, row.phi_i)
                .expect("validated table angles");
            if v <= 0.0 {
                nonpositive += 1;
            }
            radiance.push(v * row.theta_i.cos());
            angles.push(a);
            rows.push(row.index);
        }
        Self::from_radiance(angles, radiance, rows, nonpositive)
    }

    /// A scene from angles and un-normalised radiance.
    pub fn from_radiance(
        angles: Vec<Angles>,
        mut radiance: Vec<f64>,
        rows: Vec<usize>,
        nonpositive: usize,
    ) -> Self {
        normalise_by_max(&mut radiance);
        Self {
            angles,
            data: radiance,
            rows,
            nonpositive,
        }
    }

    /// Number of kept measurements K.
    pub fn len(&self) -> usize {
        self.angles.len()
    }

    /// True when no measurement is kept.
    pub fn is_empty(&self) -> bool {
        self.angles.is_empty()
    }
}
