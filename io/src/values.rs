//! N × K arrays of values (N measurement sets, K measurements each, in the
//! order of a geometry file): `.npy` (f32 or f64, little-endian, C order, two
//! dimensions; read with `npyz`) or CSV (N lines of K numbers, `#` comments).

use crate::error::ReadError;
use std::path::Path;

/// An N × K array of values, row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct Values {
    /// Rows N (measurement sets).
    pub rows: usize,
    /// Columns K (measurements per set).
    pub cols: usize,
    /// `rows × cols` values, row after row.
    pub data: Vec<f64>,
}

impl Values {
    /// Row `i`.
    pub fn row(&self, i: usize) -> &[f64] {
        &self.data[i * self.cols..(i + 1) * self.cols]
    }
}

/// Reads `.npy` or `.csv` values by the file's extension.
///
/// # Errors
/// [`ReadError`] naming the file (and for CSV the line, column and value):
/// another extension, dtype, byte order, memory order or dimension count, or
/// rows of unequal length.
pub fn read_values(file: &Path) -> Result<Values, ReadError> {
    let bytes = std::fs::read(file).map_err(|e| ReadError::io(file, "read", e))?;
    match file.extension().and_then(|e| e.to_str()) {
        Some("npy") => parse_npy(file, &bytes),
        Some("csv") => parse_csv_values(file, &bytes),
        _ => Err(ReadError::format(
            file,
            0,
            "values must be a .npy or .csv file".to_string(),
        )),
    }
}

/// An `.npy` array in memory (`file` names it in errors).
///
/// # Errors
/// As [`read_values`].
pub fn parse_npy(file: &Path, bytes: &[u8]) -> Result<Values, ReadError> {
    let bad = |m: String| ReadError::format(file, 0, m);
    let npy = npyz::NpyFile::new(bytes).map_err(|e| bad(format!("not an .npy file: {e}")))?;
    let shape = npy.shape().to_vec();
    if shape.len() != 2 {
        return Err(bad(format!(
            "the array has shape {shape:?}; an N × K array (sets × measurements) is needed"
        )));
    }
    if npy.order() != npyz::Order::C {
        return Err(bad(
            "the array is in Fortran order; C order is needed".into()
        ));
    }
    let descr = npy.dtype().descr();
    let (rows, cols) = (shape[0] as usize, shape[1] as usize);
    let data: Vec<f64> = match descr.as_str() {
        "'<f8'" => npy.into_vec::<f64>(),
        "'<f4'" => npy
            .into_vec::<f32>()
            .map(|v| v.into_iter().map(f64::from).collect()),
        other => {
            return Err(bad(format!(
                "dtype {other}; little-endian float32 (<f4) or float64 (<f8) is needed"
            )))
        }
    }
    .map_err(|e| bad(format!("cannot read the data: {e}")))?;
    if data.len() != rows * cols {
        return Err(bad(format!(
            "{} values for a {rows} × {cols} array",
            data.len()
        )));
    }
    Ok(Values { rows, cols, data })
}

/// CSV values in memory: one set per line, K comma-separated numbers.
///
/// # Errors
/// As [`read_values`].
pub fn parse_csv_values(file: &Path, bytes: &[u8]) -> Result<Values, ReadError> {
    let text = crate::curet::utf8(file, bytes)?;
    let text = text.trim_start_matches('\u{feff}');
    let (mut data, mut cols, mut rows) = (Vec::new(), 0, 0);
    for (i, line) in text.lines().enumerate() {
        let line_no = i + 1;
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if rows == 0 {
            cols = fields.len();
        } else if fields.len() != cols {
            return Err(ReadError::format(
                file,
                line_no,
                format!("{} values, but the first row has {cols}", fields.len()),
            ));
        }
        for (c, f) in fields.iter().enumerate() {
            match f.parse::<f64>() {
                Ok(v) if v.is_finite() => data.push(v),
                _ => {
                    return Err(ReadError::format(
                        file,
                        line_no,
                        format!("column {}: `{f}` is not a finite number", c + 1),
                    ))
                }
            }
        }
        rows += 1;
    }
    if rows == 0 {
        return Err(ReadError::format(file, 0, "no rows of values"));
    }
    Ok(Values { rows, cols, data })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A version-1.0 `.npy` file, written by hand from the format's definition.
    fn npy(descr: &str, shape: (usize, usize), payload: &[u8]) -> Vec<u8> {
        let mut header = format!(
            "{{'descr': '{descr}', 'fortran_order': False, 'shape': ({}, {}), }}",
            shape.0, shape.1
        );
        while (10 + header.len() + 1) % 64 != 0 {
            header.push(' ');
        }
        header.push('\n');
        let mut out = b"\x93NUMPY\x01\x00".to_vec();
        out.extend_from_slice(&(header.len() as u16).to_le_bytes());
        out.extend_from_slice(header.as_bytes());
        out.extend_from_slice(payload);
        out
    }

    #[test]
    fn npy_f64_and_f32_are_read_row_major() {
        let f = Path::new("v.npy");
        let v: Vec<u8> = [1.0f64, 2.0, 3.0, 4.0, 5.0, 6.0]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let a = parse_npy(f, &npy("<f8", (2, 3), &v)).unwrap();
        assert_eq!((a.rows, a.cols), (2, 3));
        assert_eq!(a.row(1), [4.0, 5.0, 6.0]);
        let v: Vec<u8> = [0.5f32, 0.25]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let a = parse_npy(f, &npy("<f4", (1, 2), &v)).unwrap();
        assert_eq!(a.data, vec![0.5, 0.25]);
        let e = parse_npy(f, &npy("<i4", (1, 1), &[0; 4]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("v.npy") && e.contains("<f4"), "{e}");
        let e = parse_npy(f, b"not numpy").unwrap_err().to_string();
        assert!(e.contains("not an .npy file"), "{e}");
    }

    #[test]
    fn csv_values_name_line_column_and_value() {
        let f = Path::new("v.csv");
        let a = parse_csv_values(f, b"# sets\n1, 2\n3,4\n").unwrap();
        assert_eq!((a.rows, a.cols, a.row(1)), (2, 2, &[3.0, 4.0][..]));
        let e = parse_csv_values(f, b"1,2\n3\n").unwrap_err().to_string();
        assert_eq!(e, "v.csv:2: 1 values, but the first row has 2");
        let e = parse_csv_values(f, b"1,x\n").unwrap_err().to_string();
        assert_eq!(e, "v.csv:1: column 2: `x` is not a finite number");
    }
}
