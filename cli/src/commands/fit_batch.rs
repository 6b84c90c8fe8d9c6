//! `laminar fit-batch`: many measurement sets on one geometry.

use super::options::{any_model, check_out, counter, progress, report_time, FitterArgs, PAIRS};
use clap::Args;
use laminar_brdf::usage::UsageError;
use laminar_brdf::CliError;
use laminar_brdf_fit::{MeasurementSet, Model, Quantity, Scene};
use laminar_brdf_io::values::ValueRows;
use laminar_brdf_io::{fits, read_geometry, AngleUnit, AtomicFile, ReadError};
use std::path::PathBuf;
use std::time::Instant;

/// Sets read and fitted per batch search: memory holds one block of sets
/// (and, for JSON output, every record), whatever N is.
const BLOCK: usize = 256;

fn io_error(file: &std::path::Path, e: std::io::Error) -> CliError {
    CliError::Read(ReadError::io(file, "write", e))
}

/// Fit many measurement sets that share one geometry (every sample of a
/// database, every pixel of a texture), a block at a time: under the free
/// objective (the default, as `fit`) the sets of a block share the grid
/// stage's model side; under --objective paper one batch search per block.
///
/// VALUES is an N × K array: N sets (rows), K measurements each in the
/// order of GEOMETRY's rows; `.npy` (float32 or float64, little-endian,
/// C order) or CSV (N lines of K numbers). Output, by the extension of
/// --out: CSV of numbers, one row per set and model: `set` (the row in
/// VALUES, from 0), `model`, then the batch fields that Python's
/// `laminar.fit_batch` and the Dask/xarray results hold (docs/formats.md);
/// or JSON, `fit`'s fitted-model file (sample = the row, channel `value`).
/// Results are bit for bit those of fitting each set alone.
#[derive(Args, Debug)]
#[command(verbatim_doc_comment)]
pub struct FitBatchArgs {
    /// Geometry of the K measurements: CSV with columns
    /// theta_i,phi_i,theta_v,phi_v (or theta_i,theta_s,phi_s).
    #[arg(long)]
    geometry: PathBuf,
    /// Unit of the angles in --geometry.
    #[arg(long, default_value_t = AngleUnit::Radians)]
    angles: AngleUnit,
    /// The N × K values (.npy or .csv).
    #[arg(long)]
    values: PathBuf,
    /// What the values are: brdf (fitted as BRDF·cos θi) or radiance.
    #[arg(long, default_value_t = Quantity::Brdf)]
    quantity: Quantity,
    /// Models, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "exp", value_parser = any_model())]
    models: Vec<Model>,
    #[command(flatten)]
    fitting: FitterArgs,
    /// Results file: .csv (the batch fields) or .json (the fitted-model file).
    #[arg(long)]
    out: PathBuf,
}

/// Runs `laminar fit-batch`.
pub fn run(args: &FitBatchArgs) -> Result<(), CliError> {
    let start = Instant::now();
    let json = match args.out.extension().and_then(|e| e.to_str()) {
        Some("json") => true,
        Some("csv") => false,
        _ => return Err(UsageError::BatchOutExtension(args.out.clone()).into()),
    };
    check_out(
        Some(&args.out),
        &[args.values.clone(), args.geometry.clone()],
    )?;
    let fitter = args.fitting.fitter()?;
    let geometry = read_geometry(&args.geometry, args.angles)?;
    let mut values = ValueRows::open(&args.values)?;
    if values.cols() != geometry.len() {
        return Err(UsageError::ValuesAgainstGeometry {
            values: args.values.clone(),
            per_set: values.cols(),
            geometry: args.geometry.clone(),
            geometries: geometry.len(),
        }
        .into());
    }
    let scene = |row: usize, set: Vec<f64>| -> Result<Scene, CliError> {
        let wrap = |source| {
            CliError::Read(ReadError::Measurements {
                file: args.values.clone(),
                source,
            })
        };
        MeasurementSet::new(row.to_string(), geometry.clone(), args.quantity)
            .and_then(|s| s.with_channel("value", set, None))
            .and_then(|s| s.scene("value"))
            .map_err(wrap)
    };
    let bar = match values.rows() {
        Some(n) => progress(n as u64, "fit-batch (sets)"),
        None => counter("fit-batch (sets)"),
    };
    // Records are written as each block is fitted (CSV rows, or the JSON
    // document's fits one by one), into a temporary file renamed into place
    // at the end: memory stays flat whatever the number of sets.
    let file = AtomicFile::create(&args.out)?;
    let mut out = if json {
        Records::Json(fits::JsonFits::new(file).map_err(|e| io_error(&args.out, e))?)
    } else {
        Records::Csv(Box::new(
            fits::BatchCsv::new(file, &args.models).map_err(|e| io_error(&args.out, e))?,
        ))
    };
    let (mut pairs, mut done) = (0.0, 0);
    loop {
        let block = values.next_rows(BLOCK)?;
        if block.is_empty() {
            break;
        }
        let scenes = block
            .into_iter()
            .enumerate()
            .map(|(i, set)| scene(done + i, set))
            .collect::<Result<Vec<_>, _>>()?;
        // Set-major, each set's models ranked (Fitter::fit_all).
        let fits = fitter.fit_all(&scenes, &args.models, |_, _| None)?;
        for (i, fit) in fits.iter().enumerate() {
            pairs += fit.evaluated as f64 * fit.measurements as f64;
            out.write(done + i / args.models.len(), fit)
                .map_err(|e| io_error(&args.out, e))?;
        }
        done += scenes.len();
        bar.inc(scenes.len() as u64);
    }
    bar.finish_and_clear();
    out.finish().map_err(|e| io_error(&args.out, e))?.commit()?;
    let secs = start.elapsed().as_secs_f64();
    laminar_brdf::note!(
        "fit-batch: {done} sets × {} models, {:.1} sets/s",
        args.models.len(),
        done as f64 / secs.max(1e-9)
    );
    report_time("fit-batch", start, pairs, PAIRS);
    Ok(())
}

/// Where `fit-batch` writes its records, one at a time.
enum Records {
    /// Boxed: the CSV writer holds its buffers inline.
    Csv(Box<fits::BatchCsv<AtomicFile>>),
    Json(fits::JsonFits<AtomicFile>),
}

impl Records {
    /// Writes `fit`, a fit of the `set`-th row of the values.
    fn write(&mut self, set: usize, fit: &laminar_brdf_fit::Fit) -> std::io::Result<()> {
        match self {
            Self::Csv(out) => out.write(set, fit),
            Self::Json(out) => out.write(fit),
        }
    }

    /// The file, complete, to commit.
    fn finish(self) -> std::io::Result<AtomicFile> {
        match self {
            Self::Csv(out) => out.into_inner(),
            Self::Json(out) => out.finish(),
        }
    }
}
