//! How often the intervals contain the truth (docs/conventions.md §11b):
//! fits of synthetic data with known parameters and seeded Gaussian noise
//! on every measurement, counted per parameter and per level.
//!
//! Two noise settings ([`NoiseModel`]): the same standard deviation on every
//! measurement, not given to the fit (it estimates the noise from the
//! residuals); and heteroscedastic noise whose standard deviation grows with
//! the signal, given to the fit as each measurement's uncertainty (it then
//! weighs by `1/σ²`).
//!
//! The data are the model at the truth in the parametrisation of the
//! fitter's objective: eq. 8's raw mix times an amplitude (peak 1) for the
//! free objective, the paper-normalised prediction for the paper one.

use crate::fit::Fitter;
use crate::fitted::{FittedModel, ModelParams};
use crate::model::{baseline_interior, Family, Model, Param};
use crate::objective::Objective;
use crate::profile::Interval;
use crate::report::{Parameter, Source};
use crate::scene::Scene;
use crate::synthetic::{geometries, Noise};
use laminar_brdf_core::measures::max_of;
use laminar_brdf_core::Angles;

/// The noise of a coverage trial (the prediction's max is 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NoiseModel {
    /// `σ` on every measurement; the fit is not told it.
    Every(f64),
    /// `σ_k = floor + relative · P_k` on every measurement, given to the fit
    /// as the measurements' uncertainties.
    Heteroscedastic {
        /// The floor.
        floor: f64,
        /// The part proportional to the signal.
        relative: f64,
    },
}

impl NoiseModel {
    /// A short label for printed tables.
    pub fn label(self) -> String {
        match self {
            Self::Every(s) => format!("σ = {s} on every measurement, estimated"),
            Self::Heteroscedastic { floor, relative } => {
                format!("σ = {floor} + {relative}·P given as sigma")
            }
        }
    }
}

/// Per parameter: how many intervals held the truth.
#[derive(Debug, Clone, PartialEq)]
pub struct Covered {
    /// The parameter.
    pub name: Param,
    /// Trials whose model-based 68.27% interval (the profile's, else the
    /// Jacobian's) held the truth.
    pub in68: usize,
    /// Trials whose model-based 95% interval held the truth.
    pub in95: usize,
    /// Trials whose headline 68.27% and 95% intervals held the truth (the
    /// robust ones where formed, [`Source::Robust`]).
    pub headline: [usize; 2],
    /// Trials with a Jacobian standard deviation.
    pub with_sd: usize,
    /// Of those, trials whose estimate ± 1 sd held the truth.
    pub in_sd: usize,
}

/// The coverage of one (model, objective, noise).
#[derive(Debug, Clone, PartialEq)]
pub struct Coverage {
    /// The model fitted.
    pub model: Model,
    /// Trials run.
    pub trials: usize,
    /// Per parameter, in output order.
    pub parameters: Vec<Covered>,
    /// Trials with an estimate outside the box that was searched (never
    /// under the free objective).
    pub outside_box: usize,
}

impl Coverage {
    /// The headline intervals' rate of parameter `name` at level 0
    /// (68.27%) or 1 (95%).
    pub fn headline_rate(&self, name: Param, level: usize) -> Option<f64> {
        let p = self.parameters.iter().find(|p| p.name == name)?;
        Some(p.headline[level] as f64 / self.trials as f64)
    }

    /// The model-based rate of parameter `name` at `level` (0: 68.27%, 1: 95%).
    pub fn rate(&self, name: Param, level: usize) -> Option<f64> {
        let p = self.parameters.iter().find(|p| p.name == name)?;
        let n = if level == 0 { p.in68 } else { p.in95 };
        Some(n as f64 / self.trials as f64)
    }
}

/// The noise settings of the coverage tests (well-specified and
/// misspecified): σ = 0.01 on every measurement, estimated; and
/// σ = 0.003 + 0.03·P given to the fit.
pub const SETTINGS: [NoiseModel; 2] = [
    NoiseModel::Every(0.01),
    NoiseModel::Heteroscedastic {
        floor: 0.003,
        relative: 0.03,
    },
];

/// The 3σ binomial band of a rate whose nominal value is `p`, over
/// `trials` trials.
pub fn band(p: f64, trials: usize) -> (f64, f64) {
    let half = 3.0 * (p * (1.0 - p) / trials as f64).sqrt();
    (p - half, p + half)
}

/// Truths drawn uniformly from inside the searched box, away from its ends:
/// for the free objective σ/T log-uniform over [0.2, 5], β ∈ [0.15, 0.85],
/// n ∈ [1.15, 2.2], a ∈ [0.1, 0.9]; for the paper objective inside the
/// paper grid's range (σ/T ∈ [0.5, 3.5], β ∈ [0.2, 0.8], n ∈ [1.34, 1.46],
/// a ∈ [0.1, 0.9]); the baselines inside their grids.
pub fn draw(model: Model, objective: Objective, rng: &mut Noise) -> ModelParams {
    let mut u = |lo: f64, hi: f64| lo + (hi - lo) * rng.uniform();
    match model.family() {
        Family::Baseline(b) => {
            let [(x0, x1), (y0, y1)] = baseline_interior(b);
            let x = u(x0, x1);
            ModelParams::baseline(b, [x, u(y0, y1)])
        }
        Family::Layered {
            absorption, untied, ..
        } => {
            let (slope, beta, n) = match objective {
                Objective::Free => (
                    libm::exp(u(libm::log(0.2), libm::log(5.0))),
                    u(0.15, 0.85),
                    u(1.15, 2.2),
                ),
                Objective::Paper => (u(0.5, 3.5), u(0.2, 0.8), u(1.34, 1.46)),
            };
            let a = if absorption { u(0.1, 0.9) } else { 0.0 };
            // Drawn after the others, so that a tied model's truths are
            // those it always had.
            let sub_slope = untied.then(|| match objective {
                Objective::Free => libm::exp(u(libm::log(0.2), libm::log(5.0))),
                Objective::Paper => slope,
            });
            ModelParams::Layered {
                slope,
                beta,
                n,
                a,
                sub_slope,
            }
        }
    }
}

/// The noise-free data of `model` at `truth` on `angles` in the
/// parametrisation of `objective`, with max 1.
pub fn clean(
    model: Model,
    objective: Objective,
    truth: ModelParams,
    angles: &[Angles],
) -> Vec<f64> {
    let fitted = match objective {
        Objective::Paper => FittedModel::normalised_on(model, truth, angles, 1.0),
        Objective::Free => Ok(FittedModel::with_amplitude(model, truth, 1.0, 1.0)),
    };
    let mut p = fitted
        .and_then(|m| m.predict(angles))
        .expect("truths are drawn inside the domain");
    let peak = max_of(&p);
    p.iter_mut().for_each(|v| *v /= peak);
    p
}

/// A scene of `model` at `truth` ([`clean`]) on the 200 built-in geometries
/// with noise `noise` on every measurement.
pub fn noisy_scene(
    model: Model,
    objective: Objective,
    truth: ModelParams,
    noise: NoiseModel,
    rng: &mut Noise,
) -> Scene {
    noisy_scene_on(geometries(), model, objective, truth, noise, rng)
}

/// [`noisy_scene`] on the geometries `angles`.
pub fn noisy_scene_on(
    angles: Vec<Angles>,
    model: Model,
    objective: Objective,
    truth: ModelParams,
    noise: NoiseModel,
    rng: &mut Noise,
) -> Scene {
    let clean = clean(model, objective, truth, &angles);
    let sigma: Vec<f64> = clean
        .iter()
        .map(|&v| match noise {
            NoiseModel::Every(s) => s,
            NoiseModel::Heteroscedastic { floor, relative } => floor + relative * v,
        })
        .collect();
    let radiance: Vec<f64> = clean
        .iter()
        .zip(&sigma)
        .map(|(&v, &s)| v + s * rng.normal())
        .collect();
    let nonpositive = radiance.iter().filter(|&&v| v <= 0.0).count();
    let rows = (1..=angles.len()).collect();
    let given = matches!(noise, NoiseModel::Heteroscedastic { .. }).then_some(sigma);
    Scene::from_radiance(angles, radiance, rows, nonpositive, given)
}

/// `count` sets of `model` on the geometries `angles`, each at a truth
/// drawn from `seed` ([`draw`]) with `noise` ([`noisy_scene_on`]): the
/// many sets on one geometry of the free objective's batch benchmark and
/// of its profiling example.
pub fn noisy_sets(
    angles: &[Angles],
    model: Model,
    objective: Objective,
    noise: NoiseModel,
    count: usize,
    seed: u64,
) -> Vec<Scene> {
    let mut rng = Noise::new(seed);
    (0..count)
        .map(|_| {
            let truth = draw(model, objective, &mut rng);
            noisy_scene_on(angles.to_vec(), model, objective, truth, noise, &mut rng)
        })
        .collect()
}

/// A parameter's model-based intervals (68.27%, 95%): the profile's, else
/// the Jacobian's.
pub fn model_based(p: &Parameter) -> [Option<Interval>; 2] {
    let profile = p.intervals(Source::Profile);
    if profile[0].is_some() {
        profile
    } else {
        p.intervals(Source::Jacobian)
    }
}

/// Fits `trials` noisy scenes of `model` ([`noisy_scene`]; truths drawn
/// from `seed`, [`draw`]) with `fitter` and counts how often each
/// parameter's intervals contain the truth.
pub fn coverage(
    fitter: &Fitter,
    model: Model,
    trials: usize,
    noise: NoiseModel,
    seed: u64,
) -> Coverage {
    let objective = fitter.objective_of_fits();
    let mut rng = Noise::new(seed);
    let cases: Vec<(ModelParams, Scene)> = (0..trials)
        .map(|_| {
            let truth = draw(model, objective, &mut rng);
            (truth, noisy_scene(model, objective, truth, noise, &mut rng))
        })
        .collect();
    let scenes: Vec<Scene> = cases.iter().map(|c| c.1.clone()).collect();
    let fits = fitter.fit_batch(&scenes, model);
    let mut parameters: Vec<Covered> = Vec::new();
    let outside_box = fits
        .iter()
        .filter(|f| {
            f.parameters.iter().any(|p| {
                p.bounds
                    .is_some_and(|(lo, hi)| !(lo..=hi).contains(&p.value()))
            })
        })
        .count();
    for ((truth, _), fit) in cases.iter().zip(&fits) {
        for p in &fit.parameters {
            let t = truth.value(p.name).expect("the model's parameter");
            let slot = match parameters.iter().position(|q| q.name == p.name) {
                Some(i) => i,
                None => {
                    parameters.push(Covered {
                        name: p.name,
                        in68: 0,
                        in95: 0,
                        headline: [0; 2],
                        with_sd: 0,
                        in_sd: 0,
                    });
                    parameters.len() - 1
                }
            };
            let c = &mut parameters[slot];
            let holds = |i: Option<Interval>| i.is_some_and(|i| i.lo <= t && t <= i.hi);
            let [m68, m95] = model_based(p);
            c.in68 += usize::from(holds(m68));
            c.in95 += usize::from(holds(m95));
            c.headline[0] += usize::from(holds(p.interval68));
            c.headline[1] += usize::from(holds(p.interval95));
            if let Some(sd) = p.sd {
                c.with_sd += 1;
                c.in_sd += usize::from((p.value() - t).abs() <= sd);
            }
        }
    }
    Coverage {
        model,
        trials,
        parameters,
        outside_box,
    }
}
