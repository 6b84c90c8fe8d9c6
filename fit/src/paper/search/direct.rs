//! SearchPath 1, the direct search: every (parameter set, measurement) pair is
//! evaluated in full by [`components`], nothing hoisted, and the error is the
//! literal two-pass form of the paper (normalise, then eq. 15). In `f64` this
//! is the accuracy reference of every other path.

use super::packed::{lane_max, lane_sum, normalise, Packed, WIDTH};
use crate::grid::Grid;
use laminar_brdf_core::{components, mix, Correlation, Lane, Params};

/// The sum of squared residuals `Σ (D − P)²` of the paper-normalised mix
/// `P = β U + (1 − β) S` (docs/conventions.md §4; eq. 15 before the root): one pass
/// for the max of the mix, a second for the residuals.
pub fn two_pass_sum<L: Lane>(packed: &Packed<L>, surface: &[L], subsurface: &[L], beta: L) -> f64 {
    let mut m = L::c(0.0);
    for (s, u) in surface.iter().zip(subsurface) {
        m = m.max(mix(beta, *u, *s));
    }
    let m = lane_max(m);
    let positive = m > L::Scalar::c(0.0);
    let m = L::splat(m);
    let mut acc = [L::c(0.0); WIDTH];
    for (stream, a) in acc.iter_mut().take(packed.streams()).enumerate() {
        let range = packed.stream(stream);
        for ((s, u), d) in surface[range.clone()]
            .iter()
            .zip(&subsurface[range.clone()])
            .zip(&packed.data[range])
        {
            let p = if positive {
                mix(beta, *u, *s) / m
            } else {
                L::c(0.0)
            };
            let e = *d - p;
            *a = *a + e * e;
        }
    }
    Packed::<L>::objective(lane_sum(&acc))
}

/// Visits every (n, a, β) of slope index `i_s` in loop order as
/// `visit(flat index, a index, Σ (D − P)²)`, evaluating the whole model for
/// every parameter set.
pub fn shard<L: Lane>(
    packed: &Packed<L>,
    grid: &Grid,
    corr: Correlation,
    i_s: usize,
    mut visit: impl FnMut(usize, usize, f64),
) {
    let chunks = packed.geom.len();
    let (mut surface, mut subsurface) = (vec![L::c(0.0); chunks], vec![L::c(0.0); chunks]);
    let slope = grid.slope.values[i_s];
    for (i_n, &n) in grid.n.values.iter().enumerate() {
        for (i_a, &a) in grid.a.values.iter().enumerate() {
            for (i_b, &beta) in grid.beta.values.iter().enumerate() {
                let p = Params::new(slope, beta, n, a).expect("grid validated");
                for (c, g) in packed.geom.iter().enumerate() {
                    let v = components(g, corr, &p);
                    surface[c] = v.surface * packed.valid[c];
                    subsurface[c] = v.subsurface * packed.valid[c];
                }
                normalise(&mut surface);
                normalise(&mut subsurface);
                visit(
                    grid.flat(i_s, i_n, i_a, i_b),
                    i_a,
                    two_pass_sum(packed, &surface, &subsurface, L::c(beta)),
                );
            }
        }
    }
}
