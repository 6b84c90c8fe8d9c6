//! SearchPath 3, the closed-form β sweep, for one scene or many on one geometry.
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
//! pass, and `M(β)` is the max over the hull's few lines, computed for
//! every β in a branch-free loop (module `sweep`). The hull drops lines that are
//! never the maximum in exact arithmetic; after rounding `M` is the full max
//! to within an ulp or two, which the tests against the direct path bound.
//!
//! **a as a quadratic.** `a` enters the unnormalised subsurface term only
//! through the absorption factor (eqs. 12–14)
//! `((1 − a) + a sin²θi)((1 − a) + a sin²θs)`, so with the subsurface base
//! `B_k` ([`laminar_brdf_core::subsurface_base`]) `U_k(a) ∝ (1 − a)² w0_k + (1 − a) a w1_k + a² w2_k` where `w0 = B`,
//! `w1 = B (sin²θi + sin²θs)`, `w2 = B sin²θi sin²θs` ([`QuadraticBasis`]). Every sum
//! against `U` is then a polynomial in `a` whose coefficients are sums
//! computed once per (σ/T, n): three for `Σ S U` and for each scene's
//! `Σ D U`, five for `Σ U²`. All coefficients and basis polynomials are
//! non-negative on `a ∈ [0, 1]`, so nothing cancels. Only the normalising
//! max `max_k U_k(a)` and the hull need a pass over the measurements for
//! each triple, and only for triples the lower bound below does not skip.
//!
//! **Skipping.** A search needs only the minimum, so each (σ/T, n) is first
//! checked against a lower bound on the error of all its (a, β) ([`bounds::Span`]),
//! and each (σ/T, n, a) against a lower bound over its β ([`Projection`]);
//! when a bound exceeds the best error found so far, none of its grid
//! points can win and they are skipped. The bounds are exact up to a stated
//! margin, so skipping never changes the result; error surfaces (parity,
//! the speed report) never skip. A batch seeds each scene's best error
//! before the search with the swept minimum of its most promising triple
//! ([`Column`], [`promising`]).
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

mod basis;
mod bounds;
mod sweep;
#[cfg(test)]
mod tests;

pub use basis::QuadraticBasis;
pub use bounds::{Projection, SurfaceFit};
use sweep::{build_hull, Mix, Scratch};

use super::packed::{Packed, Tables};
use super::sums::{dot, SurfaceSums};
use super::SweepStats;
use crate::grid::Grid;
use laminar_brdf_core::{Correlation, Lane};

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

/// What a shard is run on: the hoisted tables of the geometry, its sines,
/// the grid and the correlation.
pub struct Shard<'a, L> {
    /// The hoisted tables of the shared geometry.
    pub tables: &'a Tables<L>,
    /// [`sines`] of the geometry.
    pub sines: &'a [[f64; 2]],
    /// The grid.
    pub grid: &'a Grid,
    /// The surface-height correlation.
    pub corr: Correlation,
}

impl<L: Lane> Shard<'_, L> {
    /// The surface term's sums at σ/T index `i_s`.
    fn surface(&self, i_s: usize) -> SurfaceSums {
        let slope = self.grid.slope.values[i_s];
        SurfaceSums::new(&self.tables.packed, &self.tables.surface(self.corr, slope))
    }

    /// The subsurface basis of (σ/T index `i_s`, n index `i_n`) against
    /// `surface` (the sums of the same σ/T).
    fn basis(&self, surface: &SurfaceSums, i_s: usize, i_n: usize) -> QuadraticBasis {
        let mut base = Vec::with_capacity(self.tables.packed.geom.len());
        self.tables
            .base(self.corr, self.grid.slope.values[i_s], i_n, &mut base);
        let mut wide = vec![0.0; self.tables.packed.k];
        self.tables.packed.widen(&base, &mut wide);
        QuadraticBasis::new(surface, &wide, self.sines)
    }
}

/// Each scene's data against the surface term `surface`.
fn surface_fits(surface: &SurfaceSums, scenes: &[SceneData]) -> Vec<SurfaceFit> {
    scenes.iter().map(|s| SurfaceFit::new(surface, s)).collect()
}

/// What a walk over the triples of a σ/T shard does with each (scene,
/// triple): whether to sweep it, and what to do with the swept values.
pub trait Visitor {
    /// Whether to look at the triples `(i_n, ·)` for scene `j`, whose errors
    /// are all at least `bound` ([`bounds::Span`]; `−∞` when there is no bound).
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
    model: &Shard<'_, L>,
    i_s: usize,
    scenes: &[SceneData],
    visitor: &mut impl Visitor,
    stats: &mut [SweepStats],
) {
    let grid = model.grid;
    let surface = model.surface(i_s);
    let fits = surface_fits(&surface, scenes);
    let mut scratch = Scratch::default();
    let mut data = vec![[0.0; 3]; scenes.len()];
    let mut wanted = vec![false; scenes.len()];
    for i_n in 0..grid.n.len() {
        let basis = model.basis(&surface, i_s, i_n);
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
            continue;
        }
        for (i_a, &a) in grid.a.values.iter().enumerate() {
            let at = basis.at(a);
            let projection = Projection::new(surface.ss, at.su, at.uu);
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
    }
}

/// One (σ/T, n) of the model on its own: what seeding a search needs
/// (`super::batch`), computed exactly as [`shard`] computes it.
pub struct Column {
    surface: SurfaceSums,
    basis: QuadraticBasis,
    betas: Vec<f64>,
}

impl Column {
    /// The surface term of σ/T index `i_s` and the subsurface basis of n
    /// index `i_n`.
    pub fn new<L: Lane>(model: &Shard<'_, L>, i_s: usize, i_n: usize) -> Self {
        let surface = model.surface(i_s);
        let basis = model.basis(&surface, i_s, i_n);
        Self {
            surface,
            basis,
            betas: model.grid.beta.values.clone(),
        }
    }

    /// The bound of the triple at absorption `a` for `scene`.
    pub fn bound(&self, a: f64, scene: &SceneData) -> f64 {
        let at = self.basis.at(a);
        let fit = SurfaceFit::new(&self.surface, scene);
        let ud = at.ud(&self.basis.data(&scene.d));
        Projection::new(self.surface.ss, at.su, at.uu)
            .map_or(f64::NEG_INFINITY, |p| p.bound(&fit, ud))
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
/// `(bound, i_n)` of the smallest [`bounds::Span`] bound, and of the smallest bound
/// of the triple at a index `zero_a`.
pub fn promising<L: Lane>(
    model: &Shard<'_, L>,
    i_s: usize,
    scenes: &[SceneData],
    zero_a: Option<usize>,
) -> Vec<[Option<(f64, usize)>; 2]> {
    let grid = model.grid;
    let surface = model.surface(i_s);
    let fits = surface_fits(&surface, scenes);
    let mut out = vec![[None; 2]; scenes.len()];
    let better = |slot: &mut Option<(f64, usize)>, bound: f64, i_n: usize| {
        if slot.is_none_or(|(b, _)| bound < b) {
            *slot = Some((bound, i_n));
        }
    };
    for i_n in 0..grid.n.len() {
        let basis = model.basis(&surface, i_s, i_n);
        let at_zero = zero_a.map(|i_a| basis.at(grid.a.values[i_a]));
        let projection =
            at_zero.and_then(|at| Projection::new(surface.ss, at.su, at.uu).map(|p| (at, p)));
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
    }
    out
}
