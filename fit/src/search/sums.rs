//! Sums over the measurements in `f64`, shared by the one-pass and envelope
//! methods: with `X = S + β Δ` (`Δ = U − S`, docs/conventions.md §4),
//! `Σ X D = Σ S D + β Σ Δ D` and `Σ X² = Σ S² + β (2 Σ S Δ + β Σ Δ²)`,
//! so three sums per σ/T and three per (σ/T, n, a) give both for every β.
//!
//! The lane values are widened exactly and summed in measurement order, so
//! an `f32x8` path and its scalar twin get the same bits.

use super::packed::Packed;
use laminar_core::Lane;

/// Per-σ/T quantities: the widened surface term and data, their sums, and
/// the order of `S` (used by the envelope's Pareto front).
pub struct SurfaceSums {
    /// `S` widened, in measurement order.
    pub s: Vec<f64>,
    /// `D` widened, in measurement order.
    pub d: Vec<f64>,
    /// Measurements by decreasing `S` (ties: increasing index).
    pub order: Vec<usize>,
    /// `Σ S²`.
    pub ss: f64,
    /// `Σ S D`.
    pub sd: f64,
    /// `Σ D²`.
    pub dd: f64,
}

impl SurfaceSums {
    /// Widens `surface` and the data and computes their sums.
    pub fn new<L: Lane>(packed: &Packed<L>, surface: &[L]) -> Self {
        let mut s = vec![0.0; packed.k];
        let mut d = vec![0.0; packed.k];
        packed.widen(surface, &mut s);
        packed.widen(&packed.data, &mut d);
        let mut order: Vec<usize> = (0..packed.k).collect();
        order.sort_by(|&a, &b| s[b].total_cmp(&s[a]).then(a.cmp(&b)));
        let ss = s.iter().map(|v| v * v).sum();
        let sd = s.iter().zip(&d).map(|(a, b)| a * b).sum();
        let dd = d.iter().map(|v| v * v).sum();
        Self {
            s,
            d,
            order,
            ss,
            sd,
            dd,
        }
    }
}

impl SurfaceSums {
    /// The same surface term with the data of `packed` (a scene on the same
    /// geometry): `S`, its order and `Σ S²` are shared, `D`, `Σ S D` and
    /// `Σ D²` computed as [`SurfaceSums::new`] does, so the bits are equal.
    pub fn with_data<L: Lane>(&self, packed: &Packed<L>) -> Self {
        let mut d = vec![0.0; packed.k];
        packed.widen(&packed.data, &mut d);
        let sd = self.s.iter().zip(&d).map(|(a, b)| a * b).sum();
        let dd = d.iter().map(|v| v * v).sum();
        Self {
            s: self.s.clone(),
            d,
            order: self.order.clone(),
            ss: self.ss,
            sd,
            dd,
        }
    }
}

/// The per-(σ/T, n, a) sums over `Δ`.
#[derive(Clone, Copy)]
pub struct DeltaSums {
    /// `Σ Δ²`.
    pub del_del: f64,
    /// `Σ S Δ`.
    pub s_del: f64,
    /// `Σ D Δ`.
    pub d_del: f64,
}

impl DeltaSums {
    /// The sums for `Δ_k = delta(k)`, in measurement order.
    pub fn new(surface: &SurfaceSums, delta: impl Fn(usize) -> f64) -> Self {
        let (mut del_del, mut s_del, mut d_del) = (0.0, 0.0, 0.0);
        for (k, (s, d)) in surface.s.iter().zip(&surface.d).enumerate() {
            let del = delta(k);
            del_del += del * del;
            s_del += s * del;
            d_del += d * del;
        }
        Self {
            del_del,
            s_del,
            d_del,
        }
    }

    /// The sums for the data of `surface` (a scene on the same geometry) when
    /// `Σ Δ²` and `Σ S Δ` are this one's: `Σ D Δ` in measurement order, as
    /// [`DeltaSums::new`] sums it, so the bits are equal.
    pub fn with_data(&self, surface: &SurfaceSums, delta: &[f64]) -> Self {
        let mut d_del = 0.0;
        for (d, del) in surface.d.iter().zip(delta) {
            d_del += d * del;
        }
        Self { d_del, ..*self }
    }

    /// `(Σ X D, Σ X²)` of the mix `X = S + β Δ`.
    #[inline]
    pub fn mix(&self, surface: &SurfaceSums, beta: f64) -> (f64, f64) {
        (
            surface.sd + beta * self.d_del,
            surface.ss + beta * (2.0 * self.s_del + beta * self.del_del),
        )
    }
}
