//! The error of every reader and writer: it names the file and, for a defect
//! in the contents, the line (1-based), the column and the offending value.

use laminar_brdf_fit::{MeasurementError, ModelError};
use std::path::PathBuf;
use thiserror::Error;

/// A file that cannot be read or written, or whose contents are wrong.
#[derive(Debug, Error)]
pub enum ReadError {
    /// The file system refused.
    #[error("{}: cannot {action}: {source}", file.display())]
    Io {
        /// The file.
        file: PathBuf,
        /// `read`, `write`, `create`.
        action: &'static str,
        /// Why.
        source: std::io::Error,
    },
    /// A defect in the contents (line 0: the file as a whole).
    #[error("{}{}: {message}", file.display(), if *line > 0 { format!(":{line}") } else { String::new() })]
    Format {
        /// The file.
        file: PathBuf,
        /// 1-based line (0: the whole file).
        line: usize,
        /// What is wrong, naming the column and quoting the value.
        message: String,
    },
    /// Contents that do not make a valid measurement set.
    #[error("{}: {source}", file.display())]
    Measurements {
        /// The file.
        file: PathBuf,
        /// Why.
        source: MeasurementError,
    },
    /// An output path that names one of the command's own inputs (however
    /// the two are spelled): writing would destroy the input.
    #[error("{}: is also the input {}; choose another output path (nothing was written)", out.display(), input.display())]
    OutputIsInput {
        /// The output path as given.
        out: PathBuf,
        /// The input path as given.
        input: PathBuf,
    },
    /// A fitted model that cannot predict.
    #[error("{}: fit {fit}: {source}", file.display())]
    Model {
        /// The file.
        file: PathBuf,
        /// The fit's label, `sample/channel/model`.
        fit: String,
        /// Why.
        source: ModelError,
    },
}

impl ReadError {
    /// A defect at `line` of `file`.
    pub fn format(file: &std::path::Path, line: usize, message: impl Into<String>) -> Self {
        Self::Format {
            file: file.to_path_buf(),
            line,
            message: message.into(),
        }
    }

    /// An I/O failure.
    pub fn io(file: &std::path::Path, action: &'static str, source: std::io::Error) -> Self {
        Self::Io {
            file: file.to_path_buf(),
            action,
            source,
        }
    }

    /// The 1-based line of a contents defect, if any.
    pub fn line(&self) -> Option<usize> {
        match self {
            Self::Format { line, .. } if *line > 0 => Some(*line),
            _ => None,
        }
    }
}
