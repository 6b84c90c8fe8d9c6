//! The search end to end: recovery of known parameters on every path,
//! agreement with the f64 reference, determinism across thread counts,
//! SIMD/scalar parity, and (with `CURET_DIR`) the paper's 13 samples.

use laminar_brdf_core::{Correlation, Params};
use laminar_brdf_fit::paper::search::{error_surface, point, search, Twins};
use laminar_brdf_fit::{
    synthetic, Axis, Fitter, Grid, GridError, MeasurementAngles, MeasurementSet, Model, Objective,
    Scene,
};
use laminar_brdf_fit::{Arith, Method, SearchPath};

mod common;

/// A grid on the paper's steps with a coarser a axis (0.1 steps).
fn test_grid() -> Grid {
    Grid {
        a: Axis::stepped(0.0, 0.1, 11),
        ..Grid::paper()
    }
}

const TRUTH: (f64, f64, f64, f64) = (1.48, 0.39, 1.44, 0.2);

fn truth() -> Params {
    Params::new(TRUTH.0, TRUTH.1, TRUTH.2, TRUTH.3).unwrap()
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

/// A small grid around [`TRUTH`] on the paper's steps, for the direct path.
fn small_grid() -> Grid {
    Grid {
        slope: Axis::stepped(1.32, 0.08, 5),
        n: Axis::stepped(1.40, 0.02, 5),
        a: Axis::stepped(0.0, 0.1, 5),
        beta: Axis::stepped(0.35, 0.01, 9),
    }
}

fn assert_recovered(grid: &Grid, scene: &Scene, corr: Correlation, path: SearchPath) {
    let r = search(scene, grid, corr, path, &|| {}).unwrap();
    let (s, n, a, b) = point(grid, r.best);
    assert!(
        close(s, TRUTH.0, 1e-9)
            && close(b, TRUTH.1, 1e-9)
            && close(n, TRUTH.2, 1e-9)
            && close(a, TRUTH.3, 1e-9),
        "{corr:?} {path}: got slope={s} beta={b} n={n} a={a}"
    );
    assert!(r.best_rms < 1e-3, "{path} rms {}", r.best_rms);
}

#[test]
fn noiseless_synthetic_data_is_recovered_exactly_on_every_path() {
    for corr in [Correlation::Exponential, Correlation::Gaussian] {
        let scene = synthetic::scene(corr, &truth(), 0.0, 1);
        for path in SearchPath::all() {
            assert_recovered(&small_grid(), &scene, corr, path);
            if path.method != Method::Direct {
                assert_recovered(&test_grid(), &scene, corr, path);
            }
        }
    }
}

/// Every path's error surface against the direct f64 reference. The f64
/// paths differ only by rounding order (≤ 1e-12); the f32 paths by the f32
/// model error (a few eps per term, `tests/error_budgets.rs`) propagated
/// through the normalisation: measured max 7.8e-7 on this grid, budget 4e-6.
#[test]
fn every_path_matches_the_f64_reference() {
    let grid = small_grid();
    for corr in [Correlation::Exponential, Correlation::Gaussian] {
        let scene = synthetic::scene(corr, &truth(), 0.01, 3);
        let reference = error_surface(&scene, &grid, corr, SearchPath::REFERENCE).unwrap();
        for path in SearchPath::all() {
            let v = error_surface(&scene, &grid, corr, path).unwrap();
            let worst = v
                .iter()
                .zip(&reference)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            let budget = if path.arith == Arith::F64 {
                1e-12
            } else {
                2e-5
            };
            eprintln!("{corr:?} {path}: max |ΔRMS| = {worst:.3e}");
            assert!(
                worst <= budget,
                "{corr:?} {path}: max |ΔRMS| {worst:e} > {budget:e}"
            );
        }
    }
}

#[test]
fn slightly_noisy_data_is_recovered_within_one_grid_step() {
    let grid = test_grid();
    let scene = synthetic::scene(Correlation::Exponential, &truth(), 0.001, 7);
    let r = search(
        &scene,
        &grid,
        Correlation::Exponential,
        SearchPath::DEFAULT,
        &|| {},
    )
    .unwrap();
    let (s, n, a, b) = point(&grid, r.best);
    assert!(close(s, TRUTH.0, 0.08 + 1e-9), "slope {s}");
    assert!(close(b, TRUTH.1, 0.01 + 1e-9), "beta {b}");
    assert!(close(n, TRUTH.2, 0.02 + 1e-9), "n {n}");
    assert!(close(a, TRUTH.3, 0.1 + 1e-9), "a {a}");
}

/// The search's choice (and its a = 0 choice) is the first minimum of its
/// own error surface, which never skips: the envelope search's lower-bound
/// skipping loses nothing, on a good fit and on a poor one (Gaussian data
/// fitted with the Exponential model).
#[test]
fn search_picks_the_minimum_of_its_error_surface() {
    let first_min = |v: &[f64], keep: &dyn Fn(usize) -> bool| {
        (0..v.len())
            .filter(|&i| keep(i))
            .fold(None, |b: Option<usize>, i| match b {
                Some(j) if v[j] <= v[i] => Some(j),
                _ => Some(i),
            })
            .unwrap()
    };
    let good = synthetic::scene(Correlation::Exponential, &truth(), 0.01, 11);
    let poor = synthetic::scene(Correlation::Gaussian, &truth(), 0.01, 12);
    for scene in [&good, &poor] {
        for path in SearchPath::all() {
            let grid = if path.method == Method::Direct {
                small_grid()
            } else {
                test_grid()
            };
            let corr = Correlation::Exponential;
            let r = search(scene, &grid, corr, path, &|| {}).unwrap();
            let surface = error_surface(scene, &grid, corr, path).unwrap();
            let want = first_min(&surface, &|_| true);
            assert_eq!(r.best, want, "{path}");
            assert_eq!(r.best_rms.to_bits(), surface[want].to_bits(), "{path}");
            let on_zero_a = |i: usize| point(&grid, i).2 == 0.0;
            let rh = first_min(&surface, &on_zero_a);
            let (flat, rms) = r.rh_best.unwrap();
            assert_eq!(
                (flat, rms.to_bits()),
                (rh, surface[rh].to_bits()),
                "{path} a = 0"
            );
            if path.method == Method::Envelope {
                assert!(r.pruned.unwrap() > 0.0, "{path}: nothing skipped");
            }
        }
    }
}

#[test]
fn results_do_not_depend_on_thread_count() {
    let grid = test_grid();
    let scene = synthetic::default_scene();
    let run = |threads| {
        Fitter::new(grid.clone())
            .unwrap()
            .objective(Objective::Paper)
            .threads(threads)
            .unwrap()
            .fit(&scene, Model::Exp)
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(3));
}

#[test]
fn simd_grid_equals_scalar_twin_bit_for_bit() {
    let hoisted = Grid {
        slope: Axis::linspace(0.12, 4.04, 7),
        ..test_grid()
    };
    for corr in [Correlation::Exponential, Correlation::Gaussian] {
        let scene = synthetic::default_scene();
        for method in [Method::Direct, Method::OnePass, Method::Envelope] {
            let grid = if method == Method::Direct {
                small_grid()
            } else {
                hoisted.clone()
            };
            let twins = Twins::new(&scene, &grid, corr, method).unwrap();
            let (same, simd) = (twins.identical(), twins.simd);
            assert_eq!(
                same,
                simd.len(),
                "{corr:?} {method:?}: {same} of {} identical",
                simd.len()
            );
            assert!(simd.iter().all(|v| v.is_finite()));
        }
    }
}

#[test]
fn ragheb_hancock_slice_equals_its_own_search() {
    let grid = test_grid();
    let scene = synthetic::default_scene();
    let fitter = Fitter::new(grid).unwrap().objective(Objective::Paper);
    let full = fitter.fit(&scene, Model::Gauss);
    let rh = fitter.fit(&scene, Model::RhGauss);
    assert_eq!(full.rh.as_ref().unwrap(), &rh.best);
}

/// The paper's 13 samples from `CURET_DIR`: exp and gauss fits, the
/// specular exclusion (K = 198) and full-grid SIMD/scalar parity.
#[test]
fn curet_paper_samples_fit_and_match_scalar_twin() {
    let Some(scenes) = common::paper_scenes("CUReT end-to-end test") else {
        return;
    };
    let grid = Grid::paper();
    let fitter = Fitter::new(grid.clone())
        .unwrap()
        .objective(Objective::Paper);
    let mut identical = 0usize;
    for scene in scenes {
        assert_eq!(scene.len(), 198, "sample {}", scene.sample());
        for (model, corr) in [
            (Model::Exp, Correlation::Exponential),
            (Model::Gauss, Correlation::Gaussian),
        ] {
            let r = fitter.fit(&scene, model);
            assert!(
                r.best.rms.is_finite() && r.best.rms < 5.0,
                "sample {} {model}: rms {}",
                scene.sample(),
                r.best.rms
            );
            let rh = r.rh.as_ref().expect("a axis has 0");
            assert!(
                r.best.rms <= rh.rms + 1e-6,
                "absorptive fit worse than its a = 0 slice"
            );
            for method in [Method::OnePass, Method::Envelope] {
                let simd_path = SearchPath::new(method, Arith::F32x8);
                let twins = Twins::new(&scene, &grid, corr, method).unwrap();
                let (same, simd) = (twins.identical(), twins.simd);
                assert_eq!(
                    same,
                    simd.len(),
                    "sample {} {model} {method:?}",
                    scene.sample()
                );
                identical += same;
                // The search (which may skip triples) finds the surface's minimum.
                let found = search(&scene, &grid, corr, simd_path, &|| {}).unwrap();
                let min = simd.iter().copied().fold(f64::INFINITY, f64::min);
                assert_eq!(
                    found.best_rms.to_bits(),
                    min.to_bits(),
                    "sample {} {model} {method:?}",
                    scene.sample()
                );
                assert_eq!(simd[found.best].to_bits(), min.to_bits());
            }
        }
    }
    println!(
        "CUReT parity: {identical} of {} grid values identical",
        2 * 26 * grid.size()
    );
}

#[test]
fn invalid_grids_and_thread_counts_are_errors_not_panics() {
    let scene = synthetic::default_scene();
    let empty = Grid {
        a: Axis { values: vec![] },
        ..Grid::paper()
    };
    let e = search(
        &scene,
        &empty,
        Correlation::Exponential,
        SearchPath::DEFAULT,
        &|| {},
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            GridError::Empty {
                axis: laminar_brdf_fit::model::Param::A
            }
        ),
        "{e}"
    );
    let e = error_surface(
        &scene,
        &empty,
        Correlation::Exponential,
        SearchPath::DEFAULT,
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            GridError::Empty {
                axis: laminar_brdf_fit::model::Param::A
            }
        ),
        "{e}"
    );
    let outside = Grid {
        n: Axis { values: vec![0.5] },
        ..Grid::paper()
    };
    assert!(Fitter::new(outside).is_err());
    let e = Fitter::new(Grid::paper())
        .unwrap()
        .threads(0)
        .err()
        .unwrap();
    assert_eq!(
        e.to_string(),
        "cannot start 0 worker threads: at least one thread is needed"
    );
}

/// Scenes on one geometry: different truths and noise.
fn batch_scenes(corr: Correlation) -> Vec<Scene> {
    [
        (1.48, 0.39, 1.44, 0.2),
        (0.6, 0.7, 1.3, 0.0),
        (2.5, 0.1, 1.5, 0.9),
    ]
    .iter()
    .enumerate()
    .flat_map(|(i, &(s, b, n, a))| {
        let p = Params::new(s, b, n, a).unwrap();
        [0.0, 0.01, 0.05].map(|noise| synthetic::scene(corr, &p, noise, 7 + i as u64))
    })
    .collect()
}

/// The batch search shares the model-side work and gives, bit for bit, the
/// fit of each scene alone: every arithmetic, layered model and thread count.
#[test]
fn batch_fits_equal_single_fits_bit_for_bit() {
    let grid = test_grid();
    for corr in [Correlation::Exponential, Correlation::Gaussian] {
        let scenes = batch_scenes(corr);
        for arith in [Arith::F32x8, Arith::F32, Arith::F64] {
            let path = SearchPath::new(Method::Envelope, arith);
            for threads in [1, 3] {
                let fitter = Fitter::new(grid.clone())
                    .unwrap()
                    .objective(Objective::Paper)
                    .path(path)
                    .threads(threads)
                    .unwrap();
                for model in [Model::Exp, Model::Gauss, Model::RhExp] {
                    let batch = fitter.fit_batch(&scenes, model);
                    assert_eq!(batch.len(), scenes.len());
                    for (scene, fit) in scenes.iter().zip(&batch) {
                        assert_eq!(fit, &fitter.fit(scene, model), "{path} {model} {threads}");
                    }
                    // Any split into blocks gives the same fits.
                    let split: Vec<_> = scenes
                        .chunks(2)
                        .flat_map(|block| fitter.fit_batch(block, model))
                        .collect();
                    assert_eq!(split, batch, "{path} {model} {threads}: blocks of 2");
                }
            }
        }
    }
}

/// Scenes that do not share their geometry, baselines and other methods are
/// fitted one by one by `fit_batch`, with the same results.
#[test]
fn batch_falls_back_to_single_fits() {
    let grid = small_grid();
    let mut scenes = batch_scenes(Correlation::Exponential);
    assert!(laminar_brdf_fit::paper::search::batch::share_geometry(
        &scenes
    ));
    // A scene on the first 60 of the geometries only.
    let angles: Vec<MeasurementAngles> = synthetic::geometries()[..60]
        .iter()
        .map(|a| MeasurementAngles::Paper {
            theta_i: a.theta_i(),
            theta_s: a.theta_s(),
            phi_s: a.phi_s(),
        })
        .collect();
    let values = scenes[1].data()[..60].to_vec();
    let fewer = MeasurementSet::new("fewer", angles, laminar_brdf_fit::Quantity::Radiance)
        .and_then(|s| s.with_channel("v", values, None))
        .and_then(|s| s.scene("v"))
        .unwrap();
    scenes.push(fewer);
    assert!(!laminar_brdf_fit::paper::search::batch::share_geometry(
        &scenes
    ));
    let fitter = Fitter::new(grid).unwrap().objective(Objective::Paper);
    for model in [Model::Exp, Model::Jensen] {
        let batch = fitter.fit_batch(&scenes, model);
        for (scene, fit) in scenes.iter().zip(&batch) {
            assert_eq!(fit, &fitter.fit(scene, model));
        }
    }
    let onepass = fitter.path(SearchPath::new(Method::OnePass, Arith::F32x8));
    let batch = onepass.fit_batch(&scenes[..2], Model::Gauss);
    assert_eq!(batch[1], onepass.fit(&scenes[1], Model::Gauss));
}

/// The free objective's grid stage in `f32x8` (`Precision::F32`) leaves
/// every fit within the tolerance of the `f64` one: each refined
/// value and interval end within 10⁻³ of its 68.27% interval's width, and
/// on these sets the grid's best points the same (on CUReT and 6,400
/// synthetic sets in docs/speed.md, the fits were byte for byte the same).
#[test]
fn the_single_precision_grid_stage_leaves_the_fits_as_they_are() {
    use laminar_brdf_fit::coverage::{noisy_sets, NoiseModel};
    use laminar_brdf_fit::Precision;
    let fitter = Fitter::new(Grid::user()).unwrap();
    let single = fitter.clone().grid_precision(Precision::F32);
    for model in [Model::Exp, Model::Gauss, Model::RhGauss] {
        let sets = noisy_sets(
            &synthetic::geometries(),
            model,
            Objective::Free,
            NoiseModel::Every(0.01),
            16,
            7,
        );
        let wide = fitter.fit_batch(&sets, model);
        let narrow = single.fit_batch(&sets, model);
        for (a, b) in wide.iter().zip(&narrow) {
            for (p, q) in a.parameters.iter().zip(&b.parameters) {
                let i = p.interval68.expect("a 68% interval");
                let width = i.hi - i.lo;
                // The grid's best points themselves are the same here.
                assert_eq!(p.grid, q.grid, "{model} {}", p.name);
                let off = |x: f64, y: f64| (x - y).abs() <= 1e-3 * width;
                assert!(off(p.value(), q.value()), "{model} {}", p.name);
                for (x, y) in [(p.interval68, q.interval68), (p.interval95, q.interval95)] {
                    let (x, y) = (x.unwrap(), y.unwrap());
                    assert!(off(x.lo, y.lo) && off(x.hi, y.hi), "{model} {}", p.name);
                }
            }
        }
    }
}
