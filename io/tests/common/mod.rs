//! What the tests on the shared real data have in common: finding a data
//! directory (or saying the test was skipped), and a channel's values.
#![allow(dead_code)] // each test crate uses some of these

use laminar_brdf_fit::{MeasurementAngles, MeasurementSet};
use std::path::PathBuf;

/// The directory the environment variable `var` names, or `None` after
/// saying, past the test harness's capture, that `test` was skipped (a
/// failure instead when `require` is set).
pub fn data_dir(var: &str, require: &str, test: &str) -> Option<PathBuf> {
    match std::env::var_os(var) {
        Some(d) => Some(PathBuf::from(d)),
        None if std::env::var_os(require).is_some() => panic!("{require} is set but {var} is not"),
        None => {
            let _ = std::io::Write::write_all(
                &mut std::io::stderr(),
                format!(
                    "SKIPPED {test}: {var} is not set (set {require}=1 to make this an error)\n"
                )
                .as_bytes(),
            );
            None
        }
    }
}

/// The values of channel `name` of `set`.
pub fn values<'a>(set: &'a MeasurementSet, name: &str) -> &'a [f64] {
    let channel = set.channels().iter().find(|c| c.name == name);
    &channel
        .unwrap_or_else(|| panic!("no channel {name}"))
        .values
}

/// θi, φi, θv, φv (radians) of a lab-frame measurement.
pub fn lab(a: &MeasurementAngles) -> [f64; 4] {
    a.lab().expect("the readers give the lab frame")
}
