//! `laminar report speed-vs-error`: every search path, timed and compared
//! with the f64 reference; `laminar report scaling`: time per fit against
//! K and the grid size, one set at a time and in a batch.

use super::options::{
    check_out, emit, global_threads, progress, report_time, CuretArgs, GridArgs, ThreadArgs, PAIRS,
};
use clap::{Args, Subcommand};
use laminar_brdf::scaling::scaling;
use laminar_brdf::selection::synthetic_jobs;
use laminar_brdf::speed::speed_vs_error;
use laminar_brdf::usage::UsageError;
use laminar_brdf::CliError;
use laminar_brdf_fit::Scene;
use laminar_brdf_fit::SearchPath;
use std::path::PathBuf;
use std::time::Instant;

/// Reports on the search paths.
#[derive(Subcommand, Debug)]
pub enum ReportKind {
    /// Every search path timed and compared with the f64 reference (Markdown).
    ///
    /// Runs the exp and gauss fits of the selected data (CUReT, or the
    /// synthetic scene) on every path: pairs/s, speed-up and error against
    /// the f64 reference.
    SpeedVsError(SpeedArgs),
    /// Time per fit against K and grid size, one-set and batch (Markdown).
    ///
    /// Fits the exp model to synthetic sets on spread geometries of each K
    /// of --ks (on the grid of the grid options), and on the first K with
    /// the grid's points per axis multiplied by each of --scales; prints
    /// the time per fit of `fit` (one set at a time) and of `fit_batch`
    /// (sets sharing the geometry), and the fitted power-law exponents.
    Scaling(ScalingArgs),
}

/// Options of `report scaling`.
#[derive(Args, Debug)]
pub struct ScalingArgs {
    #[command(flatten)]
    threads: ThreadArgs,
    #[command(flatten)]
    grid: GridArgs,
    /// Numbers of measurements per set, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "198,2000,20000")]
    ks: Vec<usize>,
    /// Multipliers of the points per axis, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "1,2,4")]
    scales: Vec<usize>,
    /// Sets fitted one at a time per configuration.
    #[arg(long, default_value_t = 4)]
    sets: usize,
    /// Sets per batch.
    #[arg(long, default_value_t = 64)]
    batch_sets: usize,
    /// Also write the report to FILE.
    #[arg(long)]
    out: Option<PathBuf>,
}

/// Options of `report speed-vs-error`.
#[derive(Args, Debug)]
pub struct SpeedArgs {
    #[command(flatten)]
    curet: CuretArgs,
    #[command(flatten)]
    threads: ThreadArgs,
    #[command(flatten)]
    grid: GridArgs,
    /// σ/T values of the grid slice the direct paths run on.
    #[arg(long, default_value_t = 1)]
    direct_slopes: usize,
    /// Also write the table to FILE.
    #[arg(long)]
    out: Option<PathBuf>,
}

/// Runs a report.
pub fn run(kind: &ReportKind) -> Result<(), CliError> {
    match kind {
        ReportKind::SpeedVsError(args) => speed(args),
        ReportKind::Scaling(args) => scaling_report(args),
    }
}

fn scaling_report(args: &ScalingArgs) -> Result<(), CliError> {
    let start = Instant::now();
    check_out(args.out.as_ref(), &[])?;
    global_threads(&args.threads)?;
    if args.ks.is_empty()
        || args.ks.contains(&0)
        || args.scales.is_empty()
        || args.scales.contains(&0)
        || args.sets == 0
        || args.batch_sets == 0
    {
        return Err(UsageError::ScalingCounts.into());
    }
    let grid = args.grid.grid(laminar_brdf_fit::Objective::Paper)?;
    let bar = progress((args.ks.len() + args.scales.len()) as u64, "scaling");
    let report = scaling(
        &grid,
        &args.ks,
        &args.scales,
        args.sets,
        args.batch_sets,
        &|what| {
            bar.set_message(what.to_string());
            bar.inc(1);
        },
    )?;
    bar.finish_and_clear();
    let text = report.markdown();
    print!("{text}");
    if args.out.is_some() {
        emit(args.out.as_ref(), &text)?;
    }
    laminar_brdf::note!("report scaling: {:.1} s", start.elapsed().as_secs_f64());
    Ok(())
}

fn speed(args: &SpeedArgs) -> Result<(), CliError> {
    let start = Instant::now();
    check_out(args.out.as_ref(), &args.curet.inputs())?;
    global_threads(&args.threads)?;
    let grid = args.grid.grid(laminar_brdf_fit::Objective::Paper)?;
    let jobs = args.curet.jobs()?.unwrap_or_else(synthetic_jobs);
    let scenes: Vec<Scene> = jobs.into_iter().map(|j| j.scene).collect();
    let runs = scenes.len() as u64 * 2 * SearchPath::all().len() as u64;
    let bar = progress(runs, "speed-vs-error");
    let report = speed_vs_error(&scenes, &grid, args.direct_slopes, &|what| {
        if what.ends_with("reference") {
            bar.set_message(what.to_string());
        } else {
            bar.inc(1);
        }
    })?;
    bar.finish_and_clear();
    let text = report.markdown();
    print!("{text}");
    if args.out.is_some() {
        emit(args.out.as_ref(), &text)?;
    }
    let pairs: f64 = scenes.iter().map(|s| s.len() as f64).sum::<f64>() * grid.size() as f64;
    report_time("report speed-vs-error", start, pairs * 2.0, PAIRS);
    Ok(())
}
