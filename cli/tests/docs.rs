//! Every command in the README's and `docs/`'s `sh` blocks runs, so the
//! docs cannot go stale (docs/testing.md):
//! - each `laminar …` line (and `cargo run … -p laminar-brdf -- …`) runs
//!   through the built binary, in the order of its page, in a directory of
//!   its own holding the files the pages name (`felt.csv`,
//!   `directions.csv`, `geometry.csv`, `values.npy`), and must succeed;
//!   `$CURET_DIR`, `$CORNELL_DIR` and `$RGL_DIR` are the data directories
//!   (a command on one is skipped, with a message, without it; the
//!   `LAMINAR_REQUIRE_CURET`, `_CORNELL` and `_RGL` variables make that an
//!   error);
//! - every other command must be one [`RUN_ELSEWHERE`] names, with the file
//!   that runs it, and that file must still mention it.
//!
//! The Python blocks run in `python/tests/test_docs.py`, the TypeScript ones
//! in `cli/tests/web.rs`, the Rust ones as doctests of `laminar-brdf`.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

/// Commands of the docs run by another test or by `.ci/run`: (the start of
/// the command, the file that runs it, what that file says when it does).
const RUN_ELSEWHERE: &[(&str, &str, &str)] = &[
    ("cargo test --workspace", ".ci/run", "cargo test --workspace"),
    ("pip install ./python", ".ci/run", "pip install ./python"),
    (
        "rustup target add wasm32-unknown-unknown",
        ".ci/run",
        "rustup target add thumbv7em-none-eabihf wasm32-unknown-unknown",
    ),
    (
        "rustup target add thumbv7em-none-eabihf",
        ".ci/run",
        "rustup target add thumbv7em-none-eabihf wasm32-unknown-unknown",
    ),
    (
        "cargo install --locked wasm-bindgen-cli --version",
        ".ci/run",
        "cargo install --locked wasm-bindgen-cli --version",
    ),
    ("bash wasm/build.sh", "cli/tests/web.rs", "wasm/build.sh"),
    ("(cd target/npm && npm pack)", "cli/tests/web.rs", "\"pack\""),
    ("bash web/build.sh", "cli/tests/web.rs", "web/build.sh"),
    (
        "cargo build -p laminar-brdf-ffi --release",
        "ffi/tests/c_example.rs",
        "\"build\", \"-p\", \"laminar-brdf-ffi\"",
    ),
    (
        "cc -std=c99 -I ffi/include ffi/examples/evaluate.c",
        "ffi/tests/c_example.rs",
        "examples/evaluate.c",
    ),
    (
        "cargo rustc -p laminar-brdf-ffi --release --target thumbv7em-none-eabihf --crate-type staticlib",
        ".ci/run",
        "cargo rustc -p laminar-brdf-ffi --release --target thumbv7em-none-eabihf --crate-type staticlib",
    ),
    (
        "arm-none-eabi-gcc -mcpu=cortex-m4",
        "ffi/tests/firmware_c.rs",
        "arm-none-eabi-gcc",
    ),
    (
        "qemu-system-arm -cpu cortex-m4 -machine mps2-an386",
        "ffi/tests/firmware_c.rs",
        "mps2-an386",
    ),
    (
        "python python/examples/mitsuba_sphere.py",
        "python/tests/test_render.py",
        "from mitsuba_sphere import render",
    ),
    (
        "python python/examples/mitsuba_texture.py",
        "python/tests/test_render_native.py",
        "from mitsuba_texture import fitted_texture, scene_dict",
    ),
    (
        "python python/examples/mitsuba_inverse.py",
        "python/tests/test_render_native.py",
        "from mitsuba_inverse import GUESS, TRUTH, recover",
    ),
];

/// The prefix that runs the CLI from the source tree, as the README's
/// main job does.
const CARGO_RUN: &str = "cargo run --release -p laminar-brdf -- ";

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// One command of a code block: its page, its first line there, the text.
struct Shell {
    page: String,
    line: usize,
    text: String,
}

/// The commands of the `sh` blocks of `page`: continuation lines joined,
/// comments (a `#` after a blank, outside quotes) cut.
fn shell_commands(page: &Path) -> Vec<Shell> {
    let text = std::fs::read_to_string(page).expect("the page reads");
    let name = page
        .strip_prefix(root())
        .unwrap_or(page)
        .display()
        .to_string();
    let mut out = Vec::new();
    let mut pending: Option<Shell> = None;
    for (k, line) in common::code_blocks(&text, "sh").into_iter().flatten() {
        let code = strip_comment(line);
        let (body, continues) = match code.trim_end().strip_suffix('\\') {
            Some(body) => (body.to_string(), true),
            None => (code.trim_end().to_string(), false),
        };
        let command = pending.get_or_insert_with(|| Shell {
            page: name.clone(),
            line: k,
            text: String::new(),
        });
        command.text.push(' ');
        command.text.push_str(body.trim());
        if !continues {
            let done = pending.take().expect("a command in progress");
            if !done.text.trim().is_empty() {
                out.push(Shell {
                    text: done.text.trim().to_string(),
                    ..done
                });
            }
        }
    }
    assert!(pending.is_none(), "{name}: a block ends in a continuation");
    out
}

/// `line` without its shell comment.
fn strip_comment(line: &str) -> &str {
    let mut quote = None;
    let mut previous = ' ';
    for (i, c) in line.char_indices() {
        match (quote, c) {
            (None, '\'' | '"') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            (None, '#') if previous.is_whitespace() => return &line[..i],
            _ => {}
        }
        previous = c;
    }
    line
}

/// The CUReT directory, or why there is none.
fn curet_dir() -> Result<PathBuf, String> {
    let dir = std::env::var_os("CURET_DIR").ok_or("CURET_DIR is not set")?;
    let dir = PathBuf::from(dir);
    if dir.join("table.txt").is_file() && dir.join("abrdf.dat").is_file() {
        Ok(dir)
    } else {
        Err(format!(
            "CURET_DIR={} lacks table.txt or abrdf.dat",
            dir.display()
        ))
    }
}

/// Runs `laminar args…` in `dir`: stdout and stderr, or the failure.
fn laminar(dir: &Path, args: &[String]) -> Result<String, String> {
    common::run(
        Command::new(env!("CARGO_BIN_EXE_laminar"))
            .current_dir(dir)
            .args(args)
            .env_remove("CURET_DIR"),
    )
}

/// The lab-frame geometry of the fixtures, in degrees: θi, φi, θv, φv
/// (no specular pair: no θv equals a θi).
fn geometry_degrees() -> Vec<[f64; 4]> {
    let mut g = Vec::new();
    for theta_i in [10.0, 25.0, 40.0, 55.0, 70.0] {
        for theta_v in [5.0, 20.0, 35.0, 50.0, 65.0] {
            for phi_v in [0.0, 60.0, 120.0, 180.0, 240.0, 300.0] {
                g.push([theta_i, 0.0, theta_v, phi_v]);
            }
        }
    }
    g
}

fn geometry_csv(g: &[[f64; 4]]) -> String {
    let mut text = String::from("theta_i,phi_i,theta_v,phi_v\n");
    for row in g {
        text += &format!("{},{},{},{}\n", row[0], row[1], row[2], row[3]);
    }
    text
}

/// The model's BRDF (eq. 8's total over cos θi) at `g` (degrees), from
/// `laminar eval`.
fn brdf(dir: &Path, g: &[[f64; 4]], slope: f64) -> Vec<f64> {
    std::fs::write(dir.join("eval-geometry.csv"), geometry_csv(g)).expect("write");
    let args: Vec<String> = [
        "eval",
        "--model",
        "exp",
        "--slope",
        &slope.to_string(),
        "--beta",
        "0.4",
        "--n",
        "1.45",
        "--a",
        "0.2",
        "--geometry",
        "eval-geometry.csv",
        "--angles",
        "deg",
    ]
    .map(String::from)
    .to_vec();
    let out = common::stdout(
        Command::new(env!("CARGO_BIN_EXE_laminar"))
            .current_dir(dir)
            .args(&args),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    std::fs::remove_file(dir.join("eval-geometry.csv")).expect("remove");
    out.lines()
        .skip(1)
        .zip(g)
        .map(|(line, row)| {
            let total: f64 = line
                .rsplit(',')
                .next()
                .and_then(|v| v.parse().ok())
                .expect("eval's last column is the total");
            total / row[0].to_radians().cos()
        })
        .collect()
}

/// Writes the files the pages' commands name into `dir`.
fn fixtures(dir: &Path) {
    let g = geometry_degrees();
    let r = brdf(dir, &g, 1.3);
    let mut felt =
        String::from("# the docs' example: the model with σ/T 1.3, β 0.4, n 1.45, a 0.2\n");
    felt += "theta_i,phi_i,theta_v,phi_v,r,g,b,sigma_r\n";
    for (row, v) in g.iter().zip(&r) {
        // A deterministic ±1% ripple, so the fit has residuals.
        let ripple = 1.0 + 0.01 * ((row[0] + 3.0 * row[2] + row[3]).to_radians() * 7.0).sin();
        felt += &format!(
            "{},{},{},{},{},{},{},{}\n",
            row[0],
            row[1],
            row[2],
            row[3],
            v * ripple,
            0.8 * v / ripple,
            0.6 * v * ripple,
            0.01 * v
        );
    }
    std::fs::write(dir.join("felt.csv"), felt).expect("write");
    let directions: Vec<[f64; 4]> = (0..12)
        .map(|k| [5.0 * k as f64, 0.0, 60.0 - 5.0 * k as f64, 30.0 * k as f64])
        .collect();
    std::fs::write(dir.join("directions.csv"), geometry_csv(&directions)).expect("write");
    // geometry.csv in radians, values.npy: 8 sets on it.
    let mut text = String::from("theta_i,phi_i,theta_v,phi_v\n");
    for row in &g {
        let r = row.map(f64::to_radians);
        text += &format!("{},{},{},{}\n", r[0], r[1], r[2], r[3]);
    }
    std::fs::write(dir.join("geometry.csv"), text).expect("write");
    let sets: Vec<Vec<f64>> = (0..8)
        .map(|k| brdf(dir, &g, 0.6 + 0.25 * k as f64))
        .collect();
    let payload = sets
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let values = common::npy("<f8", sets.len(), g.len(), payload);
    std::fs::write(dir.join("values.npy"), values).expect("write");
}

/// The real-data directories the docs' commands name besides CUReT's:
/// (the variable, a file it holds, the variable that makes its absence
/// an error).
const DATA_DIRS: [(&str, &str, &str); 2] = [
    (
        "CORNELL_DIR",
        "krylon_blue_RGB.astm",
        "LAMINAR_REQUIRE_CORNELL",
    ),
    (
        "RGL_DIR",
        "cc_iris_purple_gem_rgb.bsdf",
        "LAMINAR_REQUIRE_RGL",
    ),
];

/// Each data directory variable with its directory when it is set and
/// holds its data: `CURET_DIR` ([`curet_dir`]) and [`DATA_DIRS`].
fn data_dirs() -> Vec<(&'static str, Option<PathBuf>)> {
    let mut dirs = vec![("CURET_DIR", curet_dir().ok())];
    for (name, file, require) in DATA_DIRS {
        let dir = std::env::var_os(name).map(PathBuf::from);
        match dir.filter(|d| d.join(file).is_file()) {
            Some(d) => dirs.push((name, Some(d))),
            None => {
                let why = format!("{name} is not set, or lacks {file}");
                common::skip_or_fail(require, &format!("the docs' commands on ${name}"), &why);
                dirs.push((name, None));
            }
        }
    }
    dirs
}

/// The `laminar` arguments of `command`, each `$NAME` of `dirs` that is
/// set replaced by its directory, or `None` for another program.
fn laminar_args(command: &str, dirs: &[(&str, Option<PathBuf>)]) -> Option<Vec<String>> {
    let rest = command
        .strip_prefix("laminar ")
        .or_else(|| command.strip_prefix(CARGO_RUN))
        .or((command == "laminar").then_some(""))?;
    let mut expanded = rest.to_string();
    for (name, dir) in dirs {
        if let Some(dir) = dir {
            expanded = expanded.replace(&format!("${name}"), &dir.display().to_string());
        }
    }
    Some(shlex::split(&expanded).unwrap_or_else(|| panic!("`{command}` does not split")))
}

#[test]
fn every_command_of_the_docs_runs() {
    let curet = curet_dir();
    if let Err(why) = &curet {
        common::skip_or_fail(
            "LAMINAR_REQUIRE_CURET",
            "the docs' commands on CUReT ($CURET_DIR)",
            why,
        );
    }
    let dirs = data_dirs();
    let mut ran = 0;
    let mut skipped = 0;
    let mut elsewhere = 0;
    for page in common::doc_pages() {
        let commands = shell_commands(&page);
        let dir = tempfile::tempdir().expect("a scratch directory");
        let mut unwritten: Vec<String> = Vec::new();
        if commands
            .iter()
            .any(|c| laminar_args(&c.text, &[]).is_some())
        {
            fixtures(dir.path());
        }
        for c in commands {
            let Some(args) = laminar_args(&c.text, &dirs) else {
                let (_, file, needle) = RUN_ELSEWHERE
                    .iter()
                    .find(|(start, _, _)| c.text.starts_with(start))
                    .unwrap_or_else(|| {
                        panic!(
                            "{}:{}: `{}` is neither a laminar command nor one that another \
                             test runs (cli/tests/docs.rs, RUN_ELSEWHERE)",
                            c.page, c.line, c.text
                        )
                    });
                let runner = std::fs::read_to_string(root().join(file)).expect("the runner reads");
                assert!(
                    runner.contains(needle),
                    "{}:{}: `{}` is said to run in {file}, which no longer mentions `{needle}`",
                    c.page,
                    c.line,
                    c.text
                );
                elsewhere += 1;
                continue;
            };
            // Without its data, a command on them is skipped, and so is
            // every later one that reads what a skipped one would have
            // written.
            let reads_skipped = args.iter().any(|a| unwritten.contains(a));
            let lacks_data = (dirs.iter())
                .any(|(name, dir)| dir.is_none() && c.text.contains(&format!("${name}")));
            if lacks_data || reads_skipped {
                let outs = args
                    .windows(2)
                    .filter(|w| w[0] == "--out" || w[0] == "--fits")
                    .map(|w| w[1].clone());
                unwritten.extend(outs);
                skipped += 1;
                continue;
            }
            laminar(dir.path(), &args)
                .unwrap_or_else(|e| panic!("{}:{}: `{}`:\n{e}", c.page, c.line, c.text));
            ran += 1;
        }
    }
    eprintln!(
        "docs: {ran} laminar commands ran, {skipped} skipped without their data, {elsewhere} run by other tests"
    );
    assert!(
        ran + skipped >= 20,
        "only {} laminar commands found in the docs",
        ran + skipped
    );
}

#[test]
fn comments_and_continuations_are_read_as_a_shell_does() {
    assert_eq!(strip_comment("laminar fit   # main job"), "laminar fit   ");
    assert_eq!(strip_comment("echo 'a # b' # c"), "echo 'a # b' ");
    assert_eq!(strip_comment("x#y"), "x#y");
    let dir = tempfile::tempdir().expect("dir");
    let page = dir.path().join("page.md");
    std::fs::write(
        &page,
        "text\n```sh\nlaminar fit \\\n  --models exp   # one\n\nlaminar eval\n```\n```python\nlaminar no\n```\n",
    )
    .expect("write");
    let got: Vec<(usize, String)> = shell_commands(&page)
        .into_iter()
        .map(|c| (c.line, c.text))
        .collect();
    assert_eq!(
        got,
        [
            (3, "laminar fit --models exp".to_string()),
            (6, "laminar eval".to_string())
        ]
    );
    assert_eq!(
        laminar_args(
            "laminar fit --data \"$CURET_DIR\" --samples 1",
            &[("CURET_DIR", Some(PathBuf::from("/c d")))]
        ),
        Some(
            ["fit", "--data", "/c d", "--samples", "1"]
                .map(String::from)
                .to_vec()
        )
    );
    assert_eq!(laminar_args("cc -o x", &[]), None);
}
