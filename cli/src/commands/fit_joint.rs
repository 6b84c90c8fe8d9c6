//! `laminar fit-joint`: one fit across a material's channels.

use super::options::{
    check_out, emit, jobs, layered_model, report_time, ChannelArgs, CuretArgs, FileArgs, FitterArgs,
};
use clap::Args;
use laminar_brdf::figures::{channels_vs_model_svg, spectrum_svg, SpectrumPoint};
use laminar_brdf::usage::UsageError;
use laminar_brdf::CliError;
use laminar_brdf_fit::{ChannelTest, JointFit, JointValue, Model, Scene, Variant};
use laminar_brdf_io::fits::{json_materials, MaterialEntry};
use std::path::PathBuf;
use std::time::Instant;

/// Fit one model across each sample's channels: σ/T, σ′/T′ (the untied
/// models) and n shared by every channel, a, β and the amplitude per
/// channel (docs/conventions.md §4c).
///
/// Input as `fit`: a measurement file (--measurements, its channels or
/// --channels), a CUReT directory (r, g, b per sample), or the built-in
/// scene (one channel: refused). The channels of a sample must share their
/// geometry. The free objective, with --noise (relative for goniometer
/// data) and the box of the axes; intervals are the percentile intervals
/// of a pairs bootstrap over the geometries (--resamples, --seed; none
/// with --uncertainty off), the same geometries resampled in every
/// channel.
///
/// CSV, one row per channel: sample, model, channel, then each shared
/// parameter and a with _lo68, _hi68, _lo95, _hi95, then beta (eq. 8's),
/// amplitude (of the data divided by their max), data_scale (that max),
/// sse (the channel's weighted objective), runs_p and lack_of_fit (the
/// adequacy of its residuals at the joint estimate, as `fit`'s), cv_rms
/// (sqrt(Σ w r²/K) of its residuals on held-out geometries: --folds
/// folds, the same in every channel, each refitted without its fold and
/// predicted with that fit's amplitude and β; empty with --folds 0) and
/// in_sample_rms (the same of the joint fit's own residuals), joint_sse
/// (their sum), measurements (per channel), parameters (fitted in all), resamples,
/// chromatic_p (the p-value of one a for every channel: Hotelling's T² of
/// the contrasts a_c − a_1 with the bootstrap's covariance) or
/// chromatic_note (why it is not tested: an a on a face of its box, too
/// few resamples), roughness_p (the p-value of one σ/T for every channel,
/// untied models: a robust score test at the joint estimate, each
/// geometry's score over every channel, Hotelling's T² over the
/// geometries) or roughness_note, delta_aicc_joint, delta_aicc_roughness_per_channel and
/// delta_aicc_separate (each variant's AICc above the best variant's, over
/// all channels' measurements with one noise scale: this joint fit, σ/T
/// per channel with σ′/T′ and n shared (untied models, made with the
/// roughness test), each channel fitted alone; empty where not fitted)
/// and best_variant (the lowest's name), and edges (an interval that reaches a face of the box
/// that is not a bound of the parameter: name:open_below or
/// name:open_above).
#[derive(Args, Debug)]
#[command(verbatim_doc_comment)]
pub struct FitJointArgs {
    #[command(flatten)]
    file: FileArgs,
    #[command(flatten)]
    channels: ChannelArgs,
    #[command(flatten)]
    curet: CuretArgs,
    /// The layered model fitted (exp2 and gauss2 free σ′/T′).
    #[arg(long, default_value = "exp2", value_parser = layered_model())]
    model: Model,
    #[command(flatten)]
    fitting: FitterArgs,
    /// Write the CSV to FILE instead of stdout.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Also write the fitted materials to FILE, a fitted-model file (JSON):
    /// one material per sample, its shared parameters once, each channel's
    /// own and its fitted model, selected as `sample/channel/model` by
    /// predict, render, export and the renderers (Python's
    /// `FittedModel.from_material` takes the whole material).
    #[arg(long)]
    fits: Option<PathBuf>,
    /// Also draw the absorption spectrum a(λ) with its 68% and 95% bands,
    /// and β(λ), into FILE (SVG; one sample). The x axis is the wavelength
    /// when every channel is named by one (`450nm`, `532`), else the
    /// channel's place.
    #[arg(long)]
    plot: Option<PathBuf>,
    /// Also draw data against model per channel into FILE (SVG; one
    /// sample): log–log, each channel's normalised data against its
    /// prediction at the joint estimate.
    #[arg(long)]
    plot_fit: Option<PathBuf>,
}

/// Runs `laminar fit-joint`.
pub fn run(args: &FitJointArgs) -> Result<(), CliError> {
    let start = Instant::now();
    let inputs: Vec<PathBuf> = args.file.measurements.iter().cloned().collect();
    check_out(args.out.as_ref(), &inputs)?;
    check_out(args.plot.as_ref(), &inputs)?;
    check_out(args.plot_fit.as_ref(), &inputs)?;
    check_out(args.fits.as_ref(), &inputs)?;
    let fitter = args.fitting.fitter()?;
    let jobs = jobs(&args.file, &args.channels, &args.curet)?;
    // Each sample's channels, in the order read.
    let mut samples: Vec<Vec<Scene>> = Vec::new();
    for job in jobs {
        match samples.last_mut() {
            Some(last) if last[0].sample() == job.scene.sample() => last.push(job.scene),
            _ => samples.push(vec![job.scene]),
        }
    }
    let fits = samples
        .iter()
        .map(|scenes| fitter.fit_joint(scenes, args.model))
        .collect::<Result<Vec<JointFit>, _>>()?;
    if args.plot.is_some() || args.plot_fit.is_some() {
        let ([fit], [scenes]) = (&fits[..], &samples[..]) else {
            return Err(UsageError::PlotOfSamples(fits.len()).into());
        };
        if let Some(plot) = &args.plot {
            emit(Some(plot), &spectrum(fit).map_err(CliError::Figure)?)?;
        }
        if let Some(plot) = &args.plot_fit {
            emit(Some(plot), &against_model(fit, scenes)?)?;
        }
    }
    if let Some(path) = &args.fits {
        let materials: Vec<MaterialEntry> = fits.iter().map(MaterialEntry::new).collect();
        emit(Some(path), &json_materials(&materials))?;
    }
    emit(args.out.as_ref(), &csv(&fits))?;
    report_time("fit-joint", start, fits.len() as f64, "samples");
    Ok(())
}

/// The wavelength (nm) a channel is named by: its leading number
/// (`450nm`, `532`), when it has one.
fn wavelength(channel: &str) -> Option<f64> {
    let end = channel
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(channel.len());
    channel[..end].parse().ok().filter(|w: &f64| *w > 0.0)
}

/// The spectrum figure of `fit`: a(λ) with its bands, and β(λ).
fn spectrum(fit: &JointFit) -> Result<String, String> {
    let named: Option<Vec<f64>> = fit
        .channels
        .iter()
        .map(|c| wavelength(&c.channel))
        .collect();
    let (xs, x_desc, names) = match named {
        Some(xs) => (xs, "wavelength (nm)", Vec::new()),
        None => {
            let names: Vec<String> = fit.channels.iter().map(|c| c.channel.clone()).collect();
            let xs = (0..names.len()).map(|i| i as f64).collect();
            (xs, "channel", names)
        }
    };
    let point = |x: f64, v: &JointValue| SpectrumPoint {
        x,
        value: v.value,
        bands: v
            .intervals
            .map(|[i68, i95]| [(i68.lo, i68.hi), (i95.lo, i95.hi)]),
    };
    let mut series = Vec::new();
    let a: Option<Vec<SpectrumPoint>> = (fit.channels.iter().zip(&xs))
        .map(|(c, &x)| c.a.as_ref().map(|a| point(x, a)))
        .collect();
    if let Some(a) = a {
        series.push(("absorption a", a));
    }
    let beta = (fit.channels.iter().zip(&xs))
        .map(|(c, &x)| SpectrumPoint {
            x,
            value: c.beta,
            bands: None,
        })
        .collect();
    series.push(("β (eq. 8)", beta));
    let shared: Vec<String> = (fit.shared.iter())
        .map(|v| format!("{} = {:.3}", v.name.symbol(), v.value))
        .collect();
    let title = format!("{} {}: {}", fit.sample, fit.model, shared.join(", "));
    spectrum_svg(&title, (x_desc, &names), &series)
}

/// The data-against-model figure of `fit` on its channels `scenes`.
fn against_model(fit: &JointFit, scenes: &[Scene]) -> Result<String, CliError> {
    let panels = (scenes.iter().enumerate())
        .map(|(c, scene)| {
            let fitted = fit.fitted(c).ok_or_else(|| {
                CliError::Figure(format!("channel {} has no fitted model", scene.channel()))
            })?;
            let model = fitted.predict(scene.angles())?;
            Ok((scene.channel().to_string(), scene.data().to_vec(), model))
        })
        .collect::<Result<Vec<_>, CliError>>()?;
    let title = format!(
        "{} {}: data against model per channel",
        fit.sample, fit.model
    );
    channels_vs_model_svg(&title, &panels).map_err(CliError::Figure)
}

/// The variants in the CSV's order.
const VARIANTS: [Variant; 3] = [
    Variant::Joint,
    Variant::RoughnessPerChannel,
    Variant::Separate,
];

/// Each variant's AICc above the best's (empty where it was not fitted),
/// then the best variant's name.
fn variant_cells(fit: &JointFit) -> Vec<String> {
    let rank = |variant: Variant| {
        (fit.variants.iter())
            .find(|v| v.variant == variant)
            .and_then(|v| v.rank)
    };
    let mut cells: Vec<String> = (VARIANTS.iter())
        .map(|&v| rank(v).map(|r| number(r.delta)).unwrap_or_default())
        .collect();
    let best = VARIANTS
        .into_iter()
        .find(|&v| rank(v).is_some_and(|r| r.rank == 1));
    cells.push(best.map(|v| v.name().to_string()).unwrap_or_default());
    cells
}

/// A number as the shortest text that reads back to it, with an exponent
/// where it is very small or large (`1.27e-34`, not 34 zeros).
fn number(x: f64) -> String {
    format!("{x:?}")
}

/// A value and its intervals as five cells (empty where absent).
fn cells(v: &JointValue, row: &mut Vec<String>, edges: &mut Vec<String>) {
    row.push(number(v.value));
    match v.intervals {
        Some([i68, i95]) => {
            row.extend([i68.lo, i68.hi, i95.lo, i95.hi].map(number));
            if i95.open_below {
                edges.push(format!("{}:open_below", v.name));
            }
            if i95.open_above {
                edges.push(format!("{}:open_above", v.name));
            }
        }
        None => row.extend(std::iter::repeat_n(String::new(), 4)),
    }
}

/// A test's two cells (the chromatic test's on `a`, the shared
/// roughness's on `slope`): its p-value, and why there is none.
fn channel_test(test: &ChannelTest, parameter: &str) -> [String; 2] {
    match test {
        ChannelTest::Tested { p_value, .. } => [number(*p_value), String::new()],
        ChannelTest::AtAFace(channels) => [
            String::new(),
            format!("{parameter} on a face of its box in {}", channels.join(" ")),
        ],
        ChannelTest::Untestable(why) => [String::new(), why.to_string()],
    }
}

/// The CSV of `fits` (header from the first fit's parameters).
fn csv(fits: &[JointFit]) -> String {
    let Some(first) = fits.first() else {
        return String::new();
    };
    let mut header: Vec<String> = ["sample", "model", "channel"].map(String::from).to_vec();
    let names = first
        .shared
        .iter()
        .chain(first.channels[0].a.as_ref())
        .map(|v| v.name);
    for name in names {
        header.push(name.to_string());
        header.extend(["lo68", "hi68", "lo95", "hi95"].map(|s| format!("{name}_{s}")));
    }
    header.extend(
        [
            "beta",
            "amplitude",
            "data_scale",
            "sse",
            "runs_p",
            "lack_of_fit",
            "cv_rms",
            "in_sample_rms",
            "joint_sse",
            "measurements",
            "parameters",
            "resamples",
            "chromatic_p",
            "chromatic_note",
            "roughness_p",
            "roughness_note",
        ]
        .map(String::from),
    );
    header.extend(VARIANTS.map(|v| format!("delta_aicc_{}", v.name())));
    header.extend(["best_variant", "edges"].map(String::from));
    let mut out = header.join(",") + "\n";
    for fit in fits {
        for channel in &fit.channels {
            let mut row = vec![
                fit.sample.clone(),
                fit.model.to_string(),
                channel.channel.clone(),
            ];
            let mut edges = Vec::new();
            for v in fit.shared.iter().chain(channel.a.as_ref()) {
                cells(v, &mut row, &mut edges);
            }
            row.extend(
                [
                    channel.beta,
                    channel.amplitude,
                    channel.data_scale,
                    channel.sse,
                ]
                .map(number),
            );
            let adequacy = &channel.adequacy;
            row.push(adequacy.runs_p.map(number).unwrap_or_default());
            row.push(adequacy.lack_of_fit.to_string());
            for v in channel
                .cross_validation
                .map_or([None; 2], |cv| [Some(cv.rms), Some(cv.in_sample)])
            {
                row.push(v.map(number).unwrap_or_default());
            }
            row.push(number(fit.sse));
            row.extend(
                [fit.measurements, fit.parameter_count, fit.resamples].map(|x| x.to_string()),
            );
            row.extend(channel_test(&fit.chromatic, "a"));
            row.extend(channel_test(&fit.shared_roughness, "slope"));
            row.extend(variant_cells(fit));
            row.push(edges.join(";"));
            out += &(row.join(",") + "\n");
        }
    }
    out
}
