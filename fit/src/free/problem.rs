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
use super::pool;
use super::sums::{dots, gram, total};
use crate::model::Model;
use crate::scene::Scene;
use laminar_core::f64x4;
use nalgebra::DMatrix;
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

    /// The residuals `D − p S − q U`, unweighted.
    fn misfit(&self, columns: &Columns, linear: &Linear) -> Vec<f64> {
        let Linear { p, q, .. } = *linear;
        let rows = self.data.iter().zip(&columns.s);
        let mut misfit = pool::vector(self.data.len());
        if columns.u.is_empty() {
            misfit.extend(rows.map(|(d, s)| d - p * s));
        } else {
            misfit.extend(rows.zip(&columns.u).map(|((d, s), u)| d - p * s - q * u));
        }
        misfit
    }

    /// The weighted residuals `√w (D − p S − q U)`.
    pub fn residuals(&self, columns: &Columns, linear: &Linear) -> Vec<f64> {
        let mut residuals = self.misfit(columns, linear);
        for (e, r) in residuals.iter_mut().zip(&self.root_weight) {
            *e *= r;
        }
        residuals
    }

    /// The point at `theta` with β in `beta` (the box's, or one value for a
    /// profile of β), and the columns there (what an estimate's prediction
    /// needs).
    pub fn evaluate(&self, theta: &[f64], beta: (f64, f64)) -> (Point, Columns) {
        let columns = self.basis.columns(theta);
        (self.point(theta, &columns, beta), columns)
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
        let linear = self.moments(columns).solve(beta);
        Point {
            theta: theta.to_vec(),
            sse: self.sse(columns, &linear),
            linear,
        }
    }

    /// `Σ w (D − p S − q U)²`: the weighted residuals ([`Problem::residuals`])
    /// dotted with themselves ([`dots`]: the same four partial sums, so the
    /// same bits), without forming them.
    fn sse(&self, columns: &Columns, linear: &Linear) -> f64 {
        let Linear { p, q, .. } = *linear;
        let len = self.data.len();
        let (d, d_tail) = self.data.as_chunks::<4>();
        let (s, s_tail) = columns.s[..len].as_chunks::<4>();
        let (w, w_tail) = self.root_weight[..len].as_chunks::<4>();
        let rows = d.iter().zip(s).zip(w);
        let tail = d_tail.iter().zip(s_tail).zip(w_tail);
        if columns.u.is_empty() {
            // A baseline: q times zero adds nothing, `d − p s − 0` is
            // `d − p s` exactly.
            let zeros = std::iter::repeat(&[0.0; 4]);
            let rows = rows.zip(zeros).map(|(((d, s), w), u)| [d, s, u, w]);
            let tail = tail.map(|((d, s), w)| [*d, *s, 0.0, *w]);
            return weighted_sum_of_squares(rows, tail, (p, q));
        }
        let (u, u_tail) = columns.u[..len].as_chunks::<4>();
        let rows = rows.zip(u).map(|(((d, s), w), u)| [d, s, u, w]);
        let tail = tail.zip(u_tail).map(|(((d, s), w), u)| [*d, *s, *u, *w]);
        weighted_sum_of_squares(rows, tail, (p, q))
    }

    /// The point at `theta` and the Gauss–Newton normal equations of the
    /// variable-projection residual there ([`Normal`]), with respect to the
    /// nonlinear parameters marked in `free`.
    pub fn jacobian(
        &self,
        theta: &[f64],
        beta: (f64, f64),
        held: &Held,
        free: &[bool],
    ) -> (Point, Normal) {
        let (point, evaluated) = self.evaluate_keeping(theta, beta, held);
        let normal = self.jacobian_at(&point, evaluated, beta, free);
        (point, normal)
    }

    /// [`Problem::jacobian`] at a point already evaluated: `point` and
    /// `at`, its columns ([`Problem::evaluate_keeping`]).
    ///
    /// The Jacobian is Golub and Pereyra's: with `F` the weighted columns
    /// whose coefficient moves freely at this point (both inside the cone,
    /// the active ray's mix on its edge, none at c = 0), `P` the projection
    /// onto them, `r` the weighted residuals and `A_j = √w (p ∂_j S + q ∂_j U)`
    /// the derivative at the fixed coefficients,
    ///
    /// `J_j = −(I − P) A_j − F (FᵀF)⁻¹ v_j`, `v_j = (∂_j F)ᵀ r`:
    ///
    /// Kaufman's part, and the term of the coefficients' own change that the
    /// large residuals of a misfitting model make matter. `JᵀJ` and `Jᵀr`
    /// follow from the weighted inner products of the columns, the residuals
    /// and the derivatives (the cross terms vanish, as `(I − P) F = 0`):
    ///
    /// `J_iᵀJ_j = A_iᵀA_j − (FᵀA_i)ᵀ(FᵀF)⁻¹(FᵀA_j) + v_iᵀ(FᵀF)⁻¹v_j`,
    /// `J_jᵀr = −A_jᵀr + ((FᵀA_j) − v_j)ᵀ(FᵀF)⁻¹Fᵀr`,
    ///
    /// so one pass over the measurements ([`gram`]) gives them, and no
    /// column of `J` is formed.
    pub fn jacobian_at(
        &self,
        point: &Point,
        at: Evaluated,
        beta: (f64, f64),
        free: &[bool],
    ) -> Normal {
        let (columns, derivatives) =
            self.basis
                .derivatives_at(&point.theta, &self.domain, false, at, free);
        let Linear { p, q, .. } = point.linear;
        let has_u = !columns.u.is_empty();
        let residuals = self.misfit(&columns, &point.linear);
        // The vectors whose inner products are needed, and where each is:
        // S, U (layered), the residuals, then each derivative that is not
        // zero (∂S is zero in n and a).
        let mut vectors: Vec<&[f64]> = vec![&columns.s];
        fn place<'a>(v: &'a [f64], vectors: &mut Vec<&'a [f64]>) -> Option<usize> {
            (!v.is_empty()).then(|| {
                vectors.push(v);
                vectors.len() - 1
            })
        }
        let u_at = place(&columns.u, &mut vectors);
        let r_at = place(&residuals, &mut vectors).unwrap_or(0);
        let places: Vec<Option<(Option<usize>, Option<usize>)>> = derivatives
            .iter()
            .map(|d| {
                d.as_ref()
                    .map(|d| (place(&d.s, &mut vectors), place(&d.u, &mut vectors)))
            })
            .collect();
        let n = vectors.len();
        let g = gram(&self.weight[..residuals.len()], &vectors);
        drop(vectors);
        pool::release(residuals);
        // A combination of at most two of the vectors, and the inner product
        // of two combinations.
        type Combination = [(Option<usize>, f64); 2];
        let product = |x: &Combination, y: &Combination| -> f64 {
            let mut sum = 0.0;
            for &(a, ca) in x {
                for &(b, cb) in y {
                    if let (Some(a), Some(b)) = (a, b) {
                        sum += ca * cb * g[a * n + b];
                    }
                }
            }
            sum
        };
        let e_r: Combination = [(Some(r_at), 1.0), (None, 0.0)];
        // The free columns as mixes `(weight of S, weight of U)`.
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
        let f: Vec<Combination> = mixes
            .iter()
            .map(|&(ws, wu)| [(Some(0), ws), (u_at, wu)])
            .collect();
        let ff = |l: usize, m: usize| product(&f[l], &f[m]);
        // `(FᵀF)⁻¹` when the free columns are independent (`back`), and the
        // inverse the projection uses: onto the first nonzero column alone
        // when the two are dependent.
        let (projection, back): (Option<[[f64; 2]; 2]>, bool) = match f.len() {
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
        };
        // `xᵀ M y` of two vectors of the free columns' length.
        let form = |m: &[[f64; 2]; 2], x: &[f64; 2], y: &[f64; 2]| -> f64 {
            (0..2)
                .map(|l| x[l] * (0..2).map(|k| m[l][k] * y[k]).sum::<f64>())
                .sum()
        };
        let over_free = |each: &dyn Fn(usize) -> f64| -> [f64; 2] {
            std::array::from_fn(|l| if l < f.len() { each(l) } else { 0.0 })
        };
        let f_r = over_free(&|l| product(&f[l], &e_r));
        // Per parameter: A_j, FᵀA_j and v_j.
        struct Parts {
            a: Combination,
            fa: [f64; 2],
            v: [f64; 2],
        }
        let parts: Vec<Option<Parts>> = places
            .iter()
            .map(|place| {
                let (ds, du) = (*place)?;
                let a = [(ds, p), (du, q)];
                let fa = over_free(&|l| product(&f[l], &a));
                let v = over_free(&|l| {
                    let (ws, wu) = mixes[l];
                    product(&[(ds, ws), (du, wu)], &e_r)
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
            let mut jtr = -product(&pi.a, &e_r);
            if let Some(inverse) = &projection {
                jtr += form(inverse, &pi.fa, &f_r);
                if back {
                    jtr -= form(inverse, &pi.v, &f_r);
                }
            }
            normal.jtr[i] = jtr;
            for (j, pj) in parts.iter().enumerate() {
                let Some(pj) = pj else { continue };
                let mut h = product(&pi.a, &pj.a);
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
}

/// The Gauss–Newton normal equations of the variable-projection residual
/// `r` at one point ([`Problem::jacobian_at`]): zero in the rows and
/// columns of the parameters held.
#[derive(Debug, Clone, PartialEq)]
pub struct Normal {
    /// `JᵀJ`.
    pub jtj: DMatrix<f64>,
    /// `Jᵀr`: half the objective's gradient.
    pub jtr: Vec<f64>,
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

/// `Σ ((d − p s − q u) w)²` over the groups of four `[d, s, u, w]` of
/// `rows`, then the measurements of the last, partial group (`tail`), in
/// order: the same four partial sums as [`dots`], so the same bits as the
/// weighted residuals dotted with themselves.
fn weighted_sum_of_squares<'a>(
    rows: impl Iterator<Item = [&'a [f64; 4]; 4]>,
    tail: impl Iterator<Item = [f64; 4]>,
    (p, q): (f64, f64),
) -> f64 {
    let (p4, q4) = (f64x4::splat(p), f64x4::splat(q));
    let mut acc = f64x4::ZERO;
    for row in rows {
        let [d, s, u, w] = row.map(|v| f64x4::from(*v));
        let e = (d - p4 * s - q4 * u) * w;
        acc += e * e;
    }
    let mut sum = total(acc);
    for [d, s, u, w] in tail {
        let e = (d - p * s - q * u) * w;
        sum += e * e;
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coverage::{noisy_scene, noisy_scene_on, NoiseModel};
    use crate::fitted::ModelParams;
    use crate::free::sums::dot;
    use crate::objective::Objective;
    use crate::synthetic::Noise;

    /// A point's objective is its weighted residuals dotted with
    /// themselves, bit for bit, with weights and without.
    #[test]
    fn the_objective_is_the_residuals_sum_of_squares_to_the_bit() {
        let mut rng = Noise::new(11);
        let layered = ModelParams::Layered {
            slope: 0.4,
            beta: 0.3,
            n: 1.5,
            a: 0.3,
        };
        let cases = [
            (
                Model::Exp,
                layered,
                NoiseModel::Every(0.01),
                [0.3f64.ln(), 1.4, 0.2],
            ),
            (
                Model::Gauss,
                layered,
                NoiseModel::Heteroscedastic {
                    floor: 0.005,
                    relative: 0.02,
                },
                [0.5f64.ln(), 1.7, 0.0],
            ),
        ];
        for (model, truth, noise, theta) in cases {
            // Three measurements fewer: a partial group of four, so the
            // tail's order is checked too.
            let mut angles = crate::synthetic::geometries();
            angles.truncate(angles.len() - 3);
            let scene = noisy_scene_on(angles, model, Objective::Free, truth, noise, &mut rng);
            assert_ne!(scene.len() % 4, 0);
            let bounds = vec![(libm::log(0.02), libm::log(20.0)), (1.0, 2.5), (0.0, 1.0)];
            let problem = Problem::new(
                &scene,
                (model, None),
                (bounds.clone(), bounds),
                vec![(-7.0, 7.0), (1.0, 10.0), (0.0, 1.0)],
                (0.0, 1.0),
            );
            // Points around `theta`: rounding differences in the order of
            // the sums would show at some of them.
            for i in 0..32 {
                let shift = f64::from(i) / 32.0;
                let at = [
                    theta[0] + shift,
                    theta[1] + 0.5 * shift,
                    theta[2] + 0.1 * shift,
                ];
                let (point, columns) = problem.evaluate(&at, problem.beta);
                let r = problem.residuals(&columns, &point.linear);
                assert_eq!(point.sse.to_bits(), dot(&r, &r).to_bits(), "{model} {at:?}");
                assert!(point.sse > 0.0);
            }
        }
    }

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
                let (_, normal) = problem.jacobian(&theta, beta, &held, &free);
                let residuals = |t: &[f64]| {
                    let c = problem.basis.columns(t);
                    let l = problem.moments(&c).solve(beta);
                    problem.residuals(&c, &l)
                };
                let r = residuals(&theta);
                // J by central differences of the residuals.
                let jac: Vec<Vec<f64>> = (0..3)
                    .map(|j| {
                        let h = 1e-6;
                        let (mut up, mut down) = (theta, theta);
                        up[j] += h;
                        down[j] -= h;
                        let (ru, rd) = (residuals(&up), residuals(&down));
                        ru.iter()
                            .zip(&rd)
                            .map(|(u, d)| (u - d) / (2.0 * h))
                            .collect()
                    })
                    .collect();
                let norms: Vec<f64> = jac.iter().map(|c| dot(c, c).sqrt()).collect();
                let r_norm = dot(&r, &r).sqrt();
                for i in 0..3 {
                    let want = dot(&jac[i], &r);
                    let err = (normal.jtr[i] - want).abs();
                    assert!(
                        err <= 1e-5 * norms[i] * r_norm,
                        "{model} θ {theta:?} β {beta:?} Jᵀr[{i}] {} against {want}",
                        normal.jtr[i]
                    );
                    for j in 0..3 {
                        let want = dot(&jac[i], &jac[j]);
                        let err = (normal.jtj[(i, j)] - want).abs();
                        assert!(
                            err <= 1e-5 * norms[i] * norms[j],
                            "{model} θ {theta:?} β {beta:?} JᵀJ[{i}, {j}] {} against {want}",
                            normal.jtj[(i, j)]
                        );
                    }
                }
            }
        }
    }
}
