//! Per-component throughput of the model (Fresnel, absorption, surface G/E,
//! subsurface, total) in scalar `f64`, scalar `f32` and `f32x8`; elements =
//! geometries evaluated. Run: `cargo bench --bench components`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use laminar_brdf_core::{
    absorption_factor, f32x8, fresnel, inverse_slope_squared, subsurface_radiance,
    surface_radiance, total_radiance, Angles, Correlation, Geometry, Interface, Lane, Params,
};
use std::hint::black_box;

/// 200 geometries: θi, θs on a 10 × 10 grid of [5°, 77°] × [3°, 75°], φs ∈ {−2.5, 0.9}.
fn geometries() -> Vec<Angles> {
    let deg = std::f64::consts::PI / 180.0;
    (0..200)
        .map(|k| {
            let (i, s, phi) = (k / 20, (k / 2) % 10, [-2.5, 0.9][k % 2]);
            let ti = (5.0 + 8.0 * i as f64) * deg;
            let ts = (3.0 + 8.0 * s as f64) * deg;
            Angles::new(ti, ts, phi).expect("in range")
        })
        .collect()
}

/// The 200 geometries packed into `L::LANES`-wide vectors.
fn packed<L: Lane>() -> Vec<Geometry<L>> {
    let angles = geometries();
    angles
        .chunks(L::LANES)
        .map(|c| Geometry::from_lanes(|i| c[i.min(c.len() - 1)]))
        .collect()
}

/// Benchmarks `f` over every packed geometry for one arithmetic.
fn run<L: Lane>(c: &mut Criterion, component: &str, arith: &str, f: impl Fn(&Geometry<L>) -> L) {
    let geoms = packed::<L>();
    let mut group = c.benchmark_group(component);
    group.throughput(Throughput::Elements((geoms.len() * L::LANES) as u64));
    group.bench_function(BenchmarkId::from_parameter(arith), |b| {
        b.iter(|| {
            let mut acc = L::c(0.0);
            for g in &geoms {
                acc = acc + f(black_box(g));
            }
            black_box(acc)
        })
    });
    group.finish();
}

/// Every component in one arithmetic.
fn all<L: Lane>(c: &mut Criterion, arith: &str) {
    let p = Params::new(1.48, 0.39, 1.44, 0.17).expect("valid");
    let (n, a) = (L::c(p.n()), L::c(p.a()));
    let inv_s2 = inverse_slope_squared(L::c(p.slope()));
    run::<L>(c, "fresnel", arith, |g| fresnel(g.cos_i, n));
    run::<L>(c, "absorption", arith, |g| absorption_factor(g, a));
    for (name, corr) in [
        ("surface_gaussian", Correlation::Gaussian),
        ("surface_exponential", Correlation::Exponential),
    ] {
        run::<L>(c, name, arith, |g| surface_radiance(g, corr, inv_s2));
    }
    run::<L>(c, "subsurface_exponential", arith, |g| {
        subsurface_radiance(
            g,
            &Interface::new(g, n),
            Correlation::Exponential,
            inv_s2,
            a,
        )
    });
    run::<L>(c, "total_exponential", arith, |g| {
        total_radiance(g, Correlation::Exponential, &p)
    });
}

fn components(c: &mut Criterion) {
    all::<f64>(c, "f64");
    all::<f32>(c, "f32");
    all::<f32x8>(c, "f32x8");
}

criterion_group!(benches, components);
criterion_main!(benches);
