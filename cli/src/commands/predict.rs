//! `laminar predict`: a fitted model's normalised prediction anywhere.

use super::options::{check_extension, check_out, emit, report_time, OutputFormat};
use super::select::FitFileArgs;
use clap::Args;
use laminar_brdf::selection::{FileInput, InputFormat};
use laminar_brdf::usage::UsageError;
use laminar_brdf::CliError;
use laminar_brdf_core::{rms_error, Angles};
use laminar_brdf_fit::{MeasurementSet, Quantity, Scene};
use laminar_brdf_io::curet::{Channel, CuretDir};
use laminar_brdf_io::{read_geometry, AngleUnit, ReadError};
use std::path::PathBuf;
use std::time::Instant;

/// Print a fitted model's normalised prediction (and residuals where data is given).
///
/// Columns: row (the geometry's row in its file), theta_i, theta_s, phi_s
/// (paper frame, radians), prediction = P, the normalised prediction the fit
/// compared with its data: (β L^sb/m_sb + (1−β) L^sf/m_sf)/m_mix with the
/// fit's own normalisation constants (baselines: L/m). With data (from
/// --measurements or --data): data = D, the measured radiance (BRDF·cos θi)
/// divided by its max over the non-specular measurements, and residual = D − P;
/// Δ_RMS (eq. 15) = 100·sqrt(Σ(D−P)²)/K is printed on stderr. On the fit's own
/// measurements it reproduces the fit's Δ_RMS (the refined one when the fit
/// was refined: the file's fitted model is then the refined model).
#[derive(Args, Debug)]
#[command(verbatim_doc_comment)]
pub struct PredictArgs {
    #[command(flatten)]
    fit: FitFileArgs,
    /// Geometries only (no data): CSV with columns theta_i,theta_s,phi_s or
    /// theta_i,phi_i,theta_v,phi_v; every row is predicted.
    #[arg(long, conflicts_with_all = ["measurements", "data"])]
    geometry: Option<PathBuf>,
    /// Measurement file (CSV, or MERL with --sample-at): the channel named like the fit's
    /// (or the only channel) is compared with the prediction.
    #[arg(long, conflicts_with = "data")]
    measurements: Option<PathBuf>,
    /// Format of --measurements (default: from the extension).
    #[arg(long, value_enum, requires = "measurements")]
    input_format: Option<InputFormat>,
    /// What the values in --measurements are.
    #[arg(long, default_value_t = Quantity::Brdf)]
    quantity: Quantity,
    /// Geometries to sample a MERL --measurements file at.
    #[arg(long, requires = "measurements")]
    sample_at: Option<PathBuf>,
    /// Channel of --measurements to compare (default: the fit's channel, or the only one).
    #[arg(long, requires = "measurements")]
    channel: Option<String>,
    /// Unit of the angles in CSV files.
    #[arg(long, default_value_t = AngleUnit::Radians)]
    angles: AngleUnit,
    /// CUReT directory: the fit's sample is read from the BRDF file of the fit's channel.
    #[arg(long)]
    data: Option<PathBuf>,
    /// CUReT BRDF file to read instead of the channel's (with --data).
    #[arg(long, requires = "data")]
    brdf: Option<PathBuf>,
    /// Write the CSV to FILE (whole or not at all) instead of stdout.
    #[arg(long)]
    out: Option<PathBuf>,
}

/// The scene of the fit's channel in a measurement set.
fn scene_of(
    set: &MeasurementSet,
    channel: &str,
    file: &std::path::Path,
) -> Result<Scene, CliError> {
    let names = set.channel_names();
    let name = if names.contains(&channel) {
        channel.to_string()
    } else if names.len() == 1 {
        names[0].to_string()
    } else {
        return Err(UsageError::NoChannel {
            file: file.to_path_buf(),
            channel: channel.to_string(),
            channels: names.iter().map(|n| n.to_string()).collect(),
        }
        .into());
    };
    set.scene(&name).map_err(|source| {
        CliError::Read(ReadError::Measurements {
            file: file.to_path_buf(),
            source,
        })
    })
}

/// Runs `laminar predict`.
pub fn run(args: &PredictArgs) -> Result<(), CliError> {
    let start = Instant::now();
    let mut inputs = vec![args.fit.file.clone()];
    inputs.extend(
        [&args.geometry, &args.measurements, &args.sample_at]
            .into_iter()
            .flatten()
            .cloned(),
    );
    if let Some(dir) = &args.data {
        inputs.extend(super::options::curet_inputs(dir, args.brdf.as_slice()));
    }
    check_out(args.out.as_ref(), &inputs)?;
    if let Some(out) = &args.out {
        check_extension(out, OutputFormat::Csv)?;
    }
    let sel = args.fit.selected()?;
    let (rows, angles, data): (Vec<usize>, Vec<Angles>, Option<Vec<f64>>) =
        if let Some(path) = &args.geometry {
            let angles = read_geometry(path, args.angles)?
                .iter()
                .enumerate()
                .map(|(k, g)| {
                    g.paper().map_err(|source| UsageError::Geometry {
                        file: path.clone(),
                        row: k + 1,
                        source,
                    })
                })
                .collect::<Result<Vec<_>, _>>()?;
            ((1..=angles.len()).collect(), angles, None)
        } else {
            let scene = if let Some(path) = &args.measurements {
                let input = FileInput {
                    path: path.clone(),
                    format: args.input_format,
                    angles: args.angles,
                    quantity: args.quantity,
                    sample_at: args.sample_at.clone(),
                    specular_tolerance: None,
                };
                let channel = args.channel.as_deref().unwrap_or(&sel.channel);
                scene_of(&input.read()?, channel, path)?
            } else if let Some(dir) = &args.data {
                let curet = CuretDir::open(dir)?;
                let file = args.brdf.clone().unwrap_or_else(|| {
                    let c = Channel::ALL
                        .into_iter()
                        .find(|c| c.name() == sel.channel)
                        .unwrap_or(Channel::Avg);
                    PathBuf::from(c.file_name())
                });
                let sample: u32 = sel
                    .sample
                    .parse()
                    .map_err(|_| UsageError::NotCuretSample(sel.sample.clone()))?;
                let s = curet.samples(&[file], Some(&[sample]))?.remove(0);
                scene_of(&s.set, s.channel.name(), &s.file)?
            } else {
                return Err(UsageError::NothingToPredictAt.into());
            };
            (
                scene.rows().to_vec(),
                scene.angles().to_vec(),
                Some(scene.data().to_vec()),
            )
        };
    let prediction = sel
        .fitted
        .predict(&angles)
        .map_err(|source| args.fit.model_error(&sel.label, source))?;
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut header = vec!["row", "theta_i", "theta_s", "phi_s", "prediction"];
    if data.is_some() {
        header.extend(["data", "residual"]);
    }
    let io = |source: csv::Error| CliError::Output { to: "CSV", source };
    w.write_record(&header).map_err(io)?;
    for (k, (a, p)) in angles.iter().zip(&prediction).enumerate() {
        let mut rec = vec![
            rows[k].to_string(),
            a.theta_i().to_string(),
            a.theta_s().to_string(),
            a.phi_s().to_string(),
            format!("{p:e}"),
        ];
        if let Some(d) = &data {
            rec.push(format!("{:e}", d[k]));
            rec.push(format!("{:e}", d[k] - p));
        }
        w.write_record(&rec).map_err(io)?;
    }
    let bytes = w.into_inner().map_err(|e| io(e.into_error().into()))?;
    emit(args.out.as_ref(), &String::from_utf8_lossy(&bytes))?;
    if let Some(d) = &data {
        let rms = rms_error(d, &prediction).unwrap_or(f64::NAN);
        let own = sel
            .rms
            .map(|r| format!(" (the fit's own: {r:e})"))
            .unwrap_or_default();
        laminar_brdf::note!(
            "predict {}: Δ_RMS (eq. 15) = {rms:e} over {} measurements{own}",
            sel.label,
            d.len(),
        );
    }
    report_time("predict", start, angles.len() as f64, "geometries");
    Ok(())
}
