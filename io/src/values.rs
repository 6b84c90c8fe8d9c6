//! N × K arrays of values (N measurement sets, K measurements each, in the
//! order of a geometry file): `.npy` (f32 or f64, little-endian, C order, two
//! dimensions; read with `npyz`) or CSV (N lines of K numbers, `#` comments).

use crate::error::ReadError;
use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};

/// A version-1.0 `.npy` file of header dict `dict` (any text, padded as
/// numpy pads it, to a multiple of 64 bytes with the magic and length)
/// and then `payload`: the files the tests write, well formed or not.
pub fn npy_bytes(dict: &str, payload: &[u8]) -> Vec<u8> {
    let mut header = dict.to_string();
    while !(10 + header.len() + 1).is_multiple_of(64) {
        header.push(' ');
    }
    header.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    out.extend_from_slice(payload);
    out
}

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

/// Reads `.npy` or `.csv` values by the file's extension, whole.
///
/// # Errors
/// [`ReadError`] naming the file (and for CSV the line, column and value):
/// another extension, dtype, byte order, memory order or dimension count, or
/// rows of unequal length.
pub fn read_values(file: &Path) -> Result<Values, ReadError> {
    ValueRows::open(file)?.collect_all()
}

/// An `.npy` array in memory (`file` names it in errors).
///
/// # Errors
/// As [`read_values`].
pub fn parse_npy(file: &Path, bytes: &[u8]) -> Result<Values, ReadError> {
    ValueRows::npy(file, bytes)?.collect_all()
}

/// CSV values in memory: one set per line, K comma-separated numbers.
///
/// # Errors
/// As [`read_values`].
pub fn parse_csv_values(file: &Path, bytes: &[u8]) -> Result<Values, ReadError> {
    ValueRows::csv(file, bytes)?.collect_all()
}

/// The rows of a values file read a block at a time, so that memory stays
/// bounded by the block whatever N is: [`ValueRows::open`], then
/// [`ValueRows::next_rows`] until it gives an empty block.
pub struct ValueRows<R: BufRead> {
    file: PathBuf,
    cols: usize,
    rows: Option<usize>,
    /// Rows returned so far (an `.npy` error names the set after them).
    read: usize,
    source: Source<R>,
}

/// An `.npy` stream after [`checked_header`]: the bytes it read, then the
/// rest.
type NpyStream<R> = std::io::Chain<std::io::Cursor<Vec<u8>>, R>;

enum Source<R: BufRead> {
    F64(npyz::NpyReader<f64, NpyStream<R>>),
    F32(npyz::NpyReader<f32, NpyStream<R>>),
    Csv {
        lines: std::io::Lines<R>,
        line_no: usize,
        /// The first row, read by [`ValueRows::csv`] to learn K.
        first: Option<Vec<f64>>,
    },
}

impl ValueRows<BufReader<File>> {
    /// Opens `.npy` or `.csv` values by the file's extension and reads
    /// their header (`.npy`) or first row (CSV).
    ///
    /// # Errors
    /// As [`read_values`] (for the header or first row).
    pub fn open(file: &Path) -> Result<Self, ReadError> {
        let reader = || {
            File::open(file)
                .map(BufReader::new)
                .map_err(|e| ReadError::io(file, "read", e))
        };
        match file.extension().and_then(|e| e.to_str()) {
            Some("npy") => Self::npy(file, reader()?),
            Some("csv") => Self::csv(file, reader()?),
            _ => Err(ReadError::format(
                file,
                0,
                "values must be a .npy or .csv file".to_string(),
            )),
        }
    }
}

impl<R: BufRead> ValueRows<R> {
    /// `.npy` values from `reader` (`file` names it in errors).
    ///
    /// # Errors
    /// As [`read_values`], for the header.
    pub fn npy(file: &Path, reader: R) -> Result<Self, ReadError> {
        let bad = |m: String| ReadError::format(file, 0, m);
        let reader = checked_header(file, reader)?;
        let npy = npyz::NpyFile::new(reader).map_err(|e| bad(format!("not an .npy file: {e}")))?;
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
        let cols = usize::try_from(shape[1])
            .ok()
            .filter(|&c| c > 0 || shape[0] == 0)
            .ok_or_else(|| bad(format!("the array has shape {shape:?}: no values per set")))?;
        let source = match npy.dtype().descr().as_str() {
            "'<f8'" => npy.data::<f64>().map(Source::F64),
            "'<f4'" => npy.data::<f32>().map(Source::F32),
            other => {
                return Err(bad(format!(
                    "dtype {other}; little-endian float32 (<f4) or float64 (<f8) is needed"
                )))
            }
        }
        .map_err(|e| bad(format!("cannot read the data: {e}")))?;
        Ok(Self {
            file: file.to_path_buf(),
            cols,
            rows: usize::try_from(shape[0]).ok(),
            read: 0,
            source,
        })
    }

    /// CSV values from `reader`: one set per line, K comma-separated
    /// numbers, `#` comments; reads up to the first row.
    ///
    /// # Errors
    /// As [`read_values`], for the first row; also when there is none.
    pub fn csv(file: &Path, reader: R) -> Result<Self, ReadError> {
        let mut rows = Self {
            file: file.to_path_buf(),
            cols: 0,
            rows: None,
            read: 0,
            source: Source::Csv {
                lines: reader.lines(),
                line_no: 0,
                first: None,
            },
        };
        let first = rows
            .csv_row()?
            .ok_or_else(|| ReadError::format(file, 0, "no rows of values"))?;
        rows.cols = first.len();
        if let Source::Csv { first: slot, .. } = &mut rows.source {
            *slot = Some(first);
        }
        Ok(rows)
    }

    /// K, the values per set.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// N, the number of sets, when the header states it (`.npy`).
    pub fn rows(&self) -> Option<usize> {
        self.rows
    }

    /// Up to `n` more rows; empty at the end.
    ///
    /// # Errors
    /// As [`read_values`]: a row of another length, a value that is not a
    /// finite number, or a truncated `.npy` file.
    pub fn next_rows(&mut self, n: usize) -> Result<Vec<Vec<f64>>, ReadError> {
        let mut out = Vec::with_capacity(n.min(1 << 16));
        while out.len() < n {
            let at = NpyAt {
                file: &self.file,
                set: self.read + 1,
                cols: self.cols,
            };
            let row = match &mut self.source {
                Source::Csv { .. } => self.csv_row()?,
                Source::F64(data) => npy_row(at, data, |v| v)?,
                Source::F32(data) => npy_row(at, data, f64::from)?,
            };
            match row {
                Some(row) => {
                    out.push(row);
                    self.read += 1;
                }
                None => break,
            }
        }
        Ok(out)
    }

    /// Every remaining row.
    fn collect_all(mut self) -> Result<Values, ReadError> {
        let mut data = Vec::new();
        let mut rows = 0;
        loop {
            let block = self.next_rows(1 << 12)?;
            if block.is_empty() {
                break;
            }
            rows += block.len();
            data.extend(block.into_iter().flatten());
        }
        Ok(Values {
            rows,
            cols: self.cols,
            data,
        })
    }

    /// The next CSV row (the one read by [`ValueRows::csv`] first).
    fn csv_row(&mut self) -> Result<Option<Vec<f64>>, ReadError> {
        let Source::Csv {
            lines,
            line_no,
            first,
        } = &mut self.source
        else {
            return Ok(None);
        };
        if let Some(row) = first.take() {
            return Ok(Some(row));
        }
        let file = &self.file;
        for line in lines.by_ref() {
            *line_no += 1;
            let line = line.map_err(|e| ReadError::io(file, "read", e))?;
            let line = line.trim().trim_start_matches('\u{feff}');
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let fields: Vec<&str> = line.split(',').map(str::trim).collect();
            if self.cols != 0 && fields.len() != self.cols {
                return Err(ReadError::format(
                    file,
                    *line_no,
                    format!(
                        "{} values, but the first row has {}",
                        fields.len(),
                        self.cols
                    ),
                ));
            }
            let row = fields
                .iter()
                .enumerate()
                .map(|(c, f)| match f.parse::<f64>() {
                    Ok(v) if v.is_finite() => Ok(v),
                    _ => Err(ReadError::format(
                        file,
                        *line_no,
                        format!("column {}: `{f}` is not a finite number", c + 1),
                    )),
                })
                .collect::<Result<Vec<f64>, _>>()?;
            return Ok(Some(row));
        }
        Ok(None)
    }
}

/// Most bytes of an `.npy` header: numpy writes a few hundred; format 1.0
/// allows 65,535.
pub const MOST_HEADER_BYTES: usize = 65_535;

/// Deepest nesting of brackets in an `.npy` header: `{'shape': (N, K)}` is
/// 2, a structured dtype a few more.
pub const MOST_HEADER_DEPTH: usize = 8;

/// Reads the preamble and header of an `.npy` stream and refuses, before
/// `npyz` parses it, a header longer than [`MOST_HEADER_BYTES`] or nested
/// deeper than [`MOST_HEADER_DEPTH`] (the header parser's time doubles per
/// level of nesting: 30 levels in 216 bytes never finish). Gives back the
/// bytes read followed by the rest of the stream.
fn checked_header<R: BufRead>(file: &Path, mut reader: R) -> Result<NpyStream<R>, ReadError> {
    let bad = |m: String| ReadError::format(file, 0, m);
    let mut read = |n: usize, what: &str| -> Result<Vec<u8>, ReadError> {
        let mut bytes = vec![0u8; n];
        reader
            .read_exact(&mut bytes)
            .map_err(|e| bad(format!("not an .npy file: {what}: {e}")))?;
        Ok(bytes)
    };
    let mut prefix = read(8, "the preamble")?;
    if &prefix[..6] != b"\x93NUMPY" {
        return Err(bad("not an .npy file: no \\x93NUMPY magic string".into()));
    }
    let length_bytes = if prefix[6] == 1 { 2 } else { 4 };
    let length = read(length_bytes, "the header length")?;
    let len = length
        .iter()
        .rev()
        .fold(0usize, |acc, &b| (acc << 8) | usize::from(b));
    if len > MOST_HEADER_BYTES {
        return Err(bad(format!(
            "the header claims {len} bytes (at most {MOST_HEADER_BYTES})"
        )));
    }
    let header = read(len, "the header")?;
    let mut depth = 0usize;
    for &b in &header {
        match b {
            b'(' | b'[' | b'{' => {
                depth += 1;
                if depth > MOST_HEADER_DEPTH {
                    return Err(bad(format!(
                        "the header nests brackets deeper than {MOST_HEADER_DEPTH} levels"
                    )));
                }
            }
            b')' | b']' | b'}' => depth = depth.saturating_sub(1),
            _ => {}
        }
    }
    check_shape_size(file, &header)?;
    prefix.extend(length);
    prefix.extend(header);
    Ok(std::io::Cursor::new(prefix).chain(reader))
}

/// Refuses a header whose `shape` holds more than 2⁶⁴ values (`npyz`
/// multiplies the dimensions unchecked: a fuzzed `(1, 10995116277,
/// 1099511627776)` overflowed). The header is parsed as `npyz` parses it
/// (`py_literal`, trailing newline dropped); a header it cannot parse, or
/// one without a shape of integers, is left to `npyz`'s own errors.
fn check_shape_size(file: &Path, header: &[u8]) -> Result<(), ReadError> {
    let text = header.strip_suffix(b"\n").unwrap_or(header);
    let Some(Ok(py_literal::Value::Dict(dict))) = std::str::from_utf8(text)
        .ok()
        .map(str::parse::<py_literal::Value>)
    else {
        return Ok(());
    };
    let shape = dict.iter().find_map(|(key, value)| match (key, value) {
        (
            py_literal::Value::String(k),
            py_literal::Value::Tuple(dims) | py_literal::Value::List(dims),
        ) if k == "shape" => Some(dims),
        _ => None,
    });
    let Some(dims) = shape else { return Ok(()) };
    // Every prefix product `npyz` forms (its strides, in either order) is
    // at most the product of the nonzero dimensions.
    let mut product = 1u64;
    for dim in dims {
        let py_literal::Value::Integer(dim) = dim else {
            return Ok(());
        };
        if dim.to_string().starts_with('-') {
            return Ok(()); // npyz refuses a negative dimension
        }
        let dim = match u64::try_from(dim) {
            Ok(0) => continue,
            Ok(d) => d,
            Err(_) => u64::MAX, // over 2^64 alone
        };
        product = product.checked_mul(dim).ok_or_else(|| {
            ReadError::format(
                file,
                0,
                format!(
                    "the header's shape {} holds more than 2^64 values",
                    dims.iter()
                        .map(ToString::to_string)
                        .collect::<Vec<_>>()
                        .join(" × ")
                ),
            )
        })?;
    }
    Ok(())
}

/// Where an `.npy` row is read: the file, the set's 1-based number and the
/// values per set.
#[derive(Clone, Copy)]
struct NpyAt<'a> {
    file: &'a Path,
    set: usize,
    cols: usize,
}

/// Values a row reserves before any is read: a header may claim any K,
/// so the row grows only as values arrive, each growth fallible.
const FIRST_ROW_CAPACITY: usize = 1 << 12;

/// The next row of an `.npy` data stream (set `at.set`, `at.cols` values).
fn npy_row<T: npyz::Deserialize, R: BufRead>(
    at: NpyAt,
    data: &mut npyz::NpyReader<T, R>,
    widen: impl Fn(T) -> f64,
) -> Result<Option<Vec<f64>>, ReadError> {
    let (file, set, cols) = (at.file, at.set, at.cols);
    let mut row = Vec::new();
    for (k, value) in data.by_ref().take(cols).enumerate() {
        let v = widen(value.map_err(|e| {
            ReadError::format(file, 0, format!("set {set}: cannot read the data: {e}"))
        })?);
        if !v.is_finite() {
            return Err(ReadError::format(
                file,
                0,
                format!(
                    "set {set}, measurement {} (row {set}, column {} of the array): value {v} is not a finite number",
                    k + 1,
                    k + 1
                ),
            ));
        }
        if row.len() == row.capacity() {
            let more = if row.is_empty() {
                cols.min(FIRST_ROW_CAPACITY)
            } else {
                row.len()
            };
            row.try_reserve(more).map_err(|_| {
                ReadError::format(
                    file,
                    0,
                    format!("set {set}: not enough memory for a row of {cols} values"),
                )
            })?;
        }
        row.push(v);
    }
    match row.len() {
        0 => Ok(None),
        n if n == cols => Ok(Some(row)),
        n => Err(ReadError::format(
            file,
            0,
            format!("the data end inside set {set} ({n} of {cols} values)"),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A version-1.0 `.npy` file of `descr` values of `shape`.
    fn npy(descr: &str, shape: (usize, usize), payload: &[u8]) -> Vec<u8> {
        let dict = format!(
            "{{'descr': '{descr}', 'fortran_order': False, 'shape': ({}, {}), }}",
            shape.0, shape.1
        );
        super::npy_bytes(&dict, payload)
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

    /// A 216-byte header nesting brackets 30 deep hung `npyz`'s parser
    /// (issue 24): it is refused before parsing, as is a header claiming
    /// more bytes than the format allows; a header nested as deep as
    /// allowed still reaches the parser (and its dtype check).
    /// A header claiming 2⁴⁰ values per set over a few bytes of data
    /// reserved 8 TiB for the first row and aborted; rows now grow only as
    /// values arrive. A non-finite value names its set and measurement.
    #[test]
    fn npy_claims_reserve_nothing_and_bad_values_say_where() {
        let f = Path::new("huge.npy");
        let bytes = npy("<f8", (1, 1 << 40), &1.0f64.to_le_bytes());
        let e = parse_npy(f, &bytes).unwrap_err().to_string();
        assert!(
            e.starts_with("huge.npy: set 1: cannot read the data"),
            "{e}"
        );
        let bytes = npy("<f8", (4, 1 << 30), &[]);
        let e = parse_npy(f, &bytes).unwrap_err().to_string();
        assert!(
            e.starts_with("huge.npy: set 1: cannot read the data"),
            "{e}"
        );
        let mut values = [1.0f64; 6];
        values[4] = f64::NAN;
        let payload: Vec<u8> = values.iter().flat_map(|x| x.to_le_bytes()).collect();
        let e = parse_npy(Path::new("v.npy"), &npy("<f8", (2, 3), &payload))
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "v.npy: set 2, measurement 2 (row 2, column 2 of the array): value NaN is not a finite number"
        );
    }

    #[test]
    fn npy_headers_too_deep_or_too_long_are_refused_before_parsing() {
        let f = Path::new("deep.npy");
        let nested = |depth: usize| {
            let header = format!(
                "{{'descr': {}'<f8'{}, 'fortran_order': False, 'shape': (1, 1), }}\n",
                "[".repeat(depth),
                "]".repeat(depth)
            );
            let mut out = b"\x93NUMPY\x01\x00".to_vec();
            out.extend_from_slice(&(header.len() as u16).to_le_bytes());
            out.extend_from_slice(header.as_bytes());
            out.extend_from_slice(&[0; 8]);
            out
        };
        let start = std::time::Instant::now();
        let e = parse_npy(f, &nested(30)).unwrap_err().to_string();
        assert!(e.contains("deep.npy") && e.contains("deeper than 8"), "{e}");
        // Not parsed: refused at once (the parser needed hours).
        assert!(start.elapsed().as_secs() < 5);
        let e = parse_npy(f, &nested(MOST_HEADER_DEPTH - 1))
            .unwrap_err()
            .to_string();
        assert!(!e.contains("deeper"), "{e}");
        let mut long = b"\x93NUMPY\x02\x00".to_vec();
        long.extend_from_slice(&u32::MAX.to_le_bytes());
        let e = parse_npy(f, &long).unwrap_err().to_string();
        assert!(e.contains("4294967295 bytes") && e.contains("65535"), "{e}");
        let e = parse_npy(f, b"\x93NUMPY\x01\x00\x10")
            .unwrap_err()
            .to_string();
        assert!(e.contains("the header length"), "{e}");
    }

    /// A shape whose product passes 2^64 panicked inside `npyz` (its
    /// unchecked product; found by the fuzzer). Refused, naming the shape,
    /// also when a zero dimension makes the product itself 0.
    #[test]
    fn npy_shapes_of_more_than_2_64_values_are_refused() {
        let f = Path::new("huge.npy");
        let with_shape = |shape: &str| {
            let header =
                format!("{{'descr': '<f8', 'fortran_order': False, 'shape': {shape}, }}\n");
            let mut out = b"\x93NUMPY\x01\x00".to_vec();
            out.extend_from_slice(&(header.len() as u16).to_le_bytes());
            out.extend_from_slice(header.as_bytes());
            out.extend_from_slice(&1.0f64.to_le_bytes());
            out
        };
        for shape in [
            "(1, 10995116277, 1099511627776)",
            "(0, 4294967296, 4294967296)",
            "[4294967296, 4294967297]",
            "(2, 9223372036854775808)",
        ] {
            let e = parse_npy(f, &with_shape(shape)).unwrap_err().to_string();
            assert!(
                e.contains("huge.npy") && e.contains("more than 2^64"),
                "{shape}: {e}"
            );
        }
        // Large but representable: npyz's own checks and ours follow.
        let e = parse_npy(f, &with_shape("(4294967296, 4294967295)"))
            .unwrap_err()
            .to_string();
        assert!(!e.contains("2^64"), "{e}");
        let e = parse_npy(f, &with_shape("(-1, 2)"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("negative"), "{e}");
        let e = parse_npy(f, &with_shape("(1, 100000000000000000000000)"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("larger than u64"), "{e}");
    }

    #[test]
    fn rows_stream_in_blocks_from_npy_and_csv() {
        let values: Vec<f64> = (0..10).map(f64::from).collect();
        let bytes: Vec<u8> = values.iter().flat_map(|x| x.to_le_bytes()).collect();
        let f = Path::new("v.npy");
        let npy_bytes = npy("<f8", (5, 2), &bytes);
        let mut rows = ValueRows::npy(f, &npy_bytes[..]).unwrap();
        assert_eq!(rows.cols(), 2);
        let blocks: Vec<usize> = std::iter::from_fn(|| {
            let b = rows.next_rows(2).unwrap();
            (!b.is_empty()).then_some(b.len())
        })
        .collect();
        assert_eq!(blocks, [2, 2, 1]);
        // A file cut inside its last row is an error, not a short row.
        let cut = &npy_bytes[..npy_bytes.len() - 8];
        let e = ValueRows::npy(f, cut)
            .unwrap()
            .next_rows(9)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("v.npy") && e.contains("cannot read the data"),
            "{e}"
        );
        let text = b"0,1\n# c\n2,3\n4,5\n";
        let mut rows = ValueRows::csv(Path::new("v.csv"), &text[..]).unwrap();
        assert_eq!(
            rows.next_rows(2).unwrap(),
            vec![vec![0.0, 1.0], vec![2.0, 3.0]]
        );
        assert_eq!(rows.next_rows(2).unwrap(), vec![vec![4.0, 5.0]]);
        assert!(rows.next_rows(2).unwrap().is_empty());
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
