//! The levels of a free fit's intervals (docs/conventions.md §11b). With
//! uncertainties given, the objective is χ² and the levels are χ²₁'s
//! quantiles (`Δ = 1`, `3.841`); without them the noise variance is the
//! residual estimate `s² = F_min/(K − p)` and the levels are those of
//! `F(1, K − p)` (the square of Student's t), which the estimate of `s²`
//! widens a little for small K.

use crate::free::model::FreeModel;
use crate::free::problem::Problem;
use crate::profile::Z_95;

/// The two-sided normal quantiles of the 68.27% and 95% levels.
pub const Z: [f64; 2] = [1.0, Z_95];

/// Student's t quantile for the normal quantile `z` and `nu` degrees of
/// freedom (Cornish–Fisher expansion to `ν⁻³`; better than 10⁻⁴ relative
/// for `ν ≥ 10`).
pub fn student_t(z: f64, nu: f64) -> f64 {
    let (z3, z5, z7) = (z.powi(3), z.powi(5), z.powi(7));
    z + (z3 + z) / (4.0 * nu)
        + (5.0 * z5 + 16.0 * z3 + 3.0 * z) / (96.0 * nu * nu)
        + (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / (384.0 * nu * nu * nu)
}

/// The scale of the objective's levels: the noise variance and the two
/// levels `Δ · s²` above the minimum (68.27%, 95%).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Levels {
    /// `s²` (1 when the weights are `1/σ²`).
    pub s2: f64,
    /// `Δ_68 · s²` and `Δ_95 · s²`.
    pub heights: [f64; 2],
}

impl Levels {
    /// The levels of `problem` at its minimum `sse`; `None` without degrees
    /// of freedom.
    pub fn new<M: FreeModel>(problem: &Problem<M>, sse: f64) -> Option<Self> {
        let nu = problem.data.len().checked_sub(problem.parameter_count())?;
        if nu == 0 {
            return None;
        }
        if problem.weighted {
            return Some(Self {
                s2: 1.0,
                heights: Z.map(|z| z * z),
            });
        }
        let s2 = sse / nu as f64;
        Some(Self {
            s2,
            heights: Z.map(|z| student_t(z, nu as f64).powi(2) * s2),
        })
    }
}
