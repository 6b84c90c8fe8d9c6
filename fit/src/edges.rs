//! Where each fitted parameter sits relative to what was searched
//! (docs/conventions.md §6): at the first or last value of its grid axis
//! (`range_edge`: the optimum may lie outside the range searched), or at a
//! bound of the model's domain ([`crate::model::domain`]; `domain_bound`: the data
//! push the parameter as far as it can go). A value with a flag is not a
//! measurement of that parameter in the way an interior value is. The
//! intervals ([`crate::paper::intervals`], [`crate::free::statistics`]) add
//! the flags of intervals that stay open.

use crate::grid::Axis;
use crate::model::{domain, Param};
use serde::{Deserialize, Serialize};
use std::fmt;

/// What an edge flag says.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "typescript", derive(ts_rs::TS))]
#[serde(rename_all = "snake_case")]
pub enum Edge {
    /// Paper objective: the grid value is the first or last value of the
    /// parameter's axis. Free objective: the estimate is on a face of the
    /// box (the fit then also reports what releasing that bound gives).
    RangeEdge,
    /// The value reported (the refined one when refined, else the grid's)
    /// is a bound of the model's domain (e.g. a = 0 or 1, n = 1).
    DomainBound,
    /// The 95% profile interval does not close within the range searched
    /// below the estimate (and the range does not start at a domain bound).
    OpenBelow,
    /// As [`Edge::OpenBelow`], above the estimate.
    OpenAbove,
    /// The free-amplitude objective's 95% profile interval spans the whole
    /// box: the data do not determine this parameter (e.g. Jensen's σa and
    /// σs′ alone, whose ratio is all the model sees).
    NotIdentified,
    /// The sandwich (misfit-robust) standard deviation and the model-based
    /// one differ by more than `MISFIT_SENSITIVE`× either way: the
    /// interval depends on the model fitting the data exactly.
    MisfitSensitive,
    /// The free-amplitude objective's profile is flat to within its 68.27%
    /// level (Δχ² = 1) across the whole box: the value is not determined,
    /// though the 95% interval may close on one side.
    NotDetermined,
}

/// The ratio of the robust to the model-based standard deviation beyond
/// which (or below whose reciprocal) a parameter is [`Edge::MisfitSensitive`].
pub const MISFIT_SENSITIVE: f64 = 1.5;

impl Edge {
    /// Every flag, in the order of their bits ([`Edge::bit`]).
    pub const ALL: [Edge; 7] = [
        Self::RangeEdge,
        Self::DomainBound,
        Self::OpenBelow,
        Self::OpenAbove,
        Self::NotIdentified,
        Self::MisfitSensitive,
        Self::NotDetermined,
    ];

    /// The flag's bit in a mask of flags (`1 << ` its place in
    /// [`Edge::ALL`]), for outputs that hold numbers only.
    pub fn bit(self) -> u8 {
        match self {
            Self::RangeEdge => 1,
            Self::DomainBound => 2,
            Self::OpenBelow => 4,
            Self::OpenAbove => 8,
            Self::NotIdentified => 16,
            Self::MisfitSensitive => 32,
            Self::NotDetermined => 64,
        }
    }

    /// The mask of `flags` (the sum of their bits).
    pub fn mask(flags: &[Edge]) -> u8 {
        flags.iter().fold(0, |m, f| m | f.bit())
    }
}

impl fmt::Display for Edge {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::RangeEdge => "range_edge",
            Self::DomainBound => "domain_bound",
            Self::OpenBelow => "open_below",
            Self::OpenAbove => "open_above",
            Self::NotIdentified => "not_identified",
            Self::MisfitSensitive => "misfit_sensitive",
            Self::NotDetermined => "not_determined",
        })
    }
}

/// The flags of parameter `p` whose chosen grid value is `value` on
/// `axis`: [`Edge::RangeEdge`] and [`Edge::DomainBound`].
pub fn flags(p: Param, value: f64, axis: &Axis) -> Vec<Edge> {
    let (lo, hi) = domain(p);
    let first = axis.values.iter().copied().fold(f64::INFINITY, f64::min);
    let last = axis
        .values
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    let mut flags = Vec::new();
    if value == first || value == last {
        flags.push(Edge::RangeEdge);
    }
    if value == lo || value == hi {
        flags.push(Edge::DomainBound);
    }
    flags
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_flag_has_its_own_bit_in_order() {
        for (i, f) in Edge::ALL.iter().enumerate() {
            assert_eq!(f.bit(), 1 << i, "{f}");
        }
        assert_eq!(Edge::mask(&[Edge::OpenAbove, Edge::RangeEdge]), 9);
        assert_eq!(Edge::mask(&[]), 0);
    }
    use crate::grid::Grid;

    #[test]
    fn ends_of_the_range_and_of_the_domain_are_flagged() {
        let g = Grid::paper();
        assert_eq!(flags(Param::Beta, 0.5, &g.beta), vec![]);
        assert_eq!(flags(Param::Slope, 4.04, &g.slope), vec![Edge::RangeEdge]);
        assert_eq!(
            flags(Param::A, 0.0, &g.a),
            vec![Edge::RangeEdge, Edge::DomainBound]
        );
        // A domain bound inside a wider range: β = 1 on an axis to 1.
        let beta = Axis::linspace(0.0, 1.0, 11);
        assert_eq!(
            flags(Param::Beta, 1.0, &beta),
            vec![Edge::RangeEdge, Edge::DomainBound]
        );
    }
}
