//! `laminar export`: a fitted model tabulated as a MERL file.

use super::options::{check_extension, check_out, report_time, OutputFormat};
use super::select::FitFileArgs;
use clap::Args;
use laminar_brdf::usage::UsageError;
use laminar_brdf::CliError;
use laminar_brdf_fit::MeasurementAngles;
use laminar_brdf_io::merl::{write_merl, Merl, PLANE};
use std::path::PathBuf;
use std::time::Instant;

/// Tabulate a fitted model as a MERL isotropic BRDF file (.binary).
///
/// Every bin of the 90 × 90 × 180 table holds the model's BRDF at the bin's
/// centre in index space: P · data_scale / cos θi, P the normalised
/// prediction and data_scale the max the fit's measured radiance was divided
/// by, so the table is in the units of the fitted data. The same value goes
/// to the red, green and blue planes (each divided by its MERL scale); bins
/// below the horizon hold −1 (not measured).
#[derive(Args, Debug)]
#[command(verbatim_doc_comment)]
pub struct ExportArgs {
    #[command(flatten)]
    fit: FitFileArgs,
    /// The MERL file to write.
    #[arg(long)]
    merl: PathBuf,
}

/// Runs `laminar export`.
pub fn run(args: &ExportArgs) -> Result<(), CliError> {
    let start = Instant::now();
    check_out(Some(&args.merl), std::slice::from_ref(&args.fit.file))?;
    check_extension(&args.merl, OutputFormat::Merl)?;
    let sel = args.fit.selected()?;
    // The parameters were validated by the selection: the per-bin
    // evaluations can then only fail by a value that is not finite, which
    // is kept and refused before anything is written (MERL's -1 marks a bin
    // without data, not an overflow).
    let overflow: std::cell::Cell<Option<(f64, f64, f64)>> = std::cell::Cell::new(None);
    let table = Merl::tabulate(|theta_i, phi_i, theta_v, phi_v| {
        let g = MeasurementAngles::Lab {
            theta_i,
            phi_i,
            theta_v,
            phi_v,
        };
        let brdf = match g.paper() {
            Ok(a) => match sel.fitted.predict_radiance(&[a]) {
                Ok(r) => r[0] / theta_i.cos(),
                Err(_) => f64::INFINITY,
            },
            Err(_) => -1.0,
        };
        if !brdf.is_finite() && overflow.get().is_none() {
            overflow.set(Some((theta_i, theta_v, phi_v - phi_i)));
        }
        [brdf; 3]
    });
    if let Some((theta_i, theta_v, phi)) = overflow.get() {
        return Err(UsageError::ExportOverflow {
            fits: args.fit.file.clone(),
            label: sel.label,
            theta_i,
            theta_v,
            phi,
            out: args.merl.clone(),
        }
        .into());
    }
    write_merl(&args.merl, &table)?;
    laminar_brdf::note!(
        "export: {} tabulated into {} ({} bins per channel)",
        sel.label,
        args.merl.display(),
        PLANE
    );
    report_time("export", start, PLANE as f64, "bins");
    Ok(())
}
