//! The paper's exhaustive grid search (conventions §4–§6) for the absorptive
//! model, written once over [`Lane`] and run as
//! * the SIMD path: `f32x8`, one stream of eight-measurement chunks;
//! * its scalar twin: `f32`, eight streams of one measurement each, so that
//!   every grid value is bitwise the SIMD one (same operations per
//!   measurement, lane sums reduced in the same fixed order);
//! * the `f64` reference: the same code with `f64` lanes.
//!
//! Hoisting: geometry once per scene; refraction and Fresnel (the
//! [`Interface`]) once per (scene, n); the absorption factor once per
//! (scene, a); the normalised surface term once per σ/T; the subsurface base
//! once per (σ/T, n); the normalised subsurface term once per (σ/T, n, a).
//! Only the β loop touches every measurement for every parameter set.

use crate::grid::Grid;
use crate::scene::Scene;
use laminar_core::{
    absorption_factor, f32x8, inverse_slope_squared, mix, subsurface_base, surface_radiance,
    Correlation, Geometry, Interface, Lane, Real,
};
use rayon::prelude::*;

/// Lanes of the widest path; also the number of partial sums of every path.
const WIDTH: usize = 8;

/// Which implementation evaluates the grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Path {
    /// `f32x8` SIMD (the default).
    Simd,
    /// Scalar `f32`, bitwise identical to [`Path::Simd`].
    Scalar,
    /// Scalar `f64`, the accuracy reference.
    Reference,
}

/// One chunk of `L::LANES` measurements.
struct Chunk<L> {
    geom: Geometry<L>,
    data: L,
    /// 1 for a real measurement, 0 for padding (padding gives S = U = D = 0).
    valid: L,
}

/// A scene packed into `WIDTH / L::LANES` streams of chunks. Measurement `k`
/// sits in chunk `k / 8`, at global lane `k % 8` = stream · LANES + lane.
struct Packed<L> {
    /// Chunks, stream-major: `chunks[stream * per_stream + c]`.
    chunks: Vec<Chunk<L>>,
    per_stream: usize,
    k: usize,
}

impl<L: Lane> Packed<L> {
    fn new(scene: &Scene) -> Self {
        let streams = WIDTH / L::LANES;
        let per_stream = scene.len().div_ceil(WIDTH);
        let mut chunks = Vec::with_capacity(streams * per_stream);
        let last = scene.len().saturating_sub(1);
        for s in 0..streams {
            for c in 0..per_stream {
                let k = move |lane: usize| c * WIDTH + s * L::LANES + lane;
                chunks.push(Chunk {
                    geom: Geometry::from_lanes(|lane| scene.angles[k(lane).min(last)]),
                    data: L::from_f64_lanes(|lane| scene.data.get(k(lane)).copied().unwrap_or(0.0)),
                    valid: L::from_f64_lanes(|lane| if k(lane) < scene.len() { 1.0 } else { 0.0 }),
                });
            }
        }
        Self {
            chunks,
            per_stream,
            k: scene.len(),
        }
    }

    fn stream_of(&self, flat: usize) -> usize {
        flat / self.per_stream
    }

    /// Largest lane value of `values` (exact, so order does not matter).
    fn max_of(values: &[L]) -> L::Scalar {
        let mut m = L::Scalar::c(0.0);
        for v in values {
            for lane in 0..L::LANES {
                m = m.max(v.lane(lane));
            }
        }
        m
    }

    /// `values / max(values)`, or zeros when the max is ≤ 0 (conventions §4).
    fn normalise(values: &mut [L]) {
        let m = Self::max_of(values);
        let zero = L::Scalar::c(0.0);
        for v in values.iter_mut() {
            *v = if m > zero {
                *v / L::splat(m)
            } else {
                L::c(0.0)
            };
        }
    }

    /// `Δ_RMS` (eq. 15) of the paper-normalised mix `β U + (1 − β) S`
    /// against the data, in lane precision.
    fn rms(&self, surface: &[L], subsurface: &[L], beta: L) -> L::Scalar {
        let mut m = L::c(0.0);
        for (s, u) in surface.iter().zip(subsurface) {
            m = m.max(mix(beta, *u, *s));
        }
        let m = Self::max_of(&[m]);
        let positive = m > L::Scalar::c(0.0);
        let m = L::splat(m);
        let mut acc = [L::c(0.0); WIDTH];
        for (flat, ((s, u), chunk)) in surface.iter().zip(subsurface).zip(&self.chunks).enumerate()
        {
            let p = if positive {
                mix(beta, *u, *s) / m
            } else {
                L::c(0.0)
            };
            let e = chunk.data - p;
            let a = &mut acc[self.stream_of(flat)];
            *a = *a + e * e;
        }
        // Fixed-order reduction over the eight global lanes.
        let mut sum = L::Scalar::c(0.0);
        for g in 0..WIDTH {
            sum = sum + acc[g / L::LANES].lane(g % L::LANES);
        }
        L::Scalar::c(100.0) * sum.sqrt() / L::Scalar::c(self.k as f64)
    }
}

/// Per-scene tables shared by every σ/T shard.
struct Tables<L> {
    packed: Packed<L>,
    /// `interfaces[n][flat chunk]`.
    interfaces: Vec<Vec<Interface<L>>>,
    /// `absorption[a][flat chunk]`.
    absorption: Vec<Vec<L>>,
}

impl<L: Lane + Send + Sync> Tables<L> {
    fn new(scene: &Scene, grid: &Grid) -> Self {
        let packed = Packed::<L>::new(scene);
        let interfaces = grid
            .n
            .values
            .iter()
            .map(|&n| {
                packed
                    .chunks
                    .iter()
                    .map(|c| Interface::new(&c.geom, L::c(n)))
                    .collect()
            })
            .collect();
        let absorption = grid
            .a
            .values
            .iter()
            .map(|&a| {
                packed
                    .chunks
                    .iter()
                    .map(|c| absorption_factor(&c.geom, L::c(a)))
                    .collect()
            })
            .collect();
        Self {
            packed,
            interfaces,
            absorption,
        }
    }

    /// Visits every (n, a, β) of slope index `i_s` in loop order with its RMS.
    fn shard(
        &self,
        grid: &Grid,
        corr: Correlation,
        i_s: usize,
        mut visit: impl FnMut(usize, L::Scalar),
    ) {
        let chunks = &self.packed.chunks;
        let inv_s2 = inverse_slope_squared(L::c(grid.slope.values[i_s]));
        let mut surface: Vec<L> = chunks
            .iter()
            .map(|c| surface_radiance(&c.geom, corr, inv_s2) * c.valid)
            .collect();
        Packed::normalise(&mut surface);
        let betas: Vec<L> = grid.beta.values.iter().map(|&b| L::c(b)).collect();
        let mut subsurface = vec![L::c(0.0); chunks.len()];
        for (i_n, ifaces) in self.interfaces.iter().enumerate() {
            let base: Vec<L> = ifaces
                .iter()
                .zip(chunks)
                .map(|(f, c)| subsurface_base(f, corr, inv_s2) * c.valid)
                .collect();
            for (i_a, att) in self.absorption.iter().enumerate() {
                for ((u, b), f) in subsurface.iter_mut().zip(&base).zip(att) {
                    *u = *b * *f;
                }
                Packed::normalise(&mut subsurface);
                for (i_b, &beta) in betas.iter().enumerate() {
                    visit(
                        grid.flat(i_s, i_n, i_a, i_b),
                        self.packed.rms(&surface, &subsurface, beta),
                    );
                }
            }
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
}

/// A grid point's flat index and RMS.
type Candidate = Option<(usize, f64)>;

/// Strictly-better update (keeps the smallest flat index on ties).
fn better(current: Candidate, flat: usize, rms: f64) -> Candidate {
    match current {
        Some((_, r)) if rms >= r => current,
        _ => Some((flat, rms)),
    }
}

fn search_with<L: Lane + Send + Sync>(
    scene: &Scene,
    grid: &Grid,
    corr: Correlation,
    progress: &(dyn Fn() + Sync),
) -> SearchResult {
    let tables = Tables::<L>::new(scene, grid);
    let zero_a = grid.a.values.iter().position(|&a| a == 0.0);
    let per_a = grid.beta.len();
    let shards: Vec<(Candidate, Candidate)> = (0..grid.slope.len())
        .into_par_iter()
        .map(|i_s| {
            let (mut best, mut rh) = (None, None);
            tables.shard(grid, corr, i_s, |flat, rms| {
                let rms = rms.to_f64();
                best = better(best, flat, rms);
                if zero_a == Some((flat / per_a) % grid.a.len()) {
                    rh = better(rh, flat, rms);
                }
            });
            progress();
            (best, rh)
        })
        .collect();
    let (mut best, mut rh) = (None, None);
    for (b, r) in shards {
        if let Some((f, v)) = b {
            best = better(best, f, v);
        }
        if let Some((f, v)) = r {
            rh = better(rh, f, v);
        }
    }
    let (best, best_rms) = best.unwrap_or((0, f64::INFINITY));
    SearchResult {
        best,
        best_rms,
        rh_best: rh,
    }
}

/// Runs the exhaustive search on `path`; `progress` is called once per σ/T
/// shard. Deterministic whatever the thread count (conventions §6).
pub fn search(
    scene: &Scene,
    grid: &Grid,
    corr: Correlation,
    path: Path,
    progress: &(dyn Fn() + Sync),
) -> SearchResult {
    match path {
        Path::Simd => search_with::<f32x8>(scene, grid, corr, progress),
        Path::Scalar => search_with::<f32>(scene, grid, corr, progress),
        Path::Reference => search_with::<f64>(scene, grid, corr, progress),
    }
}

/// Every grid value's RMS on `path`, in flattened order (as `f64`, widened exactly).
pub fn error_surface(scene: &Scene, grid: &Grid, corr: Correlation, path: Path) -> Vec<f64> {
    fn run<L: Lane + Send + Sync>(scene: &Scene, grid: &Grid, corr: Correlation) -> Vec<f64> {
        let tables = Tables::<L>::new(scene, grid);
        let per_slope = grid.size() / grid.slope.len();
        let mut out = vec![0.0; grid.size()];
        out.par_chunks_mut(per_slope)
            .enumerate()
            .for_each(|(i_s, slice)| {
                tables.shard(grid, corr, i_s, |flat, rms| {
                    slice[flat - i_s * per_slope] = rms.to_f64()
                });
            });
        out
    }
    match path {
        Path::Simd => run::<f32x8>(scene, grid, corr),
        Path::Scalar => run::<f32>(scene, grid, corr),
        Path::Reference => run::<f64>(scene, grid, corr),
    }
}

/// The grid point of a flattened index as (σ/T, n, a, β).
pub fn point(grid: &Grid, flat: usize) -> (f64, f64, f64, f64) {
    let b = flat % grid.beta.len();
    let rest = flat / grid.beta.len();
    let a = rest % grid.a.len();
    let rest = rest / grid.a.len();
    let n = rest % grid.n.len();
    let s = rest / grid.n.len();
    (
        grid.slope.values[s],
        grid.n.values[n],
        grid.a.values[a],
        grid.beta.values[b],
    )
}
