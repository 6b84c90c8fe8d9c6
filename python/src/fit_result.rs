//! `fit`, `compare` and `FitResult`: one set's fits and their analysis.

use crate::convert::{
    flag, lab_angles, optional_count, params_dict, parse, to_python, value_error, vec1, whole,
};
use crate::measurements::Measurements;
use laminar_brdf_core::Angles;
use laminar_brdf_fit::analysis::DEFAULT_RESAMPLES;
use laminar_brdf_fit::noise::DEFAULT_FLOOR;
use laminar_brdf_fit::{Axis, Fit, Fitter, Model, SettingError, Settings};
use laminar_brdf_io::fits;
use laminar_brdf_io::fits::FitEntry;
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::HashMap;

/// The options of `fit`, `compare` and `fit_batch` that the library's
/// settings take by name ([`Settings::set`], whose error names the option).
pub(crate) struct Named<'a> {
    pub objective: &'a str,
    pub uncertainty: &'a str,
    pub precision: &'a str,
    pub resamples: u64,
    pub seed: u64,
    pub folds: u64,
    pub noise: &'a str,
    pub noise_floor: f64,
}

/// `refine` (default true) as a flag, `threads` (default all) as a count,
/// each checked by name.
pub(crate) fn refine_threads(
    refine: Option<&Bound<'_, PyAny>>,
    threads: Option<&Bound<'_, PyAny>>,
) -> PyResult<(bool, Option<usize>)> {
    let refine = refine.map_or(Ok(true), |r| flag("refine", r))?;
    Ok((refine, optional_count("threads", threads)?))
}

/// A whole-number option `name` (default `default`), checked by name; its
/// range is the library's setting's ([`Settings::set`]).
pub(crate) fn whole_or(name: &str, obj: Option<&Bound<'_, PyAny>>, default: u64) -> PyResult<u64> {
    obj.map_or(Ok(default), |o| whole(name, o, (0, u64::MAX)))
}

/// The fitter of `fit`, `compare` and `fit_batch`: the `named` options
/// handed to the library's settings by name; a grid axis is its text or a
/// sequence of values.
pub(crate) fn fitter(
    grid: Option<HashMap<String, Bound<'_, PyAny>>>,
    threads: Option<usize>,
    refine: bool,
    named: Named<'_>,
) -> PyResult<Fitter> {
    let mut s = Settings::default();
    for (name, value) in [
        ("objective", named.objective.to_string()),
        ("uncertainty", named.uncertainty.to_string()),
        ("precision", named.precision.to_string()),
        ("resamples", named.resamples.to_string()),
        ("seed", named.seed.to_string()),
        ("folds", named.folds.to_string()),
        ("noise_floor", named.noise_floor.to_string()),
        ("noise", named.noise.to_string()),
    ] {
        s.set(name, &value).map_err(value_error)?;
    }
    s.analysis.refine = refine;
    s.threads = threads;
    for (name, spec) in grid.unwrap_or_default() {
        let at = |e: SettingError| PyValueError::new_err(format!("grid[{name:?}]: {e}"));
        let p = Settings::axis_param(&name).map_err(at)?;
        let axis = match spec.extract::<String>() {
            Ok(text) => Axis::parse(&text)
                .map_err(|e| PyValueError::new_err(format!("grid[{name:?}]: {e}")))?,
            Err(_) => Axis {
                values: spec.extract::<Vec<f64>>().map_err(|_| {
                    PyValueError::new_err(format!(
                        "grid[{name:?}]: give \"start:stop:count\" or a sequence of numbers"
                    ))
                })?,
            },
        };
        s.set_axis(p, axis);
    }
    s.fitter().map_err(value_error)
}

/// One fit: the refined estimate (the best grid point when not refined),
/// its errors and uncertainties, the best grid point, the Ragheb–Hancock
/// best of the same search (layered models), and the fitted model.
#[pyclass(module = "laminar_brdf", frozen)]
pub(crate) struct FitResult {
    pub(crate) fit: Fit,
}

#[pymethods]
impl FitResult {
    /// The model's name.
    #[getter]
    fn model(&self) -> &'static str {
        self.fit.model.name()
    }

    /// The fitted model's parameters (full precision; the file's
    /// `fitted.params`): refined when refined. A parameter the data do not
    /// determine keeps its value here, which the model predicts with;
    /// `parameters[name]["refined"]` and its flags say `not_identified`.
    #[getter]
    fn params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        params_dict(py, &self.fit.estimate().fitted.params)
    }

    /// The best grid point's parameters.
    #[getter]
    fn grid_params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        params_dict(py, &self.fit.best.fitted.params)
    }

    /// Δ_RMS (eq. 15) at the fitted parameters, in f64.
    #[getter]
    fn rms(&self) -> f64 {
        self.fit.estimate().rms
    }

    /// Δ_RMS of the best grid point.
    #[getter]
    fn rms_grid(&self) -> f64 {
        self.fit.best.rms
    }

    /// Δ_RMS of the refined estimate (None when not refined); never above
    /// `rms_grid`.
    #[getter]
    fn rms_refined(&self) -> Option<f64> {
        self.fit.refined.as_ref().map(|e| e.rms)
    }

    /// χ²/ν (eq. 16) at the fitted parameters, or None when no degree of
    /// freedom is left.
    #[getter]
    fn chi2_dof(&self) -> Option<f64> {
        self.fit.estimate().chi2.map(|c| c.per_dof)
    }

    /// The Ragheb–Hancock best (a = 0) of the same search, as
    /// `{"params": …, "rms": …}`, for exp and gauss.
    #[getter]
    fn rh<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        self.fit
            .rh
            .as_ref()
            .map(|e| {
                let d = PyDict::new(py);
                d.set_item("params", params_dict(py, &e.fitted.params)?)?;
                d.set_item("rms", e.rms)?;
                Ok(d)
            })
            .transpose()
    }

    /// Each searched parameter under its name, as in the fitted-model file:
    /// `grid`, `refined`, `lo68`, `hi68`, `lo95`, `hi95`, `interval`
    /// (`"profile"` or `"jacobian"`), `sd` (Jacobian) and `flags`
    /// (`range_edge`, `domain_bound`, `open_below`, `open_above`).
    #[getter]
    fn parameters<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &FitEntry::new(&self.fit).parameters)
    }

    /// The Jacobian correlations of the refined parameters, `{"a~b": r}`.
    #[getter]
    fn correlations<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &FitEntry::new(&self.fit).correlations)
    }

    /// The pairs whose correlation is at least 0.9 in magnitude, `{"a~b": r}`.
    #[getter]
    fn trade_offs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &FitEntry::new(&self.fit).trade_offs)
    }

    /// The search's own Δ_RMS at the best point (its precision).
    #[getter]
    fn search_rms(&self) -> f64 {
        self.fit.search_rms
    }

    /// Measurements kept (specular ones left out).
    #[getter]
    fn measurements(&self) -> usize {
        self.fit.measurements
    }

    /// The balance of eq. 8 giving the fitted lobe (layered models; the
    /// fitted β itself under the free objective).
    #[getter]
    fn beta_eq8(&self) -> Option<f64> {
        self.fit.estimate().fitted.beta_eq8
    }

    /// The objective minimised: `"free"` or `"paper"`.
    #[getter]
    fn objective(&self) -> &'static str {
        self.fit.objective.name()
    }

    /// Free objective: the fitted amplitude (prediction = amplitude · eq. 8's
    /// mix on the data divided by their max); None for the paper objective.
    #[getter]
    fn amplitude(&self) -> Option<f64> {
        self.fit.amplitude
    }

    /// Free objective: the weighted χ²/ν of the estimate (w = 1/σ²).
    #[getter]
    fn chi2_weighted(&self) -> Option<f64> {
        self.fit.chi2_weighted
    }

    /// Free objective, refined: what the residuals say of the model's
    /// adequacy, `{"chi2_p", "runs_z", "runs_p", "lack_of_fit"}` (None
    /// where not computed).
    #[getter]
    fn adequacy<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.fit.adequacy)
    }

    /// Free objective, refined: the information criteria, `{"aic", "aicc", "bic"}`.
    #[getter]
    fn information<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.fit.information)
    }

    /// From `compare`: the model's place among those compared,
    /// `{"rank", "delta", "weight"}` (ΔAICc and the Akaike weight).
    #[getter]
    fn rank<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.fit.rank)
    }

    /// From `compare`: the K-fold cross-validated error,
    /// `{"folds", "rms", "in_sample"}`.
    #[getter]
    fn cross_validation<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.fit.cross_validation)
    }

    /// The graphics literature's error measures of the estimate,
    /// `{"cosine_rms", "cube_root"}` (Ngan et al.'s cos θi-weighted RMS and
    /// Forés et al.'s cube-root distance, in the input's units).
    #[getter]
    fn graphics<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.fit.estimate().graphics)
    }

    /// The normalised prediction P at lab-frame angles (radians), as the fit
    /// predicted its own data; `radiance=True` multiplies by the data's
    /// scale (radiance in the input's units).
    #[pyo3(signature = (theta_i, phi_i, theta_v, phi_v, radiance = false))]
    fn predict<'py>(
        &self,
        py: Python<'py>,
        theta_i: PyReadonlyArray1<'py, f64>,
        phi_i: PyReadonlyArray1<'py, f64>,
        theta_v: PyReadonlyArray1<'py, f64>,
        phi_v: PyReadonlyArray1<'py, f64>,
        radiance: bool,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let angles = lab_angles(
            &vec1(&theta_i)?,
            &vec1(&phi_i)?,
            &vec1(&theta_v)?,
            &vec1(&phi_v)?,
        )?
        .iter()
        .enumerate()
        .map(|(k, a)| {
            a.paper()
                .map_err(|e| PyValueError::new_err(format!("element {k}: {e}")))
        })
        .collect::<PyResult<Vec<Angles>>>()?;
        let fitted = &self.fit.estimate().fitted;
        let out = py.detach(|| {
            if radiance {
                fitted.predict_radiance(&angles)
            } else {
                fitted.predict(&angles)
            }
        });
        Ok(out.map_err(value_error)?.into_pyarray(py))
    }

    /// The fitted-model file of this fit (what `laminar fit --format json` writes).
    fn to_json(&self) -> String {
        fits::json(std::slice::from_ref(&self.fit))
    }

    fn __repr__(&self) -> String {
        format!(
            "FitResult(model={:?}, params={}, rms={})",
            self.fit.model.name(),
            self.fit.params_text(),
            self.fit.estimate().rms
        )
    }
}

/// Fits `model` to `measurements` by the exhaustive grid search, then
/// refines it and measures the uncertainty of its parameters.
#[pyfunction]
#[pyo3(signature = (measurements, model = "exp", grid = None, refine = None, uncertainty = "both", threads = None, objective = "free", resamples = None, seed = None, precision = "f64", noise = "given", noise_floor = DEFAULT_FLOOR))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn fit(
    py: Python<'_>,
    measurements: &Measurements,
    model: &str,
    grid: Option<HashMap<String, Bound<'_, PyAny>>>,
    refine: Option<Bound<'_, PyAny>>,
    uncertainty: &str,
    threads: Option<Bound<'_, PyAny>>,
    objective: &str,
    resamples: Option<Bound<'_, PyAny>>,
    seed: Option<Bound<'_, PyAny>>,
    precision: &str,
    noise: &str,
    noise_floor: f64,
) -> PyResult<FitResult> {
    let model: Model = parse("model", model)?;
    let (refine, threads) = refine_threads(refine.as_ref(), threads.as_ref())?;
    let named = Named {
        objective,
        uncertainty,
        precision,
        resamples: whole_or("resamples", resamples.as_ref(), DEFAULT_RESAMPLES as u64)?,
        seed: whole_or("seed", seed.as_ref(), 0)?,
        folds: 0,
        noise,
        noise_floor,
    };
    let fitter = fitter(grid, threads, refine, named)?;
    fitter
        .objective_of_fits()
        .takes(model)
        .map_err(value_error)?;
    let scene = measurements.scene()?;
    let fit = py.detach(|| fitter.fit(&scene, model));
    Ok(FitResult { fit })
}

/// Fits each of ``models`` (an iterable of names; default: every model of
/// ``MODELS`` under the free objective, the tied ones under the paper's)
/// to a ``Measurements`` and compares them, as ``laminar fit``
/// does with several models: a list of ``FitResult`` in the order of
/// ``models``, each with its ``rank`` (``{"rank", "delta", "weight"}``: 1
/// for the lowest AICc, ΔAICc, the Akaike weight), ``information`` (AIC,
/// AICc, BIC), ``cross_validation`` (``folds``-fold, the folds dealt by
/// ``seed``; ``folds=0`` for none), ``adequacy`` and ``graphics``. The
/// other arguments are ``fit``'s. Ranks need the free objective and
/// ``refine``.
#[pyfunction]
#[pyo3(signature = (measurements, models = None, grid = None, refine = None, uncertainty = "both", threads = None, objective = "free", resamples = None, seed = None, folds = None, precision = "f64", noise = "given", noise_floor = DEFAULT_FLOOR))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn compare(
    py: Python<'_>,
    measurements: &Measurements,
    models: Option<Bound<'_, PyAny>>,
    grid: Option<HashMap<String, Bound<'_, PyAny>>>,
    refine: Option<Bound<'_, PyAny>>,
    uncertainty: &str,
    threads: Option<Bound<'_, PyAny>>,
    objective: &str,
    resamples: Option<Bound<'_, PyAny>>,
    seed: Option<Bound<'_, PyAny>>,
    folds: Option<Bound<'_, PyAny>>,
    precision: &str,
    noise: &str,
    noise_floor: f64,
) -> PyResult<Vec<FitResult>> {
    let (refine, threads) = refine_threads(refine.as_ref(), threads.as_ref())?;
    let models: Option<Vec<Model>> = match models {
        Some(names) if !names.is_instance_of::<pyo3::types::PyString>() => names
            .try_iter()
            .map_err(|_| PyTypeError::new_err("models: give an iterable of model names"))?
            .map(|m| {
                let name: String = m?
                    .extract()
                    .map_err(|_| PyTypeError::new_err("models: give model names (strings)"))?;
                parse("models", &name)
            })
            .collect::<PyResult<_>>()
            .map(Some)?,
        Some(_) => {
            return Err(PyTypeError::new_err(
                "models: give a list of model names, not one string",
            ))
        }
        None => None,
    };
    let named = Named {
        objective,
        uncertainty,
        precision,
        resamples: whole_or("resamples", resamples.as_ref(), DEFAULT_RESAMPLES as u64)?,
        seed: whole_or("seed", seed.as_ref(), 0)?,
        folds: whole_or("folds", folds.as_ref(), 5)?,
        noise,
        noise_floor,
    };
    let fitter = fitter(grid, threads, refine, named)?;
    let models = models.unwrap_or_else(|| fitter.objective_of_fits().default_models());
    let scene = measurements.scene()?;
    let fits = py
        .detach(|| fitter.fit_all(std::slice::from_ref(&scene), &models, |_, _| None))
        .map_err(value_error)?;
    Ok(fits.into_iter().map(|fit| FitResult { fit }).collect())
}
