//! Where each fitted parameter sits relative to what was searched
//! (docs/conventions.md §6): at the first or last value of its grid axis
//! (`range_edge`: the optimum may lie outside the range searched), or at a
//! bound of the model's domain (`domain_bound`: the data push the parameter
//! as far as it can go). A value with a flag is not a measurement of that
//! parameter in the way an interior value is. The uncertainty analysis
//! ([`crate::uncertainty`]) adds the flags of intervals that stay open.

use crate::grid::Axis;
use crate::model::Model;
use crate::uncertainty::Parameter;
use laminar_core::radiance::{INDEX_MAX, SLOPE_MAX, SLOPE_MIN};
use serde::{Deserialize, Serialize};
use std::f64::consts::FRAC_PI_2;
use std::fmt;

/// What an edge flag says.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
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
}

impl fmt::Display for Edge {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::RangeEdge => "range_edge",
            Self::DomainBound => "domain_bound",
            Self::OpenBelow => "open_below",
            Self::OpenAbove => "open_above",
            Self::NotIdentified => "not_identified",
        })
    }
}

/// The closed ends of a parameter's domain (the checks of `laminar-core`).
pub(crate) fn domain(model: Model, name: &str) -> (f64, f64) {
    match (model, name) {
        (_, "slope") => (SLOPE_MIN, SLOPE_MAX),
        (_, "beta" | "a" | "rho") => (0.0, 1.0),
        (_, "n") => (1.0, INDEX_MAX),
        (Model::OrenNayar, "sigma") => (0.0, FRAC_PI_2),
        // Jensen's σa, σs′ ∈ (0, 100]: only the upper end is attainable.
        _ => (f64::NAN, 100.0),
    }
}

/// [`domain`] with an open lower end replaced by the smallest value a fit
/// takes there (Jensen's σa, σs′ > 0: 10⁻⁹).
pub(crate) fn attainable_domain(model: Model, name: &str) -> (f64, f64) {
    let (lo, hi) = domain(model, name);
    (if lo.is_nan() { 1e-9 } else { lo }, hi)
}

/// The flags of parameter `name` of `model` whose chosen grid value is
/// `value` on `axis`: [`Edge::RangeEdge`] and [`Edge::DomainBound`].
pub fn flags(model: Model, name: &str, value: f64, axis: &Axis) -> Vec<Edge> {
    let (lo, hi) = domain(model, name);
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

/// True when `value` is a bound of `name`'s domain in `model`.
pub(crate) fn at_bound(model: Model, name: &str, value: f64) -> bool {
    let (lo, hi) = domain(model, name);
    value == lo || value == hi
}

/// The flagged parameters as `name:flag[+flag]` joined by `;` (empty when
/// every value is interior): the CSV column `edges`.
pub fn edges_text(parameters: &[Parameter]) -> String {
    parameters
        .iter()
        .filter(|e| !e.flags.is_empty())
        .map(|e| {
            let flags: Vec<String> = e.flags.iter().map(Edge::to_string).collect();
            format!("{}:{}", e.name, flags.join("+"))
        })
        .collect::<Vec<_>>()
        .join(";")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::Grid;

    #[test]
    fn ends_of_the_range_and_of_the_domain_are_flagged() {
        let g = Grid::paper();
        assert_eq!(flags(Model::Exp, "beta", 0.5, &g.beta), vec![]);
        assert_eq!(
            flags(Model::Exp, "slope", 4.04, &g.slope),
            vec![Edge::RangeEdge]
        );
        assert_eq!(
            flags(Model::Exp, "a", 0.0, &g.a),
            vec![Edge::RangeEdge, Edge::DomainBound]
        );
        let p = |name: &str, flags| Parameter {
            flags,
            ..Parameter::new(name, 0.0)
        };
        let list = [
            p("slope", vec![Edge::RangeEdge]),
            p("beta", vec![]),
            p("a", vec![Edge::RangeEdge, Edge::DomainBound]),
        ];
        assert_eq!(
            edges_text(&list),
            "slope:range_edge;a:range_edge+domain_bound"
        );
        // A domain bound inside a wider range: β = 1 on an axis to 1.
        let beta = Axis::linspace(0.0, 1.0, 11);
        assert_eq!(
            flags(Model::Gauss, "beta", 1.0, &beta),
            vec![Edge::RangeEdge, Edge::DomainBound]
        );
    }
}
