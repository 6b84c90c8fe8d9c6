//! Conversions between Python and the library: arrays, errors, options
//! by name, result types as Python objects.

use laminar_brdf_fit::{MeasurementAngles, Model, ModelParams};
use laminar_brdf_io::ReadError;
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

/// A Python object's type name, for messages.
fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .name()
        .map_or_else(|_| "?".into(), |n| n.to_string())
}

/// A Python object as messages show it: its repr and its type name.
fn shown(obj: &Bound<'_, PyAny>) -> String {
    let repr = obj.repr().map_or_else(|_| "?".into(), |r| r.to_string());
    format!("{repr} ({})", type_name(obj))
}

/// `obj` as a flag: `True` or `False` (a numpy bool too: `bool` in numpy
/// 2, `bool_` before), else `ValueError` naming the argument `name`.
pub(crate) fn flag(name: &str, obj: &Bound<'_, PyAny>) -> PyResult<bool> {
    let is_bool = obj.is_instance_of::<pyo3::types::PyBool>()
        || matches!(type_name(obj).as_str(), "bool" | "bool_");
    match obj.extract::<bool>() {
        Ok(v) if is_bool => Ok(v),
        _ => Err(PyValueError::new_err(format!(
            "{name}: give True or False, not {}",
            shown(obj)
        ))),
    }
}

/// `obj` as a whole number from `least` to `most` (a Python or numpy
/// integer; not a bool), else `ValueError` naming the argument `name`.
pub(crate) fn whole(
    name: &str,
    obj: &Bound<'_, PyAny>,
    (least, most): (u64, u64),
) -> PyResult<u64> {
    let bad = || {
        PyValueError::new_err(format!(
            "{name}: give a whole number from {least} to {most}, not {}",
            shown(obj)
        ))
    };
    if obj.is_instance_of::<pyo3::types::PyBool>() {
        return Err(bad());
    }
    let index = obj.call_method0("__index__").map_err(|_| bad())?;
    let value: i128 = index.extract().map_err(|_| bad())?;
    u64::try_from(value)
        .ok()
        .filter(|v| (least..=most).contains(v))
        .ok_or_else(bad)
}

/// An optional count (`None` is kept), as [`whole`].
pub(crate) fn optional_count(
    name: &str,
    obj: Option<&Bound<'_, PyAny>>,
) -> PyResult<Option<usize>> {
    obj.filter(|o| !o.is_none())
        .map(|o| whole(name, o, (0, u32::MAX.into())).map(|v| v as usize))
        .transpose()
}

/// `obj` (an array or a sequence) as a C-ordered float64 numpy array of
/// `ndim` dimensions: real numbers (floats, integers) only; a complex,
/// boolean or non-numeric array is a `ValueError` naming the argument
/// `name` (numpy would drop an imaginary part with a warning only).
pub(crate) fn real_array<'py>(
    name: &str,
    obj: &Bound<'py, PyAny>,
    ndim: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let numpy = obj.py().import("numpy")?;
    let array = numpy
        .call_method1("asarray", (obj,))
        .map_err(|e| PyValueError::new_err(format!("{name}: not an array of numbers ({e})")))?;
    let dtype = array.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    let shown = dtype.str()?.to_string();
    match kind.as_str() {
        "f" | "i" | "u" => {}
        "c" => {
            return Err(PyValueError::new_err(format!(
                "{name}: complex values ({shown}); give real numbers"
            )))
        }
        _ => {
            return Err(PyValueError::new_err(format!(
                "{name}: values of type {shown}; give real numbers (floats or integers)"
            )))
        }
    }
    let dims: usize = array.getattr("ndim")?.extract()?;
    if dims != ndim {
        let shape = array.getattr("shape")?.repr()?.to_string();
        return Err(PyValueError::new_err(format!(
            "{name}: shape {shape}; a {ndim}-dimensional array is needed"
        )));
    }
    numpy.call_method1("ascontiguousarray", (array, "float64"))
}

/// [`real_array`] of one dimension, its values.
pub(crate) fn real_vec(name: &str, obj: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
    let array = real_array(name, obj, 1)?;
    let array: PyReadonlyArray1<'_, f64> = array.extract()?;
    vec1(&array)
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
