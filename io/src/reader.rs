//! What every reader of a measurement file shares: the set's name (the
//! file stem), the error of a set the contents cannot make, and the
//! contents as text.

use crate::error::ReadError;
use laminar_fit::MeasurementError;
use std::path::Path;

/// The name of the set read from `file`: its stem (`fallback` when it has
/// none).
pub(crate) fn set_name(file: &Path, fallback: &str) -> String {
    file.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| fallback.into())
}

/// The error of contents of `file` that make no valid measurement set.
pub(crate) fn set_error(file: &Path) -> impl Fn(MeasurementError) -> ReadError + Copy + '_ {
    move |source| ReadError::Measurements {
        file: file.to_path_buf(),
        source,
    }
}

/// `bytes` as UTF-8 text, or an error naming the line and byte where they
/// stop being text.
pub(crate) fn text<'a>(file: &Path, bytes: &'a [u8]) -> Result<&'a str, ReadError> {
    std::str::from_utf8(bytes).map_err(|e| {
        let at = e.valid_up_to();
        let line = 1 + bytes[..at].iter().filter(|&&b| b == b'\n').count();
        ReadError::format(file, line, format!("byte {at} is not UTF-8 text"))
    })
}

/// Checks that each case `(from, to, want)` of a reader's defects, `good`
/// with `from` replaced by `to`, is an error whose message holds `want`.
#[cfg(test)]
pub(crate) fn assert_defects<T>(
    parse: impl Fn(&str) -> Result<T, String>,
    good: &str,
    cases: &[(&str, &str, &str)],
) {
    for &(from, to, want) in cases {
        assert!(
            good.contains(from),
            "the case's `{from}` is not in the file"
        );
        match parse(&good.replace(from, to)) {
            Ok(_) => panic!("{from} -> {to}: no error, {want} expected"),
            Err(e) => assert!(e.contains(want), "{want}: {e}"),
        }
    }
}
