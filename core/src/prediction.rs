//! A fitted layered model's prediction from its raw terms (docs/conventions.md
//! §4 and §4b): what a fitted-model file's parameters and normalisation
//! constants mean, shared by the fitting library and the evaluation-only
//! front ends so that both give the same bits.

use crate::radiance::mix;

/// `v / m`, or 0 for a term whose max was not positive (§4).
#[inline]
#[must_use]
pub fn scaled(v: f64, m: f64) -> f64 {
    if m > 0.0 {
        v / m
    } else {
        0.0
    }
}

/// How a fitted layered model turns its raw terms into its prediction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scaling {
    /// The paper's objective (§4): the surface and subsurface terms each
    /// divided by its max over the fit's measurements, mixed with β (eq. 8),
    /// the mix divided by its max.
    Maxima {
        /// Max of the raw surface term.
        surface: f64,
        /// Max of the raw subsurface term.
        subsurface: f64,
        /// Max of the mix of the two divided terms.
        mix: f64,
    },
    /// The free-amplitude objective (§4b): the amplitude times eq. 8's raw
    /// mix.
    Amplitude(f64),
}

impl Scaling {
    /// The prediction at one geometry from its raw `surface` (eq. 1 or 2)
    /// and `subsurface` (eq. 12 or 13) terms, at balance `beta`.
    #[inline]
    #[must_use]
    pub fn predict(self, beta: f64, surface: f64, subsurface: f64) -> f64 {
        match self {
            Self::Maxima {
                surface: sf,
                subsurface: sb,
                mix: m,
            } => scaled(mix(beta, scaled(subsurface, sb), scaled(surface, sf)), m),
            Self::Amplitude(amplitude) => amplitude * mix(beta, subsurface, surface),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maxima_divide_each_term_then_the_mix() {
        let s = Scaling::Maxima {
            surface: 2.0,
            subsurface: 4.0,
            mix: 0.5,
        };
        // (0.25·(1/4) + 0.75·(1/2)) / 0.5 = 0.875
        assert_eq!(s.predict(0.25, 1.0, 1.0), 0.875);
        assert_eq!(Scaling::Amplitude(3.0).predict(0.5, 1.0, 3.0), 6.0);
        // A term whose max was not positive contributes 0.
        let zero = Scaling::Maxima {
            surface: 0.0,
            subsurface: 1.0,
            mix: 1.0,
        };
        assert_eq!(zero.predict(0.5, 7.0, 1.0), 0.5);
    }
}
