//! The native part of the `laminar_brdf` Python package (`laminar_brdf._laminar`):
//! thin PyO3 bindings over `laminar-brdf-core` (evaluate), `laminar-brdf-fit` (fit,
//! batch fit, fitted models) and `laminar-brdf-io` (readers, the fitted-model
//! file). numpy arrays in and out; the GIL is released around every piece
//! of Rust work; errors become `ValueError` (bad input, naming the
//! parameter, file, line or row) or `OSError` (a file that cannot be read).
//! The Python-facing API (broadcasting, structured arrays, docs) is in
//! `laminar_brdf/__init__.py`.
//!
//! One module per concern: `convert` (arrays, errors and names between
//! Python and the library), `evaluate` (the model's components),
//! `measurements` (`Measurements`), `fit_result` (`fit`, `compare`,
//! `FitResult`), `fitted_model` (`FittedModel`, `render`) and `batch`
//! (`fit_batch`); this file registers them and the descriptor's lists.

mod batch;
mod convert;
mod evaluate;
mod fit_result;
mod fitted_model;
mod joint;
mod measurements;

use laminar_brdf_fit::{Edge, Grid, Model, Param};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The lanes the fitting kernels run with: `"avx2"` or `"portable"`
/// (`LAMINAR_SIMD` forces one; every path gives the same bits).
///
/// Raises `ValueError` when `LAMINAR_SIMD` names no path or one this
/// processor cannot run.
#[pyfunction]
fn simd_path() -> PyResult<&'static str> {
    laminar_brdf_fit::simd::from_env()
        .map(|path| path.name())
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))
}

/// The native module.
#[pymodule]
fn _laminar(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(evaluate::evaluate, m)?)?;
    m.add_function(wrap_pyfunction!(fit_result::fit, m)?)?;
    m.add_function(wrap_pyfunction!(batch::fit_batch, m)?)?;
    m.add_function(wrap_pyfunction!(batch::batch_fields, m)?)?;
    m.add_function(wrap_pyfunction!(fit_result::compare, m)?)?;
    m.add_function(wrap_pyfunction!(joint::fit_joint, m)?)?;
    m.add_function(wrap_pyfunction!(evaluate::paper_angles, m)?)?;
    m.add_function(wrap_pyfunction!(simd_path, m)?)?;
    m.add_class::<measurements::Measurements>()?;
    m.add_class::<fit_result::FitResult>()?;
    m.add_class::<fitted_model::FittedModel>()?;
    m.add_function(wrap_pyfunction!(fitted_model::render, m)?)?;
    // The tied layered models' fields (the untied ones: batch_fields).
    let fields = batch::batch_fields("exp")?;
    let names: Vec<&str> = fields.iter().map(|(name, _)| name.as_str()).collect();
    m.add("BATCH_COLUMNS", names)?;
    m.add("BATCH_DTYPES", fields)?;
    let flags = PyDict::new(m.py());
    for edge in Edge::ALL {
        flags.set_item(edge.to_string(), edge.bit())?;
    }
    m.add("FLAG_BITS", flags)?;
    // The model descriptor (laminar_brdf_fit::Model): every list a Python user
    // needs comes from here.
    let models = PyDict::new(m.py());
    for model in Model::ALL {
        let info = PyDict::new(m.py());
        info.set_item("description", model.description())?;
        info.set_item(
            "params",
            model.params().iter().map(|p| p.name()).collect::<Vec<_>>(),
        )?;
        info.set_item(
            "free_params",
            model
                .free_params()
                .iter()
                .map(|p| p.name())
                .collect::<Vec<_>>(),
        )?;
        info.set_item("correlation", model.correlation().map(|c| c.name()))?;
        models.set_item(model.name(), info)?;
    }
    m.add("MODELS", models)?;
    m.add("GRID_AXES", Grid::PARAMS.map(Param::name).to_vec())?;
    Ok(())
}
