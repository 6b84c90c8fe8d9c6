//! `laminar report speed-vs-error`: every search path, timed and compared
//! with the f64 reference.

use super::options::{
    check_out, emit, global_threads, progress, report_time, CuretArgs, GridArgs, ThreadArgs, PAIRS,
};
use clap::{Args, Subcommand};
use laminar_cli::selection::synthetic_jobs;
use laminar_cli::speed::speed_vs_error;
use laminar_cli::CliError;
use laminar_fit::search::Path as SearchPath;
use laminar_fit::Scene;
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
    let ReportKind::SpeedVsError(args) = kind;
    let start = Instant::now();
    check_out(args.out.as_ref())?;
    global_threads(&args.threads)?;
    let grid = args.grid.grid()?;
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
