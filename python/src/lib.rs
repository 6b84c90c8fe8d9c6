//! The native part of the `laminar` Python package (`laminar._laminar`):
//! thin PyO3 bindings over `laminar-core` (evaluate), `laminar-fit` (fit,
//! batch fit, fitted models) and `laminar-io` (readers, the fitted-model
//! file). numpy arrays in and out; the GIL is released around every piece
//! of Rust work; errors become `ValueError` (bad input, naming the
//! parameter, file, line or row) or `OSError` (a file that cannot be read).
//! The Python-facing API (broadcasting, structured arrays, docs) is in
//! `laminar/__init__.py`.

use laminar_core::{components, Angles, Geometry, Params};
use laminar_fit::{
    Axis, Edge, Fit, Fitter, Grid, MeasurementAngles, MeasurementSet, Model, ModelParams, Param,
    Quantity, Scene, SettingError, Settings,
};
use laminar_io::curet::{Channel, CuretDir};
use laminar_io::fits::{BatchRow, FitEntry};
use laminar_io::{fits, merl, read_csv, read_geometry, AngleUnit, ReadError};
use numpy::{IntoPyArray, PyArray1, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::{PyMemoryError, PyOSError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::HashMap;
use std::path::PathBuf;

/// Sets per batch search in [`fit_batch`] (as `laminar fit-batch`).
const BLOCK: usize = 256;

/// The values of a 1-D array, whatever its strides (a broadcast array may
/// claim more elements than memory holds: [`reserve`]).
fn vec1(a: &PyReadonlyArray1<'_, f64>) -> PyResult<Vec<f64>> {
    let a = a.as_array();
    let mut out = reserve(a.len(), "an array")?;
    out.extend(a.iter().copied());
    Ok(out)
}

/// An empty vector with room for `len` values, or `MemoryError` naming
/// `what` and the size: a size that comes from the caller's arrays is never
/// allocated infallibly (that aborted the interpreter).
fn reserve<T>(len: usize, what: &str) -> PyResult<Vec<T>> {
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

fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

fn read_error(e: ReadError) -> PyErr {
    match e {
        ReadError::Io { .. } => PyOSError::new_err(e.to_string()),
        other => value_error(other),
    }
}

/// A result type as Python objects (dicts, lists, floats, strings, None),
/// straight from its serde form: the same fields and names the
/// fitted-model file holds, without going through JSON text.
fn to_python<'py>(py: Python<'py>, value: &impl serde::Serialize) -> PyResult<Bound<'py, PyAny>> {
    pythonize::pythonize(py, value).map_err(|e| PyValueError::new_err(e.to_string()))
}

fn parse<T: std::str::FromStr>(what: &str, text: &str) -> PyResult<T>
where
    T::Err: std::fmt::Display,
{
    text.parse()
        .map_err(|e| PyValueError::new_err(format!("{what}: {e}")))
}

/// Evaluates every component of a layered model (eqs. 1–14, eq. 8 total) at
/// equal-length arrays of paper-frame angles and parameters.
#[pyfunction]
#[pyo3(signature = (model, theta_i, theta_s, phi_s, slope, beta, n, a, precision = "f64"))]
#[allow(clippy::too_many_arguments)]
fn evaluate<'py>(
    py: Python<'py>,
    model: &str,
    theta_i: PyReadonlyArray1<'py, f64>,
    theta_s: PyReadonlyArray1<'py, f64>,
    phi_s: PyReadonlyArray1<'py, f64>,
    slope: PyReadonlyArray1<'py, f64>,
    beta: PyReadonlyArray1<'py, f64>,
    n: PyReadonlyArray1<'py, f64>,
    a: PyReadonlyArray1<'py, f64>,
    precision: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let model: Model = parse("model", model)?;
    let corr = model.correlation().ok_or_else(|| {
        PyValueError::new_err(format!(
            "model: {model} is not a layered model (exp, gauss, rh-exp, rh-gauss)"
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
    let columns = [&theta_i, &theta_s, &phi_s, &slope, &beta, &n, &a].map(|c| c.as_array());
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
            let [ti, ts, ps, s, b, n, a] = columns.each_ref().map(|c| c[i]);
            if rh && a != 0.0 {
                return Err(format!("a: element {i} is {a}; {model} is the a = 0 model"));
            }
            let p = Params::new(s, b, n, a).map_err(|e| format!("element {i}: {e}"))?;
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
    for (name, column) in laminar_core::Components::<f64>::NAMES.iter().zip(out) {
        dict.set_item(*name, column.into_pyarray(py))?;
    }
    Ok(dict)
}

/// A measurement set and the channel of it to fit.
#[pyclass(module = "laminar", frozen)]
struct Measurements {
    set: MeasurementSet,
    channel: String,
}

impl Measurements {
    fn pick(set: MeasurementSet, channel: Option<&str>) -> PyResult<Self> {
        let names: Vec<String> = set.channel_names().iter().map(|c| c.to_string()).collect();
        let channel = match channel {
            Some(c) if names.iter().any(|n| n == c) => c.to_string(),
            Some(c) => {
                return Err(PyValueError::new_err(format!(
                    "channel: `{c}` is not one of {}",
                    names.join(", ")
                )))
            }
            None if names.len() == 1 => names[0].clone(),
            None => {
                return Err(PyValueError::new_err(format!(
                    "channel: the set has channels {}; name one",
                    names.join(", ")
                )))
            }
        };
        Ok(Self { set, channel })
    }

    fn scene(&self) -> PyResult<Scene> {
        self.set.scene(&self.channel).map_err(value_error)
    }
}

fn lab_angles(
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

#[pymethods]
impl Measurements {
    /// From arrays of lab-frame angles (radians) and values.
    #[staticmethod]
    #[pyo3(signature = (theta_i, phi_i, theta_v, phi_v, values, sigma = None, quantity = "brdf", name = "arrays"))]
    #[allow(clippy::too_many_arguments)]
    fn from_arrays(
        theta_i: PyReadonlyArray1<'_, f64>,
        phi_i: PyReadonlyArray1<'_, f64>,
        theta_v: PyReadonlyArray1<'_, f64>,
        phi_v: PyReadonlyArray1<'_, f64>,
        values: PyReadonlyArray1<'_, f64>,
        sigma: Option<PyReadonlyArray1<'_, f64>>,
        quantity: &str,
        name: &str,
    ) -> PyResult<Self> {
        let angles = lab_angles(
            &vec1(&theta_i)?,
            &vec1(&phi_i)?,
            &vec1(&theta_v)?,
            &vec1(&phi_v)?,
        )?;
        let quantity: Quantity = parse("quantity", quantity)?;
        let sigma = sigma.map(|s| vec1(&s)).transpose()?;
        let values = vec1(&values)?;
        let set = MeasurementSet::new(name, angles, quantity)
            .and_then(|s| s.with_channel("value", values, sigma))
            .map_err(value_error)?;
        Self::pick(set, Some("value"))
    }

    /// From a long-format CSV file (`laminar fit --measurements`).
    #[staticmethod]
    #[pyo3(signature = (path, channel = None, angles = "rad", quantity = "brdf"))]
    fn from_csv(
        path: PathBuf,
        channel: Option<&str>,
        angles: &str,
        quantity: &str,
    ) -> PyResult<Self> {
        let unit: AngleUnit = parse("angles", angles)?;
        let quantity: Quantity = parse("quantity", quantity)?;
        Self::pick(
            read_csv(&path, unit, quantity).map_err(read_error)?,
            channel,
        )
    }

    /// From a CUReT directory: `sample`'s BRDF of `channel` (avg, r, g, b).
    #[staticmethod]
    #[pyo3(signature = (dir, sample, channel = "avg"))]
    fn from_curet(dir: PathBuf, sample: u32, channel: &str) -> PyResult<Self> {
        let channel = Channel::ALL
            .into_iter()
            .find(|c| c.name() == channel)
            .ok_or_else(|| {
                PyValueError::new_err(format!("channel: `{channel}` is not avg, r, g or b"))
            })?;
        let samples = CuretDir::open(&dir)
            .and_then(|d| d.samples(&[PathBuf::from(channel.file_name())], Some(&[sample])))
            .map_err(read_error)?;
        let found = samples.into_iter().next().ok_or_else(|| {
            PyValueError::new_err(format!("sample: {} has no sample {sample}", dir.display()))
        })?;
        Self::pick(found.set, None)
    }

    /// From a MERL `.binary` file, sampled at the geometries of the CSV file
    /// `sample_at` (columns theta_i,phi_i,theta_v,phi_v in `angles` units).
    #[staticmethod]
    #[pyo3(signature = (path, sample_at, channel = None, angles = "rad"))]
    fn from_merl(
        path: PathBuf,
        sample_at: PathBuf,
        channel: Option<&str>,
        angles: &str,
    ) -> PyResult<Self> {
        let unit: AngleUnit = parse("angles", angles)?;
        let geometry = read_geometry(&sample_at, unit).map_err(read_error)?;
        let data = merl::read_merl(&path).map_err(read_error)?;
        let (set, _) = merl::sample(&path, &data, &geometry).map_err(read_error)?;
        Self::pick(set, channel)
    }

    /// The set's channels.
    #[getter]
    fn channels(&self) -> Vec<String> {
        self.set
            .channel_names()
            .iter()
            .map(|c| c.to_string())
            .collect()
    }

    /// The channel fitted.
    #[getter]
    fn channel(&self) -> String {
        self.channel.clone()
    }

    fn __len__(&self) -> usize {
        self.set.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "Measurements(name={:?}, measurements={}, channel={:?})",
            self.set.name(),
            self.set.len(),
            self.channel
        )
    }
}

/// The fitter of `fit` and `fit_batch`: each option handed to the
/// library's settings by name ([`Settings::set`]); a grid axis is its
/// text or a sequence of values.
fn fitter(
    grid: Option<HashMap<String, Bound<'_, PyAny>>>,
    threads: Option<usize>,
    refine: bool,
    uncertainty: &str,
    objective: &str,
    (resamples, seed, folds): (u64, u64, u64),
) -> PyResult<Fitter> {
    let mut s = Settings::default();
    s.set("folds", &folds.to_string()).map_err(value_error)?;
    s.set("objective", objective).map_err(value_error)?;
    s.set("uncertainty", uncertainty).map_err(value_error)?;
    s.set("resamples", &resamples.to_string())
        .map_err(value_error)?;
    s.set("seed", &seed.to_string()).map_err(value_error)?;
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

fn params_dict<'py>(py: Python<'py>, params: &ModelParams) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (p, value) in params.pairs() {
        d.set_item(p.name(), value)?;
    }
    Ok(d)
}

/// One fit: the refined estimate (the best grid point when not refined),
/// its errors and uncertainties, the best grid point, the Ragheb–Hancock
/// best of the same search (layered models), and the fitted model.
#[pyclass(module = "laminar", frozen)]
struct FitResult {
    fit: Fit,
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
    fn chi2w_dof(&self) -> Option<f64> {
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

/// Two float arrays.
type ArrayPair<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

/// A fitted model to predict with, from a fitted-model file (one fit,
/// picked by its label `sample/channel/model` as `laminar predict
/// --select` picks it) or from a [`FitResult`].
#[pyclass(module = "laminar", frozen)]
struct FittedModel {
    label: String,
    fitted: laminar_fit::FittedModel,
}

#[pymethods]
impl FittedModel {
    /// The fit labelled `select` in the fitted-model file `path` (the
    /// file's only fit when `select` is None).
    #[staticmethod]
    #[pyo3(signature = (path, select = None))]
    fn from_file(path: PathBuf, select: Option<&str>) -> PyResult<Self> {
        let file = fits::read_fits(&path).map_err(read_error)?;
        let chosen = file
            .select(select)
            .map_err(|e| PyValueError::new_err(format!("{}: {e}", path.display())))?;
        chosen.fitted.predict(&[]).map_err(|e| {
            PyValueError::new_err(format!("{}: fit {}: {e}", path.display(), chosen.label))
        })?;
        Ok(Self {
            label: chosen.label,
            fitted: chosen.fitted,
        })
    }

    /// `model` at `params` (a dict of the model's parameters: `slope`,
    /// `beta`, `n`, `a`; `sigma_a`, `sigma_s`; or `sigma`, `rho`) times
    /// `amplitude`: the prediction is `amplitude · ((1 − β) L^sf + β L^sb)`
    /// (eq. 8's raw mix; a baseline's raw radiance), times `data_scale`
    /// in the input's units. A missing, extra or out-of-domain parameter
    /// raises ValueError naming it.
    #[staticmethod]
    #[pyo3(signature = (model, params, amplitude = 1.0, data_scale = 1.0))]
    fn from_params(
        model: &str,
        params: HashMap<String, f64>,
        amplitude: f64,
        data_scale: f64,
    ) -> PyResult<Self> {
        let kind: Model = parse("model", model)?;
        let values =
            ModelParams::from_values(kind, |p| params.get(p.name()).copied().unwrap_or(f64::NAN));
        let names: Vec<&str> = kind.params().iter().map(|p| p.name()).collect();
        if let Some(missing) = names.iter().find(|n| !params.contains_key(**n)) {
            return Err(PyValueError::new_err(format!(
                "params: `{missing}` is missing; {model} takes {}",
                names.join(", ")
            )));
        }
        if let Some(extra) = params.keys().find(|k| !names.contains(&k.as_str())) {
            return Err(PyValueError::new_err(format!(
                "params: `{extra}` is not a parameter of {model} ({})",
                names.join(", ")
            )));
        }
        if !(amplitude >= 0.0
            && amplitude.is_finite()
            && data_scale > 0.0
            && data_scale.is_finite())
        {
            return Err(PyValueError::new_err(format!(
                "amplitude {amplitude} must be finite and ≥ 0, data_scale {data_scale} finite and > 0"
            )));
        }
        let fitted = laminar_fit::FittedModel::with_amplitude(kind, values, amplitude, data_scale);
        fitted.predict(&[]).map_err(value_error)?;
        Ok(Self {
            label: format!("{model}({})", values.text()),
            fitted,
        })
    }

    /// The fitted model of a fit (the refined one when refined).
    #[staticmethod]
    fn from_fit(fit: &FitResult) -> Self {
        Self {
            label: fits::FitEntry::new(&fit.fit).label(),
            fitted: fit.fit.estimate().fitted,
        }
    }

    /// `sample/channel/model`.
    #[getter]
    fn label(&self) -> &str {
        &self.label
    }

    /// The model's name.
    #[getter]
    fn model(&self) -> &'static str {
        self.fitted.model.name()
    }

    /// The max the fit's data were divided by: the prediction times it is
    /// in the input's units.
    #[getter]
    fn data_scale(&self) -> f64 {
        self.fitted.data_scale
    }

    /// The prediction in the input's units, `f · cos θi` (the fitted
    /// radiance: `P · data_scale`), at paper-frame angles (radians; arrays
    /// of one length). Not finite or out of range raises ValueError naming
    /// the element.
    fn radiance<'py>(
        &self,
        py: Python<'py>,
        theta_i: PyReadonlyArray1<'py, f64>,
        theta_s: PyReadonlyArray1<'py, f64>,
        phi_s: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (ti, ts, ps) = (vec1(&theta_i)?, vec1(&theta_s)?, vec1(&phi_s)?);
        if ti.len() != ts.len() || ti.len() != ps.len() {
            return Err(PyValueError::new_err(format!(
                "theta_i, theta_s and phi_s have {}, {} and {} elements; they must have one length",
                ti.len(),
                ts.len(),
                ps.len()
            )));
        }
        let mut angles = reserve::<Angles>(ti.len(), "angles")?;
        for k in 0..ti.len() {
            angles.push(
                Angles::new(ti[k], ts[k], ps[k])
                    .map_err(|e| PyValueError::new_err(format!("element {k}: {e}")))?,
            );
        }
        let fitted = self.fitted;
        let out = py.detach(|| fitted.predict_radiance(&angles));
        Ok(out.map_err(value_error)?.into_pyarray(py))
    }

    /// The directional albedo ρ(θv) = ∫ f cos θi dωi at each view angle
    /// (radians), in the input's units, and each value's quadrature error
    /// (docs/conventions.md §12): two arrays. `tolerance`: the relative
    /// agreement of two successive quadrature rules, from 1e-12 up to (not
    /// including) 1.
    #[pyo3(signature = (theta_v, tolerance = 1e-6))]
    fn albedo<'py>(
        &self,
        py: Python<'py>,
        theta_v: PyReadonlyArray1<'py, f64>,
        tolerance: f64,
    ) -> PyResult<ArrayPair<'py>> {
        let thetas = vec1(&theta_v)?;
        let tolerance = laminar_fit::albedo::Tolerance::new(tolerance).map_err(value_error)?;
        let fitted = self.fitted;
        let table = py
            .detach(|| laminar_fit::albedo::albedo_table(&fitted, &thetas, tolerance))
            .map_err(value_error)?;
        let albedo: Vec<f64> = table.iter().map(|a| a.albedo).collect();
        let error: Vec<f64> = table.iter().map(|a| a.error).collect();
        Ok((albedo.into_pyarray(py), error.into_pyarray(py)))
    }

    fn __repr__(&self) -> String {
        format!(
            "FittedModel(label={:?}, model={:?}, params={})",
            self.label,
            self.fitted.model.name(),
            self.fitted.params.text()
        )
    }
}

/// A sphere of the fitted models (one per channel: one for grey, three
/// for RGB) under a directional light and a constant environment, as
/// `laminar render` draws it (docs/conventions.md §12): the linear radiance
/// (size × size × channels, 0 off the sphere) and the 8-bit sRGB image
/// (size × size × 3).
#[pyfunction]
#[pyo3(signature = (models, size = 256, light_polar = None, light_azimuth = None, environment = None))]
fn render<'py>(
    py: Python<'py>,
    models: Vec<PyRef<'py, FittedModel>>,
    size: usize,
    light_polar: Option<f64>,
    light_azimuth: Option<f64>,
    environment: Option<f64>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    use laminar_fit::preview::{render as draw, Stage};
    if !(models.len() == 1 || models.len() == 3) {
        return Err(PyValueError::new_err(format!(
            "render takes one or three models (got {})",
            models.len()
        )));
    }
    let scene = Stage::new(size, light_polar, light_azimuth, environment).map_err(value_error)?;
    let fitted: Vec<laminar_fit::FittedModel> = models.iter().map(|m| m.fitted).collect();
    let image = py.detach(|| draw(&fitted, &scene)).map_err(value_error)?;
    let srgb = image.to_srgb8();
    let channels = image.channels;
    let radiance = image
        .radiance
        .into_pyarray(py)
        .reshape([size, size, channels])?;
    let srgb = srgb.into_pyarray(py).reshape([size, size, 3])?;
    Ok((radiance.into_any(), srgb.into_any()))
}

/// Fits `model` to `measurements` by the exhaustive grid search, then
/// refines it and measures the uncertainty of its parameters.
#[pyfunction]
#[pyo3(signature = (measurements, model = "exp", grid = None, refine = true, uncertainty = "both", threads = None, objective = "free", resamples = 200, seed = 0))]
#[allow(clippy::too_many_arguments)]
fn fit(
    py: Python<'_>,
    measurements: &Measurements,
    model: &str,
    grid: Option<HashMap<String, Bound<'_, PyAny>>>,
    refine: bool,
    uncertainty: &str,
    threads: Option<usize>,
    objective: &str,
    resamples: u64,
    seed: u64,
) -> PyResult<FitResult> {
    let model: Model = parse("model", model)?;
    let fitter = fitter(
        grid,
        threads,
        refine,
        uncertainty,
        objective,
        (resamples, seed, 0),
    )?;
    let scene = measurements.scene()?;
    let fit = py.detach(|| fitter.fit(&scene, model));
    Ok(FitResult { fit })
}

/// Fits each of ``models`` (an iterable of names; default: every model of
/// ``MODELS``) to a ``Measurements`` and compares them, as ``laminar fit``
/// does with several models: a list of ``FitResult`` in the order of
/// ``models``, each with its ``rank`` (``{"rank", "delta", "weight"}``: 1
/// for the lowest AICc, ΔAICc, the Akaike weight), ``information`` (AIC,
/// AICc, BIC), ``cross_validation`` (``folds``-fold, the folds dealt by
/// ``seed``; ``folds=0`` for none), ``adequacy`` and ``graphics``. The
/// other arguments are ``fit``'s. Ranks need the free objective and
/// ``refine``.
#[pyfunction]
#[pyo3(signature = (measurements, models = None, grid = None, refine = true, uncertainty = "both", threads = None, objective = "free", resamples = 200, seed = 0, folds = 5))]
#[allow(clippy::too_many_arguments)]
fn compare(
    py: Python<'_>,
    measurements: &Measurements,
    models: Option<Bound<'_, PyAny>>,
    grid: Option<HashMap<String, Bound<'_, PyAny>>>,
    refine: bool,
    uncertainty: &str,
    threads: Option<usize>,
    objective: &str,
    resamples: u64,
    seed: u64,
    folds: u64,
) -> PyResult<Vec<FitResult>> {
    let models: Vec<Model> = match models {
        Some(names) if !names.is_instance_of::<pyo3::types::PyString>() => names
            .try_iter()
            .map_err(|_| PyTypeError::new_err("models: give an iterable of model names"))?
            .map(|m| {
                let name: String = m?
                    .extract()
                    .map_err(|_| PyTypeError::new_err("models: give model names (strings)"))?;
                parse("models", &name)
            })
            .collect::<PyResult<_>>()?,
        Some(_) => {
            return Err(PyTypeError::new_err(
                "models: give a list of model names, not one string",
            ))
        }
        None => Model::ALL.to_vec(),
    };
    let fitter = fitter(
        grid,
        threads,
        refine,
        uncertainty,
        objective,
        (resamples, seed, folds),
    )?;
    let scene = measurements.scene()?;
    let fits = py
        .detach(|| fitter.fit_all(std::slice::from_ref(&scene), &models, |_, _| None))
        .map_err(value_error)?;
    Ok(fits.into_iter().map(|fit| FitResult { fit }).collect())
}

/// The batch fields of the layered models (every layered model has the
/// same, [`BatchRow`]): `fit_batch`'s columns.
fn batch_row() -> BatchRow {
    BatchRow::new(&[Model::Exp])
}

/// Fits `model` (a layered model) to every row of `values` (N × K) on one
/// geometry (`geometry`: K × 4 lab-frame angles theta_i, phi_i, theta_v,
/// phi_v in radians), by the shared-geometry batch search, 256 rows at a time.
#[pyfunction]
#[pyo3(signature = (geometry, values, model = "exp", grid = None, threads = None, quantity = "brdf", refine = true, uncertainty = "both", objective = "free"))]
#[allow(clippy::too_many_arguments)]
fn fit_batch<'py>(
    py: Python<'py>,
    geometry: PyReadonlyArray2<'py, f64>,
    values: PyReadonlyArray2<'py, f64>,
    model: &str,
    grid: Option<HashMap<String, Bound<'py, PyAny>>>,
    threads: Option<usize>,
    quantity: &str,
    refine: bool,
    uncertainty: &str,
    objective: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let model: Model = parse("model", model)?;
    if model.correlation().is_none() {
        return Err(PyValueError::new_err(format!(
            "model: fit_batch fits the layered models (exp, gauss, rh-exp, rh-gauss), not {model}"
        )));
    }
    let quantity: Quantity = parse("quantity", quantity)?;
    let fitter = fitter(
        grid,
        threads,
        refine,
        uncertainty,
        objective,
        (laminar_fit::analysis::DEFAULT_RESAMPLES as u64, 0, 0),
    )?;
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
    let row = batch_row();
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

/// The paper-frame angles `(theta_i, theta_s, phi_s)` of lab-frame ones
/// (docs/conventions.md §1).
#[pyfunction]
fn paper_angles(theta_i: f64, phi_i: f64, theta_v: f64, phi_v: f64) -> PyResult<(f64, f64, f64)> {
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

/// The native module.
#[pymodule]
fn _laminar(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(evaluate, m)?)?;
    m.add_function(wrap_pyfunction!(fit, m)?)?;
    m.add_function(wrap_pyfunction!(fit_batch, m)?)?;
    m.add_function(wrap_pyfunction!(compare, m)?)?;
    m.add_function(wrap_pyfunction!(paper_angles, m)?)?;
    m.add_class::<Measurements>()?;
    m.add_class::<FitResult>()?;
    m.add_class::<FittedModel>()?;
    m.add_function(wrap_pyfunction!(render, m)?)?;
    let row = batch_row();
    m.add("BATCH_COLUMNS", row.names())?;
    let kinds: Vec<(String, &str)> = row
        .names()
        .into_iter()
        .zip(row.kinds().into_iter().map(|k| k.dtype()))
        .collect();
    m.add("BATCH_DTYPES", kinds)?;
    let flags = PyDict::new(m.py());
    for edge in Edge::ALL {
        flags.set_item(edge.to_string(), edge.bit())?;
    }
    m.add("FLAG_BITS", flags)?;
    // The model descriptor (laminar_fit::Model): every list a Python user
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
