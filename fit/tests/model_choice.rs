//! Model choice (docs/estimation.md, "Choosing a model"): the models fitted
//! to one set are ranked by AICc and cross-validated, the same on any
//! number of threads.

use laminar_brdf_core::{Correlation, Params};
use laminar_brdf_fit::{synthetic, Fit, Fitter, Grid, Model, Param};

/// Every model fitted to a set made by exp (noise 1% of the max) on
/// `threads` threads.
fn compared(threads: usize) -> Vec<Fit> {
    let truth = Params::new(1.48, 0.39, 1.44, 0.2).unwrap();
    let scene = synthetic::scene(Correlation::Exponential, &truth, 0.01, 3);
    Fitter::new(Grid::user())
        .unwrap()
        .threads(threads)
        .unwrap()
        .fit_all(&[scene], &Model::ALL, |_, _| None)
        .unwrap()
}

fn of(fits: &[Fit], model: Model) -> &Fit {
    fits.iter().find(|f| f.model == model).unwrap()
}

#[test]
fn models_are_ranked_and_cross_validated() {
    let fits = compared(2);
    let mut ranks: Vec<usize> = fits.iter().map(|f| f.rank.unwrap().rank).collect();
    ranks.sort_unstable();
    assert_eq!(ranks[0], 1);
    let weights: f64 = fits.iter().map(|f| f.rank.unwrap().weight).sum();
    assert!(
        (weights - 1.0).abs() < 1e-12,
        "Akaike weights sum to {weights}"
    );
    for f in &fits {
        let cv = f.cross_validation.unwrap();
        assert_eq!(cv.folds, 5);
        // Held-out measurements are predicted no better than fitted ones.
        assert!(
            cv.rms >= cv.in_sample,
            "{}: cross-validated {} below in-sample {}",
            f.model,
            cv.rms,
            cv.in_sample
        );
    }
    // The model that made the data predicts held-out data about as well
    // as it fits (K = 198, p = 5), and better than the baselines, which
    // have no specular lobe; the winner is a layered model.
    let exp = of(&fits, Model::Exp).cross_validation.unwrap();
    assert!(exp.rms < 1.25 * exp.in_sample, "{exp:?}");
    for baseline in [Model::Jensen, Model::OrenNayar] {
        let b = of(&fits, baseline);
        assert!(b.cross_validation.unwrap().rms > 2.0 * exp.rms, "{b:?}");
        assert!(b.rank.unwrap().weight < 1e-6);
    }
    let best = fits.iter().find(|f| f.rank.unwrap().rank == 1).unwrap();
    assert!(best.model.is_layered(), "{} ranked first", best.model);
}

#[test]
fn one_model_alone_is_not_cross_validated() {
    let truth = Params::new(1.48, 0.39, 1.44, 0.2).unwrap();
    let scene = synthetic::scene(Correlation::Exponential, &truth, 0.01, 3);
    let fitter = Fitter::new(Grid::user()).unwrap();
    let alone = fitter.fit_all(std::slice::from_ref(&scene), &[Model::Exp], |_, _| None);
    let alone = &alone.unwrap()[0];
    assert!(alone.cross_validation.is_none() && alone.rank.is_none());
    assert_eq!(alone, &fitter.fit(&scene, Model::Exp));
}

#[test]
fn the_comparison_does_not_depend_on_the_thread_count() {
    assert_eq!(compared(1), compared(2));
}

/// A set of `k` measurements made by exp (σ = 0.01, estimated).
fn few(k: usize) -> laminar_brdf_fit::Scene {
    use laminar_brdf_fit::coverage::{noisy_scene_on, NoiseModel};
    use laminar_brdf_fit::{ModelParams, Objective};
    let mut angles = synthetic::geometries();
    angles.truncate(k);
    let truth = ModelParams::Layered {
        slope: 0.5,
        beta: 0.4,
        n: 1.5,
        a: 0.2,
        sub_slope: None,
    };
    let mut rng = synthetic::Noise::new(3);
    noisy_scene_on(
        angles,
        Model::Exp,
        Objective::Free,
        truth,
        NoiseModel::Every(0.01),
        &mut rng,
    )
}

/// On 7 measurements the absorptive models (5 fitted parameters, k = 6
/// with the noise variance) have no AICc: every model of the set is then
/// ranked by AIC, not theirs by AIC against the others' AICc (which put
/// exp above rh-exp, the same fit with a parameter fewer; issue 55, item 1).
#[test]
fn a_set_is_ranked_by_one_criterion_when_a_model_has_no_aicc() {
    let fits = Fitter::new(Grid::user())
        .unwrap()
        .fit_all(&[few(7)], &Model::ALL, |_, _| None)
        .unwrap();
    let info = |m: Model| of(&fits, m).information.unwrap();
    assert!(info(Model::Exp).aicc.is_none() && info(Model::RhExp).aicc.is_some());
    let best = Model::ALL
        .into_iter()
        .find(|&m| of(&fits, m).rank.unwrap().rank == 1)
        .unwrap();
    for m in Model::ALL {
        let rank = of(&fits, m).rank.unwrap();
        assert_eq!(rank.delta, info(m).aic - info(best).aic, "{m}");
    }
    // exp is rh-exp with a free: where its fit is no better by AIC's price
    // of a parameter, it ranks below.
    let (exp, rh) = (info(Model::Exp).aic, info(Model::RhExp).aic);
    let (exp_rank, rh_rank) = (of(&fits, Model::Exp).rank, of(&fits, Model::RhExp).rank);
    assert_eq!(exp < rh, exp_rank.unwrap().rank < rh_rank.unwrap().rank);
}

/// A model named twice is refused (it was fitted twice, and its two rows
/// split its Akaike weight; issue 55, item 3).
#[test]
fn a_model_named_twice_is_refused() {
    let err = Fitter::new(Grid::user())
        .unwrap()
        .fit_all(
            &[few(30)],
            &[Model::Exp, Model::Exp, Model::Gauss],
            |_, _| None,
        )
        .unwrap_err()
        .to_string();
    assert!(err.contains("model exp is named twice"), "{err}");
}

/// Without degrees of freedom (2 measurements) the bootstrap gives no
/// interval, as the profile and Jacobian give none: its resamples are each
/// fitted exactly, and their intervals were of zero width with no flag
/// (issue 55, item 2).
#[test]
fn the_bootstrap_gives_no_interval_without_degrees_of_freedom() {
    use laminar_brdf_fit::report::Source;
    use laminar_brdf_fit::{Analysis, Uncertainty};
    let analysis = Analysis {
        uncertainty: Uncertainty::Bootstrap,
        resamples: 50,
        ..Analysis::FULL
    };
    let fitter = Fitter::new(Grid::user()).unwrap().analysis(analysis);
    for k in [2, 5] {
        let fit = fitter.fit(&few(k), Model::Exp);
        for p in &fit.parameters {
            assert!(
                p.interval68.is_none() && p.interval95.is_none(),
                "{k}: {p:?}"
            );
            assert!(p.intervals(Source::Bootstrap)[0].is_none(), "{k}: {p:?}");
        }
    }
    // With degrees of freedom, bootstrap intervals, of nonzero width.
    let fit = fitter.fit(&few(40), Model::Exp);
    let n = fit
        .parameters
        .iter()
        .find(|p| p.name.name() == "n")
        .unwrap();
    let i = n.intervals(Source::Bootstrap)[1].unwrap();
    assert!(i.hi > i.lo, "{i:?}");
}

/// The paper objective computes no bootstrap: asking for one is refused
/// with what it computes instead (it gave profile intervals silently).
#[test]
fn the_bootstrap_under_the_paper_objective_is_refused() {
    let mut settings = laminar_brdf_fit::Settings::default();
    settings.set("objective", "paper").unwrap();
    settings.set("uncertainty", "bootstrap").unwrap();
    let Err(err) = settings.fitter() else {
        panic!("the bootstrap under the paper objective was taken");
    };
    let err = err.to_string();
    assert!(
        err.contains("uncertainty bootstrap is not computed under the paper objective"),
        "{err}"
    );
    settings.set("uncertainty", "both").unwrap();
    assert!(settings.fitter().is_ok());
}

/// A surface whose subsurface is rougher than its top coat (σ/T 0.3,
/// σ′/T′ 1.5; noise 1% of the max): the untied model recovers both slopes
/// within its 95% intervals, and the ranking prefers it to the tied model,
/// which cannot fit both lobes with one slope.
#[test]
fn an_untied_surface_is_recovered_and_preferred_to_the_tied_model() {
    let truth = Params::untied(0.3, 1.5, 0.39, 1.44, 0.2).unwrap();
    let scene = synthetic::scene(Correlation::Exponential, &truth, 0.01, 5);
    let fits = Fitter::new(Grid::user())
        .unwrap()
        .fit_all(&[scene], &[Model::Exp, Model::Exp2], |_, _| None)
        .unwrap();
    let untied = of(&fits, Model::Exp2);
    for (param, value) in [
        (Param::Slope, truth.slope()),
        (Param::SubSlope, truth.sub_slope()),
        (Param::N, truth.n()),
    ] {
        let p = untied.parameters.iter().find(|p| p.name == param).unwrap();
        let i = p.interval95.expect("an interval");
        assert!(
            i.lo <= value && value <= i.hi,
            "{param}: {value} outside {i:?} ({:?})",
            p.refined
        );
    }
    assert_eq!(untied.rank.unwrap().rank, 1);
    assert!(of(&fits, Model::Exp).rank.unwrap().weight < 1e-3);
}
