//! One fit on one thread and on several gives the same record, bit for
//! bit: the grid's columns, the refinements from several basins, the
//! corner start and the interval ends run side by side, and each result is
//! chosen in a fixed order, whatever finished first.

use laminar_brdf_core::Correlation;
use laminar_brdf_fit::{synthetic, Analysis, Fitter, Grid, Model, Uncertainty};

#[test]
fn a_single_fit_is_the_same_on_one_thread_and_on_four() {
    let angles = synthetic::spread(150);
    let analysis = Analysis {
        uncertainty: Uncertainty::Both,
        ..Analysis::FULL
    };
    for (corr, model) in [
        (Correlation::Exponential, Model::Exp),
        (Correlation::Gaussian, Model::Gauss),
        (Correlation::Exponential, Model::Exp2),
    ] {
        for (i, scene) in synthetic::sets(corr, &angles, 4, 0.01, 41)
            .iter()
            .enumerate()
        {
            let fit = |threads| {
                Fitter::new(Grid::user())
                    .expect("the default grid")
                    .analysis(analysis)
                    .threads(threads)
                    .expect("a thread count")
                    .fit(scene, model)
            };
            let (one, four) = (fit(1), fit(4));
            // Debug prints every float's shortest round-trip digits.
            assert_eq!(format!("{one:?}"), format!("{four:?}"), "{model} set {i}");
        }
    }
}
