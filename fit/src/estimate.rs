//! A fitted model with its error measures on the scene it was fitted to:
//! what each stage of a fit hands on (the search's best, the refined
//! estimate).

use crate::error::ModelError;
use crate::fitted::{FittedModel, ModelParams};
use crate::graphics_metrics::GraphicsMetrics;
use crate::model::Model;
use crate::scene::Scene;
use laminar_brdf_core::{chi_square_per_dof, rms_error, ChiSquare};

/// A fitted model with its error measures on the scene it was fitted to
/// (computed in f64 from [`FittedModel::predict`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Estimate {
    /// The fitted model, portable.
    pub fitted: FittedModel,
    /// `Δ_RMS = 100·sqrt(Σ(D−P)²)/K` (eq. 15).
    pub rms: f64,
    /// `χ²/ν` (eq. 16), when there are degrees of freedom left.
    pub chi2: Option<ChiSquare<f64>>,
    /// The graphics literature's measures ([`crate::graphics_metrics`]).
    pub graphics: Option<GraphicsMetrics>,
}

impl Estimate {
    /// Normalises `model` at `params` on `scene` and measures its error there.
    ///
    /// # Errors
    /// [`ModelError`] when the parameters are outside their domain or not the model's.
    pub fn new(scene: &Scene, model: Model, params: ModelParams) -> Result<Self, ModelError> {
        let fitted = FittedModel::normalised_on(model, params, &scene.angles, scene.data_scale)?;
        let prediction = fitted.predict(&scene.angles)?;
        Ok(Self {
            fitted,
            rms: rms_error(&scene.data, &prediction).unwrap_or(f64::NAN),
            chi2: chi_square_per_dof(&scene.data, &prediction, model.parameter_count()).ok(),
            graphics: GraphicsMetrics::new(&scene.data, &prediction, scene.data_scale),
        })
    }

    /// The error measures of `fitted` on `scene`, `p` fitted parameters
    /// counted in χ²/ν.
    ///
    /// # Errors
    /// [`ModelError`] when the parameters are outside their domain or not the model's.
    pub fn of_fitted(scene: &Scene, fitted: FittedModel, p: usize) -> Result<Self, ModelError> {
        let prediction = fitted.predict(&scene.angles)?;
        Ok(Self::of_prediction(scene, fitted, &prediction, p))
    }

    /// [`Estimate::of_fitted`] from the model's raw terms at the scene's
    /// measurements (`[S, U]` of a layered model, `[L, 0]` of a baseline),
    /// as a fit already has them.
    ///
    /// # Errors
    /// [`ModelError`] when a prediction is not finite.
    pub(crate) fn of_raw(
        scene: &Scene,
        fitted: FittedModel,
        raw: &[[f64; 2]],
        p: usize,
    ) -> Result<Self, ModelError> {
        let prediction = fitted.predict_raw(raw)?;
        Ok(Self::of_prediction(scene, fitted, &prediction, p))
    }

    fn of_prediction(scene: &Scene, fitted: FittedModel, prediction: &[f64], p: usize) -> Self {
        Self {
            fitted,
            rms: rms_error(&scene.data, prediction).unwrap_or(f64::NAN),
            chi2: chi_square_per_dof(&scene.data, prediction, p).ok(),
            graphics: GraphicsMetrics::new(&scene.data, prediction, scene.data_scale),
        }
    }

    /// The parameters.
    pub fn params(&self) -> &ModelParams {
        &self.fitted.params
    }

    /// `name=value` pairs joined by `;` (the `params` column).
    pub fn params_text(&self) -> String {
        self.fitted.params.text()
    }

    /// The value of a named parameter.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.fitted.params.get(name)
    }
}
