//! The C ABI on an emulated Cortex-M4F: builds `ffi/firmware` for
//! `thumbv7em-none-eabihf`, runs its probe image in QEMU (`mps2-an386`),
//! and compares every value it prints with the same calls on the host,
//! bit for bit; and checks that the linked image holds no panic path.
//! Skips as `common` says.

mod common;

use laminar_brdf_ffi::probe;
use std::io::Write;

/// The lines the firmware prints, computed on the host.
fn host_lines() -> Vec<String> {
    let mut lines = Vec::new();
    for g in 0..probe::GEOMETRIES {
        let mut line = format!("G {g}");
        for v in probe::geometry_values(g) {
            line += &format!(" {v:08x}");
        }
        lines.push(line);
        for j in 0..probe::PARAMS {
            for corr in 0..2 {
                let mut line = format!("{g} {j} {corr}");
                for v in probe::case_values(g, j, corr) {
                    line += &format!(" {v:x}");
                }
                lines.push(line);
            }
        }
    }
    lines.push("done".into());
    lines
}

#[test]
fn cortex_m4_gives_the_hosts_bits() {
    let Some(images) = common::build("firmware test", "3") else {
        return;
    };
    let image = images.join("laminar-firmware");
    let text = common::run(&image, false);
    let got: Vec<&str> = text.lines().collect();
    let want = host_lines();
    assert_eq!(got.len(), want.len(), "{text}");
    for (k, (got, want)) in got.iter().zip(&want).enumerate() {
        assert_eq!(got, want, "line {}", k + 1);
    }
    let cases = probe::GEOMETRIES * probe::PARAMS * 2;
    let _ = writeln!(
        std::io::stderr(),
        "firmware: {cases} cases × {} values and {} geometries × 16 fields identical on the emulated Cortex-M4F and the host",
        probe::CASE_VALUES,
        probe::GEOMETRIES
    );
    // No panic path in the linked image.
    let symbols = common::symbols(&image);
    assert!(symbols.len() > 50, "read no symbols");
    let panics: Vec<&String> = symbols
        .iter()
        .map(|(name, _)| name)
        .filter(|name| name.contains("panic"))
        .collect();
    assert!(panics.is_empty(), "panic paths in the image: {panics:?}");
}

#[test]
fn probe_geometries_build() {
    // Every probe geometry is inside the f32 constructors' domain, so the
    // device comparison covers their values, not their error codes.
    for g in 0..probe::GEOMETRIES {
        let (a, d) = probe::f32_geometries(g);
        assert!(a.is_ok() && d.is_ok(), "geometry {g}: {a:?} {d:?}");
    }
}
