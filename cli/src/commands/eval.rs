//! `laminar eval`: the model's raw terms at given geometries.

use super::options::{layered_model, report_time};
use clap::{Args, ValueEnum};
use laminar_brdf::usage::UsageError;
use laminar_brdf::CliError;
use laminar_brdf_core::{components, Angles, Components, Geometry, Params};
use laminar_brdf_fit::Model;
use laminar_brdf_io::{read_geometry, AngleUnit};
use std::path::PathBuf;
use std::time::Instant;

/// Arithmetic precision of `eval`.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Precision {
    /// Scalar f32.
    F32,
    /// Scalar f64 (the reference).
    F64,
}

/// Evaluate the layered model's raw (un-normalised) terms at given geometries, as CSV.
///
/// Columns: theta_i, theta_s, phi_s (paper frame, radians), then
/// fresnel_in = f(θi, n), fresnel_out = f(θs′, 1/n) (eq. 6),
/// absorb_in = A1, absorb_out = A2 (eqs. 10, 11, 14),
/// surface = L^sf (eq. 1 or 2), subsurface = L^sb (eq. 12 or 13),
/// total = β L^sb + (1 − β) L^sf (eq. 8): radiance for unit incident
/// radiance with the constants k and K set to 1 (docs/conventions.md §2).
///
/// These are NOT the normalised predictions `fit` compares with data: `fit`
/// divides L^sf and L^sb each by its max over the measured geometries
/// before mixing with β, so a fitted β is not eq. 8's β. The fitted-model
/// file (`fit --format json`) gives beta_eq8 for eq. 8; `laminar predict`
/// prints the normalised prediction.
#[derive(Args, Debug)]
#[command(verbatim_doc_comment)]
pub struct EvalArgs {
    /// Layered model.
    #[arg(long, value_parser = layered_model())]
    model: Model,
    /// RMS slope σ/T, in [1e-3, 1e3].
    #[arg(long, allow_negative_numbers = true)]
    slope: f64,
    /// Subsurface RMS slope σ′/T′ of the untied models (exp2, gauss2), in
    /// [1e-3, 1e3]; the tied models take σ/T.
    #[arg(long, allow_negative_numbers = true)]
    sub_slope: Option<f64>,
    /// Balance β of eq. 8, in [0, 1].
    #[arg(long, allow_negative_numbers = true)]
    beta: f64,
    /// Refractive index n, in [1, 10].
    #[arg(long, allow_negative_numbers = true)]
    n: f64,
    /// Absorption a, in [0, 1] (must be 0 for rh-*).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    a: f64,
    /// Arithmetic precision.
    #[arg(long, value_enum, default_value_t = Precision::F64)]
    precision: Precision,
    /// CSV file of geometries, columns found by name: theta_i,theta_s,phi_s
    /// (paper frame) or theta_i,phi_i,theta_v,phi_v (lab frame, outward azimuths).
    #[arg(long, conflicts_with_all = ["theta_i", "theta_s", "phi_s"])]
    geometry: Option<PathBuf>,
    /// Unit of the angles in --geometry.
    #[arg(long, default_value_t = AngleUnit::Radians, requires = "geometry")]
    angles: AngleUnit,
    /// Incident polar angle θi (radians).
    #[arg(
        long,
        required_unless_present = "geometry",
        allow_negative_numbers = true
    )]
    theta_i: Option<f64>,
    /// Scattering polar angle θs (radians).
    #[arg(
        long,
        required_unless_present = "geometry",
        allow_negative_numbers = true
    )]
    theta_s: Option<f64>,
    /// Scattering azimuth φs (radians; 0 is the forward specular direction).
    #[arg(
        long,
        required_unless_present = "geometry",
        allow_negative_numbers = true
    )]
    phi_s: Option<f64>,
}

/// Runs `laminar eval`.
pub fn run(args: &EvalArgs) -> Result<(), CliError> {
    let start = Instant::now();
    let corr = args
        .model
        .correlation()
        .ok_or(UsageError::EvalModel(args.model))?;
    if args.model.is_ragheb_hancock() && args.a != 0.0 {
        return Err(UsageError::AbsorptionOfRaghebHancock {
            model: args.model,
            a: args.a,
        }
        .into());
    }
    let sub_slope = match (args.model.is_untied(), args.sub_slope) {
        (true, Some(sub)) => sub,
        (false, None) => args.slope,
        _ => return Err(UsageError::SubSlopeOfModel { model: args.model }.into()),
    };
    let p = Params::untied(args.slope, sub_slope, args.beta, args.n, args.a)
        .map_err(UsageError::from)?;
    let angles: Vec<Angles> = match &args.geometry {
        Some(path) => read_geometry(path, args.angles)?
            .iter()
            .enumerate()
            .map(|(k, g)| {
                g.paper().map_err(|source| UsageError::Geometry {
                    file: path.clone(),
                    row: k + 1,
                    source,
                })
            })
            .collect::<Result<_, _>>()?,
        None => vec![Angles::new(
            args.theta_i.unwrap_or_default(),
            args.theta_s.unwrap_or_default(),
            args.phi_s.unwrap_or_default(),
        )
        .map_err(UsageError::from)?],
    };
    let mut w = csv::Writer::from_writer(std::io::stdout());
    let header = ["theta_i", "theta_s", "phi_s"]
        .into_iter()
        .chain(Components::<f64>::NAMES);
    let io = |source: csv::Error| CliError::Output {
        to: "stdout",
        source,
    };
    w.write_record(header).map_err(io)?;
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
        w.write_record(&rec).map_err(io)?;
    }
    w.flush().map_err(|e| io(e.into()))?;
    report_time("eval", start, angles.len() as f64, "geometries");
    Ok(())
}
