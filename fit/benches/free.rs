//! The free-amplitude objective's cost (docs/conventions.md §4b, §11b):
//! one fit with the defaults (grid stage, refinement, 68%/95% profile
//! intervals and the Jacobian), the grid stage alone, and batches of sets
//! on one geometry with the defaults (elements = sets, so criterion reports
//! sets per second). The scene is CUReT sample 21 (K = 198) when
//! `CURET_DIR` is set, else the built-in synthetic one (K = 200); the
//! batch's sets are the model at parameters drawn inside the box plus
//! seeded noise of 1% of the max on every measurement on that geometry.
//! The `free_analysis` group times what docs/estimation.md's analyses cost
//! per set on one thread: the pairs bootstrap (B = 200, on top of the
//! defaults) and the comparison of the six models (each fitted with the
//! defaults and 5-fold cross-validated, then ranked).
//! Run: `cargo bench --bench free`.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use laminar_fit::coverage::{noisy_sets, NoiseModel};
use laminar_fit::synthetic;
use laminar_fit::{Analysis, Fitter, Grid, Model, Objective, Scene, Uncertainty};
use laminar_io::curet::CuretDir;
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
    for model in [Model::Exp, Model::Gauss] {
        let full = fitter(Analysis::FULL);
        group.bench_function(format!("{model}_one_fit_defaults"), |b| {
            b.iter(|| black_box(full.fit(&scene, model)))
        });
    }
    let grid_only = fitter(Analysis::NONE);
    group.bench_function("exp_grid_stage_only", |b| {
        b.iter(|| black_box(grid_only.fit(&scene, Model::Exp)))
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

criterion_group!(benches, free, analyses);
criterion_main!(benches);
