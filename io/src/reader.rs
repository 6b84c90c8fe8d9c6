//! What every reader of a measurement file shares: the file's contents
//! (as bytes and as text), a field as a number, the set's name (the file
//! stem), the error of a set the contents cannot make, and a BRDF set from
//! its angles and channels.

use crate::error::ReadError;
use laminar_brdf_fit::{MeasurementAngles, MeasurementError, MeasurementSet, Quantity};
use std::path::Path;

/// The contents of `file`.
pub(crate) fn contents(file: &Path) -> Result<Vec<u8>, ReadError> {
    std::fs::read(file).map_err(|e| ReadError::io(file, "read", e))
}

/// `field` (on `line`, in the 0-based `column` named `name`) as a finite
/// number; a field that is not one, infinities and NaN included, is an
/// error naming the column and the field.
pub(crate) fn number(
    file: &Path,
    line: usize,
    column: usize,
    name: &str,
    field: &str,
) -> Result<f64, ReadError> {
    let field = field.trim();
    field
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| {
            ReadError::format(
                file,
                line,
                format!("column {} ({name}): `{field}` is not a number", column + 1),
            )
        })
}

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

/// The BRDF set read from `file` (named by its stem, else `fallback`): its
/// angles, the file's line of each (when it has lines) and its channels.
pub(crate) fn brdf_set<N: Into<String>>(
    file: &Path,
    fallback: &str,
    angles: Vec<MeasurementAngles>,
    lines: Option<Vec<usize>>,
    channels: impl IntoIterator<Item = (N, Vec<f64>)>,
) -> Result<MeasurementSet, ReadError> {
    let wrap = set_error(file);
    let mut set =
        MeasurementSet::new(set_name(file, fallback), angles, Quantity::Brdf).map_err(wrap)?;
    if let Some(lines) = lines {
        set = set.with_rows(lines).map_err(wrap)?;
    }
    for (name, values) in channels {
        set = set.with_channel(name, values, None).map_err(wrap)?;
    }
    Ok(set)
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
