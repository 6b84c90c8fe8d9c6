//! A C firmware built by GCC: `ffi/firmware-c/main.c` compiled and linked
//! by Debian's `arm-none-eabi-gcc` (newlib, semihosting) against
//! `include/laminar.h` and the thumbv7em static library, run in QEMU
//! (`mps2-an386`, a Cortex-M4F); the same source built by the host's `cc`
//! against the host's static library. Both must print the same lines, bit
//! for bit, and the linked C image must hold no panic symbol. Needs `arm-none-eabi-gcc` with `libnewlib-arm-none-eabi`,
//! `qemu-system-arm` and `cc`; skips as `common` says (CI requires it).

mod common;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The flags of the Cortex-M4F's hard-float ABI (what `thumbv7em-none-eabihf` uses).
const ARM_FLAGS: [&str; 4] = [
    "-mcpu=cortex-m4",
    "-mthumb",
    "-mfloat-abi=hard",
    "-mfpu=fpv4-sp-d16",
];

/// Builds laminar-brdf-ffi's static library for `target` (`None`: the host)
/// into `target/firmware-c` and returns its path.
fn static_library(target: Option<&str>) -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let target_dir = dir.join("../target/firmware-c");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let mut c = Command::new(cargo);
    c.current_dir(dir)
        .args([
            "rustc",
            "-p",
            "laminar-brdf-ffi",
            "--release",
            "--crate-type",
            "staticlib",
        ])
        .env("CARGO_TARGET_DIR", &target_dir)
        .env_remove("RUSTFLAGS")
        .env_remove("CARGO_ENCODED_RUSTFLAGS");
    if let Some(t) = target {
        c.args(["--target", t]);
    }
    let built = c.output().expect("cargo runs");
    assert!(
        built.status.success(),
        "{}",
        String::from_utf8_lossy(&built.stderr)
    );
    match target {
        Some(t) => target_dir.join(t).join("release/liblaminar_brdf_ffi.a"),
        None => target_dir.join("release/liblaminar_brdf_ffi.a"),
    }
}

/// Runs `command`, failing with its stderr unless it succeeds.
fn ok(command: &mut Command) -> Vec<u8> {
    let out = command
        .output()
        .unwrap_or_else(|e| panic!("{command:?}: {e}"));
    assert!(
        out.status.success(),
        "{command:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

#[test]
fn gcc_firmware_prints_the_hosts_bits() {
    const TEST: &str = "C firmware test";
    for (tool, packages) in [
        (
            "arm-none-eabi-gcc",
            "gcc-arm-none-eabi libnewlib-arm-none-eabi",
        ),
        ("qemu-system-arm", "qemu-system-arm"),
    ] {
        if Command::new(tool).arg("--version").output().is_err() {
            return common::skip_or_fail(
                TEST,
                &format!("{tool} is not installed (Debian: {packages})"),
            );
        }
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let (src, include) = (dir.join("firmware-c"), dir.join("include"));
    let scratch = dir.join("../target/firmware-c");
    std::fs::create_dir_all(&scratch).unwrap();

    // The device: exactly the command line of docs/c.md's firmware section.
    let image = scratch.join("laminar-c-firmware.elf");
    ok(Command::new("arm-none-eabi-gcc")
        .args(ARM_FLAGS)
        .args([
            "-std=c99",
            "-O2",
            "-Wall",
            "-Werror",
            "-ffunction-sections",
            "-fdata-sections",
            "-I",
        ])
        .arg(&include)
        .arg(src.join("main.c"))
        .arg(src.join("startup.c"))
        .arg(static_library(Some("thumbv7em-none-eabihf")))
        .args(["-nostartfiles", "-T"])
        .arg(src.join("link.ld"))
        .args([
            "-Wl,--gc-sections",
            "-Wl,-z,noexecstack",
            "--specs=rdimon.specs",
            "-lc",
            "-lrdimon",
            "-lm",
            "-o",
        ])
        .arg(&image));
    let device = common::run(&image, false);

    // The host: the same source, the host's static library.
    let host_exe = scratch.join("laminar-c-firmware-host");
    ok(Command::new("cc")
        .args(["-std=c99", "-O2", "-Wall", "-Werror", "-I"])
        .arg(&include)
        .arg(src.join("main.c"))
        .arg(static_library(None))
        .args(["-lm", "-lpthread", "-ldl", "-o"])
        .arg(&host_exe));
    let host = String::from_utf8(ok(&mut Command::new(&host_exe))).expect("UTF-8");

    let (d, h): (Vec<&str>, Vec<&str>) = (device.lines().collect(), host.lines().collect());
    assert_eq!(d.len(), h.len(), "device:\n{device}\nhost:\n{host}");
    for (k, (d, h)) in d.iter().zip(&h).enumerate() {
        assert_eq!(d, h, "line {}", k + 1);
    }
    // What the lines say: every evaluation OK; the statuses of bad input
    // (BAD_N 5 with the output untouched, BAD_CORRELATION 2, NULL_POINTER
    // 1, BAD_PHI_S 9, BAD_LENGTH 13); the fit OK at the data's grid point
    // (σ/T 1.2, n 1.5, a 0.25), BAD_DATA 11 and BAD_COUNT 10 at the end.
    assert_eq!(d[0], "geometry: 0");
    assert!(d[1..7].iter().all(|l| l.contains(": 0 ")), "{device}");
    assert_eq!(
        d[7..12],
        [
            "bad n: 5, out[0] bf800000",
            "bad correlation: 2",
            "null geometries: 1",
            "bad phi_s: 9",
            "huge count: 13"
        ]
    );
    assert!(d[12].starts_with("fit: 0 "), "{}", d[12]);
    assert_eq!(d[13], "fit slope 3ff3333333333333");
    assert_eq!(d[15], "fit n 3ff8000000000000");
    assert_eq!(d[16], "fit a 3fd0000000000000");
    // The free fit OK at the same point (its β and amplitude in closed
    // form), weighted too; BAD_SIGMA 14 and EMPTY_AXIS 12 (an empty β box).
    assert!(d[19].starts_with("free fit: 0 "), "{}", d[19]);
    assert_eq!(d[20], "free fit slope 3ff3333333333333");
    assert_eq!(d[22], "free fit n 3ff8000000000000");
    assert_eq!(d[23], "free fit a 3fd0000000000000");
    assert_eq!(
        d[27],
        d[19]
            .replace("free fit:", "free fit weighted:")
            .split(" rh")
            .next()
            .unwrap()
    );
    assert_eq!(
        d[28..],
        [
            "free fit bad sigma: 14",
            "free fit empty beta box: 12",
            "fit bad data: 11",
            "fit too many: 10 (at most 64)",
            "done"
        ]
    );
    // The link-time proof that the shipped library has no panic path: the
    // C image, linked with --gc-sections from everything the firmware
    // calls (evaluation, geometry, the fit), holds no panic symbol.
    let symbols = common::symbols(&image);
    assert!(symbols.len() > 50, "read no symbols");
    let panics: Vec<&String> = symbols
        .iter()
        .map(|(name, _)| name)
        .filter(|n| n.contains("panic") || n.contains("slice_index_fail") || n.contains("unwind"))
        .collect();
    assert!(panics.is_empty(), "panic paths in the C image: {panics:?}");
    let _ = writeln!(
        std::io::stderr(),
        "C firmware (arm-none-eabi-gcc, newlib, QEMU mps2-an386): {} lines, the host's bits; image {} bytes of flash",
        d.len(),
        common::flash_bytes(&image)
    );
}
