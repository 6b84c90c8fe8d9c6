//! The free-amplitude objective's cost (docs/conventions.md §4b, §11b):
//! one fit with the defaults (grid stage, refinement, 68%/95% profile
//! intervals and the Jacobian; the tied models and the untied), the grid stage alone (and both again with
//! the grid stage's model terms in `f32x8`, `_f32`), and batches of sets
//! on one geometry with the defaults (elements = sets, so criterion reports
//! sets per second). The scene is CUReT sample 21 (K = 198) when
//! `CURET_DIR` is set, else the built-in synthetic one (K = 200); the
//! batch's sets are the model at parameters drawn inside the box plus
//! seeded noise of 1% of the max on every measurement on that geometry.
//! The `free_analysis` group times what docs/estimation.md's analyses cost
//! per set on one thread: the pairs bootstrap (B = 200, on top of the
//! defaults) and the comparison of the six models (each fitted with the
//! defaults and 5-fold cross-validated, then ranked).
//! The `free_large_k` group is a bidirectional texture's size: 151 light
//! by 151 view directions (K = 22,801, as one UBO2014 material), 48 exp
//! sets on that geometry, fitted with the defaults and by the search alone
//! (in `f64` and `f32x8`; elements = sets).
//! The `joint_krylon_blue` group is the joint fit of Cornell's
//! `krylon_blue` (`CORNELL_DIR`) at three wavelengths and at all 31.
//! Run: `cargo bench --bench free` (one group: `cargo bench --bench free -- free_large_k`).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use laminar_brdf_core::Angles;
use laminar_brdf_fit::coverage::{noisy_sets, NoiseModel};
use laminar_brdf_fit::synthetic;
use laminar_brdf_fit::{
    Analysis, Fitter, Grid, Model, Noise, Objective, Precision, Scene, Uncertainty,
};
use laminar_brdf_io::curet::CuretDir;
use std::hint::black_box;
use std::path::{Path, PathBuf};

fn scene() -> (String, Scene) {
    match std::env::var_os("CURET_DIR") {
        Some(dir) => {
            let samples = CuretDir::open(Path::new(&dir))
                .and_then(|d| d.samples(&[PathBuf::from("abrdf.dat")], Some(&[21])))
                .expect("CURET_DIR holds table.txt and abrdf.dat with sample 21");
            (
                "curet21_k198".into(),
                samples[0].set.scene("avg").expect("sample 21 fits"),
            )
        }
        None => {
            eprintln!("CURET_DIR is not set: using the built-in synthetic scene");
            ("synthetic_k200".into(), synthetic::default_scene())
        }
    }
}

/// `count` sets of the exp model on `scene`'s geometry (noise on every
/// measurement, not given to the fit).
fn sets(scene: &Scene, count: usize) -> Vec<Scene> {
    noisy_sets(
        scene.angles(),
        Model::Exp,
        Objective::Free,
        NoiseModel::Every(0.01),
        count,
        5,
    )
}

fn free(c: &mut Criterion) {
    let (label, scene) = scene();
    let fitter = |analysis| {
        Fitter::new(Grid::user())
            .expect("the default box is valid")
            .objective(Objective::Free)
            .analysis(analysis)
    };
    let mut group = c.benchmark_group(format!("free_{label}"));
    group.sample_size(20);
    // The untied models beside the tied (issue 53: one untied fit within
    // 3× a tied one).
    for model in [Model::Exp, Model::Gauss, Model::Exp2, Model::Gauss2] {
        let full = fitter(Analysis::FULL);
        group.bench_function(format!("{model}_one_fit_defaults"), |b| {
            b.iter(|| black_box(full.fit(&scene, model)))
        });
    }
    for precision in Precision::ALL {
        let grid_only = fitter(Analysis::NONE).grid_precision(precision);
        let suffix = if precision == Precision::F64 {
            ""
        } else {
            "_f32"
        };
        group.bench_function(format!("exp_grid_stage_only{suffix}"), |b| {
            b.iter(|| black_box(grid_only.fit(&scene, Model::Exp)))
        });
    }
    let gauss_f32 = fitter(Analysis::FULL).grid_precision(Precision::F32);
    group.bench_function("gauss_one_fit_defaults_f32", |b| {
        b.iter(|| black_box(gauss_f32.fit(&scene, Model::Gauss)))
    });
    group.finish();

    let count = 256;
    let batch = sets(&scene, count);
    let full = fitter(Analysis::FULL);
    let mut group = c.benchmark_group(format!("free_batch_{label}"));
    group.sample_size(10);
    group.throughput(Throughput::Elements(count as u64));
    group.bench_function(format!("exp_{count}_sets_defaults"), |b| {
        b.iter(|| black_box(full.fit_batch(&batch, Model::Exp)))
    });
    group.finish();
}

fn analyses(c: &mut Criterion) {
    let (label, scene) = scene();
    let one_thread = |analysis| {
        Fitter::new(Grid::user())
            .expect("the default box is valid")
            .threads(1)
            .expect("one thread")
            .analysis(analysis)
    };
    let mut group = c.benchmark_group(format!("free_analysis_{label}"));
    group.sample_size(10);
    let bootstrap = one_thread(Analysis {
        uncertainty: Uncertainty::Bootstrap,
        ..Analysis::FULL
    });
    group.bench_function("exp_bootstrap_200_one_thread", |b| {
        b.iter(|| black_box(bootstrap.fit(&scene, Model::Exp)))
    });
    let compare = one_thread(Analysis::FULL);
    let scenes = std::slice::from_ref(&scene);
    group.bench_function("six_models_5_fold_one_thread", |b| {
        b.iter(|| black_box(compare.fit_all(scenes, &Model::ALL, |_, _| None)))
    });
    group.finish();
}

/// `count` directions on the hemisphere up to 75° from the normal, a
/// Fibonacci spiral (about equal solid angle each): `(θ, φ)`.
fn hemisphere(count: usize) -> Vec<(f64, f64)> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let cos_max = 75f64.to_radians().cos();
    (0..count)
        .map(|i| {
            let cos = 1.0 - (1.0 - cos_max) * (i as f64 + 0.5) / count as f64;
            (cos.acos(), golden * i as f64)
        })
        .collect()
}

/// Every pair of 151 light and 151 view directions (K = 22,801) in the
/// paper's frame: θi, θs and the azimuth between them.
fn texture_geometry() -> Vec<Angles> {
    let directions = hemisphere(151);
    directions
        .iter()
        .flat_map(|&(theta_i, phi_i)| {
            directions.iter().map(move |&(theta_s, phi_s)| {
                Angles::new(theta_i, theta_s, phi_s - phi_i).expect("inside the hemisphere")
            })
        })
        .collect()
}

fn large_k(c: &mut Criterion) {
    let angles = texture_geometry();
    let count = 48;
    let batch = noisy_sets(
        &angles,
        Model::Exp,
        Objective::Free,
        NoiseModel::Every(0.01),
        count,
        5,
    );
    let mut group = c.benchmark_group(format!("free_large_k_{}", angles.len()));
    group.sample_size(10);
    group.throughput(Throughput::Elements(count as u64));
    for (label, analysis, precision) in [
        ("defaults", Analysis::FULL, Precision::F64),
        ("search_only", Analysis::NONE, Precision::F64),
        ("search_only_f32", Analysis::NONE, Precision::F32),
    ] {
        let fitter = Fitter::new(Grid::user())
            .expect("the default box is valid")
            .analysis(analysis)
            .grid_precision(precision);
        group.bench_function(format!("exp_{count}_sets_{label}"), |b| {
            b.iter(|| black_box(fitter.fit_batch(&batch, Model::Exp)))
        });
    }
    group.finish();
}

/// Cornell's `krylon_blue` (1,439 geometries × 31 wavelengths), when
/// `CORNELL_DIR` is set.
fn krylon_blue() -> Option<Vec<Scene>> {
    let dir = std::env::var_os("CORNELL_DIR").or_else(|| {
        eprintln!("SKIPPED the joint fits: CORNELL_DIR is not set");
        None
    })?;
    let set = laminar_brdf_io::astm::read_astm(&Path::new(&dir).join("krylon_blue.astm"))
        .expect("CORNELL_DIR holds krylon_blue.astm");
    Some(set.scenes().expect("its channels make scenes"))
}

/// The joint fit of `exp2` (issue targets: three channels ≤ 0.2 s, all 31
/// wavelengths ≤ 2 s) with the defaults (200 resamples, 5 folds, the
/// tests and the variants) under relative noise.
fn joint(c: &mut Criterion) {
    let Some(all) = krylon_blue() else {
        return;
    };
    let three: Vec<Scene> = ["450nm", "550nm", "650nm"]
        .iter()
        .map(|name| {
            (all.iter().find(|s| s.channel() == *name).cloned())
                .expect("krylon_blue has 450, 550 and 650 nm")
        })
        .collect();
    let fitter = Fitter::new(Grid::user())
        .and_then(|f| {
            f.noise(Noise::Relative {
                floor: laminar_brdf_fit::noise::DEFAULT_FLOOR,
            })
        })
        .expect("the defaults are valid");
    let mut group = c.benchmark_group("joint_krylon_blue");
    group.sample_size(10);
    for (label, scenes) in [("3_channels", &three), ("31_wavelengths", &all)] {
        group.bench_function(format!("exp2_{label}_defaults"), |b| {
            b.iter(|| black_box(fitter.fit_joint(scenes, Model::Exp2).expect("fits")))
        });
    }
    group.finish();
}

criterion_group!(benches, free, analyses, large_k, joint);
criterion_main!(benches);
