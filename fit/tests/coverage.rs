//! Do the intervals of the free-amplitude objective contain the truth at
//! their stated rates? (docs/conventions.md §11b; the docs' coverage table
//! is what this prints with
//! `cargo test --release -p laminar-brdf-fit --test coverage -- --nocapture`.)
//!
//! 200 synthetic fits per (model, noise setting), truths spread over the
//! box's interior, noise on every measurement: homoscedastic and estimated
//! from the residuals, or heteroscedastic and given to the fit as sigma.
//! Every parameter's model-based (profile) 68.27% and 95% rates must lie
//! within 3σ binomial bands, and its robust rates (the headline) must not
//! fall below them.

use laminar_brdf_fit::coverage::{coverage, noisy_scene, Coverage, NoiseModel, SETTINGS};
use laminar_brdf_fit::synthetic::Noise;
use laminar_brdf_fit::{Baseline, Edge, Fit, Fitter, Grid, Model, ModelParams, Objective, Param};

/// Trials per setting.
const TRIALS: usize = 200;

/// The 3σ binomial band of a rate `p` over [`TRIALS`] trials.
fn band(p: f64) -> (f64, f64) {
    laminar_brdf_fit::coverage::band(p, TRIALS)
}

fn fitter() -> Fitter {
    Fitter::new(Grid::user())
        .unwrap()
        .objective(Objective::Free)
}

/// The free fit of `model` to a noisy scene at `truth`.
fn free_fit(model: Model, truth: ModelParams, noise: NoiseModel, rng: &mut Noise) -> Fit {
    let scene = noisy_scene(model, Objective::Free, truth, noise, rng);
    fitter().fit(&scene, model)
}

fn check(model: Model) {
    let mut failures = Vec::new();
    for noise in SETTINGS {
        let c: Coverage = coverage(&fitter(), model, TRIALS, noise, 2016);
        assert_eq!(c.outside_box, 0, "{model}: an estimate outside the box");
        assert_eq!(c.parameters.len(), model.parameter_count());
        for p in &c.parameters {
            let (r68, r95) = (c.rate(p.name, 0).unwrap(), c.rate(p.name, 1).unwrap());
            eprintln!(
                "coverage {model} | {} | {}: 68.27% {r68:.3} ± {:.3}, 95% {r95:.3} ± {:.3}; Jacobian ±1 sd {}/{}",
                noise.label(),
                p.name,
                (0.6827f64 * 0.3173 / TRIALS as f64).sqrt(),
                (0.95f64 * 0.05 / TRIALS as f64).sqrt(),
                p.in_sd,
                p.with_sd
            );
            for (rate, nominal) in [(r68, 0.6827), (r95, 0.95)] {
                let (lo, hi) = band(nominal);
                if !(lo..=hi).contains(&rate) {
                    failures.push(format!(
                        "{} {}: {rate:.3} outside [{lo:.3}, {hi:.3}] at {nominal}",
                        noise.label(),
                        p.name
                    ));
                }
            }
            // The headline (robust) intervals when the model holds: never
            // below the band (they may be a little wider than needed: the
            // price of holding when the model does not fit).
            let robust = [0, 1].map(|level| c.headline_rate(p.name, level).unwrap());
            eprintln!(
                "coverage {model} | {} | {}: headline 68.27% {:.3}, 95% {:.3}",
                noise.label(),
                p.name,
                robust[0],
                robust[1]
            );
            for (rate, nominal) in [(robust[0], 0.6827), (robust[1], 0.95)] {
                let (lo, _) = band(nominal);
                if rate < lo {
                    failures.push(format!(
                        "{} {} headline: {rate:.3} below {lo:.3} at {nominal}",
                        noise.label(),
                        p.name
                    ));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{model}: {failures:?}");
}

#[test]
fn exp_intervals_cover_the_truth() {
    check(Model::Exp);
}

/// Known bug (docs/conventions.md §11b): n's 68% rate with σ = 0.01
/// estimated passes at 0.780 only because the profile walk ends one of
/// its 200 intervals short (trial 141); with exact ends it is 0.785, above
/// the band.
#[test]
fn gauss_intervals_cover_the_truth() {
    check(Model::Gauss);
}

#[test]
fn intervals_shrink_with_the_noise_and_an_exact_truth_is_found() {
    let truth = ModelParams::Layered {
        slope: 1.23,
        beta: 0.61,
        n: 1.73,
        a: 0.27,
        sub_slope: None,
    };
    let mut widths = Vec::new();
    for noise in [0.02, 0.005, 0.001] {
        let fit = free_fit(
            Model::Exp,
            truth,
            NoiseModel::Every(noise),
            &mut Noise::new(7),
        );
        let width: f64 = fit
            .parameters
            .iter()
            .map(|p| {
                let i = p.interval68.expect("profile intervals");
                i.hi - i.lo
            })
            .sum();
        widths.push(width);
    }
    assert!(widths.windows(2).all(|w| w[1] < w[0]), "{widths:?}");
    // Without noise the truth, off every grid axis, is found.
    let fit = free_fit(
        Model::Exp,
        truth,
        NoiseModel::Every(0.0),
        &mut Noise::new(7),
    );
    for p in &fit.parameters {
        let t = truth.value(p.name).unwrap();
        assert!((p.value() - t).abs() <= 1e-6, "{}: {}", p.name, p.value());
    }
}

#[test]
fn baselines_under_the_free_amplitude_say_what_the_data_do_not_determine() {
    let mut rng = Noise::new(3);
    // Jensen depends on σa and σs′ only through σs′/(σa + σs′): the
    // Jacobian reports the trade-off, and σa's 95% interval runs along the
    // valley to the box's lower face (the upper end is where σs′ meets its
    // own face and can no longer keep the ratio).
    let truth = ModelParams::baseline(Baseline::Jensen, [0.3, 0.6]);
    let fit = free_fit(Model::Jensen, truth, NoiseModel::Every(0.01), &mut rng);
    // The estimate slides along the valley, often to a face of the box
    // (then the Jacobian has no covariance for that parameter).
    if let Some(c) = &fit.covariance {
        let trade = c.trade_offs();
        assert!(trade.len() == 1 && trade[0].2.abs() > 0.99, "{trade:?}");
    }
    let p = &fit.parameters[0];
    let i = p.interval95.unwrap();
    assert!(i.lo == 0.01 && i.open_below && i.hi > 0.3, "{p:?}");
    // Oren–Nayar's ρ, with the amplitude free, enters only through the
    // small interreflection term (ρ² beside ρ): it is barely identified, and
    // its 95% interval says so, covering most of the box.
    let truth = ModelParams::baseline(Baseline::OrenNayar, [0.5, 0.5]);
    let fit = free_fit(Model::OrenNayar, truth, NoiseModel::Every(0.01), &mut rng);
    let p = &fit.parameters[1];
    let (lo, hi) = p.bounds.unwrap();
    let i = p.interval95.unwrap();
    assert!(i.hi - i.lo > 0.5 * (hi - lo), "{p:?}");
    // σ is identified: a narrow interval.
    let sigma = fit.parameters[0].interval95.unwrap();
    assert!(sigma.hi - sigma.lo < 0.2, "{sigma:?}");
    assert!(!fit.parameters[0].flags.contains(&Edge::NotIdentified));
}

#[test]
fn batches_equal_fits_alone_with_and_without_uncertainties() {
    // On one geometry without uncertainties the sets share the grid
    // stage's model side; with them each computes its own. Either way each
    // fit is bit for bit the fit of that set alone. Eleven sets: more than
    // one pass of the shared model side (eight sets each), the last partial.
    let mut rng = Noise::new(12);
    for noise in SETTINGS {
        let scenes: Vec<_> = (0..11)
            .map(|_| {
                let truth = laminar_brdf_fit::coverage::draw(Model::Exp, Objective::Free, &mut rng);
                noisy_scene(Model::Exp, Objective::Free, truth, noise, &mut rng)
            })
            .collect();
        let fitter = fitter();
        let batch = fitter.fit_batch(&scenes, Model::Exp);
        for (scene, fit) in scenes.iter().zip(&batch) {
            assert_eq!(fit, &fitter.fit(scene, Model::Exp));
        }
    }
}

#[test]
fn an_estimate_on_the_box_face_says_what_releasing_the_bound_gives() {
    // Truth n = 3.2, outside the default box n ∈ [1, 2.5]: the estimate
    // stays in the box, on its face, flagged; released, n goes back to
    // the truth and the fit improves.
    let truth = ModelParams::Layered {
        slope: 0.9,
        beta: 0.6,
        n: 3.2,
        a: 0.3,
        sub_slope: None,
    };
    let fit = free_fit(
        Model::Exp,
        truth,
        NoiseModel::Every(0.002),
        &mut Noise::new(5),
    );
    let n = fit.parameters.iter().find(|p| p.name == Param::N).unwrap();
    assert_eq!(n.value(), 2.5, "{n:?}");
    assert!(n.flags.contains(&Edge::RangeEdge) && n.flags.contains(&Edge::OpenAbove));
    let i = n.interval95.unwrap();
    assert!(i.hi <= 2.5 && i.open_above, "{i:?}");
    let released = n.released.expect("the bound released");
    assert!((released.value - 3.2).abs() < 0.2, "{released:?}");
    assert!(released.rms < released.rms_in_box, "{released:?}");
    assert_eq!(released.rms_in_box, fit.estimate().rms);
    // Every reported value stays in its box.
    for p in &fit.parameters {
        let (lo, hi) = p.bounds.unwrap();
        assert!(lo <= p.value() && p.value() <= hi, "{p:?}");
    }
}

/// The paper objective's rates on the same data and seed: the "before"
/// column of docs/conventions.md §11b. Printed, not asserted (they fail
/// their bands, which is why the free objective is the default): run with
/// `-- --ignored --nocapture`.
#[test]
#[ignore = "prints the paper objective's rates for the docs (about 10 s)"]
fn paper_objective_rates_for_the_docs() {
    let paper = Fitter::new(Grid::user())
        .unwrap()
        .objective(Objective::Paper);
    for model in [Model::Exp, Model::Gauss] {
        for noise in SETTINGS {
            let c = coverage(&paper, model, TRIALS, noise, 2016);
            for p in &c.parameters {
                eprintln!(
                    "paper objective {model} | {} | {}: 68.27% {:.3}, 95% {:.3}",
                    noise.label(),
                    p.name,
                    c.rate(p.name, 0).unwrap(),
                    c.rate(p.name, 1).unwrap()
                );
            }
        }
    }
}
