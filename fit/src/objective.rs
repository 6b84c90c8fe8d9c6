//! Which objective a fit minimises (docs/conventions.md §4, §4b).

use crate::error::FitError;
use crate::error::{find_named, UnknownName};
use crate::grid::Grid;
use crate::model::Model;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// The objective of a fit.
///
/// ```
/// use laminar_brdf_fit::{synthetic, Fitter, Grid, Model, Objective, Param};
/// // The built-in scene: exp at σ/T 1.48, n 1.44, a 0.17, noise σ = 0.005.
/// let scene = synthetic::default_scene();
/// let fit = Fitter::new(Grid::user())?
///     .objective(Objective::Free)
///     .fit(&scene, Model::Exp);
/// for (name, truth) in [(Param::Slope, 1.48), (Param::N, 1.44), (Param::A, 0.17)] {
///     let p = fit.parameters.iter().find(|p| p.name == name).unwrap();
///     let (lo, hi) = p.bounds.unwrap();
///     assert!(lo <= p.value() && p.value() <= hi, "{name}: in the box");
///     let i = p.interval95.unwrap();
///     assert!(i.lo <= truth && truth <= i.hi, "{name}: {i:?}");
/// }
/// assert_eq!(fit.objective, Objective::Free);
/// # Ok::<(), laminar_brdf_fit::FitError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "typescript", derive(ts_rs::TS))]
#[serde(rename_all = "snake_case")]
pub enum Objective {
    /// Weighted least squares with a free amplitude (docs/conventions.md
    /// §4b): `Σ w (D − c M(θ))²`, `M` eq. 8's raw mix, `c ≥ 0` and β in
    /// closed form, `w = 1/σ²` when the input gives uncertainties. The
    /// default for a user's own data.
    #[default]
    Free,
    /// The paper's: data and model each divided by their max over the
    /// measurements, unweighted (docs/conventions.md §4). What `reproduce`
    /// uses to reproduce the paper's tables.
    Paper,
}

impl Objective {
    /// Both, default first.
    pub const ALL: [Objective; 2] = [Objective::Free, Objective::Paper];

    /// The name in every interface.
    pub fn name(self) -> &'static str {
        match self {
            Self::Free => "free",
            Self::Paper => "paper",
        }
    }

    /// The grid (and so the box) a fit of this objective searches unless
    /// told otherwise: [`Grid::user`] for `free`, [`Grid::paper`] for `paper`.
    pub fn default_grid(self) -> Grid {
        match self {
            Self::Free => Grid::user(),
            Self::Paper => Grid::paper(),
        }
    }

    /// Whether this objective fits `model`: the paper's search ties σ′/T′
    /// to σ/T, so it does not fit the untied models.
    ///
    /// # Errors
    /// [`FitError::UntiedUnderPaper`] for an untied model under `paper`.
    pub fn takes(self, model: Model) -> Result<(), FitError> {
        match self {
            Self::Paper if model.is_untied() => Err(FitError::UntiedUnderPaper {
                model: model.name(),
                tied: model.tied_model().name(),
            }),
            Self::Paper | Self::Free => Ok(()),
        }
    }

    /// The models a comparison of this objective fits unless told
    /// otherwise: every model for `free`; for `paper`, the models of the
    /// paper's search ([`Model::tied`]: it ties σ′/T′ to σ/T).
    pub fn default_models(self) -> Vec<Model> {
        match self {
            Self::Free => Model::ALL.to_vec(),
            Self::Paper => Model::tied().collect(),
        }
    }
}

impl fmt::Display for Objective {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Objective {
    type Err = UnknownName;
    fn from_str(s: &str) -> Result<Self, UnknownName> {
        find_named("objective", &Self::ALL, Self::name, s)
    }
}
