//! `Measurements`: a measurement set and the channel of it to fit, from
//! arrays, CSV, CUReT or MERL.

use crate::convert::{lab_angles, parse, read_error, real_vec, value_error};
use laminar_brdf_fit::{MeasurementSet, Quantity, Scene};
use laminar_brdf_io::curet::{Channel, CuretDir};
use laminar_brdf_io::{merl, read_csv, read_geometry, AngleUnit};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::path::{Path, PathBuf};

/// A measurement set and the channel of it to fit.
#[pyclass(module = "laminar_brdf", frozen)]
pub(crate) struct Measurements {
    pub(crate) set: MeasurementSet,
    pub(crate) channel: String,
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

    /// The set `reader` reads from `path`, one of its channels picked.
    fn read(
        reader: fn(&Path) -> Result<MeasurementSet, laminar_brdf_io::ReadError>,
        path: &Path,
        channel: Option<&str>,
    ) -> PyResult<Self> {
        Self::pick(reader(path).map_err(read_error)?, channel)
    }

    pub(crate) fn scene(&self) -> PyResult<Scene> {
        self.set.scene(&self.channel).map_err(value_error)
    }
}

#[pymethods]
impl Measurements {
    /// From arrays of lab-frame angles (radians) and values.
    #[staticmethod]
    #[pyo3(signature = (theta_i, phi_i, theta_v, phi_v, values, sigma = None, quantity = "brdf", name = "arrays"))]
    #[allow(clippy::too_many_arguments)]
    fn from_arrays(
        theta_i: &Bound<'_, PyAny>,
        phi_i: &Bound<'_, PyAny>,
        theta_v: &Bound<'_, PyAny>,
        phi_v: &Bound<'_, PyAny>,
        values: &Bound<'_, PyAny>,
        sigma: Option<&Bound<'_, PyAny>>,
        quantity: &str,
        name: &str,
    ) -> PyResult<Self> {
        let angles = lab_angles(
            &real_vec("theta_i", theta_i)?,
            &real_vec("phi_i", phi_i)?,
            &real_vec("theta_v", theta_v)?,
            &real_vec("phi_v", phi_v)?,
        )?;
        let quantity: Quantity = parse("quantity", quantity)?;
        let sigma = sigma
            .filter(|s| !s.is_none())
            .map(|s| real_vec("sigma", s))
            .transpose()?;
        let values = real_vec("values", values)?;
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

    /// From an ASTM E1392 file (the Cornell gonioreflectometer's `.astm`):
    /// each column after the geometry a channel (`550nm`, or `r`, `g`, `b`).
    #[staticmethod]
    #[pyo3(signature = (path, channel = None))]
    fn from_astm(path: PathBuf, channel: Option<&str>) -> PyResult<Self> {
        Self::read(laminar_brdf_io::astm::read_astm, &path, channel)
    }

    /// From NIST's Mueller-matrix BRDF CSV (Germer 2017): each wavelength a
    /// channel (`532nm`).
    #[staticmethod]
    #[pyo3(signature = (path, channel = None))]
    fn from_nist(path: PathBuf, channel: Option<&str>) -> PyResult<Self> {
        Self::read(laminar_brdf_io::nist::read_nist, &path, channel)
    }

    /// From an RGL-EPFL isotropic RGB `.bsdf` file: channels `r`, `g`, `b`.
    #[staticmethod]
    #[pyo3(signature = (path, channel = None))]
    fn from_rgl(path: PathBuf, channel: Option<&str>) -> PyResult<Self> {
        Self::read(laminar_brdf_io::rgl::read_rgl, &path, channel)
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

    /// The same measurements with the specular test's tolerance set to
    /// `tolerance` radians (``laminar --specular-tolerance``; default
    /// 1e-4, the exact mirror only): a measurement within it of the
    /// mirror configuration on every angle is left out of the fit
    /// (docs/conventions.md §4b, near-mirror values).
    fn with_specular_tolerance(&self, tolerance: f64) -> PyResult<Self> {
        let set = (self.set.clone())
            .with_specular_tolerance(tolerance)
            .map_err(value_error)?;
        Ok(Self {
            set,
            channel: self.channel.clone(),
        })
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
