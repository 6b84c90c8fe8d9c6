//! Model choice (docs/estimation.md, "Choosing a model"): the models fitted
//! to one set are ranked by AICc and cross-validated, the same on any
//! number of threads.

use laminar_core::{Correlation, Params};
use laminar_fit::{synthetic, Fit, Fitter, Grid, Model};

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
