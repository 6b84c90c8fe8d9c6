//! The models laminar fits (docs/conventions.md §3, §7): the one
//! descriptor every front end derives its lists from. Each [`Model`] names
//! itself, its correlation function, its parameters ([`Param`], from
//! `laminar-brdf-core`, with their domains) and which of them a fit estimates.
//! Command-line options and help, the Python and WebAssembly accepted
//! names, the C status codes and the TypeScript types are built from here.

use crate::error::ModelError;
use crate::grid::Axis;
pub use laminar_brdf_core::baselines::Baseline;
use laminar_brdf_core::Correlation;
pub use laminar_brdf_core::Param;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;
use std::str::FromStr;

/// A model that laminar can fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "typescript", derive(ts_rs::TS))]
// Serialised by [`Model::name`]; laminar-brdf-io's test `typescript` checks
// that these names are those.
#[cfg_attr(feature = "typescript", ts(rename_all = "kebab-case"))]
pub enum Model {
    /// Absorptive, Exponential correlation (eq. 13).
    Exp,
    /// Absorptive, Gaussian correlation (eq. 12).
    Gauss,
    /// Absorptive, Exponential, the lower boundary's σ′/T′ free beside σ/T
    /// (eqs. 3–4 and 13 as printed).
    Exp2,
    /// Absorptive, Gaussian, σ′/T′ free beside σ/T (eqs. 3–4 and 12).
    Gauss2,
    /// Ragheb–Hancock, Exponential (a = 0).
    RhExp,
    /// Ragheb–Hancock, Gaussian (a = 0).
    RhGauss,
    /// Jensen et al. 2001 (docs/conventions.md §7).
    Jensen,
    /// Full Oren–Nayar (docs/conventions.md §7).
    OrenNayar,
}

/// What kind of model a [`Model`] is ([`Model::family`]): every other
/// question about a model is answered from this, by exhaustive matches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    /// A model of eq. 8 (layers with a rough boundary).
    Layered {
        /// Its correlation function (eqs. 1–2, 12–13).
        correlation: Correlation,
        /// True when a is fitted (the absorptive model), false for the
        /// Ragheb–Hancock variant (a = 0).
        absorption: bool,
        /// True when the lower boundary's σ′/T′ is a parameter of its own
        /// (eqs. 3–4 as printed), false when it is σ/T (the paper's search).
        untied: bool,
    },
    /// A baseline (docs/conventions.md §7).
    Baseline(Baseline),
}

/// The layered models' parameters, in output order.
const LAYERED: &[Param] = &[Param::Slope, Param::Beta, Param::N, Param::A];
/// The untied models' parameters, in output order.
const UNTIED: &[Param] = &[
    Param::Slope,
    Param::SubSlope,
    Param::Beta,
    Param::N,
    Param::A,
];
/// The Ragheb–Hancock variants' fitted parameters (a fixed at 0).
const RAGHEB_HANCOCK: &[Param] = &[Param::Slope, Param::Beta, Param::N];

impl Model {
    /// Every model, in output order.
    pub const ALL: [Model; 8] = [
        Model::Exp,
        Model::Gauss,
        Model::Exp2,
        Model::Gauss2,
        Model::RhExp,
        Model::RhGauss,
        Model::Jensen,
        Model::OrenNayar,
    ];

    /// What kind of model this is.
    pub fn family(self) -> Family {
        let layered = |correlation, absorption, untied| Family::Layered {
            correlation,
            absorption,
            untied,
        };
        match self {
            Self::Exp => layered(Correlation::Exponential, true, false),
            Self::Gauss => layered(Correlation::Gaussian, true, false),
            Self::Exp2 => layered(Correlation::Exponential, true, true),
            Self::Gauss2 => layered(Correlation::Gaussian, true, true),
            Self::RhExp => layered(Correlation::Exponential, false, false),
            Self::RhGauss => layered(Correlation::Gaussian, false, false),
            Self::Jensen => Family::Baseline(Baseline::Jensen),
            Self::OrenNayar => Family::Baseline(Baseline::OrenNayar),
        }
    }

    /// The name used in every interface (`exp`, `rh-gauss`, …).
    pub fn name(self) -> &'static str {
        match self {
            Self::Exp => Correlation::Exponential.name(),
            Self::Gauss => Correlation::Gaussian.name(),
            Self::Exp2 => "exp2",
            Self::Gauss2 => "gauss2",
            Self::RhExp => "rh-exp",
            Self::RhGauss => "rh-gauss",
            Self::Jensen => "jensen",
            Self::OrenNayar => "oren-nayar",
        }
    }

    /// The correlation function of the layered models (`None` for the baselines).
    pub fn correlation(self) -> Option<Correlation> {
        match self.family() {
            Family::Layered { correlation, .. } => Some(correlation),
            Family::Baseline(_) => None,
        }
    }

    /// The baseline this model is (`None` for the layered models).
    pub fn baseline(self) -> Option<Baseline> {
        match self.family() {
            Family::Layered { .. } => None,
            Family::Baseline(b) => Some(b),
        }
    }

    /// True for the Ragheb–Hancock variants (a fixed at 0).
    pub fn is_ragheb_hancock(self) -> bool {
        matches!(
            self.family(),
            Family::Layered {
                absorption: false,
                ..
            }
        )
    }

    /// The Ragheb–Hancock variant of an absorptive model (its a = 0 slice).
    pub fn ragheb_hancock(self) -> Option<Model> {
        match self.family() {
            Family::Layered {
                correlation,
                absorption: true,
                untied: false,
            } => Self::ALL.into_iter().find(|m| {
                m.family()
                    == Family::Layered {
                        correlation,
                        absorption: false,
                        untied: false,
                    }
            }),
            Family::Layered { .. } | Family::Baseline(_) => None,
        }
    }

    /// True for the untied models (σ′/T′ a parameter of its own).
    pub fn is_untied(self) -> bool {
        matches!(self.family(), Family::Layered { untied: true, .. })
    }

    /// The untied model of a tied absorptive model (exp → exp2), `None`
    /// for the others.
    pub fn untied(self) -> Option<Model> {
        match self.family() {
            Family::Layered {
                correlation,
                absorption: true,
                untied: false,
            } => Self::ALL
                .into_iter()
                .find(|m| m.correlation() == Some(correlation) && m.is_untied()),
            Family::Layered { .. } | Family::Baseline(_) => None,
        }
    }

    /// The tied model of an untied one (exp2 → exp); every other model is
    /// its own.
    pub fn tied_model(self) -> Model {
        match self.correlation() {
            Some(corr) if self.is_untied() => Model::absorptive(corr),
            _ => self,
        }
    }

    /// The models of the paper's search (every model but the untied ones,
    /// whose σ′/T′ that search ties to σ/T), in output order.
    pub fn tied() -> impl Iterator<Item = Model> {
        Self::ALL.into_iter().filter(|m| !m.is_untied())
    }

    /// True for the models of eq. 8 (exp, gauss and their Ragheb–Hancock variants).
    pub fn is_layered(self) -> bool {
        self.correlation().is_some()
    }

    /// The layered models ([`Model::is_layered`]), in output order.
    pub fn layered() -> impl Iterator<Item = Model> {
        Self::ALL.into_iter().filter(|m| m.is_layered())
    }

    /// What the model is, in a few words (help texts, the page's list).
    pub fn description(self) -> &'static str {
        match self {
            Self::Exp => "absorptive, exponential correlation (eq. 13)",
            Self::Gauss => "absorptive, Gaussian correlation (eq. 12)",
            Self::Exp2 => "absorptive, exponential, subsurface roughness σ′/T′ free (eqs. 3–4)",
            Self::Gauss2 => "absorptive, Gaussian, subsurface roughness σ′/T′ free (eqs. 3–4)",
            Self::RhExp => "Ragheb–Hancock, exponential (a = 0)",
            Self::RhGauss => "Ragheb–Hancock, Gaussian (a = 0)",
            Self::Jensen => "Jensen et al. 2001 dipole diffusion (σa, σs′)",
            Self::OrenNayar => "Oren–Nayar 1994, full model (σ, ρ)",
        }
    }

    /// The model's parameters in output order: what its fitted model holds
    /// ([`crate::ModelParams`]) and every output lists.
    pub fn params(self) -> &'static [Param] {
        match self.family() {
            Family::Layered { untied: true, .. } => UNTIED,
            Family::Layered { .. } => LAYERED,
            Family::Baseline(b) => b.params(),
        }
    }

    /// The parameters a fit estimates: [`Model::params`] without the
    /// Ragheb–Hancock variants' a (fixed at 0).
    pub fn free_params(self) -> &'static [Param] {
        match self.family() {
            Family::Layered {
                absorption: false, ..
            } => RAGHEB_HANCOCK,
            Family::Layered { .. } | Family::Baseline(_) => self.params(),
        }
    }

    /// The absorptive model of a correlation function (its name is the
    /// correlation's, [`Correlation::name`]).
    pub fn absorptive(corr: Correlation) -> Model {
        Self::ALL
            .into_iter()
            .find(|m| m.correlation() == Some(corr) && !m.is_ragheb_hancock() && !m.is_untied())
            .expect("every correlation has its absorptive model")
    }

    /// Number of fitted parameters p, for χ²/ν (docs/conventions.md §5).
    pub fn parameter_count(self) -> usize {
        self.free_params().len()
    }

    /// Every model's name joined by `", "` (help texts and errors).
    pub fn names(models: impl IntoIterator<Item = Model>) -> String {
        models
            .into_iter()
            .map(Model::name)
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The parameters of `models`, each once, in order of first appearance
/// (the CSV's parameter columns).
pub fn all_params(models: impl IntoIterator<Item = Model>) -> Vec<Param> {
    let mut out: Vec<Param> = Vec::new();
    for model in models {
        for &p in model.params() {
            if !out.contains(&p) {
                out.push(p);
            }
        }
    }
    out
}

/// A baseline's search grid (docs/conventions.md §7), outer and inner
/// axes in [`Baseline::params`]' order: Jensen's σa, σs′ ∈ {0.01, …, 1.00};
/// Oren–Nayar's σ = 0.01 s (s = 0..100), ρ = 0.02 r (r = 1..50).
pub fn baseline_grid(baseline: Baseline) -> (Axis, Axis) {
    match baseline {
        Baseline::Jensen => (
            Axis::stepped(0.01, 0.01, 100),
            Axis::stepped(0.01, 0.01, 100),
        ),
        Baseline::OrenNayar => (Axis::stepped(0.0, 0.01, 101), Axis::stepped(0.02, 0.02, 50)),
    }
}

/// The interior of a baseline's grid that synthetic truths are drawn from
/// (away from the grid's ends), per parameter in [`Baseline::params`]' order.
pub fn baseline_interior(baseline: Baseline) -> [(f64, f64); 2] {
    match baseline {
        Baseline::Jensen => [(0.1, 0.9), (0.1, 0.9)],
        Baseline::OrenNayar => [(0.2, 0.8), (0.2, 0.8)],
    }
}

/// The closed ends of a parameter's domain (the checks of `laminar-brdf-core`,
/// [`Param::domain`]); an open end is NaN (Jensen's σa, σs′ > 0).
pub fn domain(p: Param) -> (f64, f64) {
    let (lo, hi) = p.domain();
    (if p.lower_open() { f64::NAN } else { lo }, hi)
}

/// [`domain`] with an open lower end replaced by the smallest value a fit
/// takes there (Jensen's σa, σs′ > 0: 10⁻⁹).
pub fn attainable_domain(p: Param) -> (f64, f64) {
    let (lo, hi) = domain(p);
    (if lo.is_nan() { 1e-9 } else { lo }, hi)
}

/// True when `value` is a bound of parameter `p`'s domain.
pub fn at_bound(p: Param, value: f64) -> bool {
    let (lo, hi) = domain(p);
    value == lo || value == hi
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
            .ok_or_else(|| ModelError::UnknownModel {
                given: s.to_string(),
                expected: Model::names(Model::ALL),
            })
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Every correlation has its absorptive and Ragheb–Hancock models, the
    /// absorptive one named as the correlation; every name reads back.
    #[test]
    fn the_descriptor_is_consistent() {
        for corr in Correlation::ALL {
            let m = Model::absorptive(corr);
            assert_eq!(m.name(), corr.name());
            let rh = m.ragheb_hancock().expect("an a = 0 variant");
            assert_eq!(rh.correlation(), Some(corr));
            assert!(!rh.free_params().contains(&Param::A));
            let untied = m.untied().expect("an untied variant");
            assert_eq!(untied.correlation(), Some(corr));
            assert_eq!(untied.params()[..2], [Param::Slope, Param::SubSlope]);
            assert!(!Model::tied().any(|t| t == untied));
        }
        for m in Model::ALL {
            assert_eq!(m.name().parse::<Model>(), Ok(m));
            assert!(m.free_params().iter().all(|p| m.params().contains(p)));
            assert_eq!(m.is_layered(), m.correlation().is_some());
        }
        let e = "lambert".parse::<Model>().unwrap_err().to_string();
        assert!(
            e.contains("exp, gauss, exp2, gauss2, rh-exp, rh-gauss, jensen, oren-nayar"),
            "{e}"
        );
    }
}
