//! The CUReT reader end to end on files the tests write: line endings,
//! per-channel files, Oren–Nayar parameter files and every error message
//! (file, line, column, value).

use laminar_brdf_core::{Correlation, Params};
use laminar_brdf_fit::{synthetic, Axis, Fitter, Grid, Model, Objective};
use laminar_brdf_io::curet::{read_brdf, read_table, CuretDir, CuretSample};
use std::path::{Path as FsPath, PathBuf};

/// Every sample of every BRDF file in `dir`, as the CLI reads them.
fn jobs(dir: &FsPath, samples: Option<&[u32]>) -> Result<Vec<CuretSample>, String> {
    let d = CuretDir::open(dir).map_err(|e| e.to_string())?;
    let files = d.brdf_files();
    let out = d.samples(&files, samples).map_err(|e| e.to_string())?;
    for s in &out {
        s.set
            .scene(s.channel.name())
            .map_err(|e| format!("{}: {e}", s.file.display()))?;
    }
    Ok(out)
}

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
    let e = jobs(dir, samples).unwrap_err();
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
        // Inverse of docs/conventions.md §1 with φi = 0: φv = φs + π.
        let phi_v = laminar_brdf_core::wrap_pi(a.phi_s() + std::f64::consts::PI);
        table += &format!("{} {} {} {} 0\n", i + 1, a.theta_s(), phi_v, a.theta_i());
    }
    write(d.path(), "table.txt", &table);
    for (k, name) in ["rbrdf.dat", "gbrdf.dat", "bbrdf.dat"].iter().enumerate() {
        let values: Vec<String> = (0..12)
            .map(|i| format!("{}", 0.1 + 0.01 * (i + k) as f64))
            .collect();
        write(d.path(), name, &format!("4 {}\n", values.join(" ")));
    }
    let js = jobs(d.path(), Some(&[4])).unwrap();
    let channels: Vec<&str> = js.iter().map(|j| j.channel.name()).collect();
    assert_eq!(channels, ["r", "g", "b"]);
    let grid = Grid {
        slope: Axis::linspace(0.12, 4.04, 5),
        a: Axis::stepped(0.0, 0.25, 5),
        ..Grid::paper()
    };
    let fitter = Fitter::new(grid).unwrap().objective(Objective::Paper);
    for j in &js {
        let scene = j.set.scene(j.channel.name()).unwrap();
        assert_eq!(scene.len(), 12);
        assert_eq!(scene.channel(), j.channel.name());
        let r = fitter.fit(&scene, Model::Exp);
        assert!(r.best.rms.is_finite());
    }
}

/// A CUReT-format directory of `rows` synthetic geometries with samples 19
/// and 21 in `abrdf.dat` and `rbrdf.dat` (radiance made by the exp model).
fn synthetic_curet_dir(rows: usize) -> tempfile::TempDir {
    let d = tempfile::tempdir().unwrap();
    let angles = synthetic::geometries();
    let mut table = String::new();
    for (i, a) in angles.iter().take(rows).enumerate() {
        let phi_v = laminar_brdf_core::wrap_pi(a.phi_s() + std::f64::consts::PI);
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
                    let g = laminar_brdf_core::Geometry::<f64>::splat(a);
                    let l = laminar_brdf_core::total_radiance(&g, Correlation::Exponential, &p);
                    // BRDF = radiance / cos θi (docs/conventions.md §4).
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
        let e = jobs(d.path(), Some(&[21])).unwrap_err();
        for n in needles {
            assert!(e.contains(n), "error `{e}` lacks `{n}`");
        }
    }
}
