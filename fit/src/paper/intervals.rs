//! The paper objective's uncertainty (docs/conventions.md §11): the
//! Jacobian's covariance at the refined minimum, and the 68% and 95%
//! intervals of each parameter from its continuous profile (the objective
//! minimised over the other parameters, [`super::refine::profile_at`]) or
//! from the Jacobian.
//!
//! The noise variance `s²` is the mean of the squared per-measurement
//! uncertainties when the input gives them, and otherwise the residual
//! estimate `Σ (D − P)² / ν` at the (refined) minimum, `ν = K − p`.

use super::objective::SumOfSquares;
use super::refine::profile_at;
use crate::covariance::Covariance;
use crate::paper::search::{GridProfile, Searched};
use crate::profile::{Interval, Profile, DELTA_68, DELTA_95, Z_95};
use crate::scene::Scene;
use nalgebra::DMatrix;

/// How far above the minimum (in units of `s²`) the profile is computed:
/// twice the 95% level, so the first point outside that level is usually
/// known exactly.
pub const PROFILE_REACH: f64 = 2.0 * DELTA_95;

/// Relative step of the Jacobian's central differences.
const STEP: f64 = 1e-6;

/// The noise variance: the mean squared uncertainty when the scene has
/// them, else `sse / ν`; `None` without degrees of freedom.
pub(crate) fn noise_variance(scene: &Scene, sse: f64, free: usize) -> Option<f64> {
    match scene.sigma() {
        Some(sigma) => Some(sigma.iter().map(|s| s * s).sum::<f64>() / sigma.len() as f64),
        None => (scene.len() > free).then(|| sse / (scene.len() - free) as f64),
    }
}

/// The profile cutoff and basin cutoff for a grid minimum `sse`.
pub(crate) fn cutoffs(scene: &Scene, sse: f64, free: usize) -> Option<(f64, f64)> {
    let s2 = noise_variance(scene, sse, free)?;
    Some((sse + PROFILE_REACH * s2, sse + DELTA_68 * s2))
}

/// `s² (JᵀJ)⁻¹` at the free values `x`, `J_kj = ∂P_k/∂θ_j` by central
/// differences; `None` when a parameter is within a difference step of a
/// bound of its domain, or `JᵀJ` is singular.
pub(crate) fn jacobian_covariance(
    objective: &SumOfSquares,
    x: &[f64],
    s2: f64,
) -> Option<Covariance> {
    let k = objective.prediction(x).ok()?.len();
    let mut jacobian = DMatrix::<f64>::zeros(k, x.len());
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
    Covariance::from_jacobian(objective.names(), &jacobian, s2)
}

/// The grid's profile of the searched parameter `s` (the smallest grid
/// objective at each of its axis values), from the grid search's `profile`.
pub(crate) fn grid_profile(s: &Searched, profile: &GridProfile) -> Profile {
    Profile {
        points: s
            .values
            .values
            .iter()
            .zip(&profile.axes[s.axis])
            .map(|(&v, &(e, _))| (v, e))
            .collect(),
        cutoff: profile.cutoff,
    }
}

/// The 68% and 95% intervals `θ ± sd` and `θ ± Z_95 sd` of a parameter at
/// `value` with standard deviation `sd`, cut to its `domain`.
pub(crate) fn jacobian_intervals(value: f64, sd: f64, (lo, hi): (f64, f64)) -> [Interval; 2] {
    [1.0, Z_95].map(|k| Interval {
        lo: (value - k * sd).max(lo),
        hi: (value + k * sd).min(hi),
        open_below: false,
        open_above: false,
    })
}

/// Most probes of the continuous profile per interval end.
const MOST_PROBES: usize = 4;

/// What locating an interval end on the continuous profile needs: the
/// objective, its covariance at the minimum `x` (objective `sse`), the
/// noise variance and the first steps.
pub(crate) struct Probe<'a> {
    pub objective: &'a SumOfSquares<'a>,
    pub covariance: Option<&'a Covariance>,
    pub x: &'a [f64],
    pub sse: f64,
    pub s2: f64,
    pub steps: &'a [f64],
}

impl Probe<'_> {
    /// The 68% and 95% profile intervals of parameter `i`, searched over
    /// `range` (its axis's first and last values), from first guesses of
    /// the 95% ends: the Jacobian's `θ ± Z_95 sd`, else `grid`'s interval
    /// (the grid profile's, [`grid_profile`]), else one step each side.
    pub(crate) fn intervals(
        &self,
        i: usize,
        range: (f64, f64),
        grid: Option<Profile>,
    ) -> [Interval; 2] {
        let x = self.x[i];
        let guess = match self.covariance {
            Some(c) => {
                let d = Z_95 * c.sd(i);
                (x - d, x + d)
            }
            None => grid
                .map(|g| g.interval((x, self.sse), DELTA_95, self.s2, self.objective.bounds()[i]))
                .map_or((x - self.steps[i], x + self.steps[i]), |g| (g.lo, g.hi)),
        };
        let (lo68, lo95, open_below) = self.end(i, -1.0, x - guess.0, range);
        let (hi68, hi95, open_above) = self.end(i, 1.0, guess.1 - x, range);
        [(lo68, hi68), (lo95, hi95)].map(|(lo, hi)| Interval {
            lo,
            hi,
            open_below,
            open_above,
        })
    }

    /// The 68% and 95% ends of parameter `i` on the side `side` (−1 below,
    /// +1 above; `guess` is a first guess of the 95% end's distance, one
    /// grid step when it is not positive), and whether the interval is open
    /// there: the end lies outside the range
    /// searched `(first, last)`, or the profile did not reach the 95% level
    /// within [`MOST_PROBES`] probes (the end is then the last probe).
    ///
    /// Each probe is the continuous profile at one value
    /// ([`Probe::height`]). Once a probe's height `h = sqrt(profile − min)`
    /// reaches the 95% level, a second probe goes where a parabola through
    /// the first puts the 68% end, and each end is interpolated linearly in
    /// `h` between the points that bracket it (exact for a parabola). A
    /// probe below the level moves further out; at a bound of the domain
    /// the interval closes there.
    fn end(&self, i: usize, side: f64, guess: f64, (first, last): (f64, f64)) -> (f64, f64, bool) {
        let centre = self.x[i];
        let domain = self.objective.bounds()[i];
        let (t68, t95) = ((DELTA_68 * self.s2).sqrt(), (DELTA_95 * self.s2).sqrt());
        let clamp = |v: f64| v.clamp(domain.0, domain.1);
        let mut distance = guess;
        if distance.is_nan() || distance <= 0.0 || distance.is_infinite() {
            distance = self.steps[i];
        }
        let outside = |v: f64| v < first.min(last) || v > first.max(last);
        let at = |t: f64, h: f64, d: f64| centre + side * d * (t / h).min(1.0);
        if t95 == 0.0 {
            return (centre, centre, false);
        }
        let mut last_probe = centre;
        for _ in 0..MOST_PROBES {
            let value = clamp(centre + side * distance);
            let d = (value - centre).abs();
            if d == 0.0 {
                // The estimate is at this bound of the domain.
                return (centre, centre, false);
            }
            last_probe = value;
            let h = self.height(i, value);
            if h >= t95 {
                // One more probe where a parabola through this one puts the
                // 68% end; each end is then interpolated between the two
                // points (of 0, the inner probe, this probe) that bracket it.
                let d68 = d * t68 / h;
                let h68 = self.height(i, centre + side * d68);
                let points = [(0.0, 0.0), (d68, h68), (d, h)];
                let cross = |t: f64| {
                    let k = points.windows(2).position(|w| w[1].1 >= t).unwrap_or(1);
                    let ((d0, h0), (d1, h1)) = (points[k], points[k + 1]);
                    let f = if h1 > h0 { (t - h0) / (h1 - h0) } else { 1.0 };
                    centre + side * (d0 + f.clamp(0.0, 1.0) * (d1 - d0))
                };
                let (e68, e95) = (cross(t68), cross(t95));
                return (e68, e95, outside(e95));
            }
            if value == domain.0 || value == domain.1 {
                let e68 = if h >= t68 { at(t68, h, d) } else { value };
                return (e68, value, outside(value));
            }
            // Below the level: go out to where a parabola through this
            // probe would reach it, with a little to spare.
            let grow = if h > 0.0 { 1.25 * t95 / h } else { 4.0 };
            distance = d * grow.clamp(1.25, 4.0);
        }
        (last_probe, last_probe, true)
    }

    /// `sqrt(profile − min)` of parameter `i` at `value`: Nelder–Mead over
    /// the other parameters, started where the Jacobian's linearisation puts
    /// the profile's path (at the minimum without a Jacobian).
    fn height(&self, i: usize, value: f64) -> f64 {
        let start = path_start(self.x, self.covariance, i, value);
        let steps = path_steps(self.steps, self.covariance, i);
        let r = profile_at(self.objective, i, value, &start, &steps);
        (r.sse - self.sse).max(0.0).sqrt()
    }
}

/// Where the Jacobian's linearisation puts the profile's path when
/// parameter `i` moves from the minimum `x` to `value`: the other
/// parameters move by their regression on it, `C_ki / C_ii`. `x` itself
/// (with `value`) without a covariance.
pub(crate) fn path_start(
    x: &[f64],
    covariance: Option<&Covariance>,
    i: usize,
    value: f64,
) -> Vec<f64> {
    match covariance {
        Some(c) => (0..x.len())
            .map(|k| x[k] + c.matrix[k][i] / c.matrix[i][i] * (value - x[i]))
            .collect(),
        None => x.to_vec(),
    }
}

/// First simplex steps of a profile probe of parameter `i`: each other
/// parameter's standard deviation given parameter `i`
/// (`sqrt(C_kk − C_ki²/C_ii)`, the width of the valley across the path),
/// at most its grid step; the grid steps without a covariance.
fn path_steps(steps: &[f64], covariance: Option<&Covariance>, i: usize) -> Vec<f64> {
    match covariance {
        Some(c) => (0..steps.len())
            .map(|k| {
                let m = &c.matrix;
                let across = (m[k][k] - m[k][i] * m[k][i] / m[i][i]).max(0.0).sqrt();
                if across > 0.0 {
                    across.min(steps[k])
                } else {
                    steps[k]
                }
            })
            .collect(),
        None => steps.to_vec(),
    }
}
