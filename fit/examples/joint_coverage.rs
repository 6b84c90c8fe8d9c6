//! Coverage of the joint fit's bootstrap intervals (`Fitter::fit_joint`):
//! three channels of one untied surface (`exp2`: σ/T 0.12, σ′/T′ 0.8,
//! n 1.5, β 0.3) whose absorption follows a colour (a 0.05, 0.35, 0.6), on
//! the Cornell gonioreflectometer's 1,439 geometries (`krylon_blue.astm`
//! under `CORNELL_DIR`; the 200 built-in ones without it), each value with
//! noise σ = `NOISE_FLOOR` (0.002 of the peak by default) + 5% of the
//! value, independent per channel. Fitted with the relative noise model
//! (`relative`, the default, with its `FLOOR`, the library's default
//! unless given) or with the true σ given (`given`). Per parameter, the
//! fraction of trials whose 68.27% and 95% intervals hold the truth, with
//! the 3σ binomial band of the nominal rate, the chromatic test's
//! rejections at 5% (it should reject: the absorption is chromatic) and
//! the shared-roughness test's (it should reject at 5%: σ/T is shared);
//! then
//! the same for each channel fitted alone (`Fitter::fit`, its headline
//! intervals), the shared parameters pooled over the channels. The table
//! of docs/conventions.md §4b. Run:
//! `cargo run --release -p laminar-brdf-fit --example joint_coverage -- [TRIALS] [RESAMPLES] [relative|given] [FLOOR] [NOISE_FLOOR]`

use laminar_brdf_core::Angles;
use laminar_brdf_fit::coverage::{band, noisy_scene_on, NoiseModel};
use laminar_brdf_fit::synthetic::{geometries, Noise as Rng};
use laminar_brdf_fit::{
    Analysis, ChannelTest, Fitter, Grid, Model, ModelParams, Noise, Objective, Param, Scene,
};
use std::path::Path;
use std::time::Instant;

/// The shared truth and each channel's a.
const SLOPE: f64 = 0.12;
const SUB_SLOPE: f64 = 0.8;
const N: f64 = 1.5;
const BETA: f64 = 0.3;
const A: [f64; 3] = [0.05, 0.35, 0.6];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let trials: usize = args.next().map_or(Ok(200), |a| a.parse())?;
    let resamples: usize = args.next().map_or(Ok(200), |a| a.parse())?;
    let weights = args.next();
    let floor: f64 = args
        .next()
        .map_or(Ok(laminar_brdf_fit::noise::DEFAULT_FLOOR), |a| a.parse())?;
    let truth_floor: f64 = args.next().map_or(Ok(0.002), |a| a.parse())?;
    let noise_model = match weights.as_deref() {
        None | Some("relative") => Noise::Relative { floor },
        Some("given") => Noise::Given,
        Some(other) => return Err(format!("weights `{other}`: give relative or given").into()),
    };
    let (label, angles) = geometry()?;
    let fitter = Fitter::new(Grid::user())?
        .objective(Objective::Free)
        .noise(noise_model)?
        .analysis(Analysis {
            resamples,
            ..Analysis::FULL
        });
    let noise = NoiseModel::Heteroscedastic {
        floor: truth_floor,
        relative: 0.05,
    };
    let names = ["σ/T", "σ′/T′", "n", "a (450)", "a (550)", "a (650)"];
    let truths = [SLOPE, SUB_SLOPE, N, A[0], A[1], A[2]];
    let mut covered = [[0usize; 2]; 6];
    // Per parameter, each trial's joint estimate and its 68.27% interval's
    // half width (on the log scale for the roughnesses).
    let mut spread: [Vec<(f64, f64)>; 6] = Default::default();
    // Each channel fitted alone: per parameter, (covered per level, fits).
    let mut alone = [([0usize; 2], 0usize); 6];
    let (mut chromatic, mut at_face, mut counted) = (0, 0, 0);
    // The shared-roughness test: rejections, tests made, tests not made.
    let mut roughness = (0, 0, 0);
    let start = Instant::now();
    for trial in 0..trials {
        let mut rng = Rng::new(7919 * trial as u64 + 1);
        let scenes: Vec<Scene> = A
            .iter()
            .zip(["450nm", "550nm", "650nm"])
            .map(|(&a, name)| {
                let truth = ModelParams::Layered {
                    slope: SLOPE,
                    beta: BETA,
                    n: N,
                    a,
                    sub_slope: Some(SUB_SLOPE),
                };
                noisy_scene_on(
                    angles.clone(),
                    Model::Exp2,
                    Objective::Free,
                    truth,
                    noise,
                    &mut rng,
                )
                .labelled("paint", name)
            })
            .collect();
        for (c, scene) in scenes.iter().enumerate() {
            let fit = fitter.fit(scene, Model::Exp2);
            for p in &fit.parameters {
                let i = match p.name {
                    Param::Slope => 0,
                    Param::SubSlope => 1,
                    Param::N => 2,
                    Param::A => 3 + c,
                    _ => continue,
                };
                alone[i].1 += 1;
                for (level, interval) in [p.interval68, p.interval95].into_iter().enumerate() {
                    if interval.is_some_and(|v| v.lo <= truths[i] && truths[i] <= v.hi) {
                        alone[i].0[level] += 1;
                    }
                }
            }
        }
        let joint = fitter.fit_joint(&scenes, Model::Exp2)?;
        let values = [Param::Slope, Param::SubSlope, Param::N]
            .map(|p| joint.shared.iter().find(|v| v.name == p).cloned());
        let a = joint.channels.iter().map(|c| c.a.clone());
        for (i, value) in values.into_iter().chain(a).enumerate() {
            let Some((estimate, [i68, i95])) = value.and_then(|v| Some((v.value, v.intervals?)))
            else {
                continue;
            };
            let t = |v: f64| if i < 2 { v.ln() } else { v };
            spread[i].push((t(estimate), 0.5 * (t(i68.hi) - t(i68.lo))));
            for (level, interval) in [i68, i95].into_iter().enumerate() {
                if interval.lo <= truths[i] && truths[i] <= interval.hi {
                    covered[i][level] += 1;
                }
            }
        }
        counted += 1;
        match joint.chromatic {
            ChannelTest::Tested { p_value, .. } if p_value < 0.05 => chromatic += 1,
            ChannelTest::AtAFace(_) => at_face += 1,
            _ => {}
        }
        // The data share their σ/T: every rejection is a false one.
        match joint.shared_roughness {
            ChannelTest::Tested { p_value, .. } => {
                roughness.1 += 1;
                if p_value < 0.05 {
                    roughness.0 += 1;
                }
            }
            _ => roughness.2 += 1,
        }
    }
    let seconds = start.elapsed().as_secs_f64();
    println!(
        "{counted} trials on {label} ({} geometries × 3 channels), weights: {}, {resamples} \
         resamples each, {seconds:.0} s ({:.2} s per joint fit)\n",
        angles.len(),
        match noise_model {
            Noise::Given => "the true σ, given",
            _ => "relative noise about the data",
        },
        seconds / counted.max(1) as f64
    );
    let (b68, b95) = (band(0.6827, counted), band(0.95, counted));
    if let Noise::Relative { floor } = noise_model {
        println!("Relative noise's floor: {floor} of the median positive value.");
    }
    println!("The data's noise: σ = {truth_floor} + 0.05 × value (the peak is 1).\n");
    println!(
        "3σ binomial bands: 68.27% [{:.3}, {:.3}], 95% [{:.3}, {:.3}] (✗ outside)\n",
        b68.0, b68.1, b95.0, b95.1
    );
    println!("| parameter | truth | 68.27% covered | 95% covered |");
    println!("|---|---|---|---|");
    for ((name, truth), hits) in names.iter().zip(truths).zip(covered) {
        println!("| {name} | {truth} | {} |", rates(hits, counted));
    }
    println!(
        "\nThe joint estimates over the trials (σ/T and σ′/T′ as ln): the spread of the \
         estimates (the sd, and 1.4826 × the median absolute deviation, robust to a few far \
         ones), the median's bias and the bootstrap's median 68.27% half width, both in units \
         of the robust spread:\n"
    );
    println!("| parameter | sd | robust spread | bias ÷ spread | half width ÷ spread |");
    println!("|---|---|---|---|---|");
    for ((name, truth), values) in names.iter().zip(truths).zip(&spread) {
        let t = if name.starts_with('σ') {
            truth.ln()
        } else {
            truth
        };
        let k = values.len().max(2) as f64;
        let mean = values.iter().map(|v| v.0).sum::<f64>() / k;
        let sd = (values.iter().map(|v| (v.0 - mean).powi(2)).sum::<f64>() / (k - 1.0)).sqrt();
        let estimates: Vec<f64> = values.iter().map(|v| v.0).collect();
        let centre = median(estimates.clone());
        let robust = 1.4826 * median(estimates.iter().map(|v| (v - centre).abs()).collect());
        let width = median(values.iter().map(|v| v.1).collect());
        println!(
            "| {name} | {sd:.4} | {robust:.4} | {:.2} | {:.2} |",
            (centre - t) / robust,
            width / robust
        );
    }
    println!(
        "\nEach channel fitted alone (`exp2`, the same noise model, its headline intervals):\n"
    );
    println!("| parameter | fits | 68.27% covered | 95% covered |");
    println!("|---|---|---|---|");
    for (name, (hits, fits)) in names.iter().zip(alone) {
        println!("| {name} | {fits} | {} |", rates(hits, fits));
    }
    println!(
        "\nChromatic test: rejected one a for all channels at 5% in {chromatic} of {counted} \
         trials ({at_face} not tested: an a on a face)."
    );
    let (lo, hi) = band(0.05, roughness.1);
    println!(
        "Shared-roughness test (true under these data): rejected one σ/T for all channels at 5% \
         in {} of {} tested trials ({:.3}; 3σ band [{lo:.3}, {hi:.3}]); {} not tested.",
        roughness.0,
        roughness.1,
        roughness.0 as f64 / roughness.1.max(1) as f64,
        roughness.2
    );
    Ok(())
}

/// The median of `values` (NaN for none).
fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied().unwrap_or(f64::NAN)
}

/// The 68.27% and 95% coverage rates of `hits` in `trials` as two table
/// cells, each marked ✗ outside the 3σ binomial band of its nominal rate.
fn rates([c68, c95]: [usize; 2], trials: usize) -> String {
    let cell = |hits: usize, nominal: f64| {
        let rate = hits as f64 / trials.max(1) as f64;
        let (lo, hi) = band(nominal, trials);
        let mark = if rate < lo || rate > hi { " ✗" } else { "" };
        format!("{rate:.3}{mark}")
    };
    format!("{} | {}", cell(c68, 0.6827), cell(c95, 0.95))
}

/// Cornell's `krylon_blue.astm` geometry when `CORNELL_DIR` names it, else
/// the built-in geometries.
fn geometry() -> Result<(String, Vec<Angles>), Box<dyn std::error::Error>> {
    match std::env::var_os("CORNELL_DIR") {
        Some(dir) => {
            let path = Path::new(&dir).join("krylon_blue.astm");
            let set = laminar_brdf_io::astm::read_astm(&path)?;
            let scene = set.scenes()?.remove(0);
            Ok(("krylon_blue.astm".into(), scene.angles().to_vec()))
        }
        None => Ok(("the built-in geometry".into(), geometries())),
    }
}
