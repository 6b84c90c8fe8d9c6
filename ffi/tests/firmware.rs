//! The C ABI on an emulated Cortex-M4F: builds `ffi/firmware` for
//! `thumbv7em-none-eabihf`, runs it in QEMU (`mps2-an386`), and compares
//! every value it prints with the same call on the host, bit for bit; and
//! checks that the linked image holds no panic path.
//!
//! Needs the `thumbv7em-none-eabihf` target, `qemu-system-arm` and `nm`.
//! When one is missing the test prints `SKIPPED` and passes, unless
//! `LAMINAR_REQUIRE_QEMU=1` (set by `.ci/run`), when it fails.

use laminar_ffi::{laminar_components_f64, laminar_total_radiance_f32, probe, LAMINAR_COMPONENTS};
use std::io::Write;
use std::path::Path;
use std::process::Command;

fn skip_or_fail(why: &str) {
    if std::env::var_os("LAMINAR_REQUIRE_QEMU").is_some() {
        panic!("firmware test cannot run: {why}");
    }
    let _ = writeln!(
        std::io::stderr(),
        "SKIPPED firmware test: {why} (set LAMINAR_REQUIRE_QEMU=1 to make this an error)"
    );
}

/// The line the firmware prints for (geometry, parameters, correlation),
/// computed on the host.
fn host_line(g: u32, j: u32, corr: u32) -> String {
    let (a, p) = (probe::angles(g), probe::params(j));
    let mut total = [0.0f32];
    let mut parts = [0.0f64; LAMINAR_COMPONENTS];
    laminar_total_radiance_f32(corr, p, &a, 1, total.as_mut_ptr());
    laminar_components_f64(corr, p, &a, 1, parts.as_mut_ptr());
    let mut line = format!("{g} {j} {corr} {:08x}", total[0].to_bits());
    for v in parts {
        line += &format!(" {:016x}", v.to_bits());
    }
    line
}

#[test]
fn cortex_m4_gives_the_hosts_bits() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("firmware");
    if Command::new("qemu-system-arm")
        .arg("--version")
        .output()
        .is_err()
    {
        return skip_or_fail("qemu-system-arm is not installed (Debian: qemu-system-arm)");
    }
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let target_dir = dir.join("../../target/firmware");
    let built = Command::new(cargo)
        .current_dir(&dir)
        .args(["build", "--release"])
        .env("CARGO_TARGET_DIR", &target_dir)
        .env_remove("RUSTFLAGS")
        .env_remove("CARGO_ENCODED_RUSTFLAGS")
        .output()
        .expect("cargo runs");
    if !built.status.success() {
        let err = String::from_utf8_lossy(&built.stderr);
        if err.contains("thumbv7em-none-eabihf") && err.contains("target may not be installed") {
            return skip_or_fail("the thumbv7em-none-eabihf target is not installed");
        }
        panic!("firmware build failed:\n{err}");
    }
    let image = target_dir.join("thumbv7em-none-eabihf/release/laminar-firmware");
    let run = Command::new("timeout")
        .arg("120")
        .args([
            "qemu-system-arm",
            "-cpu",
            "cortex-m4",
            "-machine",
            "mps2-an386",
        ])
        .args([
            "-nographic",
            "-semihosting-config",
            "enable=on,target=native",
        ])
        .arg("-kernel")
        .arg(&image)
        .output()
        .expect("qemu runs");
    assert!(
        run.status.success(),
        "QEMU: {:?}\n{}",
        run.status,
        String::from_utf8_lossy(&run.stderr)
    );
    let text = String::from_utf8(run.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let expected = (probe::GEOMETRIES * probe::PARAMS * 2) as usize;
    assert_eq!(lines.len(), expected + 1, "{text}");
    assert_eq!(lines[expected], "done");
    let mut k = 0;
    for g in 0..probe::GEOMETRIES {
        for j in 0..probe::PARAMS {
            for corr in 0..2 {
                assert_eq!(lines[k], host_line(g, j, corr), "line {}", k + 1);
                k += 1;
            }
        }
    }
    let _ = writeln!(
        std::io::stderr(),
        "firmware: {expected} (geometry, parameters, correlation) cases × 8 values identical on the emulated Cortex-M4F and the host"
    );
    // No panic path in the linked image.
    match Command::new("nm").arg(&image).output() {
        Ok(symbols) => {
            let symbols = String::from_utf8_lossy(&symbols.stdout);
            assert!(symbols.lines().count() > 50, "nm read no symbols");
            let panics: Vec<&str> = symbols.lines().filter(|l| l.contains("panic")).collect();
            assert!(panics.is_empty(), "panic paths in the image: {panics:?}");
        }
        Err(e) => skip_or_fail(&format!("nm: {e}")),
    }
}
