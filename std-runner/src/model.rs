//! The models the runner fits and their f64 predictions (conventions §4, §7).

use crate::scene::Scene;
use laminar_core::baselines::jensen::{jensen_radiance, JensenCoefficients, JensenGeometry};
use laminar_core::baselines::oren_nayar::{
    oren_nayar_radiance, OrenNayarCoefficients, OrenNayarGeometry,
};
use laminar_core::measures::normalised_prediction;
use laminar_core::{components, normalise_by_max, Correlation, Geometry, Normalisation, Params};
use std::fmt;
use std::str::FromStr;

/// A model that `laminar fit` can fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Model {
    /// Absorptive, Exponential correlation (eq. 13).
    Exp,
    /// Absorptive, Gaussian correlation (eq. 12).
    Gauss,
    /// Ragheb–Hancock, Exponential (a = 0).
    RhExp,
    /// Ragheb–Hancock, Gaussian (a = 0).
    RhGauss,
    /// Jensen et al. 2001 (conventions §7).
    Jensen,
    /// Full Oren–Nayar (conventions §7).
    OrenNayar,
}

impl Model {
    /// Every model, in output order.
    pub const ALL: [Model; 6] = [
        Model::Exp,
        Model::Gauss,
        Model::RhExp,
        Model::RhGauss,
        Model::Jensen,
        Model::OrenNayar,
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Exp => "exp",
            Self::Gauss => "gauss",
            Self::RhExp => "rh-exp",
            Self::RhGauss => "rh-gauss",
            Self::Jensen => "jensen",
            Self::OrenNayar => "oren-nayar",
        }
    }

    /// The correlation function of the layered models.
    pub fn correlation(self) -> Option<Correlation> {
        match self {
            Self::Exp | Self::RhExp => Some(Correlation::Exponential),
            Self::Gauss | Self::RhGauss => Some(Correlation::Gaussian),
            _ => None,
        }
    }

    /// True for the Ragheb–Hancock variants (a fixed at 0).
    pub fn is_ragheb_hancock(self) -> bool {
        matches!(self, Self::RhExp | Self::RhGauss)
    }

    /// Number of fitted parameters p, for χ²/ν (conventions §5).
    pub fn parameter_count(self) -> usize {
        match self {
            Self::Exp | Self::Gauss => 4,
            Self::RhExp | Self::RhGauss => 3,
            Self::Jensen | Self::OrenNayar => 2,
        }
    }
}

impl fmt::Display for Model {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Model {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| format!("unknown model `{s}` (expected one of exp, gauss, rh-exp, rh-gauss, jensen, oren-nayar)"))
    }
}

/// Paper-normalised f64 prediction of the layered model at `p` (conventions §4).
pub fn predict_layered(scene: &Scene, corr: Correlation, p: &Params) -> Vec<f64> {
    let (mut surface, mut subsurface): (Vec<f64>, Vec<f64>) = scene
        .angles
        .iter()
        .map(|a| {
            let c = components(&Geometry::<f64>::splat(a), corr, p);
            (c.surface, c.subsurface)
        })
        .unzip();
    let mut out = vec![0.0; scene.len()];
    normalised_prediction(
        Normalisation::Paper,
        p.beta(),
        &mut surface,
        &mut subsurface,
        &scene.data,
        &mut out,
    )
    .expect("equal lengths by construction");
    out
}

/// Max-normalised f64 Jensen prediction (conventions §7) on precomputed geometry.
pub fn predict_jensen(geometry: &[JensenGeometry<f64>], k: &JensenCoefficients<f64>) -> Vec<f64> {
    let mut v: Vec<f64> = geometry.iter().map(|g| jensen_radiance(g, k)).collect();
    normalise_by_max(&mut v);
    v
}

/// Max-normalised f64 Oren–Nayar prediction (conventions §7) on precomputed geometry.
pub fn predict_oren_nayar(
    geometry: &[OrenNayarGeometry<f64>],
    k: &OrenNayarCoefficients<f64>,
) -> Vec<f64> {
    let mut v: Vec<f64> = geometry.iter().map(|g| oren_nayar_radiance(g, k)).collect();
    normalise_by_max(&mut v);
    v
}
