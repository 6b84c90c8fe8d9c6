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
use super::sums::{dot, dot4, DataSums, SurfaceSums};
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
/// (module docs): `w0, w1, w2` over the measurements, the coefficients of
/// `Σ S U` and `Σ U²` in the basis `(1 − a)^(m−j) a^j`, and the bound of
/// every `a` at once ([`Span`]).
pub struct Basis {
    w: [Vec<f64>; 3],
    su: [f64; 3],
    uu: [f64; 5],
    span: Option<Span>,
}

impl Basis {
    /// The basis of the widened subsurface base `base` with the widened
    /// sines `sines`, and its sums against the surface term.
    pub fn new(surface: &SurfaceSums, base: &[f64], sines: &[[f64; 2]]) -> Self {
        let w = [
            base.to_vec(),
            base.iter()
                .zip(sines)
                .map(|(&b, &[si, ss])| b * (si + ss))
                .collect(),
            base.iter()
                .zip(sines)
                .map(|(&b, &[si, ss])| b * (si * ss))
                .collect(),
        ];
        let su = [0, 1, 2].map(|i| dot4(&surface.s, &w[i]));
        let mut ww = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in i..3 {
                ww[i][j] = dot4(&w[i], &w[j]);
            }
        }
        // (t² w0 + t a w1 + a² w2)², by powers of a.
        let uu = [
            ww[0][0],
            2.0 * ww[0][1],
            ww[1][1] + 2.0 * ww[0][2],
            2.0 * ww[1][2],
            ww[2][2],
        ];
        let gram = [
            [surface.ss, su[0], su[1], su[2]],
            [su[0], ww[0][0], ww[0][1], ww[0][2]],
            [su[1], ww[0][1], ww[1][1], ww[1][2]],
            [su[2], ww[0][2], ww[1][2], ww[2][2]],
        ];
        Self {
            w,
            su,
            uu,
            span: Span::new(&gram),
        }
    }

    /// `Σ D w_j` of the widened data `d`, for [`At::ud`].
    pub fn data(&self, d: &[f64]) -> [f64; 3] {
        [0, 1, 2].map(|i| dot4(&self.w[i], d))
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
    /// `U_k` (unnormalised) of measurement `k` of `basis`.
    #[inline]
    fn value(&self, basis: &Basis, k: usize) -> f64 {
        self.b[0] * basis.w[0][k] + self.b[1] * basis.w[1][k] + self.b[2] * basis.w[2][k]
    }

    /// `Σ D U` (unnormalised) from a scene's [`Basis::data`].
    #[inline]
    pub fn ud(&self, data: &[f64; 3]) -> f64 {
        dot(&self.b, data)
    }
}

/// Relative margin of every lower bound: a bound is the exact residual it
/// stands for minus `MARGIN · Σ D²`, which covers the rounding of the bound
/// and of the errors the sweep computes (see [`Projection`] and [`Span`]).
const MARGIN: f64 = 1e-8;

/// The lower bound on a triple's error over every β, from the sums alone.
///
/// For every β the prediction `X/M = ((1 − β)/M) S + (β/M) U` is a point
/// of the cone of non-negative combinations of `S` and `U`, so its error is
/// at least the least-squares residual of `D` on that cone (which does not
/// depend on the scale of `U`, so the unnormalised sums serve). On the plane
/// it is `R = Σ D² − (Σ S D)² / Σ S² − t² / q` with
/// `q = Σ U² − (Σ S U)² / Σ S²` (the part of `U` orthogonal to `S`) and
/// `t = Σ D U − Σ S U Σ S D / Σ S²`, attained at `c_U = t / q`,
/// `c_S = (Σ S D − c_U Σ S U) / Σ S²`; when either is negative the cone's
/// minimum is on one of its edges, `S` or `U` alone. The model side (`q`,
/// `Σ S U / Σ S²`) is per triple, the rest per scene.
///
/// Rounding: with `q ≥ 10⁻⁶ Σ U²` (otherwise there is no bound) the
/// computed `R` is within about `10⁻⁹ Σ D²` of the exact one, and the error
/// the sweep computes is within about `10⁻¹³ Σ D²` of the exact error. The
/// bound is `R − MARGIN Σ D²`, so every computed error of the triple is at
/// least the bound: a triple is skipped only if none of its values could
/// reach the threshold.
#[derive(Clone, Copy)]
pub struct Projection {
    su: f64,
    uu: f64,
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
            su: at.su,
            uu: at.uu,
            su_over_ss,
            inv_q: 1.0 / q,
        })
    }

    /// The bound for a scene with `Σ S D`, `Σ D²` in `fit` and (unnormalised)
    /// `Σ D U = ud`.
    #[inline]
    pub fn bound(&self, fit: &SurfaceFit, ud: f64) -> f64 {
        let sd = fit.sums.sd;
        let t = ud - self.su_over_ss * sd;
        let c_u = t * self.inv_q;
        if c_u >= 0.0 && sd >= c_u * self.su {
            return fit.residual - t * t * self.inv_q;
        }
        // On an edge: S alone (fit.residual when its coefficient Σ S D / Σ S²
        // is positive) or U alone.
        let floor = fit.sums.dd - MARGIN * fit.sums.dd;
        let on_s = if sd > 0.0 { fit.residual } else { floor };
        let on_u = if ud > 0.0 {
            floor - ud * ud / self.uu
        } else {
            floor
        };
        on_s.min(on_u)
    }
}

/// The lower bound on the error of every (a, β) of one (σ/T, n) at once:
/// `U(a)` lies in the span of `w0, w1, w2` for every `a`, so every
/// prediction lies in the span of `S, w0, w1, w2`, and its error is at
/// least the least-squares residual of `D` on that span, `Σ D² − |L⁻¹ b|²`
/// with `L Lᵀ` the Cholesky factorisation of the vectors' Gram matrix and
/// `b = (Σ S D, Σ w0 D, Σ w1 D, Σ w2 D)`. The model side (`L`) is per
/// (σ/T, n), the rest per scene.
///
/// Rounding: each vector must keep at least 10⁻⁴ of its squared norm
/// outside the span of the ones before it (else there is no bound), which
/// keeps the computed residual within about `10⁻¹⁰ Σ D²` of the exact one
/// for K up to thousands; the bound is the residual minus `MARGIN Σ D²`.
#[derive(Clone, Copy)]
pub struct Span {
    l: [[f64; 4]; 4],
}

impl Span {
    fn new(gram: &[[f64; 4]; 4]) -> Option<Self> {
        let mut l = [[0.0; 4]; 4];
        for i in 0..4 {
            for j in 0..=i {
                let sum = gram[i][j] - dot(&l[i][..j], &l[j][..j]);
                if i == j {
                    // Also refuses NaN.
                    if !(sum >= 1e-4 * gram[i][i] && gram[i][i] > 0.0) {
                        return None;
                    }
                    l[i][i] = sum.sqrt();
                } else {
                    l[i][j] = sum / l[j][j];
                }
            }
        }
        Some(Self { l })
    }

    /// The bound for a scene with sums `fit` and [`Basis::data`] `data`.
    #[inline]
    pub fn bound(&self, fit: &SurfaceFit, data: &[f64; 3]) -> f64 {
        let b = [fit.sums.sd, data[0], data[1], data[2]];
        let mut y = [0.0; 4];
        let mut projected = 0.0;
        for i in 0..4 {
            y[i] = (b[i] - dot(&self.l[i][..i], &y[..i])) / self.l[i][i];
            projected += y[i] * y[i];
        }
        fit.sums.dd - MARGIN * fit.sums.dd - projected
    }
}

/// A scene's data against the surface term of one σ/T: its sums and the part
/// of the bound that does not depend on `U`, `Σ D² − (Σ S D)² / Σ S² − MARGIN Σ D²`.
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
            residual: sums.dd - projected - MARGIN * sums.dd,
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
    sweep: Sweep,
}

/// The normalising max of `at`'s subsurface term, the Pareto front of
/// `(S_k, U_k)` with `U` normalised by it, and the upper hull of the front's
/// lines (into `scratch`). Returns the max.
fn build_hull(surface: &SurfaceSums, basis: &Basis, at: &At, scratch: &mut Scratch) -> f64 {
    let [w0, w1, w2] = &basis.w;
    let [b0, b1, b2] = at.b;
    let max = (w0.iter().zip(w1).zip(w2))
        .map(|((w0, w1), w2)| b0 * w0 + b1 * w1 + b2 * w2)
        .fold(0.0, |m: f64, v| if v > m { v } else { m });
    let normalised = |k: usize| {
        if max > 0.0 {
            at.value(basis, k) / max
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

/// Buffers of a β sweep.
#[derive(Default)]
struct Sweep {
    /// `M(β)` per β.
    max: Vec<f64>,
    /// `Σ (D − P)²` per β.
    values: Vec<f64>,
}

impl Sweep {
    /// Fills `values` with `Σ (D − P)²` for every β: `M(β)` as the max of
    /// the hull's lines, then the closed form, each a branch-free loop over
    /// β (which the compiler vectorises).
    fn run(&mut self, hull: &[(f64, f64)], sums: &Mix, betas: &[f64]) {
        self.max.clear();
        self.max.resize(betas.len(), 0.0);
        for &(s, u) in hull {
            for (m, &beta) in self.max.iter_mut().zip(betas) {
                let v = mix(beta, u, s);
                *m = if v > *m { v } else { *m };
            }
        }
        self.values.clear();
        self.values
            .extend(betas.iter().zip(&self.max).map(|(&beta, &m)| {
                // M = 0 makes every prediction 0, and the error Σ D².
                let inv = if m > 0.0 { 1.0 / m } else { 0.0 };
                let (xd, xx) = sums.at(beta);
                (sums.dd + inv * (inv * xx - 2.0 * xd)).max(0.0)
            }));
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

/// What a walk over the triples of a σ/T shard does with each (scene,
/// triple): whether to sweep it, and what to do with the swept values.
pub trait Visitor {
    /// Whether to look at the triples `(i_n, ·)` for scene `j`, whose errors
    /// are all at least `bound` ([`Span`]; `−∞` when there is no bound).
    fn wants_n(&mut self, j: usize, i_n: usize, bound: f64) -> bool;
    /// Whether to sweep triple `(i_n, i_a)` for scene `j`, whose error is at
    /// least `bound` at every β (`−∞` when there is no bound).
    fn wants(&mut self, j: usize, i_n: usize, i_a: usize, bound: f64) -> bool;
    /// The objectives (sums of squared residuals) of scene `j` at the grid
    /// points `(i_n, i_a, i_b)` of the shard, by β index `i_b`.
    fn sweep(&mut self, j: usize, i_n: usize, i_a: usize, values: &[f64]);
}

/// One σ/T shard (index `i_s`) of the envelope search for every scene of
/// `scenes` (on the geometry of `model`), in loop order: each (σ/T, n)'s
/// bound goes to [`Visitor::wants_n`], and when wanted each of its (n, a)
/// triples' bounds to [`Visitor::wants`] and, when wanted, its β sweep to
/// [`Visitor::sweep`]. Counts the sweeps and skips into `stats[scene]`.
pub fn shard<L: Lane>(
    model: &Model<'_, L>,
    i_s: usize,
    scenes: &[SceneData],
    visitor: &mut impl Visitor,
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
    let mut wanted = vec![false; scenes.len()];
    tables.for_each_base(corr, slope, |i_n, base| {
        scratch.base.resize(tables.packed.k, 0.0);
        tables.packed.widen(base, &mut scratch.base);
        let basis = Basis::new(&surface, &scratch.base, sines);
        let mut any = false;
        for (j, (fit, scene)) in fits.iter().zip(scenes).enumerate() {
            data[j] = basis.data(&scene.d);
            let bound = basis
                .span
                .map_or(f64::NEG_INFINITY, |span| span.bound(fit, &data[j]));
            wanted[j] = visitor.wants_n(j, i_n, bound);
            if !wanted[j] {
                stats[j].pruned += grid.a.len();
            }
            any |= wanted[j];
        }
        if !any {
            return;
        }
        for (i_a, &a) in grid.a.values.iter().enumerate() {
            let at = basis.at(a);
            let projection = Projection::new(surface.ss, &at);
            let mut max = None;
            for (j, (fit, data)) in fits.iter().zip(&data).enumerate() {
                if !wanted[j] {
                    continue;
                }
                let ud = at.ud(data);
                let bound = projection.map_or(f64::NEG_INFINITY, |p| p.bound(fit, ud));
                if !visitor.wants(j, i_n, i_a, bound) {
                    stats[j].pruned += 1;
                    continue;
                }
                let max =
                    *max.get_or_insert_with(|| build_hull(&surface, &basis, &at, &mut scratch));
                stats[j].sweeps += 1;
                stats[j].front_total += scratch.front.len();
                let sums = Mix::new(&surface, &at, fit, ud, max);
                scratch.sweep.run(&scratch.hull, &sums, &grid.beta.values);
                visitor.sweep(j, i_n, i_a, &scratch.sweep.values);
            }
        }
    });
}

/// One (σ/T, n) of the model on its own: what seeding a search needs
/// (`super::batch`), computed exactly as [`shard`] computes it.
pub struct Column {
    surface: SurfaceSums,
    basis: Basis,
    betas: Vec<f64>,
}

impl Column {
    /// The surface term of σ/T index `i_s` and the subsurface basis of n
    /// index `i_n`.
    pub fn new<L: Lane>(model: &Model<'_, L>, i_s: usize, i_n: usize) -> Self {
        let Model {
            tables,
            sines,
            grid,
            corr,
        } = *model;
        let slope = grid.slope.values[i_s];
        let surface = SurfaceSums::new(&tables.packed, &tables.surface(corr, slope));
        let mut base = Vec::new();
        tables.base(corr, slope, i_n, &mut base);
        let mut wide = vec![0.0; tables.packed.k];
        tables.packed.widen(&base, &mut wide);
        let basis = Basis::new(&surface, &wide, sines);
        Self {
            surface,
            basis,
            betas: grid.beta.values.clone(),
        }
    }

    /// The bound of the triple at absorption `a` for `scene`.
    pub fn bound(&self, a: f64, scene: &SceneData) -> f64 {
        let at = self.basis.at(a);
        let fit = SurfaceFit::new(&self.surface, scene);
        let ud = at.ud(&self.basis.data(&scene.d));
        Projection::new(self.surface.ss, &at).map_or(f64::NEG_INFINITY, |p| p.bound(&fit, ud))
    }

    /// The smallest error over β of the triple at absorption `a` for `scene`.
    pub fn minimum(&self, a: f64, scene: &SceneData) -> f64 {
        let at = self.basis.at(a);
        let fit = SurfaceFit::new(&self.surface, scene);
        let ud = at.ud(&self.basis.data(&scene.d));
        let mut scratch = Scratch::default();
        let max = build_hull(&self.surface, &self.basis, &at, &mut scratch);
        let sums = Mix::new(&self.surface, &at, &fit, ud, max);
        scratch.sweep.run(&scratch.hull, &sums, &self.betas);
        scratch
            .sweep
            .values
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min)
    }
}

/// Each scene's most promising (σ/T, n) pairs of one σ/T shard, by bound:
/// `(bound, i_n)` of the smallest [`Span`] bound, and of the smallest bound
/// of the triple at a index `zero_a`.
pub fn promising<L: Lane>(
    model: &Model<'_, L>,
    i_s: usize,
    scenes: &[SceneData],
    zero_a: Option<usize>,
) -> Vec<[Option<(f64, usize)>; 2]> {
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
    let mut out = vec![[None; 2]; scenes.len()];
    let mut wide = vec![0.0; tables.packed.k];
    let better = |slot: &mut Option<(f64, usize)>, bound: f64, i_n: usize| {
        if slot.is_none_or(|(b, _)| bound < b) {
            *slot = Some((bound, i_n));
        }
    };
    tables.for_each_base(corr, slope, |i_n, base| {
        tables.packed.widen(base, &mut wide);
        let basis = Basis::new(&surface, &wide, sines);
        let at_zero = zero_a.map(|i_a| basis.at(grid.a.values[i_a]));
        let projection = at_zero.and_then(|at| Projection::new(surface.ss, &at).map(|p| (at, p)));
        for ((slots, fit), scene) in out.iter_mut().zip(&fits).zip(scenes) {
            let data = basis.data(&scene.d);
            let span = basis
                .span
                .map_or(f64::NEG_INFINITY, |span| span.bound(fit, &data));
            better(&mut slots[0], span, i_n);
            if zero_a.is_some() {
                let bound =
                    projection.map_or(f64::NEG_INFINITY, |(at, p)| p.bound(fit, at.ud(&data)));
                better(&mut slots[1], bound, i_n);
            }
        }
    });
    out
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

    /// A visitor that sweeps the triples whose bound is at most
    /// `threshold[i_a]` (and the (σ/T, n) whose bound is at most the largest
    /// of them), recording every value swept and every bound seen.
    struct Record<'g> {
        grid: &'g Grid,
        i_s: usize,
        threshold: Vec<f64>,
        values: Vec<Option<f64>>,
        triple_bounds: Vec<f64>,
        n_bounds: Vec<f64>,
    }

    impl<'g> Record<'g> {
        fn new(grid: &'g Grid, threshold: Vec<f64>) -> Self {
            Self {
                grid,
                i_s: 0,
                threshold,
                values: vec![None; grid.size()],
                triple_bounds: vec![f64::NAN; grid.size() / grid.beta.len()],
                n_bounds: vec![f64::NAN; grid.slope.len() * grid.n.len()],
            }
        }
    }

    impl Visitor for Record<'_> {
        fn wants_n(&mut self, _: usize, i_n: usize, bound: f64) -> bool {
            self.n_bounds[self.i_s * self.grid.n.len() + i_n] = bound;
            bound
                <= self
                    .threshold
                    .iter()
                    .copied()
                    .fold(f64::NEG_INFINITY, f64::max)
        }

        fn wants(&mut self, _: usize, i_n: usize, i_a: usize, bound: f64) -> bool {
            let triple = self.grid.flat(self.i_s, i_n, i_a, 0) / self.grid.beta.len();
            self.triple_bounds[triple] = bound;
            bound <= self.threshold[i_a]
        }

        fn sweep(&mut self, _: usize, i_n: usize, i_a: usize, values: &[f64]) {
            for (i_b, &e) in values.iter().enumerate() {
                self.values[self.grid.flat(self.i_s, i_n, i_a, i_b)] = Some(e);
            }
        }
    }

    /// Runs every shard of `grid` on a noisy synthetic scene made by `corr`
    /// at `truth`, with `threshold` per a index.
    fn record<'g, L: Lane>(
        corr: Correlation,
        truth: &Params,
        grid: &'g Grid,
        threshold: Vec<f64>,
    ) -> Record<'g> {
        let scene = synthetic::scene(corr, truth, 0.01, 3);
        let tables = Tables::<L>::new(&scene, grid);
        let sines = sines(&tables.packed);
        let model = Model {
            tables: &tables,
            sines: &sines,
            grid,
            corr,
        };
        let data = [SceneData::new(&tables.packed)];
        let mut record = Record::new(grid, threshold);
        for i_s in 0..grid.slope.len() {
            record.i_s = i_s;
            shard(
                &model,
                i_s,
                &data,
                &mut record,
                &mut [SweepStats::default()],
            );
        }
        record
    }

    /// The smallest value of each triple, in loop order.
    fn minima(values: &[Option<f64>], per_triple: usize) -> Vec<f64> {
        values
            .chunks(per_triple)
            .map(|t| {
                t.iter()
                    .map(|v| v.expect("swept"))
                    .fold(f64::INFINITY, f64::min)
            })
            .collect()
    }

    /// Every (σ/T, n, a) of a grid that includes n = 1, a = 0 and poor fits
    /// far from the truth: with nothing skipped, no triple's bound exceeds
    /// any value its sweep computes, no (σ/T, n) bound exceeds any value of
    /// its triples, and neither bound is vacuous.
    #[test]
    fn lower_bounds_are_below_every_computed_error() {
        for corr in [Correlation::Exponential, Correlation::Gaussian] {
            let truth = Params::new(1.48, 0.39, 1.44, 0.2).unwrap();
            let grid = grid((0.12, 4.04, 9), 6, 6);
            let all = record::<f32x8>(corr, &truth, &grid, vec![f64::INFINITY; 6]);
            let min = minima(&all.values, grid.beta.len());
            let (mut useful, mut useful_n) = (0, 0);
            for (bound, min) in all.triple_bounds.iter().zip(&min) {
                assert!(bound <= min, "{corr:?}: triple bound {bound} > min {min}");
                useful += usize::from(*bound > 0.5 * min);
            }
            for (bound, triples) in all.n_bounds.iter().zip(min.chunks(grid.a.len())) {
                let min = triples.iter().copied().fold(f64::INFINITY, f64::min);
                assert!(
                    *bound <= min,
                    "{corr:?}: (σ/T, n) bound {bound} > min {min}"
                );
                useful_n += usize::from(*bound > 0.5 * min);
            }
            assert!(
                useful > min.len() / 2,
                "triple bound useful on {useful} of {}",
                min.len()
            );
            assert!(useful_n > 0, "(σ/T, n) bound never useful");
        }
    }

    /// A threshold at or above a triple's minimum never skips it; one below
    /// its bound does.
    #[test]
    fn thresholds_skip_only_triples_that_cannot_reach_them() {
        let corr = Correlation::Gaussian;
        let truth = Params::new(0.68, 0.5, 1.3, 0.4).unwrap();
        // One n and one σ/T, so the a index names the triple.
        let grid = Grid {
            slope: Axis::linspace(0.68, 0.68, 1),
            n: Axis::linspace(1.3, 1.3, 1),
            ..grid((0.2, 3.0, 1), 1, 8)
        };
        let all = record::<f32>(corr, &truth, &grid, vec![f64::INFINITY; 8]);
        let min = minima(&all.values, grid.beta.len());
        let at_min = record::<f32>(corr, &truth, &grid, min.clone());
        assert!(
            at_min.values.iter().all(Option::is_some),
            "skipped a triple reaching its threshold"
        );
        let below: Vec<f64> = all
            .triple_bounds
            .iter()
            .map(|b| b - 1e-3 * b.abs())
            .collect();
        let skipped = record::<f32>(corr, &truth, &grid, below.clone());
        let mut checked = 0;
        for (i_a, bound) in all.triple_bounds.iter().enumerate() {
            if bound.is_finite() {
                checked += 1;
                let swept = skipped.values[i_a * grid.beta.len()].is_some();
                assert!(!swept, "swept a triple whose bound exceeds its threshold");
            }
        }
        assert!(checked > 0, "no triple had a bound");
    }
}
