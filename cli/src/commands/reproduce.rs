//! `laminar reproduce`: the paper's experiment, tables and figures.

use super::options::{
    progress, report_time, settings, AnalysisArgs, CuretArgs, GridArgs, PathArgs, ThreadArgs, PAIRS,
};
use clap::Args;
use laminar_brdf::reproduce::{fit_jobs_shards, prepare_out_dir, reproduce, FITTED};
use laminar_brdf::usage::UsageError;
use laminar_brdf::CliError;
use laminar_brdf_fit::{Objective, Settings};
use std::path::PathBuf;
use std::time::Instant;

/// Reproduce the paper's experiment on CUReT: Tables II–V and figures.
///
/// Fits exp, gauss, jensen and oren-nayar (the Ragheb–Hancock fits are the
/// a = 0 slices of the absorptive searches), then writes Tables II–V
/// (Markdown, CSV), fits.csv, summary.md, Fig. 2 and data-against-model
/// figures (SVG) as one set: into a fresh sibling directory that replaces
/// --out whole, so an interrupted run leaves the earlier set as it was.
/// Figures of an earlier run that this run does not write are listed as
/// removed; a directory holding other files is refused.
#[derive(Args, Debug)]
pub struct ReproduceArgs {
    #[command(flatten)]
    curet: CuretArgs,
    #[command(flatten)]
    path: PathArgs,
    #[command(flatten)]
    threads: ThreadArgs,
    #[command(flatten)]
    grid: GridArgs,
    #[command(flatten)]
    analysis: AnalysisArgs,
    /// Output directory (created if missing).
    #[arg(long)]
    out: PathBuf,
}

/// Runs `laminar reproduce`.
pub fn run(args: &ReproduceArgs) -> Result<(), CliError> {
    let start = Instant::now();
    prepare_out_dir(&args.out)?;
    let fitter = Settings {
        objective: Objective::Paper,
        ..settings(&args.grid, &args.threads, args.path.path, &args.analysis)
    }
    .fitter()?;
    let jobs = args
        .curet
        .jobs()?
        .ok_or_else(|| CliError::from(UsageError::ReproduceWithoutData))?;
    let total = fit_jobs_shards(&fitter, &jobs, &FITTED);
    let bar = progress(total, "reproduce");
    let tick = bar.clone();
    let fitter = fitter.on_progress(move || tick.inc(1));
    let r = reproduce(&fitter, &jobs, &args.out)?;
    bar.finish_and_clear();
    for path in &r.removed {
        laminar_brdf::note!(
            "reproduce: removed stale figure {} (earlier run)",
            path.display()
        );
    }
    laminar_brdf::note!(
        "reproduce: {} fits of {} jobs, {} files written to {}",
        r.records.len(),
        jobs.len(),
        r.files.len(),
        args.out.display()
    );
    report_time("reproduce", start, r.pairs, PAIRS);
    Ok(())
}
