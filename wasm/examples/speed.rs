//! The native library on the work `wasm/bench/speed.js` gives the package:
//! eq. 8 at 100,000 geometries (f64, and f32 in f32x8 lanes), and one fit of
//! the built-in example on the paper grid (search alone, and with
//! refinement and both uncertainties), the best of several runs.
//!
//! `RAYON_NUM_THREADS=1 cargo run --release -p laminar-wasm --example speed`
//! (one thread, as in the browser).

use laminar_brdf_fit::Analysis;
use laminar_brdf_fit::Settings;
use laminar_wasm::evaluate::{total_radiance_f32, total_radiance_f64};
use laminar_wasm::fitting::fit;
use laminar_wasm::measurements::{example_csv, Measurements};
use std::time::Instant;

fn best(runs: usize, mut f: impl FnMut()) -> f64 {
    (0..runs)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64() * 1e3
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() {
    let k = 100_000;
    let deg = std::f64::consts::PI / 180.0;
    let angles: Vec<f64> = (0..k)
        .flat_map(|i| {
            [
                (i % 89) as f64 * deg,
                ((i * 7) % 89) as f64 * deg,
                ((i % 360) as f64 - 180.0) * deg,
            ]
        })
        .collect();
    let ok = "valid input";
    let rate = |f: &dyn Fn()| k as f64 / (best(5, f) / 1e3);
    let f64_per_s = rate(&|| {
        total_radiance_f64("exp", &angles, 1.2, 0.4, 1.4, 0.3).expect(ok);
    });
    let f32_per_s = rate(&|| {
        total_radiance_f32("exp", &angles, 1.2, 0.4, 1.4, 0.3).expect(ok);
    });
    let m = Measurements::from_csv("example.csv", example_csv().as_bytes(), "rad", "radiance")
        .expect(ok);
    let search = Settings {
        analysis: Analysis::NONE,
        ..Settings::default()
    };
    let search_ms = best(5, || {
        fit(&m, "value", "exp", &search, None).expect(ok);
    });
    let full_fit_ms = best(3, || {
        fit(&m, "value", "exp", &Settings::default(), None).expect(ok);
    });
    println!(
        "{{\"threads\": {}, \"f64_per_s\": {f64_per_s:.0}, \"f32_per_s\": {f32_per_s:.0}, \"search_ms\": {search_ms:.2}, \"full_fit_ms\": {full_fit_ms:.2}}}",
        rayon_threads()
    );
}

fn rayon_threads() -> usize {
    std::env::var("RAYON_NUM_THREADS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}
