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
use crate::uncertainty::Z_95;
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

/// The Jacobian covariance of the reported parameters (nonlinear ones in
/// reported units, then β for the layered models, then the amplitude).
#[derive(Debug, Clone, PartialEq)]
pub struct JacobianCovariance {
    /// `s² (JᵀJ)⁻¹` over the parameters not on a face of the box; a
    /// parameter on a face has `None` in its row and column.
    pub matrix: Vec<Vec<Option<f64>>>,
}

impl JacobianCovariance {
    /// The covariance at the minimum `point`, with the noise variance `s2`;
    /// `None` when `JᵀJ` is singular.
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
        let has_u = !columns.u.is_empty();
        let u = |v: &[f64], i: usize| if has_u { v[i] } else { 0.0 };
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
                        .map(|i| c * ((1.0 - beta) * d.s[i] + beta * u(&d.u, i)) * scale)
                        .collect();
                    let (lo, hi) = problem.bounds[j];
                    (col, point.theta[j] <= lo || point.theta[j] >= hi)
                }
                Coordinate::Beta => {
                    let col = (0..k)
                        .map(|i| c * (u(&columns.u, i) - columns.s[i]))
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
                .map(|i| (1.0 - beta) * columns.s[i] + beta * u(&columns.u, i))
                .collect(),
        );
        on_face.push(c <= 0.0);
        let kept: Vec<usize> = (0..jac.len()).filter(|&i| !on_face[i]).collect();
        let mut normal = DMatrix::<f64>::zeros(kept.len(), kept.len());
        for (a, &i) in kept.iter().enumerate() {
            for (b, &j) in kept.iter().enumerate() {
                normal[(a, b)] = (0..k)
                    .map(|r| {
                        let w = problem.root_weight[r] * problem.root_weight[r];
                        w * jac[i][r] * jac[j][r]
                    })
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
        let inverse = scaled.cholesky()?.inverse();
        let mut matrix = vec![vec![None; jac.len()]; jac.len()];
        for (a, &i) in kept.iter().enumerate() {
            for (b, &j) in kept.iter().enumerate() {
                matrix[i][j] = Some(s2 * inverse[(a, b)] / (d[a] * d[b]));
            }
        }
        Some(Self { matrix })
    }

    /// The standard deviation of parameter `i`.
    pub fn sd(&self, i: usize) -> Option<f64> {
        self.matrix[i][i].map(f64::sqrt)
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

/// The minimisations of a profile stop at this gain: `sqrt(profile − min)`
/// is then known far better than [`END_TOLERANCE`] of its level.
pub const PROFILE_TOLERANCE: f64 = 1e-7;

/// Most profile evaluations per end.
pub const MOST_STEPS: usize = 12;

/// An end is accepted when `sqrt(profile − min)` is within this fraction of
/// its target.
pub const END_TOLERANCE: f64 = 5e-3;

impl Side<'_> {
    /// The profile at `value`: the minimum over every other parameter with
    /// this one held at `value`, started on the Jacobian's linearised path;
    /// when that lands more than twice `target` (in `sqrt(profile − min)`)
    /// above the minimum, also from the minimum's own values (the path can
    /// start in another valley), keeping the lower.
    fn profile(&self, value: f64, target: f64) -> Point {
        let problem = self.problem;
        let estimate = self.coordinate.value(self.minimum, problem);
        let mut start = self.minimum.theta.clone();
        if let Some(cov) = self.covariance {
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
        let mut free = vec![true; problem.dim()];
        let beta = match self.coordinate {
            Coordinate::Nonlinear { j, log } => {
                start[j] = if log { libm::log(value) } else { value };
                free[j] = false;
                problem.beta
            }
            Coordinate::Beta => (value, value),
        };
        let from_path = minimise(problem, &start, &free, beta, PROFILE_TOLERANCE).point;
        if from_path.sse - self.minimum.sse <= 4.0 * target * target {
            return from_path;
        }
        let mut plain = self.minimum.theta.clone();
        if let Coordinate::Nonlinear { j, log } = self.coordinate {
            plain[j] = if log { libm::log(value) } else { value };
        }
        if plain == start {
            return from_path;
        }
        let from_minimum = minimise(problem, &plain, &free, beta, PROFILE_TOLERANCE).point;
        if from_minimum.sse < from_path.sse {
            from_minimum
        } else {
            from_path
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
        // (distance from the estimate, sqrt(profile − min)) of every probe.
        let mut probes: Vec<(f64, f64)> = vec![(0.0, 0.0)];
        let room = (face - estimate).abs();
        let mut ends = [(face, true); 2];
        for (level, &height) in self.levels.heights.iter().enumerate() {
            let target = height.sqrt();
            if room == 0.0 {
                ends[level] = (face, true);
                continue;
            }
            let mut next = match (level, sd) {
                (1, _) if ends[0].1 => room,
                (1, _) => {
                    (ends[0].0 - estimate).abs()
                        * (self.levels.heights[1] / self.levels.heights[0]).sqrt()
                }
                (_, Some(sd)) if sd > 0.0 => sd * (height / self.levels.s2).sqrt(),
                _ => 0.1 * room,
            }
            .min(room);
            let mut found = None;
            for _ in 0..MOST_STEPS {
                let value = if next >= room {
                    face
                } else {
                    estimate + self.direction * next
                };
                let point = self.profile(value, target);
                if point.sse < sse_min * (1.0 - 1e-9) - 1e-300 {
                    return Walk::NewMinimum(point);
                }
                let h = (point.sse - sse_min).max(0.0).sqrt();
                probes.push((next.min(room), h));
                if (h - target).abs() <= END_TOLERANCE * target {
                    found = Some((value, false));
                    break;
                }
                if h < target && next >= room {
                    found = Some((face, true));
                    break;
                }
                // The nearest probes on either side of the level.
                let below = probes
                    .iter()
                    .filter(|p| p.1 < target)
                    .fold((0.0, 0.0), |b, &p| if p.0 > b.0 { p } else { b });
                let above = probes.iter().filter(|p| p.1 >= target).fold(
                    None,
                    |b: Option<(f64, f64)>, &p| match b {
                        Some(q) if q.0 <= p.0 => Some(q),
                        _ => Some(p),
                    },
                );
                next = match above {
                    Some(above) if above.1 > below.1 => {
                        let t = (target - below.1) / (above.1 - below.1);
                        below.0 + t * (above.0 - below.0)
                    }
                    Some(above) => 0.5 * (below.0 + above.0),
                    None if h > 0.0 => (next * target / h * 1.1).max(next * 1.2),
                    None => next * 2.0,
                }
                .min(room);
            }
            ends[level] = found.unwrap_or_else(|| {
                // Out of steps: the interpolated crossing, or the face.
                let below = probes
                    .iter()
                    .filter(|p| p.1 < target)
                    .fold((0.0, 0.0), |b, &p| if p.0 > b.0 { p } else { b });
                match probes
                    .iter()
                    .filter(|p| p.1 >= target)
                    .map(|p| p.0)
                    .reduce(f64::min)
                {
                    Some(d) => {
                        let above = probes
                            .iter()
                            .find(|p| p.0 == d)
                            .copied()
                            .unwrap_or((d, target));
                        let t = if above.1 > below.1 {
                            (target - below.1) / (above.1 - below.1)
                        } else {
                            1.0
                        };
                        (
                            estimate + self.direction * (below.0 + t * (above.0 - below.0)),
                            false,
                        )
                    }
                    None => (face, true),
                }
            });
        }
        Walk::Ends(ends)
    }
}
