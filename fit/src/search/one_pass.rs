//! Path 2, the hoisted one-pass β sweep: for each β, one pass over the
//! measurements accumulates the max `M` of the mix `X = S + β Δ`
//! (`Δ = U − S`, i.e. `β U + (1 − β) S`) and the one sum from which, with
//! sums hoisted out of the β loop, the paper-normalised error follows
//! (docs/conventions.md §4, eq. 15) without a second pass.
//!
//! With a shift `c` chosen before the pass, `D − X/M = r + δ X` where
//! `r = D − c X` and `δ = c − 1/M`, so
//! `Σ (D − X/M)² = Σ r² + 2 δ Σ r X + δ² Σ X²`.
//! Taking `c = 1/M` of the previous β (which moves little from one β to the
//! next) keeps `δ` small, so the sum is not the difference of large terms
//! that `Σ D² − 2 Σ X D / M + Σ X² / M²` would be (about 100× cancellation
//! on CUReT fits, fatal in `f32`). The pass accumulates `Σ r²` and the max in
//! the path's arithmetic. The two correction terms are polynomials in β of
//! sums that do not depend on β ([`super::sums`]: `Σ X² = Σ S² + β (2 Σ S Δ
//! + β Σ Δ²)`, `Σ r X = Σ D X − c Σ X²` with `Σ D X = Σ S D + β Σ D Δ`),
//! hoisted to once per (σ/T, n, a) and evaluated in `f64`. `Σ r X` is itself
//! a cancelling difference, but it enters multiplied by `δ`, so its rounding
//! reaches the objective scaled by that small factor (measured: `onepass-f64`
//! within 1e-14 of `direct-f64` in Δ_RMS, README).

use super::packed::{lane_max, lane_sum, Packed, WIDTH};
use super::sums::{DataSums, DeltaSums, SurfaceSums};
use laminar_core::{Lane, Real};

/// Per-stream accumulators of one pass.
#[derive(Clone, Copy)]
struct Sums<L> {
    max: L,
    rr: L,
}

/// The widened side of one σ/T: the surface term's sums and the scene's
/// data `d` with its sums against it.
pub struct Widened<'a> {
    /// The surface term widened.
    pub surface: &'a SurfaceSums,
    /// The data widened, in measurement order.
    pub d: &'a [f64],
    /// `Σ S D`, `Σ D²`.
    pub data: DataSums,
}

/// Reusable per-shard buffers: `Δ` in lanes and widened.
pub struct Scratch<L> {
    delta: Vec<L>,
    delta_f64: Vec<f64>,
}

impl<L> Default for Scratch<L> {
    fn default() -> Self {
        Self {
            delta: Vec::new(),
            delta_f64: Vec::new(),
        }
    }
}

/// Calls `visit(i_b, Σ (D − P)²)` for every β of `betas`, in order, for one
/// (σ/T, n, a) with normalised surface `surface` (widened in `wide`) and
/// subsurface `subsurface`.
pub fn sweep<L: Lane>(
    packed: &Packed<L>,
    surface: &[L],
    wide: &Widened<'_>,
    subsurface: &[L],
    betas: &[f64],
    scratch: &mut Scratch<L>,
    mut visit: impl FnMut(usize, f64),
) {
    let zero = L::Scalar::c(0.0);
    let one = L::Scalar::c(1.0);
    let Scratch { delta, delta_f64 } = scratch;
    delta.clear();
    delta.extend(subsurface.iter().zip(surface).map(|(u, s)| *u - *s));
    delta_f64.resize(packed.k, 0.0);
    packed.widen(delta, delta_f64);
    let hoisted = DeltaSums::new(wide.surface, wide.d, delta_f64);
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
        for (stream, a) in acc.iter_mut().take(packed.streams()).enumerate() {
            let range = packed.stream(stream);
            for ((s, dl), d) in surface[range.clone()]
                .iter()
                .zip(&delta[range.clone()])
                .zip(&packed.data[range])
            {
                let x = *s + b * *dl;
                let r = *d - shift * x;
                a.max = a.max.max(x);
                a.rr = a.rr + r * r;
            }
        }
        let m = acc
            .iter()
            .take(packed.streams())
            .fold(zero, |m, a| m.max(lane_max(a.max)));
        let rr = lane_sum(&acc.map(|a| a.rr)).to_f64();
        let e = if m > zero {
            let (c64, m64) = (c.to_f64(), m.to_f64());
            // δ = c − 1/M.
            let shift_error = c64 - 1.0 / m64;
            c = one / m;
            let (xd, xx) = hoisted.mix(wide.surface, &wide.data, beta_lane.to_f64());
            let rx = xd - c64 * xx;
            rr + 2.0 * shift_error * rx + shift_error * shift_error * xx
        } else {
            // Every X is 0, so P = 0 and r = D.
            rr
        };
        visit(i_b, e.max(0.0));
    }
}
