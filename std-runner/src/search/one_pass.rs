//! Path 2, the hoisted one-pass β sweep: for each β, one pass over the
//! measurements accumulates the max `M` of the mix `X = β U + (1 − β) S` and
//! three sums from which the paper-normalised error follows (conventions §4,
//! eq. 15) without a second pass.
//!
//! With a shift `c` chosen before the pass, `D − X/M = r + δ X` where
//! `r = D − c X` and `δ = c − 1/M`, so
//! `Σ (D − X/M)² = Σ r² + 2 δ Σ r X + δ² Σ X²`.
//! Taking `c = 1/M` of the previous β (which moves little from one β to the
//! next) keeps `δ` small, so the sum is not the difference of large terms
//! that `Σ D² − 2 Σ X D / M + Σ X² / M²` would be (about 100× cancellation
//! on CUReT fits, fatal in `f32`).

use super::packed::{lane_max, lane_sum, Packed, WIDTH};
use laminar_core::Lane;

/// Per-stream accumulators of one pass.
#[derive(Clone, Copy)]
struct Sums<L> {
    max: L,
    rr: L,
    rx: L,
    xx: L,
}

/// Calls `visit(i_b, Σ (D − P)²)` for every β of `betas`, in order, for one
/// (σ/T, n, a) with normalised surface `surface` and subsurface `subsurface`.
pub fn sweep<L: Lane>(
    packed: &Packed<L>,
    surface: &[L],
    subsurface: &[L],
    betas: &[L],
    mut visit: impl FnMut(usize, f64),
) {
    let zero = L::Scalar::c(0.0);
    let one = L::Scalar::c(1.0);
    let delta: Vec<L> = subsurface
        .iter()
        .zip(surface)
        .map(|(u, s)| *u - *s)
        .collect();
    let mut c = one;
    for (i_b, &beta) in betas.iter().enumerate() {
        let shift = L::splat(c);
        let mut acc = [Sums {
            max: L::c(0.0),
            rr: L::c(0.0),
            rx: L::c(0.0),
            xx: L::c(0.0),
        }; WIDTH];
        for (stream, a) in acc.iter_mut().take(packed.streams()).enumerate() {
            let range = packed.stream(stream);
            for ((s, dl), d) in surface[range.clone()]
                .iter()
                .zip(&delta[range.clone()])
                .zip(&packed.data[range])
            {
                let x = *s + beta * *dl;
                let r = *d - shift * x;
                a.max = a.max.max(x);
                a.rr = a.rr + r * r;
                a.rx = a.rx + r * x;
                a.xx = a.xx + x * x;
            }
        }
        let m = acc
            .iter()
            .take(packed.streams())
            .fold(zero, |m, a| m.max(lane_max(a.max)));
        let rr = lane_sum(&acc.map(|a| a.rr));
        let e = if m > zero {
            let inv = one / m;
            let delta = c - inv;
            c = inv;
            let rx = lane_sum(&acc.map(|a| a.rx));
            let xx = lane_sum(&acc.map(|a| a.xx));
            rr + L::Scalar::c(2.0) * delta * rx + delta * delta * xx
        } else {
            // Every X is 0, so P = 0 and r = D.
            rr
        };
        visit(i_b, Packed::<L>::objective(e));
    }
}
