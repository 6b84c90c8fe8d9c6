//! Long-format CSV measurements: one row per measurement, a header naming
//! the columns.
//!
//! * Geometry: `theta_i, phi_i, theta_v, phi_v` (lab frame, outward
//!   azimuths, as CUReT) or `theta_i, theta_s, phi_s` (the paper's frame).
//!   Radians by default, degrees with [`AngleUnit::Degrees`].
//! * `sigma`: a standard uncertainty for every channel's value in the row;
//!   `sigma_<channel>`: one channel's.
//! * Every other column whose first row holds a number is a channel (e.g.
//!   `value`, or `r,g,b`); other columns (labels, notes) are ignored.
//! * Lines starting with `#` are comments; blank lines are skipped.
//!
//! Every defect is an error naming the file, the line, the column and the value.

use crate::error::ReadError;
use crate::reader::{contents, set_error, set_name};
use laminar_brdf_fit::{MeasurementAngles, MeasurementSet, Quantity};
use std::f64::consts::FRAC_PI_2;
use std::fmt;
use std::path::Path;
use std::str::FromStr;

/// The unit of the angles in a file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AngleUnit {
    /// Radians.
    #[default]
    Radians,
    /// Degrees.
    Degrees,
}

impl FromStr for AngleUnit {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "rad" => Ok(Self::Radians),
            "deg" => Ok(Self::Degrees),
            _ => Err(format!("unknown angle unit `{s}` (expected rad or deg)")),
        }
    }
}

impl fmt::Display for AngleUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Radians => "rad",
            Self::Degrees => "deg",
        })
    }
}

/// Which geometry columns a header has.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Frame {
    Lab([usize; 4]),
    Paper([usize; 3]),
}

const LAB: [&str; 4] = ["theta_i", "phi_i", "theta_v", "phi_v"];
const PAPER: [&str; 3] = ["theta_i", "theta_s", "phi_s"];

fn position(header: &[String], name: &str) -> Option<usize> {
    header.iter().position(|h| h == name)
}

fn frame(file: &Path, header: &[String]) -> Result<Frame, ReadError> {
    let find = |names: &[&str]| -> Option<Vec<usize>> {
        names.iter().map(|n| position(header, n)).collect()
    };
    if let Some(c) = find(&LAB) {
        return Ok(Frame::Lab([c[0], c[1], c[2], c[3]]));
    }
    if let Some(c) = find(&PAPER) {
        return Ok(Frame::Paper([c[0], c[1], c[2]]));
    }
    Err(ReadError::format(
        file,
        1,
        format!(
            "the header `{}` names no geometry: expected columns {} (lab frame) or {} (paper frame)",
            header.join(","),
            LAB.join(", "),
            PAPER.join(", ")
        ),
    ))
}

/// Data records with their 1-based line numbers.
type Rows = Vec<(usize, ::csv::StringRecord)>;

/// The rows of a CSV file: header (trimmed) and records with their line numbers.
fn records(file: &Path, text: &[u8]) -> Result<(Vec<String>, Rows), ReadError> {
    let mut reader = ::csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .trim(::csv::Trim::All)
        .flexible(true)
        .from_reader(text);
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| ReadError::format(file, 1, format!("cannot read the header: {e}")))?
        .iter()
        .map(|h| h.to_string())
        .collect();
    if header.iter().all(|h| h.is_empty()) {
        return Err(ReadError::format(file, 0, "no header line"));
    }
    let header_line = reader.position().line().max(1) as usize;
    let mut out = Vec::new();
    for rec in reader.records() {
        let rec = rec.map_err(|e| {
            let line = e.position().map(|p| p.line() as usize).unwrap_or(0);
            ReadError::format(file, line, format!("not CSV: {e}"))
        })?;
        let line = rec.position().map(|p| p.line() as usize).unwrap_or(0);
        if rec.iter().all(|f| f.is_empty()) {
            continue;
        }
        if rec.len() != header.len() {
            return Err(ReadError::format(
                file,
                line,
                format!(
                    "{} fields, but the header (line {header_line}) has {} columns",
                    rec.len(),
                    header.len()
                ),
            ));
        }
        out.push((line, rec));
    }
    if out.is_empty() {
        return Err(ReadError::format(file, 0, "no data rows after the header"));
    }
    Ok((header, out))
}

/// A finite number in `column` of a record.
fn number(
    file: &Path,
    line: usize,
    header: &[String],
    rec: &::csv::StringRecord,
    column: usize,
) -> Result<f64, ReadError> {
    let field = &rec[column];
    let bad = |what: &str| {
        ReadError::format(
            file,
            line,
            format!(
                "column {} ({}): `{field}` is {what}",
                column + 1,
                header[column]
            ),
        )
    };
    match field.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(bad("not a finite number")),
        Err(_) => Err(bad("not a number")),
    }
}

/// Reads the geometry columns of every row, checking polar angles against
/// `[0, π/2]` (or `[0, 90]` degrees). Returns the angles in radians.
fn geometry(
    file: &Path,
    header: &[String],
    rows: &[(usize, ::csv::StringRecord)],
    unit: AngleUnit,
) -> Result<Vec<MeasurementAngles>, ReadError> {
    let frame = frame(file, header)?;
    let scale = match unit {
        AngleUnit::Radians => 1.0,
        AngleUnit::Degrees => std::f64::consts::PI / 180.0,
    };
    let mut out = Vec::with_capacity(rows.len());
    for (line, rec) in rows {
        let line = *line;
        let angle = |column: usize, polar: bool| -> Result<f64, ReadError> {
            let v = number(file, line, header, rec, column)?;
            let r = v * scale;
            if polar && !(0.0..=FRAC_PI_2 + 1e-12).contains(&r) {
                return Err(ReadError::format(
                    file,
                    line,
                    format!(
                        "column {} ({}): polar angle `{}` is outside [0, {}] ({unit})",
                        column + 1,
                        header[column],
                        &rec[column],
                        if unit == AngleUnit::Degrees {
                            "90"
                        } else {
                            "π/2"
                        }
                    ),
                ));
            }
            // Degrees converted to radians may land a rounding above π/2.
            Ok(if polar { r.min(FRAC_PI_2) } else { r })
        };
        out.push(match frame {
            Frame::Lab(c) => MeasurementAngles::Lab {
                theta_i: angle(c[0], true)?,
                phi_i: angle(c[1], false)?,
                theta_v: angle(c[2], true)?,
                phi_v: angle(c[3], false)?,
            },
            Frame::Paper(c) => MeasurementAngles::Paper {
                theta_i: angle(c[0], true)?,
                theta_s: angle(c[1], true)?,
                phi_s: angle(c[2], false)?,
            },
        });
    }
    Ok(out)
}

/// Reads a file of geometries only: the geometry columns of a CSV file
/// (other columns are ignored), as for `--geometry` and `--sample-at`.
///
/// # Errors
/// [`ReadError`] naming the file, and for a defect the line, column and value.
pub fn read_geometry(file: &Path, unit: AngleUnit) -> Result<Vec<MeasurementAngles>, ReadError> {
    parse_geometry(file, &contents(file)?, unit)
}

/// [`read_geometry`] on contents already in memory (`file` names them in errors).
///
/// # Errors
/// [`ReadError`] naming the file, and for a defect the line, column and value.
pub fn parse_geometry(
    file: &Path,
    bytes: &[u8],
    unit: AngleUnit,
) -> Result<Vec<MeasurementAngles>, ReadError> {
    let (header, rows) = records(file, bytes)?;
    geometry(file, &header, &rows, unit)
}

/// Reads a long-format CSV file of measurements (module docs) as a set named
/// after the file stem whose rows are the file's line numbers.
///
/// ```
/// # let dir = tempfile::tempdir().unwrap();
/// let path = dir.path().join("felt.csv");
/// std::fs::write(&path, "# my goniometer\ntheta_i,phi_i,theta_v,phi_v,r,g\n\
///     10,0,20,180,0.5,0.4\n30,0,40,90,0.3,0.2\n").unwrap();
/// let set = laminar_brdf_io::csv_file::read_csv(
///     &path,
///     laminar_brdf_io::AngleUnit::Degrees,
///     laminar_brdf_fit::Quantity::Brdf,
/// )?;
/// assert_eq!(set.name(), "felt");
/// assert_eq!(set.channel_names(), ["r", "g"]);
/// assert_eq!(set.len(), 2);
/// # Ok::<(), laminar_brdf_io::ReadError>(())
/// ```
///
/// # Errors
/// [`ReadError`] naming the file, and for a defect the line, column and value;
/// [`ReadError::Measurements`] when the values do not make a measurement set.
pub fn read_csv(
    file: &Path,
    unit: AngleUnit,
    quantity: Quantity,
) -> Result<MeasurementSet, ReadError> {
    parse_csv(file, &contents(file)?, unit, quantity)
}

/// [`read_csv`] on contents already in memory (`file` names the set and the
/// errors).
///
/// # Errors
/// As [`read_csv`].
pub fn parse_csv(
    file: &Path,
    bytes: &[u8],
    unit: AngleUnit,
    quantity: Quantity,
) -> Result<MeasurementSet, ReadError> {
    let (header, rows) = records(file, bytes)?;
    let angles = geometry(file, &header, &rows, unit)?;
    let geometry_columns: &[&str] = if position(&header, "phi_i").is_some() {
        &LAB
    } else {
        &PAPER
    };
    let first = &rows[0].1;
    let channels: Vec<usize> = (0..header.len())
        .filter(|&c| {
            let h = header[c].as_str();
            !geometry_columns.contains(&h)
                && h != "sigma"
                && !h.starts_with("sigma_")
                && first[c].parse::<f64>().is_ok()
        })
        .collect();
    if channels.is_empty() {
        return Err(ReadError::format(
            file,
            rows[0].0,
            format!(
                "no value column: the header `{}` has no numeric column besides the geometry and sigma",
                header.join(",")
            ),
        ));
    }
    for (c, h) in header.iter().enumerate() {
        if let Some(name) = h.strip_prefix("sigma_") {
            if !channels.iter().any(|&k| header[k] == name) {
                return Err(ReadError::format(
                    file,
                    1,
                    format!("column {} ({h}): no channel column `{name}`", c + 1),
                ));
            }
        }
    }
    let column = |c: usize| -> Result<Vec<f64>, ReadError> {
        rows.iter()
            .map(|(line, rec)| number(file, *line, &header, rec, c))
            .collect()
    };
    let wrap = set_error(file);
    let mut set = MeasurementSet::new(set_name(file, "measurements"), angles, quantity)
        .and_then(|s| s.with_rows(rows.iter().map(|(l, _)| *l).collect()))
        .map_err(wrap)?;
    let shared_sigma = position(&header, "sigma").map(column).transpose()?;
    for &c in &channels {
        let sigma = match position(&header, &format!("sigma_{}", header[c])) {
            Some(s) => Some(column(s)?),
            None => shared_sigma.clone(),
        };
        if let Some(s) = &sigma {
            if let Some((k, v)) = s.iter().enumerate().find(|(_, v)| **v <= 0.0) {
                return Err(ReadError::format(
                    file,
                    rows[k].0,
                    format!("sigma for channel {}: `{v}` is not positive", header[c]),
                ));
            }
        }
        set = set
            .with_channel(header[c].clone(), column(c)?, sigma)
            .map_err(wrap)?;
    }
    Ok(set)
}
