//! Path 3, the closed-form β sweep, for one scene or many on one geometry.
//!
//! **The β sweep.** For the paper normalisation (docs/conventions.md §4),
//! with the mix `X = (1 − β) S + β U` and `M(β) = max_k X_k`,
//!
//! `Σ (D − X/M)² = Σ D² + (Σ X² / M − 2 Σ X D) / M`, where
//! `Σ X D = (1 − β) Σ S D + β Σ U D` and
//! `Σ X² = (1 − β)² Σ S² + 2 β (1 − β) Σ S U + β² Σ U²`,
//!
//! so six sums over the measurements give the error of every β; written in
//! `S` and `U` (both ≥ 0) each is a sum of non-negative terms. `M(β)` is the
//! upper envelope of the lines `β ↦ (1 − β) S_k + β U_k`; on β ∈ [0, 1] only
//! measurements on the Pareto front of `(S_k, U_k)` can attain it (a
//! dominated point's mix is never larger, even after rounding, since every
//! operation rounds monotonically), and the front is found from the order
//! of `S`, sorted once per σ/T; the walk stops at the first `U_k = 1` (U is
//! normalised, so no later point can join). Along the front the slopes
//! `U_k − S_k` increase, so the upper hull of its lines is one monotone-stack
//! pass, and a pointer walked along the hull gives `M(β)` in amortised O(1)
//! per β. The hull drops lines that are never the maximum in exact
//! arithmetic; after rounding `M` is the full max to within an ulp or two,
//! which the tests against the direct path bound.
//!
//! **a as a quadratic.** `a` enters the unnormalised subsurface term only
//! through the absorption factor (eqs. 12–14)
//! `((1 − a) + a sin²θi)((1 − a) + a sin²θs)`, so with the subsurface base
//! `B_k` ([`laminar_core::subsurface_base`]) `U_k(a) ∝ (1 − a)² w0_k + (1 − a) a w1_k + a² w2_k` where `w0 = B`,
//! `w1 = B (sin²θi + sin²θs)`, `w2 = B sin²θi sin²θs` ([`Basis`]). Every sum
//! against `U` is then a polynomial in `a` whose coefficients are sums
//! computed once per (σ/T, n): three for `Σ S U` and for each scene's
//! `Σ D U`, five for `Σ U²`. All coefficients and basis polynomials are
//! non-negative on `a ∈ [0, 1]`, so nothing cancels. Only the normalising
//! max `max_k U_k(a)` and the hull need a pass over the measurements for
//! each triple, and only for triples the lower bound below does not skip.
//!
//! **Skipping.** A search needs only the minimum, so before its β loop each
//! (σ/T, n, a) is checked against a lower bound on its error over every β
//! ([`Projection`]); when the bound exceeds the best error found so far, no
//! β of the triple can win and the sweep is skipped. The bound is exact up
//! to a stated margin, so skipping never changes the result; error surfaces
//! (parity, the speed report) never skip.
//!
//! **Many scenes.** The model side — `S`, `B`, the basis and its sums, the
//! max, the front and the hull — depends on the geometry only; per scene
//! remain `Σ D²`, `Σ S D` (per σ/T), the three `Σ D w_j` (per (σ/T, n)), the
//! bound and the sweeps of triples it does not skip. [`shard`] runs one σ/T
//! for any number of scenes with every value computed by the same
//! operations in the same order, so a scene's results are bit for bit the
//! same alone or in a batch.
//!
//! **Arithmetic.** `S` and `B` and the sines are computed in the lane
//! precision of the path (what the f32 variants trade for speed) and widened
//! exactly; everything after is `f64` in measurement order, so the `f32x8`
//! path and its scalar twin agree bit for bit.

use super::packed::{Packed, Tables};
use super::sums::{dot, DataSums, SurfaceSums};
use super::SweepStats;
use crate::grid::Grid;
use laminar_core::{mix, Correlation, Lane};

/// A scene's data for the envelope search: `D` widened, in measurement
/// order, and `Σ D²`.
pub struct SceneData {
    d: Vec<f64>,
    dd: f64,
}

impl SceneData {
    /// The widened data of `packed`.
    pub fn new<L: Lane>(packed: &Packed<L>) -> Self {
        let mut d = vec![0.0; packed.k];
        packed.widen(&packed.data, &mut d);
        let dd = dot(&d, &d);
        Self { d, dd }
    }
}

/// `(sin²θi, sin²θs)` of every measurement of `packed`, widened.
pub fn sines<L: Lane>(packed: &Packed<L>) -> Vec<[f64; 2]> {
    let (mut i, mut s) = (vec![0.0; packed.k], vec![0.0; packed.k]);
    let lanes_i: Vec<L> = packed.geom.iter().map(|g| g.sin2_i).collect();
    let lanes_s: Vec<L> = packed.geom.iter().map(|g| g.sin2_s).collect();
    packed.widen(&lanes_i, &mut i);
    packed.widen(&lanes_s, &mut s);
    i.into_iter().zip(s).map(|(i, s)| [i, s]).collect()
}

/// The unnormalised subsurface term of one (σ/T, n) as a quadratic in `a`
/// (module docs): per measurement `(w0, w1, w2)`, and the coefficients of
/// `Σ S U` and `Σ U²` in the basis `(1 − a)^(m−j) a^j`.
pub struct Basis {
    w: Vec<[f64; 3]>,
    su: [f64; 3],
    uu: [f64; 5],
}

impl Basis {
    /// The basis of the widened subsurface base `base` with the widened
    /// sines `sines`, and its sums against the surface term.
    pub fn new(surface: &SurfaceSums, base: &[f64], sines: &[[f64; 2]]) -> Self {
        let w: Vec<[f64; 3]> = base
            .iter()
            .zip(sines)
            .map(|(&b, &[si, ss])| [b, b * (si + ss), b * (si * ss)])
            .collect();
        let (mut su, mut uu) = ([0.0; 3], [0.0; 5]);
        for (w, s) in w.iter().zip(&surface.s) {
            let [w0, w1, w2] = *w;
            su[0] += s * w0;
            su[1] += s * w1;
            su[2] += s * w2;
            // (t² w0 + t a w1 + a² w2)², by powers of a.
            uu[0] += w0 * w0;
            uu[1] += 2.0 * (w0 * w1);
            uu[2] += w1 * w1 + 2.0 * (w0 * w2);
            uu[3] += 2.0 * (w1 * w2);
            uu[4] += w2 * w2;
        }
        Self { w, su, uu }
    }

    /// `Σ D w_j` of the widened data `d`, for [`At::ud`].
    pub fn data(&self, d: &[f64]) -> [f64; 3] {
        let mut out = [0.0; 3];
        for (w, d) in self.w.iter().zip(d) {
            out[0] += w[0] * d;
            out[1] += w[1] * d;
            out[2] += w[2] * d;
        }
        out
    }

    /// The term at absorption `a`.
    pub fn at(&self, a: f64) -> At {
        let t = 1.0 - a;
        let (t2, ta, a2) = (t * t, t * a, a * a);
        let b = [t2, ta, a2];
        let b4 = [t2 * t2, t2 * ta, t2 * a2, ta * a2, a2 * a2];
        At {
            b,
            su: dot(&b, &self.su),
            uu: dot(&b4, &self.uu),
        }
    }
}

/// The unnormalised subsurface term of one (σ/T, n, a): its basis weights,
/// `Σ S U` and `Σ U²`.
#[derive(Clone, Copy)]
pub struct At {
    b: [f64; 3],
    su: f64,
    uu: f64,
}

impl At {
    /// `U_k` (unnormalised) of the measurement with basis values `w`.
    #[inline]
    fn value(&self, w: &[f64; 3]) -> f64 {
        self.b[0] * w[0] + self.b[1] * w[1] + self.b[2] * w[2]
    }

    /// `Σ D U` (unnormalised) from a scene's [`Basis::data`].
    #[inline]
    pub fn ud(&self, data: &[f64; 3]) -> f64 {
        dot(&self.b, data)
    }
}

/// The lower bound on a triple's error over every β, from the sums alone.
///
/// For every β the prediction `X/M = ((1 − β)/M) S + (β/M) U` is one point
/// of the plane spanned by `S` and `U`, so its error is at least the
/// least-squares residual of `D` on that plane (which does not depend on the
/// scale of `U`, so the unnormalised sums serve),
/// `R = Σ D² − (Σ S D)² / Σ S² − t² / q` with `q = Σ U² − (Σ S U)² / Σ S²`
/// (the part of `U` orthogonal to `S`) and `t = Σ D U − Σ S U Σ S D / Σ S²`.
/// The model side (`q`, `Σ S U / Σ S²`) is per triple, the rest per scene.
///
/// Rounding: with `q ≥ 10⁻⁶ Σ U²` (otherwise there is no bound) the
/// computed `R` is within about `10⁻⁹ Σ D²` of the exact one, and the error
/// the sweep computes is within about `10⁻¹³ Σ D²` of the exact error. The
/// bound is `R − 10⁻⁸ Σ D²`, so every computed error of the triple is at
/// least the bound: a triple is skipped only if none of its values could
/// reach the threshold.
#[derive(Clone, Copy)]
pub struct Projection {
    su_over_ss: f64,
    inv_q: f64,
}

impl Projection {
    /// The model side of the bound of the triple `at`; `None` when `U` is
    /// (nearly) a multiple of `S` or either is 0.
    pub fn new(ss: f64, at: &At) -> Option<Self> {
        if ss <= 0.0 || at.uu <= 0.0 {
            return None;
        }
        let su_over_ss = at.su / ss;
        let q = at.uu - at.su * su_over_ss;
        (q >= 1e-6 * at.uu).then(|| Self {
            su_over_ss,
            inv_q: 1.0 / q,
        })
    }

    /// The bound for a scene with `Σ S D`, `Σ D²` in `fit` and (unnormalised)
    /// `Σ D U = ud`.
    #[inline]
    pub fn bound(&self, fit: &SurfaceFit, ud: f64) -> f64 {
        let t = ud - self.su_over_ss * fit.sums.sd;
        fit.residual - t * t * self.inv_q
    }
}

/// A scene's data against the surface term of one σ/T: its sums and the part
/// of the bound that does not depend on `U`, `Σ D² − (Σ S D)² / Σ S² − 10⁻⁸ Σ D²`.
#[derive(Clone, Copy)]
pub struct SurfaceFit {
    sums: DataSums,
    residual: f64,
}

impl SurfaceFit {
    /// The fit of `scene` to `surface`.
    pub fn new(surface: &SurfaceSums, scene: &SceneData) -> Self {
        let sums = DataSums {
            sd: dot(&surface.s, &scene.d),
            dd: scene.dd,
        };
        let projected = if surface.ss > 0.0 {
            sums.sd * sums.sd / surface.ss
        } else {
            0.0
        };
        Self {
            sums,
            residual: sums.dd - projected - 1e-8 * sums.dd,
        }
    }
}

/// Reusable per-shard buffers.
#[derive(Default)]
pub struct Scratch {
    base: Vec<f64>,
    /// The Pareto front as `(S_k, U_k)`, by decreasing `S` and increasing `U`.
    front: Vec<(f64, f64)>,
    /// The upper hull of the front's lines, as `(S_k, U_k)`.
    hull: Vec<(f64, f64)>,
}

/// The normalising max of `at`'s subsurface term, the Pareto front of
/// `(S_k, U_k)` with `U` normalised by it, and the upper hull of the front's
/// lines (into `scratch`). Returns the max.
fn build_hull(surface: &SurfaceSums, basis: &Basis, at: &At, scratch: &mut Scratch) -> f64 {
    let max = basis.w.iter().fold(0.0, |m: f64, w| m.max(at.value(w)));
    let normalised = |k: usize| {
        if max > 0.0 {
            at.value(&basis.w[k]) / max
        } else {
            0.0
        }
    };
    scratch.front.clear();
    let mut top = f64::NEG_INFINITY;
    for &i in &surface.order {
        let u = normalised(i);
        if u > top {
            top = u;
            scratch.front.push((surface.s[i], u));
            if top >= 1.0 {
                // U is normalised (no value above 1): no later point, with
                // its smaller S, can join the front.
                break;
            }
        }
    }
    upper_hull(&scratch.front, &mut scratch.hull);
    max
}

/// The six sums of the β sweep (module docs), `U` normalised.
#[derive(Clone, Copy)]
struct Mix {
    ss: f64,
    su: f64,
    uu: f64,
    sd: f64,
    ud: f64,
    dd: f64,
}

impl Mix {
    /// The sums with `U` normalised by `max` (all zero when `max` is 0).
    fn new(surface: &SurfaceSums, at: &At, fit: &SurfaceFit, ud: f64, max: f64) -> Self {
        let scale = if max > 0.0 { 1.0 / max } else { 0.0 };
        Self {
            ss: surface.ss,
            su: at.su * scale,
            uu: at.uu * scale * scale,
            sd: fit.sums.sd,
            ud: ud * scale,
            dd: fit.sums.dd,
        }
    }

    /// `(Σ X D, Σ X²)` at `β`.
    #[inline]
    fn at(&self, beta: f64) -> (f64, f64) {
        let t = 1.0 - beta;
        (
            t * self.sd + beta * self.ud,
            t * (t * self.ss + 2.0 * beta * self.su) + beta * beta * self.uu,
        )
    }
}

/// Calls `visit(i_b, Σ (D − P)²)` for every β, walking `M(β)` along `hull`.
fn sweep_hull(hull: &[(f64, f64)], sums: &Mix, betas: &[f64], mut visit: impl FnMut(usize, f64)) {
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
            let (xd, xx) = sums.at(beta);
            sums.dd + inv * (inv * xx - 2.0 * xd)
        } else {
            sums.dd
        };
        visit(i_b, e.max(0.0));
    }
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

/// What a shard is run on: the hoisted tables of the geometry, its sines,
/// the grid and the correlation.
pub struct Model<'a, L> {
    /// The hoisted tables of the shared geometry.
    pub tables: &'a Tables<L>,
    /// [`sines`] of the geometry.
    pub sines: &'a [[f64; 2]],
    /// The grid.
    pub grid: &'a Grid,
    /// The surface-height correlation.
    pub corr: Correlation,
}

/// One σ/T shard (index `i_s`) of the envelope search for every scene of
/// `scenes` (on the geometry of `model`): calls `visit(scene, flat index,
/// a index, objective)` for every grid point not skipped, where a triple is
/// skipped for a scene when its bound exceeds `threshold(scene, a index)`
/// (`∞` visits all). Counts what it did into `stats[scene]`.
pub fn shard<L: Lane>(
    model: &Model<'_, L>,
    i_s: usize,
    scenes: &[SceneData],
    threshold: impl Fn(usize, usize) -> f64,
    mut visit: impl FnMut(usize, usize, usize, f64),
    stats: &mut [SweepStats],
) {
    let Model {
        tables,
        sines,
        grid,
        corr,
    } = *model;
    let slope = grid.slope.values[i_s];
    let surface = SurfaceSums::new(&tables.packed, &tables.surface(corr, slope));
    let fits: Vec<SurfaceFit> = scenes
        .iter()
        .map(|s| SurfaceFit::new(&surface, s))
        .collect();
    let mut scratch = Scratch::default();
    let mut data = vec![[0.0; 3]; scenes.len()];
    tables.for_each_base(corr, slope, |i_n, base| {
        scratch.base.resize(tables.packed.k, 0.0);
        tables.packed.widen(base, &mut scratch.base);
        let basis = Basis::new(&surface, &scratch.base, sines);
        for (out, scene) in data.iter_mut().zip(scenes) {
            *out = basis.data(&scene.d);
        }
        for (i_a, &a) in grid.a.values.iter().enumerate() {
            let at = basis.at(a);
            let projection = Projection::new(surface.ss, &at);
            let mut max = None;
            for (j, (fit, data)) in fits.iter().zip(&data).enumerate() {
                let ud = at.ud(data);
                let bound = projection.map_or(f64::NEG_INFINITY, |p| p.bound(fit, ud));
                if bound > threshold(j, i_a) {
                    stats[j].pruned += 1;
                    continue;
                }
                let max =
                    *max.get_or_insert_with(|| build_hull(&surface, &basis, &at, &mut scratch));
                stats[j].sweeps += 1;
                stats[j].front_total += scratch.front.len();
                let sums = Mix::new(&surface, &at, fit, ud, max);
                sweep_hull(&scratch.hull, &sums, &grid.beta.values, |i_b, e| {
                    visit(j, grid.flat(i_s, i_n, i_a, i_b), i_a, e)
                });
            }
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{Axis, Grid};
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

    /// Every (σ/T, n, a) triple of `grid` on a noisy synthetic scene made by
    /// `corr` at `truth`: its β values with nothing skipped, and its bound.
    fn triples<L: Lane>(
        corr: Correlation,
        truth: &Params,
        seed: u64,
        grid: &Grid,
    ) -> Vec<(Vec<f64>, f64)> {
        let scene = synthetic::scene(corr, truth, 0.01, seed);
        let tables = Tables::<L>::new(&scene, grid);
        let sines = sines(&tables.packed);
        let model = Model {
            tables: &tables,
            sines: &sines,
            grid,
            corr,
        };
        let data = [SceneData::new(&tables.packed)];
        let per_triple = grid.beta.len();
        let mut values = vec![0.0; grid.size()];
        let mut stats = [SweepStats::default()];
        for i_s in 0..grid.slope.len() {
            shard(
                &model,
                i_s,
                &data,
                |_, _| f64::INFINITY,
                |_, flat, _, e| values[flat] = e,
                &mut stats,
            );
        }
        assert_eq!(stats[0].pruned, 0, "an infinite threshold skipped a sweep");
        // The bounds, recomputed as the shard does.
        let mut bounds = Vec::new();
        for &slope in &grid.slope.values {
            let surface = SurfaceSums::new(&tables.packed, &tables.surface(corr, slope));
            let fit = SurfaceFit::new(&surface, &data[0]);
            tables.for_each_base(corr, slope, |_, base| {
                let mut wide = vec![0.0; tables.packed.k];
                tables.packed.widen(base, &mut wide);
                let basis = Basis::new(&surface, &wide, &sines);
                let d = basis.data(&data[0].d);
                for &a in &grid.a.values {
                    let at = basis.at(a);
                    let bound = Projection::new(surface.ss, &at)
                        .map_or(f64::NEG_INFINITY, |p| p.bound(&fit, at.ud(&d)));
                    bounds.push(bound);
                }
            });
        }
        values
            .chunks(per_triple)
            .map(<[f64]>::to_vec)
            .zip(bounds)
            .collect()
    }

    /// Every (σ/T, n, a) of a grid that includes n = 1, a = 0 (where U = S
    /// up to refraction and the bound must fall back) and poor fits far from
    /// the truth: the bound never exceeds any value the sweep computes, and
    /// it is not vacuous.
    #[test]
    fn lower_bound_is_below_every_computed_error() {
        let corr = Correlation::Exponential;
        let truth = Params::new(1.48, 0.39, 1.44, 0.2).unwrap();
        let grid = grid((0.12, 4.04, 9), 6, 6);
        let all = triples::<f32x8>(corr, &truth, 3, &grid);
        assert_eq!(all.len(), 9 * 6 * 6);
        let mut useful = 0;
        for (values, bound) in &all {
            let min = values.iter().copied().fold(f64::INFINITY, f64::min);
            assert!(*bound <= min, "bound {bound} > min {min}");
            useful += usize::from(*bound > 0.5 * min);
        }
        assert!(
            useful > all.len() / 2,
            "bound useful on only {useful} of {}",
            all.len()
        );
    }

    /// A threshold at or above a triple's minimum never skips it; one below
    /// its bound does. (One n value, so within a shard the a index names the
    /// triple the threshold applies to.)
    #[test]
    fn threshold_skips_only_triples_that_cannot_reach_it() {
        let corr = Correlation::Gaussian;
        let truth = Params::new(0.68, 0.5, 1.3, 0.4).unwrap();
        let grid = Grid {
            n: Axis::linspace(1.3, 1.3, 1),
            ..grid((0.2, 3.0, 5), 1, 6)
        };
        let all = triples::<f32>(corr, &truth, 5, &grid);
        let scene = synthetic::scene(corr, &truth, 0.01, 5);
        let tables = Tables::<f32>::new(&scene, &grid);
        let sines = sines(&tables.packed);
        let model = Model {
            tables: &tables,
            sines: &sines,
            grid: &grid,
            corr,
        };
        let data = [SceneData::new(&tables.packed)];
        let a_len = grid.a.len();
        let (mut skipped, mut finite) = (0, 0);
        for i_s in 0..grid.slope.len() {
            let triple = |i_a: usize| &all[i_s * a_len + i_a];
            let min = |i_a: usize| triple(i_a).0.iter().copied().fold(f64::INFINITY, f64::min);
            for below_bound in [false, true] {
                let mut stats = [SweepStats::default()];
                let mut seen = vec![false; a_len];
                let threshold = |_, i_a: usize| {
                    if below_bound {
                        triple(i_a).1 - 1e-3 * triple(i_a).1.abs()
                    } else {
                        min(i_a)
                    }
                };
                shard(
                    &model,
                    i_s,
                    &data,
                    threshold,
                    |_, flat, _, _| seen[(flat / grid.beta.len()) % a_len] = true,
                    &mut stats,
                );
                for (i_a, &seen) in seen.iter().enumerate() {
                    if !below_bound {
                        assert!(seen, "skipped a triple that reaches the threshold");
                    } else if triple(i_a).1.is_finite() {
                        finite += 1;
                        assert!(!seen, "visited a triple whose bound exceeds the threshold");
                        skipped += 1;
                    }
                }
            }
        }
        assert!(finite > 0, "no triple had a bound");
        assert_eq!(skipped, finite);
    }
}
