//! `reproduce` end to end on a CUReT-format directory the test writes:
//! tables, figures, given Oren–Nayar parameters, stale figures.

use laminar_brdf::reproduce::{prepare_out_dir, reproduce, FITTED};
use laminar_brdf::selection::curet_jobs;
use laminar_brdf_fit::{Axis, Fitter, Grid, Model, Objective};
use std::path::{Path as FsPath, PathBuf};

fn write(dir: &FsPath, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// A CUReT-format directory of `rows` geometries (none specular) with
/// samples 19 and 21 in `abrdf.dat` and `rbrdf.dat`: smooth made-up BRDFs,
/// enough to fit and draw (the values do not matter here).
fn curet_dir(rows: usize) -> tempfile::TempDir {
    let d = tempfile::tempdir().unwrap();
    let angle = |k: usize, m: usize| 0.1 + 1.3 * (k % m) as f64 / m as f64;
    let table: String = (0..rows)
        .map(|k| {
            format!(
                "{} {} {} {} 0\n",
                k + 1,
                angle(k, 7),
                0.15 * k as f64,
                angle(k, 5)
            )
        })
        .collect();
    write(d.path(), "table.txt", &table);
    for (file, scale) in [("abrdf.dat", 1.0), ("rbrdf.dat", 0.7)] {
        let text: String = [(19, 0.3), (21, 0.5)]
            .iter()
            .map(|(sample, lobe)| {
                let values: Vec<String> = (0..rows)
                    .map(|k| format!("{:.6}", scale * (0.2 + lobe * angle(k, 7).cos())))
                    .collect();
                format!("{sample} {}\n", values.join(" "))
            })
            .collect();
        write(d.path(), file, &text);
    }
    d
}

#[test]
fn reproduce_writes_every_table_and_figure() {
    let d = curet_dir(40);
    write(d.path(), "op.dat", "21 0.6 0.25 1.0\n");
    let js = curet_jobs(d.path(), &[], Some(&[19, 21])).unwrap();
    assert_eq!(js.len(), 4, "2 samples × (avg, r)");
    let grid = Grid {
        slope: Axis::stepped(1.32, 0.08, 5),
        a: Axis::stepped(0.0, 0.1, 5),
        ..Grid::paper()
    };
    let out = d.path().join("out");
    // A stale figure from an earlier run on another sample.
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("fig_sample7_exp_avg.svg"), "<svg/>").unwrap();
    let r = reproduce(
        &Fitter::new(grid).unwrap().objective(Objective::Paper),
        &js,
        &out,
    )
    .unwrap();
    assert_eq!(r.removed, vec![out.join("fig_sample7_exp_avg.svg")]);
    assert!(!out.join("fig_sample7_exp_avg.svg").exists());
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
    // One preview (a lit sphere of the exp fit) per job of samples 19, 21.
    let previews: Vec<_> = r
        .files
        .iter()
        .filter(|f| f.to_string_lossy().contains("fig_preview"))
        .collect();
    assert_eq!(previews.len(), 4);
    let png = std::fs::File::open(out.join("fig_preview_sample21_exp_r.png")).unwrap();
    let info = png::Decoder::new(std::io::BufReader::new(png))
        .read_info()
        .unwrap();
    assert_eq!((info.info().width, info.info().height), (192, 192));
    // op.dat supplies sample 21's avg Oren–Nayar parameters: no search there.
    let on = |sample: &str, channel: &str| {
        r.records
            .iter()
            .find(|x| x.sample == sample && x.channel == channel && x.model == Model::OrenNayar)
            .unwrap()
    };
    let given = on("21", "avg");
    assert_eq!(given.evaluated, 1);
    assert_eq!(given.best.get("sigma"), Some(0.25));
    assert_eq!(given.best.get("rho"), Some(0.6));
    assert!(on("21", "r").evaluated > 1, "no opr.dat: grid search");
    assert!(on("19", "avg").evaluated > 1, "19 not in op.dat");
}

/// `reproduce` replaces its output directory whole, so it refuses one that
/// holds anything it did not write, before any work.
#[test]
fn reproduce_refuses_a_directory_with_other_files() {
    let d = curet_dir(12);
    let out = d.path().join("out");
    std::fs::create_dir_all(&out).unwrap();
    write(&out, "notes.txt", "mine");
    let js = curet_jobs(d.path(), &[], Some(&[21])).unwrap();
    let e = reproduce(
        &Fitter::new(Grid::paper())
            .unwrap()
            .objective(Objective::Paper),
        &js,
        &out,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("notes.txt") && e.contains("new or empty"), "{e}");
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "mine"
    );
    // No staging directory is left behind.
    let leftovers: Vec<_> = std::fs::read_dir(d.path())
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().contains(".partial-"))
        .collect();
    assert!(leftovers.is_empty());
}

/// `reproduce --out` into a new nested directory creates its parents
/// (issue 24: it was refused), and a parent that is a file is still refused.
#[test]
fn reproduce_creates_the_parents_of_a_new_out() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("runs").join("2026").join("out");
    prepare_out_dir(&out).unwrap();
    assert!(out.parent().unwrap().is_dir() && !out.exists());
    let file = write(d.path(), "a-file", "x");
    let e = prepare_out_dir(&file.join("out")).unwrap_err().to_string();
    assert!(e.contains("a-file"), "{e}");
}
