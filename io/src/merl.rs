//! MERL isotropic BRDF files (`.binary`, Matusik et al. 2003).
//!
//! Layout: three little-endian `i32` dimensions (90, 90, 180), then three
//! planes (red, green, blue) of 90 · 90 · 180 little-endian `f64`, each
//! indexed `phi_d + 180 (theta_d + 90 theta_h)`. A stored value times the
//! plane's scale (1/1500, 1.15/1500, 1.66/1500) is the BRDF; a negative
//! value means "not measured".
//!
//! Lookup follows the reference code (`BRDFRead.cpp`): the illumination and
//! view directions become half/difference angles (θh, θd, φd); the indices
//! are `⌊sqrt(θh / (π/2)) · 90⌋` (non-linear, finer near the specular
//! peak), `⌊θd / (π/2) · 90⌋` and `⌊φd / π · 180⌋` after `φd += π` for
//! negative φd (reciprocity), each clamped to its range. That is, a geometry
//! reads the bin that contains it (the reference's truncation; there is no
//! interpolation). The writer evaluates each bin at its centre in index
//! space, so that reading the centre back finds the same bin.

use crate::error::ReadError;
use crate::reader::{brdf_set, contents};
use laminar_brdf_fit::{MeasurementAngles, MeasurementSet};
use std::f64::consts::{FRAC_PI_2, PI};
use std::path::Path;

/// θh bins.
pub const THETA_H: usize = 90;
/// θd bins.
pub const THETA_D: usize = 90;
/// φd bins (over [0, π): the reference's 360 / 2).
pub const PHI_D: usize = 180;
/// Values per colour plane.
pub const PLANE: usize = THETA_H * THETA_D * PHI_D;
/// Scale of the red, green and blue planes.
pub const SCALES: [f64; 3] = [1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0];
/// The channel names of the three planes.
pub const CHANNELS: [&str; 3] = ["r", "g", "b"];
/// Size of a MERL file in bytes.
pub const FILE_LEN: usize = 12 + 3 * PLANE * 8;

/// The θh index: `⌊sqrt(θh / (π/2)) · 90⌋`, clamped to `0..90` (0 for θh ≤ 0).
pub fn theta_half_index(theta_half: f64) -> usize {
    if theta_half <= 0.0 {
        return 0;
    }
    // The reference: sqrt((θh / (π/2)) · 90 · 90), truncated.
    let index = (theta_half / FRAC_PI_2 * THETA_H as f64 * THETA_H as f64).sqrt();
    (index as usize).min(THETA_H - 1)
}

/// The θd index: `⌊θd / (π/2) · 90⌋`, clamped to `0..90`.
pub fn theta_diff_index(theta_diff: f64) -> usize {
    let index = theta_diff / FRAC_PI_2 * THETA_D as f64;
    if index <= 0.0 {
        0
    } else {
        (index as usize).min(THETA_D - 1)
    }
}

/// The φd index: φd + π when negative (reciprocity), then `⌊φd / π · 180⌋`,
/// clamped to `0..180`.
pub fn phi_diff_index(phi_diff: f64) -> usize {
    let phi = if phi_diff < 0.0 {
        phi_diff + PI
    } else {
        phi_diff
    };
    let index = phi / PI * PHI_D as f64;
    if index <= 0.0 {
        0
    } else {
        (index as usize).min(PHI_D - 1)
    }
}

type Vec3 = [f64; 3];

fn direction(theta: f64, phi: f64) -> Vec3 {
    [
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    ]
}

fn normalise(v: Vec3) -> Vec3 {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / l, v[1] / l, v[2] / l]
}

/// Rotation of `v` about the unit `axis` by `angle` (Rodrigues; the reference's `rotate_vector`).
fn rotate(v: Vec3, axis: Vec3, angle: f64) -> Vec3 {
    let (s, c) = angle.sin_cos();
    let dot = v[0] * axis[0] + v[1] * axis[1] + v[2] * axis[2];
    let cross = [
        axis[1] * v[2] - axis[2] * v[1],
        axis[2] * v[0] - axis[0] * v[2],
        axis[0] * v[1] - axis[1] * v[0],
    ];
    [0, 1, 2].map(|i| v[i] * c + axis[i] * dot * (1.0 - c) + cross[i] * s)
}

const NORMAL: Vec3 = [0.0, 0.0, 1.0];
const BINORMAL: Vec3 = [0.0, 1.0, 0.0];

/// Half/difference angles `(θh, φh, θd, φd)` of the directions towards the
/// light `(θi, φi)` and the viewer `(θo, φo)` (the reference's
/// `std_coords_to_half_diff_coords`).
pub fn half_diff(theta_i: f64, phi_i: f64, theta_o: f64, phi_o: f64) -> (f64, f64, f64, f64) {
    let i = direction(theta_i, phi_i);
    let o = direction(theta_o, phi_o);
    let h = normalise([i[0] + o[0], i[1] + o[1], i[2] + o[2]]);
    let theta_h = h[2].clamp(-1.0, 1.0).acos();
    let phi_h = h[1].atan2(h[0]);
    let d = rotate(rotate(i, NORMAL, -phi_h), BINORMAL, -theta_h);
    (
        theta_h,
        phi_h,
        d[2].clamp(-1.0, 1.0).acos(),
        d[1].atan2(d[0]),
    )
}

/// The directions `(θi, φi, θo, φo)` of half/difference angles (the inverse of [`half_diff`]).
pub fn std_coords(theta_h: f64, phi_h: f64, theta_d: f64, phi_d: f64) -> (f64, f64, f64, f64) {
    let h = direction(theta_h, phi_h);
    let d = direction(theta_d, phi_d);
    let i = rotate(rotate(d, BINORMAL, theta_h), NORMAL, phi_h);
    let dot = i[0] * h[0] + i[1] * h[1] + i[2] * h[2];
    let o = [0, 1, 2].map(|k| 2.0 * dot * h[k] - i[k]);
    let polar = |v: Vec3| v[2].clamp(-1.0, 1.0).acos();
    (polar(i), i[1].atan2(i[0]), polar(o), o[1].atan2(o[0]))
}

/// The directions `(θi, φi, θo, φo)` at the centre, in index space, of bin
/// `(ih, id, ip)` (θh, θd, φd indices), with φh = 0: θh = ((ih + ½)/90)² π/2,
/// θd = (id + ½)/90 · π/2, φd = (ip + ½)/180 · π. Reading it back finds the
/// same bin; either direction may be below the horizon (θ ≥ π/2).
pub fn bin_centre(ih: usize, id: usize, ip: usize) -> (f64, f64, f64, f64) {
    let u = (ih as f64 + 0.5) / THETA_H as f64;
    std_coords(
        u * u * FRAC_PI_2,
        0.0,
        (id as f64 + 0.5) / THETA_D as f64 * FRAC_PI_2,
        (ip as f64 + 0.5) / PHI_D as f64 * PI,
    )
}

/// The flat index within a plane of the bin holding the geometry.
pub fn bin(theta_i: f64, phi_i: f64, theta_o: f64, phi_o: f64) -> usize {
    let (th, _, td, pd) = half_diff(theta_i, phi_i, theta_o, phi_o);
    phi_diff_index(pd) + PHI_D * (theta_diff_index(td) + THETA_D * theta_half_index(th))
}

/// A MERL table in memory: three planes of stored values.
#[derive(Debug, Clone, PartialEq)]
pub struct Merl {
    values: Vec<f64>,
}

impl Merl {
    /// The BRDF (scaled, per channel r, g, b) at the geometry; negative where not measured.
    pub fn lookup(&self, theta_i: f64, phi_i: f64, theta_o: f64, phi_o: f64) -> [f64; 3] {
        let k = bin(theta_i, phi_i, theta_o, phi_o);
        [0, 1, 2].map(|c| self.values[k + c * PLANE] * SCALES[c])
    }

    /// A table of the BRDF `brdf(θi, φi, θo, φo) → [r, g, b]`, evaluated at
    /// each bin's centre in index space; bins whose directions fall below
    /// the horizon hold −1 (not measured).
    pub fn tabulate(brdf: impl Fn(f64, f64, f64, f64) -> [f64; 3]) -> Self {
        let mut values = vec![-1.0; 3 * PLANE];
        for ih in 0..THETA_H {
            for id in 0..THETA_D {
                for ip in 0..PHI_D {
                    let (ti, pi, to, po) = bin_centre(ih, id, ip);
                    if ti >= FRAC_PI_2 || to >= FRAC_PI_2 {
                        continue;
                    }
                    let k = ip + PHI_D * (id + THETA_D * ih);
                    let v = brdf(ti, pi, to, po);
                    for c in 0..3 {
                        values[k + c * PLANE] = v[c] / SCALES[c];
                    }
                }
            }
        }
        Self { values }
    }

    /// The stored values (three planes).
    pub fn values(&self) -> &[f64] {
        &self.values
    }
}

/// Reads a MERL `.binary` file, checking its dimensions and length.
///
/// # Errors
/// [`ReadError`] for a file that cannot be read, has other dimensions or length, or a non-finite value.
pub fn read_merl(file: &Path) -> Result<Merl, ReadError> {
    parse_merl(file, &contents(file)?)
}

/// [`read_merl`] on contents already in memory (`file` names them in errors).
///
/// # Errors
/// As [`read_merl`].
pub fn parse_merl(file: &Path, bytes: &[u8]) -> Result<Merl, ReadError> {
    if bytes.len() < 12 {
        return Err(ReadError::format(
            file,
            0,
            format!("{} bytes: too short for a MERL header", bytes.len()),
        ));
    }
    let dims: Vec<i32> = bytes[..12]
        .chunks_exact(4)
        .map(|b| i32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    if dims != [THETA_H as i32, THETA_D as i32, PHI_D as i32] {
        return Err(ReadError::format(
            file,
            0,
            format!(
                "dimensions {}×{}×{}, expected {THETA_H}×{THETA_D}×{PHI_D} (isotropic MERL)",
                dims[0], dims[1], dims[2]
            ),
        ));
    }
    if bytes.len() != FILE_LEN {
        return Err(ReadError::format(
            file,
            0,
            format!("{} bytes, expected {FILE_LEN}", bytes.len()),
        ));
    }
    let values: Vec<f64> = bytes[12..]
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
        .collect();
    if let Some(k) = values.iter().position(|v| !v.is_finite()) {
        return Err(ReadError::format(
            file,
            0,
            format!(
                "value {} at byte {} is not a finite number",
                values[k],
                12 + 8 * k
            ),
        ));
    }
    Ok(Merl { values })
}

/// Writes a MERL `.binary` file.
///
/// # Errors
/// [`ReadError::Io`] when the file cannot be written.
pub fn write_merl(file: &Path, merl: &Merl) -> Result<(), ReadError> {
    let mut bytes = Vec::with_capacity(FILE_LEN);
    for d in [THETA_H, THETA_D, PHI_D] {
        bytes.extend_from_slice(&(d as i32).to_le_bytes());
    }
    for v in &merl.values {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    crate::write_atomic_bytes(file, &bytes)
}

/// The measurement set of a MERL table sampled at `geometry` (one row per
/// geometry; paper-frame geometries are placed at φi = 0): channels r, g, b,
/// values read as BRDF. Geometries whose bin is not measured (negative) in
/// any channel are left out; their count is returned beside the set.
///
/// # Errors
/// [`ReadError::Measurements`] when no geometry is measured or the angles are invalid.
pub fn sample(
    file: &Path,
    merl: &Merl,
    geometry: &[MeasurementAngles],
) -> Result<(MeasurementSet, usize), ReadError> {
    let mut kept = Vec::new();
    let mut rows = Vec::new();
    let mut values: [Vec<f64>; 3] = Default::default();
    for (k, g) in geometry.iter().enumerate() {
        let (ti, pi, to, po) = match *g {
            MeasurementAngles::Lab {
                theta_i,
                phi_i,
                theta_v,
                phi_v,
            } => (theta_i, phi_i, theta_v, phi_v),
            MeasurementAngles::Paper {
                theta_i,
                theta_s,
                phi_s,
            } => (theta_i, 0.0, theta_s, phi_s + PI),
        };
        let v = merl.lookup(ti, pi, to, po);
        if v.iter().any(|&x| x < 0.0) {
            continue;
        }
        for c in 0..3 {
            values[c].push(v[c]);
        }
        kept.push(*g);
        rows.push(k + 1);
    }
    let missing = geometry.len() - kept.len();
    let set = brdf_set(
        file,
        "merl",
        kept,
        Some(rows),
        CHANNELS.into_iter().zip(values),
    )?;
    Ok((set, missing))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Index values worked by hand from the reference definitions.
    #[test]
    fn indices_match_the_reference_definitions() {
        // θh index: sqrt(θh/(π/2)·90·90): θh = π/8 → sqrt(0.25)·90 = 45.
        assert_eq!(theta_half_index(PI / 8.0), 45);
        // Just below: 44 (truncation, not rounding).
        assert_eq!(theta_half_index(PI / 8.0 * 0.999), 44);
        // θh = (π/2)·(1/90)² → exactly bin 1 (sqrt = 1); a hair less → 0.
        assert_eq!(theta_half_index(FRAC_PI_2 / 8100.0 * 1.0001), 1);
        assert_eq!(theta_half_index(FRAC_PI_2 / 8100.0 * 0.9999), 0);
        // Linear would give ⌊(π/8)/(π/2)·90⌋ = 22: the non-linear index is not it.
        assert_ne!(theta_half_index(PI / 8.0), 22);
        assert_eq!(theta_half_index(0.0), 0);
        assert_eq!(theta_half_index(FRAC_PI_2), 89);
        // θd index: linear. 30° → 30, 89.9° → 89, 90° clamps to 89.
        assert_eq!(theta_diff_index(30.5f64.to_radians()), 30);
        assert_eq!(theta_diff_index(FRAC_PI_2), 89);
        // φd index over [0, π): 90° → 90; −90° → +90° → 90; 179.5° → 179.
        assert_eq!(phi_diff_index(FRAC_PI_2 + 1e-9), 90);
        assert_eq!(phi_diff_index(-FRAC_PI_2 + 1e-9), 90);
        assert_eq!(phi_diff_index(179.5f64.to_radians()), 179);
        assert_eq!(phi_diff_index(PI), 179);
        // The scales: red 1/1500 (not 1.0/1500 · 1.15).
        assert_eq!(SCALES, [1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0]);
    }

    #[test]
    fn half_diff_of_a_mirror_pair_and_back() {
        // Mirror directions: θh = 0, θd = θi.
        let (th, _, td, _) = half_diff(0.4, 0.0, 0.4, PI);
        assert!(th.abs() < 1e-7 && (td - 0.4).abs() < 1e-12);
        // Round trip through std_coords.
        let (ti, pi, to, po) = (0.7, 0.3, 0.2, -2.0);
        let (th, ph, td, pd) = half_diff(ti, pi, to, po);
        let back = std_coords(th, ph, td, pd);
        for (a, b) in [(ti, back.0), (pi, back.1), (to, back.2), (po, back.3)] {
            assert!((a - b).abs() < 1e-12, "{a} vs {b}");
        }
    }

    /// A tabulated function reads back, at every bin centre above the
    /// horizon, exactly the value it had there (up to the scale's rounding).
    #[test]
    fn tabulated_values_read_back_at_bin_centres() {
        let f = |ti: f64, pi: f64, to: f64, po: f64| {
            let v = 1.0 + ti + 2.0 * to + (po - pi).cos();
            [v, 2.0 * v, 3.0 * v]
        };
        let table = Merl::tabulate(f);
        let mut checked = 0;
        for ih in (0..90).step_by(5) {
            for id in (0..90).step_by(7) {
                for ip in (0..180).step_by(11) {
                    let (ti, pi, to, po) = bin_centre(ih, id, ip);
                    let got = table.lookup(ti, pi, to, po);
                    if ti >= FRAC_PI_2 || to >= FRAC_PI_2 {
                        assert!(got.iter().all(|&v| v < 0.0));
                        continue;
                    }
                    let want = f(ti, pi, to, po);
                    for c in 0..3 {
                        assert!(
                            (got[c] - want[c]).abs() <= 4.0 * f64::EPSILON * want[c],
                            "bin ({ih}, {id}, {ip}) channel {c}: {} vs {}",
                            got[c],
                            want[c]
                        );
                    }
                    checked += 1;
                }
            }
        }
        assert!(checked > 1000, "{checked}");
    }

    #[test]
    fn bin_centres_read_back_into_their_bins() {
        for (ih, id, ip) in [(0, 0, 0), (45, 30, 90), (89, 10, 179), (3, 80, 5)] {
            let (ti, pi, to, po) = bin_centre(ih, id, ip);
            // The centre in index space, computed here from the definitions
            // (to 1e-9 rad: acos loses digits near θh = 0; the smallest bin
            // is 1.9e-4 rad wide).
            let u = (ih as f64 + 0.5) / 90.0;
            let (th, _, td, pd) = half_diff(ti, pi, to, po);
            assert!((th - u * u * FRAC_PI_2).abs() < 1e-9, "θh {th}");
            assert!(
                (td - (id as f64 + 0.5) / 90.0 * FRAC_PI_2).abs() < 1e-9,
                "θd {td}"
            );
            assert!(
                (pd - (ip as f64 + 0.5) / 180.0 * PI).abs() < 1e-9,
                "φd {pd}"
            );
            assert_eq!(bin(ti, pi, to, po), ip + 180 * (id + 90 * ih));
        }
    }
}
