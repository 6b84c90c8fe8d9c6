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
