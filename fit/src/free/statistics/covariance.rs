//! The Jacobian covariance of a free fit's reported parameters: the
//! model-based one, and the sandwich (Huber–White) one that holds when the
//! model does not fit the data exactly (docs/estimation.md).

use crate::covariance::product;
use crate::free::coordinate::Coordinate;
use crate::free::model::FreeModel;
use crate::free::problem::{Point, Problem};
use nalgebra::DMatrix;

/// The smallest pivot of the unit-diagonal `JᵀWJ`'s Cholesky factorisation
/// (`l_ii²`, at most its smallest eigenvalue times the parameter count)
/// with which a covariance is formed. Below it some combination of the
/// parameters is determined to no better than rounding (Jensen's σa and
/// σs′ enter only through their ratio): whether the factorisation even
/// succeeds is then a matter of the last bits, and the inverse is rounding
/// amplified by 10¹² or more, so there is no covariance.
pub const SINGULAR_PIVOT: f64 = 1e-12;

/// The Jacobian covariance of the reported parameters (nonlinear ones in
/// reported units, then β for the layered models, then the amplitude): the
/// model-based one, and the sandwich (Huber–White) one that holds when the
/// model does not fit the data exactly (docs/estimation.md).
#[derive(Debug, Clone, PartialEq)]
pub struct JacobianCovariance {
    /// `s² (JᵀWJ)⁻¹` over the parameters not on a face of the box; a
    /// parameter on a face has `None` in its row and column.
    pub matrix: Vec<Vec<Option<f64>>>,
    /// The sandwich `A⁻¹ B A⁻¹`, `A = JᵀWJ`,
    /// `B = Σ_k w_k² r_k² J_k J_kᵀ / (1 − h_k)²` with the leverages
    /// `h_k = w_k J_kᵀ A⁻¹ J_k` (HC3: MacKinnon and White 1985; the
    /// small-sample choice of Long and Ervin 2000), over the same
    /// parameters.
    pub robust: Vec<Vec<Option<f64>>>,
}

impl JacobianCovariance {
    /// The covariance at the minimum `point`, with the noise variance `s2`;
    /// `None` when `JᵀJ` is singular (to [`SINGULAR_PIVOT`]).
    pub fn new<M: FreeModel>(
        problem: &Problem<M>,
        point: &Point,
        coordinates: &[Coordinate],
        s2: f64,
    ) -> Option<Self> {
        let (jac, on_face, residuals) = jacobian(problem, point, coordinates);
        let kept: Vec<usize> = (0..jac.len()).filter(|&i| !on_face[i]).collect();
        let mut normal = DMatrix::<f64>::zeros(kept.len(), kept.len());
        for (a, &i) in kept.iter().enumerate() {
            for (b, &j) in kept.iter().enumerate() {
                normal[(a, b)] = (0..residuals.len())
                    .map(|r| problem.weight[r] * jac[i][r] * jac[j][r])
                    .sum();
            }
        }
        // Scale to unit diagonal before inverting: the parameters' units differ.
        let d: Vec<f64> = (0..kept.len()).map(|i| normal[(i, i)].sqrt()).collect();
        if d.iter().any(|&v| v.is_nan() || v <= 0.0 || v.is_infinite()) {
            return None;
        }
        let scaled = DMatrix::from_fn(kept.len(), kept.len(), |i, j| {
            normal[(i, j)] / (d[i] * d[j])
        });
        let cholesky = scaled.cholesky()?;
        if cholesky
            .l_dirty()
            .diagonal()
            .iter()
            .any(|l| l * l < SINGULAR_PIVOT)
        {
            return None;
        }
        let inverse = cholesky.inverse();
        let scaled_rows = |r: usize, row: &mut [f64]| {
            for ((x, &i), &di) in row.iter_mut().zip(&kept).zip(&d) {
                *x = jac[i][r] / di;
            }
        };
        let meat = meat(&problem.weight, &residuals, &inverse, scaled_rows);
        let sandwich = product(&product(&inverse, &meat), &inverse);
        let mut matrix = vec![vec![None; jac.len()]; jac.len()];
        let mut robust = vec![vec![None; jac.len()]; jac.len()];
        for (a, &i) in kept.iter().enumerate() {
            for (b, &j) in kept.iter().enumerate() {
                matrix[i][j] = Some(s2 * inverse[(a, b)] / (d[a] * d[b]));
                let v = sandwich[(a, b)] / (d[a] * d[b]);
                robust[i][j] = v.is_finite().then_some(v);
            }
        }
        Some(Self { matrix, robust })
    }

    /// The standard deviation of parameter `i`.
    pub fn sd(&self, i: usize) -> Option<f64> {
        self.matrix[i][i].map(f64::sqrt)
    }

    /// The sandwich standard deviation of parameter `i`.
    pub fn robust_sd(&self, i: usize) -> Option<f64> {
        self.robust[i][i].filter(|v| *v >= 0.0).map(f64::sqrt)
    }

    /// `robust_sd / sd` of parameter `i`: how much wider the interval that
    /// survives misfit is than the model-based one (1 when the model fits).
    pub fn misfit_ratio(&self, i: usize) -> Option<f64> {
        let r = self.robust_sd(i)? / self.sd(i)?;
        (r.is_finite() && r > 0.0).then_some(r)
    }
}

/// `∂(c M_k)/∂` each reported parameter (in its own units) at `point`,
/// then `∂/∂c`; whether each is on a face of the box; and the weighted
/// residuals there.
pub(crate) fn jacobian<M: FreeModel>(
    problem: &Problem<M>,
    point: &Point,
    coordinates: &[Coordinate],
) -> (Vec<Vec<f64>>, Vec<bool>, Vec<f64>) {
    let (columns, derivatives) = problem
        .model
        .derivatives(&point.theta, &problem.domain, true);
    let c = point.linear.amplitude();
    let beta = point.linear.beta(problem.beta.0);
    let k = problem.data.len();
    // A column, or 0 where it is empty (no U; the surface term's
    // derivative in n and a).
    let entry = |v: &[f64], i: usize| v.get(i).copied().unwrap_or(0.0);
    let mut jac: Vec<Vec<f64>> = Vec::new();
    let mut on_face: Vec<bool> = Vec::new();
    for &coordinate in coordinates {
        let (col, face) = match coordinate {
            Coordinate::Nonlinear { j, log } => {
                let scale = if log {
                    1.0 / libm::exp(point.theta[j])
                } else {
                    1.0
                };
                let d = &derivatives[j];
                let col = (0..k)
                    .map(|i| c * ((1.0 - beta) * entry(&d.s, i) + beta * entry(&d.u, i)) * scale)
                    .collect();
                let (lo, hi) = problem.bounds[j];
                (col, point.theta[j] <= lo || point.theta[j] >= hi)
            }
            Coordinate::Beta => {
                let col = (0..k)
                    .map(|i| c * (entry(&columns.u, i) - columns.s[i]))
                    .collect();
                let (lo, hi) = problem.beta;
                (col, beta <= lo || beta >= hi)
            }
        };
        jac.push(col);
        on_face.push(face);
    }
    jac.push(
        (0..k)
            .map(|i| (1.0 - beta) * columns.s[i] + beta * entry(&columns.u, i))
            .collect(),
    );
    on_face.push(c <= 0.0);
    let residuals = problem.residuals(&columns, &point.linear);
    (jac, on_face, residuals)
}

/// The sandwich's meat `Σ_k w_k² r_k² J_k J_kᵀ / (1 − h_k)²`, from the
/// weighted residuals `e_k = √w_k r_k` and the leverages
/// `h_k = w_k J_kᵀ A⁻¹ J_k` (HC3), in the scaled coordinates of `inverse`
/// (`A⁻¹`); `row(k, out)` writes measurement k's scaled Jacobian row.
fn meat(
    weight: &[f64],
    residuals: &[f64],
    inverse: &DMatrix<f64>,
    row_of: impl Fn(usize, &mut [f64]),
) -> DMatrix<f64> {
    let n = inverse.nrows();
    let mut meat = DMatrix::<f64>::zeros(n, n);
    // One measurement's scaled Jacobian row and A⁻¹ times it, reused.
    let (mut row, mut solved) = (vec![0.0; n], vec![0.0; n]);
    for (r, (&w, &e)) in weight.iter().zip(residuals).enumerate() {
        row_of(r, &mut row);
        for (a, y) in solved.iter_mut().enumerate() {
            *y = (0..n).map(|b| inverse[(a, b)] * row[b]).sum();
        }
        let leverage = w * row.iter().zip(&solved).map(|(x, y)| x * y).sum::<f64>();
        let f = w * e * e / (1.0 - leverage.min(1.0 - 1e-12)).powi(2);
        for a in 0..n {
            for b in 0..n {
                meat[(a, b)] += f * row[a] * row[b];
            }
        }
    }
    meat
}
