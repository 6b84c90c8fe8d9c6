//! `laminar parity`: the SIMD path against its scalar twin, bit for bit.

use super::options::{global_threads, layered_model};
use super::options::{
    jobs, report_time, ChannelArgs, CuretArgs, FileArgs, GridArgs, PathArgs, ThreadArgs, PAIRS,
};
use clap::Args;
use laminar_brdf::CliError;
use laminar_brdf_fit::paper::search::batch::search_batch;
use laminar_brdf_fit::paper::search::{search, SearchResult, Twins};
use laminar_brdf_fit::{Arith, Method, SearchPath};
use laminar_brdf_fit::{Grid, Model, Scene};
use std::time::Instant;

/// Compare every grid value of the SIMD path with its scalar twin, bit for bit.
///
/// Evaluates every grid value on the f32x8 path and its scalar f32 twin
/// (the method of --path). Exit status 0 only if all are identical.
#[derive(Args, Debug)]
pub struct ParityArgs {
    #[command(flatten)]
    file: FileArgs,
    #[command(flatten)]
    channels: ChannelArgs,
    #[command(flatten)]
    curet: CuretArgs,
    /// Layered models to compare, comma-separated (default: every one).
    #[arg(long, value_delimiter = ',', value_parser = layered_model())]
    models: Option<Vec<Model>>,
    #[command(flatten)]
    path: PathArgs,
    #[command(flatten)]
    threads: ThreadArgs,
    #[command(flatten)]
    grid: GridArgs,
}

/// Runs `laminar parity`; `Ok(false)` when some value differs.
pub fn run(args: &ParityArgs) -> Result<bool, CliError> {
    let start = Instant::now();
    // Layered models only: the parser takes no other.
    let models: Vec<Model> = args
        .models
        .clone()
        .unwrap_or_else(|| Model::layered().collect());
    global_threads(&args.threads)?;
    let grid = args.grid.grid(laminar_brdf_fit::Objective::Paper)?;
    let jobs = jobs(&args.file, &args.channels, &args.curet)?;
    let (mut same, mut all) = (0usize, 0usize);
    let mut pairs = 0.0;
    for job in &jobs {
        for &model in &models {
            let corr = model.correlation().expect("layered models only");
            let g = if model.is_ragheb_hancock() {
                grid.ragheb_hancock()
            } else {
                grid.clone()
            };
            let (simd_path, scalar_path) = args.path.path.twins();
            let twins = Twins::new(&job.scene, &g, corr, args.path.path.method)?;
            let (equal, simd) = (twins.identical(), twins.simd);
            println!(
                "sample {} channel {} model {} ({simd_path} vs {scalar_path}): {equal} of {} grid values identical",
                job.scene.sample(),
                job.scene.channel(),
                model.name(),
                simd.len()
            );
            same += equal;
            all += simd.len();
            pairs += 2.0 * g.size() as f64 * job.scene.len() as f64;
        }
    }
    println!("parity: {same} of {all} grid values identical");
    let batch_same = if args.path.path.method == Method::Envelope {
        let scenes: Vec<Scene> = jobs.iter().map(|j| j.scene.clone()).collect();
        batch_parity(&scenes, &models, &grid)?
    } else {
        true
    };
    report_time("parity", start, pairs, PAIRS);
    Ok(same == all && batch_same)
}

/// The batch search (envelope method) of the scenes that share the first
/// scene's geometry, on `f32x8` and on its scalar twin `f32`, against each
/// other and against searching each scene alone: every result (chosen grid
/// point, Δ_RMS bits, Ragheb–Hancock best) must be identical.
fn batch_parity(scenes: &[Scene], models: &[Model], grid: &Grid) -> Result<bool, CliError> {
    let shared: Vec<Scene> = scenes
        .iter()
        .filter(|s| s.angles() == scenes[0].angles())
        .cloned()
        .collect();
    let (mut same, mut all) = (0usize, 0usize);
    for &model in models {
        let corr = model.correlation().expect("layered models only");
        let g = if model.is_ragheb_hancock() {
            grid.ragheb_hancock()
        } else {
            grid.clone()
        };
        let simd = search_batch(&shared, &g, corr, Arith::F32x8, &|| {})?;
        let scalar = search_batch(&shared, &g, corr, Arith::F32, &|| {})?;
        for ((scene, v), s) in shared.iter().zip(&simd).zip(&scalar) {
            let alone = search(
                scene,
                &g,
                corr,
                SearchPath::new(Method::Envelope, Arith::F32x8),
                &|| {},
            )?;
            let key = |r: &SearchResult| {
                (
                    r.best,
                    r.best_rms.to_bits(),
                    r.rh_best.map(|(f, e)| (f, e.to_bits())),
                )
            };
            all += 1;
            same += usize::from(key(v) == key(s) && key(v) == key(&alone));
        }
    }
    println!(
        "batch: {same} of {all} searches identical (envelope-f32x8 batch of {} sets on one geometry vs its f32 twin vs each set alone)",
        shared.len()
    );
    Ok(same == all)
}
