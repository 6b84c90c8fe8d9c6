//! `laminar fit`: fit models to measurements by exhaustive grid search.

use super::options::{
    any_model, check_extension, check_out, emit, jobs, progress, report_time, ChannelArgs,
    CuretArgs, FileArgs, FitterArgs, OutputFormat, PAIRS,
};
use clap::{Args, ValueEnum};
use laminar_brdf::reproduce::{fit_jobs, fit_jobs_shards};
use laminar_brdf::usage::UsageError;
use laminar_brdf::CliError;
use laminar_brdf_fit::{synthetic, FittedModel, Model, ModelParams};
use laminar_brdf_io::fits::{self, Energy, FitEntry, Units};
use std::path::PathBuf;
use std::time::Instant;

/// The units of the fitted data (`--units`).
#[derive(Clone, Copy, Debug, ValueEnum)]
enum UnitsArg {
    /// A BRDF in absolute units (sr⁻¹).
    Absolute,
    /// Any other scale.
    Relative,
}

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

/// Fit models to measurements.
///
/// Input: a measurement file (--measurements: CSV, or MERL with
/// --sample-at), a CUReT directory (--data or CURET_DIR), or else the
/// built-in synthetic scene. Values are BRDF unless --quantity radiance;
/// BRDF is fitted as radiance BRDF·cos θi. Specular measurements are left
/// out and the data divided by their max.
///
/// Objective (--objective): free (default) minimises Σ w(D − c·M)², M eq.
/// 8's raw mix with β eq. 8's, the amplitude c ≥ 0 and β in closed form,
/// w = 1/σ² from sigma columns (else 1): a grid over σ/T, n, a, then
/// Levenberg–Marquardt from its basins, every estimate and interval inside
/// the box the axes give (docs/conventions.md §4b, §11b). paper: the
/// paper's exhaustive grid search, data and model each divided by their
/// max (§4, §11).
///
/// CSV columns: sample (CUReT sample number or file stem), channel, model,
/// rms = Δ_RMS (eq. 15) = 100·sqrt(Σ(D−P)²)/K over the K kept measurements,
/// chi2_dof = χ²/ν (eq. 16) = Σ(P−D)²/D over the chi2_used measurements
/// with D > 0 divided by (chi2_used − p), chi2_left_out, params (free: the
/// refined estimate, β eq. 8's; paper: the best grid point, β the paper
/// normalisation's balance, the JSON gives eq. 8's beta_eq8), rh_rms,
/// rh_chi2_dof, rh_params (the Ragheb–Hancock best, a = 0, of the same
/// box or search), measurements (K), nonpositive, search_rms (the grid's
/// Δ_RMS), edges (flags per parameter: range_edge, free: the estimate is on
/// a face of the box, paper: its grid value is an end of its axis;
/// domain_bound, the value reported is a bound of the model's domain;
/// open_below/open_above, its 95% interval reaches the box's face (free) or
/// past the range searched (paper); not_identified, its 95% interval is the
/// whole box; e.g. `n:range_edge+open_above;a:range_edge+domain_bound`).
/// Then rms_grid, rms_refined, and per parameter {name}_refined, _lo68,
/// _hi68, _lo95, _hi95 (68% and 95% intervals), _interval (profile or
/// jacobian: where the ends come from), _sd (the Jacobian's), _box_lo,
/// _box_hi (the box), _released, _released_rms (for an estimate on a face
/// of the box: one local fit with that bound released, a diagnostic), then
/// correlations, trade_offs (pairs with |r| ≥ 0.9), objective, amplitude
/// (c) and chi2_weighted (Σ w(D−P)²/(K − p)); see --refine and --uncertainty.
#[derive(Args, Debug)]
#[command(verbatim_doc_comment)]
pub struct FitArgs {
    #[command(flatten)]
    file: FileArgs,
    #[command(flatten)]
    channels: ChannelArgs,
    #[command(flatten)]
    curet: CuretArgs,
    /// Models, comma-separated (default: every one under the free objective;
    /// the tied ones, the paper's, under the paper objective).
    #[arg(long, value_delimiter = ',', value_parser = any_model())]
    models: Option<Vec<Model>>,
    #[command(flatten)]
    fitting: FitterArgs,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Csv)]
    format: Format,
    /// Add each fit's directional albedo ρ(θv) at θv = 0, 5, …, 85° to
    /// the fitted-model file (`energy`; with --format json), with --units
    /// and whether ρ > 1 anywhere in absolute units (`energy_gain`).
    #[arg(long)]
    albedo: bool,
    /// The units of the fitted data, recorded with --albedo: `absolute`
    /// (a BRDF in sr⁻¹, where ρ > 1 is a gain of energy) or `relative`
    /// (any other scale, e.g. CUReT's).
    #[arg(long, value_enum, default_value_t = UnitsArg::Relative, requires = "albedo")]
    units: UnitsArg,
    /// Write the output to FILE (whole or not at all) instead of stdout.
    #[arg(long)]
    out: Option<PathBuf>,
}

/// Runs `laminar fit`.
pub fn run(args: &FitArgs) -> Result<(), CliError> {
    let start = Instant::now();
    let inputs: Vec<PathBuf> = args
        .file
        .inputs()
        .into_iter()
        .chain(args.curet.inputs())
        .collect();
    check_out(args.out.as_ref(), &inputs)?;
    if let Some(out) = &args.out {
        let writes = match args.format {
            Format::Csv => OutputFormat::Csv,
            Format::Json => OutputFormat::Json,
            Format::Markdown => OutputFormat::Markdown,
        };
        check_extension(out, writes)?;
    }
    if args.albedo && !matches!(args.format, Format::Json) {
        return Err(UsageError::AlbedoWithoutJson.into());
    }
    let fitter = args.fitting.fitter()?;
    let jobs = jobs(&args.file, &args.channels, &args.curet)?;
    let models =
        (args.models.clone()).unwrap_or_else(|| fitter.objective_of_fits().default_models());
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
        Format::Json if args.albedo => {
            let units = match args.units {
                UnitsArg::Absolute => Units::Absolute,
                UnitsArg::Relative => Units::Relative,
            };
            let mut entries = Vec::with_capacity(records.len());
            for r in &records {
                let mut entry = FitEntry::new(r);
                entry.energy = Some(Energy::of(&entry.fitted, units)?);
                entries.push(entry);
            }
            fits::json_entries(&entries)
        }
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
                sub_slope: None,
            },
            job.scene.angles(),
            1.0,
        )
        .ok()
        .and_then(|m| m.beta_eq8)
        .unwrap_or(f64::NAN);
        laminar_brdf::note!(
            "synthetic scene: true parameters slope={s};beta={b};n={n};a={a} (exp model, paper normalisation; eq. 8's beta, the free objective's, is {beta_eq8:.4}), noise σ = {}",
            synthetic::NOISE
        );
    }
    report_time("fit", start, pairs, PAIRS);
    Ok(())
}
