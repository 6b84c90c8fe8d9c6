//! Fitting a scene with a model: the layered models by the grid search of
//! [`crate::search`], the baselines by their own grids (docs/conventions.md §7).

use crate::covariance::Covariance;
use crate::error::{FitError, ModelError};
use crate::fitted::{FittedModel, ModelParams};
use crate::grid::{Axis, Grid};
use crate::model::Model;
use crate::objective::Objective;
use crate::scene::Scene;
use crate::search::batch::{search_batch, share_geometry};
use crate::search::{grid_profile, point, search, GridProfile, Method, Path, SearchResult};
use crate::uncertainty::{
    analyse, cutoffs, profile_curves, Analysed, Analysis, Parameter, ProfileCurve, Searched,
};
use laminar_core::baselines::jensen::{jensen_radiance, JensenCoefficients, JensenGeometry};
use laminar_core::baselines::oren_nayar::{
    oren_nayar_radiance, OrenNayarCoefficients, OrenNayarGeometry,
};
use laminar_core::{chi_square_per_dof, normalise_by_max, rms_error, Angles, ChiSquare};
use rayon::prelude::*;
use std::sync::Arc;

/// A fitted model with its error measures on the scene it was fitted to
/// (computed in f64 from [`FittedModel::predict`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Estimate {
    /// The fitted model, portable.
    pub fitted: FittedModel,
    /// `Δ_RMS = 100·sqrt(Σ(D−P)²)/K` (eq. 15).
    pub rms: f64,
    /// `χ²/ν` (eq. 16), when there are degrees of freedom left.
    pub chi2: Option<ChiSquare<f64>>,
}

impl Estimate {
    /// Normalises `model` at `params` on `scene` and measures its error there.
    ///
    /// # Errors
    /// [`ModelError`] when the parameters are outside their domain or not the model's.
    pub fn new(scene: &Scene, model: Model, params: ModelParams) -> Result<Self, ModelError> {
        let fitted = FittedModel::normalised_on(model, params, &scene.angles, scene.data_scale)?;
        let prediction = fitted.predict(&scene.angles)?;
        Ok(Self {
            fitted,
            rms: rms_error(&scene.data, &prediction).unwrap_or(f64::NAN),
            chi2: chi_square_per_dof(&scene.data, &prediction, model.parameter_count()).ok(),
        })
    }

    /// The error measures of `fitted` on `scene`, `p` fitted parameters
    /// counted in χ²/ν.
    ///
    /// # Errors
    /// [`ModelError`] when the parameters are outside their domain or not the model's.
    pub fn of_fitted(scene: &Scene, fitted: FittedModel, p: usize) -> Result<Self, ModelError> {
        let prediction = fitted.predict(&scene.angles)?;
        Ok(Self {
            fitted,
            rms: rms_error(&scene.data, &prediction).unwrap_or(f64::NAN),
            chi2: chi_square_per_dof(&scene.data, &prediction, p).ok(),
        })
    }

    /// The parameters.
    pub fn params(&self) -> &ModelParams {
        &self.fitted.params
    }

    /// `name=value` pairs joined by `;` (the `params` column).
    pub fn params_text(&self) -> String {
        self.fitted.params.text()
    }

    /// The value of a named parameter.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.fitted.params.get(name)
    }
}

/// The result of fitting one (sample, channel, model).
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    /// Sample label ([`Scene::sample`]).
    pub sample: String,
    /// Channel name ([`Scene::channel`]).
    pub channel: String,
    /// Model fitted.
    pub model: Model,
    /// The best estimate.
    pub best: Estimate,
    /// For `exp` and `gauss`: the Ragheb–Hancock best of the same search (a = 0 slice).
    pub rh: Option<Estimate>,
    /// The search's own Δ_RMS at the best point (search precision).
    pub search_rms: f64,
    /// Kept measurements K.
    pub measurements: usize,
    /// Kept measurements with zero or negative value (docs/conventions.md §8).
    pub nonpositive: usize,
    /// Parameter sets evaluated.
    pub evaluated: usize,
    /// The refined estimate ([`crate::refine`]), when refined: never a
    /// larger Δ_RMS than `best`, the grid's.
    pub refined: Option<Estimate>,
    /// Each searched parameter: grid value, refined value, intervals and
    /// edge flags ([`crate::uncertainty`]); empty when nothing was searched
    /// ([`Fitter::assess`]).
    pub parameters: Vec<Parameter>,
    /// The Jacobian's covariance and correlations at the refined optimum
    /// (when asked for and no parameter is at a bound of its domain).
    pub covariance: Option<Covariance>,
    /// The objective minimised.
    pub objective: Objective,
    /// Free-amplitude fits: the fitted amplitude `c` of the estimate
    /// (prediction `c · M` on the data divided by their max).
    pub amplitude: Option<f64>,
    /// Free-amplitude fits: the weighted `χ²/ν = Σ w (D − P)²/(K − p)` of
    /// the estimate, `w = 1/σ²` (1 without uncertainties), p counting the
    /// amplitude.
    pub chi2_weighted: Option<f64>,
}

impl Fit {
    /// The estimate to use: the refined one when there is one, else the grid's.
    pub fn estimate(&self) -> &Estimate {
        self.refined.as_ref().unwrap_or(&self.best)
    }

    /// The estimate a fit's main columns report (`rms`, `chi2_dof`,
    /// `params`): the paper objective's best grid point, as in the paper's
    /// tables; the free objective's [`Fit::estimate`] (its grid only places
    /// the starts of the refinement).
    pub fn reported(&self) -> &Estimate {
        match self.objective {
            Objective::Paper => &self.best,
            Objective::Free => self.estimate(),
        }
    }
}

/// Baseline grids (docs/conventions.md §7): σa, σs′ ∈ {0.01, …, 1.00}.
pub fn jensen_grid() -> (Axis, Axis) {
    (
        Axis::stepped(0.01, 0.01, 100),
        Axis::stepped(0.01, 0.01, 100),
    )
}

/// Oren–Nayar grid (docs/conventions.md §7): σ = 0.01 s (s = 0..100), ρ = 0.02 r (r = 1..50).
pub fn oren_nayar_grid() -> (Axis, Axis) {
    (Axis::stepped(0.0, 0.01, 101), Axis::stepped(0.02, 0.02, 50))
}

/// Exhaustive 2-D search in f64 of a max-normalised baseline; ties keep the
/// first point in row-major order. The best (Δ_RMS, x, y) and every
/// point's Δ_RMS in row-major order.
fn grid2<G: Sync, K>(
    scene: &Scene,
    outer: &Axis,
    inner: &Axis,
    geometry: &[G],
    coefficients: impl Fn(f64, f64) -> K + Sync,
    radiance: impl Fn(&G, &K) -> f64 + Sync,
) -> ((f64, f64, f64), Vec<f64>) {
    let rows: Vec<Vec<f64>> = outer
        .values
        .par_iter()
        .map(|&x| {
            inner
                .values
                .iter()
                .map(|&y| {
                    let k = coefficients(x, y);
                    let mut p: Vec<f64> = geometry.iter().map(|g| radiance(g, &k)).collect();
                    normalise_by_max(&mut p);
                    rms_error(&scene.data, &p).unwrap_or(f64::INFINITY)
                })
                .collect()
        })
        .collect();
    let surface: Vec<f64> = rows.concat();
    // Starting from the first point keeps the result a grid point even if
    // no error is finite.
    let mut best = (surface[0], 0);
    for (i, &rms) in surface.iter().enumerate() {
        if rms < best.0 {
            best = (rms, i);
        }
    }
    let (x, y) = (
        outer.values[best.1 / inner.len()],
        inner.values[best.1 % inner.len()],
    );
    ((best.0, x, y), surface)
}

/// The [`GridProfile`] of a full surface of Δ_RMS over axes of lengths
/// `lens` (row-major), on `k` measurements, to the cutoffs `(profile, near)`
/// on the objective `Σ (D − P)²`.
fn profile_of(
    surface: &[f64],
    lens: [usize; 2],
    k: usize,
    (cutoff, near): (f64, f64),
) -> GridProfile {
    let mut axes: Vec<Vec<(f64, usize)>> = lens
        .iter()
        .map(|&len| vec![(f64::INFINITY, usize::MAX); len])
        .collect();
    let mut near_points = Vec::new();
    for (flat, &rms) in surface.iter().enumerate() {
        let e = sum_of_rms(rms, k);
        if e > cutoff {
            continue;
        }
        for (axis, i) in axes.iter_mut().zip([flat / lens[1], flat % lens[1]]) {
            if e < axis[i].0 {
                axis[i] = (e, flat);
            }
        }
        if e <= near {
            near_points.push((flat, e));
        }
    }
    GridProfile {
        axes,
        near: near_points,
        cutoff,
    }
}

/// `Σ (D − P)²` from `Δ_RMS = 100·sqrt(Σ(D − P)²)/K` (eq. 15).
fn sum_of_rms(rms: f64, k: usize) -> f64 {
    let root = rms * k as f64 / 100.0;
    root * root
}

type Progress = Arc<dyn Fn() + Send + Sync>;

/// Most worker threads a [`Fitter`] starts.
pub const MAX_THREADS: usize = 1024;

/// Fits scenes: the grid, the search path, the worker threads and a progress
/// callback, set once.
///
/// ```
/// use laminar_core::{Correlation, Params};
/// use laminar_fit::{synthetic, Axis, Fitter, Grid, Model};
/// // Noise-free synthetic data from the exp model.
/// let truth = Params::new(1.48, 0.39, 1.44, 0.17)?;
/// let scene = synthetic::scene(Correlation::Exponential, &truth, 0.0, 1);
/// let grid = Grid {
///     slope: Axis::stepped(1.32, 0.08, 5),
///     a: Axis::stepped(0.13, 0.01, 9),
///     ..Grid::paper()
/// };
/// let fit = Fitter::new(grid)?.threads(1)?.fit(&scene, Model::Exp);
/// assert_eq!(fit.best.params_text(), "slope=1.48;beta=0.39;n=1.44;a=0.17");
/// assert!(fit.best.rms < 1e-6);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone)]
pub struct Fitter {
    grid: Grid,
    path: Path,
    pool: Option<Arc<rayon::ThreadPool>>,
    progress: Option<Progress>,
    analysis: Analysis,
    objective: Objective,
}

impl Fitter {
    /// A fitter on `grid` (validated: [`Grid::validate`]) with the default
    /// search path, all cores, no progress callback, refinement and both
    /// uncertainties ([`Analysis::FULL`]).
    ///
    /// # Errors
    /// [`FitError::Grid`] when the grid fails [`Grid::validate`].
    pub fn new(grid: Grid) -> Result<Self, FitError> {
        grid.validate()?;
        Ok(Self {
            grid,
            path: Path::DEFAULT,
            pool: None,
            progress: None,
            analysis: Analysis::FULL,
            objective: Objective::Paper,
        })
    }

    /// The objective every fit minimises (default [`Objective::Paper`] for
    /// [`Fitter::new`]; front ends choose [`Objective::Free`] for a user's
    /// data, on [`Grid::user`]).
    pub fn objective(mut self, objective: Objective) -> Self {
        self.objective = objective;
        self
    }

    /// The objective of the fits.
    pub fn objective_of_fits(&self) -> Objective {
        self.objective
    }

    /// What each fit does after its grid search (default [`Analysis::FULL`]).
    pub fn analysis(mut self, analysis: Analysis) -> Self {
        self.analysis = analysis;
        self
    }

    /// The analysis after the grid search.
    pub fn analysis_of_fits(&self) -> Analysis {
        self.analysis
    }

    /// The search path of the layered models (default [`Path::DEFAULT`]).
    pub fn path(mut self, path: Path) -> Self {
        self.path = path;
        self
    }

    /// Runs every fit on `threads` worker threads, 1 to [`MAX_THREADS`]
    /// (default: rayon's global pool, all cores). Results do not depend on it.
    ///
    /// # Errors
    /// [`FitError::Threads`] for 0, more than [`MAX_THREADS`], or threads
    /// the system will not start.
    pub fn threads(mut self, threads: usize) -> Result<Self, FitError> {
        let error = |message: String| FitError::Threads { threads, message };
        if threads == 0 {
            return Err(error("at least one thread is needed".into()));
        }
        if threads > MAX_THREADS {
            return Err(error(format!("at most {MAX_THREADS} are allowed")));
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| error(e.to_string()))?;
        self.pool = Some(Arc::new(pool));
        Ok(self)
    }

    /// Calls `progress` once per finished search shard ([`Fitter::shards`] per fit).
    pub fn on_progress(mut self, progress: impl Fn() + Send + Sync + 'static) -> Self {
        self.progress = Some(Arc::new(progress));
        self
    }

    /// The grid.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// The search path.
    pub fn search_path(&self) -> Path {
        self.path
    }

    /// Progress calls per fit of `model`: one per σ/T value for the layered
    /// models, one for a baseline.
    pub fn shards(&self, model: Model) -> u64 {
        if model.correlation().is_some() && self.objective == Objective::Paper {
            self.grid.slope.len() as u64
        } else {
            1
        }
    }

    fn run<T: Send>(&self, work: impl FnOnce() -> T + Send) -> T {
        match &self.pool {
            Some(pool) => pool.install(work),
            None => work(),
        }
    }

    fn tick(&self) {
        if let Some(p) = &self.progress {
            p();
        }
    }

    /// Fits `model` to `scene`. Layered models search the grid (a fixed at 0
    /// for the Ragheb–Hancock variants) on the fitter's path; the baselines
    /// search their own grids ([`jensen_grid`], [`oren_nayar_grid`]).
    pub fn fit(&self, scene: &Scene, model: Model) -> Fit {
        self.run(|| self.fit_here(scene, model))
    }

    /// Fits every model of `models` to every scene, in order (scene-major).
    pub fn fit_all(&self, scenes: &[Scene], models: &[Model]) -> Vec<Fit> {
        scenes
            .iter()
            .flat_map(|s| models.iter().map(move |&m| (s, m)))
            .map(|(s, m)| self.fit(s, m))
            .collect()
    }

    /// The fit record of `model` at given parameters, without a search (e.g.
    /// a data set's own Oren–Nayar parameters, docs/conventions.md §7).
    ///
    /// # Errors
    /// [`FitError::Model`] when the parameters are outside their domain or not the model's.
    pub fn assess(
        &self,
        scene: &Scene,
        model: Model,
        params: ModelParams,
    ) -> Result<Fit, FitError> {
        let best = Estimate::new(scene, model, params)?;
        self.tick();
        Ok(Fit {
            search_rms: best.rms,
            ..self.record(scene, model, best, None, 1)
        })
    }

    fn record(
        &self,
        scene: &Scene,
        model: Model,
        best: Estimate,
        rh: Option<Estimate>,
        evaluated: usize,
    ) -> Fit {
        Fit {
            sample: scene.sample.clone(),
            channel: scene.channel.clone(),
            model,
            search_rms: best.rms,
            best,
            rh,
            measurements: scene.len(),
            nonpositive: scene.nonpositive,
            evaluated,
            refined: None,
            parameters: Vec::new(),
            covariance: None,
            objective: Objective::Paper,
            amplitude: None,
            chi2_weighted: None,
        }
    }

    /// The fit record of a search's best `best` and the analysis of it.
    #[allow(clippy::too_many_arguments)]
    fn analysed_fit(
        &self,
        scene: &Scene,
        model: Model,
        best: Estimate,
        rh: Option<Estimate>,
        (search_rms, evaluated): (f64, usize),
        searched: &[Searched],
        profile: Option<(&GridProfile, &[usize])>,
    ) -> Fit {
        let Analysed {
            refined,
            parameters,
            covariance,
        } = analyse(
            scene,
            model,
            (&best, rh.as_ref()),
            searched,
            profile,
            self.analysis,
        );
        Fit {
            search_rms,
            refined,
            parameters,
            covariance,
            ..self.record(scene, model, best, rh, evaluated)
        }
    }

    /// The profile cutoffs of a fit whose grid best is `best`, when the
    /// analysis needs the grid's profile.
    fn profile_cutoffs(&self, scene: &Scene, model: Model, best: &Estimate) -> Option<(f64, f64)> {
        if !self.analysis.needs_profile() {
            return None;
        }
        let free = model.parameter_count();
        cutoffs(scene, sum_of_rms(best.rms, scene.len()), free)
    }

    /// The grid a layered model searches: a = 0 only for Ragheb–Hancock.
    fn model_grid(&self, model: Model) -> Grid {
        if model.is_ragheb_hancock() {
            self.grid.ragheb_hancock()
        } else {
            self.grid.clone()
        }
    }

    /// The fit record of a layered model's search result.
    fn layered_fit(&self, scene: &Scene, model: Model, grid: &Grid, r: &SearchResult) -> Fit {
        let estimate =
            |model, params| Estimate::new(scene, model, params).expect("grid values are validated");
        let layered = |flat| {
            let (slope, n, a, beta) = point(grid, flat);
            ModelParams::Layered { slope, beta, n, a }
        };
        let best = estimate(model, layered(r.best));
        let rh = model
            .ragheb_hancock()
            .zip(r.rh_best)
            .map(|(rh_model, (flat, _))| estimate(rh_model, layered(flat)));
        let searched = layered_searched(grid, r.best);
        let lens = [
            grid.slope.len(),
            grid.n.len(),
            grid.a.len(),
            grid.beta.len(),
        ];
        let corr = model.correlation().expect("a layered model");
        let profile = self
            .profile_cutoffs(scene, model, &best)
            .map(|(cutoff, near)| {
                grid_profile(scene, grid, corr, self.path, cutoff, near)
                    .expect("the grid was validated by Fitter::new")
            });
        self.analysed_fit(
            scene,
            model,
            best,
            rh,
            (r.best_rms, grid.size()),
            &searched,
            profile.as_ref().map(|p| (p, &lens[..])),
        )
    }

    /// The profile of each parameter of `fit` (a fit of a layered model to
    /// `scene` by this fitter, with profile intervals) for a figure: the
    /// grid's profile and the continuous one at `points` values
    /// ([`ProfileCurve`]). Empty for the baselines, or without intervals.
    pub fn profiles(&self, scene: &Scene, fit: &Fit, points: usize) -> Vec<ProfileCurve> {
        if fit.objective != Objective::Paper {
            return Vec::new();
        }
        let Some(corr) = fit.model.correlation() else {
            return Vec::new();
        };
        let grid = self.model_grid(fit.model);
        let Some(flat) = grid_index(&grid, fit.best.params()) else {
            return Vec::new();
        };
        let searched = layered_searched(&grid, flat);
        let Some((cutoff, near)) = self.profile_cutoffs(scene, fit.model, &fit.best) else {
            return Vec::new();
        };
        self.run(|| {
            let profile = grid_profile(scene, &grid, corr, self.path, cutoff, near)
                .expect("the grid was validated by Fitter::new");
            profile_curves(scene, fit, &searched, &profile, points)
        })
    }

    /// Progress calls of [`Fitter::fit_batch`] on `scenes` with `model`.
    pub fn batch_shards(&self, scenes: &[Scene], model: Model) -> u64 {
        if self.batches(scenes, model) {
            self.shards(model)
        } else {
            scenes.len() as u64 * self.shards(model)
        }
    }

    /// True when [`Fitter::fit_batch`] runs one batch search.
    fn batches(&self, scenes: &[Scene], model: Model) -> bool {
        self.objective == Objective::Paper
            && model.correlation().is_some()
            && self.path.method == Method::Envelope
            && share_geometry(scenes)
    }

    /// Fits `model` to every scene of `scenes`. Under the free objective the
    /// scenes are fitted in parallel, sharing the grid stage's model side
    /// when they are on one geometry without uncertainties
    /// ([`crate::free::fit_batch`]); under the paper's: when the scenes share their
    /// geometry ([`share_geometry`]), the model is layered and the path is
    /// the envelope method, one batch search does the model-side work once
    /// for all of them ([`crate::search::batch`]); otherwise each scene is
    /// fitted alone. Either way every fit is bit for bit [`Fitter::fit`]'s.
    /// Progress: [`Fitter::shards`] calls for the whole batch, or per scene
    /// when fitted alone. Memory grows with the number of scenes: pass large
    /// collections (pixels of a texture) in blocks.
    ///
    /// ```
    /// use laminar_core::{Correlation, Params};
    /// use laminar_fit::{synthetic, Axis, Fitter, Grid, Model};
    /// let scenes: Vec<_> = (0..3)
    ///     .map(|seed| synthetic::scene(Correlation::Exponential, &Params::new(1.48, 0.39, 1.44, 0.2).unwrap(), 0.01, seed))
    ///     .collect();
    /// let grid = Grid { slope: Axis::stepped(1.32, 0.08, 5), a: Axis::stepped(0.0, 0.1, 5), ..Grid::paper() };
    /// let fitter = Fitter::new(grid)?;
    /// let batch = fitter.fit_batch(&scenes, Model::Exp);
    /// for (scene, fit) in scenes.iter().zip(&batch) {
    ///     assert_eq!(fit, &fitter.fit(scene, Model::Exp));
    /// }
    /// # Ok::<(), laminar_fit::FitError>(())
    /// ```
    pub fn fit_batch(&self, scenes: &[Scene], model: Model) -> Vec<Fit> {
        match model.correlation() {
            Some(corr) if self.batches(scenes, model) => {
                let grid = self.model_grid(model);
                let tick = || self.tick();
                let results = self.run(|| {
                    search_batch(scenes, &grid, corr, self.path.arith, &tick)
                        .expect("the grid was validated by Fitter::new")
                });
                self.run(|| {
                    scenes
                        .par_iter()
                        .zip(&results)
                        .map(|(scene, r)| self.layered_fit(scene, model, &grid, r))
                        .collect()
                })
            }
            _ if self.objective == Objective::Free => {
                let tick = || self.tick();
                self.run(|| crate::free::fit_batch(scenes, model, &self.grid, self.analysis, &tick))
            }
            _ => scenes.iter().map(|s| self.fit(s, model)).collect(),
        }
    }

    fn fit_here(&self, scene: &Scene, model: Model) -> Fit {
        if self.objective == Objective::Free {
            let fit = crate::free::fit(scene, model, &self.grid, self.analysis);
            self.tick();
            return fit;
        }
        let tick = || self.tick();
        match model.correlation() {
            Some(corr) => {
                let grid = self.model_grid(model);
                let r = search(scene, &grid, corr, self.path, &tick)
                    .expect("the grid was validated by Fitter::new");
                self.layered_fit(scene, model, &grid, &r)
            }
            None if model == Model::Jensen => self.baseline(
                scene,
                model,
                jensen_grid(),
                |a| JensenGeometry::from_lanes(|_| *a),
                |x, y| JensenCoefficients::<f64>::new(x, y).expect("grid in domain"),
                jensen_radiance,
                |sigma_a, sigma_s| ModelParams::Jensen { sigma_a, sigma_s },
            ),
            None => self.baseline(
                scene,
                model,
                oren_nayar_grid(),
                |a| OrenNayarGeometry::from_lanes(|_| *a),
                |x, y| OrenNayarCoefficients::<f64>::new(x, y).expect("grid in domain"),
                oren_nayar_radiance,
                |sigma, rho| ModelParams::OrenNayar { sigma, rho },
            ),
        }
    }

    /// A baseline's fit: its geometry once per measurement, then the 2-D
    /// grid search of its max-normalised radiance (docs/conventions.md §7).
    #[allow(clippy::too_many_arguments)]
    fn baseline<G: Sync, K>(
        &self,
        scene: &Scene,
        model: Model,
        (outer, inner): (Axis, Axis),
        geometry: impl Fn(&Angles) -> G,
        coefficients: impl Fn(f64, f64) -> K + Sync,
        radiance: impl Fn(&G, &K) -> f64 + Sync,
        params: impl Fn(f64, f64) -> ModelParams,
    ) -> Fit {
        let geometry: Vec<G> = scene.angles.iter().map(geometry).collect();
        let ((rms, x, y), surface) =
            grid2(scene, &outer, &inner, &geometry, coefficients, radiance);
        let best =
            Estimate::new(scene, model, params(x, y)).expect("grid values are in the domain");
        let names: Vec<&'static str> = best.fitted.params.pairs().iter().map(|p| p.0).collect();
        let searched = [
            Searched {
                axis: 0,
                name: names[0],
                value: x,
                values: &outer,
            },
            Searched {
                axis: 1,
                name: names[1],
                value: y,
                values: &inner,
            },
        ];
        let lens = [outer.len(), inner.len()];
        let profile = self
            .profile_cutoffs(scene, model, &best)
            .map(|cut| profile_of(&surface, lens, scene.len(), cut));
        let fit = self.analysed_fit(
            scene,
            model,
            best,
            None,
            (rms, outer.len() * inner.len()),
            &searched,
            profile.as_ref().map(|p| (p, &lens[..])),
        );
        self.tick();
        fit
    }
}

/// The flat index of a layered model's grid point.
fn grid_index(grid: &Grid, params: &ModelParams) -> Option<usize> {
    let ModelParams::Layered { slope, beta, n, a } = *params else {
        return None;
    };
    let at = |axis: &Axis, v: f64| axis.values.iter().position(|&x| x == v);
    Some(grid.flat(
        at(&grid.slope, slope)?,
        at(&grid.n, n)?,
        at(&grid.a, a)?,
        at(&grid.beta, beta)?,
    ))
}

/// The searched axes of a layered grid at its point `flat` (an axis of one
/// value is not searched).
fn layered_searched(grid: &Grid, flat: usize) -> Vec<Searched<'_>> {
    let (slope, n, a, beta) = point(grid, flat);
    [
        (0, "slope", slope, &grid.slope),
        (1, "n", n, &grid.n),
        (2, "a", a, &grid.a),
        (3, "beta", beta, &grid.beta),
    ]
    .into_iter()
    .filter(|s| s.3.len() > 1)
    .map(|(axis, name, value, values)| Searched {
        axis,
        name,
        value,
        values,
    })
    .collect()
}
