//! Path 3, the closed-form β sweep. For the paper normalisation
//! (docs/conventions.md §4), with `X = (1 − β) S + β U = S + β Δ` (`Δ = U − S`) and
//! `M(β) = max_k X_k`,
//!
//! `Σ (D − X/M)² = Σ D² + (Σ X² / M − 2 Σ X D) / M`, where
//! `Σ X D = Σ S D + β Σ Δ D` and `Σ X² = Σ S² + β (2 Σ S Δ + β Σ Δ²)`,
//!
//! so six sums over the measurements (three per σ/T, three per (σ/T, n, a))
//! give the error of every β. `M(β)` is the upper envelope of the lines
//! `β ↦ (1 − β) S_k + β U_k`; on β ∈ [0, 1] only measurements on the Pareto
//! front of `(S_k, U_k)` can attain it (a dominated point's mix is never
//! larger, even after rounding, since every operation rounds monotonically),
//! and the front is found from the order of `S`, which is sorted once per
//! σ/T; the walk stops at the first `U_k = 1` (U is normalised, so no later
//! point can join). Along the front the slopes `U_k − S_k` increase, so the
//! upper hull of its lines is one monotone-stack pass, and a pointer walked
//! along the hull gives `M(β)` in amortised O(1) per β (instead of O(K)). The
//! hull drops lines that are never the maximum in exact arithmetic; after
//! rounding `M` is the full max to within an ulp or two, which the tests
//! against the direct path bound.
//!
//! `S` and `U` are computed in the lane precision of the path (that is what
//! the f32 variants trade for speed); they are widened exactly, and the sums,
//! the envelope and the error are evaluated in `f64` in measurement order, so
//! the `f32x8` path and its scalar twin agree bit for bit. The sums over `Δ`
//! are formed from `Δ` itself, not as differences of sums over `U` and `S`,
//! and the remaining cancellation in the formula above (about 100× on CUReT
//! fits) costs nothing visible in `f64`.
//!
//! A search needs only the minimum, so before its β loop each (σ/T, n, a)
//! is checked against a lower bound on its error over every β (see
//! `lower_bound` below); when the bound exceeds the best error found so far, no
//! β of the triple can win and the sweep is skipped. The bound is exact up
//! to a stated margin, so skipping never changes the result; error surfaces
//! (parity, the speed report) never skip.

use super::packed::Packed;
use super::sums::{DeltaSums, SurfaceSums};
use laminar_core::{mix, Lane};

/// Reusable per-shard buffers.
#[derive(Default)]
pub struct Scratch {
    pub(super) u: Vec<f64>,
    /// The Pareto front as `(S_k, U_k)`, by decreasing `S` and increasing `U`.
    front: Vec<(f64, f64)>,
    /// The upper hull of the front's lines, as `(S_k, U_k)`.
    pub(super) hull: Vec<(f64, f64)>,
    /// Total front size over the sweeps (for the report).
    pub front_total: usize,
    /// Number of sweeps whose β loop ran.
    pub sweeps: usize,
    /// Number of sweeps skipped by the lower bound.
    pub pruned: usize,
}

impl Scratch {
    /// The size of the Pareto front built last.
    pub(super) fn front_len(&self) -> usize {
        self.front.len()
    }
}

/// Calls `visit(i_b, Σ (D − P)²)` for every β of `betas`, in order, for one
/// (σ/T, n, a) with normalised subsurface `subsurface`, unless every one of
/// those values is certainly above `threshold` (`lower_bound` below); then it
/// visits nothing. `threshold = ∞` visits every β.
pub fn sweep<L: Lane>(
    packed: &Packed<L>,
    surface: &SurfaceSums,
    subsurface: &[L],
    betas: &[f64],
    threshold: f64,
    scratch: &mut Scratch,
    visit: impl FnMut(usize, f64),
) {
    let k = packed.k;
    scratch.u.resize(k, 0.0);
    packed.widen(subsurface, &mut scratch.u);
    let u = &scratch.u;
    let sums = DeltaSums::new(surface, |k| u[k] - surface.s[k]);
    if lower_bound(surface, &sums) > threshold {
        scratch.pruned += 1;
        return;
    }
    build_hull(surface, scratch);
    sweep_hull(&scratch.hull, surface, &sums, betas, visit);
}

/// The Pareto front of `(S_k, U_k)` (`U` already widened into `scratch.u`)
/// and the upper hull of its lines, into `scratch`; counts one sweep.
pub(super) fn build_hull(surface: &SurfaceSums, scratch: &mut Scratch) {
    let u = &scratch.u;
    scratch.front.clear();
    let mut top = f64::NEG_INFINITY;
    for &i in &surface.order {
        if u[i] > top {
            top = u[i];
            scratch.front.push((surface.s[i], u[i]));
            if top >= 1.0 {
                // U is normalised (no value above 1): no later point, with
                // its smaller S, can join the front.
                break;
            }
        }
    }
    scratch.front_total += scratch.front.len();
    scratch.sweeps += 1;
    upper_hull(&scratch.front, &mut scratch.hull);
}

/// Calls `visit(i_b, Σ (D − P)²)` for every β, walking `M(β)` along `hull`.
pub(super) fn sweep_hull(
    hull: &[(f64, f64)],
    surface: &SurfaceSums,
    sums: &DeltaSums,
    betas: &[f64],
    mut visit: impl FnMut(usize, f64),
) {
    let mut p = 0;
    for (i_b, &beta) in betas.iter().enumerate() {
        let value = |i: usize| mix(beta, hull[i].1, hull[i].0);
        while p + 1 < hull.len() && value(p + 1) >= value(p) {
            p += 1;
        }
        while p > 0 && value(p - 1) > value(p) {
            p -= 1;
        }
        let m = value(p);
        let e = if m > 0.0 {
            let inv = 1.0 / m;
            let (xd, xx) = sums.mix(surface, beta);
            surface.dd + inv * (inv * xx - 2.0 * xd)
        } else {
            surface.dd
        };
        visit(i_b, e.max(0.0));
    }
}

/// A lower bound on `Σ (D − X/M)²` over every β, from the sums alone.
///
/// For every β the prediction `X/M = ((1 − β)/M) S + (β/M) U` is one point of
/// the plane spanned by `S` and `Δ`, so its error is at least the
/// least-squares residual of `D` on that plane,
/// `R = Σ D² − (Σ S D)² / Σ S² − t² / q` with `q = Σ Δ² − (Σ S Δ)² / Σ S²`
/// (the part of `Δ` orthogonal to `S`) and `t = Σ D Δ − Σ S Δ Σ S D / Σ S²`.
///
/// Rounding: with `q ≥ 10⁻⁶ Σ Δ²` (otherwise the bound falls back to 0) the
/// computed `R` is within about `2·10⁻¹² Σ D²` of the exact one, and the error
/// the sweep would compute is within about `10⁻¹⁰ Σ D²` of the exact error.
/// The bound returned is `R − 10⁻⁸ Σ D²`, so every computed error of the
/// triple is at least the bound: a triple is skipped only if none of its
/// values could reach the threshold.
pub(super) fn lower_bound(surface: &SurfaceSums, sums: &DeltaSums) -> f64 {
    let (ss, del_del) = (surface.ss, sums.del_del);
    if ss <= 0.0 || del_del <= 0.0 {
        return 0.0;
    }
    let q = del_del - sums.s_del * sums.s_del / ss;
    if q < 1e-6 * del_del {
        return 0.0;
    }
    let t = sums.d_del - sums.s_del * surface.sd / ss;
    let residual = surface.dd - surface.sd * surface.sd / ss - t * t / q;
    residual - 1e-8 * surface.dd
}

/// The upper envelope of the lines `β ↦ S + β (U − S)` of `front` (slopes
/// strictly increasing), by the monotone-stack convex-hull pass: the middle of
/// three lines goes when the outer two meet at or before where it meets the first.
fn upper_hull(front: &[(f64, f64)], hull: &mut Vec<(f64, f64)>) {
    hull.clear();
    for &(s, u) in front {
        while let [.., (s1, u1), (s2, u2)] = hull[..] {
            let (b1, b2, b3) = (u1 - s1, u2 - s2, u - s);
            if (s1 - s) * (b2 - b1) <= (s1 - s2) * (b3 - b1) {
                hull.pop();
            } else {
                break;
            }
        }
        hull.push((s, u));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{Axis, Grid};
    use crate::search::packed::Tables;
    use crate::synthetic;
    use laminar_core::{f32x8, Correlation, Params};

    /// A test grid: the paper's β axis, `slope = (first, last, count)` σ/T
    /// values, and `n`, `a` values spread over their whole domain.
    fn grid(slope: (f64, f64, usize), n: usize, a: usize) -> Grid {
        Grid {
            slope: Axis::linspace(slope.0, slope.1, slope.2),
            n: Axis::linspace(1.0, 2.0, n),
            a: Axis::linspace(0.0, 1.0, a),
            ..Grid::paper()
        }
    }

    /// Calls `f(σ/T, packed, surface sums, U, scratch)` for every (σ/T, n, a)
    /// of `grid` on a noisy synthetic scene made by `corr` at `truth`.
    fn each_triple<L: Lane>(
        corr: Correlation,
        truth: &Params,
        seed: u64,
        grid: &Grid,
        mut f: impl FnMut(f64, &Packed<L>, &SurfaceSums, &[L], &mut Scratch),
    ) {
        let scene = synthetic::scene(corr, truth, 0.01, seed);
        let tables = Tables::<L>::new(&scene, grid);
        for &slope in &grid.slope.values {
            let surface = tables.surface(corr, slope);
            let sums = SurfaceSums::new(&tables.packed, &surface);
            let mut scratch = Scratch::default();
            tables.for_each_subsurface(corr, slope, |_, _, u| {
                f(slope, &tables.packed, &sums, u, &mut scratch)
            });
        }
    }

    /// The values a sweep visits at `threshold`.
    fn visited<L: Lane>(
        packed: &Packed<L>,
        sums: &SurfaceSums,
        u: &[L],
        betas: &[f64],
        threshold: f64,
        scratch: &mut Scratch,
    ) -> Vec<f64> {
        let mut out = Vec::new();
        sweep(packed, sums, u, betas, threshold, scratch, |_, e| {
            out.push(e)
        });
        out
    }

    /// The lower bound of the triple the last sweep widened into `scratch`.
    fn bound_of(sums: &SurfaceSums, scratch: &Scratch) -> f64 {
        lower_bound(sums, &DeltaSums::new(sums, |k| scratch.u[k] - sums.s[k]))
    }

    /// Every (σ/T, n, a) of a grid that includes n = 1, a = 0 (where U = S
    /// and the bound must fall back) and poor fits far from the truth: the
    /// bound never exceeds any value the sweep computes, and it is not
    /// vacuous.
    #[test]
    fn lower_bound_is_below_every_computed_error() {
        let corr = Correlation::Exponential;
        let truth = Params::new(1.48, 0.39, 1.44, 0.2).unwrap();
        let grid = grid((0.12, 4.04, 9), 6, 6);
        let (mut checked, mut useful) = (0, 0);
        each_triple::<f32x8>(corr, &truth, 3, &grid, |slope, packed, sums, u, scratch| {
            let all = visited(packed, sums, u, &grid.beta.values, f64::INFINITY, scratch);
            assert_eq!(
                all.len(),
                grid.beta.len(),
                "an infinite threshold skipped a sweep"
            );
            let min = all.iter().copied().fold(f64::INFINITY, f64::min);
            let bound = bound_of(sums, scratch);
            assert!(bound <= min, "slope {slope}: bound {bound} > min {min}");
            checked += 1;
            useful += usize::from(bound > 0.5 * min);
        });
        assert_eq!(checked, 9 * 6 * 6);
        assert!(
            useful > checked / 2,
            "bound useful on only {useful} of {checked}"
        );
    }

    /// A threshold at or above a triple's minimum never skips it; one below
    /// its bound does.
    #[test]
    fn threshold_skips_only_triples_that_cannot_reach_it() {
        let corr = Correlation::Gaussian;
        let truth = Params::new(0.68, 0.5, 1.3, 0.4).unwrap();
        let grid = grid((0.2, 3.0, 5), 4, 4);
        let betas = &grid.beta.values;
        each_triple::<f32>(corr, &truth, 5, &grid, |_, packed, sums, u, scratch| {
            let all = visited(packed, sums, u, betas, f64::INFINITY, scratch);
            let min = all.iter().copied().fold(f64::INFINITY, f64::min);
            let again = visited(packed, sums, u, betas, min, scratch);
            assert_eq!(all, again, "skipped a triple that reaches the threshold");
            let bound = bound_of(sums, scratch);
            if bound > 0.0 {
                let before = scratch.pruned;
                let none = visited(packed, sums, u, betas, 0.5 * bound, scratch);
                assert!(
                    none.is_empty(),
                    "visited a triple whose bound exceeds the threshold"
                );
                assert_eq!(scratch.pruned, before + 1);
            }
        });
    }
}
