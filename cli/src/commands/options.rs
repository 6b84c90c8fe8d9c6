//! Option groups shared by several subcommands. Each subcommand flattens
//! only the groups it uses, so `--help` lists only options it reads.

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use laminar_brdf::selection::{
    curet_jobs, parse_samples, synthetic_jobs, FileInput, InputFormat, Job, PAPER_SAMPLES,
};
use laminar_brdf::usage::UsageError;
use laminar_brdf::CliError;
use laminar_brdf_fit::noise::DEFAULT_FLOOR;
use laminar_brdf_fit::{
    Analysis, Axis, Fitter, Model, Objective, Param, Precision, Quantity, Settings, Uncertainty,
    UnknownName,
};
use laminar_brdf_fit::{Noise, SearchPath};
use laminar_brdf_io::AngleUnit;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A parser of the names of `models`, which `--help` lists with each
/// model's description: the lists come from the model descriptor
/// ([`Model::ALL`], [`Model::layered`]), never from a help string.
pub fn model_parser(
    models: impl IntoIterator<Item = Model>,
) -> impl TypedValueParser<Value = Model> {
    let values = models
        .into_iter()
        .map(|m| PossibleValue::new(m.name()).help(m.description()));
    PossibleValuesParser::new(values).try_map(|name| name.parse::<Model>())
}

/// [`model_parser`] of every model.
pub fn any_model() -> impl TypedValueParser<Value = Model> {
    model_parser(Model::ALL)
}

/// [`model_parser`] of the layered models (eq. 8's).
pub fn layered_model() -> impl TypedValueParser<Value = Model> {
    model_parser(Model::layered())
}

/// A CUReT directory.
#[derive(Args, Debug, Clone)]
pub struct CuretArgs {
    /// CUReT directory with table.txt and BRDF files (abrdf.dat, rbrdf.dat, …) [env: CURET_DIR].
    #[arg(long, env = "CURET_DIR")]
    pub data: Option<PathBuf>,
    /// CUReT BRDF files to read (default: every abrdf/rbrdf/gbrdf/bbrdf.dat in --data).
    #[arg(long, num_args = 1..)]
    pub brdf: Vec<PathBuf>,
    /// CUReT samples: comma-separated numbers or `all` (default: the paper's 13).
    #[arg(long)]
    pub samples: Option<String>,
}

impl CuretArgs {
    /// The files the command reads ([`curet_inputs`]; none without `--data`).
    pub fn inputs(&self) -> Vec<PathBuf> {
        self.data
            .as_deref()
            .map(|dir| curet_inputs(dir, &self.brdf))
            .unwrap_or_default()
    }

    /// The jobs of the directory, or `None` without `--data`.
    pub fn jobs(&self) -> Result<Option<Vec<Job>>, CliError> {
        let Some(dir) = &self.data else {
            if !self.brdf.is_empty() || self.samples.is_some() {
                return Err(UsageError::CuretOptionsWithoutData.into());
            }
            return Ok(None);
        };
        let samples = match &self.samples {
            Some(s) => parse_samples(s)?,
            None => Some(PAPER_SAMPLES.to_vec()),
        };
        curet_jobs(dir, &self.brdf, samples.as_deref()).map(Some)
    }
}

/// A measurement file of any supported format.
#[derive(Args, Debug, Clone)]
pub struct FileArgs {
    /// Measurement file: long-format CSV (.csv), ASTM E1392 (.astm: each
    /// column after the geometry a channel, BRDF in sr⁻¹, angles in
    /// radians), NIST's Mueller-matrix BRDF CSV (--input-format nist: each
    /// wavelength a channel), RGL's isotropic RGB tensor files (.bsdf) or
    /// MERL (.binary, needs --sample-at). Takes precedence over --data and
    /// CURET_DIR.
    #[arg(long, conflicts_with_all = ["brdf", "samples"])]
    pub measurements: Option<PathBuf>,
    /// Format of --measurements (default: from the extension).
    #[arg(long, value_enum, requires = "measurements")]
    pub input_format: Option<InputFormat>,
    /// Unit of the angles in CSV files (measurements and geometries).
    #[arg(long, default_value_t = AngleUnit::Radians)]
    pub angles: AngleUnit,
    /// What the CSV values are: brdf (fitted as BRDF·cos θi) or radiance (fitted as given).
    #[arg(long, default_value_t = Quantity::Brdf)]
    pub quantity: Quantity,
    /// Geometries to sample a MERL file at: CSV with columns
    /// theta_i,phi_i,theta_v,phi_v (or theta_i,theta_s,phi_s).
    #[arg(long)]
    pub sample_at: Option<PathBuf>,
    /// Tolerance of the specular test for --measurements, radians: a
    /// measurement with θv = θi and |φv − φi| = π within it is left out.
    #[arg(long, default_value_t = laminar_brdf_fit::measurements::SPECULAR_TOLERANCE, requires = "measurements")]
    pub specular_tolerance: f64,
}

impl FileArgs {
    /// The files the command reads: `--measurements` and `--sample-at`.
    pub fn inputs(&self) -> Vec<PathBuf> {
        self.measurements
            .iter()
            .chain(&self.sample_at)
            .cloned()
            .collect()
    }
}

impl FileArgs {
    /// The file input, or `None` without `--measurements`.
    pub fn input(&self) -> Option<FileInput> {
        self.measurements.as_ref().map(|path| FileInput {
            path: path.clone(),
            format: self.input_format,
            angles: self.angles,
            quantity: self.quantity,
            sample_at: self.sample_at.clone(),
            specular_tolerance: Some(self.specular_tolerance),
        })
    }
}

/// Channels of a measurement file.
#[derive(Args, Debug, Clone)]
pub struct ChannelArgs {
    /// Channels of --measurements to use, comma-separated (default: every value column).
    #[arg(long, value_delimiter = ',', requires = "measurements")]
    pub channels: Option<Vec<String>>,
}

/// The jobs of a measurement file, else of a CUReT directory, else the
/// built-in synthetic scene.
pub fn jobs(
    file: &FileArgs,
    channels: &ChannelArgs,
    curet: &CuretArgs,
) -> Result<Vec<Job>, CliError> {
    if let Some(input) = file.input() {
        return input.jobs(channels.channels.as_deref());
    }
    if file.sample_at.is_some() {
        return Err(UsageError::SampleAtWithoutMerl.into());
    }
    Ok(curet.jobs()?.unwrap_or_else(synthetic_jobs))
}

/// The search grid of the layered models, and with the free objective the
/// box every estimate and interval stays in.
#[derive(Args, Debug, Clone)]
pub struct GridArgs {
    /// σ/T axis `start:stop:count`, `start:stop:count:log` or one value
    /// (free: 0.02:20:40:log; paper: 0.12:4.04:50).
    #[arg(long, value_parser = Axis::parse, allow_hyphen_values = true)]
    pub slope: Option<Axis>,
    /// β axis (free: 0:1, solved in closed form, so only its range is used;
    /// paper: 0.01:1:100).
    #[arg(long, value_parser = Axis::parse, allow_hyphen_values = true)]
    pub beta: Option<Axis>,
    /// n axis (free: 1:2.5:11; paper: 1.3:1.5:11).
    #[arg(long, value_parser = Axis::parse, allow_hyphen_values = true)]
    pub n: Option<Axis>,
    /// a axis (free: 0:1:21; paper: 0:1:101).
    #[arg(long, value_parser = Axis::parse, allow_hyphen_values = true)]
    pub a: Option<Axis>,
}

impl GridArgs {
    /// The axes given, by their parameter.
    pub fn axes(&self) -> Vec<(Param, Axis)> {
        [
            (Param::Slope, &self.slope),
            (Param::Beta, &self.beta),
            (Param::N, &self.n),
            (Param::A, &self.a),
        ]
        .into_iter()
        .filter_map(|(p, axis)| Some((p, axis.clone()?)))
        .collect()
    }

    /// The default grid of `objective` with the given axes replaced,
    /// validated ([`Settings::grid`]).
    pub fn grid(&self, objective: Objective) -> Result<laminar_brdf_fit::Grid, CliError> {
        let settings = Settings {
            objective,
            axes: self.axes(),
            ..Settings::default()
        };
        Ok(settings.grid()?)
    }
}

/// Worker threads.
#[derive(Args, Debug, Clone)]
pub struct ThreadArgs {
    /// Worker threads (default: all cores). Results do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
}

/// The search path.
#[derive(Args, Debug, Clone)]
pub struct PathArgs {
    /// Search path of the paper objective METHOD-ARITH: METHOD
    /// direct|onepass|envelope, ARITH f32x8|f32|f64.
    #[arg(long, default_value_t = SearchPath::DEFAULT)]
    pub path: SearchPath,
}

/// On or off.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Switch {
    /// On.
    On,
    /// Off.
    Off,
}

/// The objective a fit minimises (docs/conventions.md §4, §4b).
#[derive(Args, Debug, Clone)]
pub struct ObjectiveArgs {
    /// free: weighted least squares Σ w (D − c·M)² with a free amplitude
    /// c ≥ 0, M eq. 8's raw mix (β of eq. 8, solved with c in closed form),
    /// w = 1/σ² from sigma columns (else 1), everything inside the box the
    /// axes give. paper: the paper's objective, data and model each divided
    /// by their max (what `reproduce` uses).
    #[arg(long, default_value_t = Objective::Free, value_parser = parse_objective)]
    pub objective: Objective,
    /// The free objective's grid stage (layered models): f64, or f32 (each
    /// grid point's model terms in f32x8 lanes; the refinement and
    /// intervals still in f64; docs/speed.md gives its measured effect).
    #[arg(long, default_value_t = Precision::F64, value_parser = parse_precision)]
    pub precision: Precision,
    /// The free objective's noise model, how each measurement is weighted:
    /// given (the file's uncertainties, known; else equal weights), equal
    /// (equal weights, whatever the file gives), relative (σ ∝ the value
    /// above a floor, as a goniometer's noise; the scale estimated).
    /// docs/conventions.md §4b.
    #[arg(long, default_value = "given", value_parser = parse_noise)]
    pub noise: Noise,
    /// The floor of relative noise: σ_k ∝ √(D_k² + (f·m)²), f this
    /// fraction (0, 1] and m the median positive value; it keeps clipped
    /// zeros from infinite weights.
    #[arg(long, default_value_t = DEFAULT_FLOOR, allow_negative_numbers = true)]
    pub noise_floor: f64,
}

fn parse_noise(s: &str) -> Result<Noise, UnknownName> {
    Noise::named(s, DEFAULT_FLOOR)
}

fn parse_precision(s: &str) -> Result<Precision, UnknownName> {
    s.parse()
}

fn parse_objective(s: &str) -> Result<Objective, UnknownName> {
    s.parse()
}

/// What each fit does after its grid search (docs/conventions.md §11, §11b).
#[derive(Args, Debug, Clone)]
pub struct AnalysisArgs {
    /// Refine the best grid point: free objective, Levenberg–Marquardt from
    /// the grid's basins inside the box; paper objective, Nelder–Mead from
    /// the best grid point and other basins within the model's domain.
    /// Intervals of the free objective need it.
    #[arg(long, value_enum, default_value_t = Switch::On)]
    pub refine: Switch,
    /// Uncertainty of each parameter: profile (68%/95% intervals from the
    /// profile of the objective), jacobian (sd and correlations from
    /// the Jacobian at the refined optimum, when no bound is active), both
    /// (free objective: the robust interval, the profile's calibrated by the
    /// sandwich covariance, as the headline), bootstrap (both, and a pairs
    /// bootstrap's percentile intervals as the headline), or off.
    #[arg(long, default_value = "both", value_parser = parse_uncertainty)]
    pub uncertainty: Uncertainty,
    /// Resamples of the bootstrap (`--uncertainty bootstrap`), 2 to 100000.
    #[arg(long, default_value = "200", allow_hyphen_values = true, value_parser = parse_resamples)]
    pub resamples: usize,
    /// Seed of the bootstrap's resamples and of the cross-validation's
    /// folds: the same seed, the same intervals and errors.
    #[arg(long, default_value = "0", allow_hyphen_values = true, value_parser = parse_seed)]
    pub seed: u64,
    /// Folds of the cross-validation of each model when several are fitted
    /// (0 for none, else 2 to 100).
    #[arg(long, default_value = "5", allow_hyphen_values = true, value_parser = parse_folds)]
    pub folds: usize,
}

fn parse_folds(s: &str) -> Result<usize, String> {
    laminar_brdf_fit::analysis::parse_folds(s)
}

fn parse_resamples(s: &str) -> Result<usize, String> {
    laminar_brdf_fit::analysis::parse_resamples(s)
}

fn parse_seed(s: &str) -> Result<u64, String> {
    laminar_brdf_fit::analysis::parse_seed(s)
}

fn parse_uncertainty(s: &str) -> Result<Uncertainty, UnknownName> {
    s.parse()
}

impl AnalysisArgs {
    /// The analysis asked for.
    pub fn analysis(&self) -> Analysis {
        Analysis {
            refine: self.refine == Switch::On,
            uncertainty: self.uncertainty,
            resamples: self.resamples,
            seed: self.seed,
            folds: self.folds,
        }
    }
}

/// The options every fitting command takes: the search path, the threads,
/// the grid, the objective and the analysis (`fit`, `fit-batch`).
#[derive(Args, Debug)]
pub struct FitterArgs {
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
}

impl FitterArgs {
    /// The fitter these options describe.
    pub fn fitter(&self) -> Result<Fitter, CliError> {
        let floor = self.objective.noise_floor;
        let settings = Settings {
            objective: self.objective.objective,
            precision: self.objective.precision,
            noise: match self.objective.noise {
                Noise::Relative { .. } => Noise::Relative { floor },
                noise => noise,
            },
            noise_floor: floor,
            ..settings(&self.grid, &self.threads, self.path.path, &self.analysis)
        };
        Ok(settings.fitter()?)
    }
}

/// The settings of the grid, threads, search path and analysis given, the
/// others (the objective, the grid stage's precision) at their defaults.
pub fn settings(
    grid: &GridArgs,
    threads: &ThreadArgs,
    path: SearchPath,
    analysis: &AnalysisArgs,
) -> Settings {
    Settings {
        axes: grid.axes(),
        path,
        analysis: analysis.analysis(),
        threads: threads.threads,
        ..Settings::default()
    }
}

/// Sets the global thread pool (for work outside a [`Fitter`]).
pub fn global_threads(threads: &ThreadArgs) -> Result<(), CliError> {
    if let Some(t) = threads.threads {
        if !(1..=laminar_brdf_fit::fit::MAX_THREADS).contains(&t) {
            return Err(UsageError::Threads {
                given: t,
                most: laminar_brdf_fit::fit::MAX_THREADS,
            }
            .into());
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build_global()
            .map_err(UsageError::from)?;
    }
    Ok(())
}

/// A progress bar on stderr when it is a terminal.
pub fn progress(len: u64, what: &str) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(len);
    bar.set_style(
        ProgressStyle::with_template(
            "{msg} [{bar:40}] {pos}/{len} {elapsed_precise} eta {eta} ({per_sec})",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_message(what.to_string());
    bar
}

/// A progress counter for an unknown total (on a terminal only).
pub fn counter(what: &str) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new_spinner();
    bar.set_style(
        ProgressStyle::with_template("{msg} {pos} {elapsed_precise} ({per_sec})")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    bar.set_message(what.to_string());
    bar
}

/// What a command's throughput counts.
pub const PAIRS: &str = "(parameter set, measurement) pairs";

/// Prints elapsed time and throughput (`count` `unit` per second) on stderr.
pub fn report_time(command: &str, start: Instant, count: f64, unit: &str) {
    let secs = start.elapsed().as_secs_f64();
    laminar_brdf::note!(
        "{command}: {secs:.3} s elapsed, {:.3e} {unit}/s",
        count / secs.max(1e-9)
    );
}

/// Checks `--out` before any work: it is none of the command's `inputs`
/// ([`laminar_brdf_io::check_not_an_input`]) and its directory accepts a file.
pub fn check_out(out: Option<&PathBuf>, inputs: &[PathBuf]) -> Result<(), CliError> {
    if let Some(p) = out {
        laminar_brdf_io::check_not_an_input(p, inputs)?;
        laminar_brdf_io::check_writable(p)?;
    }
    Ok(())
}

/// The files a CUReT directory `dir` is read from: `table.txt` and the BRDF
/// files (`brdf`, as given and inside `dir`; by default the four that
/// [`laminar_brdf_io::curet::CuretDir::brdf_files`] looks for).
pub fn curet_inputs(dir: &Path, brdf: &[PathBuf]) -> Vec<PathBuf> {
    let mut inputs = vec![dir.join("table.txt")];
    if brdf.is_empty() {
        inputs.extend(
            laminar_brdf_io::curet::Channel::ALL
                .iter()
                .map(|c| dir.join(c.file_name())),
        );
    }
    for b in brdf {
        inputs.push(b.clone());
        inputs.push(dir.join(b));
    }
    inputs
}

/// The formats the commands write, by the extension that names each.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputFormat {
    /// Comma-separated values.
    Csv,
    /// JSON (the fitted-model file, a batch's results).
    Json,
    /// A Markdown table.
    Markdown,
    /// A PNG image.
    Png,
    /// A MERL binary BRDF.
    Merl,
}

impl OutputFormat {
    const ALL: [OutputFormat; 5] = [Self::Csv, Self::Json, Self::Markdown, Self::Png, Self::Merl];

    /// Its name in messages.
    fn name(self) -> &'static str {
        match self {
            Self::Csv => "CSV",
            Self::Json => "JSON",
            Self::Markdown => "Markdown",
            Self::Png => "PNG",
            Self::Merl => "MERL",
        }
    }

    /// The extensions that name it, the usual one first.
    fn extensions(self) -> &'static [&'static str] {
        match self {
            Self::Csv => &["csv"],
            Self::Json => &["json"],
            Self::Markdown => &["md", "markdown"],
            Self::Png => &["png"],
            Self::Merl => &["binary"],
        }
    }

    /// The format an extension names, if any (also images a command does
    /// not write, so `--out a.jpg` is caught).
    fn named_by(extension: &str) -> Option<&'static str> {
        let e = extension.to_ascii_lowercase();
        if let Some(f) = Self::ALL
            .into_iter()
            .find(|f| f.extensions().contains(&e.as_str()))
        {
            return Some(f.name());
        }
        match e.as_str() {
            "jpg" | "jpeg" => Some("JPEG"),
            "exr" => Some("OpenEXR"),
            "tif" | "tiff" => Some("TIFF"),
            "txt" => Some("text"),
            "zarr" => Some("Zarr"),
            _ => None,
        }
    }
}

/// Refuses an output whose extension names another format than `writes`
/// (`render --out a.jpg`, `fit --format json --out fits.csv`); a name
/// with no extension, or one no format claims, is taken as given.
///
/// # Errors
/// [`UsageError::OutExtension`] naming the file and both formats.
pub fn check_extension(out: &Path, writes: OutputFormat) -> Result<(), UsageError> {
    let Some(extension) = out.extension().and_then(|e| e.to_str()) else {
        return Ok(());
    };
    let lower = extension.to_ascii_lowercase();
    match OutputFormat::named_by(&lower) {
        Some(named) if !writes.extensions().contains(&lower.as_str()) => {
            Err(UsageError::OutExtension {
                out: out.to_path_buf(),
                named,
                writes: writes.name(),
                extension: writes.extensions()[0],
            })
        }
        _ => Ok(()),
    }
}

/// Writes `text` to `out` (whole or not at all), or prints it.
pub fn emit(out: Option<&PathBuf>, text: &str) -> Result<(), CliError> {
    match out {
        Some(path) => laminar_brdf_io::write_atomic(path, text)?,
        None => print!("{text}"),
    }
    Ok(())
}
