//! `examples/evaluate.c` builds against the committed header and the static
//! library, and prints the Rust core's f32 bits. Needs a C compiler (`cc`);
//! without one it says it was skipped, where the user sees it, unless
//! `LAMINAR_REQUIRE_CC=1` (CI) makes that a failure.

use laminar_brdf_core::{total_radiance, Angles, Correlation, Geometry, Params};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Builds this crate's static library (`cargo test` builds only the rlib)
/// into its own target directory and returns its path.
fn static_library() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let target_dir = dir.join("../target/ffi-c");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let built = Command::new(cargo)
        .current_dir(dir)
        .args(["build", "-p", "laminar-brdf-ffi", "--lib"])
        .env("CARGO_TARGET_DIR", &target_dir)
        .output()
        .expect("cargo runs");
    assert!(
        built.status.success(),
        "{}",
        String::from_utf8_lossy(&built.stderr)
    );
    target_dir.join("debug/liblaminar_brdf_ffi.a")
}

#[test]
fn c_example_prints_the_cores_bits() {
    let dir = env!("CARGO_MANIFEST_DIR");
    let lib = static_library();
    assert!(lib.exists(), "{} was not built", lib.display());
    let exe = std::env::temp_dir().join(format!("laminar-evaluate-{}", std::process::id()));
    let built = Command::new("cc")
        .args(["-std=c99", "-Wall", "-Werror", "-I"])
        .arg(format!("{dir}/include"))
        .arg(format!("{dir}/examples/evaluate.c"))
        .arg(&lib)
        .args(["-lm", "-lpthread", "-ldl", "-o"])
        .arg(&exe)
        .output();
    let built = match built {
        Ok(b) => b,
        Err(e) if std::env::var_os("LAMINAR_REQUIRE_CC").is_none() => {
            let _ = std::io::Write::write_all(
                &mut std::io::stderr(),
                format!("SKIPPED C example: no C compiler `cc` ({e})\n").as_bytes(),
            );
            return;
        }
        Err(e) => panic!("cc: {e}"),
    };
    assert!(
        built.status.success(),
        "{}",
        String::from_utf8_lossy(&built.stderr)
    );
    let run = Command::new(&exe).output().unwrap();
    let _ = std::fs::remove_file(&exe);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let text = String::from_utf8(run.stdout).unwrap();
    let p = Params::new(1.48, 0.39, 1.44, 0.17).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    for (k, line) in lines.iter().take(12).enumerate() {
        let a = Angles::new(
            0.1 * k as f64,
            0.05 + 0.11 * k as f64,
            -2.5 + 0.4 * k as f64,
        )
        .unwrap();
        let v = total_radiance(&Geometry::<f32>::splat(&a), Correlation::Exponential, &p);
        let bits = line.split_whitespace().next().unwrap();
        assert_eq!(bits, format!("{:08x}", v.to_bits()), "geometry {k}");
    }
    assert_eq!(lines[12], "bad n: 5");
    assert_eq!(lines[13], "bad theta_s: 8, out[3] still -1");
    assert_eq!(lines[14], "null output: 1");
    assert_eq!(lines[15], "bad correlation: 2");
    assert_eq!(lines[16], "f32 path same bits: yes");
    // The fit finds the grid point the data came from (f32 rounding
    // leaves a Δ_RMS far below one in a thousand).
    let fit: Vec<&str> = lines[17].split_whitespace().collect();
    assert_eq!(
        fit[..11],
        ["fit:", "status", "0", "slope", "0.68", "beta", "0.60", "n", "1.50", "a", "0.25"],
        "{}",
        lines[17]
    );
    let rms: f64 = fit[12].parse().unwrap();
    assert!(rms < 1e-3, "{}", lines[17]);
    // BAD_DATA (11) for data the library refuses, nothing written; the
    // header's constant compiles; BAD_COUNT (10) above it; BAD_LENGTH (13)
    // for a count no buffer holds; a finite φs outside [−π, π] is valid in
    // double, as the header says.
    assert_eq!(lines[18], "bad data: 11 11, fit untouched: yes");
    assert_eq!(lines[19], "max measurements: 64, too many: 10");
    assert_eq!(lines[20], "huge count: 13");
    assert_eq!(lines[21], "phi_s 7 (double): 0");
    assert_eq!(lines.len(), 22, "{text}");
}
