//! The bad-input matrix (issue 24): every surface of the `laminar` command
//! given input it must refuse, and the faults a run meets (a kill, a full
//! disk, an output that is a directory or under a file). Each case must:
//! exit with status 2; print one `error:` naming the file (and line and
//! column where there is one) and what is wrong; never panic; write
//! nothing at the output path; leave no temporary file behind. The counts
//! per surface are printed (run with `--nocapture` to see them).

mod common;

use common::npy_with_header as npy;
use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

/// One case: the surface it exercises, the arguments (`{d}` is the case's
/// directory, whose files are written first), and what the message holds.
struct Case {
    surface: &'static str,
    args: &'static str,
    files: fn() -> Vec<(&'static str, Vec<u8>)>,
    needles: &'static [&'static str],
}

const GEOMETRY: &[u8] =
    b"theta_i,phi_i,theta_v,phi_v\n0.1,0,0.2,3\n0.3,0,0.4,3\n0.5,0,0.2,1\n0.2,0,0.6,2\n";
const VALUES: &[u8] = b"0.5,0.4,0.3,0.2\n0.4,0.4,0.3,0.1\n";
const MEASUREMENTS: &[u8] =
    b"theta_i,phi_i,theta_v,phi_v,value\n0.1,0,0.2,3,0.5\n0.3,0,0.4,3,0.4\n0.5,0,0.2,1,NaN\n";

/// 2 × 4 little-endian f64 values, the second NaN.
fn with_nan() -> Vec<u8> {
    [0.5, f64::NAN, 0.5, 0.5, 0.4, 0.3, 0.2, 0.1]
        .iter()
        .flat_map(|v: &f64| v.to_le_bytes())
        .collect()
}

const F8: &str = "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 4), }";

const CASES: &[Case] = &[
    // fit-batch: the values file.
    Case {
        surface: "fit-batch values (.npy)",
        args: "fit-batch --geometry {d}/g.csv --values {d}/v.npy --out {d}/out.csv",
        files: || vec![("g.csv", GEOMETRY.to_vec()), ("v.npy", npy(F8, &with_nan()))],
        needles: &["v.npy", "set 1, measurement 2", "NaN is not a finite number"],
    },
    Case {
        surface: "fit-batch values (.npy)",
        args: "fit-batch --geometry {d}/g.csv --values {d}/v.npy --out {d}/out.csv",
        files: || vec![
            ("g.csv", GEOMETRY.to_vec()),
            ("v.npy", npy("{'descr': '<f8', 'fortran_order': False, 'shape': (9, 4), }", &[])),
        ],
        needles: &["v.npy", "set 1: cannot read the data"],
    },
    Case {
        surface: "fit-batch values (.npy)",
        args: "fit-batch --geometry {d}/g.csv --values {d}/v.npy --out {d}/out.csv",
        files: || vec![
            ("g.csv", GEOMETRY.to_vec()),
            ("v.npy", npy("{'descr': '<i4', 'fortran_order': False, 'shape': (2, 4), }", &[0; 32])),
        ],
        needles: &["v.npy", "dtype '<i4'"],
    },
    Case {
        surface: "fit-batch values (.npy)",
        args: "fit-batch --geometry {d}/g.csv --values {d}/v.npy --out {d}/out.csv",
        files: || vec![
            ("g.csv", GEOMETRY.to_vec()),
            ("v.npy", npy("{'descr': '<f8', 'fortran_order': True, 'shape': (2, 4), }", &[0; 64])),
        ],
        needles: &["v.npy", "Fortran order"],
    },
    Case {
        surface: "fit-batch values (.npy)",
        args: "fit-batch --geometry {d}/g.csv --values {d}/v.npy --out {d}/out.csv",
        files: || vec![
            ("g.csv", GEOMETRY.to_vec()),
            ("v.npy", npy("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 4, 1), }", &[0; 64])),
        ],
        needles: &["v.npy", "shape [2, 4, 1]"],
    },
    Case {
        surface: "fit-batch values (.npy)",
        args: "fit-batch --geometry {d}/g.csv --values {d}/v.npy --out {d}/out.csv",
        files: || vec![("g.csv", GEOMETRY.to_vec()), ("v.npy", b"\x93NUMPY\x01\x00\x10".to_vec())],
        needles: &["v.npy", "the header length"],
    },
    Case {
        surface: "fit-batch values (.csv)",
        args: "fit-batch --geometry {d}/g.csv --values {d}/v.csv --out {d}/out.csv",
        files: || vec![("g.csv", GEOMETRY.to_vec()), ("v.csv", b"0.5,0.4,0.3,0.2\n0.5,x,0.3,0.2\n".to_vec())],
        needles: &["v.csv:2: column 2", "`x` is not a finite number"],
    },
    Case {
        surface: "fit-batch values (.csv)",
        args: "fit-batch --geometry {d}/g.csv --values {d}/v.csv --out {d}/out.csv",
        files: || vec![("g.csv", GEOMETRY.to_vec()), ("v.csv", b"0.5,0.4,0.3\n".to_vec())],
        needles: &["v.csv has 3 values per set", "g.csv has 4 geometries"],
    },
    Case {
        surface: "fit-batch values (.csv)",
        args: "fit-batch --geometry {d}/g.csv --values {d}/v.csv --out {d}/out.csv",
        files: || vec![("g.csv", GEOMETRY.to_vec()), ("v.csv", b"-0.5,-0.4,-0.3,-0.2\n".to_vec())],
        needles: &["v.csv", "no positive value"],
    },
    // fit-batch: the geometry file and the options.
    Case {
        surface: "fit-batch geometry",
        args: "fit-batch --geometry {d}/g.csv --values {d}/v.csv --out {d}/out.csv",
        files: || vec![("g.csv", b"theta_i,phi_i,theta_v\n0.1,0,0.2\n".to_vec()), ("v.csv", VALUES.to_vec())],
        needles: &["g.csv:1", "names no geometry"],
    },
    Case {
        surface: "fit-batch geometry",
        args: "fit-batch --geometry {d}/g.csv --values {d}/v.csv --out {d}/out.csv",
        files: || vec![("g.csv", b"theta_i,phi_i,theta_v,phi_v\n0.1,0,2.2,3\n".to_vec()), ("v.csv", VALUES.to_vec())],
        needles: &["g.csv:2: column 3 (theta_v)", "`2.2` is outside [0, π/2]"],
    },
    Case {
        surface: "fit-batch options",
        args: "fit-batch --geometry {d}/g.csv --values {d}/v.csv --models exp,lambert --out {d}/out.csv",
        files: || vec![("g.csv", GEOMETRY.to_vec()), ("v.csv", VALUES.to_vec())],
        needles: &["invalid value 'lambert'", "exp, gauss, exp2, gauss2, rh-exp, rh-gauss, jensen, oren-nayar"],
    },
    Case {
        surface: "fit-batch options",
        args: "fit-batch --geometry {d}/g.csv --values {d}/v.csv --slope 1:2:x --out {d}/out.csv",
        files: || vec![("g.csv", GEOMETRY.to_vec()), ("v.csv", VALUES.to_vec())],
        needles: &["count `x`", "not a positive integer"],
    },
    // fit: measurement files and options.
    Case {
        surface: "fit measurements",
        args: "fit --measurements {d}/m.csv --out {d}/out.csv",
        files: || vec![("m.csv", MEASUREMENTS.to_vec())],
        needles: &["m.csv:4", "value", "NaN"],
    },
    Case {
        surface: "fit measurements",
        args: "fit --measurements {d}/m.csv --out {d}/out.csv",
        files: || vec![("m.csv", b"".to_vec())],
        needles: &["m.csv", "no header line"],
    },
    Case {
        surface: "fit measurements",
        args: "fit --measurements {d}/missing.csv --out {d}/out.csv",
        files: || vec![],
        needles: &["missing.csv", "cannot read"],
    },
    Case {
        surface: "fit measurements",
        args: "fit --data {d}/nodir --samples 21 --out {d}/out.csv",
        files: || vec![],
        needles: &["nodir/table.txt", "cannot read"],
    },
    Case {
        surface: "fit options",
        args: "fit --threads 0 --out {d}/out.csv",
        files: || vec![],
        needles: &["0 worker threads"],
    },
    Case {
        surface: "fit options",
        args: "fit --samples 21 --out {d}/out.csv",
        files: || vec![],
        needles: &["--samples select from a CUReT directory", "give --data DIR"],
    },
    Case {
        surface: "fit options",
        args: "fit --data {d} --samples 0,x --out {d}/out.csv",
        files: || vec![],
        needles: &["--samples: sample `0` is not a positive integer"],
    },
    // predict and export: fitted-model files, selection, geometry.
    Case {
        surface: "fitted-model file",
        args: "predict --fit {d}/f.json --geometry {d}/g.csv --out {d}/out.csv",
        files: || vec![("f.json", b"[1, 2".to_vec()), ("g.csv", GEOMETRY.to_vec())],
        needles: &["f.json:1", "not a laminar fitted-model file"],
    },
    Case {
        surface: "fitted-model file",
        args: "predict --fit {d}/f.json --geometry {d}/g.csv --out {d}/out.csv",
        files: || vec![("f.json", b"{\"format\":\"laminar-fits\",\"version\":99,\"fits\":[]}".to_vec()), ("g.csv", GEOMETRY.to_vec())],
        needles: &["f.json:1", "not a laminar fitted-model file"],
    },
    Case {
        surface: "fitted-model file",
        args: "export --fit {d}/missing.json --merl {d}/out.binary",
        files: || vec![],
        needles: &["missing.json", "cannot read"],
    },
    Case {
        surface: "predict geometry",
        args: "predict --fit {d}/fit.json --select synthetic/avg/exp --geometry {d}/g.csv --out {d}/out.csv",
        files: || vec![("g.csv", b"theta_i,theta_s,phi_s\n0.1,1.7,0.3\n".to_vec())],
        needles: &["g.csv:2: column 2 (theta_s)", "`1.7` is outside [0, π/2]"],
    },
    Case {
        surface: "predict selection",
        args: "predict --fit {d}/fit.json --select 21/avg/exp --geometry {d}/g.csv --out {d}/out.csv",
        files: || vec![("g.csv", GEOMETRY.to_vec())],
        needles: &["fit.json: no fit `21/avg/exp`", "synthetic/avg/exp"],
    },
    Case {
        surface: "predict selection",
        args: "predict --fit {d}/fit.json --geometry {d}/g.csv --out {d}/out.csv",
        files: || vec![("g.csv", GEOMETRY.to_vec())],
        needles: &["fit.json holds 2 fits", "--select"],
    },
    // eval and reproduce.
    Case {
        surface: "eval",
        args: "eval --model exp --slope 1 --beta 0.5 --n 0.5 --a 0 --geometry {d}/g.csv",
        files: || vec![("g.csv", GEOMETRY.to_vec())],
        needles: &["n = 0.5 is outside [1, 10]"],
    },
    Case {
        surface: "eval",
        args: "eval --model exp --slope 1 --beta 0.5 --n 1.5 --a 0 --geometry {d}/g.csv",
        files: || vec![("g.csv", b"theta_i,theta_s,phi_s\n0.1,0.2,inf\n".to_vec())],
        needles: &["g.csv:2: column 3 (phi_s)", "inf"],
    },
    Case {
        surface: "reproduce",
        args: "reproduce --data {d}/nodir --out {d}/out",
        files: || vec![],
        needles: &["nodir/table.txt", "cannot read"],
    },
    // Negative numbers reach each option's own check (issue 39).
    Case {
        surface: "numeric options",
        args: "render --fit {d}/fit.json --select synthetic/avg/exp --out {d}/out.png --environment -1",
        files: || vec![],
        needles: &["--environment -1: must be a finite number ≥ 0"],
    },
    Case {
        surface: "numeric options",
        args: "render --fit {d}/fit.json --select synthetic/avg/exp --out {d}/out.png --size -3",
        files: || vec![],
        needles: &["--size -3: must lie in [16, 4096]"],
    },
    Case {
        surface: "numeric options",
        args: "albedo --fit {d}/fit.json --select synthetic/avg/exp --tolerance -1",
        files: || vec![],
        needles: &["tolerance -1.0: give a relative tolerance from 1e-12"],
    },
    Case {
        surface: "numeric options",
        args: "albedo --fit {d}/fit.json --select synthetic/avg/exp --theta-v -10",
        files: || vec![],
        needles: &["--theta-v: -10° is outside [0, 90]"],
    },
    Case {
        surface: "numeric options",
        args: "albedo --fit {d}/fit.json --select synthetic/avg/exp --tolerance 1e-300",
        files: || vec![],
        needles: &["tolerance 1e-300: give a relative tolerance from 1e-12"],
    },
    Case {
        surface: "numeric options",
        args: "fit --models exp --slope -1:2:3",
        files: || vec![],
        needles: &["slope = -1 is outside"],
    },
    Case {
        surface: "numeric options",
        args: "fit --models exp --folds 1",
        files: || vec![],
        needles: &["--folds", "give 0 (no cross-validation) or a whole number from 2 to 100"],
    },
    // An output whose extension names another format.
    Case {
        surface: "output extension",
        args: "render --fit {d}/fit.json --select synthetic/avg/exp --out {d}/out.jpg",
        files: || vec![],
        needles: &["out.jpg: --out names a JPEG file, but this writes PNG"],
    },
    Case {
        surface: "output extension",
        args: "fit --models exp --format json --out {d}/out.csv",
        files: || vec![],
        needles: &["out.csv: --out names a CSV file, but this writes JSON"],
    },
    Case {
        surface: "output extension",
        args: "predict --fit {d}/fit.json --select synthetic/avg/exp --geometry {d}/g.csv --out {d}/out.json",
        files: || vec![("g.csv", GEOMETRY.to_vec())],
        needles: &["out.json: --out names a JSON file, but this writes CSV"],
    },
    // Faults of the output path.
    Case {
        surface: "output path",
        args: "fit-batch --geometry {d}/g.csv --values {d}/v.csv --out {d}/v.csv",
        files: || vec![("g.csv", GEOMETRY.to_vec()), ("v.csv", VALUES.to_vec())],
        needles: &["v.csv: is also the input", "nothing was written"],
    },
    Case {
        surface: "output path",
        args: "fit-batch --geometry {d}/g.csv --values {d}/v.csv --out {d}/g.csv/out.csv",
        files: || vec![("g.csv", GEOMETRY.to_vec()), ("v.csv", VALUES.to_vec())],
        needles: &["g.csv/out.csv: cannot write", "Not a directory"],
    },
    Case {
        surface: "output path",
        args: "fit --models jensen --out {d}",
        files: || vec![],
        needles: &["cannot write: it is a directory"],
    },
];

fn laminar() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_laminar"));
    c.env_remove("CURET_DIR");
    c
}

/// The names in `dir` (hidden ones included).
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn every_surface_refuses_bad_input_cleanly() {
    let root = tempfile::tempdir().unwrap();
    // A fitted-model file of two fits for the selection cases.
    let fit = root.path().join("fit.json");
    let made = laminar()
        .args(["fit", "--models", "exp,jensen", "--format", "json", "--out"])
        .arg(&fit)
        .output()
        .unwrap();
    assert!(
        made.status.success(),
        "{}",
        String::from_utf8_lossy(&made.stderr)
    );
    let mut counts: BTreeMap<&str, usize> = BTreeMap::new();
    for (k, case) in CASES.iter().enumerate() {
        let d = root.path().join(format!("case{k}"));
        std::fs::create_dir(&d).unwrap();
        std::fs::copy(&fit, d.join("fit.json")).unwrap();
        for (name, bytes) in (case.files)() {
            std::fs::write(d.join(name), bytes).unwrap();
        }
        let before = names(&d);
        let args: Vec<String> = case
            .args
            .split(' ')
            .map(|a| a.replace("{d}", d.to_str().unwrap()))
            .collect();
        let out = laminar().args(&args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        let what = format!("case {k} ({}): laminar {}\n{err}", case.surface, case.args);
        assert_eq!(out.status.code(), Some(2), "{what}");
        assert!(
            err.starts_with("error: ") && !err.contains("panicked"),
            "{what}"
        );
        for n in case.needles {
            assert!(err.contains(n), "`{n}` missing: {what}");
        }
        assert!(out.stdout.is_empty(), "{what}");
        // Nothing written, nothing left behind.
        assert_eq!(names(&d), before, "{what}");
        *counts.entry(case.surface).or_default() += 1;
    }
    eprintln!("bad-input matrix: {} cases", CASES.len());
    for (surface, n) in &counts {
        eprintln!("  {surface}: {n}");
    }
}

/// kill -9 in the middle of a run: the output path holds nothing torn, and
/// the next run removes the temporary file the killed one left.
#[cfg(unix)]
#[test]
fn a_killed_run_leaves_nothing_torn_and_the_next_cleans_up() {
    let d = tempfile::tempdir().unwrap();
    let geometry = d.path().join("g.csv");
    std::fs::write(&geometry, GEOMETRY).unwrap();
    let values = d.path().join("v.csv");
    let row = "0.5,0.4,0.3,0.2\n";
    std::fs::write(&values, row.repeat(200_000)).unwrap();
    let out = d.path().join("out.csv");
    let run = || {
        let mut c = laminar();
        c.args([
            "fit-batch",
            "--refine",
            "off",
            "--uncertainty",
            "off",
            "--geometry",
        ])
        .arg(&geometry)
        .arg("--values")
        .arg(&values)
        .arg("--out")
        .arg(&out);
        c
    };
    let mut child = run().stderr(std::process::Stdio::null()).spawn().unwrap();
    // Killed once its temporary file exists (or after 20 s at most).
    let started = std::time::Instant::now();
    while !names(d.path())
        .iter()
        .any(|n| n.starts_with(".out.csv.tmp-"))
        && started.elapsed().as_secs() < 20
    {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(!out.exists(), "a killed run left {}", out.display());
    let left = names(d.path());
    assert!(
        left.iter().any(|n| n.starts_with(".out.csv.tmp-")),
        "{left:?}"
    );
    let done = run()
        .args(["--slope", "1", "--n", "1.5", "--a", "0"])
        .output()
        .unwrap();
    assert!(
        done.status.success(),
        "{}",
        String::from_utf8_lossy(&done.stderr)
    );
    assert_eq!(names(d.path()), ["g.csv", "out.csv", "v.csv"]);
}

/// A full disk (the file-size limit, `ulimit -f`, with SIGXFSZ ignored, as
/// the disk refusing more bytes): an error naming the output, no output
/// file and no temporary file left.
#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_is_an_error_and_leaves_nothing() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("out.csv");
    let run = Command::new("sh")
        .arg("-c")
        .arg("ulimit -f 1 && trap '' XFSZ && exec \"$0\" fit --models exp,jensen --out \"$1\"")
        .arg(env!("CARGO_BIN_EXE_laminar"))
        .arg(&out)
        .env_remove("CURET_DIR")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{err}");
    assert!(err.contains("out.csv: cannot write"), "{err}");
    assert!(names(d.path()).is_empty(), "{:?}", names(d.path()));
}
