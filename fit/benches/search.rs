//! One full paper-preset fit (exp model) per search path; elements =
//! parameter sets × measurements. Uses CUReT sample 21 when `CURET_DIR` is
//! set, else the built-in synthetic scene. The direct paths run on the first
//! σ/T value only (1/50 of the grid), so their elements are counted on that
//! slice. The `analysis_*` group times one default-path fit with each
//! analysis after the search (none, refinement, profile intervals, both
//! uncertainties): what refinement and uncertainty add to a fit.
//! Run: `cargo bench --bench search`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use laminar_brdf_core::Correlation;
use laminar_brdf_fit::paper::search::search;
use laminar_brdf_fit::{Analysis, Axis, Fitter, Grid, Model, Objective, Scene, Uncertainty};
use laminar_brdf_fit::{Method, SearchPath};
use laminar_brdf_io::curet::CuretDir;
use std::hint::black_box;
use std::path::PathBuf;

fn scene() -> (String, Scene) {
    match std::env::var_os("CURET_DIR") {
        Some(dir) => {
            let samples = CuretDir::open(std::path::Path::new(&dir))
                .and_then(|d| d.samples(&[PathBuf::from("abrdf.dat")], Some(&[21])))
                .expect("CURET_DIR holds table.txt and abrdf.dat with sample 21");
            let scene = samples[0].set.scene("avg").expect("sample 21 fits");
            ("curet-21".into(), scene)
        }
        None => {
            eprintln!("CURET_DIR is not set: benchmarking the built-in synthetic scene");
            (
                "synthetic".into(),
                laminar_brdf_fit::synthetic::default_scene(),
            )
        }
    }
}

fn fits(c: &mut Criterion) {
    let (label, scene) = scene();
    let full = Grid::paper();
    let slice = Grid {
        slope: Axis {
            values: vec![full.slope.values[0]],
        },
        ..full.clone()
    };
    let mut group = c.benchmark_group(format!("fit_{label}"));
    group.sample_size(10);
    for path in SearchPath::all() {
        let grid = if path.method == Method::Direct {
            &slice
        } else {
            &full
        };
        group.throughput(Throughput::Elements((grid.size() * scene.len()) as u64));
        group.bench_function(BenchmarkId::from_parameter(path), |b| {
            b.iter(|| black_box(search(&scene, grid, Correlation::Exponential, path, &|| {})))
        });
    }
    group.finish();
}

fn analysis(c: &mut Criterion) {
    let (label, scene) = scene();
    let mut group = c.benchmark_group(format!("analysis_{label}"));
    group.sample_size(10);
    let cases = [
        ("search_only", Analysis::NONE),
        (
            "refine",
            Analysis {
                refine: true,
                uncertainty: Uncertainty::Off,
                ..Analysis::FULL
            },
        ),
        (
            "refine_profile",
            Analysis {
                refine: true,
                uncertainty: Uncertainty::Profile,
                ..Analysis::FULL
            },
        ),
        ("refine_both", Analysis::FULL),
    ];
    for (name, analysis) in cases {
        let fitter = Fitter::new(Grid::paper())
            .expect("the paper grid is valid")
            .objective(Objective::Paper)
            .analysis(analysis);
        group.bench_function(name, |b| {
            b.iter(|| black_box(fitter.fit(&scene, Model::Exp)))
        });
    }
    group.finish();
}

criterion_group!(benches, fits, analysis);
criterion_main!(benches);
