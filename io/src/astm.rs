//! ASTM E1392 text files of measured BRDFs, as the Cornell Program of
//! Computer Graphics' gonioreflectometer data are published
//! (docs/formats.md, "ASTM E1392"):
//!
//! ```text
//! LAB_NAME Cornell University, Program of Computer Graphics
//! SAMPLE_NAME Krylon Blue
//! NUM_POINTS 1439
//! VARS theta_i,phi_i,theta_s,phi_s,400nm,410nm,…,700nm
//!
//! 0.872665,0.000000,0.573513,0.000000,0.017415,0.036844,…
//! ```
//!
//! A header of keyword lines (`KEYWORD value`; blank lines between them),
//! `VARS` naming the columns, then one row of comma-separated numbers per
//! measurement. The first four columns are `theta_i, phi_i, theta_s,
//! phi_s` in radians: both directions (polar, azimuth) pointing away from
//! the sample, the mirror direction at `phi_s = phi_i + π`, which is this
//! library's lab frame with `theta_v = theta_s`, `phi_v = phi_s`. Every
//! other column is a channel of BRDF values (sr⁻¹): a wavelength (`550nm`)
//! or a colour (`R`). `NUM_POINTS`, when present, must be the number of
//! rows. Line endings LF or CRLF.

use crate::error::ReadError;
use crate::reader::{brdf_set, contents, number, text};
use laminar_brdf_fit::{MeasurementAngles, MeasurementSet};
use std::path::Path;

/// The first four columns `VARS` must name, in order.
pub const GEOMETRY: [&str; 4] = ["theta_i", "phi_i", "theta_s", "phi_s"];

/// Reads an ASTM E1392 file (module docs) as a set named after the file
/// stem, whose rows are the file's line numbers, each channel a column of
/// `VARS` after the geometry, as BRDF values.
///
/// ```
/// # let dir = tempfile::tempdir().unwrap();
/// let path = dir.path().join("paint.astm");
/// std::fs::write(
///     &path,
///     "SAMPLE_NAME Paint\nNUM_POINTS 2\nVARS theta_i,phi_i,theta_s,phi_s,450nm,550nm\n\n\
///      0.5,0,0.4,3.0,0.09,0.03\n0.5,0,0.6,2.0,0.08,0.02\n",
/// )?;
/// let set = laminar_brdf_io::astm::read_astm(&path)?;
/// assert_eq!(set.channel_names(), ["450nm", "550nm"]);
/// assert_eq!(set.len(), 2);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`ReadError`] naming the file, line, column and value: a missing or
/// malformed `VARS`, a row of the wrong length, a field that is not a
/// number, `NUM_POINTS` that is not the number of rows, or angles outside
/// their domain.
pub fn read_astm(file: &Path) -> Result<MeasurementSet, ReadError> {
    parse_astm(file, &contents(file)?)
}

/// The header's `VARS` (with its line) and `NUM_POINTS`, and the data
/// rows: each its line number and fields.
struct Parsed<'a> {
    vars: Vec<String>,
    num_points: Option<(usize, usize)>,
    rows: Vec<(usize, Vec<&'a str>)>,
}

/// [`read_astm`] on contents already in memory (`file` names the set and
/// the errors).
///
/// # Errors
/// As [`read_astm`].
pub fn parse_astm(file: &Path, bytes: &[u8]) -> Result<MeasurementSet, ReadError> {
    let text = text(file, bytes)?;
    let parsed = split(file, text)?;
    let vars = &parsed.vars;
    if let Some((line, count)) = parsed.num_points {
        if count != parsed.rows.len() {
            return Err(ReadError::format(
                file,
                line,
                format!(
                    "NUM_POINTS `{count}`, but the file has {} data rows",
                    parsed.rows.len()
                ),
            ));
        }
    }
    if parsed.rows.is_empty() {
        return Err(ReadError::format(file, 0, "no data rows after VARS"));
    }
    // Every field a number, by column.
    let mut columns: Vec<Vec<f64>> = vec![Vec::with_capacity(parsed.rows.len()); vars.len()];
    for (line, fields) in &parsed.rows {
        if fields.len() != vars.len() {
            return Err(ReadError::format(
                file,
                *line,
                format!(
                    "{} fields, but VARS names {} columns ({})",
                    fields.len(),
                    vars.len(),
                    vars.join(",")
                ),
            ));
        }
        for (c, field) in fields.iter().enumerate() {
            columns[c].push(number(file, *line, c, &vars[c], field)?);
        }
    }
    let [theta_i, phi_i, theta_s, phi_s] = [0, 1, 2, 3].map(|c| &columns[c]);
    let angles = (0..parsed.rows.len())
        .map(|k| MeasurementAngles::Lab {
            theta_i: theta_i[k],
            phi_i: phi_i[k],
            theta_v: theta_s[k],
            phi_v: phi_s[k],
        })
        .collect();
    let lines = parsed.rows.iter().map(|(line, _)| *line).collect();
    let channels = vars.iter().cloned().zip(columns).skip(GEOMETRY.len());
    brdf_set(file, "measurements", angles, Some(lines), channels)
}

/// The header and the data rows of `text`.
fn split<'a>(file: &Path, text: &'a str) -> Result<Parsed<'a>, ReadError> {
    let mut vars: Option<Vec<String>> = None;
    let mut num_points = None;
    let mut rows = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.trim_end_matches('\r').trim();
        if content.is_empty() {
            continue;
        }
        if vars.is_some() {
            rows.push((line, content.split(',').collect()));
            continue;
        }
        let (keyword, value) = content
            .split_once(char::is_whitespace)
            .map_or((content, ""), |(k, v)| (k, v.trim()));
        match keyword {
            "VARS" => vars = Some(variables(file, line, value)?),
            "NUM_POINTS" => {
                let count = value.parse::<usize>().map_err(|_| {
                    ReadError::format(
                        file,
                        line,
                        format!("NUM_POINTS: `{value}` is not a whole number"),
                    )
                })?;
                num_points = Some((line, count));
            }
            _ if keyword
                .chars()
                .all(|c| c.is_ascii_uppercase() || c == '_' || c.is_ascii_digit()) => {}
            _ => {
                return Err(ReadError::format(
                    file,
                    line,
                    format!(
                        "`{}` before VARS: the header is keyword lines (KEYWORD value), \
                         and VARS must name the columns before the data",
                        shorten(content)
                    ),
                ))
            }
        }
    }
    let vars = vars.ok_or_else(|| {
        ReadError::format(
            file,
            0,
            "no VARS line: an ASTM E1392 file names its columns with VARS theta_i,phi_i,theta_s,phi_s,…",
        )
    })?;
    Ok(Parsed {
        vars,
        num_points,
        rows,
    })
}

/// The column names of a `VARS` line at `line`: the geometry's four, then
/// at least one channel, each named once.
fn variables(file: &Path, line: usize, value: &str) -> Result<Vec<String>, ReadError> {
    let names: Vec<String> = value.split(',').map(|n| n.trim().to_string()).collect();
    for (c, want) in GEOMETRY.iter().enumerate() {
        match names.get(c) {
            Some(got) if got.eq_ignore_ascii_case(want) => {}
            got => {
                return Err(ReadError::format(
                    file,
                    line,
                    format!(
                        "VARS column {}: `{}`, expected `{want}` (the first four are {})",
                        c + 1,
                        got.map_or("", |g| shorten(g)),
                        GEOMETRY.join(",")
                    ),
                ))
            }
        }
    }
    if names.len() == GEOMETRY.len() {
        return Err(ReadError::format(
            file,
            line,
            "VARS names no channel after the geometry",
        ));
    }
    for (c, name) in names.iter().enumerate().skip(GEOMETRY.len()) {
        if name.is_empty() {
            return Err(ReadError::format(
                file,
                line,
                format!("VARS column {}: an empty name", c + 1),
            ));
        }
        if names[..c].contains(name) {
            return Err(ReadError::format(
                file,
                line,
                format!("VARS column {}: `{}` is named twice", c + 1, shorten(name)),
            ));
        }
    }
    Ok(names.into_iter().map(|n| n.to_ascii_lowercase()).collect())
}

/// At most 40 characters of `text` (a quoted value in an error).
fn shorten(text: &str) -> &str {
    match text.char_indices().nth(40) {
        Some((at, _)) => &text[..at],
        None => text,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<MeasurementSet, String> {
        parse_astm(Path::new("t.astm"), text.as_bytes()).map_err(|e| e.to_string())
    }

    const GOOD: &str = "LAB_NAME A lab\nNUM_POINTS 2\nVARS theta_i,phi_i,theta_s,phi_s,R,G,B\n\n\
                        0.5,0,0.4,3.0,0.09,0.03,-0.001\n0.5,0,0.6,2.0,0.08,0.02,0.1\n";

    #[test]
    fn a_file_reads_as_channels_in_the_lab_frame() {
        let set = parse(GOOD).unwrap();
        assert_eq!(set.channel_names(), ["r", "g", "b"]);
        assert_eq!(set.len(), 2);
        // CRLF endings read the same.
        let crlf = parse(&GOOD.replace('\n', "\r\n")).unwrap();
        assert_eq!(crlf.channel_names(), set.channel_names());
    }

    #[test]
    fn defects_name_the_line_column_and_value() {
        // Each case: GOOD with `from` replaced by `to`, and the error it gives.
        #[rustfmt::skip]
        let cases = [
            ("NUM_POINTS 2", "NUM_POINTS 3", "t.astm:2: NUM_POINTS `3`, but the file has 2 data rows"),
            ("0.08,0.02", "0.08,x", "t.astm:6: column 6 (g): `x` is not a number"),
            ("0.08,0.02", "0.08,inf", "t.astm:6: column 6 (g): `inf` is not a number"),
            (",0.1\n", "\n", "t.astm:6: 6 fields, but VARS names 7 columns"),
            ("theta_s,phi_s", "theta_v,phi_v", "t.astm:3: VARS column 3: `theta_v`, expected `theta_s`"),
            (",R,G,B", "", "t.astm:3: VARS names no channel"),
            ("R,G,B", "R,G,R", "t.astm:3: VARS column 7: `R` is named twice"),
            ("VARS", "VARZ", "t.astm:5: `0.5,0,0.4,3.0,0.09,0.03,-0.001` before VARS"),
            ("LAB_NAME A lab", "0.1,0.2", "t.astm:1: `0.1,0.2` before VARS"),
            ("NUM_POINTS 2", "NUM_POINTS two", "t.astm:2: NUM_POINTS: `two` is not a whole number"),
            ("0.5,0,0.6", "0.5,0,1.7", "theta_v"),
        ];
        crate::reader::assert_defects(parse, GOOD, &cases);
        let e = parse("LAB_NAME A lab\n").unwrap_err();
        assert!(e.contains("t.astm: no VARS line"), "{e}");
        let e = parse("VARS theta_i,phi_i,theta_s,phi_s,R\n").unwrap_err();
        assert!(e.contains("no data rows"), "{e}");
        let e = parse_astm(Path::new("t.astm"), b"VARS \xff\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("t.astm:1: byte 5 is not UTF-8"), "{e}");
    }
}
