//! What a fit does after its grid search: refine or not, and which
//! uncertainty to compute (docs/conventions.md §11). Both objectives and
//! every front end read these settings.

use crate::error::{find_named, UnknownName};
use std::fmt;
use std::str::FromStr;

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
    /// Both: intervals from the profile, standard deviations and
    /// correlations from the Jacobian.
    Both,
}

impl Uncertainty {
    /// Every choice, in the order help texts list them.
    pub const ALL: [Uncertainty; 4] = [Self::Off, Self::Profile, Self::Jacobian, Self::Both];

    /// True for profile intervals.
    pub fn profile(self) -> bool {
        matches!(self, Self::Profile | Self::Both)
    }

    /// True for the Jacobian's standard deviations.
    pub fn jacobian(self) -> bool {
        matches!(self, Self::Jacobian | Self::Both)
    }
}

impl fmt::Display for Uncertainty {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Off => "off",
            Self::Profile => "profile",
            Self::Jacobian => "jacobian",
            Self::Both => "both",
        })
    }
}

impl FromStr for Uncertainty {
    type Err = UnknownName;
    fn from_str(s: &str) -> Result<Self, UnknownName> {
        find_named("uncertainty", &Self::ALL, |u| u.to_string(), s)
    }
}

/// What a fit does after its grid search.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Analysis {
    /// Refine the best grid point (and the best of each other basin).
    pub refine: bool,
    /// Which uncertainty to compute.
    pub uncertainty: Uncertainty,
}

impl Analysis {
    /// Refinement and both uncertainties: every command's default.
    pub const FULL: Analysis = Analysis {
        refine: true,
        uncertainty: Uncertainty::Both,
    };
    /// The grid search alone.
    pub const NONE: Analysis = Analysis {
        refine: false,
        uncertainty: Uncertainty::Off,
    };

    /// True when the grid's profile is needed (for intervals or for the
    /// starts of the refinement).
    pub(crate) fn needs_profile(self) -> bool {
        self.refine || self.uncertainty.profile()
    }
}
