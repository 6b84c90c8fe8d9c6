//! `laminar render`: a preview of fitted models, a lit sphere as a PNG.

use super::options::{check_extension, check_out, report_time, OutputFormat};
use super::select::FitFileArgs;
use clap::Args;
use laminar_brdf::usage::UsageError;
use laminar_brdf::CliError;
use laminar_brdf_fit::preview::{render, Stage, StageError};
use std::path::PathBuf;
use std::time::Instant;

/// Render a sphere of the fitted material as a PNG.
///
/// An orthographic view of a sphere under a directional light and a
/// constant environment (docs/conventions.md §12): the fitted prediction
/// lit by the light, plus the environment reflected with the model's
/// directional albedo. One --select gives a grey image; three (e.g. the r,
/// g and b fits of one sample) give its colour. One exposure for all
/// channels (the sphere's 99.5th percentile at 0.95), sRGB-encoded.
#[derive(Args, Debug)]
#[command(verbatim_doc_comment)]
pub struct RenderArgs {
    /// Fitted-model file (`laminar fit --format json --out FIT.json`).
    #[arg(long = "fit")]
    file: PathBuf,
    /// The fit of each channel, SAMPLE/CHANNEL/MODEL: once (grey) or three
    /// times (red, green, blue). May be left out when the file holds one fit.
    #[arg(long)]
    select: Vec<String>,
    /// The PNG to write (its name ends in .png).
    #[arg(long)]
    out: PathBuf,
    /// Image width and height in pixels (16 to 4096).
    #[arg(long, default_value_t = 256)]
    size: i64,
    /// The light's angle from the view axis, degrees (0 to 89; default 60).
    #[arg(long)]
    light_polar: Option<f64>,
    /// The light's direction in the image, degrees counter-clockwise from
    /// the right (default 135: the upper left).
    #[arg(long, allow_negative_numbers = true)]
    light_azimuth: Option<f64>,
    /// The environment's radiance, relative to the light's irradiance
    /// (default 0.05).
    #[arg(long)]
    environment: Option<f64>,
}

/// Runs `laminar render`.
pub fn run(args: &RenderArgs) -> Result<(), CliError> {
    let start = Instant::now();
    check_out(Some(&args.out), std::slice::from_ref(&args.file))?;
    check_extension(&args.out, OutputFormat::Png)?;
    let size = usize::try_from(args.size).map_err(|_| UsageError::Size(args.size))?;
    let scene =
        Stage::new(size, args.light_polar, args.light_azimuth, args.environment).map_err(|e| {
            match e {
                StageError::Size(_) => UsageError::Size(args.size),
                StageError::LightPolar(v) => UsageError::LightPolar(v),
                StageError::LightAzimuth(v) => UsageError::LightAzimuth(v),
                StageError::Environment(v) => UsageError::Environment(v),
            }
        })?;
    let selections: Vec<Option<String>> = match args.select.len() {
        0 => vec![None],
        1 | 3 => args.select.iter().cloned().map(Some).collect(),
        n => return Err(UsageError::SelectCount(n).into()),
    };
    let mut models = Vec::new();
    let mut labels = Vec::new();
    for select in selections {
        let fit = FitFileArgs {
            file: args.file.clone(),
            select,
        };
        let sel = fit.selected()?;
        models.push(sel.fitted);
        labels.push(sel.label);
    }
    let image = render(&models, &scene).map_err(|source| {
        CliError::Read(laminar_brdf_io::ReadError::Model {
            file: args.file.clone(),
            fit: labels.join(", "),
            source,
        })
    })?;
    let side = u32::try_from(args.size).unwrap_or(4096);
    laminar_brdf_io::image::write_png(&args.out, side, side, &image.to_srgb8())?;
    laminar_brdf::note!(
        "render: {} → {} ({} × {})",
        labels.join(", "),
        args.out.display(),
        args.size,
        args.size
    );
    report_time("render", start, (args.size * args.size) as f64, "pixels");
    Ok(())
}
