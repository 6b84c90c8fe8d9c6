//! Where each reported parameter of a free fit is in the objective: a
//! nonlinear parameter at its place in θ (in its coordinate), or β, which
//! the linear part solves for.

use super::problem::{Point, Problem};

/// A reported parameter: one of the nonlinear ones (index into `θ`), or β.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Coordinate {
    /// Nonlinear parameter `j`; `log` when `θ_j` is the logarithm of the
    /// reported value (σ/T).
    Nonlinear {
        /// Index into `θ`.
        j: usize,
        /// `θ_j = ln(value)`.
        log: bool,
    },
    /// β of eq. 8.
    Beta,
}

impl Coordinate {
    /// The reported value at `point` (σ/T from its logarithm, kept in the box).
    pub fn value<M>(self, point: &Point, problem: &Problem<M>) -> f64 {
        match self {
            Self::Nonlinear { j, log } => {
                if log {
                    let (lo, hi) = problem.reported[j];
                    libm::exp(point.theta[j]).clamp(lo, hi)
                } else {
                    point.theta[j]
                }
            }
            Self::Beta => point.linear.beta(problem.beta.0),
        }
    }

    /// The box in reported units.
    pub fn bounds<M>(self, problem: &Problem<M>) -> (f64, f64) {
        match self {
            Self::Nonlinear { j, .. } => problem.reported[j],
            Self::Beta => problem.beta,
        }
    }
}
