//! The names of what the validating constructors check: every model
//! parameter ([`Param`], with its domain) and every angle ([`Angle`]).
//! Errors carry these enums, not strings, so a caller maps them to codes
//! (the C ABI's status) or to names (every other front end) from one place.

use core::f64::consts::FRAC_PI_2;
use core::fmt;

/// Smallest RMS slope σ/T accepted. Below it `(T/σ)²` leaves the `f32` range.
pub const SLOPE_MIN: f64 = 1.0e-3;
/// Largest RMS slope σ/T accepted.
pub const SLOPE_MAX: f64 = 1.0e3;
/// Largest refractive index accepted.
pub const INDEX_MAX: f64 = 10.0;
/// Largest Jensen coefficient σa, σs′ accepted (mm⁻¹).
pub const JENSEN_MAX: f64 = 100.0;

/// A parameter of a model laminar evaluates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Param {
    /// RMS slope σ/T of the rough boundary (eqs. 1–2, 12–13).
    Slope,
    /// Balance β of eq. 8 between subsurface and surface terms.
    Beta,
    /// Refractive index n (eq. 6).
    N,
    /// Absorption a (eqs. 10–11).
    A,
    /// Jensen's absorption coefficient σa (mm⁻¹).
    SigmaA,
    /// Jensen's reduced scattering coefficient σs′ (mm⁻¹).
    SigmaS,
    /// Oren–Nayar's roughness σ (radians).
    Sigma,
    /// Oren–Nayar's albedo ρ.
    Rho,
    /// RMS slope σ′/T′ of the lower boundary (eqs. 3–4), when it is free
    /// beside σ/T (the untied models); the paper's search ties it to σ/T.
    SubSlope,
}

impl Param {
    /// Every parameter.
    pub const ALL: [Param; 9] = [
        Param::Slope,
        Param::Beta,
        Param::N,
        Param::A,
        Param::SigmaA,
        Param::SigmaS,
        Param::Sigma,
        Param::Rho,
        Param::SubSlope,
    ];

    /// The name in every interface (`slope`, `beta`, `sigma_a`, …).
    #[must_use]
    pub const fn name(self) -> &'static str {
        // A table, not a match: the evaluation-only WebAssembly package
        // carries this for its error messages, and data is smaller than code.
        const NAMES: [&str; 9] = [
            "slope",
            "beta",
            "n",
            "a",
            "sigma_a",
            "sigma_s",
            "sigma",
            "rho",
            "sub_slope",
        ];
        NAMES[self as usize]
    }

    /// The symbol a table or a plot shows.
    #[must_use]
    pub const fn symbol(self) -> &'static str {
        match self {
            Self::Slope => "σ/T",
            Self::Beta => "β",
            Self::N => "n",
            Self::A => "a",
            Self::SigmaA => "σa",
            Self::SigmaS => "σs′",
            Self::Sigma => "σ",
            Self::Rho => "ρ",
            Self::SubSlope => "σ′/T′",
        }
    }

    /// The parameter of a name ([`Param::name`]).
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|p| p.name() == name)
    }

    /// The ends of the domain the validating constructors accept. Both are
    /// closed except the lower end of σa and σs′, which is open (> 0):
    /// [`Param::lower_open`].
    #[must_use]
    pub const fn domain(self) -> (f64, f64) {
        match self {
            Self::Slope | Self::SubSlope => (SLOPE_MIN, SLOPE_MAX),
            Self::Beta | Self::A | Self::Rho => (0.0, 1.0),
            Self::N => (1.0, INDEX_MAX),
            Self::SigmaA | Self::SigmaS => (0.0, JENSEN_MAX),
            Self::Sigma => (0.0, FRAC_PI_2),
        }
    }

    /// True when the lower end of [`Param::domain`] is excluded.
    #[must_use]
    pub const fn lower_open(self) -> bool {
        matches!(self, Self::SigmaA | Self::SigmaS)
    }

    /// The domain in words, for an error message.
    #[must_use]
    pub const fn allowed(self) -> &'static str {
        match self {
            Self::Slope | Self::SubSlope => "[1e-3, 1e3]",
            Self::Beta | Self::A | Self::Rho => "[0, 1]",
            Self::N => "[1, 10]",
            Self::SigmaA | Self::SigmaS => "(0, 100]",
            Self::Sigma => "[0, π/2]",
        }
    }
}

impl fmt::Display for Param {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An angle of a measurement's geometry.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Angle {
    /// Incidence polar angle θi.
    ThetaI,
    /// Scattering polar angle θs (the paper's frame).
    ThetaS,
    /// Scattering azimuth φs (the paper's frame).
    PhiS,
    /// Viewing polar angle θv (the lab frame).
    ThetaV,
    /// Incidence azimuth φi (the lab frame).
    PhiI,
    /// Viewing azimuth φv (the lab frame).
    PhiV,
}

impl Angle {
    /// The name in every interface (`theta_i`, …).
    #[must_use]
    pub const fn name(self) -> &'static str {
        // A table, as [`Param::name`].
        const NAMES: [&str; 6] = ["theta_i", "theta_s", "phi_s", "theta_v", "phi_i", "phi_v"];
        NAMES[self as usize]
    }
}

/// What a validating constructor checked: a parameter or an angle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Input {
    /// A model parameter.
    Param(Param),
    /// An angle of the geometry.
    Angle(Angle),
}

impl Input {
    /// Its name ([`Param::name`], [`Angle::name`]).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Param(p) => p.name(),
            Self::Angle(a) => a.name(),
        }
    }
}

impl fmt::Display for Input {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_reads_back_to_its_parameter() {
        for p in Param::ALL {
            assert_eq!(Param::from_name(p.name()), Some(p));
            let (lo, hi) = p.domain();
            assert!(lo < hi, "{p}");
        }
        assert_eq!(Param::from_name("Slope"), None);
    }
}
