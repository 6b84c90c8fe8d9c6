//! Where each fitted parameter sits relative to what was searched
//! (docs/conventions.md §6): at the first or last value of its grid axis
//! (`range_edge`: the optimum may lie outside the range searched), or at a
//! bound of the model's domain (`domain_bound`: the data push the parameter
//! as far as it can go). A value with a flag is not a measurement of that
//! parameter in the way an interior value is.

use crate::grid::Axis;
use crate::model::Model;
use laminar_core::radiance::{INDEX_MAX, SLOPE_MAX, SLOPE_MIN};
use serde::{Deserialize, Serialize};
use std::f64::consts::FRAC_PI_2;
use std::fmt;

/// What an edge flag says.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Edge {
    /// The first or last value of the parameter's grid axis.
    RangeEdge,
    /// A bound of the model's domain (e.g. a = 0 or 1, n = 1).
    DomainBound,
}

impl fmt::Display for Edge {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::RangeEdge => "range_edge",
            Self::DomainBound => "domain_bound",
        })
    }
}

/// One searched parameter of a fit: its grid value and its flags.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParameterEdges {
    /// The parameter's name (as in [`crate::ModelParams`]).
    pub name: String,
    /// The chosen grid value.
    pub grid: f64,
    /// Its flags (empty for an interior value).
    pub flags: Vec<Edge>,
}

/// The closed ends of a parameter's domain (the checks of `laminar-core`).
fn domain(model: Model, name: &str) -> (f64, f64) {
    match (model, name) {
        (_, "slope") => (SLOPE_MIN, SLOPE_MAX),
        (_, "beta" | "a" | "rho") => (0.0, 1.0),
        (_, "n") => (1.0, INDEX_MAX),
        (Model::OrenNayar, "sigma") => (0.0, FRAC_PI_2),
        // Jensen's σa, σs′ ∈ (0, 100]: only the upper end is attainable.
        _ => (f64::NAN, 100.0),
    }
}

/// The flags of every searched parameter: `searched` pairs each parameter's
/// name and chosen value with the axis it was searched on. An axis of one
/// value is not a search of that parameter (a of Ragheb–Hancock), so it is
/// left out.
pub fn edges(model: Model, searched: &[(&str, f64, &Axis)]) -> Vec<ParameterEdges> {
    searched
        .iter()
        .filter(|(_, _, axis)| axis.len() > 1)
        .map(|&(name, value, axis)| {
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
            ParameterEdges {
                name: name.to_string(),
                grid: value,
                flags,
            }
        })
        .collect()
}

/// The flagged parameters as `name:flag[+flag]` joined by `;` (empty when
/// every value is interior): the CSV column `edges`.
pub fn edges_text(edges: &[ParameterEdges]) -> String {
    edges
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
        let searched = [
            ("slope", 4.04, &g.slope),
            ("beta", 0.5, &g.beta),
            ("n", 1.3, &g.n),
            ("a", 0.0, &g.a),
        ];
        let e = edges(Model::Exp, &searched);
        assert_eq!(e[1].flags, vec![]);
        assert_eq!(e[0].flags, vec![Edge::RangeEdge]);
        assert_eq!(e[3].flags, vec![Edge::RangeEdge, Edge::DomainBound]);
        assert_eq!(
            edges_text(&e),
            "slope:range_edge;n:range_edge;a:range_edge+domain_bound"
        );
        // a fixed at 0 (Ragheb–Hancock) is not a searched parameter.
        let rh = g.ragheb_hancock();
        let e = edges(Model::RhExp, &[("a", 0.0, &rh.a), ("n", 1.42, &rh.n)]);
        assert_eq!(e.len(), 1);
        assert_eq!(edges_text(&e), "");
        // A domain bound inside a wider range: β = 1 on an axis to 1.
        let beta = Axis::linspace(0.0, 1.0, 11);
        let e = edges(Model::Gauss, &[("beta", 1.0, &beta)]);
        assert_eq!(e[0].flags, vec![Edge::RangeEdge, Edge::DomainBound]);
    }
}
