//! The models laminar fits (docs/conventions.md §3, §7).

use crate::error::ModelError;
use laminar_core::radiance::{INDEX_MAX, SLOPE_MAX, SLOPE_MIN};
use laminar_core::Correlation;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::f64::consts::FRAC_PI_2;
use std::fmt;
use std::str::FromStr;

/// A model that laminar can fit.
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
    /// Jensen et al. 2001 (docs/conventions.md §7).
    Jensen,
    /// Full Oren–Nayar (docs/conventions.md §7).
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

    /// The name used in every interface (`exp`, `rh-gauss`, …).
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

    /// The correlation function of the layered models (`None` for the baselines).
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

    /// The Ragheb–Hancock variant of an absorptive model (its a = 0 slice).
    pub fn ragheb_hancock(self) -> Option<Model> {
        match self {
            Self::Exp => Some(Self::RhExp),
            Self::Gauss => Some(Self::RhGauss),
            _ => None,
        }
    }

    /// Number of fitted parameters p, for χ²/ν (docs/conventions.md §5).
    pub fn parameter_count(self) -> usize {
        match self {
            Self::Exp | Self::Gauss => 4,
            Self::RhExp | Self::RhGauss => 3,
            Self::Jensen | Self::OrenNayar => 2,
        }
    }

    /// The closed ends of parameter `name`'s domain (the checks of
    /// `laminar-core`); an open end is NaN (Jensen's σa, σs′ > 0).
    pub fn domain(self, name: &str) -> (f64, f64) {
        match (self, name) {
            (_, "slope") => (SLOPE_MIN, SLOPE_MAX),
            (_, "beta" | "a" | "rho") => (0.0, 1.0),
            (_, "n") => (1.0, INDEX_MAX),
            (Self::OrenNayar, "sigma") => (0.0, FRAC_PI_2),
            // Jensen's σa, σs′ ∈ (0, 100]: only the upper end is attainable.
            _ => (f64::NAN, 100.0),
        }
    }

    /// [`Model::domain`] with an open lower end replaced by the smallest
    /// value a fit takes there (Jensen's σa, σs′ > 0: 10⁻⁹).
    pub fn attainable_domain(self, name: &str) -> (f64, f64) {
        let (lo, hi) = self.domain(name);
        (if lo.is_nan() { 1e-9 } else { lo }, hi)
    }

    /// True when `value` is a bound of parameter `name`'s domain.
    pub fn at_bound(self, name: &str, value: f64) -> bool {
        let (lo, hi) = self.domain(name);
        value == lo || value == hi
    }
}

impl fmt::Display for Model {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Model {
    type Err = ModelError;
    fn from_str(s: &str) -> Result<Self, ModelError> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| ModelError::UnknownModel(s.to_string()))
    }
}

impl Serialize for Model {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for Model {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        name.parse().map_err(serde::de::Error::custom)
    }
}
