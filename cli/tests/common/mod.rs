//! What the tests that drive outside tools share: running a command, and
//! skipping with a message the user sees (or failing, when required).
#![allow(dead_code)] // each test crate uses some of these

use std::io::Write;
use std::process::Command;

/// Says on the terminal (past the test harness's capture) that `what` was
/// skipped and why, or fails when the environment variable `require` is set.
pub fn skip_or_fail(require: &str, what: &str, why: &str) {
    if std::env::var_os(require).is_some() {
        panic!("{what} cannot run: {why}");
    }
    let _ = writeln!(
        std::io::stderr(),
        "SKIPPED {what}: {why} (set {require}=1 to make this an error)"
    );
}

/// `Ok` when a slow integration test (one that builds a package for
/// minutes: the Python package, the npm package and page) runs here: its
/// variable `require` or `LAMINAR_INTEGRATION` is set. Otherwise why it
/// does not, and how to run it alone (`alone`, the cargo command) or with
/// the others: the README's test command then ends in minutes, and
/// `.ci/run` runs every integration (it sets each `require`).
pub fn integration(require: &str, alone: &str) -> Result<(), String> {
    if std::env::var_os(require).is_some() || std::env::var_os("LAMINAR_INTEGRATION").is_some() {
        return Ok(());
    }
    Err(format!(
        "a slow integration (it builds its package for minutes); run it alone with \
         `{require}=1 {alone}`, or every integration with `LAMINAR_INTEGRATION=1`"
    ))
}

/// Runs `cmd`: its stdout and stderr together, or an error with both.
pub fn run(cmd: &mut Command) -> Result<String, String> {
    let out = cmd.output().map_err(|e| format!("{cmd:?}: {e}"))?;
    let text =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    if out.status.success() {
        Ok(text)
    } else {
        Err(format!("{cmd:?} failed:\n{text}"))
    }
}

/// Runs `cmd`: its stdout alone, or an error with stdout and stderr.
pub fn stdout(cmd: &mut Command) -> Result<String, String> {
    let out = cmd.output().map_err(|e| format!("{cmd:?}: {e}"))?;
    if out.status.success() {
        Ok(String::from_utf8_lossy(&out.stdout).to_string())
    } else {
        Err(format!(
            "{cmd:?} failed:\n{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

/// A version-1.0 `.npy` file of little-endian f32 or f64 values, written by
/// hand from the format's definition.
pub fn npy(descr: &str, rows: usize, cols: usize, payload: Vec<u8>) -> Vec<u8> {
    let dict =
        format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': ({rows}, {cols}), }}");
    npy_with_header(&dict, &payload)
}

/// A version-1.0 `.npy` file of header dict `dict` and then `payload`
/// (`laminar_brdf_io::values::npy_bytes`): also the malformed files the
/// bad-input tests write.
pub fn npy_with_header(dict: &str, payload: &[u8]) -> Vec<u8> {
    laminar_brdf_io::values::npy_bytes(dict, payload)
}

/// The README and every page of `docs/`, the README first, the pages in
/// name order: where the docs tests look for code blocks.
pub fn doc_pages() -> Vec<std::path::PathBuf> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut pages: Vec<std::path::PathBuf> = std::fs::read_dir(root.join("docs"))
        .expect("docs/ is there")
        .map(|e| e.expect("docs/ lists").path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    pages.sort();
    pages.insert(0, root.join("README.md"));
    pages
}

/// The fenced code blocks of `text` whose info string is `lang`: each as its
/// lines with their line numbers (from 1). Panics on a block left open.
pub fn code_blocks<'a>(text: &'a str, lang: &str) -> Vec<Vec<(usize, &'a str)>> {
    let mut blocks = Vec::new();
    let mut open: Option<(bool, Vec<(usize, &str)>)> = None;
    for (k, line) in text.lines().enumerate() {
        let fence = line.trim_start().strip_prefix("```");
        match (&mut open, fence) {
            (None, Some(info)) => open = Some((info.trim() == lang, Vec::new())),
            (Some(_), Some(_)) => {
                let (wanted, lines) = open.take().expect("a block is open");
                if wanted {
                    blocks.push(lines);
                }
            }
            (Some((_, lines)), None) => lines.push((k + 1, line)),
            (None, None) => {}
        }
    }
    assert!(open.is_none(), "a code block is not closed");
    blocks
}
