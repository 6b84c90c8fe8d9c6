//! The weighted free-amplitude objective of one (scene, model, box)
//! (docs/conventions.md §4b):
//!
//! `F(θ) = min over c ≥ 0, β ∈ box of Σ_k w_k (D_k − c M_k(θ, β))²`,
//!
//! `M = (1 − β) S + β U` (eq. 8's raw mix) for the layered models and
//! `M = L` for the baselines, `w_k = 1/σ_k²` when the scene has
//! uncertainties and 1 otherwise. `θ` are the nonlinear parameters in the
//! internal coordinates of the model's table ([`FreeModel::table`]); the
//! linear part is solved in closed form ([`crate::free::linear`]).

use super::jacobian::{normal_equations, Normal};
use super::linear::{Linear, Moments};
use super::model::{Columns, Evaluated, FreeModel};
use super::pool;
use super::sums::{dots, total};
use crate::model::Model;
use crate::scene::Scene;
use crate::simd;
use laminar_brdf_core::simd::{Kernel, Lane4};
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

/// The objective of one fit of the model `M`.
#[derive(Debug)]
pub struct Problem<M> {
    /// The model at the scene's measurements (shared by the sets of a
    /// batch on one geometry).
    pub model: Arc<M>,
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

impl<M> Clone for Problem<M> {
    fn clone(&self) -> Self {
        Self {
            model: Arc::clone(&self.model),
            data: self.data.clone(),
            root_weight: self.root_weight.clone(),
            weight: self.weight.clone(),
            weighted_data: self.weighted_data.clone(),
            dd: self.dd,
            weighted: self.weighted,
            bounds: self.bounds.clone(),
            reported: self.reported.clone(),
            domain: self.domain.clone(),
            beta: self.beta,
        }
    }
}

impl<M: FreeModel> Problem<M> {
    /// The objective of `model` on `scene` in the box `bounds` (nonlinear
    /// parameters, internal coordinates, with `reported`, the same box in
    /// the parameters' units) and `beta`, on `built`: the model at the
    /// scene's measurements (`None` to build it).
    pub fn new(
        scene: &Scene,
        (model, built): (Model, Option<Arc<M>>),
        (bounds, reported): (Ranges, Ranges),
        domain: Vec<(f64, f64)>,
        beta: (f64, f64),
    ) -> Self {
        let model = built.unwrap_or_else(|| Arc::new(M::new(model, scene.angles())));
        let (root_weight, weighted) = match scene.weights() {
            Some((sigma, known)) => (sigma.iter().map(|s| 1.0 / s).collect(), known),
            None => (vec![1.0; scene.len()], false),
        };
        let beta = if model.has_balance() {
            beta
        } else {
            (0.0, 0.0)
        };
        let data = scene.data().to_vec();
        let weight: Vec<f64> = root_weight.iter().map(|r| r * r).collect();
        let weighted_data: Vec<f64> = weight.iter().zip(&data).map(|(w, d)| w * d).collect();
        let [dd] = dots(&weighted_data, [&data]);
        Self {
            model,
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
        self.dim() + 1 + usize::from(self.model.has_balance())
    }

    /// Every nonlinear parameter free.
    pub fn all_free(&self) -> Vec<bool> {
        self.model.table().all_free()
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
        let columns = self.model.columns(theta);
        (self.point(theta, &columns, beta), columns)
    }

    /// [`Problem::evaluate`], keeping what [`Problem::jacobian_at`] needs,
    /// and reusing what `held` keeps.
    pub fn evaluate_keeping(
        &self,
        theta: &[f64],
        beta: (f64, f64),
        held: &M::Held,
    ) -> (Point, Evaluated<M::Kept>) {
        let evaluated = self.model.evaluate(theta, held);
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
        simd::run(WeightedSquares {
            d: &self.data,
            s: &columns.s[..len],
            // A baseline: q times zero adds nothing, `d − p s − 0` is
            // `d − p s` exactly.
            u: (!columns.u.is_empty()).then(|| &columns.u[..len]),
            root_weight: &self.root_weight[..len],
            p,
            q,
        })
    }

    /// The point at `theta` and the Gauss–Newton normal equations of the
    /// variable-projection residual there ([`Normal`]), with respect to the
    /// nonlinear parameters marked in `free`.
    pub fn jacobian(
        &self,
        theta: &[f64],
        beta: (f64, f64),
        held: &M::Held,
        free: &[bool],
    ) -> (Point, Normal) {
        let (point, evaluated) = self.evaluate_keeping(theta, beta, held);
        let normal = self.jacobian_at(&point, evaluated, beta, free);
        (point, normal)
    }

    /// [`Problem::jacobian`] at a point already evaluated: `point` and
    /// `at`, its columns ([`Problem::evaluate_keeping`]); the Jacobian is
    /// Golub and Pereyra's ([`super::jacobian`]).
    pub fn jacobian_at(
        &self,
        point: &Point,
        at: Evaluated<M::Kept>,
        beta: (f64, f64),
        free: &[bool],
    ) -> Normal {
        let (columns, derivatives) =
            self.model
                .derivatives_at(&point.theta, &self.domain, false, at, free);
        let residuals = self.misfit(&columns, &point.linear);
        let weight = &self.weight[..residuals.len()];
        let normal = normal_equations(
            weight,
            (&columns, &residuals, &derivatives),
            &point.linear,
            beta,
        );
        pool::release(residuals);
        normal
    }
}

/// `Σ w s²`, `Σ w s u` and `Σ w u²`, four partial sums each in the fixed
/// order of [`dots`].
fn squares(w: &[f64], s: &[f64], u: &[f64]) -> [f64; 3] {
    simd::run(Squares { w, s, u })
}

/// The pass of [`squares`].
struct Squares<'a> {
    w: &'a [f64],
    s: &'a [f64],
    u: &'a [f64],
}

impl Kernel for Squares<'_> {
    type Output = [f64; 3];

    #[inline(always)]
    fn run<L: Lane4>(self) -> [f64; 3] {
        let Self { w, s, u } = self;
        let len = w.len();
        let (ws, w_tail) = w.as_chunks::<4>();
        let (ss, s_tail) = s[..len].as_chunks::<4>();
        let (us, u_tail) = u[..len].as_chunks::<4>();
        let mut acc = [L::zero(); 3];
        for ((&wk, &sk), &uk) in ws.iter().zip(ss).zip(us) {
            let (wk, sk, uk) = (L::from_array(wk), L::from_array(sk), L::from_array(uk));
            let wsk = wk * sk;
            acc[0] += wsk * sk;
            acc[1] += wsk * uk;
            acc[2] += wk * uk * uk;
        }
        let mut out = [total(acc[0]), total(acc[1]), total(acc[2])];
        for ((w, s), u) in w_tail.iter().zip(s_tail).zip(u_tail) {
            let ws = w * s;
            out[0] += ws * s;
            out[1] += ws * u;
            out[2] += w * u * u;
        }
        out
    }
}

/// `Σ ((d − p s − q u) w)²` over the measurements (`u` zero when absent,
/// `w` the root weights): groups of four, then the last, partial group, in
/// order: the same four partial sums as [`dots`], so the same bits as the
/// weighted residuals dotted with themselves.
struct WeightedSquares<'a> {
    d: &'a [f64],
    s: &'a [f64],
    u: Option<&'a [f64]>,
    root_weight: &'a [f64],
    p: f64,
    q: f64,
}

impl Kernel for WeightedSquares<'_> {
    type Output = f64;

    #[inline(always)]
    fn run<L: Lane4>(self) -> f64 {
        let Self {
            d,
            s,
            u,
            root_weight,
            p,
            q,
        } = self;
        let (d4, d_tail) = d.as_chunks::<4>();
        let (s4, s_tail) = s.as_chunks::<4>();
        let (w4, w_tail) = root_weight.as_chunks::<4>();
        let u4 = u.map(|u| u.as_chunks::<4>());
        let (p4, q4) = (L::splat(p), L::splat(q));
        let mut acc = L::zero();
        for i in 0..d4.len() {
            let u = match u4 {
                Some((u, _)) => L::from_array(u[i]),
                None => L::zero(),
            };
            let (d, s, w) = (
                L::from_array(d4[i]),
                L::from_array(s4[i]),
                L::from_array(w4[i]),
            );
            let e = (d - p4 * s - q4 * u) * w;
            acc += e * e;
        }
        let mut sum = total(acc);
        for i in 0..d_tail.len() {
            let u = match u4 {
                Some((_, u)) => u[i],
                None => 0.0,
            };
            let e = (d_tail[i] - p * s_tail[i] - q * u) * w_tail[i];
            sum += e * e;
        }
        sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coverage::{noisy_scene, noisy_scene_on, NoiseModel};
    use crate::fitted::ModelParams;
    use crate::free::model::LayeredModel;
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
            sub_slope: None,
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
            let problem = Problem::<LayeredModel>::new(
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
                // σ/T's logarithm, n and a moved by their own steps.
                let steps = [1.0, 0.5, 0.1];
                let at: [f64; 3] = std::array::from_fn(|j| theta[j] + steps[j] * shift);
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
                sub_slope: None,
            };
            let scene = noisy_scene(
                model,
                Objective::Free,
                truth,
                NoiseModel::Every(0.01),
                &mut rng,
            );
            let bounds = vec![(libm::log(0.02), libm::log(20.0)), (1.0, 2.5), (0.0, 1.0)];
            let problem = Problem::<LayeredModel>::new(
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
                let held = problem.model.held(&theta, &free);
                let (_, normal) = problem.jacobian(&theta, beta, &held, &free);
                let residuals = |t: &[f64]| {
                    let c = problem.model.columns(t);
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
