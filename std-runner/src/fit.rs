//! Fitting one scene with one model: the layered models by the grid search
//! of [`crate::search`], the baselines by their own grids (conventions §7).

use crate::data::Channel;
use crate::grid::{Axis, Grid};
use crate::model::{predict_jensen, predict_layered, predict_oren_nayar, Model};
use crate::scene::Scene;
use crate::search::{point, search, Path};
use crate::selection::Job;
use laminar_core::baselines::jensen::{JensenCoefficients, JensenGeometry};
use laminar_core::baselines::oren_nayar::{OrenNayarCoefficients, OrenNayarGeometry};
use laminar_core::{chi_square_per_dof, rms_error, ChiSquare, Params};
use rayon::prelude::*;

/// A fitted parameter set with its error measures (computed in f64).
#[derive(Debug, Clone, PartialEq)]
pub struct Estimate {
    /// Parameter names and values, in output order.
    pub params: Vec<(&'static str, f64)>,
    /// `Δ_RMS` (eq. 15) of the f64 prediction at these parameters.
    pub rms: f64,
    /// `χ²/ν` (eq. 16), when there are degrees of freedom left.
    pub chi2: Option<ChiSquare<f64>>,
}

impl Estimate {
    fn new(scene: &Scene, params: Vec<(&'static str, f64)>, prediction: &[f64], p: usize) -> Self {
        Self {
            params,
            rms: rms_error(&scene.data, prediction).unwrap_or(f64::NAN),
            chi2: chi_square_per_dof(&scene.data, prediction, p).ok(),
        }
    }

    /// `name=value` pairs joined by `;`.
    pub fn params_text(&self) -> String {
        self.params
            .iter()
            .map(|(k, v)| format!("{k}={}", format_value(*v)))
            .collect::<Vec<_>>()
            .join(";")
    }

    /// The value of a named parameter.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.params
            .iter()
            .find(|(k, _)| *k == name)
            .map(|(_, v)| *v)
    }
}

/// A value without float noise (rounded to 10 decimals).
pub fn format_value(v: f64) -> String {
    let r = (v * 1e10).round() / 1e10;
    format!("{}", if r == 0.0 { 0.0 } else { r })
}

/// The result of fitting one (sample, channel, model).
#[derive(Debug, Clone, PartialEq)]
pub struct FitRecord {
    /// Sample label (CUReT sample number, or `synthetic`).
    pub sample: String,
    /// Colour channel.
    pub channel: Channel,
    /// Model fitted.
    pub model: Model,
    /// The best estimate.
    pub best: Estimate,
    /// For `exp` and `gauss`: the Ragheb–Hancock best of the same search (a = 0 slice).
    pub rh: Option<Estimate>,
    /// The search's own RMS at the best point (search precision).
    pub search_rms: f64,
    /// Kept measurements K.
    pub measurements: usize,
    /// Kept measurements with zero or negative BRDF (conventions §8).
    pub nonpositive: usize,
    /// Parameter sets evaluated.
    pub evaluated: usize,
}

fn layered_estimate(scene: &Scene, model: Model, grid: &Grid, flat: usize) -> Estimate {
    let (slope, n, a, beta) = point(grid, flat);
    let p = Params::new(slope, beta, n, a).expect("grid validated");
    let corr = model.correlation().expect("layered model");
    let prediction = predict_layered(scene, corr, &p);
    let params = vec![("slope", slope), ("beta", beta), ("n", n), ("a", a)];
    Estimate::new(scene, params, &prediction, model.parameter_count())
}

/// Baseline grids (conventions §7).
pub fn jensen_grid() -> (Axis, Axis) {
    (
        Axis::stepped(0.01, 0.01, 100),
        Axis::stepped(0.01, 0.01, 100),
    )
}

/// Oren–Nayar grid (conventions §7): σ = 0.01 s (s = 0..100), ρ = 0.02 r (r = 1..50).
pub fn oren_nayar_grid() -> (Axis, Axis) {
    (Axis::stepped(0.0, 0.01, 101), Axis::stepped(0.02, 0.02, 50))
}

/// Jensen geometry of every kept measurement.
fn jensen_geometry(scene: &Scene) -> Vec<JensenGeometry<f64>> {
    scene
        .angles
        .iter()
        .map(|a| JensenGeometry::from_lanes(|_| *a))
        .collect()
}

/// Oren–Nayar geometry of every kept measurement.
fn oren_nayar_geometry(scene: &Scene) -> Vec<OrenNayarGeometry<f64>> {
    scene
        .angles
        .iter()
        .map(|a| OrenNayarGeometry::from_lanes(|_| *a))
        .collect()
}

/// The f64 normalised prediction of `model` at `estimate` (for plots).
pub fn prediction(scene: &Scene, model: Model, estimate: &Estimate) -> Vec<f64> {
    let get = |name| estimate.get(name).unwrap_or(0.0);
    match model.correlation() {
        Some(corr) => match Params::new(get("slope"), get("beta"), get("n"), get("a")) {
            Ok(p) => predict_layered(scene, corr, &p),
            Err(_) => vec![0.0; scene.len()],
        },
        None if model == Model::Jensen => {
            let geometry = jensen_geometry(scene);
            match JensenCoefficients::<f64>::new(get("sigma_a"), get("sigma_s")) {
                Ok(k) => predict_jensen(&geometry, &k),
                Err(_) => vec![0.0; scene.len()],
            }
        }
        None => {
            let geometry = oren_nayar_geometry(scene);
            match OrenNayarCoefficients::<f64>::new(get("sigma"), get("rho")) {
                Ok(k) => predict_oren_nayar(&geometry, &k),
                Err(_) => vec![0.0; scene.len()],
            }
        }
    }
}

/// Exhaustive 2-D search in f64; ties keep the first point in row-major order.
fn grid2<G: Sync>(
    scene: &Scene,
    outer: &Axis,
    inner: &Axis,
    geometry: &[G],
    predict: impl Fn(&[G], f64, f64) -> Vec<f64> + Sync,
) -> (f64, f64, f64) {
    let rows: Vec<(f64, f64, f64)> = outer
        .values
        .par_iter()
        .map(|&x| {
            let mut best = (f64::INFINITY, x, inner.values[0]);
            for &y in &inner.values {
                let rms = rms_error(&scene.data, &predict(geometry, x, y)).unwrap_or(f64::INFINITY);
                if rms < best.0 {
                    best = (rms, x, y);
                }
            }
            best
        })
        .collect();
    rows.into_iter().fold(
        (f64::INFINITY, 0.0, 0.0),
        |b, r| if r.0 < b.0 { r } else { b },
    )
}

/// Fits `model` to `scene`. Layered models use `grid` (a fixed at 0 for the
/// Ragheb–Hancock variants) on `path`; `progress` is called once per shard.
pub fn fit(
    job: &Job,
    model: Model,
    grid: &Grid,
    path: Path,
    progress: &(dyn Fn() + Sync),
) -> FitRecord {
    let scene = &job.scene;
    let record = |best, rh, search_rms, evaluated| FitRecord {
        sample: job.sample.clone(),
        channel: job.channel,
        model,
        best,
        rh,
        search_rms,
        measurements: scene.len(),
        nonpositive: scene.nonpositive,
        evaluated,
    };
    match model {
        Model::Exp | Model::Gauss | Model::RhExp | Model::RhGauss => {
            let grid = if model.is_ragheb_hancock() {
                grid.ragheb_hancock()
            } else {
                grid.clone()
            };
            let corr = model.correlation().expect("layered model");
            let r = search(scene, &grid, corr, path, progress);
            let best = layered_estimate(scene, model, &grid, r.best);
            let rh = if model.is_ragheb_hancock() {
                None
            } else {
                r.rh_best.map(|(flat, _)| {
                    let rh_model = if model == Model::Exp {
                        Model::RhExp
                    } else {
                        Model::RhGauss
                    };
                    layered_estimate(scene, rh_model, &grid, flat)
                })
            };
            record(best, rh, r.best_rms, grid.size())
        }
        Model::Jensen => {
            let geometry = jensen_geometry(scene);
            let (sa, ss) = jensen_grid();
            let coefficients = |x, y| JensenCoefficients::<f64>::new(x, y).expect("grid in domain");
            let (rms, x, y) = grid2(scene, &sa, &ss, &geometry, |g, x, y| {
                predict_jensen(g, &coefficients(x, y))
            });
            let prediction = predict_jensen(&geometry, &coefficients(x, y));
            let best = Estimate::new(scene, vec![("sigma_a", x), ("sigma_s", y)], &prediction, 2);
            progress();
            record(best, None, rms, sa.len() * ss.len())
        }
        Model::OrenNayar => {
            let geometry = oren_nayar_geometry(scene);
            let coefficients =
                |x, y| OrenNayarCoefficients::<f64>::new(x, y).expect("validated domain");
            let (rms, x, y, evaluated) = match job.oren_nayar {
                // The data set's own parameters (conventions §7): nothing to search.
                Some(given) => {
                    let p = predict_oren_nayar(&geometry, &coefficients(given.sigma, given.rho));
                    let rms = rms_error(&scene.data, &p).unwrap_or(f64::NAN);
                    (rms, given.sigma, given.rho, 1)
                }
                None => {
                    let (sigma, rho) = oren_nayar_grid();
                    let (rms, x, y) = grid2(scene, &sigma, &rho, &geometry, |g, x, y| {
                        predict_oren_nayar(g, &coefficients(x, y))
                    });
                    (rms, x, y, sigma.len() * rho.len())
                }
            };
            let prediction = predict_oren_nayar(&geometry, &coefficients(x, y));
            let best = Estimate::new(scene, vec![("sigma", x), ("rho", y)], &prediction, 2);
            progress();
            record(best, None, rms, evaluated)
        }
    }
}
