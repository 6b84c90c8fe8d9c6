//! Building the firmware images (`ffi/firmware`) and running them in QEMU
//! (`mps2-an386`, a Cortex-M4F), for the firmware tests.
//!
//! Needs the `thumbv7em-none-eabihf` target and `qemu-system-arm`. When
//! one is missing a test prints `SKIPPED` and passes, unless
//! `LAMINAR_REQUIRE_QEMU=1` (set by `.ci/run`), when it fails.

#![allow(dead_code)] // each test binary uses part of it

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Says why the firmware cannot run: fails under `LAMINAR_REQUIRE_QEMU`,
/// else prints `SKIPPED` where the user sees it.
pub fn skip_or_fail(test: &str, why: &str) {
    if std::env::var_os("LAMINAR_REQUIRE_QEMU").is_some() {
        panic!("{test} cannot run: {why}");
    }
    let _ = writeln!(
        std::io::stderr(),
        "SKIPPED {test}: {why} (set LAMINAR_REQUIRE_QEMU=1 to make this an error)"
    );
}

/// Builds every image of `ffi/firmware` at `opt_level` and returns the
/// directory of the images, or `None` (after [`skip_or_fail`]) when QEMU
/// or the target is missing.
pub fn build(test: &str, opt_level: &str) -> Option<PathBuf> {
    if Command::new("qemu-system-arm")
        .arg("--version")
        .output()
        .is_err()
    {
        skip_or_fail(
            test,
            "qemu-system-arm is not installed (Debian: qemu-system-arm)",
        );
        return None;
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("firmware");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let target_dir = dir.join(format!("../../target/firmware-{opt_level}"));
    let built = Command::new(cargo)
        .current_dir(&dir)
        .args(["build", "--release", "--bins"])
        .env("CARGO_TARGET_DIR", &target_dir)
        .env("CARGO_PROFILE_RELEASE_OPT_LEVEL", opt_level)
        .env_remove("RUSTFLAGS")
        .env_remove("CARGO_ENCODED_RUSTFLAGS")
        .output()
        .expect("cargo runs");
    if !built.status.success() {
        let err = String::from_utf8_lossy(&built.stderr);
        if err.contains("thumbv7em-none-eabihf") && err.contains("target may not be installed") {
            skip_or_fail(test, "the thumbv7em-none-eabihf target is not installed");
            return None;
        }
        panic!("firmware build failed:\n{err}");
    }
    Some(target_dir.join("thumbv7em-none-eabihf/release"))
}

/// Runs `image` in QEMU (with `-icount shift=0`, one instruction per
/// virtual nanosecond, when `icount`) and returns what it printed; fails
/// on a non-zero exit or after 300 s.
pub fn run(image: &Path, icount: bool) -> String {
    let mut qemu = Command::new("timeout");
    qemu.args(["300", "qemu-system-arm", "-cpu", "cortex-m4"])
        .args(["-machine", "mps2-an386", "-nographic"])
        .args(["-semihosting-config", "enable=on,target=native"]);
    if icount {
        qemu.args(["-icount", "shift=0,align=off,sleep=off"]);
    }
    let run = qemu.arg("-kernel").arg(image).output().expect("qemu runs");
    assert!(
        run.status.success(),
        "QEMU {}: {:?}\n{}",
        image.display(),
        run.status,
        String::from_utf8_lossy(&run.stderr)
    );
    String::from_utf8(run.stdout).expect("UTF-8 output")
}

/// The names of the symbols defined in the ELF file `image`.
pub fn symbols(image: &Path) -> Vec<(String, u64)> {
    use object::{Object, ObjectSymbol};
    let data = std::fs::read(image).expect("image readable");
    let file = object::File::parse(&*data).expect("an ELF image");
    file.symbols()
        .filter(|s| s.is_definition())
        .filter_map(|s| Some((s.name().ok()?.to_string(), s.size())))
        .collect()
}

/// Bytes of flash the image takes: its allocated sections that are loaded
/// from flash (vector table, code, constants, initialised data).
pub fn flash_bytes(image: &Path) -> u64 {
    use object::{Object, ObjectSection, SectionFlags};
    let data = std::fs::read(image).expect("image readable");
    let file = object::File::parse(&*data).expect("an ELF image");
    file.sections()
        .filter(|s| match s.flags() {
            SectionFlags::Elf { sh_flags } => sh_flags & 2 != 0, // SHF_ALLOC
            _ => false,
        })
        .filter(|s| s.kind() != object::SectionKind::UninitializedData)
        .map(|s| s.size())
        .sum()
}
