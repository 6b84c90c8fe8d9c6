//! The runner end to end: recovery of known parameters, determinism across
//! thread counts, SIMD/scalar parity, CUReT reading and its error messages,
//! and (with `CURET_DIR`) the paper's 13 samples.

use laminar_core::{Correlation, Params};
use laminar_runner::data::{read_brdf, read_table, Channel};
use laminar_runner::fit::fit;
use laminar_runner::grid::{Axis, Grid};
use laminar_runner::model::Model;
use laminar_runner::search::{error_surface, point, search, Arith, Method, Path};
use laminar_runner::selection::{jobs, Job, PAPER_SAMPLES};
use laminar_runner::synthetic;
use std::path::{Path as FsPath, PathBuf};

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

fn assert_recovered(
    grid: &Grid,
    scene: &laminar_runner::scene::Scene,
    corr: Correlation,
    path: Path,
) {
    let r = search(scene, grid, corr, path, &|| {});
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
        for path in Path::all() {
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
        let reference = error_surface(&scene, &grid, corr, Path::REFERENCE);
        for path in Path::all() {
            let v = error_surface(&scene, &grid, corr, path);
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
        Path::DEFAULT,
        &|| {},
    );
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
        for path in Path::all() {
            let grid = if path.method == Method::Direct {
                small_grid()
            } else {
                test_grid()
            };
            let corr = Correlation::Exponential;
            let r = search(scene, &grid, corr, path, &|| {});
            let surface = error_surface(scene, &grid, corr, path);
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
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                fit(
                    &Job::new("s", Channel::Avg, scene.clone()),
                    Model::Exp,
                    &grid,
                    Path::DEFAULT,
                    &|| {},
                )
            })
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
            let (simd_path, scalar_path) = Path::new(method, Arith::F32x8).twins();
            let simd = error_surface(&scene, &grid, corr, simd_path);
            let scalar = error_surface(&scene, &grid, corr, scalar_path);
            let same = simd
                .iter()
                .zip(&scalar)
                .filter(|(a, b)| a.to_bits() == b.to_bits())
                .count();
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
    let full = fit(
        &Job::new("s", Channel::Avg, scene.clone()),
        Model::Gauss,
        &grid,
        Path::DEFAULT,
        &|| {},
    );
    let rh = fit(
        &Job::new("s", Channel::Avg, scene.clone()),
        Model::RhGauss,
        &grid,
        Path::DEFAULT,
        &|| {},
    );
    assert_eq!(full.rh.as_ref().unwrap().params, rh.best.params);
}

// ---------- CUReT files ----------

fn write(dir: &FsPath, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

const TABLE: &str =
    "1 0.5 0.0 0.4 3.141593\r\n2 0.3 1.0 0.3 -2.141593\r\n3 0.2 0.5 0.6 0.1\r\n4 0.9 -1.0 0.1 2.0";

#[test]
fn crlf_and_missing_final_newline_are_accepted() {
    let d = tempfile::tempdir().unwrap();
    let t = read_table(&write(d.path(), "table.txt", TABLE)).unwrap();
    assert_eq!(t.len(), 4);
    let b = read_brdf(
        &write(d.path(), "abrdf.dat", "1 0.1 0.2 0.3 0.4\n5 1 2 3 -4"),
        4,
    )
    .unwrap();
    assert_eq!(b[1].sample, 5);
}

fn expect_error(dir: &FsPath, table: &str, brdf: &str, samples: Option<&[u32]>, needles: &[&str]) {
    write(dir, "table.txt", table);
    write(dir, "abrdf.dat", brdf);
    let e = jobs(Some(dir), &[], samples).unwrap_err();
    for n in needles {
        assert!(e.contains(n), "error `{e}` lacks `{n}`");
    }
}

#[test]
fn bad_input_errors_name_file_line_and_value() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let ok_brdf = "1 0.1 0.2 0.3 0.4\n";
    expect_error(
        p,
        "1 0.5 0.0 0.4\n",
        ok_brdf,
        None,
        &["table.txt:1", "5 columns"],
    );
    expect_error(
        p,
        "1 0.5 x 0.4 0\n",
        ok_brdf,
        None,
        &["table.txt:1", "`x` is not a number"],
    );
    expect_error(p, "1 0.5 0 NaN 0\n", ok_brdf, None, &["table.txt:1", "NaN"]);
    expect_error(
        p,
        "1 0.5 0 0.4 0\n2 2.0 0 0.4 0\n",
        "1 0.1 0.2\n",
        None,
        &["table.txt:2", "2 polar angle"],
    );
    expect_error(p, "", ok_brdf, None, &["table.txt", "empty"]);
    expect_error(
        p,
        TABLE,
        "1 0.1 0.2 0.3\n",
        None,
        &["abrdf.dat:1", "found 3 values"],
    );
    expect_error(
        p,
        TABLE,
        "1 0.1 0.2 0.3 inf\n",
        None,
        &["abrdf.dat:1", "column 5", "inf"],
    );
    expect_error(
        p,
        TABLE,
        ok_brdf,
        Some(&[99]),
        &["abrdf.dat", "sample 99 not found"],
    );
    expect_error(p, TABLE, "\n\n", None, &["abrdf.dat", "empty"]);
    expect_error(p, TABLE, "x 1 2 3 4\n", None, &["abrdf.dat:1", "`x`"]);
}

#[test]
fn per_channel_files_are_read_and_fitted() {
    let d = tempfile::tempdir().unwrap();
    // A 12-measurement table from the synthetic geometries, one channel per file.
    let angles = synthetic::geometries();
    let mut table = String::new();
    for (i, a) in angles.iter().take(12).enumerate() {
        // Inverse of conventions §1 with φi = 0: φv = φs + π.
        let phi_v = laminar_core::wrap_pi(a.phi_s() + std::f64::consts::PI);
        table += &format!("{} {} {} {} 0\n", i + 1, a.theta_s(), phi_v, a.theta_i());
    }
    write(d.path(), "table.txt", &table);
    for (k, name) in ["rbrdf.dat", "gbrdf.dat", "bbrdf.dat"].iter().enumerate() {
        let values: Vec<String> = (0..12)
            .map(|i| format!("{}", 0.1 + 0.01 * (i + k) as f64))
            .collect();
        write(d.path(), name, &format!("4 {}\n", values.join(" ")));
    }
    let js = jobs(Some(d.path()), &[], Some(&[4])).unwrap();
    let channels: Vec<&str> = js.iter().map(|j| j.channel.name()).collect();
    assert_eq!(channels, ["r", "g", "b"]);
    let grid = Grid {
        slope: Axis::linspace(0.12, 4.04, 5),
        a: Axis::stepped(0.0, 0.25, 5),
        ..Grid::paper()
    };
    for j in &js {
        assert_eq!(j.scene.len(), 12);
        let r = fit(j, Model::Exp, &grid, Path::DEFAULT, &|| {});
        assert!(r.best.rms.is_finite());
    }
}

/// The paper's 13 samples from `CURET_DIR`: exp and gauss fits, the
/// specular exclusion (K = 198) and full-grid SIMD/scalar parity.
#[test]
fn curet_paper_samples_fit_and_match_scalar_twin() {
    let Some(dir) = std::env::var_os("CURET_DIR") else {
        if std::env::var_os("LAMINAR_REQUIRE_CURET").is_some() {
            panic!("LAMINAR_REQUIRE_CURET is set but CURET_DIR is not");
        }
        eprintln!("SKIPPED CUReT end-to-end test: CURET_DIR is not set");
        return;
    };
    let js = jobs(
        Some(FsPath::new(&dir)),
        &[PathBuf::from("abrdf.dat")],
        Some(&PAPER_SAMPLES),
    )
    .unwrap();
    assert_eq!(js.len(), 13);
    let grid = Grid::paper();
    let mut identical = 0usize;
    for j in &js {
        assert_eq!(j.scene.len(), 198, "sample {}", j.sample);
        for (model, corr) in [
            (Model::Exp, Correlation::Exponential),
            (Model::Gauss, Correlation::Gaussian),
        ] {
            let r = fit(j, model, &grid, Path::DEFAULT, &|| {});
            assert!(
                r.best.rms.is_finite() && r.best.rms < 5.0,
                "sample {} {model}: rms {}",
                j.sample,
                r.best.rms
            );
            let rh = r.rh.as_ref().expect("a axis has 0");
            assert!(
                r.best.rms <= rh.rms + 1e-6,
                "absorptive fit worse than its a = 0 slice"
            );
            for method in [Method::OnePass, Method::Envelope] {
                let (simd_path, scalar_path) = Path::new(method, Arith::F32x8).twins();
                let simd = error_surface(&j.scene, &grid, corr, simd_path);
                let scalar = error_surface(&j.scene, &grid, corr, scalar_path);
                let same = simd
                    .iter()
                    .zip(&scalar)
                    .filter(|(a, b)| a.to_bits() == b.to_bits())
                    .count();
                assert_eq!(same, simd.len(), "sample {} {model} {method:?}", j.sample);
                identical += same;
                // The search (which may skip triples) finds the surface's minimum.
                let found = search(&j.scene, &grid, corr, simd_path, &|| {});
                let min = simd.iter().copied().fold(f64::INFINITY, f64::min);
                assert_eq!(
                    found.best_rms.to_bits(),
                    min.to_bits(),
                    "sample {} {model} {method:?}",
                    j.sample
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

/// A CUReT-format directory of `rows` synthetic geometries with samples 19
/// and 21 in `abrdf.dat` and `rbrdf.dat` (radiance made by the exp model).
fn synthetic_curet_dir(rows: usize) -> tempfile::TempDir {
    let d = tempfile::tempdir().unwrap();
    let angles = synthetic::geometries();
    let mut table = String::new();
    for (i, a) in angles.iter().take(rows).enumerate() {
        let phi_v = laminar_core::wrap_pi(a.phi_s() + std::f64::consts::PI);
        table += &format!("{} {} {} {} 0\n", i + 1, a.theta_s(), phi_v, a.theta_i());
    }
    write(d.path(), "table.txt", &table);
    for (file, scale) in [("abrdf.dat", 1.0), ("rbrdf.dat", 0.7)] {
        let mut text = String::new();
        for (sample, beta) in [(19, 0.3), (21, 0.5)] {
            let p = Params::new(1.48, beta, 1.44, 0.2).unwrap();
            let values: Vec<String> = angles[..rows]
                .iter()
                .map(|a| {
                    let g = laminar_core::Geometry::<f64>::splat(a);
                    let l = laminar_core::total_radiance(&g, Correlation::Exponential, &p);
                    // BRDF = radiance / cos θi (conventions §4).
                    format!("{:.6}", scale * l / a.theta_i().cos())
                })
                .collect();
            text += &format!("{sample} {}\n", values.join(" "));
        }
        write(d.path(), file, &text);
    }
    d
}

#[test]
fn reproduce_writes_every_table_and_figure() {
    use laminar_runner::reproduce::{reproduce, FITTED};
    let d = synthetic_curet_dir(40);
    write(d.path(), "op.dat", "21 0.6 0.25 1.0\n");
    let js = jobs(Some(d.path()), &[], Some(&[19, 21])).unwrap();
    assert_eq!(js.len(), 4, "2 samples × (avg, r)");
    let grid = Grid {
        slope: Axis::stepped(1.32, 0.08, 5),
        a: Axis::stepped(0.0, 0.1, 5),
        ..Grid::paper()
    };
    let out = d.path().join("out");
    let r = reproduce(&js, &grid, Path::DEFAULT, &out, &|| {}).unwrap();
    assert_eq!(r.records.len(), 4 * FITTED.len());
    for name in [
        "table2_rms",
        "table3_exp_params",
        "table4_gauss_params",
        "table5_chi2",
    ] {
        let md = std::fs::read_to_string(out.join(format!("{name}.md"))).unwrap();
        let csv = std::fs::read_to_string(out.join(format!("{name}.csv"))).unwrap();
        assert!(md.starts_with("## Table "), "{name}");
        // Header plus one row per (sample, channel).
        assert_eq!(csv.lines().count(), 1 + 4, "{name}:\n{csv}");
        assert!(csv.starts_with("sample,material,channel,"), "{name}");
    }
    let rms = std::fs::read_to_string(out.join("table2_rms.csv")).unwrap();
    assert!(
        rms.starts_with("sample,material,channel,exp,gauss,rh-exp,rh-gauss,jensen,oren-nayar\n")
    );
    assert!(rms.contains("21,Sponge,r,"));
    let fig2 = std::fs::read_to_string(out.join("fig2_transmission_absorption.svg")).unwrap();
    assert!(fig2.contains("<svg") && fig2.contains("a = 0.5"));
    // One data-against-model figure per model (6) and job of samples 19, 21.
    let figures = r
        .files
        .iter()
        .filter(|f| f.to_string_lossy().contains("fig_sample"))
        .count();
    assert_eq!(figures, 6 * 4);
    assert!(out.join("fig_sample21_rh-gauss_r.svg").exists());
    // op.dat supplies sample 21's avg Oren–Nayar parameters: no search there.
    let on = |sample: &str, channel: Channel| {
        r.records
            .iter()
            .find(|x| x.sample == sample && x.channel == channel && x.model == Model::OrenNayar)
            .unwrap()
    };
    let given = on("21", Channel::Avg);
    assert_eq!(given.evaluated, 1);
    assert_eq!(given.best.get("sigma"), Some(0.25));
    assert_eq!(given.best.get("rho"), Some(0.6));
    assert!(
        on("21", Channel::R).evaluated > 1,
        "no opr.dat: grid search"
    );
    assert!(on("19", Channel::Avg).evaluated > 1, "19 not in op.dat");
}

#[test]
fn bad_oren_nayar_files_name_file_line_and_value() {
    let d = synthetic_curet_dir(12);
    for (text, needles) in [
        ("21 0.6 0.25\n", &["op.dat:1", "4 columns"][..]),
        (
            "21 0.6 20 1\n",
            &["op.dat:1", "column 3", "`20`", "radians"],
        ),
        ("21 1.6 0.2 1\n", &["op.dat:1", "column 2", "`1.6`"]),
        ("21 0.5 0.2 1\n21 0.5 0.2 1\n", &["op.dat:2", "twice"]),
        ("21 0.5 x 1\n", &["op.dat:1", "`x` is not a number"]),
    ] {
        write(d.path(), "op.dat", text);
        let e = jobs(Some(d.path()), &[], Some(&[21])).unwrap_err();
        for n in needles {
            assert!(e.contains(n), "error `{e}` lacks `{n}`");
        }
    }
}
