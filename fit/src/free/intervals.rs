//! Uncertainty of a free-amplitude fit (docs/conventions.md §11b): the
//! Jacobian covariance of the reported parameters, and profile intervals
//! found MINOS-style, each end located by re-fitting every other parameter
//! with this one held fixed.
//!
//! Both use the weighted objective with the amplitude profiled out. With
//! uncertainties given, the objective is χ² and the levels are χ²₁'s
//! quantiles (`Δ = 1`, `3.841`); without them the noise variance is the
//! residual estimate `s² = F_min/(K − p)` and the levels are those of
//! `F(1, K − p)` (the square of Student's t), which the estimate of `s²`
//! widens a little for small K.

use super::problem::{Point, Problem};
use super::refine::minimise;
use crate::profile::Z_95;
use nalgebra::DMatrix;

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
    pub fn new(problem: &Problem, sse: f64) -> Option<Self> {
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
    pub fn value(self, point: &Point, problem: &Problem) -> f64 {
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
    pub fn bounds(self, problem: &Problem) -> (f64, f64) {
        match self {
            Self::Nonlinear { j, .. } => problem.reported[j],
            Self::Beta => problem.beta,
        }
    }
}

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
    pub fn new(
        problem: &Problem,
        point: &Point,
        coordinates: &[Coordinate],
        s2: f64,
    ) -> Option<Self> {
        let (columns, derivatives) = problem
            .basis
            .derivatives(&point.theta, &problem.domain, true);
        let c = point.linear.amplitude();
        let beta = point.linear.beta(problem.beta.0);
        let k = problem.data.len();
        // A column, or 0 where it is empty (no U; the surface term's
        // derivative in n and a).
        let entry = |v: &[f64], i: usize| v.get(i).copied().unwrap_or(0.0);
        // ∂(c M_k)/∂ each reported parameter, then ∂/∂c.
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
                        .map(|i| {
                            c * ((1.0 - beta) * entry(&d.s, i) + beta * entry(&d.u, i)) * scale
                        })
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
        let kept: Vec<usize> = (0..jac.len()).filter(|&i| !on_face[i]).collect();
        let mut normal = DMatrix::<f64>::zeros(kept.len(), kept.len());
        for (a, &i) in kept.iter().enumerate() {
            for (b, &j) in kept.iter().enumerate() {
                normal[(a, b)] = (0..k)
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
        // The meat: Σ_k w_k² r_k² J_k J_kᵀ / (1 − h_k)², from the weighted
        // residuals e_k = √w_k r_k and the leverages
        // h_k = w_k J_kᵀ A⁻¹ J_k (HC3), in the same scaled coordinates.
        let e = problem.residuals(&columns, &point.linear);
        let n = kept.len();
        let mut meat = DMatrix::<f64>::zeros(n, n);
        // One measurement's scaled Jacobian row and A⁻¹ times it, reused.
        let (mut row, mut solved) = (vec![0.0; n], vec![0.0; n]);
        for (r, (&w, &e)) in problem.weight.iter().zip(&e).enumerate() {
            for ((x, &i), &di) in row.iter_mut().zip(&kept).zip(&d) {
                *x = jac[i][r] / di;
            }
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
        let sandwich = &inverse * meat * &inverse;
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

/// What the walk along a profile found.
#[derive(Debug, Clone, PartialEq)]
pub enum Walk {
    /// The two ends (68.27%, 95%) on this side, and whether each stopped at
    /// the face of the box with the profile still below its level.
    Ends([(f64, bool); 2]),
    /// A point below the minimum (MINOS's "new minimum"): the refinement
    /// missed it, and starts again from there.
    NewMinimum(Point),
}

/// One side of one parameter's profile.
pub struct Side<'a> {
    /// The objective.
    pub problem: &'a Problem,
    /// The minimum.
    pub minimum: &'a Point,
    /// The parameter.
    pub coordinate: Coordinate,
    /// Its index among the covariance's parameters.
    pub index: usize,
    /// The covariance at the minimum, when there is one.
    pub covariance: Option<&'a JacobianCovariance>,
    /// The coordinates of every reported parameter (covariance order).
    pub coordinates: &'a [Coordinate],
    /// −1 below the estimate, +1 above.
    pub direction: f64,
    /// The levels.
    pub levels: Levels,
}

/// The minimisations of a profile stop when a step gains less than this
/// fraction of the 68.27% level's height `Δ s²`: `sqrt(profile − min)` is
/// then known to about half of it, fifty times inside [`END_TOLERANCE`].
pub const PROFILE_TOLERANCE: f64 = 1e-3;

/// Most profile evaluations per end.
pub const MOST_STEPS: usize = 12;

/// A probe ends the search for a level when `sqrt(profile − min)` is within
/// this fraction of its target; the end is then one Newton step from the
/// probe (on the local slope of `sqrt(profile − min)`), whose error is of
/// the order of the square of this fraction when the step's slope is right
/// (with the probe's own error from [`PROFILE_TOLERANCE`]). Measured
/// against bisection of the profile: median 2·10⁻⁴ of the end's distance,
/// 99% within 1.3·10⁻², with known faults up to 0.12 (docs/conventions.md
/// §11b).
pub const END_TOLERANCE: f64 = 5e-2;

/// A walk ends when its bracket of the crossing is narrower than this
/// fraction of the crossing's distance, even with no probe within
/// [`END_TOLERANCE`] of the level: where the profile jumps across the level
/// (its minimum moves to another valley), no probe comes near it.
pub const BRACKET_TOLERANCE: f64 = 1e-2;

/// One probe of a walk: the distance from the estimate, `sqrt(profile − min)`
/// there, and the profile's minimising parameters.
#[derive(Debug, Clone)]
struct Probe {
    distance: f64,
    height: f64,
    theta: Vec<f64>,
    /// Minimised again from the profile's path below it (a jump's far side).
    rechecked: bool,
}

impl Side<'_> {
    /// `value` in the internal coordinate of the held parameter.
    fn internal(&self, value: f64) -> f64 {
        match self.coordinate {
            Coordinate::Nonlinear { log: true, .. } => libm::log(value),
            _ => value,
        }
    }

    /// Where the profile's minimisation at `value` (at `distance` from the
    /// estimate) starts. After the first probe: on the profile's own path,
    /// interpolated (or extrapolated) between the two probes nearest in
    /// distance. Before it: on the Jacobian's linearised path.
    fn start(&self, value: f64, distance: f64, probes: &[Probe]) -> Vec<f64> {
        let problem = self.problem;
        let mut start = self.minimum.theta.clone();
        if probes.len() >= 2 {
            let mut nearest: Vec<&Probe> = probes.iter().collect();
            nearest.sort_by(|p, q| {
                (p.distance - distance)
                    .abs()
                    .total_cmp(&(q.distance - distance).abs())
            });
            let (p, q) = (nearest[0], nearest[1]);
            if p.distance != q.distance {
                let t = (distance - p.distance) / (q.distance - p.distance);
                for (x, (a, b)) in start.iter_mut().zip(p.theta.iter().zip(&q.theta)) {
                    *x = a + t * (b - a);
                }
            }
        } else if let Some(cov) = self.covariance {
            let estimate = self.coordinate.value(self.minimum, problem);
            if let Some(vv) = cov.matrix[self.index][self.index] {
                for (i, c) in self.coordinates.iter().enumerate() {
                    if let (Coordinate::Nonlinear { j, log }, Some(cv)) =
                        (c, cov.matrix[i][self.index])
                    {
                        let shift = cv / vv * (value - estimate);
                        let here = self.coordinates[i].value(self.minimum, problem);
                        let moved = here + shift;
                        start[*j] = if *log {
                            libm::log(moved.max(1e-300))
                        } else {
                            moved
                        };
                    }
                }
            }
        }
        if let Coordinate::Nonlinear { j, .. } = self.coordinate {
            start[j] = self.internal(value);
        }
        start
    }

    /// The profile at `value`: the minimum over every other parameter with
    /// this one held at `value`, from `start`; when that lands more than
    /// twice `target` (in `sqrt(profile − min)`) above the minimum, also
    /// from the minimum's own values (the path can start in another
    /// valley), keeping the lower.
    fn profile(&self, value: f64, target: f64, start: &[f64]) -> Point {
        let problem = self.problem;
        let mut free = vec![true; problem.dim()];
        let beta = match self.coordinate {
            Coordinate::Nonlinear { j, .. } => {
                free[j] = false;
                problem.beta
            }
            Coordinate::Beta => (value, value),
        };
        // `minimise` takes its tolerance as a fraction of the objective.
        let tolerance = PROFILE_TOLERANCE * self.levels.heights[0] / self.minimum.sse.max(1e-300);
        let from_start = minimise(problem, start, &free, beta, tolerance).point;
        if from_start.sse - self.minimum.sse <= 4.0 * target * target {
            return from_start;
        }
        let mut plain = self.minimum.theta.clone();
        if let Coordinate::Nonlinear { j, .. } = self.coordinate {
            plain[j] = self.internal(value);
        }
        if plain == start {
            return from_start;
        }
        let from_minimum = minimise(problem, &plain, &free, beta, tolerance).point;
        if from_minimum.sse < from_start.sse {
            from_minimum
        } else {
            from_start
        }
    }

    /// The farthest probe below `target` (the origin at least), and the
    /// nearest probe beyond it at or above `target`, when there is one: the
    /// crossing of the level lies between them.
    fn bracket(probes: &[Probe], target: f64) -> (&Probe, Option<&Probe>) {
        let near = probes
            .iter()
            .filter(|p| p.height < target)
            .max_by(|p, q| p.distance.total_cmp(&q.distance))
            .expect("the origin is below every level");
        let above = probes
            .iter()
            .filter(|p| p.height >= target && p.distance > near.distance)
            .min_by(|p, q| p.distance.total_cmp(&q.distance));
        (near, above)
    }

    /// The next distance to probe for `target`. With the Jacobian's slope
    /// `alpha` of `sqrt(profile − min)` at the estimate (`√s² / sd`), the
    /// model `h(d) = α d + γ d²` through the probe nearest the target, kept
    /// inside the bracket when there is one. Otherwise inside a bracket,
    /// linear interpolation between its ends (nearly exact, as `sqrt(profile
    /// − min)` is nearly linear in the distance); beyond every probe, the
    /// secant of the two farthest (the origin among them). Never more than
    /// four times as far as the farthest probe below the target.
    ///
    /// Inside a bracket, when the last two of this walk's `fresh` probes
    /// fell on one side of the target, neither the model nor false position
    /// is used (false position creeps towards the crossing from that side
    /// when the far end sits where the profile is steep, at a face or
    /// across a jump): the secant through those two probes when it lands
    /// inside the bracket, else the bracket's midpoint, so that the bracket
    /// at least halves.
    fn next_distance(probes: &[Probe], fresh: usize, target: f64, alpha: Option<f64>) -> f64 {
        let mut below: Vec<&Probe> = probes.iter().filter(|p| p.height < target).collect();
        below.sort_by(|p, q| p.distance.total_cmp(&q.distance));
        let (near, above) = Self::bracket(probes, target);
        let most = match above {
            Some(above) => above.distance,
            None => 4.0 * near.distance,
        };
        // How many of this walk's latest probes fell below (above) the target
        // in a row.
        let streak = |below_target: bool| {
            probes[probes.len() - fresh.min(probes.len())..]
                .iter()
                .rev()
                .take_while(|p| (p.height < target) == below_target)
                .count()
        };
        let stalled = above.is_some() && (streak(true) >= 2 || streak(false) >= 2);
        let quadratic = alpha.filter(|_| !stalled).and_then(|alpha| {
            let nearest = probes.iter().filter(|p| p.distance > 0.0).min_by(|p, q| {
                (p.height - target)
                    .abs()
                    .total_cmp(&(q.height - target).abs())
            })?;
            let (d, h) = (nearest.distance, nearest.height);
            let gamma = (h - alpha * d) / (d * d);
            let root = if gamma == 0.0 {
                target / alpha
            } else {
                let disc = alpha * alpha + 4.0 * gamma * target;
                (disc >= 0.0).then(|| 2.0 * target / (alpha + disc.sqrt()))?
            };
            (root > near.distance && root < most).then_some(root)
        });
        if let Some(root) = quadratic {
            return root;
        }
        match above {
            Some(above) if stalled => {
                // The secant through the streak's last two probes, when it
                // lands inside the bracket; else its midpoint.
                let n = probes.len();
                let (p, q) = (&probes[n - 2], &probes[n - 1]);
                let secant = q.distance
                    + (target - q.height) * (q.distance - p.distance) / (q.height - p.height);
                let inside = secant > near.distance && secant < above.distance;
                if inside {
                    secant
                } else {
                    0.5 * (near.distance + above.distance)
                }
            }
            Some(above) if above.height > near.height => {
                let t = (target - near.height) / (above.height - near.height);
                near.distance + t * (above.distance - near.distance)
            }
            Some(above) => 0.5 * (near.distance + above.distance),
            None => {
                let far = near.distance;
                let slope = match below.len() {
                    1 => 0.0,
                    n => {
                        let before = below[n - 2];
                        (near.height - before.height) / (far - before.distance)
                    }
                };
                if slope > 0.0 {
                    (far + (target - near.height) / slope).min(most)
                } else {
                    2.0 * far
                }
            }
        }
    }

    /// The slope of `sqrt(profile − min)` in the distance at the probe
    /// `here` (near `target`): the secant with another probe near the
    /// target when there is one; else the derivative of the model
    /// `h(d) = α d + γ d²` through `here` with the Jacobian's slope `alpha`
    /// at the estimate; else the secant from the estimate.
    fn local_slope(probes: &[Probe], here: &Probe, target: f64, alpha: Option<f64>) -> f64 {
        let other = probes
            .iter()
            .filter(|p| p.distance > 0.0 && p.distance != here.distance)
            .filter(|p| (p.height - target).abs() <= 0.25 * target)
            .min_by(|p, q| {
                (p.distance - here.distance)
                    .abs()
                    .total_cmp(&(q.distance - here.distance).abs())
            });
        let secant = |p: &Probe| (here.height - p.height) / (here.distance - p.distance);
        match (other, alpha) {
            (Some(p), _) if secant(p) > 0.0 => secant(p),
            (_, Some(alpha)) => {
                let (d, h) = (here.distance, here.height);
                let gamma = (h - alpha * d) / (d * d);
                let slope = alpha + 2.0 * gamma * d;
                if slope > 0.0 {
                    slope
                } else {
                    h / d
                }
            }
            _ => here.height / here.distance,
        }
    }

    /// Walks out to both levels' ends on this side.
    pub fn walk(&self) -> Walk {
        let problem = self.problem;
        let estimate = self.coordinate.value(self.minimum, problem);
        let (lo, hi) = self.coordinate.bounds(problem);
        let face = if self.direction < 0.0 { lo } else { hi };
        let sse_min = self.minimum.sse;
        let sd = self.covariance.and_then(|c| c.sd(self.index));
        let alpha = sd
            .filter(|&sd| sd > 0.0)
            .map(|sd| self.levels.s2.sqrt() / sd);
        let room = (face - estimate).abs();
        // The held value at a distance from the estimate (the face from
        // `room` on).
        let value_at = |distance: f64| {
            if distance >= room {
                face
            } else {
                estimate + self.direction * distance
            }
        };
        // The profile at `value` from `start` and `sqrt(profile − min)`
        // there, or a point below the minimum.
        let measure = |value: f64, target: f64, start: &[f64]| {
            let point = self.profile(value, target, start);
            if point.sse < sse_min * (1.0 - 1e-9) - 1e-300 {
                return Err(point);
            }
            Ok(((point.sse - sse_min).max(0.0).sqrt(), point.theta))
        };
        let mut probes = vec![Probe {
            distance: 0.0,
            height: 0.0,
            theta: self.minimum.theta.clone(),
            rechecked: false,
        }];
        let mut ends = [(face, true); 2];
        for (level, &height) in self.levels.heights.iter().enumerate() {
            let target = height.sqrt();
            if room == 0.0 || (level == 1 && ends[0].1) {
                // No room, or the face is inside the 68.27% level already.
                continue;
            }
            let mut next = match (level, sd) {
                (1, _) => Self::next_distance(&probes, 0, target, alpha),
                (_, Some(sd)) if sd > 0.0 => sd * (height / self.levels.s2).sqrt(),
                _ => 0.1 * room,
            }
            .min(room);
            let mut found = None;
            let before = probes.len();
            for step in 0..MOST_STEPS {
                if step + 1 == MOST_STEPS && probes.iter().all(|p| p.height < target) {
                    // The last step probes the face, so that an end is put
                    // there only when the profile is seen below the level
                    // at the face itself.
                    next = room;
                }
                let value = value_at(next);
                let start = self.start(value, next, &probes);
                let (h, theta) = match measure(value, target, &start) {
                    Ok(measured) => measured,
                    Err(lower) => return Walk::NewMinimum(lower),
                };
                probes.push(Probe {
                    distance: next.min(room),
                    height: h,
                    theta,
                    rechecked: false,
                });
                if h < target && next >= room {
                    found = Some((face, true));
                    break;
                }
                if (h - target).abs() <= END_TOLERANCE * target {
                    let here = probes.last().expect("just pushed");
                    let slope = Self::local_slope(&probes, here, target, alpha);
                    let end = here.distance + (target - h) / slope;
                    found = Some(if end.is_nan() || end <= 0.0 {
                        (value, false)
                    } else if end >= room {
                        (face, true)
                    } else {
                        (estimate + self.direction * end, false)
                    });
                    break;
                }
                next = Self::next_distance(&probes, probes.len() - before, target, alpha).min(room);
                if let (near, Some(above)) = Self::bracket(&probes, target) {
                    if above.distance - near.distance <= BRACKET_TOLERANCE * above.distance {
                        // A bracket this narrow without a probe near the
                        // level: the profile jumps across it (another
                        // valley takes over), and the end is the jump;
                        // unless the far side's minimisation stopped in
                        // another valley, which minimising there again
                        // from the near side's parameters (the profile's
                        // path continued) shows.
                        if !above.rechecked {
                            let (distance, mut start) = (above.distance, near.theta.clone());
                            let value = value_at(distance);
                            if let Coordinate::Nonlinear { j, .. } = self.coordinate {
                                start[j] = self.internal(value);
                            }
                            let (h, theta) = match measure(value, target, &start) {
                                Ok(measured) => measured,
                                Err(lower) => return Walk::NewMinimum(lower),
                            };
                            let far = probes
                                .iter_mut()
                                .find(|p| p.distance == distance && p.height >= target)
                                .expect("the bracket's far probe");
                            far.rechecked = true;
                            if h < far.height {
                                (far.height, far.theta) = (h, theta);
                            }
                            if h < target {
                                next = Self::next_distance(
                                    &probes,
                                    probes.len() - before,
                                    target,
                                    alpha,
                                )
                                .min(room);
                                continue;
                            }
                        }
                        found = Some((estimate + self.direction * next, false));
                        break;
                    }
                }
            }
            ends[level] = found.unwrap_or_else(|| {
                // Out of steps with a probe above the level (the last step
                // saw to that): the crossing interpolated in the bracket.
                let d = Self::next_distance(&probes, probes.len() - before, target, alpha);
                (estimate + self.direction * d.min(room), false)
            });
        }
        Walk::Ends(ends)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn probe(distance: f64, height: f64) -> Probe {
        Probe {
            distance,
            height,
            theta: Vec::new(),
            rechecked: false,
        }
    }

    /// Probes `h` from `first` as a walk does (stopping within
    /// [`END_TOLERANCE`] of the level 1, or on a bracket narrower than
    /// [`BRACKET_TOLERANCE`]), with the face's probe at 2 already taken;
    /// returns the probes taken and the final bracket.
    fn search(h: impl Fn(f64) -> f64, first: f64) -> (usize, f64, f64) {
        let mut probes = vec![probe(0.0, 0.0), probe(2.0, h(2.0))];
        let before = probes.len();
        let mut d = first;
        for _ in 0..MOST_STEPS {
            probes.push(probe(d, h(d)));
            if (h(d) - 1.0).abs() <= END_TOLERANCE {
                break;
            }
            let (near, above) = Side::bracket(&probes, 1.0);
            let above = above.expect("the face is above");
            if above.distance - near.distance <= BRACKET_TOLERANCE * above.distance {
                break;
            }
            d = Side::next_distance(&probes, probes.len() - before, 1.0, None);
            assert!(
                d > near.distance && d < above.distance,
                "{d} outside the bracket"
            );
        }
        let (near, above) = Side::bracket(&probes, 1.0);
        (
            probes.len() - before,
            near.distance,
            above.unwrap().distance,
        )
    }

    #[test]
    fn a_bracket_with_a_steep_far_end_shrinks_from_both_ends() {
        // The profile crosses 1 at d = 1.5 and rises to 40 at the face
        // (d = 2): plain false position between (1.2, 0.8) and (2, 40)
        // steps to 1.204, then keeps creeping up from below.
        let steep = |d: f64| {
            if d <= 1.5 {
                d / 1.5
            } else {
                1.0 + 78.0 * (d - 1.5)
            }
        };
        let (taken, near, _) = search(steep, 1.2);
        assert!(taken <= 3, "{taken} probes to come within 5% of the level");
        assert!((near - 1.5).abs() < 0.1, "ended near {near}");
    }

    #[test]
    fn a_jump_across_the_level_ends_on_a_narrow_bracket() {
        // Below the level up to d = 1.5, far above it beyond (another
        // valley takes over): no probe comes near the level.
        let jump = |d: f64| if d < 1.5 { 0.5 * d / 1.5 } else { 40.0 };
        let (taken, near, above) = search(jump, 1.2);
        // Within the step budget (plain false position would still be 17%
        // of the distance short of the jump after 12 probes).
        assert!(taken <= MOST_STEPS, "{taken} probes for the jump");
        assert!(near < 1.5 && above >= 1.5);
        assert!(
            above - near <= BRACKET_TOLERANCE * above,
            "[{near}, {above}]"
        );
    }
}
