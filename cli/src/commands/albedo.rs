//! `laminar albedo`: a fitted model's directional albedo over view angles.

use super::options::{check_extension, check_out, emit, report_time, OutputFormat};
use super::select::FitFileArgs;
use clap::Args;
use laminar_brdf::usage::UsageError;
use laminar_brdf::CliError;
use laminar_brdf_fit::albedo::{albedo_table, Tolerance};
use laminar_brdf_fit::Axis;
use std::path::PathBuf;
use std::time::Instant;

/// Print a fitted model's directional albedo ρ(θv) = ∫ f cos θi dωi.
///
/// The integral of the fitted prediction (P · data_scale = f · cos θi, in
/// the units of the fitted data) over the light's hemisphere, by
/// Gauss–Legendre rules in cos θi and φs, doubled until two agree to
/// --tolerance (docs/conventions.md §12). Columns: theta_v (degrees),
/// albedo, error (the last two rules' difference), nodes (per dimension),
/// above_one (1 where albedo > 1). `above_one` means a gain of energy only
/// when the fitted data were a BRDF in absolute units (sr⁻¹); for data on
/// an arbitrary scale (CUReT, a camera's counts) the albedo carries that
/// scale and no bound applies.
#[derive(Args, Debug)]
#[command(verbatim_doc_comment)]
pub struct AlbedoArgs {
    #[command(flatten)]
    fit: FitFileArgs,
    /// View angles θv in degrees, `start:stop:count` (within [0, 90]).
    #[arg(long, value_parser = Axis::parse, default_value = "0:85:18")]
    theta_v: Axis,
    /// Relative agreement of two successive quadrature rules, from 1e-12
    /// up to (not including) 1.
    #[arg(long, default_value = "1e-6", value_parser = parse_tolerance)]
    tolerance: Tolerance,
    /// Write the CSV to FILE (whole or not at all) instead of stdout.
    #[arg(long)]
    out: Option<PathBuf>,
}

/// `--tolerance`, by the library's rule ([`Tolerance::new`]).
fn parse_tolerance(text: &str) -> Result<Tolerance, String> {
    let value: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a number"))?;
    Tolerance::new(value).map_err(|e| e.to_string())
}

/// Runs `laminar albedo`.
pub fn run(args: &AlbedoArgs) -> Result<(), CliError> {
    let start = Instant::now();
    check_out(args.out.as_ref(), std::slice::from_ref(&args.fit.file))?;
    if let Some(out) = &args.out {
        check_extension(out, OutputFormat::Csv)?;
    }
    if let Some(bad) = args
        .theta_v
        .values
        .iter()
        .find(|t| !(0.0..=90.0).contains(*t))
    {
        return Err(UsageError::ThetaV(*bad).into());
    }
    let sel = args.fit.selected()?;
    let radians: Vec<f64> = args.theta_v.values.iter().map(|t| t.to_radians()).collect();
    let table = albedo_table(&sel.fitted, &radians, args.tolerance)
        .map_err(|source| args.fit.model_error(&sel.label, source))?;
    let mut text = String::from("theta_v,albedo,error,nodes,above_one\n");
    for (row, degrees) in table.iter().zip(&args.theta_v.values) {
        text += &format!(
            "{degrees},{:.9e},{:.3e},{},{}\n",
            row.albedo,
            row.error,
            row.nodes,
            u8::from(row.albedo > 1.0)
        );
    }
    emit(args.out.as_ref(), &text)?;
    let most = table.iter().map(|r| r.albedo).fold(0.0, f64::max);
    laminar_brdf::note!(
        "albedo: {}: max ρ(θv) = {most:.6} in the fitted data's units{}",
        sel.label,
        if most > 1.0 {
            " (above 1: more energy out than in, if those units are an absolute BRDF in sr⁻¹)"
        } else {
            ""
        }
    );
    report_time("albedo", start, table.len() as f64, "view angles");
    Ok(())
}
