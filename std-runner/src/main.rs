//! `laminar`: fit, check and reproduce the absorptive scattering model.

use clap::{Args, Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use laminar_core::{components, Angles, Components, Correlation, Geometry, Params};
use laminar_runner::fit::{fit, FitRecord};
use laminar_runner::grid::{Axis, Grid};
use laminar_runner::model::Model;
use laminar_runner::search::{error_surface, Path as SearchPath};
use laminar_runner::selection::{jobs, parse_samples, Job, PAPER_SAMPLES};
use laminar_runner::{report, reproduce};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

#[derive(Parser)]
#[command(
    name = "laminar",
    version,
    about = "Fit measured BRDF data with the absorptive scattering model for rough laminar surfaces (Dahlan & Hancock 2016)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Fit models by exhaustive grid search (default: the built-in synthetic scene).
    Fit {
        #[command(flatten)]
        select: Select,
        /// Output format.
        #[arg(long, value_enum, default_value_t = Format::Csv)]
        format: Format,
        /// Write the output to FILE (whole or not at all) instead of stdout.
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Evaluate every grid value with the SIMD path and the scalar path and compare bits.
    Parity {
        #[command(flatten)]
        select: Select,
    },
    /// Evaluate the model at given geometries (radians), un-normalised, as CSV.
    Eval(EvalArgs),
    /// Reports on the search paths.
    #[command(subcommand)]
    Report(ReportKind),
    /// Reproduce the paper's experiment: Tables II–V (Markdown, CSV) and figures (SVG).
    Reproduce {
        #[command(flatten)]
        select: Select,
        /// Output directory (created if missing).
        #[arg(long)]
        out: PathBuf,
    },
}

#[derive(Subcommand)]
enum ReportKind {
    /// Every search path on the selected fits (exp and gauss): pairs/s, speed-up
    /// and error against the f64 reference, as a Markdown table.
    SpeedVsError {
        #[command(flatten)]
        select: Select,
        /// σ/T values of the grid slice the direct paths run on.
        #[arg(long, default_value_t = 1)]
        direct_slopes: usize,
        /// Also write the table to FILE.
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

#[derive(Args)]
struct Select {
    /// Directory with table.txt and CUReT BRDF files [env: CURET_DIR]. Without it: the built-in synthetic scene.
    #[arg(long, env = "CURET_DIR")]
    data: Option<PathBuf>,
    /// BRDF files to read (default: every abrdf/rbrdf/gbrdf/bbrdf.dat in --data).
    #[arg(long, num_args = 1..)]
    brdf: Vec<PathBuf>,
    /// Samples: comma-separated numbers or `all` (default: the paper's 13).
    #[arg(long)]
    samples: Option<String>,
    /// Models, comma-separated: exp, gauss, rh-exp, rh-gauss, jensen,
    /// oren-nayar (default: all six; `fit` and `parity` only).
    #[arg(long, value_delimiter = ',')]
    models: Option<Vec<Model>>,
    /// Search path METHOD-ARITH: direct|onepass|envelope - f32x8|f32|f64
    /// (default: envelope-f32x8; not for `report`, which runs every path).
    /// `parity` compares the f32x8 and f32 twins of its method.
    #[arg(long)]
    path: Option<SearchPath>,
    /// Worker threads (default: all cores). Results do not depend on it.
    #[arg(long)]
    threads: Option<usize>,
    /// σ/T axis `start:stop:count` (paper: 0.12:4.04:50).
    #[arg(long, value_parser = Axis::parse)]
    slope: Option<Axis>,
    /// β axis (paper: 0.01:1:100).
    #[arg(long, value_parser = Axis::parse)]
    beta: Option<Axis>,
    /// n axis (paper: 1.3:1.5:11).
    #[arg(long, value_parser = Axis::parse)]
    n: Option<Axis>,
    /// a axis (paper: 0:1:101).
    #[arg(long, value_parser = Axis::parse)]
    a: Option<Axis>,
}

impl Select {
    /// `--models`, or all six.
    fn models(&self) -> Vec<Model> {
        self.models.clone().unwrap_or_else(|| Model::ALL.to_vec())
    }

    /// `--path`, or the default path.
    fn path(&self) -> SearchPath {
        self.path.unwrap_or(SearchPath::DEFAULT)
    }

    /// An error when an option the command does not use was given.
    fn reject(&self, command: &str, models: bool, path: bool) -> Result<(), String> {
        if models && self.models.is_some() {
            return Err(format!(
                "{command} fits a fixed set of models (see --help); --models is not accepted"
            ));
        }
        if path && self.path.is_some() {
            return Err(format!(
                "{command} runs every search path; --path is not accepted"
            ));
        }
        Ok(())
    }

    fn grid(&self) -> Result<Grid, String> {
        let mut g = Grid::paper();
        for (axis, given) in [
            (&mut g.slope, &self.slope),
            (&mut g.beta, &self.beta),
            (&mut g.n, &self.n),
            (&mut g.a, &self.a),
        ] {
            if let Some(v) = given {
                *axis = v.clone();
            }
        }
        g.validate()?;
        Ok(g)
    }

    fn jobs(&self) -> Result<Vec<Job>, String> {
        let samples = match &self.samples {
            Some(s) => parse_samples(s)?,
            None => Some(PAPER_SAMPLES.to_vec()),
        };
        jobs(self.data.as_deref(), &self.brdf, samples.as_deref())
    }

    fn setup(&self) -> Result<(Grid, Vec<Job>), String> {
        if let Some(t) = self.threads {
            if t == 0 {
                return Err("--threads must be at least 1".into());
            }
            rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build_global()
                .map_err(|e| e.to_string())?;
        }
        Ok((self.grid()?, self.jobs()?))
    }
}

#[derive(Clone, Copy, ValueEnum)]
enum Format {
    Csv,
    Json,
    Markdown,
}

#[derive(Clone, Copy, ValueEnum)]
enum Precision {
    F32,
    F64,
}

#[derive(Args)]
struct EvalArgs {
    /// Layered model: exp, gauss, rh-exp or rh-gauss.
    #[arg(long)]
    model: Model,
    /// RMS slope σ/T.
    #[arg(long)]
    slope: f64,
    /// Balance β.
    #[arg(long)]
    beta: f64,
    /// Refractive index n.
    #[arg(long)]
    n: f64,
    /// Absorption a (forced to 0 for rh-*).
    #[arg(long, default_value_t = 0.0)]
    a: f64,
    /// Arithmetic precision.
    #[arg(long, value_enum, default_value_t = Precision::F64)]
    precision: Precision,
    /// CSV file with columns theta_i,theta_s,phi_s (radians, header line).
    #[arg(long, conflicts_with_all = ["theta_i", "theta_s", "phi_s"])]
    geometry: Option<PathBuf>,
    /// Incident zenith θi.
    #[arg(
        long,
        required_unless_present = "geometry",
        allow_negative_numbers = true
    )]
    theta_i: Option<f64>,
    /// Scattering zenith θs.
    #[arg(
        long,
        required_unless_present = "geometry",
        allow_negative_numbers = true
    )]
    theta_s: Option<f64>,
    /// Scattering azimuth φs.
    #[arg(
        long,
        required_unless_present = "geometry",
        allow_negative_numbers = true
    )]
    phi_s: Option<f64>,
}

/// A progress bar on stderr when it is a terminal.
fn progress(len: u64, what: &str) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(len);
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} {elapsed_precise} eta {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_message(what.to_string());
    bar
}

fn shards(model: Model, grid: &Grid) -> u64 {
    if model.correlation().is_some() {
        grid.slope.len() as u64
    } else {
        1
    }
}

fn report_time(command: &str, start: Instant, pairs: f64) {
    let secs = start.elapsed().as_secs_f64();
    eprintln!(
        "{command}: {secs:.3} s elapsed, {:.3e} (parameter set, measurement) pairs/s",
        pairs / secs.max(1e-9)
    );
}

fn run_fits(select: &Select) -> Result<(Vec<FitRecord>, f64), String> {
    let (grid, jobs) = select.setup()?;
    let total: u64 = jobs.len() as u64
        * select
            .models()
            .iter()
            .map(|&m| shards(m, &grid))
            .sum::<u64>();
    let bar = progress(total, "fit");
    let mut records = Vec::new();
    let mut pairs = 0.0;
    for job in &jobs {
        for &model in &select.models() {
            let r = fit(job, model, &grid, select.path(), &|| bar.inc(1));
            pairs += r.evaluated as f64 * r.measurements as f64;
            records.push(r);
        }
    }
    bar.finish_and_clear();
    Ok((records, pairs))
}

fn cmd_fit(select: &Select, format: Format, out: Option<&PathBuf>) -> Result<(), String> {
    let start = Instant::now();
    let (records, pairs) = run_fits(select)?;
    let text = match format {
        Format::Csv => report::csv(&records),
        Format::Json => report::json(&records),
        Format::Markdown => report::markdown(&records),
    };
    match out {
        Some(path) => report::write_atomic(path, &text)
            .map_err(|e| format!("{}: cannot write: {e}", path.display()))?,
        None => print!("{text}"),
    }
    if select.data.is_none() {
        let (s, b, n, a) = laminar_runner::synthetic::TRUE_PARAMS;
        eprintln!(
            "synthetic scene: true parameters slope={s};beta={b};n={n};a={a} (exp model, noise σ = {})",
            laminar_runner::synthetic::NOISE
        );
    }
    report_time("fit", start, pairs);
    Ok(())
}

fn cmd_parity(select: &Select) -> Result<bool, String> {
    let start = Instant::now();
    let (grid, jobs) = select.setup()?;
    let (mut same, mut all) = (0usize, 0usize);
    let mut pairs = 0.0;
    for job in &jobs {
        for &model in &select.models() {
            let Some(corr) = model.correlation() else {
                continue;
            };
            let g = if model.is_ragheb_hancock() {
                grid.ragheb_hancock()
            } else {
                grid.clone()
            };
            let (simd_path, scalar_path) = select.path().twins();
            let simd = error_surface(&job.scene, &g, corr, simd_path);
            let scalar = error_surface(&job.scene, &g, corr, scalar_path);
            let equal = simd
                .iter()
                .zip(&scalar)
                .filter(|(a, b)| a.to_bits() == b.to_bits())
                .count();
            println!(
                "sample {} channel {} model {} ({simd_path} vs {scalar_path}): {equal} of {} grid values identical",
                job.sample,
                job.channel.name(),
                model.name(),
                simd.len()
            );
            same += equal;
            all += simd.len();
            pairs += 2.0 * g.size() as f64 * job.scene.len() as f64;
        }
    }
    println!("parity: {same} of {all} grid values identical");
    report_time("parity", start, pairs);
    Ok(same == all)
}

fn cmd_speed(select: &Select, direct_slopes: usize, out: Option<&PathBuf>) -> Result<(), String> {
    let start = Instant::now();
    select.reject("report speed-vs-error (exp and gauss)", true, true)?;
    let (grid, jobs) = select.setup()?;
    let runs = jobs.len() as u64 * 2 * SearchPath::all().len() as u64;
    let bar = progress(runs, "speed-vs-error");
    let report = laminar_runner::speed::speed_vs_error(&jobs, &grid, direct_slopes, &|what| {
        if what.ends_with("reference") {
            bar.set_message(what.to_string());
        } else {
            bar.inc(1);
        }
    });
    bar.finish_and_clear();
    let text = report.markdown();
    print!("{text}");
    if let Some(path) = out {
        report::write_atomic(path, &text)
            .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
    }
    let pairs: f64 = jobs.iter().map(|j| j.scene.len() as f64).sum::<f64>() * grid.size() as f64;
    report_time("report speed-vs-error", start, pairs * 2.0);
    Ok(())
}

fn cmd_reproduce(select: &Select, out: &std::path::Path) -> Result<(), String> {
    let start = Instant::now();
    select.reject("reproduce", true, false)?;
    if select.data.is_none() {
        return Err(
            "reproduce needs --data DIR (or CURET_DIR) with table.txt and abrdf.dat".into(),
        );
    }
    let (grid, jobs) = select.setup()?;
    let total = jobs.len() as u64
        * reproduce::FITTED
            .iter()
            .map(|&m| shards(m, &grid))
            .sum::<u64>();
    let bar = progress(total, "reproduce");
    let r = reproduce::reproduce(&jobs, &grid, select.path(), out, &|| bar.inc(1))?;
    bar.finish_and_clear();
    eprintln!(
        "reproduce: {} fits of {} jobs, {} files written to {}",
        r.records.len(),
        jobs.len(),
        r.files.len(),
        out.display()
    );
    report_time("reproduce", start, r.pairs);
    Ok(())
}

fn read_geometry_csv(path: &PathBuf) -> Result<Vec<Angles>, String> {
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_path(path)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let mut out = Vec::new();
    for (i, rec) in reader.records().enumerate() {
        let line = i + 2;
        let rec = rec.map_err(|e| format!("{}:{line}: {e}", path.display()))?;
        if rec.len() != 3 {
            return Err(format!(
                "{}:{line}: expected 3 columns theta_i,theta_s,phi_s, found {}",
                path.display(),
                rec.len()
            ));
        }
        let mut v = [0.0; 3];
        for (c, slot) in v.iter_mut().enumerate() {
            *slot = rec[c].parse::<f64>().map_err(|_| {
                format!(
                    "{}:{line}: column {}: `{}` is not a number",
                    path.display(),
                    c + 1,
                    &rec[c]
                )
            })?;
        }
        out.push(
            Angles::new(v[0], v[1], v[2]).map_err(|e| format!("{}:{line}: {e}", path.display()))?,
        );
    }
    if out.is_empty() {
        return Err(format!("{}: no geometry rows", path.display()));
    }
    Ok(out)
}

fn cmd_eval(args: &EvalArgs) -> Result<(), String> {
    let start = Instant::now();
    let corr: Correlation = args.model.correlation().ok_or_else(|| {
        format!(
            "eval supports exp, gauss, rh-exp and rh-gauss, not {}",
            args.model
        )
    })?;
    let a = if args.model.is_ragheb_hancock() {
        0.0
    } else {
        args.a
    };
    let p = Params::new(args.slope, args.beta, args.n, a).map_err(|e| e.to_string())?;
    let angles = match &args.geometry {
        Some(path) => read_geometry_csv(path)?,
        None => vec![Angles::new(
            args.theta_i.unwrap_or_default(),
            args.theta_s.unwrap_or_default(),
            args.phi_s.unwrap_or_default(),
        )
        .map_err(|e| e.to_string())?],
    };
    let mut w = csv::Writer::from_writer(std::io::stdout());
    let header = ["theta_i", "theta_s", "phi_s"]
        .into_iter()
        .chain(Components::<f64>::NAMES);
    w.write_record(header).map_err(|e| e.to_string())?;
    for g in &angles {
        let v: [f64; 7] = match args.precision {
            Precision::F64 => components(&Geometry::<f64>::splat(g), corr, &p).to_array(),
            Precision::F32 => components(&Geometry::<f32>::splat(g), corr, &p)
                .to_array()
                .map(f64::from),
        };
        let mut rec = vec![
            g.theta_i().to_string(),
            g.theta_s().to_string(),
            g.phi_s().to_string(),
        ];
        rec.extend(v.iter().map(|x| format!("{x:e}")));
        w.write_record(&rec).map_err(|e| e.to_string())?;
    }
    w.flush().map_err(|e| e.to_string())?;
    report_time("eval", start, angles.len() as f64);
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Fit {
            select,
            format,
            out,
        } => cmd_fit(select, *format, out.as_ref()).map(|_| true),
        Command::Parity { select } => cmd_parity(select),
        Command::Eval(args) => cmd_eval(args).map(|_| true),
        Command::Report(ReportKind::SpeedVsError {
            select,
            direct_slopes,
            out,
        }) => cmd_speed(select, *direct_slopes, out.as_ref()).map(|_| true),
        Command::Reproduce { select, out } => cmd_reproduce(select, out).map(|_| true),
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
