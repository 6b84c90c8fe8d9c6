//! `laminar fit-batch`: many measurement sets on one geometry.

use super::options::{
    check_out, emit, fitter, progress, report_time, GridArgs, PathArgs, ThreadArgs, PAIRS,
};
use clap::Args;
use laminar_cli::CliError;
use laminar_fit::{MeasurementSet, Model, Quantity, Scene};
use laminar_io::values::read_values;
use laminar_io::{fits, read_geometry, AngleUnit, ReadError};
use std::path::PathBuf;
use std::time::Instant;

/// Sets fitted per batch search (bounds memory; the progress bar counts sets).
const BLOCK: usize = 64;

/// Fit many measurement sets that share one geometry (every sample of a
/// database, every pixel of a texture) with one batch search per block.
///
/// VALUES is an N × K array: N sets (rows), K measurements each in the
/// order of GEOMETRY's rows; `.npy` (float32 or float64, little-endian,
/// C order) or CSV (N lines of K numbers). Output: `fit`'s CSV columns (or
/// its JSON fitted-model file, by the extension of --out), with `sample` the
/// row index in VALUES (from 0) and `channel` `value`. Results are bit for
/// bit those of fitting each set alone.
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
    /// Models, comma-separated: exp, gauss, rh-exp, rh-gauss, jensen, oren-nayar (default: exp).
    #[arg(long, value_delimiter = ',', default_value = "exp")]
    models: Vec<Model>,
    #[command(flatten)]
    path: PathArgs,
    #[command(flatten)]
    threads: ThreadArgs,
    #[command(flatten)]
    grid: GridArgs,
    /// Results file: .csv (fit's columns) or .json (the fitted-model file).
    #[arg(long)]
    out: PathBuf,
}

/// Runs `laminar fit-batch`.
pub fn run(args: &FitBatchArgs) -> Result<(), CliError> {
    let start = Instant::now();
    let json = match args.out.extension().and_then(|e| e.to_str()) {
        Some("json") => true,
        Some("csv") => false,
        _ => {
            return Err(CliError::Usage(format!(
                "{}: --out must end in .csv or .json",
                args.out.display()
            )))
        }
    };
    check_out(Some(&args.out))?;
    let fitter = fitter(&args.grid, &args.threads, args.path.path)?;
    let geometry = read_geometry(&args.geometry, args.angles)?;
    let values = read_values(&args.values)?;
    if values.cols != geometry.len() {
        return Err(CliError::Usage(format!(
            "{} has {} values per set but {} has {} geometries",
            args.values.display(),
            values.cols,
            args.geometry.display(),
            geometry.len()
        )));
    }
    let scene = |row: usize| -> Result<Scene, CliError> {
        let wrap = |source| {
            CliError::Read(ReadError::Measurements {
                file: args.values.clone(),
                source,
            })
        };
        MeasurementSet::new(row.to_string(), geometry.clone(), args.quantity)
            .and_then(|s| s.with_channel("value", values.row(row).to_vec(), None))
            .and_then(|s| s.scene("value"))
            .map_err(wrap)
    };
    let bar = progress(values.rows as u64, "fit-batch (sets)");
    let mut by_model: Vec<Vec<laminar_fit::Fit>> = args.models.iter().map(|_| Vec::new()).collect();
    let mut pairs = 0.0;
    for block in (0..values.rows).collect::<Vec<_>>().chunks(BLOCK) {
        let scenes = block
            .iter()
            .map(|&r| scene(r))
            .collect::<Result<Vec<_>, _>>()?;
        for (m, &model) in args.models.iter().enumerate() {
            let fits = fitter.fit_batch(&scenes, model);
            pairs += fits
                .iter()
                .map(|f| f.evaluated as f64 * f.measurements as f64)
                .sum::<f64>();
            by_model[m].extend(fits);
        }
        bar.inc(block.len() as u64);
    }
    bar.finish_and_clear();
    let records: Vec<laminar_fit::Fit> = (0..values.rows)
        .flat_map(|row| by_model.iter().map(move |fits| fits[row].clone()))
        .collect();
    let text = if json {
        fits::json(&records)
    } else {
        fits::csv(&records)
    };
    emit(Some(&args.out), &text)?;
    let secs = start.elapsed().as_secs_f64();
    eprintln!(
        "fit-batch: {} sets × {} models, {:.1} sets/s",
        values.rows,
        args.models.len(),
        values.rows as f64 / secs.max(1e-9)
    );
    report_time("fit-batch", start, pairs, PAIRS);
    Ok(())
}
