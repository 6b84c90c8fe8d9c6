//! Many scenes on one geometry (every sample of a database, every channel,
//! every pixel of a texture): the envelope search (`super::envelope`) with
//! the model-side work done once per σ/T shard and shared by every scene.
//!
//! Every value a scene sees is computed by the same operations, in the same
//! order, as in the one-scene envelope search (both run
//! `envelope::shard`), so each result is bit for bit the one of searching
//! that scene alone, whatever the thread count (each scene keeps its own
//! shared best for the skipping).

use super::envelope::{self, Column, SceneData};
use super::packed::Tables;
use super::{combine, Arith, SearchResult, ShardBest, SharedBest, SweepStats};
use crate::error::GridError;
use crate::grid::Grid;
use crate::scene::Scene;
use laminar_brdf_core::{f32x8, Correlation, Lane};
use rayon::prelude::*;

/// True when every scene has the kept geometry of the first (same angles,
/// same order), so that one batch search can serve them all.
pub fn share_geometry(scenes: &[Scene]) -> bool {
    scenes.iter().all(|s| s.angles == scenes[0].angles)
}

/// The envelope search of every scene of `scenes`, which must share their
/// geometry ([`share_geometry`]), in the arithmetic `arith`; `progress` is
/// called once per σ/T shard of the whole batch. The results are in the
/// order of `scenes` and equal, bit for bit, those of
/// [`super::search`] on each scene with the envelope method.
///
/// # Errors
/// [`GridError`] from [`Grid::validate`].
///
/// # Panics
/// If the scenes do not share their geometry (a caller's bug: check with
/// [`share_geometry`]).
pub fn search_batch(
    scenes: &[Scene],
    grid: &Grid,
    corr: Correlation,
    arith: Arith,
    progress: &(dyn Fn() + Sync),
) -> Result<Vec<SearchResult>, GridError> {
    grid.validate()?;
    assert!(
        share_geometry(scenes),
        "search_batch needs scenes on one geometry"
    );
    if scenes.is_empty() {
        return Ok(Vec::new());
    }
    Ok(match arith {
        Arith::F32x8 => run::<f32x8>(scenes, grid, corr, progress),
        Arith::F32 => run::<f32>(scenes, grid, corr, progress),
        Arith::F64 => run::<f64>(scenes, grid, corr, progress),
    })
}

/// Batches of at least this many scenes are seeded ([`seed`]): seeding
/// repeats the model side of the search once, which one scene does not win
/// back (measured, criterion: a paper-grid fit of CUReT sample 21 took
/// 1.55 ms seeded, 1.33 ms not), while a batch shares it.
const SEED_FROM: usize = 2;

fn run<L: Lane + Send + Sync>(
    scenes: &[Scene],
    grid: &Grid,
    corr: Correlation,
    progress: &(dyn Fn() + Sync),
) -> Vec<SearchResult> {
    let tables = Tables::<L>::new(&scenes[0], grid);
    let sines = envelope::sines(&tables.packed);
    let model = envelope::Shard {
        tables: &tables,
        sines: &sines,
        grid,
        corr,
    };
    let data: Vec<SceneData> = scenes
        .iter()
        .map(|s| SceneData::new(&tables.packed.with_data(s)))
        .collect();
    let zero_a = grid.a.values.iter().position(|&a| a == 0.0);
    let shared: Vec<SharedBest> = scenes.iter().map(|_| SharedBest::new(zero_a)).collect();
    if scenes.len() >= SEED_FROM {
        seed(&model, &data, &shared, zero_a);
    }
    let shards: Vec<Vec<ShardBest>> = (0..grid.slope.len())
        .into_par_iter()
        .map(|i_s| {
            let mut searcher = Searcher {
                grid,
                i_s,
                shared: &shared,
                found: scenes.iter().map(|_| ShardBest::default()).collect(),
            };
            let mut stats = vec![SweepStats::default(); scenes.len()];
            envelope::shard(&model, i_s, &data, &mut searcher, &mut stats);
            for (f, s) in searcher.found.iter_mut().zip(stats) {
                f.stats = s;
            }
            progress();
            searcher.found
        })
        .collect();
    // Regroup by scene, in σ/T order.
    let mut per_scene: Vec<Vec<ShardBest>> = scenes.iter().map(|_| Vec::new()).collect();
    for shard in shards {
        for (j, f) in shard.into_iter().enumerate() {
            per_scene[j].push(f);
        }
    }
    let k = tables.packed.k;
    per_scene.into_iter().map(|s| combine(s, k)).collect()
}

/// Gives every scene a threshold close to its minimum before the search
/// proper: per scene, the (σ/T, n) with the smallest [`envelope`]'s `Span`
/// bound and, within it, the triple with the smallest bound; and the a = 0
/// triple with the smallest bound. Their swept minima seed the scene's
/// shared best. Any computed value of a grid point is a valid threshold, so
/// the result does not change; only fewer triples are swept.
fn seed<L: Lane + Send + Sync>(
    model: &envelope::Shard<'_, L>,
    data: &[SceneData],
    shared: &[SharedBest],
    zero_a: Option<usize>,
) {
    type Slot = Option<(f64, [usize; 2])>;
    let pick = |a: Slot, b: Slot| match (a, b) {
        (Some(x), Some(y)) if y.0 < x.0 => Some(y),
        (None, y) => y,
        (x, _) => x,
    };
    let none = || vec![[None; 2]; data.len()];
    let promising: Vec<[Slot; 2]> = (0..model.grid.slope.len())
        .into_par_iter()
        .map(|i_s| {
            let found = envelope::promising(model, i_s, data, zero_a);
            found
                .into_iter()
                .map(|slots| slots.map(|s| s.map(|(b, i_n)| (b, [i_s, i_n]))))
                .collect::<Vec<_>>()
        })
        .reduce(none, |a, b| {
            a.into_iter()
                .zip(b)
                .map(|(a, b)| [pick(a[0], b[0]), pick(a[1], b[1])])
                .collect()
        });
    let a_values = &model.grid.a.values;
    promising
        .par_iter()
        .zip(data)
        .zip(shared)
        .for_each(|((slots, scene), shared)| {
            if let Some((_, [i_s, i_n])) = slots[0] {
                let column = Column::new(model, i_s, i_n);
                let bounds = a_values.iter().map(|&a| column.bound(a, scene));
                let (i_a, _) =
                    bounds.enumerate().fold(
                        (0, f64::INFINITY),
                        |b, (i, v)| if v < b.1 { (i, v) } else { b },
                    );
                shared.seed(i_a, column.minimum(a_values[i_a], scene));
            }
            if let (Some((_, [i_s, i_n])), Some(i_a)) = (slots[1], zero_a) {
                let column = Column::new(model, i_s, i_n);
                shared.seed(i_a, column.minimum(a_values[i_a], scene));
            }
        });
}

/// The search's [`envelope::Visitor`]: sweeps a triple for a scene unless
/// its bound exceeds that scene's threshold, and records what it visits.
struct Searcher<'a> {
    grid: &'a Grid,
    i_s: usize,
    shared: &'a [SharedBest],
    found: Vec<ShardBest>,
}

impl envelope::Visitor for Searcher<'_> {
    fn wants_n(&mut self, j: usize, _: usize, bound: f64) -> bool {
        bound <= self.shared[j].loosest() || bound.is_nan()
    }

    fn wants(&mut self, j: usize, _: usize, i_a: usize, bound: f64) -> bool {
        // A NaN bound bounds nothing.
        bound <= self.shared[j].threshold(i_a) || bound.is_nan()
    }

    fn sweep(&mut self, j: usize, i_n: usize, i_a: usize, values: &[f64]) {
        // Only the first smallest value can be recorded (visits keep the
        // first of equal values), so it is the only one visited.
        let e = values
            .iter()
            .fold(f64::INFINITY, |m, &e| if e < m { e } else { m });
        let i_b = values.iter().position(|&v| v == e).unwrap_or(0);
        let flat = self.grid.flat(self.i_s, i_n, i_a, i_b);
        self.found[j].visit(&self.shared[j], flat, i_a, e);
    }
}
