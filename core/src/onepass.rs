//! The one-pass β sweep of the grid search (docs/conventions.md §4, eq. 15),
//! allocation-free over caller-owned slices: the kernel of the fitting
//! library's `onepass` paths and of the on-device fit ([`crate::small_fit`]).
//!
//! **Layout.** Measurements are packed in chunks of `L::LANES` so that
//! every lane type sees measurement `k` at the same *global lane*
//! `k % WIDTH`: chunk `k / WIDTH` of stream `(k % WIDTH) / L::LANES`, chunks
//! stream-major ([`Layout`]). With `f32x8` there is one stream; with a
//! scalar type there are eight, one per global lane. Sums keep one partial
//! sum per global lane and add them in a fixed order, so a scalar twin
//! gets the SIMD path's bits.
//!
//! **The sweep.** For each β, one pass over the measurements accumulates
//! the max `M` of the mix `X = S + β Δ` (`Δ = U − S`, i.e.
//! `β U + (1 − β) S`) and the one sum from which, with sums hoisted out of
//! the β loop, the paper-normalised error follows without a second pass.
//! With a shift `c` chosen before the pass, `D − X/M = r + δ X` where
//! `r = D − c X` and `δ = c − 1/M`, so
//! `Σ (D − X/M)² = Σ r² + 2 δ Σ r X + δ² Σ X²`.
//! Taking `c = 1/M` of the previous β (which moves little from one β to the
//! next) keeps `δ` small, so the sum is not the difference of large terms
//! that `Σ D² − 2 Σ X D / M + Σ X² / M²` would be (about 100× cancellation
//! on CUReT fits, fatal in `f32`). The pass accumulates `Σ r²` and the max in
//! the lane arithmetic. The two correction terms are polynomials in β of
//! sums that do not depend on β (`Σ X² = Σ S² + β (2 Σ S Δ + β Σ Δ²)`,
//! `Σ r X = Σ D X − c Σ X²` with `Σ D X = Σ S D + β Σ D Δ`), hoisted to once
//! per (σ/T, n, a) and evaluated in `f64`. `Σ r X` is itself a cancelling
//! difference, but it enters multiplied by `δ`, so its rounding reaches the
//! objective scaled by that small factor.

use crate::lane::{Lane, Real};
use core::ops::Range;

/// Global lanes: the lanes of the widest path, and the number of partial
/// sums every path keeps, so that a scalar twin adds in the SIMD order.
pub const WIDTH: usize = 8;

/// Where each of `k` measurements sits in packed slices (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Number of measurements K.
    pub k: usize,
    /// Chunks per stream (`⌈K / WIDTH⌉`).
    pub per_stream: usize,
}

impl Layout {
    /// The layout of `k` measurements.
    #[must_use]
    pub fn new(k: usize) -> Self {
        Self {
            k,
            per_stream: k.div_ceil(WIDTH),
        }
    }

    /// Number of streams for lane type `L` (`WIDTH / L::LANES`).
    #[must_use]
    pub fn streams<L: Lane>(&self) -> usize {
        WIDTH / L::LANES
    }

    /// Number of packed chunks for lane type `L`.
    #[must_use]
    pub fn chunks<L: Lane>(&self) -> usize {
        self.per_stream * self.streams::<L>()
    }

    /// The flat chunk indices of stream `stream`.
    #[must_use]
    pub fn stream(&self, stream: usize) -> Range<usize> {
        stream * self.per_stream..(stream + 1) * self.per_stream
    }

    /// The measurement in lane `lane` of flat chunk `chunk` for lane type
    /// `L` (≥ K in padding lanes).
    #[must_use]
    pub fn measurement<L: Lane>(&self, chunk: usize, lane: usize) -> usize {
        let (stream, c) = (chunk / self.per_stream, chunk % self.per_stream);
        c * WIDTH + stream * L::LANES + lane
    }

    /// The lane values of `values` widened to `f64`, in measurement order
    /// (slots past the end of `out` are skipped: no panic path).
    pub fn widen<L: Lane>(&self, values: &[L], out: &mut [f64]) {
        for (s, stream) in values.chunks_exact(self.per_stream).enumerate() {
            for (c, v) in stream.iter().enumerate() {
                let first = c * WIDTH + s * L::LANES;
                for lane in 0..L::LANES.min(self.k.saturating_sub(first)) {
                    if let Some(slot) = out.get_mut(first + lane) {
                        *slot = v.lane(lane).to_f64();
                    }
                }
            }
        }
    }
}

/// `Δ_RMS` (eq. 15) from the sum of squared residuals `e` over `k` measurements.
#[must_use]
pub fn rms_of_sum(e: f64, k: usize) -> f64 {
    100.0 * libm::sqrt(e) / k as f64
}

/// The sum of squared residuals `e` clamped at 0 and widened to `f64`:
/// what every method hands to the search.
#[must_use]
pub fn objective<S: Real>(e: S) -> f64 {
    e.max(S::c(0.0)).to_f64()
}

/// Largest lane value of `values` (exact, so order does not matter); 0 when
/// every value is ≤ 0.
#[must_use]
pub fn max_of<L: Lane>(values: &[L]) -> L::Scalar {
    let mut m = L::c(0.0);
    for v in values {
        m = m.max(*v);
    }
    lane_max(m)
}

/// Largest lane of one vector, at least 0.
#[must_use]
pub fn lane_max<L: Lane>(v: L) -> L::Scalar {
    (0..L::LANES).fold(L::Scalar::c(0.0), |m, lane| m.max(v.lane(lane)))
}

/// `Σ` over the eight global lanes of per-stream partial sums, in a fixed order.
#[must_use]
pub fn lane_sum<L: Lane>(partial: &[L]) -> L::Scalar {
    (0..WIDTH).fold(L::Scalar::c(0.0), |sum, g| {
        sum + partial[g / L::LANES].lane(g % L::LANES)
    })
}

/// `values / max(values)`, or zeros when the max is ≤ 0 (docs/conventions.md §4).
pub fn normalise<L: Lane>(values: &mut [L]) {
    let m = max_of(values);
    let zero = L::Scalar::c(0.0);
    for v in values.iter_mut() {
        *v = if m > zero {
            *v / L::splat(m)
        } else {
            L::c(0.0)
        };
    }
}

/// The chunks `range` of `values` (empty past its end: never reached by a
/// layout's own ranges, and no panic path in the embedded library).
fn part<'a, L>(values: &'a [L], range: &Range<usize>) -> &'a [L] {
    values.get(range.clone()).unwrap_or(&[])
}

/// `Σ x_k y_k` in measurement order.
#[must_use]
pub fn dot(x: &[f64], y: &[f64]) -> f64 {
    x.iter().zip(y).map(|(a, b)| a * b).sum()
}

/// The data side of one scene at one σ/T: `Σ S D` and `Σ D²`.
#[derive(Clone, Copy, Debug)]
pub struct DataSums {
    /// `Σ S D`.
    pub sd: f64,
    /// `Σ D²`.
    pub dd: f64,
}

impl DataSums {
    /// The sums of the widened data `d` against the widened surface term
    /// `s` (both in measurement order).
    #[must_use]
    pub fn new(s: &[f64], d: &[f64]) -> Self {
        Self {
            sd: dot(s, d),
            dd: dot(d, d),
        }
    }
}

/// The per-(σ/T, n, a) sums over `Δ = U − S` of the sweep.
#[derive(Clone, Copy, Debug)]
pub struct DeltaSums {
    /// `Σ Δ²`.
    pub del_del: f64,
    /// `Σ S Δ`.
    pub s_del: f64,
    /// `Σ D Δ`.
    pub d_del: f64,
}

impl DeltaSums {
    /// The sums for the widened `s`, data `d` and `Δ`, in measurement order.
    #[must_use]
    pub fn new(s: &[f64], d: &[f64], delta: &[f64]) -> Self {
        Self {
            del_del: dot(delta, delta),
            s_del: dot(s, delta),
            d_del: dot(d, delta),
        }
    }

    /// `(Σ X D, Σ X²)` of the mix `X = S + β Δ`, with `ss = Σ S²`.
    #[inline]
    #[must_use]
    pub fn mix(&self, ss: f64, data: &DataSums, beta: f64) -> (f64, f64) {
        (
            data.sd + beta * self.d_del,
            ss + beta * (2.0 * self.s_del + beta * self.del_del),
        )
    }
}

/// The widened side of one σ/T: the surface term `s` and `Σ S²`, the
/// scene's data `d`, and their sums.
#[derive(Clone, Copy, Debug)]
pub struct Widened<'a> {
    /// The normalised surface term widened, in measurement order.
    pub s: &'a [f64],
    /// `Σ S²`.
    pub ss: f64,
    /// The data widened, in measurement order.
    pub d: &'a [f64],
    /// `Σ S D`, `Σ D²`.
    pub data: DataSums,
}

/// The packed inputs of one (σ/T, n, a): the data `D`, the normalised
/// surface term `S` and subsurface term `U`, all in [`Layout`] order.
#[derive(Clone, Copy, Debug)]
pub struct Terms<'a, L> {
    /// Where each measurement sits.
    pub layout: &'a Layout,
    /// `D` (0 in padding lanes).
    pub data: &'a [L],
    /// `S` (0 in padding lanes).
    pub surface: &'a [L],
    /// `U` (0 in padding lanes).
    pub subsurface: &'a [L],
}

/// Per-stream accumulators of one pass.
#[derive(Clone, Copy)]
struct Sums<L> {
    max: L,
    rr: L,
}

/// Calls `visit(i_b, Σ (D − P)²)` for every β of `betas`, in order, for one
/// (σ/T, n, a). `delta` (one slot per chunk) and `delta_f64` (one per
/// measurement) are scratch.
pub fn sweep<L: Lane>(
    terms: Terms<'_, L>,
    wide: &Widened<'_>,
    betas: &[f64],
    (delta, delta_f64): (&mut [L], &mut [f64]),
    mut visit: impl FnMut(usize, f64),
) {
    let Terms {
        layout,
        data,
        surface,
        subsurface,
    } = terms;
    let zero = L::Scalar::c(0.0);
    let one = L::Scalar::c(1.0);
    for ((d, u), s) in delta.iter_mut().zip(subsurface).zip(surface) {
        *d = *u - *s;
    }
    layout.widen(delta, delta_f64);
    // `get`, not indexing: the same slices for every layout the callers
    // build, and no panic path in the embedded library.
    let hoisted = DeltaSums::new(wide.s, wide.d, delta_f64.get(..layout.k).unwrap_or(&[]));
    let delta = &*delta;
    let mut c = one;
    for (i_b, &beta) in betas.iter().enumerate() {
        // β as the lanes see it, so that the hoisted sums describe the same mix.
        let beta_lane = L::Scalar::from_f64(beta);
        let (b, shift) = (L::splat(beta_lane), L::splat(c));
        let mut acc = [Sums {
            max: L::c(0.0),
            rr: L::c(0.0),
        }; WIDTH];
        for (stream, a) in acc.iter_mut().take(layout.streams::<L>()).enumerate() {
            let range = layout.stream(stream);
            for ((s, dl), d) in part(surface, &range)
                .iter()
                .zip(part(delta, &range))
                .zip(part(data, &range))
            {
                let x = *s + b * *dl;
                let r = *d - shift * x;
                a.max = a.max.max(x);
                a.rr = a.rr + r * r;
            }
        }
        let m = acc
            .iter()
            .take(layout.streams::<L>())
            .fold(zero, |m, a| m.max(lane_max(a.max)));
        let rr = lane_sum(&acc.map(|a| a.rr)).to_f64();
        let e = if m > zero {
            let (c64, m64) = (c.to_f64(), m.to_f64());
            // δ = c − 1/M.
            let shift_error = c64 - 1.0 / m64;
            c = one / m;
            let (xd, xx) = hoisted.mix(wide.ss, &wide.data, beta_lane.to_f64());
            let rx = xd - c64 * xx;
            rr + 2.0 * shift_error * rx + shift_error * shift_error * xx
        } else {
            // Every X is 0, so P = 0 and r = D.
            rr
        };
        visit(i_b, e.max(0.0));
    }
}
