//! The RGL-EPFL material database's isotropic RGB `.bsdf` files (Dupuy
//! and Jakob 2018, "An Adaptive Parameterization for Efficient Material
//! Acquisition and Rendering"; docs/formats.md, "RGL `.bsdf`").
//!
//! A `tensor_file` (v1.0, little-endian): the magic `tensor_file\0`, the
//! version (two bytes), the number of fields (u32), then per field its
//! name (u16 length, bytes), its number of dimensions (u16), its type
//! (u8: 1 `u8`, 10 `f32`), the absolute offset of its data (u64) and its
//! shape (u64 each). The fields read: `theta_i` (radians), `phi_i` (one
//! value: isotropic), `ndf` and `sigma` (2 × S), `vndf` (1 × T × V × V)
//! and `rgb` (1 × T × 3 × N × N); `description` names the material.
//!
//! The `rgb` values are not at plain angles: node `(row j, column k)` of
//! slice `t` is the point `(k/(N − 1), j/(N − 1))` of the unit square that
//! the VNDF's warp maps to the half vector. Each node is turned into a
//! measurement as the method of the paper (and RGL's reference reader)
//! does, written here from that description:
//!
//! 1. the node through the marginal–conditional warp of `vndf[0, t]`
//!    (bilinear density) gives `(u_θ, u_φ)`;
//! 2. `θm = u_θ² π/2`, `φm = (2 u_φ − 1) π + φi`, and the viewer's
//!    direction is the light's `ωi = (sin θi cos φi, sin θi sin φi, cos θi)`
//!    reflected about `ωm`: `ωo = 2 (ωm · ωi) ωm − ωi`;
//! 3. the BRDF of channel c is `max(0, rgb) · NDF(u_θ, u_φ) / (4 σ(u(θi),
//!    u(φi)))`, with `ndf` and `σ` bilinearly interpolated (negative `rgb`
//!    values are colours out of gamut, which the reference reader clips).
//!
//! The lab frame's light is `ωi` and its viewer `ωo`. Nodes below the
//! horizon, and the slice `θi = 90°` (grazing, outside what a
//! gonioreflectometer observes; its values are extrapolated), are left
//! out. The first column of nodes (one per row) is the mirror direction's
//! neighbourhood: the warp takes it to the first column of the VNDF with
//! mass, within 0.02° of the mirror.

use crate::error::ReadError;
use crate::reader::{brdf_set, contents};
use laminar_brdf_fit::{MeasurementAngles, MeasurementSet};
use std::f64::consts::PI;
use std::path::Path;

/// The magic bytes a tensor file starts with.
const MAGIC: &[u8; 12] = b"tensor_file\0";

/// The largest sample of the warp, as the reference's (the largest `f32`
/// below 1): samples are clamped to `[1 − ε, ε]`.
const ONE_MINUS_EPSILON: f64 = 0.999_999_940_395_355_2;

/// Polar angles of the light at or above this (radians, 89.9°) are the
/// extrapolated grazing slice, left out.
const GRAZING: f64 = 89.9 * PI / 180.0;

/// One field of a tensor file: its type, shape and data bytes.
struct Field<'a> {
    dtype: u8,
    shape: Vec<usize>,
    data: &'a [u8],
}

impl Field<'_> {
    /// The values of an `f32` field of `shape`, else an error naming it.
    fn f32s(
        &self,
        file: &Path,
        name: &str,
        shape: &[Option<usize>],
    ) -> Result<Vec<f64>, ReadError> {
        let fits = self.shape.len() == shape.len()
            && self
                .shape
                .iter()
                .zip(shape)
                .all(|(&s, want)| want.is_none_or(|w| w == s));
        if self.dtype != 10 || !fits {
            return Err(ReadError::format(
                file,
                0,
                format!(
                    "field `{name}`: type {} of shape {:?}, expected f32 (10) of shape {}",
                    self.dtype,
                    self.shape,
                    shown(shape)
                ),
            ));
        }
        Ok(self
            .data
            .chunks_exact(4)
            .map(|b| f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])))
            .collect())
    }
}

/// A shape with its free dimensions as `*`.
fn shown(shape: &[Option<usize>]) -> String {
    let dims: Vec<String> = shape
        .iter()
        .map(|d| d.map_or("*".into(), |d| d.to_string()))
        .collect();
    format!("({})", dims.join(", "))
}

/// Reads an RGL isotropic RGB `.bsdf` file (module docs) as a set named
/// after the file stem, with the channels `r`, `g` and `b` of BRDF values
/// at every node of every slice of the light's polar angle.
///
/// # Errors
/// [`ReadError`] naming the file and the byte offset or field: a file that
/// is not a tensor file of version 1.0, a field missing or of another type
/// or shape, data outside the file, an anisotropic material, or a slice
/// whose VNDF has no mass.
pub fn read_rgl(file: &Path) -> Result<MeasurementSet, ReadError> {
    parse_rgl(file, &contents(file)?)
}

/// [`read_rgl`] on contents already in memory (`file` names the set and
/// the errors).
///
/// # Errors
/// As [`read_rgl`].
pub fn parse_rgl(file: &Path, bytes: &[u8]) -> Result<MeasurementSet, ReadError> {
    let fields = fields(file, bytes)?;
    let field = |name: &str| {
        fields
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, f)| f)
            .ok_or_else(|| {
                ReadError::format(file, 0, format!("no field `{name}`: not an RGL BRDF file"))
            })
    };
    let theta_i = field("theta_i")?.f32s(file, "theta_i", &[None])?;
    let phi_i = field("phi_i")?.f32s(file, "phi_i", &[None])?;
    if phi_i.len() != 1 {
        return Err(ReadError::format(
            file,
            0,
            format!(
                "field `phi_i`: {} values; only isotropic materials (one) are read",
                phi_i.len()
            ),
        ));
    }
    let slices = theta_i.len();
    let ndf_field = field("ndf")?;
    let s = ndf_field.shape.get(1).copied().unwrap_or(0);
    let ndf = Grid::new(ndf_field.f32s(file, "ndf", &[Some(2), Some(s)])?, s, 2);
    let sigma = Grid::new(
        field("sigma")?.f32s(file, "sigma", &[Some(2), Some(s)])?,
        s,
        2,
    );
    let vndf_field = field("vndf")?;
    let v = vndf_field.shape.get(3).copied().unwrap_or(0);
    let vndf = vndf_field.f32s(file, "vndf", &[Some(1), Some(slices), Some(v), Some(v)])?;
    let rgb_field = field("rgb")?;
    let n = rgb_field.shape.get(4).copied().unwrap_or(0);
    let rgb = rgb_field.f32s(
        file,
        "rgb",
        &[Some(1), Some(slices), Some(3), Some(n), Some(n)],
    )?;
    if [s, v, n].iter().any(|&d| d < 2)
        || theta_i.iter().any(|t| !(0.0..=PI / 2.0 + 1e-6).contains(t))
    {
        return Err(ReadError::format(
            file,
            0,
            format!("grids of {s}, {v} and {n} points and light angles {theta_i:?}: not an RGL BRDF file"),
        ));
    }
    let phi_i = phi_i[0];
    let (mut angles, mut values) = (Vec::new(), [Vec::new(), Vec::new(), Vec::new()]);
    for (t, &theta) in theta_i.iter().enumerate() {
        if theta >= GRAZING {
            continue;
        }
        let warp = Warp::new(&vndf[t * v * v..(t + 1) * v * v], v).ok_or_else(|| {
            ReadError::format(file, 0, format!("field `vndf`: slice {t} has no mass"))
        })?;
        let light = [
            theta.sin() * phi_i.cos(),
            theta.sin() * phi_i.sin(),
            theta.cos(),
        ];
        let scale = 4.0 * sigma.eval([theta2u(theta), phi2u(phi_i)]);
        for j in 0..n {
            for k in 0..n {
                let node = [k as f64 / (n - 1) as f64, j as f64 / (n - 1) as f64];
                let u = warp.sample(node);
                let (theta_m, phi_m) = (u[0] * u[0] * PI / 2.0, (2.0 * u[1] - 1.0) * PI + phi_i);
                let m = [
                    theta_m.sin() * phi_m.cos(),
                    theta_m.sin() * phi_m.sin(),
                    theta_m.cos(),
                ];
                let d = 2.0 * (m[0] * light[0] + m[1] * light[1] + m[2] * light[2]);
                let view = [
                    d * m[0] - light[0],
                    d * m[1] - light[1],
                    d * m[2] - light[2],
                ];
                if view[2] <= 0.0 {
                    continue;
                }
                let factor = ndf.eval(u) / scale;
                angles.push(MeasurementAngles::Lab {
                    theta_i: theta,
                    phi_i,
                    theta_v: view[2].clamp(-1.0, 1.0).acos(),
                    phi_v: view[1].atan2(view[0]),
                });
                for (c, out) in values.iter_mut().enumerate() {
                    let value = rgb[((t * 3 + c) * n + j) * n + k];
                    out.push(value.max(0.0) * factor);
                }
            }
        }
    }
    brdf_set(
        file,
        "measurements",
        angles,
        None,
        ["r", "g", "b"].into_iter().zip(values),
    )
}

/// `u(θ) = √(2θ/π)`.
fn theta2u(theta: f64) -> f64 {
    (theta * 2.0 / PI).sqrt()
}

/// `u(φ) = (φ + π)/(2π)`.
fn phi2u(phi: f64) -> f64 {
    (phi + PI) / (2.0 * PI)
}

/// The fields of a tensor file by name.
fn fields<'a>(file: &Path, bytes: &'a [u8]) -> Result<Vec<(String, Field<'a>)>, ReadError> {
    let at = |offset: usize, message: &str| {
        ReadError::format(file, 0, format!("byte {offset}: {message}"))
    };
    if bytes.get(..12) != Some(&MAGIC[..]) {
        return Err(at(
            0,
            "not a tensor file (it starts with `tensor_file` and a zero byte)",
        ));
    }
    if bytes.get(12..14) != Some(&[1, 0]) {
        return Err(at(12, "not a tensor file of version 1.0"));
    }
    let mut pos: usize = 14;
    let mut take = |len: usize| -> Result<&'a [u8], ReadError> {
        let end = pos.checked_add(len).filter(|&e| e <= bytes.len());
        let out = end
            .map(|e| &bytes[pos..e])
            .ok_or_else(|| at(pos, "the header ends early"))?;
        pos += len;
        Ok(out)
    };
    let le = |b: &[u8]| b.iter().rev().fold(0u64, |v, &x| (v << 8) | u64::from(x));
    let count = le(take(4)?);
    let mut out = Vec::new();
    for _ in 0..count {
        let name_len = le(take(2)?) as usize;
        let name = String::from_utf8_lossy(take(name_len)?).into_owned();
        let ndim = le(take(2)?) as usize;
        let dtype = take(1)?[0];
        let offset = le(take(8)?);
        let mut shape = Vec::with_capacity(ndim.min(8));
        for _ in 0..ndim {
            shape.push(le(take(8)?));
        }
        let width: u64 = match dtype {
            1 | 2 => 1,
            3 | 4 => 2,
            5 | 6 | 10 => 4,
            7 | 8 | 11 => 8,
            9 => 2,
            _ => return Err(at(0, &format!("field `{name}`: unknown type {dtype}"))),
        };
        let size = shape
            .iter()
            .try_fold(width, |s, &d| s.checked_mul(d))
            .and_then(|s| s.checked_add(offset).map(|end| (s, end)))
            .filter(|&(_, end)| end <= bytes.len() as u64);
        let Some((size, _)) = size else {
            return Err(at(
                offset.min(usize::MAX as u64) as usize,
                &format!(
                    "field `{name}`: its data ({shape:?} of type {dtype}) lies outside the file"
                ),
            ));
        };
        let data = &bytes[offset as usize..(offset + size) as usize];
        let shape = shape.into_iter().map(|d| d as usize).collect();
        out.push((name, Field { dtype, shape, data }));
    }
    Ok(out)
}

/// A grid of values over the unit square (x: columns, y: rows), evaluated
/// bilinearly.
struct Grid {
    values: Vec<f64>,
    width: usize,
    height: usize,
}

impl Grid {
    fn new(values: Vec<f64>, width: usize, height: usize) -> Self {
        Self {
            values,
            width,
            height,
        }
    }

    /// The bilinear interpolant at `[x, y]` in the unit square.
    fn eval(&self, [x, y]: [f64; 2]) -> f64 {
        let (px, py) = (x * (self.width - 1) as f64, y * (self.height - 1) as f64);
        let (ix, iy) = (
            (px.max(0.0) as usize).min(self.width - 2),
            (py.max(0.0) as usize).min(self.height - 2),
        );
        let (wx, wy) = (px - ix as f64, py - iy as f64);
        let at = |i: usize, j: usize| self.values[j * self.width + i];
        (1.0 - wy) * ((1.0 - wx) * at(ix, iy) + wx * at(ix + 1, iy))
            + wy * ((1.0 - wx) * at(ix, iy + 1) + wx * at(ix + 1, iy + 1))
    }
}

/// The marginal–conditional warp of a density given at the nodes of a
/// `size × size` grid over the unit square, bilinear in each cell: the
/// conditional CDF of each row over x, the marginal over y of the rows'
/// totals (trapezoids), both normalised to end at 1.
struct Warp {
    size: usize,
    data: Vec<f64>,
    conditional: Vec<f64>,
    marginal: Vec<f64>,
}

impl Warp {
    /// The warp of `density` (row-major, `size × size`); `None` when its
    /// mass is not positive and finite.
    fn new(density: &[f64], size: usize) -> Option<Self> {
        let mut conditional = vec![0.0; size * size];
        for y in 0..size {
            let row = &density[y * size..(y + 1) * size];
            let mut sum = 0.0;
            for x in 0..size - 1 {
                sum += 0.5 * (row[x] + row[x + 1]);
                conditional[y * size + x + 1] = sum;
            }
        }
        let mut marginal = vec![0.0; size];
        let mut sum = 0.0;
        for y in 0..size - 1 {
            sum += 0.5 * (conditional[(y + 1) * size - 1] + conditional[(y + 2) * size - 1]);
            marginal[y + 1] = sum;
        }
        let total = marginal[size - 1];
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let data = density.iter().map(|d| d / total).collect();
        conditional.iter_mut().for_each(|c| *c /= total);
        marginal.iter_mut().for_each(|m| *m /= total);
        Some(Self {
            size,
            data,
            conditional,
            marginal,
        })
    }

    /// The largest `i` in `[0, size − 2]` with `pred(i)` true, the
    /// predicate being monotone (true then false), as the reference's
    /// interval search (0 when none is).
    fn interval(size: usize, pred: impl Fn(usize) -> bool) -> usize {
        (1..size - 1).take_while(|&i| pred(i)).last().unwrap_or(0)
    }

    /// The point of the unit square that the uniform `sample` maps to: the
    /// row by the marginal CDF (the density linear in y within a cell), then
    /// the column by the conditional CDF between the row's two edges.
    fn sample(&self, sample: [f64; 2]) -> [f64; 2] {
        let n = self.size;
        let [mut sx, mut sy] = sample.map(|s| s.clamp(1.0 - ONE_MINUS_EPSILON, ONE_MINUS_EPSILON));
        let row = Self::interval(n, |i| self.marginal[i] < sy);
        sy -= self.marginal[row];
        let offset = row * n;
        let (r0, r1) = (
            self.conditional[offset + n - 1],
            self.conditional[offset + 2 * n - 1],
        );
        sy = solve(r0, r1, sy);
        sx *= (1.0 - sy) * r0 + sy * r1;
        let conditional = |i: usize| {
            (1.0 - sy) * self.conditional[offset + i] + sy * self.conditional[offset + n + i]
        };
        let col = Self::interval(n, |i| conditional(i) < sx);
        sx -= conditional(col);
        let at = offset + col;
        let c0 = (1.0 - sy) * self.data[at] + sy * self.data[at + n];
        let c1 = (1.0 - sy) * self.data[at + 1] + sy * self.data[at + n + 1];
        sx = solve(c0, c1, sx);
        let patch = 1.0 / (n - 1) as f64;
        [(col as f64 + sx) * patch, (row as f64 + sy) * patch]
    }
}

/// Where in a cell the integral of a density linear from `v0` to `v1`
/// reaches `target` (the cell's width 1): the root of `v0 t + (v1 − v0)
/// t²/2 = target`, or `2 target/(v0 + v1)` where the two nearly agree.
fn solve(v0: f64, v1: f64, target: f64) -> f64 {
    if (v0 - v1).abs() < 1e-4 * (v0 + v1) {
        2.0 * target / (v0 + v1)
    } else {
        (v0 - (v0 * v0 - 2.0 * target * (v0 - v1)).max(0.0).sqrt()) / (v0 - v1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The warp of a constant density is the identity; of a density rising
    /// along x, it moves samples towards larger x; every output stays in the
    /// unit square and is monotone in each coordinate.
    #[test]
    fn the_warp_is_the_identity_on_a_constant_and_monotone() {
        let flat = Warp::new(&[1.0; 16], 4).unwrap();
        for &(x, y) in &[(0.1, 0.2), (0.5, 0.5), (0.9, 0.3)] {
            let [u, v] = flat.sample([x, y]);
            assert!(
                (u - x).abs() < 1e-9 && (v - y).abs() < 1e-9,
                "{x} {y} -> {u} {v}"
            );
        }
        let rising: Vec<f64> = (0..16).map(|i| 1.0 + (i % 4) as f64).collect();
        let warp = Warp::new(&rising, 4).unwrap();
        let mut last = 0.0;
        for i in 0..=20 {
            let x = i as f64 / 20.0;
            let [u, v] = warp.sample([x, 0.5]);
            assert!((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v));
            assert!(u >= last, "not monotone at {x}");
            last = u;
        }
        assert!(warp.sample([0.5, 0.5])[0] > 0.5);
        assert!(Warp::new(&[0.0; 16], 4).is_none());
    }

    /// A tensor file of the wrong kind is an error naming the defect.
    #[test]
    fn defects_name_the_byte_and_field() {
        let parse = |b: &[u8]| parse_rgl(Path::new("m.bsdf"), b).unwrap_err().to_string();
        assert!(parse(b"hello").contains("m.bsdf: byte 0: not a tensor file"));
        let mut head = MAGIC.to_vec();
        head.extend_from_slice(&[2, 0]);
        assert!(parse(&head).contains("byte 12: not a tensor file of version 1.0"));
        head[12] = 1;
        head.extend_from_slice(&1u32.to_le_bytes());
        assert!(parse(&head).contains("byte 18: the header ends early"));
        // One field whose data lie beyond the end.
        head.extend_from_slice(&7u16.to_le_bytes());
        head.extend_from_slice(b"theta_i");
        head.extend_from_slice(&1u16.to_le_bytes());
        head.push(10);
        head.extend_from_slice(&1000u64.to_le_bytes());
        head.extend_from_slice(&8u64.to_le_bytes());
        let e = parse(&head);
        assert!(
            e.contains("field `theta_i`: its data ([8] of type 10) lies outside the file"),
            "{e}"
        );
        // A readable file without the fields an RGL BRDF has.
        let len = head.len() as u64;
        head.truncate(head.len() - 16);
        head.extend_from_slice(&len.to_le_bytes());
        head.extend_from_slice(&1u64.to_le_bytes());
        head.extend_from_slice(&0.5f32.to_le_bytes());
        let e = parse(&head);
        assert!(e.contains("no field `phi_i`"), "{e}");
    }
}
