//! Many scenes on one geometry (every sample of a database, every channel,
//! every pixel of a texture): the envelope search with the model-side work
//! done once per (σ/T, n, a) and shared by every scene — the terms `S` and
//! `U`, `Σ S²`, `Σ Δ²`, `Σ S Δ`, the Pareto front of `(S_k, U_k)` and the
//! upper hull of its lines. Per scene remain `Σ S D`, `Σ D²` (per σ/T),
//! `Σ D Δ`, the lower bound and the β sweep of the triples it does not skip.
//!
//! Every value a scene sees is computed by the same operations, in the same
//! order, as in the one-scene envelope search ([`super::envelope`]), so each
//! result is bit for bit the one of searching that scene alone, whatever the
//! thread count (each scene keeps its own shared best for the skipping).

use super::envelope::{build_hull, lower_bound, sweep_hull, Scratch};
use super::packed::{Packed, Tables};
use super::sums::{DeltaSums, SurfaceSums};
use super::{combine, Arith, SearchResult, ShardBest, SharedBest};
use crate::error::GridError;
use crate::grid::Grid;
use crate::scene::Scene;
use laminar_core::{f32x8, Correlation, Lane};
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

fn run<L: Lane + Send + Sync>(
    scenes: &[Scene],
    grid: &Grid,
    corr: Correlation,
    progress: &(dyn Fn() + Sync),
) -> Vec<SearchResult> {
    let tables = Tables::<L>::new(&scenes[0], grid);
    let packs: Vec<Packed<L>> = scenes.iter().map(|s| tables.packed.with_data(s)).collect();
    let zero_a = grid.a.values.iter().position(|&a| a == 0.0);
    let shared: Vec<SharedBest> = scenes.iter().map(|_| SharedBest::new(zero_a)).collect();
    let k = tables.packed.k;
    let shards: Vec<Vec<ShardBest>> = (0..grid.slope.len())
        .into_par_iter()
        .map(|i_s| {
            let slope = grid.slope.values[i_s];
            let surface = tables.surface(corr, slope);
            let base = SurfaceSums::new(&tables.packed, &surface);
            let sums: Vec<SurfaceSums> = packs.iter().map(|p| base.with_data(p)).collect();
            let mut found: Vec<ShardBest> = scenes.iter().map(|_| ShardBest::default()).collect();
            let mut scratch = Scratch::default();
            let mut delta = vec![0.0; k];
            tables.for_each_subsurface(corr, slope, |i_n, i_a, u| {
                scratch.u.resize(k, 0.0);
                tables.packed.widen(u, &mut scratch.u);
                for (d, (u, s)) in delta.iter_mut().zip(scratch.u.iter().zip(&base.s)) {
                    *d = u - s;
                }
                let shared_sums = DeltaSums::new(&base, |i| delta[i]);
                let mut hull_ready = false;
                for (j, sums_j) in sums.iter().enumerate() {
                    let ds = shared_sums.with_data(sums_j, &delta);
                    let f = &mut found[j];
                    if lower_bound(sums_j, &ds) > shared[j].threshold(i_a) {
                        f.stats.pruned += 1;
                        continue;
                    }
                    if !hull_ready {
                        build_hull(&base, &mut scratch);
                        hull_ready = true;
                    }
                    f.stats.sweeps += 1;
                    f.stats.front_total += scratch.front_len();
                    sweep_hull(&scratch.hull, sums_j, &ds, &grid.beta.values, |i_b, e| {
                        f.visit(&shared[j], grid.flat(i_s, i_n, i_a, i_b), i_a, e)
                    });
                }
            });
            progress();
            found
        })
        .collect();
    // Regroup by scene, in σ/T order.
    let mut per_scene: Vec<Vec<ShardBest>> = scenes.iter().map(|_| Vec::new()).collect();
    for shard in shards {
        for (j, f) in shard.into_iter().enumerate() {
            per_scene[j].push(f);
        }
    }
    per_scene.into_iter().map(|s| combine(s, k)).collect()
}
