//! The Gauss–Newton normal equations of the variable-projection residual
//! at one point (Golub and Pereyra), from the weighted inner products of
//! the columns, the residuals and the derivatives, without forming a
//! column of the Jacobian.
//!
//! With `F` the weighted columns whose coefficient moves freely at the
//! point (both inside the cone, the active ray's mix on its edge, none at
//! c = 0), `P` the projection onto them, `r` the weighted residuals and
//! `A_j = √w (p ∂_j S + q ∂_j U)` the derivative at the fixed coefficients,
//!
//! `J_j = −(I − P) A_j − F (FᵀF)⁻¹ v_j`, `v_j = (∂_j F)ᵀ r`:
//!
//! Kaufman's part, and the term of the coefficients' own change that the
//! large residuals of a misfitting model make matter. The cross terms
//! vanish, as `(I − P) F = 0`, so
//!
//! `J_iᵀJ_j = A_iᵀA_j − (FᵀA_i)ᵀ(FᵀF)⁻¹(FᵀA_j) + v_iᵀ(FᵀF)⁻¹v_j`,
//! `J_jᵀr = −A_jᵀr + ((FᵀA_j) − v_j)ᵀ(FᵀF)⁻¹Fᵀr`,
//!
//! and one pass over the measurements ([`gram`]) gives them.

use super::linear::Linear;
use super::model::Columns;
use super::sums::gram;
use nalgebra::DMatrix;

/// The Gauss–Newton normal equations of the variable-projection residual
/// `r` at one point: zero in the rows and columns of the parameters held.
#[derive(Debug, Clone, PartialEq)]
pub struct Normal {
    /// `JᵀJ`.
    pub jtj: DMatrix<f64>,
    /// `Jᵀr`: half the objective's gradient.
    pub jtr: Vec<f64>,
}

/// A combination of at most two of the vectors of [`Products`]: each its
/// place (`None`: a zero vector) and coefficient.
type Combination = [(Option<usize>, f64); 2];

/// The weighted inner products of `S`, `U`, the residuals and each wanted
/// derivative's nonzero columns, and where each vector is among them.
struct Products {
    gram: Vec<f64>,
    /// Number of vectors.
    n: usize,
    u_at: Option<usize>,
    r_at: usize,
    /// Per parameter: the places of `∂S` and `∂U` (`None` when held).
    places: Vec<Option<(Option<usize>, Option<usize>)>>,
}

impl Products {
    fn new(
        weight: &[f64],
        columns: &Columns,
        residuals: &[f64],
        derivatives: &[Option<Columns>],
    ) -> Self {
        // S, U (when the model has it), the residuals, then each derivative
        // that is not zero (∂S is zero in n and a).
        let mut vectors: Vec<&[f64]> = vec![&columns.s];
        fn place<'a>(v: &'a [f64], vectors: &mut Vec<&'a [f64]>) -> Option<usize> {
            (!v.is_empty()).then(|| {
                vectors.push(v);
                vectors.len() - 1
            })
        }
        let u_at = place(&columns.u, &mut vectors);
        let r_at = place(residuals, &mut vectors).unwrap_or(0);
        let places = derivatives
            .iter()
            .map(|d| {
                d.as_ref()
                    .map(|d| (place(&d.s, &mut vectors), place(&d.u, &mut vectors)))
            })
            .collect();
        Self {
            gram: gram(weight, &vectors),
            n: vectors.len(),
            u_at,
            r_at,
            places,
        }
    }

    /// The inner product of two combinations.
    fn product(&self, x: &Combination, y: &Combination) -> f64 {
        let mut sum = 0.0;
        for &(a, ca) in x {
            for &(b, cb) in y {
                if let (Some(a), Some(b)) = (a, b) {
                    sum += ca * cb * self.gram[a * self.n + b];
                }
            }
        }
        sum
    }
}

/// The columns whose coefficient moves freely at a point, as mixes
/// `(weight of S, weight of U)`: none at c = 0, `S` alone for a one-column
/// model, both inside β's box, the active ray's mix on its edge.
fn free_mixes(linear: &Linear, has_u: bool, beta: (f64, f64)) -> Vec<(f64, f64)> {
    if linear.amplitude() <= 0.0 {
        return Vec::new();
    }
    if !has_u {
        return vec![(1.0, 0.0)];
    }
    let b = linear.beta(beta.0);
    if beta.0 < beta.1 && b > beta.0 && b < beta.1 {
        vec![(1.0, 0.0), (0.0, 1.0)]
    } else {
        vec![(1.0 - b, b)]
    }
}

/// `(FᵀF)⁻¹` of the free columns' Gram matrix `ff` when they are
/// independent (`true`), else the inverse the projection uses: onto the
/// first nonzero column alone when the two are dependent (`false`).
fn inverse(count: usize, ff: impl Fn(usize, usize) -> f64) -> (Option<[[f64; 2]; 2]>, bool) {
    match count {
        0 => (None, false),
        1 => {
            let a = ff(0, 0);
            ((a > 0.0).then(|| [[1.0 / a, 0.0], [0.0, 0.0]]), a > 0.0)
        }
        _ => {
            let [a, b, d] = [ff(0, 0), ff(0, 1), ff(1, 1)];
            let det = a * d - b * b;
            if det > 1e-12 * a * d {
                (Some([[d / det, -b / det], [-b / det, a / det]]), true)
            } else if a > 0.0 {
                (Some([[1.0 / a, 0.0], [0.0, 0.0]]), false)
            } else {
                ((d > 0.0).then(|| [[0.0, 0.0], [0.0, 1.0 / d]]), false)
            }
        }
    }
}

/// `xᵀ M y` of two vectors of the free columns' length.
fn form(m: &[[f64; 2]; 2], x: &[f64; 2], y: &[f64; 2]) -> f64 {
    (0..2)
        .map(|l| x[l] * (0..2).map(|k| m[l][k] * y[k]).sum::<f64>())
        .sum()
}

/// One parameter's `A_j`, `FᵀA_j` and `v_j`.
struct Parts {
    a: Combination,
    fa: [f64; 2],
    v: [f64; 2],
}

/// The normal equations at a point with coefficients `linear` and β's box
/// `beta`, from its columns, weighted residuals' unweighted misfit
/// `residuals` and the derivatives with respect to each parameter (`None`
/// for a held one), with the weights `weight`.
pub fn normal_equations(
    weight: &[f64],
    (columns, residuals, derivatives): (&Columns, &[f64], &[Option<Columns>]),
    linear: &Linear,
    beta: (f64, f64),
) -> Normal {
    let g = Products::new(weight, columns, residuals, derivatives);
    let Linear { p, q, .. } = *linear;
    let e_r: Combination = [(Some(g.r_at), 1.0), (None, 0.0)];
    let mixes = free_mixes(linear, !columns.u.is_empty(), beta);
    let f: Vec<Combination> = mixes
        .iter()
        .map(|&(ws, wu)| [(Some(0), ws), (g.u_at, wu)])
        .collect();
    let (projection, back) = inverse(f.len(), |l, m| g.product(&f[l], &f[m]));
    let over_free = |each: &dyn Fn(usize) -> f64| -> [f64; 2] {
        std::array::from_fn(|l| if l < f.len() { each(l) } else { 0.0 })
    };
    let f_r = over_free(&|l| g.product(&f[l], &e_r));
    let parts: Vec<Option<Parts>> = g
        .places
        .iter()
        .map(|place| {
            let (ds, du) = (*place)?;
            let a = [(ds, p), (du, q)];
            let fa = over_free(&|l| g.product(&f[l], &a));
            let v = over_free(&|l| {
                let (ws, wu) = mixes[l];
                g.product(&[(ds, ws), (du, wu)], &e_r)
            });
            Some(Parts { a, fa, v })
        })
        .collect();
    let m = parts.len();
    let mut normal = Normal {
        jtj: DMatrix::zeros(m, m),
        jtr: vec![0.0; m],
    };
    for (i, pi) in parts.iter().enumerate() {
        let Some(pi) = pi else { continue };
        let mut jtr = -g.product(&pi.a, &e_r);
        if let Some(inverse) = &projection {
            jtr += form(inverse, &pi.fa, &f_r);
            if back {
                jtr -= form(inverse, &pi.v, &f_r);
            }
        }
        normal.jtr[i] = jtr;
        for (j, pj) in parts.iter().enumerate() {
            let Some(pj) = pj else { continue };
            let mut h = g.product(&pi.a, &pj.a);
            if let Some(inverse) = &projection {
                h -= form(inverse, &pi.fa, &pj.fa);
                if back {
                    h += form(inverse, &pi.v, &pj.v);
                }
            }
            normal.jtj[(i, j)] = h;
        }
    }
    normal
}
