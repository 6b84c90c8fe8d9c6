//! Runs the core's wasm32 build under node and compares every probe value,
//! bit for bit, with the native build: the f32x8 path (wide's scalar
//! fallback, and with `+simd128`), the scalar f32 path and the f64 path.
//!
//! Needs the `wasm32-unknown-unknown` target and `node`. When either is
//! missing the test prints `SKIPPED` and passes, unless
//! `LAMINAR_REQUIRE_WASM=1` (set by `.ci/run`), when it fails.

#[path = "../wasm-probe/src/cases.rs"]
mod cases;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;

fn skip_or_fail(why: &str) {
    if std::env::var_os("LAMINAR_REQUIRE_WASM").is_some() {
        panic!("wasm parity test cannot run: {why}");
    }
    // Written to stderr directly, past the test harness's capture, so that
    // the user sees it.
    let _ = writeln!(
        std::io::stderr(),
        "SKIPPED wasm parity test: {why} (set LAMINAR_REQUIRE_WASM=1 to make this an error)"
    );
}

/// Builds the probe into its own target directory with `rustflags`.
fn build_probe(root: &Path, dir: &str, rustflags: &str) -> Result<PathBuf, String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    // The workspace target directory, beside the workspace root.
    let target_dir = root.join("../target").join(dir);
    let out = Command::new(cargo)
        .current_dir(root)
        .args([
            "build",
            "-p",
            "laminar-wasm-probe",
            "--lib",
            "--target",
            "wasm32-unknown-unknown",
            "--release",
        ])
        .env("CARGO_TARGET_DIR", &target_dir)
        .env("RUSTFLAGS", rustflags)
        .env_remove("CARGO_ENCODED_RUSTFLAGS")
        .output()
        .map_err(|e| format!("cannot run cargo: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "cargo build for wasm32 failed:\n{}",
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    Ok(target_dir.join("wasm32-unknown-unknown/release/laminar_wasm_probe.wasm"))
}

#[test]
fn wasm_build_matches_native_bit_for_bit() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    if Command::new("node").arg("--version").output().is_err() {
        return skip_or_fail("node is not installed");
    }
    let installed = Command::new("rustup")
        .args(["target", "list", "--installed"])
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).contains("wasm32-unknown-unknown"))
        .unwrap_or(false);
    if !installed {
        return skip_or_fail("rustup target wasm32-unknown-unknown is not installed");
    }
    for (dir, flags) in [
        ("wasm-probe", ""),
        ("wasm-probe-simd128", "-C target-feature=+simd128"),
    ] {
        let wasm = build_probe(root, dir, flags).unwrap_or_else(|e| panic!("{e}"));
        let out = Command::new("node")
            .arg(root.join("tests/wasm/probe.mjs"))
            .arg(&wasm)
            .output()
            .expect("node runs");
        assert!(
            out.status.success(),
            "node failed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = String::from_utf8(out.stdout).expect("utf-8");
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len() as u32, cases::count(), "{dir}: probe count");
        let mut mismatches = Vec::new();
        for (i, line) in lines.iter().enumerate() {
            let i = i as u32;
            let f: Vec<u64> = line
                .split(' ')
                .map(|h| u64::from_str_radix(h, 16).expect("hex"))
                .collect();
            let native = [
                cases::value_f32x8(i) as u64,
                cases::value_f32(i) as u64,
                cases::value_f64(i),
            ];
            // Native SIMD must equal native scalar too.
            assert_eq!(
                native[0], native[1],
                "native f32x8 vs f32 differ at value {i}"
            );
            if f != native {
                mismatches.push(format!("value {i}: wasm {f:x?} native {native:x?}"));
            }
        }
        assert!(
            mismatches.is_empty(),
            "{dir}: {} of {} values differ, first: {:?}",
            mismatches.len(),
            lines.len(),
            &mismatches[..mismatches.len().min(5)]
        );
        println!(
            "{dir}: {} values identical to native (f32x8, f32, f64)",
            lines.len()
        );
    }
}
