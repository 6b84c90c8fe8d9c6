//! Reading CUReT-format files (docs/conventions.md §1, §8): the geometry table
//! (`table.txt`: `index θv φv θi φi`, radians) and BRDF tables (`abrdf.dat`,
//! `rbrdf.dat`, `gbrdf.dat`, `bbrdf.dat`: `sample v1 … vN`). LF or CRLF line
//! endings and a missing final newline are accepted; every other defect is an
//! error naming the file, the line and the offending value.

use crate::error::ReadError;
use crate::reader::{contents, text};
use laminar_brdf_fit::{MeasurementAngles, MeasurementSet, Quantity};
use std::path::{Path, PathBuf};

fn err(file: &Path, line: usize, message: impl Into<String>) -> ReadError {
    ReadError::format(file, line, message)
}

/// The non-blank lines of a file's contents with their 1-based numbers.
fn lines(file: &Path, bytes: &[u8]) -> Result<Vec<(usize, String)>, ReadError> {
    let text = text(file, bytes)?;
    // A UTF-8 byte-order mark (as some editors write) is not part of the data.
    let lines: Vec<(usize, String)> = text
        .trim_start_matches('\u{feff}')
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim_end_matches('\r').to_string()))
        .filter(|(_, l)| !l.trim().is_empty())
        .collect();
    if lines.is_empty() {
        return Err(err(file, 0, "the file is empty"));
    }
    Ok(lines)
}

/// Parses one whitespace-separated field as a finite number.
fn number(file: &Path, line: usize, column: usize, field: &str) -> Result<f64, ReadError> {
    match field.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(v) => Err(err(
            file,
            line,
            format!("column {column}: value `{field}` is {v}, not a finite number"),
        )),
        Err(_) => Err(err(
            file,
            line,
            format!("column {column}: `{field}` is not a number"),
        )),
    }
}

/// Parses column 1 of a sample row: a positive integer not among `seen`.
fn sample_number(
    file: &Path,
    line: usize,
    field: &str,
    mut seen: impl Iterator<Item = u32>,
) -> Result<u32, ReadError> {
    let sample = field
        .parse::<u32>()
        .ok()
        .filter(|&s| s > 0)
        .ok_or_else(|| {
            err(
                file,
                line,
                format!("column 1: sample number `{field}` is not a positive integer"),
            )
        })?;
    if seen.any(|s| s == sample) {
        return Err(err(
            file,
            line,
            format!("column 1: sample {sample} appears twice"),
        ));
    }
    Ok(sample)
}

/// One row of the geometry table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TableRow {
    /// 1-based measurement index.
    pub index: usize,
    /// View polar angle θv.
    pub theta_v: f64,
    /// View azimuth φv.
    pub phi_v: f64,
    /// Illumination polar angle θi.
    pub theta_i: f64,
    /// Illumination azimuth φi.
    pub phi_i: f64,
}

/// Reads `table.txt`: exactly 5 columns per row, indices 1, 2, … in order,
/// polar angles in [0, π/2], azimuths in [−2π, 2π].
///
/// # Errors
/// [`ReadError`] naming the file, line, column and value.
pub fn read_table(file: &Path) -> Result<Vec<TableRow>, ReadError> {
    parse_table(file, &contents(file)?)
}

/// [`read_table`] on contents already in memory (`file` names them in errors).
///
/// # Errors
/// [`ReadError`] naming the file, line, column and value.
pub fn parse_table(file: &Path, bytes: &[u8]) -> Result<Vec<TableRow>, ReadError> {
    let mut rows = Vec::new();
    for (line, text) in lines(file, bytes)? {
        let fields: Vec<&str> = text.split_whitespace().collect();
        if fields.len() != 5 {
            return Err(err(
                file,
                line,
                format!(
                    "expected 5 columns (index θv φv θi φi), found {}",
                    fields.len()
                ),
            ));
        }
        let index = fields[0].parse::<usize>().map_err(|_| {
            err(
                file,
                line,
                format!("column 1: index `{}` is not a positive integer", fields[0]),
            )
        })?;
        if index != rows.len() + 1 {
            return Err(err(
                file,
                line,
                format!(
                    "column 1: index {index} out of order (expected {})",
                    rows.len() + 1
                ),
            ));
        }
        let mut v = [0.0; 4];
        for (c, slot) in v.iter_mut().enumerate() {
            *slot = number(file, line, c + 2, fields[c + 1])?;
        }
        let polar_ok = |x: f64| (0.0..=std::f64::consts::FRAC_PI_2).contains(&x);
        let azimuth_ok = |x: f64| x.abs() <= 2.0 * std::f64::consts::PI;
        for (c, ok) in [
            (0, polar_ok(v[0])),
            (1, azimuth_ok(v[1])),
            (2, polar_ok(v[2])),
            (3, azimuth_ok(v[3])),
        ] {
            if !ok {
                let what = if c % 2 == 0 {
                    "polar angle outside [0, π/2]"
                } else {
                    "azimuth outside [−2π, 2π]"
                };
                return Err(err(
                    file,
                    line,
                    format!("column {}: {} {what}", c + 2, v[c]),
                ));
            }
        }
        rows.push(TableRow {
            index,
            theta_v: v[0],
            phi_v: v[1],
            theta_i: v[2],
            phi_i: v[3],
        });
    }
    Ok(rows)
}

/// One sample's row of a BRDF table.
#[derive(Debug, Clone, PartialEq)]
pub struct BrdfRow {
    /// CUReT sample number.
    pub sample: u32,
    /// BRDF values, one per table row.
    pub values: Vec<f64>,
}

/// Reads a BRDF table whose rows must each hold a sample number and exactly
/// `measurements` values; sample numbers must be unique positive integers.
///
/// # Errors
/// [`ReadError`] naming the file, line, column and value.
pub fn read_brdf(file: &Path, measurements: usize) -> Result<Vec<BrdfRow>, ReadError> {
    parse_brdf(file, &contents(file)?, measurements)
}

/// [`read_brdf`] on contents already in memory (`file` names them in errors).
///
/// # Errors
/// [`ReadError`] naming the file, line, column and value.
pub fn parse_brdf(
    file: &Path,
    bytes: &[u8],
    measurements: usize,
) -> Result<Vec<BrdfRow>, ReadError> {
    let mut rows: Vec<BrdfRow> = Vec::new();
    for (line, text) in lines(file, bytes)? {
        let fields: Vec<&str> = text.split_whitespace().collect();
        if fields.len() != measurements + 1 {
            return Err(err(
                file,
                line,
                format!(
                    "expected a sample number and {measurements} values (one per table row), found {} values",
                    fields.len().saturating_sub(1)
                ),
            ));
        }
        let sample = sample_number(file, line, fields[0], rows.iter().map(|r| r.sample))?;
        let values = fields[1..]
            .iter()
            .enumerate()
            .map(|(c, f)| number(file, line, c + 2, f))
            .collect::<Result<Vec<_>, _>>()?;
        rows.push(BrdfRow { sample, values });
    }
    Ok(rows)
}

/// One row of a CUReT Oren–Nayar parameter file (`op.dat`, `opr.dat`,
/// `opg.dat`, `opb.dat`; rows `sample rho sigma kd`, docs/conventions.md §7).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrenNayarRow {
    /// CUReT sample number.
    pub sample: u32,
    /// Albedo ρ ∈ [0, 1].
    pub rho: f64,
    /// Roughness σ in radians, ∈ [0, π/2].
    pub sigma: f64,
    /// Diffuse scale k_d (cancels under max normalisation; kept for output).
    pub kd: f64,
}

/// Reads an Oren–Nayar parameter file; σ must be in radians (a value above
/// π/2, as a file in degrees would have, is an error naming it).
///
/// # Errors
/// [`ReadError`] naming the file, line, column and value.
pub fn read_oren_nayar(file: &Path) -> Result<Vec<OrenNayarRow>, ReadError> {
    parse_oren_nayar(file, &contents(file)?)
}

/// [`read_oren_nayar`] on contents already in memory (`file` names them in errors).
///
/// # Errors
/// [`ReadError`] naming the file, line, column and value.
pub fn parse_oren_nayar(file: &Path, bytes: &[u8]) -> Result<Vec<OrenNayarRow>, ReadError> {
    let mut rows: Vec<OrenNayarRow> = Vec::new();
    for (line, text) in lines(file, bytes)? {
        let fields: Vec<&str> = text.split_whitespace().collect();
        if fields.len() != 4 {
            return Err(err(
                file,
                line,
                format!(
                    "expected 4 columns `sample rho sigma kd`, found {}",
                    fields.len()
                ),
            ));
        }
        let sample = sample_number(file, line, fields[0], rows.iter().map(|r| r.sample))?;
        let rho = number(file, line, 2, fields[1])?;
        let sigma = number(file, line, 3, fields[2])?;
        let kd = number(file, line, 4, fields[3])?;
        if !(0.0..=1.0).contains(&rho) {
            return Err(err(
                file,
                line,
                format!("column 2: rho `{}` is outside [0, 1]", fields[1]),
            ));
        }
        if !(0.0..=std::f64::consts::FRAC_PI_2).contains(&sigma) {
            return Err(err(
                file,
                line,
                format!(
                    "column 3: sigma `{}` is outside [0, π/2] radians (degrees are not accepted)",
                    fields[2]
                ),
            ));
        }
        rows.push(OrenNayarRow {
            sample,
            rho,
            sigma,
            kd,
        });
    }
    Ok(rows)
}

/// A colour channel of the CUReT BRDF files.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Channel {
    /// RGB average (`abrdf.dat`).
    Avg,
    /// Red (`rbrdf.dat`).
    R,
    /// Green (`gbrdf.dat`).
    G,
    /// Blue (`bbrdf.dat`).
    B,
}

impl Channel {
    /// All channels in output order.
    pub const ALL: [Channel; 4] = [Channel::Avg, Channel::R, Channel::G, Channel::B];

    /// The name used in output (`avg`, `r`, `g`, `b`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Avg => "avg",
            Self::R => "r",
            Self::G => "g",
            Self::B => "b",
        }
    }

    /// The CUReT file name.
    pub fn file_name(self) -> &'static str {
        match self {
            Self::Avg => "abrdf.dat",
            Self::R => "rbrdf.dat",
            Self::G => "gbrdf.dat",
            Self::B => "bbrdf.dat",
        }
    }

    /// The CUReT Oren–Nayar parameter file of this channel.
    pub fn oren_nayar_file_name(self) -> &'static str {
        match self {
            Self::Avg => "op.dat",
            Self::R => "opr.dat",
            Self::G => "opg.dat",
            Self::B => "opb.dat",
        }
    }

    /// The channel of a BRDF file name (`rbrdf.dat` → r; anything else → avg).
    pub fn from_file(path: &Path) -> Self {
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        Self::ALL
            .into_iter()
            .find(|c| c.file_name() == name)
            .unwrap_or(Self::Avg)
    }
}

/// The measurement set of one sample's BRDF row on the geometry table:
/// named by the sample number, lab-frame angles, one channel named after
/// `channel`, values read as BRDF, rows numbered by the table's index.
///
/// # Errors
/// [`ReadError::Measurements`] when the angles or values are invalid.
pub fn measurement_set(
    file: &Path,
    table: &[TableRow],
    row: &BrdfRow,
    channel: Channel,
) -> Result<MeasurementSet, ReadError> {
    let angles = table
        .iter()
        .map(|t| MeasurementAngles::Lab {
            theta_i: t.theta_i,
            phi_i: t.phi_i,
            theta_v: t.theta_v,
            phi_v: t.phi_v,
        })
        .collect();
    let wrap = |source| ReadError::Measurements {
        file: file.to_path_buf(),
        source,
    };
    MeasurementSet::new(row.sample.to_string(), angles, Quantity::Brdf)
        .and_then(|s| s.with_rows(table.iter().map(|t| t.index).collect()))
        .and_then(|s| s.with_channel(channel.name(), row.values.clone(), None))
        .map_err(wrap)
}

/// A CUReT directory: its geometry table and the BRDF files to read.
#[derive(Debug, Clone)]
pub struct CuretDir {
    /// The directory.
    pub dir: PathBuf,
    /// `table.txt`, read.
    pub table: Vec<TableRow>,
}

/// One sample of one BRDF file, ready to fit, with the data set's own
/// Oren–Nayar parameters when the directory has them.
#[derive(Debug, Clone)]
pub struct CuretSample {
    /// The sample's measurement set (one channel).
    pub set: MeasurementSet,
    /// The channel.
    pub channel: Channel,
    /// The BRDF file it came from.
    pub file: PathBuf,
    /// The row of the channel's Oren–Nayar file, if present.
    pub oren_nayar: Option<OrenNayarRow>,
}

impl CuretDir {
    /// Reads `dir/table.txt`.
    ///
    /// # Errors
    /// [`ReadError`] for `table.txt`.
    pub fn open(dir: &Path) -> Result<Self, ReadError> {
        Ok(Self {
            dir: dir.to_path_buf(),
            table: read_table(&dir.join("table.txt"))?,
        })
    }

    /// The BRDF files present, in channel order (abrdf, rbrdf, gbrdf, bbrdf).
    pub fn brdf_files(&self) -> Vec<PathBuf> {
        Channel::ALL
            .iter()
            .map(|c| self.dir.join(c.file_name()))
            .filter(|p| p.exists())
            .collect()
    }

    /// The samples `samples` (`None`: every sample) of each of `files`
    /// (relative paths are looked up in the directory first), file-major.
    ///
    /// # Errors
    /// [`ReadError`] for a BRDF or Oren–Nayar file, or a sample not in a file.
    pub fn samples(
        &self,
        files: &[PathBuf],
        samples: Option<&[u32]>,
    ) -> Result<Vec<CuretSample>, ReadError> {
        let mut out = Vec::new();
        for file in files {
            let file = if file.exists() || file.is_absolute() {
                file.clone()
            } else {
                self.dir.join(file)
            };
            let rows = read_brdf(&file, self.table.len())?;
            let channel = Channel::from_file(&file);
            let op_file = self.dir.join(channel.oren_nayar_file_name());
            // An entry that exists but cannot be read (a dangling link, a
            // loop) is an error, not a silent grid search.
            let op_rows = if std::fs::symlink_metadata(&op_file).is_ok() {
                read_oren_nayar(&op_file)?
            } else {
                Vec::new()
            };
            let wanted: Vec<u32> = match samples {
                Some(s) => s.to_vec(),
                None => rows.iter().map(|r| r.sample).collect(),
            };
            for sample in wanted {
                let row = rows
                    .iter()
                    .find(|r| r.sample == sample)
                    .ok_or_else(|| err(&file, 0, format!("sample {sample} not found")))?;
                out.push(CuretSample {
                    set: measurement_set(&file, &self.table, row, channel)?,
                    channel,
                    file: file.clone(),
                    oren_nayar: op_rows.iter().find(|r| r.sample == sample).copied(),
                });
            }
        }
        Ok(out)
    }
}
