//! The `laminar` binary: options a command does not use are refused, not
//! silently ignored.

use std::process::Command;

fn laminar(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_laminar"))
        .args(args)
        .env_remove("CURET_DIR")
        .output()
        .expect("runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn options_a_command_ignores_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_str().unwrap();
    let (code, err) = laminar(&["reproduce", "--data", d, "--out", d, "--models", "exp"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--models is not accepted"), "{err}");
    let (code, err) = laminar(&["report", "speed-vs-error", "--path", "onepass-f32"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--path is not accepted"), "{err}");
    let (code, err) = laminar(&["report", "speed-vs-error", "--models", "exp"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--models is not accepted"), "{err}");
}

#[test]
fn fit_takes_models_and_path() {
    let (code, err) = laminar(&[
        "fit",
        "--models",
        "rh-exp",
        "--path",
        "onepass-f32x8",
        "--slope",
        "1.4:1.56:3",
        "--n",
        "1.4:1.5:6",
        "--a",
        "0:0.2:3",
    ]);
    assert_eq!(code, 0, "{err}");
}
