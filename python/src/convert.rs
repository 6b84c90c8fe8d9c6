//! Conversions between Python and the library: arrays, errors, options
//! by name, result types as Python objects.

use laminar_fit::{MeasurementAngles, Model, ModelParams};
use laminar_io::ReadError;
use numpy::PyReadonlyArray1;
use pyo3::exceptions::{PyMemoryError, PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The values of a 1-D array, whatever its strides (a broadcast array may
/// claim more elements than memory holds: [`reserve`]).
pub(crate) fn vec1(a: &PyReadonlyArray1<'_, f64>) -> PyResult<Vec<f64>> {
    let a = a.as_array();
    let mut out = reserve(a.len(), "an array")?;
    out.extend(a.iter().copied());
    Ok(out)
}

/// An empty vector with room for `len` values, or `MemoryError` naming
/// `what` and the size: a size that comes from the caller's arrays is never
/// allocated infallibly (that aborted the interpreter).
pub(crate) fn reserve<T>(len: usize, what: &str) -> PyResult<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(len).map_err(|_| {
        let bytes = len as f64 * std::mem::size_of::<T>() as f64;
        PyMemoryError::new_err(format!(
            "not enough memory for {what} of {len} values ({:.3} GiB)",
            bytes / f64::from(1u32 << 30)
        ))
    })?;
    Ok(v)
}

pub(crate) fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

pub(crate) fn read_error(e: ReadError) -> PyErr {
    match e {
        ReadError::Io { .. } => PyOSError::new_err(e.to_string()),
        other => value_error(other),
    }
}

/// A result type as Python objects (dicts, lists, floats, strings, None),
/// straight from its serde form: the same fields and names the
/// fitted-model file holds, without going through JSON text.
pub(crate) fn to_python<'py>(
    py: Python<'py>,
    value: &impl serde::Serialize,
) -> PyResult<Bound<'py, PyAny>> {
    pythonize::pythonize(py, value).map_err(|e| PyValueError::new_err(e.to_string()))
}

pub(crate) fn parse<T: std::str::FromStr>(what: &str, text: &str) -> PyResult<T>
where
    T::Err: std::fmt::Display,
{
    text.parse()
        .map_err(|e| PyValueError::new_err(format!("{what}: {e}")))
}

pub(crate) fn lab_angles(
    theta_i: &[f64],
    phi_i: &[f64],
    theta_v: &[f64],
    phi_v: &[f64],
) -> PyResult<Vec<MeasurementAngles>> {
    let k = theta_i.len();
    if phi_i.len() != k || theta_v.len() != k || phi_v.len() != k {
        return Err(value_error(
            "theta_i, phi_i, theta_v, phi_v must have the same length",
        ));
    }
    Ok((0..k)
        .map(|i| MeasurementAngles::Lab {
            theta_i: theta_i[i],
            phi_i: phi_i[i],
            theta_v: theta_v[i],
            phi_v: phi_v[i],
        })
        .collect())
}

pub(crate) fn params_dict<'py>(
    py: Python<'py>,
    params: &ModelParams,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (p, value) in params.pairs() {
        d.set_item(p.name(), value)?;
    }
    Ok(d)
}

/// The layered models' names (from the descriptor, [`Model::ALL`]), for
/// the messages of what takes only them.
pub(crate) fn layered_names() -> String {
    Model::ALL
        .into_iter()
        .filter(|m| m.correlation().is_some())
        .map(Model::name)
        .collect::<Vec<_>>()
        .join(", ")
}
