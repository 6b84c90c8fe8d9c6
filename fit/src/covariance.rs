//! The covariance of a refined estimate from the Jacobian of the prediction
//! (docs/conventions.md §11): `C = s² (JᵀJ)⁻¹`, `J_kj = ∂P_k/∂θ_j` by central
//! differences, valid when no parameter is at a bound of its domain (there
//! the linearisation does not hold and only the profile intervals apply).

use crate::refine::Objective;
use nalgebra::DMatrix;

/// The covariance and correlation of the free parameters of a refined fit.
#[derive(Debug, Clone, PartialEq)]
pub struct Covariance {
    /// Names, in [`Objective::names`] order.
    pub names: Vec<String>,
    /// `C_ij`.
    pub matrix: Vec<Vec<f64>>,
}

/// A correlation at least this large in magnitude is reported as a
/// trade-off between two parameters.
pub const TRADE_OFF: f64 = 0.9;

/// Relative step of the central differences.
const STEP: f64 = 1e-6;

impl Covariance {
    /// `s² (JᵀJ)⁻¹` at the free values `x`, or `None` when a parameter is
    /// within a difference step of a bound of its domain, or `JᵀJ` is
    /// singular (a parameter the data do not constrain at all).
    pub fn new(objective: &Objective, x: &[f64], s2: f64) -> Option<Self> {
        let k = objective.prediction(x).ok()?.len();
        let p = x.len();
        let mut jacobian = DMatrix::<f64>::zeros(k, p);
        for (j, &(lo, hi)) in objective.bounds().iter().enumerate() {
            let h = STEP * x[j].abs().max(1e-3);
            if x[j] - h < lo || x[j] + h > hi {
                return None;
            }
            let at = |v: f64| {
                let mut y = x.to_vec();
                y[j] = v;
                objective.prediction(&y).ok()
            };
            let (up, down) = (at(x[j] + h)?, at(x[j] - h)?);
            for (row, (u, d)) in up.iter().zip(&down).enumerate() {
                jacobian[(row, j)] = (u - d) / (2.0 * h);
            }
        }
        let inverse = (jacobian.transpose() * &jacobian).cholesky()?.inverse();
        let matrix = (0..p)
            .map(|i| (0..p).map(|j| s2 * inverse[(i, j)]).collect())
            .collect();
        Some(Self {
            names: objective.names().iter().map(|n| n.to_string()).collect(),
            matrix,
        })
    }

    /// The standard deviation of parameter `i`.
    pub fn sd(&self, i: usize) -> f64 {
        self.matrix[i][i].sqrt()
    }

    /// The correlation of parameters `i` and `j`.
    pub fn correlation(&self, i: usize, j: usize) -> f64 {
        self.matrix[i][j] / (self.sd(i) * self.sd(j))
    }

    /// Every pair whose correlation is at least [`TRADE_OFF`] in magnitude,
    /// as (name, name, correlation).
    pub fn trade_offs(&self) -> Vec<(String, String, f64)> {
        let mut out = Vec::new();
        for i in 0..self.names.len() {
            for j in i + 1..self.names.len() {
                let r = self.correlation(i, j);
                if r.abs() >= TRADE_OFF {
                    out.push((self.names[i].clone(), self.names[j].clone(), r));
                }
            }
        }
        out
    }

    /// Every correlation as `a~b=r` joined by `;` (r to 3 decimals).
    pub fn correlations_text(&self) -> String {
        let mut out = Vec::new();
        for i in 0..self.names.len() {
            for j in i + 1..self.names.len() {
                out.push(format!(
                    "{}~{}={:.3}",
                    self.names[i],
                    self.names[j],
                    self.correlation(i, j)
                ));
            }
        }
        out.join(";")
    }
}
