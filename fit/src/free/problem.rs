//! The weighted free-amplitude objective of one (scene, model, box)
//! (docs/conventions.md §4b):
//!
//! `F(θ) = min over c ≥ 0, β ∈ box of Σ_k w_k (D_k − c M_k(θ, β))²`,
//!
//! `M = (1 − β) S + β U` (eq. 8's raw mix) for the layered models and
//! `M = L` for the baselines, `w_k = 1/σ_k²` when the scene has
//! uncertainties and 1 otherwise. `θ` are the nonlinear parameters in the
//! internal coordinates of [`Basis`]; the linear part is solved in closed
//! form ([`crate::free::linear`]).

use super::basis::{Basis, Columns, Evaluated, Held};
use super::linear::{Linear, Moments};
use super::sums::{dot, dots, total};
use crate::model::Model;
use crate::scene::Scene;
use laminar_core::f64x4;
use std::sync::Arc;

/// A `[lo, hi]` range per parameter.
pub type Ranges = Vec<(f64, f64)>;

/// One evaluated point.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    /// Nonlinear parameters (internal coordinates).
    pub theta: Vec<f64>,
    /// The linear coefficients.
    pub linear: Linear,
    /// `Σ w r²` from the residuals.
    pub sse: f64,
}

/// The objective of one fit.
#[derive(Debug, Clone)]
pub struct Problem {
    /// The basis at the scene's measurements (shared by the sets of a
    /// batch on one geometry).
    pub basis: Arc<Basis>,
    /// `D_k`.
    pub data: Vec<f64>,
    /// `√w_k`.
    pub root_weight: Vec<f64>,
    /// `w_k`.
    pub weight: Vec<f64>,
    /// `w_k D_k`.
    pub weighted_data: Vec<f64>,
    /// `Σ w D²`.
    pub dd: f64,
    /// True when the weights come from the scene's uncertainties.
    pub weighted: bool,
    /// The box of each nonlinear parameter, internal coordinates.
    pub bounds: Vec<(f64, f64)>,
    /// The same box in the parameters' own units, exactly as the user gave
    /// it (`ln` and `exp` do not round-trip: σ/T's ends are kept here).
    pub reported: Vec<(f64, f64)>,
    /// The domain of each nonlinear parameter (for difference steps).
    pub domain: Vec<(f64, f64)>,
    /// The box of β (`(0, 0)` for a baseline).
    pub beta: (f64, f64),
}

impl Problem {
    /// The objective of `model` on `scene` in the box `bounds` (nonlinear
    /// parameters, internal coordinates, with `reported`, the same box in
    /// the parameters' units) and `beta`, on `basis`: the model's basis at
    /// the scene's measurements (`None` to build it).
    pub fn new(
        scene: &Scene,
        (model, basis): (Model, Option<Arc<Basis>>),
        (bounds, reported): (Ranges, Ranges),
        domain: Vec<(f64, f64)>,
        beta: (f64, f64),
    ) -> Self {
        let basis = basis.unwrap_or_else(|| Arc::new(Basis::new(model, scene.angles())));
        let (root_weight, weighted) = match scene.sigma() {
            Some(sigma) => (sigma.iter().map(|s| 1.0 / s).collect(), true),
            None => (vec![1.0; scene.len()], false),
        };
        let beta = if basis.has_balance() {
            beta
        } else {
            (0.0, 0.0)
        };
        let data = scene.data().to_vec();
        let weight: Vec<f64> = root_weight.iter().map(|r| r * r).collect();
        let weighted_data: Vec<f64> = weight.iter().zip(&data).map(|(w, d)| w * d).collect();
        let [dd] = dots(&weighted_data, [&data]);
        Self {
            basis,
            data,
            root_weight,
            weight,
            weighted_data,
            dd,
            weighted,
            bounds,
            reported,
            domain,
            beta,
        }
    }

    /// Number of nonlinear parameters.
    pub fn dim(&self) -> usize {
        self.bounds.len()
    }

    /// Number of fitted parameters: the nonlinear ones, the amplitude and,
    /// for the layered models, β.
    pub fn parameter_count(&self) -> usize {
        self.dim() + 1 + usize::from(self.basis.has_balance())
    }

    /// The weighted moments of `columns`.
    pub fn moments(&self, columns: &Columns) -> Moments {
        let (s, u) = (&columns.s[..], &columns.u[..]);
        if u.is_empty() {
            let [ds] = dots(&self.weighted_data, [s]);
            let [ss, _, _] = squares(&self.weight, s, s);
            return Moments {
                dd: self.dd,
                ds,
                ss,
                ..Moments::default()
            };
        }
        let [ds, du] = dots(&self.weighted_data, [s, u]);
        let [ss, su, uu] = squares(&self.weight, s, u);
        Moments {
            dd: self.dd,
            ds,
            du,
            ss,
            su,
            uu,
        }
    }

    /// The weighted residuals `√w (D − p S − q U)`.
    pub fn residuals(&self, columns: &Columns, linear: &Linear) -> Vec<f64> {
        let Linear { p, q, .. } = *linear;
        let rows = self.root_weight.iter().zip(&self.data).zip(&columns.s);
        if columns.u.is_empty() {
            rows.map(|((r, d), s)| r * (d - p * s)).collect()
        } else {
            rows.zip(&columns.u)
                .map(|(((r, d), s), u)| r * (d - p * s - q * u))
                .collect()
        }
    }

    /// `√w (a S + b U)` of two columns of the measurements (`U` empty for a
    /// baseline: `√w a S`).
    fn weighted_mix(&self, s: &[f64], u: &[f64], (a, b): (f64, f64)) -> Vec<f64> {
        let rows = self.root_weight.iter().zip(s);
        if u.is_empty() {
            rows.map(|(r, s)| r * (a * s)).collect()
        } else {
            rows.zip(u).map(|((r, s), u)| r * (a * s + b * u)).collect()
        }
    }

    /// The point at `theta` with β in `beta` (the box's, or one value for a
    /// profile of β).
    pub fn evaluate(&self, theta: &[f64], beta: (f64, f64)) -> Point {
        let columns = self.basis.columns(theta);
        self.point(theta, &columns, beta)
    }

    /// [`Problem::evaluate`], keeping what [`Problem::jacobian_at`] needs,
    /// and reusing what `held` keeps.
    pub fn evaluate_keeping(
        &self,
        theta: &[f64],
        beta: (f64, f64),
        held: &Held,
    ) -> (Point, Evaluated) {
        let evaluated = self.basis.evaluate_held(theta, held);
        (self.point(theta, &evaluated.columns, beta), evaluated)
    }

    /// The point at `theta` from its columns.
    pub fn point(&self, theta: &[f64], columns: &Columns, beta: (f64, f64)) -> Point {
        self.point_and_residuals(theta, columns, beta).0
    }

    /// [`Problem::point`] and the weighted residuals its objective sums.
    fn point_and_residuals(
        &self,
        theta: &[f64],
        columns: &Columns,
        beta: (f64, f64),
    ) -> (Point, Vec<f64>) {
        let linear = self.moments(columns).solve(beta);
        let residuals = self.residuals(columns, &linear);
        let sse = dot(&residuals, &residuals);
        let point = Point {
            theta: theta.to_vec(),
            linear,
            sse,
        };
        (point, residuals)
    }

    /// The point at `theta`, its weighted residuals and the Jacobian of the
    /// variable-projection residual with respect to the nonlinear
    /// parameters (Golub and Pereyra's: the derivative at the fixed linear
    /// coefficients projected off the columns whose coefficient is free,
    /// plus the term of the coefficients' own change), one column per
    /// parameter marked in `free` (empty for the others).
    pub fn jacobian(
        &self,
        theta: &[f64],
        beta: (f64, f64),
        held: &Held,
        free: &[bool],
    ) -> (Point, Vec<f64>, Vec<Vec<f64>>) {
        self.jacobian_at(theta, beta, self.basis.evaluate_held(theta, held), free)
    }

    /// [`Problem::jacobian`] at a point already evaluated.
    pub fn jacobian_at(
        &self,
        theta: &[f64],
        beta: (f64, f64),
        at: Evaluated,
        free: &[bool],
    ) -> (Point, Vec<f64>, Vec<Vec<f64>>) {
        let (columns, derivatives) =
            self.basis
                .derivatives_at(theta, &self.domain, false, at, free);
        let (point, residuals) = self.point_and_residuals(theta, &columns, beta);
        let Linear { p, q, .. } = point.linear;
        let has_u = !columns.u.is_empty();
        // The columns whose coefficient moves freely at this point: both
        // inside the cone, the active ray's mix on its edge, none at c = 0;
        // as mixes `(weight of S, weight of U)` of the two columns.
        let mixes: Vec<(f64, f64)> = if point.linear.amplitude() <= 0.0 {
            Vec::new()
        } else if !has_u {
            vec![(1.0, 0.0)]
        } else {
            let b = point.linear.beta(beta.0);
            if beta.0 < beta.1 && b > beta.0 && b < beta.1 {
                vec![(1.0, 0.0), (0.0, 1.0)]
            } else {
                vec![(1.0 - b, b)]
            }
        };
        let free: Vec<Vec<f64>> = mixes
            .iter()
            .map(|&m| self.weighted_mix(&columns.s, &columns.u, m))
            .collect();
        // `(FᵀF)⁻¹` of the free columns F, when they are independent.
        let gram_inverse: Option<[[f64; 2]; 2]> = match free.as_slice() {
            [] => None,
            [f] => {
                let g = dot(f, f);
                (g > 0.0).then(|| [[1.0 / g, 0.0], [0.0, 0.0]])
            }
            [f, h] => {
                let [a, b, d] = [dot(f, f), dot(f, h), dot(h, h)];
                let det = a * d - b * b;
                (det > 1e-12 * a * d).then(|| [[d / det, -b / det], [-b / det, a / det]])
            }
            _ => unreachable!("at most two columns"),
        };
        let basis = orthonormal(&free);
        let k = residuals.len();
        // `√w r`, against which `(∂F)ᵀ r = Σ √w (ws ∂S + wu ∂U) r` is formed.
        let weighted_residuals: Vec<f64> = residuals
            .iter()
            .zip(&self.root_weight)
            .map(|(r, w)| r * w)
            .collect();
        // Up to two basis vectors and two free columns, zeros for those
        // there are not. The basis vectors times √w give their products
        // with a column `−√w (p ∂S + q ∂U)` from ∂S and ∂U, in the same
        // pass as the products with `√w r`.
        let zeros = vec![0.0; k];
        fn two<'a>(v: &'a [Vec<f64>], zeros: &'a [f64]) -> [&'a [f64]; 2] {
            [0, 1].map(|i| v.get(i).map_or(zeros, |x| &x[..zeros.len()]))
        }
        let rooted: Vec<Vec<f64>> = basis
            .iter()
            .map(|e| {
                e.iter()
                    .zip(&self.root_weight)
                    .map(|(e, w)| e * w)
                    .collect()
            })
            .collect();
        let [r0, r1] = two(&rooted, &zeros);
        let against = [r0, r1, &weighted_residuals[..]];
        let ([e0, e1], [f0, f1]) = (two(&basis, &zeros), two(&free, &zeros));
        let w = &self.root_weight[..k];
        let jac = derivatives
            .iter()
            .map(|d| {
                let Some(d) = d else {
                    return Vec::new();
                };
                let ds = &d.s[..k];
                let du = if has_u { &d.u[..k] } else { &zeros[..k] };
                let sums_s = dots(ds, against);
                let sums_u = if has_u { dots(du, against) } else { [0.0; 3] };
                // Kaufman's part: −P⊥ (∂Φ c) of the derivative at the fixed
                // coefficients `−√w (∂Φ c)`, projected off the orthonormal
                // basis of the free columns.
                let along = [0, 1].map(|i| -(p * sums_s[i] + q * sums_u[i]));
                // Golub–Pereyra's second part: −F (FᵀF)⁻¹ (∂F)ᵀ r, which the
                // large residuals of a misfitting model make matter.
                let back = match &gram_inverse {
                    Some(inverse) => {
                        let v: Vec<f64> = mixes
                            .iter()
                            .map(|&(ws, wu)| ws * sums_s[2] + wu * sums_u[2])
                            .collect();
                        [0, 1].map(|i| (0..v.len()).map(|l| inverse[i][l] * v[l]).sum())
                    }
                    None => [0.0; 2],
                };
                (0..k)
                    .map(|i| {
                        w[i] * (-p * ds[i] - q * du[i])
                            - along[0] * e0[i]
                            - along[1] * e1[i]
                            - back[0] * f0[i]
                            - back[1] * f1[i]
                    })
                    .collect()
            })
            .collect();
        (point, residuals, jac)
    }
}

/// `Σ w s²`, `Σ w s u` and `Σ w u²`, four partial sums each in the fixed
/// order of [`dots`].
fn squares(w: &[f64], s: &[f64], u: &[f64]) -> [f64; 3] {
    let len = w.len();
    let (ws, w_tail) = w.as_chunks::<4>();
    let (ss, s_tail) = s[..len].as_chunks::<4>();
    let (us, u_tail) = u[..len].as_chunks::<4>();
    let mut acc = [f64x4::ZERO; 3];
    for ((&wk, &sk), &uk) in ws.iter().zip(ss).zip(us) {
        let (wk, sk, uk) = (f64x4::from(wk), f64x4::from(sk), f64x4::from(uk));
        let wsk = wk * sk;
        acc[0] += wsk * sk;
        acc[1] += wsk * uk;
        acc[2] += wk * uk * uk;
    }
    let mut out = acc.map(total);
    for ((w, s), u) in w_tail.iter().zip(s_tail).zip(u_tail) {
        let ws = w * s;
        out[0] += ws * s;
        out[1] += ws * u;
        out[2] += w * u * u;
    }
    out
}

/// Gram–Schmidt (twice) of a few columns, dropping any that are
/// dependent on the others.
fn orthonormal(columns: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let mut out: Vec<Vec<f64>> = Vec::new();
    for v in columns {
        let mut v = v.clone();
        let norm0 = dot(&v, &v).sqrt();
        for _ in 0..2 {
            for e in &out {
                let c = dot(e, &v);
                for (x, y) in v.iter_mut().zip(e) {
                    *x -= c * y;
                }
            }
        }
        let norm = dot(&v, &v).sqrt();
        if norm > 1e-10 * norm0 && norm > 0.0 {
            v.iter_mut().for_each(|x| *x /= norm);
            out.push(v);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coverage::{noisy_scene, NoiseModel};
    use crate::fitted::ModelParams;
    use crate::objective::Objective;
    use crate::synthetic::Noise;

    #[test]
    fn the_jacobian_is_the_derivative_of_the_residuals() {
        let mut rng = Noise::new(7);
        for model in [Model::Exp, Model::Gauss] {
            let truth = ModelParams::Layered {
                slope: 0.4,
                beta: 0.3,
                n: 1.5,
                a: 0.3,
            };
            let scene = noisy_scene(
                model,
                Objective::Free,
                truth,
                NoiseModel::Every(0.01),
                &mut rng,
            );
            let bounds = vec![(libm::log(0.02), libm::log(20.0)), (1.0, 2.5), (0.0, 1.0)];
            let problem = Problem::new(
                &scene,
                (model, None),
                (bounds.clone(), bounds.clone()),
                vec![(-7.0, 7.0), (1.0, 10.0), (0.0, 1.0)],
                (0.0, 1.0),
            );
            let free = [true; 3];
            // Near the truth, far from it (large residuals), and with β held.
            for (theta, beta) in [
                ([libm::log(0.45), 1.4, 0.35], (0.0, 1.0)),
                ([libm::log(0.3), 1.2, 0.1], (0.0, 1.0)),
                ([libm::log(1.5), 2.0, 0.7], (0.0, 1.0)),
                ([libm::log(0.4), 1.6, 0.2], (0.05, 0.05)),
                ([libm::log(0.3), 1.2, 0.4], (0.6, 0.6)),
            ] {
                let held = problem.basis.held(&theta, &free);
                let (_, _, jac) = problem.jacobian(&theta, beta, &held, &free);
                let residuals = |t: &[f64]| {
                    let c = problem.basis.columns(t);
                    let l = problem.moments(&c).solve(beta);
                    problem.residuals(&c, &l)
                };
                for j in 0..3 {
                    let h = 1e-6;
                    let (mut up, mut down) = (theta, theta);
                    up[j] += h;
                    down[j] -= h;
                    let (ru, rd) = (residuals(&up), residuals(&down));
                    let fd: Vec<f64> = ru
                        .iter()
                        .zip(&rd)
                        .map(|(u, d)| (u - d) / (2.0 * h))
                        .collect();
                    let scale = dot(&fd, &fd).sqrt().max(dot(&jac[j], &jac[j]).sqrt());
                    let diff: Vec<f64> = fd.iter().zip(&jac[j]).map(|(a, b)| a - b).collect();
                    let err = dot(&diff, &diff).sqrt();
                    assert!(
                        err <= 1e-5 * scale,
                        "{model} θ {theta:?} β {beta:?} parameter {j}: |J − FD| = {err:e} of {scale:e}"
                    );
                }
            }
        }
    }
}
