//! What a fit says about each parameter beyond its grid value
//! (docs/conventions.md §11): the refined value ([`crate::refine`]), its
//! 68% and 95% intervals from the profile of the error surface
//! ([`crate::profile`]) or from the Jacobian ([`crate::covariance`]), the
//! Jacobian's standard deviation and correlations, and the edge flags
//! ([`crate::edges`]).
//!
//! The noise variance `s²` is the mean of the squared per-measurement
//! uncertainties when the input gives them, and otherwise the residual
//! estimate `Σ (D − P)² / ν` at the (refined) minimum, `ν = K − p`.

use crate::covariance::Covariance;
use crate::edges::{at_bound, flags, Edge};
use crate::fit::Estimate;
use crate::grid::Axis;
use crate::model::Model;
use crate::profile::{basins, Interval, Profile, DELTA_68, DELTA_95};
use crate::refine::{free_names, profile_at, refine, Objective};
use crate::scene::Scene;
use crate::search::GridProfile;
use rayon::prelude::*;
use std::fmt;
use std::str::FromStr;

/// Which uncertainty a fit computes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Uncertainty {
    /// None.
    Off,
    /// Intervals from the profile of the error surface.
    Profile,
    /// Standard deviations and correlations from the Jacobian at the refined
    /// optimum; intervals `θ ± 1 sd` and `θ ± 1.96 sd`.
    Jacobian,
    /// Both: intervals from the profile, standard deviations and
    /// correlations from the Jacobian.
    Both,
}

impl Uncertainty {
    fn profile(self) -> bool {
        matches!(self, Self::Profile | Self::Both)
    }

    fn jacobian(self) -> bool {
        matches!(self, Self::Jacobian | Self::Both)
    }
}

impl fmt::Display for Uncertainty {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Off => "off",
            Self::Profile => "profile",
            Self::Jacobian => "jacobian",
            Self::Both => "both",
        })
    }
}

impl FromStr for Uncertainty {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        [Self::Off, Self::Profile, Self::Jacobian, Self::Both]
            .into_iter()
            .find(|u| u.to_string() == s)
            .ok_or_else(|| {
                format!("unknown uncertainty `{s}` (expected off, profile, jacobian or both)")
            })
    }
}

/// What a fit does after its grid search.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Analysis {
    /// Refine the best grid point (and the best of each other basin).
    pub refine: bool,
    /// Which uncertainty to compute.
    pub uncertainty: Uncertainty,
}

impl Analysis {
    /// Refinement and both uncertainties: every command's default.
    pub const FULL: Analysis = Analysis {
        refine: true,
        uncertainty: Uncertainty::Both,
    };
    /// The grid search alone.
    pub const NONE: Analysis = Analysis {
        refine: false,
        uncertainty: Uncertainty::Off,
    };

    /// True when the grid's profile is needed (for intervals or for the
    /// starts of the refinement).
    pub(crate) fn needs_profile(self) -> bool {
        self.refine || self.uncertainty.profile()
    }
}

/// Where an interval comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// The profile of the error surface ([`crate::profile`]).
    Profile,
    /// The Jacobian at the refined optimum ([`crate::covariance`]).
    Jacobian,
}

impl fmt::Display for Source {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Profile => "profile",
            Self::Jacobian => "jacobian",
        })
    }
}

/// One searched parameter of a fit.
#[derive(Debug, Clone, PartialEq)]
pub struct Parameter {
    /// The parameter's name (as in [`crate::ModelParams`]).
    pub name: String,
    /// The chosen grid value.
    pub grid: f64,
    /// The refined value (when refined).
    pub refined: Option<f64>,
    /// The 68.27% interval.
    pub interval68: Option<Interval>,
    /// The 95% interval.
    pub interval95: Option<Interval>,
    /// Where both intervals come from.
    pub source: Option<Source>,
    /// The Jacobian's standard deviation (no bound active).
    pub sd: Option<f64>,
    /// Edge flags (empty for an interior value).
    pub flags: Vec<Edge>,
    /// The box the parameter was searched, refined and bounded in
    /// (free-amplitude fits; `None` for the paper objective, whose grid
    /// range is not a bound of the refinement).
    pub bounds: Option<(f64, f64)>,
    /// For an estimate on an edge of the box that is not a bound of the
    /// model's domain: where one local fit with that bound released goes.
    pub released: Option<Released>,
}

/// What releasing a bound of the box gives: a diagnostic, not an estimate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Released {
    /// The parameter's value with its bound released (within the model's domain).
    pub value: f64,
    /// Δ_RMS (eq. 15) there.
    pub rms: f64,
    /// Δ_RMS of the fit in the box, to compare.
    pub rms_in_box: f64,
}

impl Parameter {
    /// A parameter with its grid value only.
    pub fn new(name: &str, grid: f64) -> Self {
        Self {
            name: name.to_string(),
            grid,
            refined: None,
            interval68: None,
            interval95: None,
            source: None,
            sd: None,
            flags: Vec::new(),
            bounds: None,
            released: None,
        }
    }

    /// The refined value, or the grid value when not refined.
    pub fn value(&self) -> f64 {
        self.refined.unwrap_or(self.grid)
    }
}

/// One axis a fit searched: its index among the grid's axes (as in
/// [`GridProfile::axes`]), the parameter's name, its grid value and the axis.
pub(crate) struct Searched<'a> {
    pub axis: usize,
    pub name: &'static str,
    pub value: f64,
    pub values: &'a Axis,
}

/// What [`analyse`] adds to a fit.
pub(crate) struct Analysed {
    pub refined: Option<Estimate>,
    pub parameters: Vec<Parameter>,
    pub covariance: Option<Covariance>,
}

/// The normal quantile of a two-sided 95% interval (Jacobian intervals are
/// `θ ± Z_95 sd`).
pub const Z_95: f64 = 1.959_963_984_540_054;

/// How far above the minimum (in units of `s²`) the profile is computed:
/// twice the 95% level, so the first point outside that level is usually
/// known exactly.
pub const PROFILE_REACH: f64 = 2.0 * DELTA_95;

/// Most starts of the refinement from the grid (the best grid point and
/// the best points of other basins within `DELTA_68 · s²` of it); the
/// Ragheb–Hancock best is one more.
pub const MOST_STARTS: usize = 4;

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

/// Refines and measures the uncertainty of `model`'s grid best `best` on
/// `scene` (refining also from `rh`, the best of the a = 0 slice). `searched` lists the searched axes; `profile` is the grid's
/// profile (over all the grid's axes, of lengths `lens`) when
/// [`Analysis::needs_profile`], computed with [`cutoffs`].
pub(crate) fn analyse(
    scene: &Scene,
    model: Model,
    (best, rh): (&Estimate, Option<&Estimate>),
    searched: &[Searched],
    profile: Option<(&GridProfile, &[usize])>,
    analysis: Analysis,
) -> Analysed {
    let axis_of = |name: &str| searched.iter().find(|s| s.name == name);
    if analysis == Analysis::NONE {
        // The grid search alone: the grid values' flags, and no model
        // evaluation (batches of pixels take this path).
        let parameters = free_names(model)
            .into_iter()
            .filter_map(|name| axis_of(name).map(|s| grid_parameter(model, s)))
            .collect();
        return Analysed {
            refined: None,
            parameters,
            covariance: None,
        };
    }
    let objective = Objective::new(scene, model);
    let names = objective.names().to_vec();
    let x_grid = objective.values(best.params());
    let sse_grid = objective.sse(&x_grid);

    // First simplex steps: one grid step per parameter.
    let steps: Vec<f64> = names
        .iter()
        .map(|&n| axis_of(n).map_or(0.01, |s| step(s.values)))
        .collect();

    // Refinement: from the best grid point and the best of each basin.
    let (mut refined, mut x, mut sse) = (None, x_grid.clone(), sse_grid);
    if analysis.refine {
        let mut starts = vec![x_grid.clone()];
        if let Some((grid_profile, lens)) = profile {
            for (flat, _) in basins(&grid_profile.near, lens, MOST_STARTS) {
                let start = point_of(flat, lens, searched, &names, &x_grid);
                if !starts.contains(&start) {
                    starts.push(start);
                }
            }
            starts.truncate(MOST_STARTS);
        }
        // The Ragheb–Hancock best (a = 0) is a point of this model too, and
        // often in another basin.
        if let Some(rh) = rh {
            let start = objective.values(rh.params());
            if !starts.contains(&start) {
                starts.push(start);
            }
        }
        let r = refine(&objective, &starts, &steps);
        let estimate = Estimate::new(scene, model, objective.params(&r.x))
            .expect("refined values are projected onto the domain");
        // Never worse than the grid (the refinement starts there; a tie in
        // the last bit keeps the grid's point).
        if estimate.rms <= best.rms {
            x = r.x;
            sse = r.sse;
            refined = Some(estimate);
        } else {
            refined = Some(best.clone());
        }
    }

    let s2 = noise_variance(scene, sse, names.len());
    let uncertain = analysis.uncertainty != Uncertainty::Off;
    // The covariance also guides the profile's probes, so it is computed
    // for either kind of uncertainty and reported for the Jacobian's.
    let covariance = match s2 {
        Some(s2) if uncertain => Covariance::new(&objective, &x, s2),
        _ => None,
    };
    // Each parameter's interval is independent of the others': they run in
    // parallel, collected in parameter order.
    let parameters: Vec<Parameter> = names
        .par_iter()
        .enumerate()
        .filter_map(|(i, &name)| {
            let s = axis_of(name)?;
            let mut p = grid_parameter(model, s);
            if analysis.refine {
                // domain_bound describes the value reported: the refined one.
                p.refined = Some(x[i]);
                p.flags.retain(|&f| f != Edge::DomainBound);
                if at_bound(model, name, x[i]) {
                    p.flags.push(Edge::DomainBound);
                }
            }
            if analysis.uncertainty.jacobian() {
                p.sd = covariance.as_ref().map(|c| c.sd(i));
            }
            // The attainable domain (Jensen's open lower end is 1e-9).
            let domain = objective.bounds()[i];
            match s2 {
                Some(s2) if analysis.uncertainty.profile() => {
                    // First guesses of the 95% ends: the Jacobian's, else the
                    // grid profile's.
                    let guess = match &covariance {
                        Some(c) => {
                            let d = Z_95 * c.sd(i);
                            (x[i] - d, x[i] + d)
                        }
                        None => {
                            let grid_interval = profile.map(|(g, _)| {
                                Profile {
                                    points: s
                                        .values
                                        .values
                                        .iter()
                                        .zip(&g.axes[s.axis])
                                        .map(|(&v, &(e, _))| (v, e))
                                        .collect(),
                                    cutoff: g.cutoff,
                                }
                                .interval(
                                    (x[i], sse),
                                    DELTA_95,
                                    s2,
                                    domain,
                                )
                            });
                            grid_interval
                                .map_or((x[i] - steps[i], x[i] + steps[i]), |g| (g.lo, g.hi))
                        }
                    };
                    let probe = Probe {
                        objective: &objective,
                        covariance: covariance.as_ref(),
                        x: &x,
                        sse,
                        s2,
                        steps: &steps,
                        domain,
                    };
                    let range = s
                        .values
                        .values
                        .iter()
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                            (lo.min(v), hi.max(v))
                        });
                    let (lo68, lo95, open_below) = probe.end(i, -1.0, x[i] - guess.0, range);
                    let (hi68, hi95, open_above) = probe.end(i, 1.0, guess.1 - x[i], range);
                    if open_below {
                        p.flags.push(Edge::OpenBelow);
                    }
                    if open_above {
                        p.flags.push(Edge::OpenAbove);
                    }
                    p.interval68 = Some(Interval {
                        lo: lo68,
                        hi: hi68,
                        open_below,
                        open_above,
                    });
                    p.interval95 = Some(Interval {
                        lo: lo95,
                        hi: hi95,
                        open_below,
                        open_above,
                    });
                    p.source = Some(Source::Profile);
                }
                _ => {
                    if let Some(sd) = p.sd {
                        let (lo, hi) = domain;
                        let around = |k: f64| Interval {
                            lo: (x[i] - k * sd).max(lo),
                            hi: (x[i] + k * sd).min(hi),
                            open_below: false,
                            open_above: false,
                        };
                        p.interval68 = Some(around(1.0));
                        p.interval95 = Some(around(Z_95));
                        p.source = Some(Source::Jacobian);
                    }
                }
            }
            Some(p)
        })
        .collect();
    Analysed {
        refined,
        parameters,
        covariance: covariance.filter(|_| analysis.uncertainty.jacobian()),
    }
}

impl Probe<'_> {
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
fn path_start(x: &[f64], covariance: Option<&Covariance>, i: usize, value: f64) -> Vec<f64> {
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

/// Most probes of the continuous profile per interval end.
const MOST_PROBES: usize = 4;

/// What locating an interval end on the continuous profile needs: the
/// objective, the minimum `x` (objective `sse`), the noise variance, the
/// first steps and the parameter's domain.
struct Probe<'a> {
    objective: &'a Objective<'a>,
    covariance: Option<&'a Covariance>,
    x: &'a [f64],
    sse: f64,
    s2: f64,
    steps: &'a [f64],
    domain: (f64, f64),
}

impl Probe<'_> {
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
        let (t68, t95) = ((DELTA_68 * self.s2).sqrt(), (DELTA_95 * self.s2).sqrt());
        let clamp = |v: f64| v.clamp(self.domain.0, self.domain.1);
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
            if value == self.domain.0 || value == self.domain.1 {
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
}

/// A searched parameter with its grid value and that value's flags.
fn grid_parameter(model: Model, s: &Searched) -> Parameter {
    Parameter {
        flags: flags(model, s.name, s.value, s.values),
        ..Parameter::new(s.name, s.value)
    }
}

/// The spacing of an axis near its values (the first step; 0.01 for an axis
/// of one value).
fn step(axis: &Axis) -> f64 {
    match axis.values.as_slice() {
        [a, b, ..] => (b - a).abs(),
        _ => 0.01,
    }
}

/// The free values of the grid point `flat` (row-major over `lens`),
/// taking parameters not searched from `fallback`.
fn point_of(
    flat: usize,
    lens: &[usize],
    searched: &[Searched],
    names: &[&str],
    fallback: &[f64],
) -> Vec<f64> {
    names
        .iter()
        .zip(fallback)
        .map(|(&name, &f)| {
            searched.iter().find(|s| s.name == name).map_or(f, |s| {
                let stride: usize = lens[s.axis + 1..].iter().product();
                s.values.values[(flat / stride) % lens[s.axis]]
            })
        })
        .collect()
}

/// A parameter's profile for a figure, on the `Δχ²` scale
/// `(Σ (D − P)² − min) / s²` ([`crate::Fitter::profiles`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ProfileCurve {
    /// The parameter's name.
    pub name: String,
    /// The grid's profile (the smallest objective over the grid values of
    /// the other parameters) at each axis value in the plotted range whose
    /// profile was computed, as (value, Δχ²).
    pub grid: Vec<(f64, f64)>,
    /// The continuous profile (minimised over the other parameters by
    /// Nelder–Mead) at evenly spaced values, as (value, Δχ²).
    pub refined: Vec<(f64, f64)>,
    /// The estimate (refined value).
    pub estimate: f64,
}

/// The profiles of every parameter of `fit` with a 95% interval, over its
/// interval widened by half its width each side (within the domain), with
/// `points` values on the refined curve. `grid_profile` is the grid's
/// profile over axes `searched`.
pub(crate) fn profile_curves(
    scene: &Scene,
    fit: &crate::Fit,
    searched: &[Searched],
    grid_profile: &GridProfile,
    points: usize,
) -> Vec<ProfileCurve> {
    let objective = Objective::new(scene, fit.model);
    let names = objective.names().to_vec();
    let x = objective.values(fit.estimate().params());
    let sse = objective.sse(&x);
    let Some(s2) = noise_variance(scene, sse, names.len()).filter(|&s2| s2 > 0.0) else {
        return Vec::new();
    };
    let covariance = Covariance::new(&objective, &x, s2);
    let steps: Vec<f64> = names
        .iter()
        .map(|&n| {
            searched
                .iter()
                .find(|s| s.name == n)
                .map_or(0.01, |s| step(s.values))
        })
        .collect();
    let mut out = Vec::new();
    for (i, &name) in names.iter().enumerate() {
        let (Some(s), Some(p)) = (
            searched.iter().find(|s| s.name == name),
            fit.parameters.iter().find(|p| p.name == name),
        ) else {
            continue;
        };
        let Some(i95) = p.interval95 else { continue };
        let (lo_d, hi_d) = objective.bounds()[i];
        let width = (i95.hi - i95.lo).max(steps[i]);
        let (lo, hi) = (
            (i95.lo - width / 2.0).max(lo_d),
            (i95.hi + width / 2.0).min(hi_d),
        );
        let scale = |e: f64| (e - sse) / s2;
        let grid = s
            .values
            .values
            .iter()
            .zip(&grid_profile.axes[s.axis])
            .filter(|(&v, &(e, _))| v >= lo && v <= hi && e.is_finite())
            .map(|(&v, &(e, _))| (v, scale(e)))
            .collect();
        let refined = (0..points)
            .map(|k| {
                let v = lo + (hi - lo) * k as f64 / (points - 1).max(1) as f64;
                let start = path_start(&x, covariance.as_ref(), i, v);
                (v, scale(profile_at(&objective, i, v, &start, &steps).sse))
            })
            .collect();
        out.push(ProfileCurve {
            name: name.to_string(),
            grid,
            refined,
            estimate: x[i],
        });
    }
    out
}
