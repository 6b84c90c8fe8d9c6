//! # laminar-brdf-io
//!
//! Readers and writers of the files laminar meets, beside the fitting
//! library (`laminar-brdf-fit`), which names no format. Every reader returns a
//! [`laminar_brdf_fit::MeasurementSet`] (or the parts of one) and every defect is
//! a [`ReadError`] naming the file, the line, the column and the value;
//! no input makes a reader panic.
//!
//! * [`astm`]: ASTM E1392 text files (the Cornell gonioreflectometer's spectral BRDFs).
//! * [`curet`]: CUReT's `table.txt`, BRDF tables and Oren–Nayar parameter files.
//! * [`csv_file`]: long-format CSV (one row per measurement, columns by name).
//! * [`nist`]: NIST's Mueller-matrix BRDF CSV (Germer 2017), a channel per wavelength.
//! * [`rgl`]: the RGL-EPFL database's isotropic RGB `.bsdf` tensor files.
//! * [`merl`]: MERL isotropic `.binary` files, read and written.
//! * [`fits`]: fits as CSV, Markdown and the JSON fitted-model file, read back.
//! * [`values`]: N × K arrays of values (`.npy`, CSV) for batch fits.

pub mod astm;
pub mod csv_file;
pub mod curet;
pub mod error;
pub mod fits;
pub mod image;
pub mod merl;
pub mod nist;
mod reader;
pub mod rgl;
pub mod selection;
pub mod staging;
pub mod values;

pub use csv_file::{read_csv, read_geometry, AngleUnit};
pub use error::ReadError;
pub use staging::{
    check_not_an_input, check_writable, write_atomic, write_atomic_bytes, AtomicFile,
};

#[cfg(test)]
mod typescript;
