//! `FittedModel` and `render`: a fitted model to predict and draw with.

use crate::convert::{parse, read_error, reserve, value_error, vec1};
use crate::fit_result::FitResult;
use laminar_brdf_core::Angles;
use laminar_brdf_fit::{Model, ModelParams, Param};
use laminar_brdf_io::fits;
use numpy::{IntoPyArray, PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::HashMap;
use std::path::PathBuf;

/// Two float arrays.
type ArrayPair<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

/// A fitted model to predict with, from a fitted-model file (one fit,
/// picked by its label `sample/channel/model` as `laminar predict
/// --select` picks it) or from a [`FitResult`].
#[pyclass(module = "laminar_brdf", frozen)]
pub(crate) struct FittedModel {
    pub(crate) label: String,
    pub(crate) fitted: laminar_brdf_fit::FittedModel,
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

    /// Each channel of the material labelled `select` (`sample/model`) in
    /// the fitted-model file `path` (``laminar fit-joint --fits``; the
    /// file's only material when `select` is None), in the order fitted:
    /// one fitted model per channel at the joint estimate, labelled
    /// `sample/channel/model`.
    #[staticmethod]
    #[pyo3(signature = (path, select = None))]
    fn from_material(path: PathBuf, select: Option<&str>) -> PyResult<Vec<Self>> {
        let file = fits::read_fits(&path).map_err(read_error)?;
        let material = file
            .select_material(select)
            .map_err(|e| PyValueError::new_err(format!("{}: {e}", path.display())))?;
        (material.channels.iter())
            .map(|channel| {
                let label = material.channel_label(channel);
                channel.fitted.predict(&[]).map_err(|e| {
                    PyValueError::new_err(format!("{}: fit {label}: {e}", path.display()))
                })?;
                Ok(Self {
                    label,
                    fitted: channel.fitted,
                })
            })
            .collect()
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
        let fitted =
            laminar_brdf_fit::FittedModel::with_amplitude(kind, values, amplitude, data_scale);
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

    /// A layered model in the form of eq. 8's raw mix, for renderers that
    /// evaluate it themselves (`laminar.mitsuba`'s native BSDF): a dict of
    /// `correlation` (`exp` or `gauss`), `slope`, `n`, `a`, `beta_eq8` (β′)
    /// and `scale`, with radiance in the input's units
    /// `scale · (β′ L^sb + (1 − β′) L^sf)` (eqs. 1–14). None for a baseline,
    /// or when both terms were zero at every fitted measurement.
    #[getter]
    fn eq8<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let f = &self.fitted;
        let (Some(correlation), Some(beta), Some(scale)) =
            (f.model.correlation(), f.beta_eq8, f.eq8_scale)
        else {
            return Ok(None);
        };
        let out = PyDict::new(py);
        out.set_item("correlation", correlation.name())?;
        for (p, v) in f.params.pairs() {
            if p != Param::Beta {
                out.set_item(p.name(), v)?;
            }
        }
        out.set_item("beta_eq8", beta)?;
        out.set_item("scale", scale * f.data_scale)?;
        Ok(Some(out))
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
        let tolerance = laminar_brdf_fit::albedo::Tolerance::new(tolerance).map_err(value_error)?;
        let fitted = self.fitted;
        let table = py
            .detach(|| laminar_brdf_fit::albedo::albedo_table(&fitted, &thetas, tolerance))
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
pub(crate) fn render<'py>(
    py: Python<'py>,
    models: Vec<PyRef<'py, FittedModel>>,
    size: usize,
    light_polar: Option<f64>,
    light_azimuth: Option<f64>,
    environment: Option<f64>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    use laminar_brdf_fit::preview::{render as draw, Stage};
    if !(models.len() == 1 || models.len() == 3) {
        return Err(PyValueError::new_err(format!(
            "render takes one or three models (got {})",
            models.len()
        )));
    }
    let scene = Stage::new(size, light_polar, light_azimuth, environment).map_err(value_error)?;
    let fitted: Vec<laminar_brdf_fit::FittedModel> = models.iter().map(|m| m.fitted).collect();
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
