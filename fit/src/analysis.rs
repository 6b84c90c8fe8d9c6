//! What a fit does after its grid search: refine or not, and which
//! uncertainty to compute (docs/conventions.md §11). Both objectives and
//! every front end read these settings.

use crate::error::{find_named, UnknownName};
use std::fmt;
use std::str::FromStr;

/// Resamples a bootstrap draws unless told otherwise.
pub const DEFAULT_RESAMPLES: usize = 200;

/// Most resamples a fit takes.
pub const MOST_RESAMPLES: usize = 100_000;

/// Which uncertainty a fit computes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Uncertainty {
    /// None.
    Off,
    /// Intervals from the profile of the error surface.
    Profile,
    /// Standard deviations and correlations from the Jacobian at the refined
    /// optimum; intervals `θ ± 1 sd` and `θ ± 1.96 sd`.
    Jacobian,
    /// Both (the default): profile intervals, standard deviations and
    /// correlations from the Jacobian; under the free objective the
    /// headline interval is the robust one (the profile's calibrated by
    /// the sandwich covariance), the profile's and the Jacobian's kept.
    Both,
    /// What `both` computes, and a pairs bootstrap (free objective) whose
    /// percentile intervals are the headline ([`Analysis::resamples`]
    /// refits, seeded by [`Analysis::seed`]).
    Bootstrap,
}

impl Uncertainty {
    /// Every choice, in the order help texts list them.
    pub const ALL: [Uncertainty; 5] = [
        Self::Off,
        Self::Profile,
        Self::Jacobian,
        Self::Both,
        Self::Bootstrap,
    ];

    /// True for profile intervals.
    pub fn profile(self) -> bool {
        matches!(self, Self::Profile | Self::Both | Self::Bootstrap)
    }

    /// True for the Jacobian's standard deviations.
    pub fn jacobian(self) -> bool {
        matches!(self, Self::Jacobian | Self::Both | Self::Bootstrap)
    }
}

impl fmt::Display for Uncertainty {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Off => "off",
            Self::Profile => "profile",
            Self::Jacobian => "jacobian",
            Self::Both => "both",
            Self::Bootstrap => "bootstrap",
        })
    }
}

impl FromStr for Uncertainty {
    type Err = UnknownName;
    fn from_str(s: &str) -> Result<Self, UnknownName> {
        find_named("uncertainty", &Self::ALL, |u| u.to_string(), s)
    }
}

/// The bootstrap's resample count from its text: a whole number from 2
/// to [`MOST_RESAMPLES`] (the rule every front end applies).
///
/// # Errors
/// A message naming the value and the rule.
pub fn parse_resamples(text: &str) -> Result<usize, String> {
    let rule = format!("give a whole number from 2 to {MOST_RESAMPLES}");
    match text.trim().parse::<usize>() {
        Ok(n) if (2..=MOST_RESAMPLES).contains(&n) => Ok(n),
        _ => Err(format!("`{text}`: {rule}")),
    }
}

/// The bootstrap's seed from its text: a whole number from 0 to 2⁶⁴ − 1.
///
/// # Errors
/// A message naming the value and the rule.
pub fn parse_seed(text: &str) -> Result<u64, String> {
    text.trim()
        .parse::<u64>()
        .map_err(|_| format!("`{text}`: give a whole number from 0 to {}", u64::MAX))
}

/// Folds of a model comparison's cross-validation unless told otherwise.
pub const DEFAULT_FOLDS: usize = 5;

/// Most folds (leave-one-out on 100 measurements).
pub const MOST_FOLDS: usize = 100;

/// The cross-validation's fold count from its text: 0 (none) or a whole
/// number from 2 to [`MOST_FOLDS`] (the rule every front end applies).
///
/// # Errors
/// A message naming the value and the rule.
pub fn parse_folds(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if n == 0 || (2..=MOST_FOLDS).contains(&n) => Ok(n),
        _ => Err(format!(
            "`{text}`: give 0 (no cross-validation) or a whole number from 2 to {MOST_FOLDS}"
        )),
    }
}

/// What a fit does after its grid search.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Analysis {
    /// Refine the best grid point (and the best of each other basin).
    pub refine: bool,
    /// Which uncertainty to compute.
    pub uncertainty: Uncertainty,
    /// Resamples of the bootstrap ([`Uncertainty::Bootstrap`]), 2 to
    /// [`MOST_RESAMPLES`] ([`parse_resamples`]).
    pub resamples: usize,
    /// The seed of the bootstrap and of the cross-validation's folds: the
    /// same seed, the same intervals and errors.
    pub seed: u64,
    /// Folds of the cross-validation of each model when several are
    /// compared on one set ([`crate::Fitter::fit_all`]; 0 for none, else
    /// 2 to [`MOST_FOLDS`], [`parse_folds`]).
    pub folds: usize,
}

impl Analysis {
    /// Refinement and both uncertainties: every command's default.
    pub const FULL: Analysis = Analysis {
        refine: true,
        uncertainty: Uncertainty::Both,
        resamples: DEFAULT_RESAMPLES,
        seed: 0,
        folds: DEFAULT_FOLDS,
    };
    /// The grid search alone.
    pub const NONE: Analysis = Analysis {
        refine: false,
        uncertainty: Uncertainty::Off,
        ..Analysis::FULL
    };

    /// This analysis without the cross-validation (a model fitted alone).
    pub(crate) fn alone(self) -> Analysis {
        Analysis { folds: 0, ..self }
    }

    /// True when the grid's profile is needed (for intervals or for the
    /// starts of the refinement).
    pub(crate) fn needs_profile(self) -> bool {
        self.refine || self.uncertainty.profile()
    }
}
