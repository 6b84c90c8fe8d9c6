//! The paper's exhaustive grid search (docs/conventions.md §4–§6) for the absorptive
//! model. Three methods, each written once over [`Lane`]:
//!
//! 1. [`Method::Direct`] (`direct`): every pair evaluated in full; in `f64`
//!    the accuracy reference.
//! 2. [`Method::OnePass`] (`onepass`): hoisted terms, one pass over the
//!    measurements per parameter set.
//! 3. [`Method::Envelope`] (`envelope`): hoisted terms, closed-form β sweep.
//!
//! Each runs in three arithmetics: `f32x8` SIMD, its scalar twin `f32` (eight
//! streams of one measurement, lane sums reduced in the same fixed order, so
//! every grid value is bitwise the SIMD one) and `f64`.
//!
//! Hoisting (methods 2 and 3, `packed::Tables`): geometry once per scene;
//! refraction and Fresnel once per (scene, n); the absorption factor once per
//! (scene, a); the normalised surface term once per σ/T; the subsurface base
//! once per (σ/T, n); the normalised subsurface term once per (σ/T, n, a).

pub(crate) mod baselines;
pub mod batch;
pub(crate) mod direct;
pub(crate) mod envelope;
pub(crate) mod onepass;
pub(crate) mod packed;
pub(crate) mod sums;

use crate::error::GridError;
use crate::grid::{Axis, Grid};
use crate::model::Param;
use crate::scene::Scene;
pub use crate::settings::search_path::{Arith, Method, SearchPath};
use laminar_brdf_core::{f32x8, Correlation, Lane};
use packed::{Packed, Tables};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};

/// Per-scene state of a search.
enum Prepared<L> {
    Direct(Packed<L>),
    OnePass(Tables<L>),
    Envelope {
        tables: Tables<L>,
        sines: Vec<[f64; 2]>,
        data: [envelope::SceneData; 1],
    },
}

impl<L: Lane> Prepared<L> {
    fn new(scene: &Scene, grid: &Grid, method: Method) -> Self {
        match method {
            Method::Direct => Self::Direct(Packed::new(scene)),
            Method::OnePass => Self::OnePass(Tables::new(scene, grid)),
            Method::Envelope => {
                let tables = Tables::new(scene, grid);
                Self::Envelope {
                    sines: envelope::sines(&tables.packed),
                    data: [envelope::SceneData::new(&tables.packed)],
                    tables,
                }
            }
        }
    }

    /// Visits every (n, a, β) of slope index `i_s` in loop order as
    /// `visit(flat index, a index, objective)`, the objective being the sum
    /// of squared residuals `Σ (D − P)²` (eq. 15 before the root, widened to
    /// `f64`). The envelope method may skip points whose objective exceeds
    /// `cutoff` (+∞: none is skipped); the others visit every point.
    fn shard(
        &self,
        grid: &Grid,
        corr: Correlation,
        i_s: usize,
        cutoff: f64,
        mut visit: impl FnMut(usize, usize, f64),
    ) {
        let slope = grid.slope.values[i_s];
        match self {
            Self::Direct(packed) => direct::shard(packed, grid, corr, i_s, &mut visit),
            Self::Envelope {
                tables,
                sines,
                data,
            } => {
                let model = envelope::Shard {
                    tables,
                    sines,
                    grid,
                    corr,
                };
                let mut every = Every {
                    grid,
                    i_s,
                    cutoff,
                    visit,
                };
                envelope::shard(&model, i_s, data, &mut every, &mut [SweepStats::default()]);
            }
            Self::OnePass(tables) => {
                let packed = &tables.packed;
                let surface = tables.surface(corr, slope);
                let widened = sums::SurfaceSums::new(packed, &surface);
                let mut d = vec![0.0; packed.k];
                packed.widen(&packed.data, &mut d);
                let wide = laminar_brdf_core::onepass::Widened {
                    s: &widened.s,
                    ss: widened.ss,
                    data: sums::DataSums::new(&widened.s, &d),
                    d: &d,
                };
                let mut scratch = onepass::Scratch::default();
                tables.for_each_subsurface(corr, slope, |i_n, i_a, u| {
                    onepass::sweep(
                        packed,
                        (&surface, u),
                        &wide,
                        &grid.beta.values,
                        &mut scratch,
                        |i_b, r| visit(grid.flat(i_s, i_n, i_a, i_b), i_a, r),
                    );
                });
            }
        }
    }
}

/// An envelope [`envelope::Visitor`] that sweeps every triple of one scene
/// whose bound does not exceed `cutoff` (every triple when it is +∞) and
/// hands each value to `visit(flat index, a index, objective)`.
struct Every<'g, V> {
    grid: &'g Grid,
    i_s: usize,
    cutoff: f64,
    visit: V,
}

impl<V> Every<'_, V> {
    fn below(&self, bound: f64) -> bool {
        self.cutoff == f64::INFINITY || bound <= self.cutoff
    }
}

impl<V: FnMut(usize, usize, f64)> envelope::Visitor for Every<'_, V> {
    fn wants_n(&mut self, _: usize, _: usize, bound: f64) -> bool {
        self.below(bound)
    }

    fn wants(&mut self, _: usize, _: usize, _: usize, bound: f64) -> bool {
        self.below(bound)
    }

    fn sweep(&mut self, _: usize, i_n: usize, i_a: usize, values: &[f64]) {
        for (i_b, &e) in values.iter().enumerate() {
            (self.visit)(self.grid.flat(self.i_s, i_n, i_a, i_b), i_a, e)
        }
    }
}

/// What the envelope method did in a shard (zeros for the other methods).
#[derive(Debug, Clone, Copy, Default)]
pub struct SweepStats {
    /// Total Pareto-front size over the sweeps that ran.
    pub front_total: usize,
    /// Sweeps whose β loop ran.
    pub sweeps: usize,
    /// Sweeps skipped by the lower bound.
    pub pruned: usize,
}

impl SweepStats {
    fn add(self, o: Self) -> Self {
        Self {
            front_total: self.front_total + o.front_total,
            sweeps: self.sweeps + o.sweeps,
            pruned: self.pruned + o.pruned,
        }
    }
}

/// The best objective found so far by any shard of a search, overall and on
/// the a = 0 slice, as `f64` bits (the objectives are never negative, so
/// their bit patterns order like their values). Shards only ever lower them,
/// and each is the value of a visited grid point, so it never falls below
/// the final minimum: skipping a triple whose values all exceed it cannot
/// change the result, whatever the thread timing.
struct SharedBest {
    best: AtomicU64,
    rh: AtomicU64,
    zero_a: Option<usize>,
}

impl SharedBest {
    fn new(zero_a: Option<usize>) -> Self {
        Self {
            best: AtomicU64::new(f64::INFINITY.to_bits()),
            rh: AtomicU64::new(f64::INFINITY.to_bits()),
            zero_a,
        }
    }

    /// A triple at a index `i_a` may be skipped when all its values exceed
    /// this: the overall best, or on the a = 0 slice the (larger) best of
    /// that slice, which the search also reports.
    fn threshold(&self, i_a: usize) -> f64 {
        let slot = if self.zero_a == Some(i_a) {
            &self.rh
        } else {
            &self.best
        };
        f64::from_bits(slot.load(Ordering::Relaxed))
    }

    /// The largest threshold of any a index: every triple of an (σ/T, n)
    /// may be skipped when all its values exceed this.
    fn loosest(&self) -> f64 {
        let best = f64::from_bits(self.best.load(Ordering::Relaxed));
        match self.zero_a {
            Some(_) => best.max(f64::from_bits(self.rh.load(Ordering::Relaxed))),
            None => best,
        }
    }

    fn offer(slot: &AtomicU64, e: f64) {
        slot.fetch_min(e.to_bits(), Ordering::Relaxed);
    }

    /// Offers `e`, the value of a grid point at a index `i_a`, before the
    /// search proper: it lowers the thresholds as a visit would, without
    /// becoming a candidate (the search visits that point again).
    fn seed(&self, i_a: usize, e: f64) {
        Self::offer(&self.best, e);
        if self.zero_a == Some(i_a) {
            Self::offer(&self.rh, e);
        }
    }
}

/// The best grid point of a search, and the best of its a = 0 slice.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SearchResult {
    /// Flattened index of the minimum (smallest index on ties).
    pub best: usize,
    /// Its RMS in the search precision, widened.
    pub best_rms: f64,
    /// The minimum over the grid points with a = 0 (Ragheb–Hancock), if the
    /// a axis contains 0.
    pub rh_best: Option<(usize, f64)>,
    /// Envelope method: mean size of the Pareto front of `(S_k, U_k)` over
    /// the sweeps that ran.
    pub mean_front: Option<f64>,
    /// Envelope method: fraction of the (σ/T, n, a) triples whose β loop the
    /// lower bound skipped (varies a little with thread timing; the result
    /// does not).
    pub pruned: Option<f64>,
}

pub use laminar_brdf_core::onepass::rms_of_sum;

/// A grid point's flat index and objective (sum of squared residuals).
type Candidate = Option<(usize, f64)>;

/// Strictly-better update (keeps the smallest flat index on ties of the
/// objective; the RMS is a monotone function of it).
fn better(current: Candidate, flat: usize, rms: f64) -> Candidate {
    match current {
        Some((_, r)) if rms >= r => current,
        _ => Some((flat, rms)),
    }
}

/// What one σ/T shard found.
#[derive(Default)]
struct ShardBest {
    best: Candidate,
    rh: Candidate,
    stats: SweepStats,
}

impl ShardBest {
    /// Records the objective `e` of grid point `flat` (a index `i_a`) and
    /// offers an improvement to every shard through `shared`.
    fn visit(&mut self, shared: &SharedBest, flat: usize, i_a: usize, e: f64) {
        if self.best.is_none_or(|(_, b)| e < b) {
            self.best = Some((flat, e));
            SharedBest::offer(&shared.best, e);
        }
        if shared.zero_a == Some(i_a) && self.rh.is_none_or(|(_, b)| e < b) {
            self.rh = Some((flat, e));
            SharedBest::offer(&shared.rh, e);
        }
    }
}

/// The search result of the shards of one scene with `k` measurements.
fn combine(shards: impl IntoIterator<Item = ShardBest>, k: usize) -> SearchResult {
    let (mut best, mut rh, mut stats) = (None, None, SweepStats::default());
    for s in shards {
        if let Some((f, v)) = s.best {
            best = better(best, f, v);
        }
        if let Some((f, v)) = s.rh {
            rh = better(rh, f, v);
        }
        stats = stats.add(s.stats);
    }
    let (best, best_sum) = best.unwrap_or((0, f64::INFINITY));
    SearchResult {
        best,
        best_rms: rms_of_sum(best_sum, k),
        rh_best: rh.map(|(flat, e)| (flat, rms_of_sum(e, k))),
        mean_front: (stats.sweeps > 0).then(|| stats.front_total as f64 / stats.sweeps as f64),
        pruned: (stats.sweeps + stats.pruned > 0)
            .then(|| stats.pruned as f64 / (stats.sweeps + stats.pruned) as f64),
    }
}

fn search_with<L: Lane + Send + Sync>(
    scene: &Scene,
    grid: &Grid,
    corr: Correlation,
    method: Method,
    progress: &(dyn Fn() + Sync),
) -> SearchResult {
    let prepared = Prepared::<L>::new(scene, grid, method);
    let zero_a = grid.a.values.iter().position(|&a| a == 0.0);
    let shared = SharedBest::new(zero_a);
    let shards: Vec<ShardBest> = (0..grid.slope.len())
        .into_par_iter()
        .map(|i_s| {
            let mut found = ShardBest::default();
            prepared.shard(grid, corr, i_s, f64::INFINITY, |flat, i_a, e| {
                found.visit(&shared, flat, i_a, e)
            });
            progress();
            found
        })
        .collect();
    combine(shards, scene.len())
}

/// Runs the exhaustive search on `path` (after [`Grid::validate`]);
/// `progress` is called once per σ/T shard. Deterministic whatever the
/// thread count (docs/conventions.md §6).
///
/// # Errors
/// [`GridError`] from [`Grid::validate`].
pub fn search(
    scene: &Scene,
    grid: &Grid,
    corr: Correlation,
    path: SearchPath,
    progress: &(dyn Fn() + Sync),
) -> Result<SearchResult, GridError> {
    grid.validate()?;
    if path.method == Method::Envelope {
        let mut results = batch::search_batch(
            std::slice::from_ref(scene),
            grid,
            corr,
            path.arith,
            progress,
        )?;
        return Ok(results.remove(0));
    }
    Ok(match path.arith {
        Arith::F32x8 => search_with::<f32x8>(scene, grid, corr, path.method, progress),
        Arith::F32 => search_with::<f32>(scene, grid, corr, path.method, progress),
        Arith::F64 => search_with::<f64>(scene, grid, corr, path.method, progress),
    })
}

/// Every grid value's RMS on `path`, in flattened order (widened exactly to
/// `f64`), after [`Grid::validate`]. A grid whose table cannot be allocated
/// is refused with its size.
///
/// # Errors
/// [`GridError`] from [`Grid::validate`], or [`GridError::Allocation`].
pub fn error_surface(
    scene: &Scene,
    grid: &Grid,
    corr: Correlation,
    path: SearchPath,
) -> Result<Vec<f64>, GridError> {
    fn run<L: Lane + Send + Sync>(
        scene: &Scene,
        grid: &Grid,
        corr: Correlation,
        method: Method,
    ) -> Result<Vec<f64>, GridError> {
        let prepared = Prepared::<L>::new(scene, grid, method);
        let per_slope = grid.size() / grid.slope.len();
        let mut out = Vec::new();
        out.try_reserve_exact(grid.size())
            .map_err(|_| GridError::Allocation {
                size: grid.size(),
                bytes: grid.size() as u128 * 8,
            })?;
        out.resize(grid.size(), 0.0);
        out.par_chunks_mut(per_slope)
            .enumerate()
            .for_each(|(i_s, slice)| {
                prepared.shard(grid, corr, i_s, f64::INFINITY, |flat, _, e| {
                    slice[flat - i_s * per_slope] = rms_of_sum(e, scene.len())
                });
            });
        Ok(out)
    }
    grid.validate()?;
    match path.arith {
        Arith::F32x8 => run::<f32x8>(scene, grid, corr, path.method),
        Arith::F32 => run::<f32>(scene, grid, corr, path.method),
        Arith::F64 => run::<f64>(scene, grid, corr, path.method),
    }
}

/// The profiles of the error surface along each axis, and the grid points
/// near the minimum: what the uncertainty of a fit is read from
/// ([`crate::profile`]).
#[derive(Debug, Clone, PartialEq)]
pub struct GridProfile {
    /// Per axis in the order σ/T, n, a, β: for each axis value, the smallest
    /// objective `Σ (D − P)²` over the other axes and the flat index where
    /// it is, or `(+∞, usize::MAX)` when every point there exceeds the
    /// profile cutoff.
    pub axes: Vec<Vec<(f64, usize)>>,
    /// Every grid point whose objective does not exceed the basin cutoff,
    /// as (flat index, objective), in flat order.
    pub near: Vec<(usize, f64)>,
    /// The profile cutoff: a profile value above it is +∞.
    pub cutoff: f64,
}

/// The [`GridProfile`] of `scene` on `path`: exact for every axis value whose
/// profile is at most `cutoff`, and the points at most `near` (≤ `cutoff`).
/// The envelope method skips everything above `cutoff` by its bounds, so
/// this costs about as much as a search.
///
/// # Errors
/// [`GridError`] from [`Grid::validate`].
pub fn grid_profile(
    scene: &Scene,
    grid: &Grid,
    corr: Correlation,
    path: SearchPath,
    cutoff: f64,
    near: f64,
) -> Result<GridProfile, GridError> {
    fn run<L: Lane + Send + Sync>(
        scene: &Scene,
        grid: &Grid,
        corr: Correlation,
        method: Method,
        cutoff: f64,
        near: f64,
    ) -> GridProfile {
        let prepared = Prepared::<L>::new(scene, grid, method);
        let lens = [
            grid.slope.len(),
            grid.n.len(),
            grid.a.len(),
            grid.beta.len(),
        ];
        let empty = || -> Vec<Vec<(f64, usize)>> {
            lens.iter()
                .map(|&len| vec![(f64::INFINITY, usize::MAX); len])
                .collect()
        };
        type ShardBests = (Vec<Vec<(f64, usize)>>, Vec<(usize, f64)>);
        let shards: Vec<ShardBests> = (0..grid.slope.len())
            .into_par_iter()
            .map(|i_s| {
                let (mut axes, mut points) = (empty(), Vec::new());
                prepared.shard(grid, corr, i_s, cutoff, |flat, _, e| {
                    if e > cutoff {
                        return;
                    }
                    let (s, n, a, b) = grid.indices(flat);
                    for (axis, i) in axes.iter_mut().zip([s, n, a, b]) {
                        // Smallest flat index on ties (shards run in flat order).
                        if e < axis[i].0 {
                            axis[i] = (e, flat);
                        }
                    }
                    if e <= near {
                        points.push((flat, e));
                    }
                });
                (axes, points)
            })
            .collect();
        let (mut axes, mut near_points) = (empty(), Vec::new());
        for (shard_axes, points) in shards {
            for (axis, part) in axes.iter_mut().zip(shard_axes) {
                for (slot, p) in axis.iter_mut().zip(part) {
                    if p.0 < slot.0 {
                        *slot = p;
                    }
                }
            }
            near_points.extend(points);
        }
        near_points.sort_unstable_by_key(|p| p.0);
        GridProfile {
            axes,
            near: near_points,
            cutoff,
        }
    }
    grid.validate()?;
    Ok(match path.arith {
        Arith::F32x8 => run::<f32x8>(scene, grid, corr, path.method, cutoff, near),
        Arith::F32 => run::<f32>(scene, grid, corr, path.method, cutoff, near),
        Arith::F64 => run::<f64>(scene, grid, corr, path.method, cutoff, near),
    })
}

/// The error surfaces of a method's `f32x8` path and its scalar `f32` twin
/// ([`SearchPath::twins`]), which must agree bit for bit (the parity check).
#[derive(Debug, Clone, PartialEq)]
pub struct Twins {
    /// Every grid value on the `f32x8` path, in flattened order.
    pub simd: Vec<f64>,
    /// Every grid value on the scalar `f32` twin.
    pub scalar: Vec<f64>,
}

impl Twins {
    /// The error surfaces of `method`'s twins on `scene`.
    ///
    /// # Errors
    /// As [`error_surface`].
    pub fn new(
        scene: &Scene,
        grid: &Grid,
        corr: Correlation,
        method: Method,
    ) -> Result<Self, GridError> {
        let (simd, scalar) = SearchPath::new(method, Arith::F32x8).twins();
        Ok(Self {
            simd: error_surface(scene, grid, corr, simd)?,
            scalar: error_surface(scene, grid, corr, scalar)?,
        })
    }

    /// How many grid values are bitwise identical on both paths.
    pub fn identical(&self) -> usize {
        self.simd
            .iter()
            .zip(&self.scalar)
            .filter(|(a, b)| a.to_bits() == b.to_bits())
            .count()
    }
}

/// The grid point of a flattened index as (σ/T, n, a, β).
pub fn point(grid: &Grid, flat: usize) -> (f64, f64, f64, f64) {
    let (s, n, a, b) = grid.indices(flat);
    (
        grid.slope.values[s],
        grid.n.values[n],
        grid.a.values[a],
        grid.beta.values[b],
    )
}

/// One axis a fit searched: its index among the grid's axes (as in
/// [`GridProfile::axes`]), the parameter, its grid value and the axis.
pub(crate) struct Searched<'a> {
    pub axis: usize,
    pub name: Param,
    pub value: f64,
    pub values: &'a Axis,
}
