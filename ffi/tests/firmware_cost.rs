//! What the f32 path costs on the emulated Cortex-M4F, at opt-level 3 and
//! "s": instructions and stack per function (the `bench` image under QEMU
//! `-icount`; instructions, not cycles), and the flash of the
//! evaluation-only image (`eval_only`), which must link no `f64` software
//! routine and no panic path. Asserts docs/c.md's targets and prints the
//! table docs/c.md shows. Skips as `common` says.

mod common;

use std::collections::BTreeMap;
use std::io::Write;

/// `name → (instructions, stack bytes)` from the bench image's output.
fn costs(text: &str) -> BTreeMap<String, (f64, u64)> {
    text.lines()
        .filter(|l| *l != "done")
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            assert_eq!(f.len(), 3, "bad bench line `{l}`");
            (
                f[0].to_string(),
                (f[1].parse().unwrap(), f[2].parse().unwrap()),
            )
        })
        .collect()
}

/// Soft-float `f64` routines (and the f32 → f64 conversion) of the ARM EABI.
fn soft_f64(name: &str) -> bool {
    name.starts_with("__aeabi_d") || name == "__aeabi_f2d" || name.starts_with("__adddf")
}

#[test]
fn the_f32_path_meets_its_targets_on_the_cortex_m4() {
    let mut table = String::from(
        "| function | instructions (O3) | stack B (O3) | instructions (s) | stack B (s) |\n|---|---|---|---|---|\n",
    );
    let mut measured = Vec::new();
    let mut fits = String::new();
    for level in ["3", "s"] {
        let Some(images) = common::build("firmware cost test", level) else {
            return;
        };
        let text = common::run(&images.join("bench"), true);
        assert!(text.ends_with("done\n"), "{text}");
        let costs = costs(&text);
        let total_limit = if level == "3" { 450.0 } else { 600.0 };
        for name in ["total_radiance_exp", "total_radiance_gauss"] {
            let (count, _) = costs[name];
            assert!(
                count <= total_limit,
                "{name} at O{level}: {count} instructions > {total_limit}"
            );
        }
        let (geometry, _) = costs["geometry_from_angles_f32"];
        assert!(
            geometry <= 1500.0,
            "geometry at O{level}: {geometry} instructions"
        );

        let eval_only = images.join("eval_only");
        let symbols = common::symbols(&eval_only);
        let soft: Vec<&String> = symbols
            .iter()
            .map(|s| &s.0)
            .filter(|n| soft_f64(n))
            .collect();
        assert!(
            soft.is_empty(),
            "f64 software routines in the f32 image at O{level}: {soft:?}"
        );
        let panics: Vec<&String> = symbols
            .iter()
            .map(|s| &s.0)
            .filter(|n| n.contains("panic"))
            .collect();
        assert!(
            panics.is_empty(),
            "panic paths in the f32 image at O{level}: {panics:?}"
        );
        common::run(&eval_only, false); // and it runs, with every status Ok
        let flash = common::flash_bytes(&eval_only);
        assert!(
            flash <= 4096,
            "evaluation-only image: {flash} bytes of flash at O{level}"
        );
        measured.push((costs, flash));
        if level == "3" {
            fits = fit_lines(&images);
        }
    }
    let (o3, s) = (&measured[0].0, &measured[1].0);
    for (name, (count, stack)) in o3 {
        let (count_s, stack_s) = s[name];
        table += &format!("| `{name}` | {count:.0} | {stack} | {count_s:.0} | {stack_s} |\n");
    }
    table += &format!(
        "| evaluation-only image, flash bytes | {} | | {} | |\n",
        measured[0].1, measured[1].1
    );
    let _ = writeln!(
        std::io::stderr(),
        "Cortex-M4F (QEMU mps2-an386, icount):\n{table}\n{fits}"
    );
}

/// Runs the paper and free fits on the device (O3 only: two minutes of
/// QEMU), checks each against the same call on the host, asserts the free
/// fit's target (≤ 10⁸ instructions at K = 32), and reports their cost.
fn fit_lines(images: &std::path::Path) -> String {
    let text = common::run(&images.join("fit_bench"), true);
    let mut out = String::new();
    for line in text.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        let (objective, host) = match f.first() {
            Some(&"FIT") => {
                let (status, index, rms) =
                    laminar_brdf_ffi::probe::fit_values(f[1].parse().unwrap());
                ("paper", format!("{} {} {:x}", status as u32, index, rms))
            }
            Some(&"FREE") => {
                let (status, index, objective, rms) =
                    laminar_brdf_ffi::probe::free_fit_values(f[1].parse().unwrap());
                let host = format!("{} {} {:x} {:x}", status as u32, index, objective, rms);
                ("free", host)
            }
            _ => continue,
        };
        let (k, count): (usize, f64) = (f[1].parse().unwrap(), f[2].parse().unwrap());
        assert_eq!(
            f[3..].join(" "),
            host,
            "{objective} fit at K = {k}: device vs host"
        );
        assert!(f[3] == "0", "{objective} fit at K = {k}: status {}", f[3]);
        if objective == "free" && k == 32 {
            assert!(
                count <= 1e8,
                "free fit, K = 32: {count} instructions > 10^8"
            );
        }
        out += &format!(
            "{objective} fit, K = {k}: {count:.0} instructions, same result as the host\n"
        );
    }
    assert_eq!(out.lines().count(), 4, "{text}");
    out
}
