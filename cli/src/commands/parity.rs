//! `laminar parity`: the SIMD path against its scalar twin, bit for bit.

use super::options::global_threads;
use super::options::{
    jobs, report_time, ChannelArgs, CuretArgs, FileArgs, GridArgs, PathArgs, ThreadArgs, PAIRS,
};
use clap::Args;
use laminar_cli::CliError;
use laminar_fit::search::Twins;
use laminar_fit::Model;
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
    /// Layered models to compare, comma-separated: exp, gauss, rh-exp, rh-gauss (default: all four).
    #[arg(long, value_delimiter = ',')]
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
    let models: Vec<Model> = args
        .models
        .clone()
        .unwrap_or_else(|| Model::ALL.to_vec())
        .into_iter()
        .filter(|m| m.correlation().is_some())
        .collect();
    if models.is_empty() {
        return Err(CliError::Usage(
            "parity compares the grid values of the layered models; --models names none of exp, gauss, rh-exp, rh-gauss".into(),
        ));
    }
    global_threads(&args.threads)?;
    let grid = args.grid.grid()?;
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
    report_time("parity", start, pairs, PAIRS);
    Ok(same == all)
}
