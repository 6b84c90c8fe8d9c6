//! The npm package (`wasm/`) and the web page (`web/`):
//!
//! * the package's values are bitwise the native library's (f32 and f64,
//!   plain and `+simd128` builds, under node);
//! * `npm pack` makes a package that a TypeScript project imports, type-checks
//!   (`tsc`, strict) and runs;
//! * the page, in Debian's Chromium driven by playwright-core: the built-in
//!   example fitted in the page gives the fitted-model file of `laminar fit`
//!   on the same data byte for byte, the parameter table shows its numbers,
//!   a slider redraws the lobe, and a screenshot is saved
//!   (`target/web-test/page.png`).
//!
//! Needs node and npm, the `wasm32-unknown-unknown` target, `wasm-bindgen`
//! of the version pinned in `wasm/Cargo.toml`, the npm registry once (for
//! `web/package.json`'s typescript and playwright-core), and for the page
//! `/usr/bin/chromium` (or `$CHROMIUM`). When one is missing the tests say
//! `SKIPPED` on the terminal and pass, unless `LAMINAR_REQUIRE_WEB=1` (set
//! by `.ci/run`), when they fail. They run only when asked
//! (`LAMINAR_REQUIRE_WEB` or `LAMINAR_INTEGRATION`): building the package
//! takes minutes.

mod common;

use common::{run, stdout};
use laminar_brdf_core::{probe, total_radiance, Angles, Correlation, Geometry, Params};
use laminar_brdf_fit::Model;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

fn skip_or_fail(why: &str) {
    common::skip_or_fail("LAMINAR_REQUIRE_WEB", "web tests", why);
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn scratch(name: &str) -> PathBuf {
    let dir = root().join("target/web-test").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

/// The built package (`target/npm`) and its `npm pack` tarball.
struct Package {
    dir: PathBuf,
    tarball: PathBuf,
}

/// Builds the package once for all the tests: `Err` says why it cannot be
/// built here (a missing tool); a failing build panics.
fn package() -> Result<&'static Package, String> {
    static PACKAGE: OnceLock<Result<Package, String>> = OnceLock::new();
    PACKAGE
        .get_or_init(|| {
            common::integration(
                "LAMINAR_REQUIRE_WEB",
                "cargo test -p laminar-brdf --test web",
            )?;
            for tool in ["node", "npm", "wasm-bindgen"] {
                run(Command::new(tool).arg("--version"))
                    .map_err(|e| format!("`{tool}` is not available ({e})"))?;
            }
            let targets = run(Command::new("rustup").args(["target", "list", "--installed"]));
            if !targets.is_ok_and(|t| t.contains("wasm32-unknown-unknown")) {
                return Err("the wasm32-unknown-unknown target is not installed".into());
            }
            let root = root();
            let dir = root.join("target/npm");
            let built = run(Command::new("bash")
                .arg(root.join("wasm/build.sh"))
                .arg(&dir)
                .env_remove("CARGO_TARGET_DIR")
                .env_remove("CARGO_ENCODED_RUSTFLAGS"));
            if let Err(e) = built {
                if e.contains("cargo install --locked wasm-bindgen-cli") {
                    return Err(e);
                }
                panic!("wasm/build.sh: {e}");
            }
            let packs = scratch("pack");
            let name = stdout(
                Command::new("npm")
                    .current_dir(&dir)
                    .args(["pack", "--silent", "--pack-destination"])
                    .arg(&packs),
            )
            .unwrap_or_else(|e| panic!("npm pack: {e}"));
            Ok(Package {
                tarball: packs.join(name.trim()),
                dir,
            })
        })
        .as_ref()
        .map_err(Clone::clone)
}

/// `web/node_modules` (typescript, playwright-core, vite), installed by `npm ci`
/// when missing.
fn web_tools() -> Result<PathBuf, String> {
    common::integration(
        "LAMINAR_REQUIRE_WEB",
        "cargo test -p laminar-brdf --test web",
    )?;
    let web = root().join("web");
    let modules = web.join("node_modules");
    let tools = ["typescript", "playwright-core", "@types/node", "vite"];
    if !tools.iter().all(|t| modules.join(t).exists()) {
        run(Command::new("npm")
            .current_dir(&web)
            .args(["ci", "--no-audit", "--no-fund"]))
        .map_err(|e| format!("cannot install web/package.json's tools: {e}"))?;
    }
    Ok(modules)
}

/// Strict `tsc` (web/package.json's) on the TypeScript project `project`.
fn tsc(tools: &Path, project: &Path) -> Result<String, String> {
    run(Command::new("node")
        .arg(tools.join("typescript/bin/tsc"))
        .arg("-p")
        .arg(project))
}

/// Geometries: the core's probe cases and a lattice over the whole domain
/// (1,441, not a multiple of 8, so the f32x8 path pads its last chunk).
fn geometries() -> Vec<Angles> {
    let mut out: Vec<Angles> = (0..probe::GEOMETRIES)
        .map(|g| {
            let (ti, ts, ps) = probe::angles(g);
            Angles::new(ti, ts, ps).expect("probe angles")
        })
        .collect();
    let half_pi = std::f64::consts::FRAC_PI_2;
    for i in 0..17 {
        for j in 0..9 {
            for k in 0..9 {
                let (ti, ts) = (half_pi * i as f64 / 16.0, half_pi * j as f64 / 8.0);
                let ps = std::f64::consts::PI * (k as f64 / 4.0 - 1.0);
                out.push(Angles::new(ti, ts, ps).expect("lattice angles"));
            }
        }
    }
    out
}

#[test]
fn npm_package_gives_the_native_bits() {
    let package = match package() {
        Ok(p) => p,
        Err(why) => return skip_or_fail(&why),
    };
    let angles = geometries();
    let params: Vec<(f64, f64, f64, f64)> = (0..probe::PARAMS).map(probe::params).collect();
    let models = [
        ("exp", Correlation::Exponential),
        ("gauss", Correlation::Gaussian),
    ];
    let cases = serde_json::json!({
        "angles": angles.iter().flat_map(|a| [a.theta_i(), a.theta_s(), a.phi_s()]).collect::<Vec<_>>(),
        "params": params.iter().map(|&(s, b, n, a)| [s, b, n, a]).collect::<Vec<_>>(),
        "models": models.iter().map(|m| m.0).collect::<Vec<_>>(),
    });
    let dir = scratch("bitwise");
    std::fs::write(dir.join("cases.json"), cases.to_string()).expect("cases");
    let out = stdout(
        Command::new("node")
            .arg(root().join("wasm/tests/bitwise.mjs"))
            .arg(&package.dir)
            .arg(dir.join("cases.json")),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let got: serde_json::Value = serde_json::from_str(&out).expect("bitwise.mjs prints JSON");

    let (mut f32_bits, mut f64_bits) = (Vec::new(), Vec::new());
    for (_, corr) in models {
        for &(s, b, n, a) in &params {
            let p = Params::new(s, b, n, a).expect("probe params");
            for g in &angles {
                f32_bits.push(total_radiance(&Geometry::<f32>::splat(g), corr, &p).to_bits());
                let v = total_radiance(&Geometry::<f64>::splat(g), corr, &p).to_bits();
                f64_bits.extend([(v >> 32) as u32, v as u32]);
            }
        }
    }
    for build in ["plain", "simd", "eval_plain", "eval_simd"] {
        let side = &got[build];
        assert_eq!(
            side["build"],
            build.ends_with("simd"),
            "{build}: load() gave the other build"
        );
        for (name, native) in [("f32", &f32_bits), ("f64", &f64_bits)] {
            let wasm: Vec<u32> = serde_json::from_value(side[name].clone()).expect("bits");
            assert_eq!(wasm.len(), native.len(), "{build} {name}: count");
            let differ = wasm.iter().zip(native).filter(|(w, n)| w != n).count();
            assert_eq!(
                differ, 0,
                "{build} {name}: {differ} values differ from native"
            );
        }
    }
    // The evaluation-only package's predictFitted is the whole package's
    // predict, bit for bit (f64 values as u32 halves).
    let fitted = &got["fitted"];
    assert!(fitted["compared"].as_u64().unwrap_or(0) > 0, "{fitted}");
    assert_eq!(
        fitted["differ"], 0,
        "predictFitted against predict: {fitted}"
    );
    let _ = writeln!(
        std::io::stderr(),
        "npm package: {} f32 and {} f64 values per build, whole and eval packages, plain and \
         +simd128, bitwise native; eval's predictFitted equals predict on {} values",
        f32_bits.len(),
        f64_bits.len() / 2,
        fitted["compared"]
    );
}

/// The gzip size (level 9) of `path`.
fn gzip_size(path: &Path) -> usize {
    let out = Command::new("gzip")
        .args(["-9", "-c"])
        .arg(path)
        .output()
        .expect("gzip runs");
    assert!(out.status.success(), "gzip {}", path.display());
    out.stdout.len()
}

/// The sizes docs/javascript.md states: its table's rows (`| build | .wasm
/// | gzip -9 |`) by the build's directory, and the `npm pack` tarball's.
struct DocumentedSizes {
    wasm: Vec<(&'static str, usize, usize)>,
    tarball: usize,
}

/// A number written with thousands separators (`1,031,967`).
fn bytes(text: &str) -> Option<usize> {
    text.trim()
        .trim_end_matches(" B")
        .replace(',', "")
        .parse()
        .ok()
}

/// Reads [`DocumentedSizes`] from docs/javascript.md.
fn documented_sizes() -> DocumentedSizes {
    let doc =
        std::fs::read_to_string(root().join("docs/javascript.md")).expect("docs/javascript.md");
    let rows = [
        ("| whole, plain", "plain"),
        ("| whole, `+simd128`", "simd"),
        ("| eval, plain", "eval/plain"),
        ("| eval, `+simd128`", "eval/simd"),
    ];
    let wasm = rows
        .iter()
        .map(|&(start, dir)| {
            let line = doc
                .lines()
                .find(|l| l.starts_with(start))
                .unwrap_or_else(|| panic!("docs/javascript.md: no size row `{start}`"));
            let cells: Vec<&str> = line.split('|').collect();
            match (
                cells.get(2).and_then(|c| bytes(c)),
                cells.get(3).and_then(|c| bytes(c)),
            ) {
                (Some(raw), Some(gzip)) => (dir, raw, gzip),
                _ => panic!("docs/javascript.md: the row `{line}` has no sizes in bytes"),
            }
        })
        .collect();
    let tarball = doc
        .lines()
        .find_map(|l| {
            let after = l.split(".tgz, ").nth(1)?;
            bytes(after.split(" B").next()?)
        })
        .expect("docs/javascript.md: no `<name>.tgz, <bytes> B`");
    DocumentedSizes { wasm, tarball }
}

/// Whether a documented size is within 2% of the measured one.
fn near(documented: usize, measured: usize) -> bool {
    documented.abs_diff(measured) * 50 <= measured
}

/// The evaluation-only package (`laminar-brdf/eval`) fits a page's budget:
/// each build's `.wasm` at most 40 KiB gzip; and docs/javascript.md's sizes
/// (each build's `.wasm`, plain and gzip, and the tarball) are within 2% of
/// the built ones. Needs binaryen's `wasm-opt` (wasm/build.sh runs it on the
/// eval builds).
#[test]
fn evaluation_only_package_fits_40_kib_and_docs_state_the_sizes() {
    let package = match package() {
        Ok(p) => p,
        Err(why) => return skip_or_fail(&why),
    };
    if run(Command::new("wasm-opt").arg("--version")).is_err() {
        return skip_or_fail(
            "binaryen's `wasm-opt` is not available (the eval package's size needs it)",
        );
    }
    let documented = documented_sizes();
    let mut line = Vec::new();
    let mut stale = Vec::new();
    for &(dir, doc_raw, doc_gzip) in &documented.wasm {
        let wasm = package.dir.join(dir).join("laminar_wasm_bg.wasm");
        let raw = std::fs::metadata(&wasm).expect("the built .wasm").len() as usize;
        let size = gzip_size(&wasm);
        if dir.starts_with("eval") {
            assert!(
                size <= 40 * 1024,
                "{dir}: {size} bytes gzip, more than 40 KiB"
            );
        }
        if !near(doc_raw, raw) || !near(doc_gzip, size) {
            stale.push(format!(
                "{dir}: documented {doc_raw} B, {doc_gzip} B gzip; built {raw} B, {size} B gzip"
            ));
        }
        line.push(format!("{dir} {raw} B, {size} B gzip"));
    }
    let tarball = std::fs::metadata(&package.tarball)
        .expect("the tarball")
        .len() as usize;
    if !near(documented.tarball, tarball) {
        stale.push(format!(
            "the tarball: documented {} B; packed {tarball} B",
            documented.tarball
        ));
    }
    let _ = writeln!(
        std::io::stderr(),
        "wasm sizes: {}; tarball {tarball} B",
        line.join("; ")
    );
    assert!(
        stale.is_empty(),
        "docs/javascript.md's sizes are stale (more than 2% off):\n{}",
        stale.join("\n")
    );
}

/// The packed package in a bundler: a minimal Vite app
/// (`wasm/tests/vite-app`) importing both entry points builds with `vite
/// build` against the tarball, with no Node built-in externalised, and runs
/// in Chromium (`web/tests/bundler.mjs`): every build of both packages
/// loads, each `.wasm` fetched with status 200, no page or console error,
/// and the values are the native library's bits.
#[test]
fn packed_package_runs_bundled_by_vite_in_chromium() {
    let chromium = std::env::var("CHROMIUM").unwrap_or_else(|_| "/usr/bin/chromium".into());
    if !Path::new(&chromium).exists() {
        return skip_or_fail(&format!(
            "no Chromium at {chromium} (apt-get install chromium)"
        ));
    }
    let (package, tools) = match package().and_then(|p| web_tools().map(|t| (p, t))) {
        Ok(p) => p,
        Err(why) => return skip_or_fail(&why),
    };
    let project = scratch("vite-app");
    for f in ["index.html", "main.js", "package.json"] {
        std::fs::copy(root().join("wasm/tests/vite-app").join(f), project.join(f)).expect("copy");
    }
    run(Command::new("npm")
        .current_dir(&project)
        .args(["install", "--no-audit", "--no-fund", "--offline"])
        .arg(&package.tarball))
    .unwrap_or_else(|e| panic!("npm install of the packed tarball: {e}"));
    let built = run(Command::new("node")
        .current_dir(&project)
        .arg(tools.join("vite/bin/vite.js"))
        .arg("build"))
    .unwrap_or_else(|e| panic!("vite build: {e}"));
    assert!(
        !built.contains("externalized for browser compatibility"),
        "vite build externalised a Node built-in:\n{built}"
    );
    let out = stdout(
        Command::new("node")
            .arg(root().join("web/tests/bundler.mjs"))
            .arg(project.join("dist"))
            .env("CHROMIUM", &chromium),
    )
    .unwrap_or_else(|e| panic!("the bundled app in Chromium: {e}"));
    let v: serde_json::Value = serde_json::from_str(&out).expect("bundler.mjs prints JSON");
    let p = Params::new(1.2, 0.4, 1.4, 0.3).expect("params");
    let native: Vec<String> = [(0.3, 0.2, 0.5), (0.9, 0.4, 2.5)]
        .iter()
        .map(|&(ti, ts, ps)| {
            let a = Angles::new(ti, ts, ps).expect("angles");
            let t = total_radiance(&Geometry::<f64>::splat(&a), Correlation::Exponential, &p);
            format!("{:016x}", t.to_bits())
        })
        .collect();
    for build in ["whole/plain", "whole/simd", "eval/plain", "eval/simd"] {
        assert_eq!(
            v["result"][build],
            serde_json::json!(native),
            "{build} in the bundled app: {out}"
        );
    }
    let fetched = v["wasm"].as_array().expect("the fetched .wasm files");
    assert!(
        fetched.len() >= 4 && fetched.iter().all(|f| f["status"] == 200),
        "the .wasm fetches: {out}"
    );
    let _ = writeln!(
        std::io::stderr(),
        "the packed package bundled by Vite runs in Chromium: {} .wasm files fetched, the native bits",
        fetched.len()
    );
}

/// Every export of the package, both builds, called with 3,000 seeded
/// draws of arguments of every JavaScript type (`wasm/tests/arguments.mjs`):
/// each call returns or throws an `Error`, never traps, and leaves the
/// module working.
#[test]
fn npm_package_survives_arguments_of_every_type() {
    let package = match package() {
        Ok(p) => p,
        Err(why) => return skip_or_fail(&why),
    };
    let out = stdout(
        Command::new("node")
            .arg(root().join("wasm/tests/arguments.mjs"))
            .arg(&package.dir)
            .arg("3000"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let got: serde_json::Value = serde_json::from_str(&out).expect("arguments.mjs prints JSON");
    for build in ["plain", "simd"] {
        let t = &got[build];
        assert_eq!(t["calls"], 3000, "{build}: {t}");
        // The draws reach both sides of the boundary.
        for key in ["returned", "typeErrors", "errors"] {
            assert!(t[key].as_u64().unwrap_or(0) > 0, "{build}: no {key}: {t}");
        }
    }
    let _ = writeln!(std::io::stderr(), "npm arguments: {got}");
}

#[test]
fn packed_package_imports_in_typescript() {
    let package = match package().and_then(|p| web_tools().map(|t| (p, t))) {
        Ok(p) => p,
        Err(why) => return skip_or_fail(&why),
    };
    let (package, tools) = package;
    // The tarball carries the licence texts, and its README no placeholder link.
    let listing = stdout(Command::new("tar").arg("tzf").arg(&package.tarball))
        .unwrap_or_else(|e| panic!("tar tzf: {e}"));
    for licence in ["package/LICENSE-MIT", "package/LICENSE-APACHE"] {
        assert!(
            listing.lines().any(|l| l == licence),
            "{licence} missing from the tarball:\n{listing}"
        );
    }
    let readme = std::fs::read_to_string(package.dir.join("README.md")).expect("README.md");
    assert!(
        !readme.contains("](https://github.com/)"),
        "the npm README links to a placeholder"
    );
    let project = scratch("ts-example");
    for f in ["example.ts", "tsconfig.json", "package.json"] {
        std::fs::copy(
            root().join("wasm/tests/ts-example").join(f),
            project.join(f),
        )
        .expect("copy");
    }
    run(Command::new("npm")
        .current_dir(&project)
        .args(["install", "--no-audit", "--no-fund", "--offline"])
        .arg(&package.tarball))
    .unwrap_or_else(|e| panic!("npm install of the packed tarball: {e}"));
    tsc(&tools, &project).unwrap_or_else(|e| panic!("tsc: {e}"));
    let out = stdout(
        Command::new("node")
            .current_dir(&project)
            .arg("dist/example.js"),
    )
    .unwrap_or_else(|e| panic!("the compiled example: {e}"));
    let v: serde_json::Value = serde_json::from_str(&out).expect("the example prints JSON");
    assert_eq!(
        v["simd"], true,
        "node has WebAssembly SIMD: load() should pick it"
    );
    assert_eq!(v["message"], "beta = 1.5 is outside [0, 1]");
    // The package lists every model of the descriptor and fits each by its
    // name; every correlation's name evaluates.
    let names: Vec<&str> = Model::ALL.iter().map(|m| m.name()).collect();
    assert_eq!(v["models"], serde_json::json!(names));
    assert_eq!(v["fittedModels"], serde_json::json!(names));
    let params: Vec<String> = Model::ALL
        .iter()
        .map(|m| {
            m.params()
                .iter()
                .map(|p| p.name())
                .collect::<Vec<_>>()
                .join(",")
        })
        .collect();
    assert_eq!(v["modelParams"], serde_json::json!(params));
    let correlations: Vec<&str> = Correlation::ALL.iter().map(|c| c.name()).collect();
    assert_eq!(v["correlations"], serde_json::json!(correlations));
    assert_eq!(v["lobes"], serde_json::json!(vec![2; correlations.len()]));
    // `laminar-brdf/eval` types and runs: the same bits as the whole package.
    assert_eq!(
        (&v["evalSame"], &v["evalSimd"]),
        (&true.into(), &true.into()),
        "{v}"
    );
    assert_eq!(
        v["evalErrors"],
        serde_json::json!([
            "normalisation constant amplitude = -1: a finite number ≥ 0 is needed",
            "TypeError: fitted.params.beta: give a number (got undefined)"
        ])
    );
    // Every bad input is a JS Error naming what is wrong.
    let errors: Vec<String> = serde_json::from_value(v["errors"].clone()).expect("errors");
    assert_eq!(
        errors,
        [
            "geometry 0: theta_s = 2 is outside [0, π/2]",
            "angles has 2 numbers: give (theta_i, theta_s, phi_s) triples, radians",
            "model `lambert`: give `exp` or `gauss`",
            "slope = 0 is outside [1e-3, 1e3]",
            // The library's selection rule: an exp fit's a = 0 best is a candidate too.
            "select `example/value/gauss` matches no fit; the file holds example/value/exp, \
             example/value/rh-exp",
            "fitted-model file:1: column 2: not a laminar fitted-model file (missing field `format` \
             at line 1 column 2); write one with `laminar fit --format json`",
            "example: no channel `r` (channels: value)",
            "angles: unknown angle unit `grad` (expected rad or deg)",
            "options.n: count `x` in axis `1.5:1.3:x` is not a positive integer",
            "options.refine: give true or false",
            "options.objective: unknown objective `max` (expected free or paper)",
        ]
    );
    // Wrong types are TypeErrors naming the argument (a number for a model
    // name trapped; '1.2' for a number was coerced).
    let type_errors: Vec<String> =
        serde_json::from_value(v["typeErrors"].clone()).expect("typeErrors");
    assert_eq!(
        type_errors,
        [
            "TypeError: model: give a string (got the number 3)",
            "TypeError: slope: give a number (got the string \"1.2\")",
            "TypeError: angles: give a Float64Array (or an array of numbers) (got the string \"angles\")",
            "TypeError: angles[1]: give a number (got the string \"0.2\")",
            "TypeError: select: give a string (got the number 7)",
            "TypeError: bytes: give a Uint8Array (got the string \"text\")",
            "TypeError: channel: give a string (got the number 5)",
        ]
    );
    assert_eq!(
        v["fromArray"], v["total"][0],
        "an array of numbers as a Float64Array"
    );
    // A fit from its own onProgress: it runs, the outer fit gets all its
    // three shards' calls, and the Measurements object is not left borrowed.
    assert_eq!(
        (&v["inner"], &v["outerCalls"]),
        (&"rh-exp".into(), &3.into())
    );
    assert_eq!(v["afterNested"], "value");
    // The options reach the fitter: a one-point σ/T, n, a grid, one shard.
    let custom = &v["custom"];
    assert_eq!(
        (&custom["slope"], &custom["n"], &custom["a"]),
        (&1.48.into(), &1.44.into(), &0.17.into()),
        "{custom}"
    );
    assert_eq!(v["customCalls"], 1);
    assert_eq!(
        v["calls"], 50,
        "the paper objective: one progress call per σ/T value"
    );
    assert_eq!(v["freeCalls"], 1, "the free objective: one call per fit");
    assert_eq!(v["freeObjective"], "free");
    let free_box: Vec<f64> = serde_json::from_value(v["freeBox"].clone()).expect("a box");
    assert_eq!(free_box, [1.0, 2.5]);
    assert_eq!(v["predicted"], v["measured"]);
    let p = Params::new(1.2, 0.4, 1.4, 0.3).expect("params");
    let a = Angles::new(0.3, 0.2, 0.5).expect("angles");
    let native = total_radiance(&Geometry::<f64>::splat(&a), Correlation::Exponential, &p);
    assert_eq!(
        v["total"][0].as_f64(),
        Some(native),
        "f64 total through the package"
    );
    let _ = writeln!(std::io::stderr(), "TypeScript example: {out}");
}

/// The ```ts blocks of the README and of docs/, each with the first line of
/// its block (page:line).
fn typescript_blocks() -> Vec<(String, String)> {
    let mut blocks = Vec::new();
    for page in common::doc_pages() {
        let text = std::fs::read_to_string(&page).expect("the page reads");
        let name = page
            .file_name()
            .expect("a name")
            .to_string_lossy()
            .to_string();
        for lines in common::code_blocks(&text, "ts") {
            // The fence's line, as the page shows it.
            let at = lines.first().map_or(0, |(k, _)| k - 1);
            let code: String = lines.iter().map(|(_, l)| format!("{l}\n")).collect();
            blocks.push((format!("{name}:{at}"), code));
        }
    }
    blocks
}

/// Every TypeScript block of the docs type-checks (strict `tsc`) against
/// the packed package and runs under node, in a project holding a
/// fitted-model file `fits.json` (docs/testing.md).
#[test]
fn the_docs_typescript_compiles_and_runs() {
    let (package, tools) = match package().and_then(|p| web_tools().map(|t| (p, t))) {
        Ok(p) => p,
        Err(why) => return skip_or_fail(&why),
    };
    let blocks = typescript_blocks();
    assert!(blocks.len() >= 2, "the docs' TypeScript blocks: {blocks:?}");
    let project = scratch("ts-docs");
    std::fs::copy(
        root().join("wasm/tests/ts-example/package.json"),
        project.join("package.json"),
    )
    .expect("copy");
    let files: Vec<String> = (0..blocks.len()).map(|k| format!("doc{k}.ts")).collect();
    let config = std::fs::read_to_string(root().join("wasm/tests/ts-example/tsconfig.json"))
        .expect("tsconfig")
        .replace(
            "\"files\": [\"example.ts\"]",
            &format!("\"files\": {files:?}"),
        )
        .replace(
            "\"types\": []",
            &format!(
                "\"types\": [\"node\"], \"typeRoots\": [{:?}]",
                tools.join("@types")
            ),
        );
    std::fs::write(project.join("tsconfig.json"), config).expect("tsconfig");
    for (file, (_, code)) in files.iter().zip(&blocks) {
        std::fs::write(project.join(file), code).expect("a block");
    }
    run(Command::new("npm")
        .current_dir(&project)
        .args(["install", "--no-audit", "--no-fund", "--offline"])
        .arg(&package.tarball))
    .unwrap_or_else(|e| panic!("npm install: {e}"));
    run(Command::new(env!("CARGO_BIN_EXE_laminar"))
        .current_dir(&project)
        .args([
            "fit",
            "--models",
            "exp",
            "--format",
            "json",
            "--out",
            "fits.json",
        ]))
    .unwrap_or_else(|e| panic!("laminar fit: {e}"));
    tsc(&tools, &project).unwrap_or_else(|e| panic!("tsc on the docs' blocks {blocks:?}: {e}"));
    for (file, (at, _)) in files.iter().zip(&blocks) {
        let js = format!("dist/{}", file.replace(".ts", ".js"));
        run(Command::new("node").current_dir(&project).arg(&js))
            .unwrap_or_else(|e| panic!("{at} ({js}): {e}"));
    }
    let _ = writeln!(
        std::io::stderr(),
        "docs' TypeScript: {} blocks compiled and ran",
        blocks.len()
    );
}

#[test]
fn page_fits_in_chromium_as_the_cli_does() {
    let chromium = std::env::var("CHROMIUM").unwrap_or_else(|_| "/usr/bin/chromium".into());
    if !Path::new(&chromium).exists() {
        return skip_or_fail(&format!(
            "no Chromium at {chromium} (apt-get install chromium)"
        ));
    }
    let package = match package().and_then(|p| web_tools().map(|_| p)) {
        Ok(p) => p,
        Err(why) => return skip_or_fail(&why),
    };
    let root = root();
    let dir = scratch("page");
    let site = dir.join("site");
    run(Command::new("bash")
        .arg(root.join("web/build.sh"))
        .arg(&site)
        .env("NPM_PACKAGE", &package.dir))
    .unwrap_or_else(|e| panic!("web/build.sh: {e}"));
    // The page's built-in example, fitted by the CLI.
    let example = dir.join("example.csv");
    let csv = stdout(
        Command::new("node")
            .arg("--input-type=module")
            .arg("-e")
            .arg(format!(
        "const {{ load }} = await import({:?}); process.stdout.write((await load()).exampleCsv());",
        format!("file://{}", package.dir.join("node.js").display())
    )),
    )
    .unwrap_or_else(|e| panic!("exampleCsv: {e}"));
    std::fs::write(&example, csv).expect("example.csv");
    let expected = dir.join("expected.json");
    run(Command::new(env!("CARGO_BIN_EXE_laminar"))
        .args(["fit", "--measurements"])
        .arg(&example)
        .args([
            "--quantity",
            "radiance",
            "--models",
            "exp",
            "--format",
            "json",
            "--out",
        ])
        .arg(&expected))
    .unwrap_or_else(|e| panic!("laminar fit: {e}"));
    // The same example with every model compared.
    let comparison = dir.join("comparison.json");
    let every = Model::ALL.map(|m| m.name()).join(",");
    run(Command::new(env!("CARGO_BIN_EXE_laminar"))
        .args(["fit", "--measurements"])
        .arg(&example)
        .args(["--quantity", "radiance", "--models", &every])
        .args(["--format", "json", "--out"])
        .arg(&comparison))
    .unwrap_or_else(|e| panic!("laminar fit --models {every}: {e}"));
    // Cornell's blue paint (RGB), fitted jointly by the CLI, when the data
    // are here.
    let joint = match std::env::var_os("CORNELL_DIR") {
        Some(cornell) => {
            let data = Path::new(&cornell).join("krylon_blue_RGB.astm");
            let out = dir.join("joint.json");
            run(Command::new(env!("CARGO_BIN_EXE_laminar"))
                .args(["fit-joint", "--measurements"])
                .arg(&data)
                .args(["--model", "exp2", "--noise", "relative", "--fits"])
                .arg(&out))
            .unwrap_or_else(|e| panic!("laminar fit-joint: {e}"));
            Some((data, out))
        }
        None => {
            common::skip_or_fail(
                "LAMINAR_REQUIRE_CORNELL",
                "the page's joint fit",
                "CORNELL_DIR is not set",
            );
            None
        }
    };
    let screenshot = root.join("target/web-test/page.png");
    let mut browser = Command::new("node");
    browser
        .arg(root.join("web/tests/browser.mjs"))
        .arg(&site)
        .arg(&expected)
        .arg(&screenshot)
        .arg(&comparison)
        .env("CHROMIUM", &chromium);
    if let Some((data, out)) = &joint {
        browser.arg(data).arg(out);
    }
    let out = stdout(&mut browser).unwrap_or_else(|e| panic!("{e}"));
    let _ = writeln!(
        std::io::stderr(),
        "Chromium page test passed; screenshot {}; {out}",
        screenshot.display()
    );
}
