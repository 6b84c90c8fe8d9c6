//! # laminar-brdf
//!
//! The `laminar` command's building blocks: which data a command runs on
//! ([`selection`]), the paper's experiment ([`reproduce`], [`tables`],
//! [`figures`]) and the speed-against-error report ([`speed`]). The fitting
//! itself is `laminar-brdf-fit`; files are read and written by `laminar-brdf-io`.

pub mod figures;
pub mod reproduce;
pub mod scaling;
pub mod selection;
pub mod speed;
pub mod tables;
pub mod terminal;
pub mod usage;

/// The README's Rust code, compiled and run by `cargo test --doc` (its other
/// blocks run in `tests/docs.rs` and the Python and web tests).
#[doc = include_str!("../../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

use thiserror::Error;

/// Why a command failed (the binary prints it and exits with status 2).
#[derive(Debug, Error)]
pub enum CliError {
    /// A file.
    #[error(transparent)]
    Read(#[from] laminar_brdf_io::ReadError),
    /// A fit.
    #[error(transparent)]
    Fit(#[from] laminar_brdf_fit::FitError),
    /// The grid.
    #[error(transparent)]
    Grid(#[from] laminar_brdf_fit::GridError),
    /// A model or its parameters.
    #[error(transparent)]
    Model(#[from] laminar_brdf_fit::ModelError),
    /// Measurements that cannot be fitted.
    #[error(transparent)]
    Measurements(#[from] laminar_brdf_fit::MeasurementError),
    /// A CSV output could not be written.
    #[error("writing {to}: {source}")]
    Output {
        /// Where (`stdout`, `CSV`).
        to: &'static str,
        /// Why.
        source: csv::Error,
    },
    /// A figure could not be drawn.
    #[error("drawing a figure: {0}")]
    Figure(String),
    /// `LAMINAR_SIMD` names lanes this processor cannot run, or none.
    #[error(transparent)]
    Simd(#[from] laminar_brdf_fit::simd::SimdError),
    /// Options that do not fit together, values out of range, inputs that
    /// do not match.
    #[error(transparent)]
    Usage(#[from] usage::UsageError),
}
