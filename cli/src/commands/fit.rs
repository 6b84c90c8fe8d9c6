//! `laminar fit`: fit models to measurements by exhaustive grid search.

use super::options::{
    check_out, emit, fitter, jobs, progress, report_time, AnalysisArgs, ChannelArgs, CuretArgs,
    FileArgs, GridArgs, ObjectiveArgs, PathArgs, ThreadArgs, PAIRS,
};
use clap::{Args, ValueEnum};
use laminar_cli::reproduce::{fit_jobs, fit_jobs_shards};
use laminar_cli::CliError;
use laminar_fit::{synthetic, FittedModel, Model, ModelParams};
use laminar_io::fits;
use std::path::PathBuf;
use std::time::Instant;

/// Output formats of `fit`.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Format {
    /// One row per fit (columns: see `laminar fit --help`).
    Csv,
    /// The fitted-model file: every fit with what `predict` and `export` need.
    Json,
    /// A Markdown table.
    Markdown,
}

/// Fit models by exhaustive grid search.
///
/// Input: a measurement file (--measurements: CSV, or MERL with
/// --sample-at), a CUReT directory (--data or CURET_DIR), or else the
/// built-in synthetic scene. Values are BRDF unless --quantity radiance;
/// BRDF is fitted as radiance BRDF·cos θi. Specular measurements are left
/// out; data and model are each divided by their max (the paper
/// normalisation; docs/conventions.md §4).
///
/// CSV columns: sample (CUReT sample number or file stem), channel, model,
/// rms = Δ_RMS (eq. 15) = 100·sqrt(Σ(D−P)²)/K over the K kept measurements,
/// chi2_dof = χ²/ν (eq. 16) = Σ(P−D)²/D over the chi2_used measurements
/// with D > 0 divided by (chi2_used − p), chi2_left_out, params (β is the
/// paper normalisation's balance; the JSON gives eq. 8's beta_eq8), rh_rms,
/// rh_chi2_dof, rh_params (the Ragheb–Hancock best, a = 0, of the same
/// search), measurements (K), nonpositive, search_rms (the search's own
/// Δ_RMS in its precision), edges (flags per searched parameter: range_edge,
/// its grid value is an end of its axis; domain_bound, the value reported
/// is a bound of the model's domain; open_below/open_above, its 95%
/// interval reaches past the range searched; e.g.
/// `n:range_edge+open_above;a:range_edge+domain_bound`). rms and chi2_dof
/// are recomputed in f64 at the best grid point. Then rms_grid,
/// rms_refined, and per parameter {name}_refined, _lo68, _hi68, _lo95,
/// _hi95 (68% and 95% intervals), _interval (profile or jacobian: where
/// the ends come from), _sd (the Jacobian's), then correlations and
/// trade_offs (pairs with |r| ≥ 0.9); see --refine and --uncertainty
/// (docs/conventions.md §11).
#[derive(Args, Debug)]
#[command(verbatim_doc_comment)]
pub struct FitArgs {
    #[command(flatten)]
    file: FileArgs,
    #[command(flatten)]
    channels: ChannelArgs,
    #[command(flatten)]
    curet: CuretArgs,
    /// Models, comma-separated: exp, gauss, rh-exp, rh-gauss, jensen, oren-nayar (default: all six).
    #[arg(long, value_delimiter = ',')]
    models: Option<Vec<Model>>,
    #[command(flatten)]
    path: PathArgs,
    #[command(flatten)]
    threads: ThreadArgs,
    #[command(flatten)]
    grid: GridArgs,
    #[command(flatten)]
    objective: ObjectiveArgs,
    #[command(flatten)]
    analysis: AnalysisArgs,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Csv)]
    format: Format,
    /// Write the output to FILE (whole or not at all) instead of stdout.
    #[arg(long)]
    out: Option<PathBuf>,
}

/// Runs `laminar fit`.
pub fn run(args: &FitArgs) -> Result<(), CliError> {
    let start = Instant::now();
    check_out(args.out.as_ref())?;
    let fitter = fitter(
        &args.grid,
        &args.threads,
        args.path.path,
        &args.analysis,
        args.objective.objective,
    )?;
    let jobs = jobs(&args.file, &args.channels, &args.curet)?;
    let models = args.models.clone().unwrap_or_else(|| Model::ALL.to_vec());
    let bar = progress(fit_jobs_shards(&fitter, &jobs, &models), "fit");
    let tick = bar.clone();
    let fitter = fitter.on_progress(move || tick.inc(1));
    let records = fit_jobs(&fitter, &jobs, &models)?;
    let pairs: f64 = records
        .iter()
        .map(|r| r.evaluated as f64 * r.measurements as f64)
        .sum();
    bar.finish_and_clear();
    let text = match args.format {
        Format::Csv => fits::csv(&records),
        Format::Json => fits::json(&records),
        Format::Markdown => fits::markdown(&records),
    };
    emit(args.out.as_ref(), &text)?;
    if let Some(job) = jobs.iter().find(|j| j.scene.sample() == "synthetic") {
        let (s, b, n, a) = synthetic::TRUE_PARAMS;
        // The scene is paper-normalised; the same lobe as eq. 8's mix has
        // the balance beta_eq8 (docs/conventions.md §4), the free
        // objective's β.
        let beta_eq8 = FittedModel::normalised_on(
            Model::Exp,
            ModelParams::Layered {
                slope: s,
                beta: b,
                n,
                a,
            },
            job.scene.angles(),
            1.0,
        )
        .ok()
        .and_then(|m| m.beta_eq8)
        .unwrap_or(f64::NAN);
        eprintln!(
            "synthetic scene: true parameters slope={s};beta={b};n={n};a={a} (exp model, paper normalisation; eq. 8's beta, the free objective's, is {beta_eq8:.4}), noise σ = {}",
            synthetic::NOISE
        );
    }
    report_time("fit", start, pairs, PAIRS);
    Ok(())
}
