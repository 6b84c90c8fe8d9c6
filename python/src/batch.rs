//! `fit_batch`: many sets on one geometry, as the batch fields
//! ([`BatchRow`]) that `laminar fit-batch` writes.

use crate::convert::{lab_angles, layered_names, parse, real_array, reserve};
use crate::fit_result::{fitter, refine_threads, Named};
use laminar_brdf_fit::analysis::DEFAULT_RESAMPLES;
use laminar_brdf_fit::noise::DEFAULT_FLOOR;
use laminar_brdf_fit::{MeasurementSet, Model, Quantity};
use laminar_brdf_io::fits::BatchRow;
use numpy::{IntoPyArray, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::HashMap;

/// Sets per batch search in [`fit_batch`] (as `laminar fit-batch`).
const BLOCK: usize = 256;

/// The layered `model` named by `name`, or a ValueError naming the
/// layered models.
fn layered(name: &str) -> PyResult<Model> {
    let model: Model = parse("model", name)?;
    if model.correlation().is_none() {
        return Err(PyValueError::new_err(format!(
            "model: fit_batch fits the layered models ({}), not {model}",
            layered_names()
        )));
    }
    Ok(model)
}

/// The fields of `fit_batch`'s result for `model` (a layered model), in
/// order, each with its dtype: the tied models' `BATCH_DTYPES`, and the
/// untied models' (`exp2`, `gauss2`) those with σ′/T′'s fields
/// (`sub_slope`, `sub_slope_lo68`, …) after σ/T's.
#[pyfunction]
#[pyo3(signature = (model = "exp"))]
pub(crate) fn batch_fields(model: &str) -> PyResult<Vec<(String, &'static str)>> {
    let row = BatchRow::new(&[layered(model)?]);
    Ok(row
        .names()
        .into_iter()
        .zip(row.kinds().into_iter().map(|k| k.dtype()))
        .collect())
}

/// Fits `model` (a layered model) to every row of `values` (N × K) on one
/// geometry (`geometry`: K × 4 lab-frame angles theta_i, phi_i, theta_v,
/// phi_v in radians), by the shared-geometry batch search, 256 rows at a time:
/// a column per field of [`batch_fields`]`(model)`.
#[pyfunction]
#[pyo3(signature = (geometry, values, model = "exp", grid = None, threads = None, quantity = "brdf", refine = None, uncertainty = "both", objective = "free", precision = "f64", noise = "given", noise_floor = DEFAULT_FLOOR))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn fit_batch<'py>(
    py: Python<'py>,
    geometry: Bound<'py, PyAny>,
    values: Bound<'py, PyAny>,
    model: &str,
    grid: Option<HashMap<String, Bound<'py, PyAny>>>,
    threads: Option<Bound<'py, PyAny>>,
    quantity: &str,
    refine: Option<Bound<'py, PyAny>>,
    uncertainty: &str,
    objective: &str,
    precision: &str,
    noise: &str,
    noise_floor: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let model = layered(model)?;
    let quantity: Quantity = parse("quantity", quantity)?;
    let named = Named {
        objective,
        uncertainty,
        precision,
        resamples: DEFAULT_RESAMPLES as u64,
        seed: 0,
        folds: 0,
        noise,
        noise_floor,
    };
    let (refine, threads) = refine_threads(refine.as_ref(), threads.as_ref())?;
    let fitter = fitter(grid, threads, refine, named)?;
    let geometry: PyReadonlyArray2<'py, f64> = real_array("geometry", &geometry, 2)?.extract()?;
    let values: PyReadonlyArray2<'py, f64> = real_array("values", &values, 2)?.extract()?;
    let g = geometry.as_array();
    if g.ncols() != 4 {
        return Err(PyValueError::new_err(format!(
            "geometry: shape ({}, {}); (K, 4) lab-frame angles theta_i, phi_i, theta_v, phi_v are needed",
            g.nrows(),
            g.ncols()
        )));
    }
    let col = |c: usize| g.column(c).to_vec();
    let angles = lab_angles(&col(0), &col(1), &col(2), &col(3))?;
    let v = values.as_array();
    if v.ncols() != angles.len() {
        return Err(PyValueError::new_err(format!(
            "values: {} values per set but the geometry has {} rows",
            v.ncols(),
            angles.len()
        )));
    }
    // The sets are read a block at a time from the caller's array; what
    // grows with N (the result rows) is reserved first.
    let sets = v.nrows();
    let row = BatchRow::new(&[model]);
    let width = row.width();
    let mut out: Vec<f64> = reserve(sets.saturating_mul(width), "the results")?;
    py.detach(|| -> Result<(), String> {
        for start in (0..sets).step_by(BLOCK) {
            let scenes = (start..(start + BLOCK).min(sets))
                .map(|r| {
                    MeasurementSet::new(r.to_string(), angles.clone(), quantity)
                        .and_then(|s| s.with_channel("value", v.row(r).to_vec(), None))
                        .and_then(|s| s.scene("value"))
                        .map_err(|e| format!("values row {r}: {e}"))
                })
                .collect::<Result<Vec<_>, _>>()?;
            for fit in fitter.fit_batch(&scenes, model) {
                row.push_row(&fit, &mut out);
            }
        }
        Ok(())
    })
    .map_err(PyValueError::new_err)?;
    let dict = PyDict::new(py);
    for (c, name) in row.names().iter().enumerate() {
        let mut column: Vec<f64> = reserve(sets, "an output column")?;
        column.extend(out.iter().skip(c).step_by(width));
        dict.set_item(name, column.into_pyarray(py))?;
    }
    Ok(dict)
}
