//! Sums over the measurements in `f64`, shared by the one-pass and envelope
//! methods (docs/conventions.md §4). The model side ([`SurfaceSums`], per
//! σ/T) is kept apart from the data side ([`DataSums`], per scene and σ/T),
//! so that scenes on one geometry share the first.
//!
//! The lane values are widened exactly and summed in measurement order, so
//! an `f32x8` path and its scalar twin get the same bits.

use super::packed::Packed;
pub use laminar_brdf_core::onepass::{dot, DataSums};
use laminar_brdf_core::Lane;

/// Per-σ/T model quantities: the widened normalised surface term `S`, the
/// order of `S` (used by the envelope's Pareto front) and `Σ S²`.
pub struct SurfaceSums {
    /// `S` widened, in measurement order.
    pub s: Vec<f64>,
    /// Measurements by decreasing `S` (ties: increasing index).
    pub order: Vec<usize>,
    /// `Σ S²`.
    pub ss: f64,
}

impl SurfaceSums {
    /// Widens `surface` and computes its sum of squares and order.
    pub fn new<L: Lane>(packed: &Packed<L>, surface: &[L]) -> Self {
        let mut s = vec![0.0; packed.k];
        packed.widen(surface, &mut s);
        let mut order: Vec<usize> = (0..packed.k).collect();
        order.sort_by(|&a, &b| s[b].total_cmp(&s[a]).then(a.cmp(&b)));
        let ss = dot(&s, &s);
        Self { s, order, ss }
    }
}

/// `Σ x_k y_k` as four partial sums over `k mod 4`, added as
/// `(p0 + p1) + (p2 + p3)` and then the remainder in order: independent
/// chains the compiler vectorises, in a fixed order (the same bits on
/// every path that uses it).
pub fn dot4(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len().min(y.len());
    let (xc, xr) = x[..n].split_at(n - n % 4);
    let (yc, yr) = y[..n].split_at(n - n % 4);
    let mut p = [0.0; 4];
    for (x, y) in xc.chunks_exact(4).zip(yc.chunks_exact(4)) {
        for l in 0..4 {
            p[l] += x[l] * y[l];
        }
    }
    let mut sum = (p[0] + p[1]) + (p[2] + p[3]);
    for (x, y) in xr.iter().zip(yr) {
        sum += x * y;
    }
    sum
}
