//! Do the intervals hold when the model does not fit? (docs/estimation.md,
//! "When the model does not fit"; the table there is what this prints
//! with `cargo test --release -p laminar-brdf-fit --test misspecified -- --nocapture`.)
//!
//! Data from a reflectance richer than the fitted model
//! ([`laminar_brdf_fit::misspecified::Truth`]: the Gaussian model plus a
//! Lambertian term and a second lobe), fitted by exp and by gauss, on
//! random designs of K = 200 angles from a CUReT-like distribution, noise
//! on every measurement. The target is the pseudo-true parameter: the fit
//! to the noise-free truth on a dense design of 20,000 angles from the same
//! distribution. The fits compute every interval (`uncertainty =
//! bootstrap`, B = 200); the default headline's (the robust interval's)
//! and the bootstrap's 68.27% and 95% rates must lie in 3σ binomial bands;
//! the model-based (profile) rates are printed beside them, and at least
//! one of them must fall below its band (else the test would not be
//! testing misfit).

use laminar_brdf_fit::coverage::SETTINGS;
use laminar_brdf_fit::misspecified::{design, Truth};
use laminar_brdf_fit::report::Source;
use laminar_brdf_fit::synthetic::Noise;
use laminar_brdf_fit::{Analysis, Fit, Fitter, Grid, Model, Param, Uncertainty};

/// Trials per setting.
const TRIALS: usize = 200;
/// Measurements per trial.
const K: usize = 200;
/// Angles of the dense design.
const DENSE: usize = 20_000;

/// The 3σ binomial band of a rate `p` over [`TRIALS`] trials.
fn band(p: f64) -> (f64, f64) {
    laminar_brdf_fit::coverage::band(p, TRIALS)
}

fn value(fit: &Fit, name: Param) -> f64 {
    fit.parameters
        .iter()
        .find(|p| p.name == name)
        .unwrap()
        .value()
}

#[test]
fn robust_intervals_cover_the_pseudo_true_parameters() {
    let truth = Truth::standard();
    let mut rng = Noise::new(36);
    let dense = design(DENSE, &mut rng);
    let fitter = Fitter::new(Grid::user()).unwrap().analysis(Analysis {
        uncertainty: Uncertainty::Bootstrap,
        ..Analysis::FULL
    });
    let mut failures = Vec::new();
    let mut model_based_misses = 0;
    for model in [Model::Exp, Model::Gauss] {
        for noise in SETTINGS {
            // The pseudo-true parameters, with the noisy fits' weights.
            let target = fitter
                .clone()
                .analysis(Analysis {
                    refine: true,
                    uncertainty: Uncertainty::Off,
                    ..Analysis::FULL
                })
                .fit(&truth.clean_scene(dense.clone(), noise), model);
            let names: Vec<Param> = target.parameters.iter().map(|p| p.name).collect();
            for p in &target.parameters {
                let (lo, hi) = p.bounds.unwrap();
                assert!(
                    lo < p.value() && p.value() < hi,
                    "{model} {}: the pseudo-true {} {} lies on a face of the box",
                    noise.label(),
                    p.name,
                    p.value()
                );
            }
            let scenes: Vec<_> = (0..TRIALS)
                .map(|_| truth.noisy_scene(design(K, &mut rng), &dense, noise, &mut rng))
                .collect();
            let fits = fitter.fit_batch(&scenes, model);
            for &name in &names {
                let t = value(&target, name);
                // The rate of a source's intervals.
                let rate = |source: Source, level: usize| {
                    let held = fits
                        .iter()
                        .filter(|f| {
                            let p = f.parameters.iter().find(|p| p.name == name).unwrap();
                            p.intervals(source)[level].is_some_and(|i| i.lo <= t && t <= i.hi)
                        })
                        .count();
                    held as f64 / TRIALS as f64
                };
                let headline = fits[0].parameters.iter().find(|p| p.name == name).unwrap();
                assert_eq!(
                    headline.source,
                    Some(Source::Bootstrap),
                    "{model} {name}: the headline"
                );
                let sensitive = fits
                    .iter()
                    .filter(|f| {
                        f.parameters.iter().any(|p| {
                            p.name == name
                                && p.flags.contains(&laminar_brdf_fit::Edge::MisfitSensitive)
                        })
                    })
                    .count();
                let [robust, bootstrap, profile] =
                    [Source::Robust, Source::Bootstrap, Source::Profile]
                        .map(|source| [rate(source, 0), rate(source, 1)]);
                eprintln!(
                    "misspecified {model} | {} | {name} (pseudo-true {t:.4}): 68.27%/95% robust {:.3}/{:.3}, bootstrap {:.3}/{:.3}, profile {:.3}/{:.3}; misfit_sensitive {sensitive}/{TRIALS}",
                    noise.label(),
                    robust[0], robust[1], bootstrap[0], bootstrap[1], profile[0], profile[1],
                );
                for (level, nominal) in [(0, 0.6827), (1, 0.95)] {
                    let (lo, hi) = band(nominal);
                    for (source, got) in
                        [("robust", robust[level]), ("bootstrap", bootstrap[level])]
                    {
                        if !(lo..=hi).contains(&got) {
                            failures.push(format!(
                                "{model} {} {name} {source} level {level}: {got}",
                                noise.label()
                            ));
                        }
                    }
                    if profile[level] < lo {
                        model_based_misses += 1;
                    }
                }
            }
        }
    }
    assert!(failures.is_empty(), "outside the 3σ bands: {failures:?}");
    assert!(
        model_based_misses > 0,
        "the model-based intervals held everywhere: the truth is not misspecified enough to test"
    );
}
