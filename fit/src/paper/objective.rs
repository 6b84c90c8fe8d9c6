//! The paper objective after its grid search (docs/conventions.md §11):
//! the sum of squared residuals of the max-normalised prediction as a
//! function of a model's continuous parameters, which the refinement
//! ([`super::refine`]) minimises and the intervals ([`super::intervals`])
//! profile.

use crate::error::ModelError;
use crate::fitted::{FittedModel, Geometries, ModelParams};
use crate::model::{attainable_domain, Model, Param};
use crate::scene::Scene;

/// The objective of one (scene, model): the sum of squared residuals
/// `Σ (D − P)²` (eq. 15 before the root) as a function of the model's free
/// parameters, in f64, with the geometry built once.
#[derive(Debug, Clone)]
pub struct SumOfSquares<'a> {
    scene: &'a Scene,
    model: Model,
    geometries: Geometries,
    names: &'static [Param],
    bounds: Vec<(f64, f64)>,
}

impl<'a> SumOfSquares<'a> {
    /// The objective of `model` on `scene`. Its free parameters are the
    /// model's parameters in output order, without a of the Ragheb–Hancock
    /// variants (fixed at 0).
    pub fn new(scene: &'a Scene, model: Model) -> Self {
        let names = model.free_params();
        let bounds = names.iter().map(|&p| attainable_domain(p)).collect();
        Self {
            scene,
            model,
            geometries: Geometries::new(model, &scene.angles),
            names,
            bounds,
        }
    }

    /// The free parameters.
    pub fn names(&self) -> &'static [Param] {
        self.names
    }

    /// The closed domain `[lo, hi]` of each free parameter.
    pub fn bounds(&self) -> &[(f64, f64)] {
        &self.bounds
    }

    /// `x` moved onto the domain, coordinate by coordinate.
    pub fn project(&self, x: &[f64]) -> Vec<f64> {
        x.iter()
            .zip(&self.bounds)
            .map(|(&v, &(lo, hi))| v.clamp(lo, hi))
            .collect()
    }

    /// The model's parameters at free values `x` (taken as they are).
    pub fn params(&self, x: &[f64]) -> ModelParams {
        ModelParams::from_values(self.model, |name| {
            self.names
                .iter()
                .position(|&n| n == name)
                .map_or(0.0, |i| x[i])
        })
    }

    /// The free values of `params`, in [`SumOfSquares::names`] order.
    pub fn values(&self, params: &ModelParams) -> Vec<f64> {
        self.names
            .iter()
            .map(|&n| params.value(n).unwrap_or(f64::NAN))
            .collect()
    }

    /// The normalised prediction `P` at every measurement at free values
    /// `x` (inside the domain).
    ///
    /// # Errors
    /// [`ModelError`] for values outside the domain.
    pub fn prediction(&self, x: &[f64]) -> Result<Vec<f64>, ModelError> {
        let params = self.params(x);
        let raw = self.geometries.raw(self.model, &params)?;
        FittedModel::from_raw(self.model, params, &raw, self.scene.data_scale).predict_raw(&raw)
    }

    /// `Σ (D − P)²` at `x` projected onto the domain (+∞ if the model
    /// cannot be evaluated there).
    pub fn sse(&self, x: &[f64]) -> f64 {
        match self.prediction(&self.project(x)) {
            Ok(p) => self
                .scene
                .data
                .iter()
                .zip(&p)
                .map(|(d, p)| (d - p) * (d - p))
                .sum(),
            Err(_) => f64::INFINITY,
        }
    }
}
