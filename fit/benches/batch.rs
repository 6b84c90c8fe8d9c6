//! Batch fitting throughput: `LAMINAR_BATCH_SETS` (default 10,000) synthetic
//! measurement sets on one geometry, fitted with the paper grid and the exp
//! model by [`Fitter::fit_batch`] in blocks of `LAMINAR_BATCH_BLOCK` (default
//! 256) sets; elements = sets, so criterion reports sets per second. The
//! geometry is CUReT sample 21's kept geometry (K = 198) when `CURET_DIR` is
//! set, else the built-in synthetic one (K = 200). Each set is the model at
//! parameters drawn inside the paper grid's range, plus seeded Gaussian
//! noise of 1% of the max ([`synthetic::sets`]). Run: `cargo bench --bench batch`.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use laminar_brdf_core::{Angles, Correlation};
use laminar_brdf_fit::synthetic;
use laminar_brdf_fit::{Analysis, Fitter, Grid, Model, Objective};
use laminar_brdf_io::curet::CuretDir;
use std::hint::black_box;
use std::path::{Path, PathBuf};

fn env_usize(name: &str, default: usize) -> usize {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// The geometry of the sets and its label.
fn geometry() -> (String, Vec<Angles>) {
    match std::env::var_os("CURET_DIR") {
        Some(dir) => {
            let samples = CuretDir::open(Path::new(&dir))
                .and_then(|d| d.samples(&[PathBuf::from("abrdf.dat")], Some(&[21])))
                .expect("CURET_DIR holds table.txt and abrdf.dat with sample 21");
            let scene = samples[0].set.scene("avg").expect("sample 21 fits");
            ("curet".into(), scene.angles().to_vec())
        }
        None => {
            eprintln!("CURET_DIR is not set: using the built-in synthetic geometry");
            ("synthetic".into(), synthetic::geometries())
        }
    }
}

fn batch(c: &mut Criterion) {
    let (label, angles) = geometry();
    let count = env_usize("LAMINAR_BATCH_SETS", 10_000);
    let block = env_usize("LAMINAR_BATCH_BLOCK", 256).max(1);
    let scenes = synthetic::sets(Correlation::Exponential, &angles, count, 0.01, 11);
    // The search's throughput: no refinement or uncertainty after it.
    let fitter = Fitter::new(Grid::paper())
        .expect("the paper grid is valid")
        .objective(Objective::Paper)
        .analysis(Analysis::NONE);
    let mut group = c.benchmark_group(format!("batch_{label}_k{}", angles.len()));
    group.sample_size(10);
    group.throughput(Throughput::Elements(count as u64));
    group.bench_function(format!("exp_{count}_sets"), |b| {
        b.iter(|| {
            for chunk in scenes.chunks(block) {
                black_box(fitter.fit_batch(chunk, Model::Exp));
            }
        })
    });
    group.finish();
}

criterion_group!(benches, batch);
criterion_main!(benches);
