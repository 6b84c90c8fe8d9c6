//! The covariance of a refined estimate from the Jacobian of the prediction
//! (docs/conventions.md §11): `C = s² (JᵀJ)⁻¹`, valid when no parameter is
//! at a bound of its domain (there the linearisation does not hold and only
//! the profile intervals apply). Each objective builds its own Jacobian
//! (the paper's by central differences, [`crate::paper::intervals`]; the
//! free-amplitude one analytically, [`crate::free::statistics::covariance`]); this is
//! what a fit reports of it.

use crate::model::Param;
use nalgebra::DMatrix;

/// The covariance and correlation of the free parameters of a refined fit.
#[derive(Debug, Clone, PartialEq)]
pub struct Covariance {
    /// The parameters, in the fit's order.
    pub names: Vec<Param>,
    /// `C_ij`.
    pub matrix: Vec<Vec<f64>>,
}

/// A correlation at least this large in magnitude is reported as a
/// trade-off between two parameters.
pub const TRADE_OFF: f64 = 0.9;

/// `a · b`, summed in index order: nalgebra's products of dynamic
/// matrices above a few rows go through `matrixmultiply`, which picks FMA
/// kernels at run time, so the same fit gave other bits on another CPU or
/// in wasm (the untied models' six parameters did).
pub(crate) fn product(a: &DMatrix<f64>, b: &DMatrix<f64>) -> DMatrix<f64> {
    DMatrix::from_fn(a.nrows(), b.ncols(), |i, j| {
        (0..a.ncols()).map(|k| a[(i, k)] * b[(k, j)]).sum()
    })
}

impl Covariance {
    /// `s² (JᵀJ)⁻¹` of the Jacobian `jacobian` (one column per parameter
    /// of `names`), or `None` when `JᵀJ` is singular (a parameter the data
    /// do not constrain at all).
    pub fn from_jacobian(names: &[Param], jacobian: &DMatrix<f64>, s2: f64) -> Option<Self> {
        let p = jacobian.ncols();
        let inverse = product(&jacobian.transpose(), jacobian)
            .cholesky()?
            .inverse();
        let matrix = (0..p)
            .map(|i| (0..p).map(|j| s2 * inverse[(i, j)]).collect())
            .collect();
        Some(Self {
            names: names.to_vec(),
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

    /// Every pair whose correlation is at least `TRADE_OFF` (0.9) in magnitude,
    /// as (parameter, parameter, correlation).
    pub fn trade_offs(&self) -> Vec<(Param, Param, f64)> {
        let mut out = Vec::new();
        for i in 0..self.names.len() {
            for j in i + 1..self.names.len() {
                let r = self.correlation(i, j);
                if r.abs() >= TRADE_OFF {
                    out.push((self.names[i], self.names[j], r));
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
