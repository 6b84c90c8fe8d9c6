//! The Python package (`python/`): built into a virtual environment with
//! maturin and tested with pytest against this crate's `laminar` binary
//! (`python/tests`: results equal the CLI's, errors, the GIL, and the Dask
//! scale-out test when `dask.distributed` is installed).
//!
//! Needs `python3` (or `$LAMINAR_PYTHON`) with `venv`, and the package
//! index for `python/requirements-test.txt` the first time. When either is
//! missing the test says `SKIPPED` on the terminal and passes, unless
//! `LAMINAR_REQUIRE_PYTHON=1` (set by `.ci/run`), when it fails. It runs
//! only when asked (`LAMINAR_REQUIRE_PYTHON` or `LAMINAR_INTEGRATION`): its
//! first build takes minutes.

mod common;

use common::run;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;

fn skip_or_fail(why: &str) {
    common::skip_or_fail("LAMINAR_REQUIRE_PYTHON", "Python package tests", why);
}

#[test]
fn python_package() {
    if let Err(why) = common::integration(
        "LAMINAR_REQUIRE_PYTHON",
        "cargo test -p laminar-brdf --test python",
    ) {
        return skip_or_fail(&why);
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let package = root.join("python");
    let python = std::env::var("LAMINAR_PYTHON").unwrap_or_else(|_| "python3".into());
    if run(Command::new(&python).arg("--version")).is_err() {
        return skip_or_fail(&format!("`{python}` is not available"));
    }
    let scratch = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("python");
    let venv = scratch.join("venv");
    let bin = venv.join("bin");
    if !bin.join("pytest").exists() {
        let made = run(Command::new(&python).args(["-m", "venv"]).arg(&venv)).and_then(|_| {
            run(Command::new(bin.join("python"))
                .args(["-m", "pip", "install", "-q", "-r"])
                .arg(package.join("requirements-test.txt")))
        });
        if let Err(e) = made {
            let _ = std::fs::remove_dir_all(&venv);
            return skip_or_fail(&format!("cannot make the virtual environment: {e}"));
        }
    }
    // Build and install the package (incremental after the first time).
    run(Command::new(bin.join("maturin"))
        .current_dir(&package)
        .args(["develop", "--release", "--quiet"])
        .env("VIRTUAL_ENV", &venv)
        .env("CARGO_TARGET_DIR", scratch.join("target")))
    .unwrap_or_else(|e| panic!("maturin develop: {e}"));
    let mut pytest = Command::new(bin.join("python"));
    pytest
        .current_dir(&package)
        .args([
            "-m",
            "pytest",
            "-q",
            "-rs",
            "-p",
            "no:cacheprovider",
            "--durations=8",
            "tests",
        ])
        .env("LAMINAR_BIN", env!("CARGO_BIN_EXE_laminar"));
    let out = run(&mut pytest).unwrap_or_else(|e| panic!("pytest: {e}"));
    let summary = out
        .lines()
        .filter(|l| {
            // The summary, skips, and the slowest tests (`--durations`).
            l.contains("passed")
                || l.starts_with("SKIPPED")
                || l.contains("s call ")
                || l.contains("s setup ")
        })
        .collect::<Vec<_>>()
        .join("\n");
    let _ = writeln!(std::io::stderr(), "Python package tests: {summary}");
}
