//! `evaluate` and `paper_angles`: the model's components at given angles.

use crate::convert::{layered_names, parse, reserve, value_error};
use laminar_brdf_core::{components, Angles, Geometry, Params};
use laminar_brdf_fit::{MeasurementAngles, Model};
use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Evaluates every component of a layered model (eqs. 1–14, eq. 8 total) at
/// equal-length arrays of paper-frame angles and parameters; `sub_slope`
/// (σ′/T′) for the untied models, and for them only.
#[pyfunction]
#[pyo3(signature = (model, theta_i, theta_s, phi_s, slope, beta, n, a, sub_slope = None, precision = "f64"))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn evaluate<'py>(
    py: Python<'py>,
    model: &str,
    theta_i: PyReadonlyArray1<'py, f64>,
    theta_s: PyReadonlyArray1<'py, f64>,
    phi_s: PyReadonlyArray1<'py, f64>,
    slope: PyReadonlyArray1<'py, f64>,
    beta: PyReadonlyArray1<'py, f64>,
    n: PyReadonlyArray1<'py, f64>,
    a: PyReadonlyArray1<'py, f64>,
    sub_slope: Option<PyReadonlyArray1<'py, f64>>,
    precision: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let model: Model = parse("model", model)?;
    let corr = model.correlation().ok_or_else(|| {
        PyValueError::new_err(format!(
            "model: {model} is not a layered model ({})",
            layered_names()
        ))
    })?;
    let single = match precision {
        "f64" => false,
        "f32" => true,
        other => {
            return Err(PyValueError::new_err(format!(
                "precision: `{other}` is not f32 or f64"
            )))
        }
    };
    let sub_slope = match (model.is_untied(), sub_slope) {
        (true, Some(sub)) => sub,
        (true, None) => {
            return Err(value_error(format!(
                "sub_slope: {model} frees the subsurface slope σ′/T′; give sub_slope"
            )))
        }
        (false, Some(_)) => {
            return Err(value_error(format!(
                "sub_slope: {model} ties σ′/T′ to σ/T; give sub_slope to {} only",
                Model::ALL
                    .into_iter()
                    .filter(|m| m.is_untied())
                    .map(Model::name)
                    .collect::<Vec<_>>()
                    .join(", ")
            )))
        }
        (false, None) => slope.clone(),
    };
    let columns = [
        &theta_i, &theta_s, &phi_s, &slope, &beta, &n, &a, &sub_slope,
    ]
    .map(|c| c.as_array());
    let len = columns[0].len();
    if columns.iter().any(|c| c.len() != len) {
        return Err(value_error("all arrays must have the same length"));
    }
    // The seven output columns, each reserved before any work: read in
    // place, nothing else grows with the length.
    let mut out: Vec<Vec<f64>> = Vec::with_capacity(7);
    for _ in 0..7 {
        out.push(reserve(len, "an output column")?);
    }
    let rh = model.is_ragheb_hancock();
    py.detach(|| -> Result<(), String> {
        for i in 0..len {
            let [ti, ts, ps, s, b, n, a, sub] = columns.each_ref().map(|c| c[i]);
            if rh && a != 0.0 {
                return Err(format!("a: element {i} is {a}; {model} is the a = 0 model"));
            }
            let p = Params::untied(s, sub, b, n, a).map_err(|e| format!("element {i}: {e}"))?;
            let g = Angles::new(ti, ts, ps).map_err(|e| format!("element {i}: {e}"))?;
            let values = if single {
                components(&Geometry::<f32>::splat(&g), corr, &p)
                    .to_array()
                    .map(f64::from)
            } else {
                components(&Geometry::<f64>::splat(&g), corr, &p).to_array()
            };
            for (column, v) in out.iter_mut().zip(values) {
                column.push(v);
            }
        }
        Ok(())
    })
    .map_err(PyValueError::new_err)?;
    let dict = PyDict::new(py);
    for (name, column) in laminar_brdf_core::Components::<f64>::NAMES.iter().zip(out) {
        dict.set_item(*name, column.into_pyarray(py))?;
    }
    Ok(dict)
}

/// The paper-frame angles `(theta_i, theta_s, phi_s)` of lab-frame ones
/// (docs/conventions.md §1).
#[pyfunction]
pub(crate) fn paper_angles(
    theta_i: f64,
    phi_i: f64,
    theta_v: f64,
    phi_v: f64,
) -> PyResult<(f64, f64, f64)> {
    let a = MeasurementAngles::Lab {
        theta_i,
        phi_i,
        theta_v,
        phi_v,
    }
    .paper()
    .map_err(value_error)?;
    Ok((a.theta_i(), a.theta_s(), a.phi_s()))
}
