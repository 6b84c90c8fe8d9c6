//! A baseline's geometry at a scene's measurements, built once and
//! evaluated at any parameters (docs/conventions.md §7). This is the one
//! place the fitting library turns a [`Baseline`] into its
//! [`BaselineModel`] for evaluation: the paper's grid search, the free
//! objective's columns and a fitted model's prediction all call
//! [`BaselineGeometry::radiance`].

use laminar_brdf_core::baselines::{Baseline, BaselineModel, WithBaseline};
use laminar_brdf_core::{Angles, InputError};
use std::fmt::Debug;

/// Evaluation of one baseline's per-measurement terms (object-safe, so a
/// [`BaselineGeometry`] holds any baseline).
trait Evaluate: Debug + Send + Sync {
    /// The raw radiance at each measurement at `params`.
    fn radiance(&self, params: [f64; 2]) -> Result<Vec<f64>, InputError>;
    /// Number of measurements.
    fn len(&self) -> usize;
    /// A boxed copy.
    fn boxed(&self) -> Box<dyn Evaluate>;
}

/// The terms of baseline `B` at each measurement.
struct Measured<B: BaselineModel>(Vec<B::Geometry<f64>>);

impl<B: BaselineModel> Debug for Measured<B> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("Measured").field(&self.0).finish()
    }
}

impl<B: BaselineModel> Evaluate for Measured<B> {
    fn radiance(&self, params: [f64; 2]) -> Result<Vec<f64>, InputError> {
        let k = B::coefficients::<f64>(params)?;
        Ok(self.0.iter().map(|g| B::radiance(g, &k)).collect())
    }

    fn len(&self) -> usize {
        self.0.len()
    }

    fn boxed(&self) -> Box<dyn Evaluate> {
        Box::new(Measured::<B>(self.0.clone()))
    }
}

/// A baseline's terms at a scene's measurements.
#[derive(Debug)]
pub struct BaselineGeometry {
    baseline: Baseline,
    terms: Box<dyn Evaluate>,
}

impl Clone for BaselineGeometry {
    fn clone(&self) -> Self {
        Self {
            baseline: self.baseline,
            terms: self.terms.boxed(),
        }
    }
}

impl BaselineGeometry {
    /// The terms of `baseline` at `angles`.
    pub fn new(baseline: Baseline, angles: &[Angles]) -> Self {
        struct Build<'a>(&'a [Angles]);
        impl WithBaseline for Build<'_> {
            type Output = Box<dyn Evaluate>;
            fn run<B: BaselineModel>(self) -> Box<dyn Evaluate> {
                let terms = self.0.iter().map(|a| B::geometry(|_| *a)).collect();
                Box::new(Measured::<B>(terms))
            }
        }
        Self {
            baseline,
            terms: baseline.with(Build(angles)),
        }
    }

    /// The baseline.
    pub fn baseline(&self) -> Baseline {
        self.baseline
    }

    /// The raw (un-normalised) radiance at each measurement at `params`
    /// ([`Baseline::params`]' order).
    ///
    /// # Errors
    /// [`InputError::OutOfRange`] naming a parameter outside its domain.
    pub fn radiance(&self, params: [f64; 2]) -> Result<Vec<f64>, InputError> {
        self.terms.radiance(params)
    }

    /// Number of measurements.
    pub fn len(&self) -> usize {
        self.terms.len()
    }
}
