//! The grid stage of the free-amplitude fit: the objective at every grid
//! point of the nonlinear parameters, with the linear part (β and the
//! amplitude) in closed form at each, and the grid's basins as the starts
//! of the refinement.
//!
//! Layered models: per (σ/T, n) the weighted inner products of the data,
//! the surface term `S` and the three coefficients of `U` as a quadratic in
//! a (`U = B0 + a B1 + a² B2`, `B0 = B`, `B1 = −B (cos²θi + cos²θs)`,
//! `B2 = B cos²θi cos²θs`) are formed once; every a of the axis is then a
//! 2×2 solve from polynomials in a, with no pass over the measurements.

use super::linear::Moments;
use super::problem::Problem;
use crate::profile::basins;
use rayon::prelude::*;

/// The grid axes of the nonlinear parameters, in the model's values (σ/T,
/// not its logarithm).
#[derive(Debug, Clone, PartialEq)]
pub struct GridAxes {
    /// One axis per nonlinear parameter.
    pub axes: Vec<Vec<f64>>,
}

/// The grid's objective in row-major order over [`GridAxes`].
#[derive(Debug, Clone, PartialEq)]
pub struct GridValues {
    /// Axis lengths.
    pub lens: Vec<usize>,
    /// Objective at each grid point (moments form).
    pub sse: Vec<f64>,
}

impl GridValues {
    /// The axis indices of a flat index.
    pub fn indices(&self, flat: usize) -> Vec<usize> {
        let mut out = vec![0; self.lens.len()];
        let mut rest = flat;
        for (i, &len) in self.lens.iter().enumerate().rev() {
            out[i] = rest % len;
            rest /= len;
        }
        out
    }
}

/// Per (σ/T, n) inner products of the quadratic-in-a form.
struct Quadratic {
    dd: f64,
    ds: f64,
    ss: f64,
    db: [f64; 3],
    sb: [f64; 3],
    /// `bb[i][j] = Σ w B_i B_j`.
    bb: [[f64; 3]; 3],
}

impl Quadratic {
    fn moments(&self, a: f64) -> Moments {
        let pow = [1.0, a, a * a];
        let lin = |v: &[f64; 3]| v[0] + a * v[1] + a * a * v[2];
        let mut uu = 0.0;
        for (i, pi) in pow.iter().enumerate() {
            for (j, pj) in pow.iter().enumerate() {
                uu += pi * pj * self.bb[i][j];
            }
        }
        Moments {
            dd: self.dd,
            ds: self.ds,
            du: lin(&self.db),
            ss: self.ss,
            su: lin(&self.sb),
            uu,
        }
    }
}

/// The objective at every grid point of `axes` (layered: σ/T, n and, for
/// the absorptive models, a; baselines: their two parameters).
pub fn grid_values(problem: &Problem, axes: &GridAxes) -> GridValues {
    let lens: Vec<usize> = axes.axes.iter().map(Vec::len).collect();
    let beta = problem.beta;
    let sse = if problem.basis.has_balance() {
        let basis = &problem.basis;
        let (ci, cs) = basis.cosines();
        let interfaces: Vec<_> = axes.axes[1].iter().map(|&n| basis.interfaces(n)).collect();
        let a_axis: Vec<f64> = axes.axes.get(2).cloned().unwrap_or_else(|| vec![0.0]);
        let w: Vec<f64> = problem.root_weight.iter().map(|r| r * r).collect();
        let d = &problem.data;
        let rows: Vec<Vec<f64>> = axes.axes[0]
            .par_iter()
            .map(|&slope| {
                let s = basis.surface(slope);
                let (mut dd, mut ds, mut ss) = (0.0, 0.0, 0.0);
                for k in 0..d.len() {
                    dd += w[k] * d[k] * d[k];
                    ds += w[k] * d[k] * s[k];
                    ss += w[k] * s[k] * s[k];
                }
                let mut row = Vec::with_capacity(interfaces.len() * a_axis.len());
                for iface in &interfaces {
                    let base = basis.base(slope, iface);
                    let mut q = Quadratic {
                        dd,
                        ds,
                        ss,
                        db: [0.0; 3],
                        sb: [0.0; 3],
                        bb: [[0.0; 3]; 3],
                    };
                    for k in 0..d.len() {
                        let b = [
                            base[k],
                            -base[k] * (ci[k] + cs[k]),
                            base[k] * ci[k] * cs[k],
                        ];
                        for i in 0..3 {
                            q.db[i] += w[k] * d[k] * b[i];
                            q.sb[i] += w[k] * s[k] * b[i];
                            for j in i..3 {
                                q.bb[i][j] += w[k] * b[i] * b[j];
                            }
                        }
                    }
                    for i in 0..3 {
                        for j in 0..i {
                            q.bb[i][j] = q.bb[j][i];
                        }
                    }
                    row.extend(a_axis.iter().map(|&a| q.moments(a).solve(beta).sse));
                }
                row
            })
            .collect();
        rows.concat()
    } else {
        let (outer, inner) = (&axes.axes[0], &axes.axes[1]);
        let rows: Vec<Vec<f64>> = outer
            .par_iter()
            .map(|&x| {
                inner
                    .iter()
                    .map(|&y| {
                        let columns = problem.basis.columns(&[x, y]);
                        problem.moments(&columns).solve(beta).sse
                    })
                    .collect()
            })
            .collect();
        rows.concat()
    };
    GridValues { lens, sse }
}

/// The best point of each of the grid's basins (no axis neighbour lower),
/// best first, at most `most`, as axis indices with their objective.
pub fn grid_starts(values: &GridValues, most: usize) -> Vec<(Vec<usize>, f64)> {
    let near: Vec<(usize, f64)> = values
        .sse
        .iter()
        .copied()
        .enumerate()
        .filter(|(_, e)| e.is_finite())
        .collect();
    basins(&near, &values.lens, most)
        .into_iter()
        .map(|(flat, e)| (values.indices(flat), e))
        .collect()
}
