//! Fitting a scene with a model: [`Fitter`] holds the settings and the
//! worker threads, and dispatches each fit to the pipeline of its objective
//! (docs/conventions.md §11): `crate::free::driver` (the default) or
//! `crate::paper::driver`. Both end in a [`Fit`] ([`crate::report`]).

use crate::analysis::Analysis;
use crate::error::{FitError, JointError};
use crate::estimate::Estimate;
use crate::fitted::ModelParams;
use crate::free::joint::JointFit;
use crate::grid::Grid;
use crate::model::Model;
use crate::noise::Noise;
use crate::objective::Objective;
use crate::paper::profiles::ProfileCurve;
use crate::report::Fit;
use crate::scene::Scene;
use crate::settings::precision::Precision;
use crate::settings::search_path::SearchPath;
use crate::{choice, free, paper};
use std::sync::Arc;

type Progress = Arc<dyn Fn() + Send + Sync>;

/// Most worker threads a [`Fitter`] starts.
pub const MAX_THREADS: usize = 1024;

/// Fits scenes: the objective, the grid (the free objective's box), the
/// search path, the worker threads and a progress callback, set once.
///
/// By default a fitter minimises the free-amplitude objective
/// ([`Objective::Free`], as [`crate::Settings`] and every front end do);
/// [`Fitter::objective`] selects the paper's, with [`Grid::paper`].
///
/// ```
/// use laminar_brdf_core::{Correlation, Params};
/// use laminar_brdf_fit::{synthetic, Axis, Fitter, Grid, Model, Objective, Param};
/// // Noise-free synthetic data from the exp model (β in the paper's normalisation).
/// let truth = Params::new(1.48, 0.39, 1.44, 0.17)?;
/// let scene = synthetic::scene(Correlation::Exponential, &truth, 0.0, 1);
/// // The default: the free amplitude, refined inside the default box.
/// let fit = Fitter::new(Grid::user())?.threads(1)?.fit(&scene, Model::Exp);
/// assert_eq!(fit.objective, Objective::Free);
/// let value = |name| fit.parameters.iter().find(|p| p.name == name).unwrap().value();
/// for (name, want) in [(Param::Slope, 1.48), (Param::N, 1.44), (Param::A, 0.17)] {
///     assert!((value(name) - want).abs() < 1e-6 * want, "{name}: {}", value(name));
/// }
/// // The paper's exhaustive grid search, on a grid that holds the truth.
/// let grid = Grid {
///     slope: Axis::stepped(1.32, 0.08, 5),
///     a: Axis::stepped(0.13, 0.01, 9),
///     ..Grid::paper()
/// };
/// let paper = Fitter::new(grid)?.objective(Objective::Paper).threads(1)?.fit(&scene, Model::Exp);
/// assert_eq!(paper.best.params_text(), "slope=1.48;beta=0.39;n=1.44;a=0.17");
/// assert!(paper.best.rms < 1e-6);
/// // The free objective's β is eq. 8's own balance: the paper fit's, converted.
/// let beta_eq8 = paper.best.fitted.beta_eq8.unwrap();
/// assert!((value(Param::Beta) - beta_eq8).abs() < 1e-6, "{} {beta_eq8}", value(Param::Beta));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone)]
pub struct Fitter {
    grid: Grid,
    path: SearchPath,
    pool: Option<Arc<rayon::ThreadPool>>,
    progress: Option<Progress>,
    analysis: Analysis,
    objective: Objective,
    precision: Precision,
    noise: Noise,
}

impl Fitter {
    /// A fitter on `grid` (validated: [`Grid::validate`]) minimising the
    /// free-amplitude objective ([`Objective::default`]) with the default
    /// search path, all cores, no progress callback, refinement and both
    /// uncertainties ([`Analysis::FULL`]).
    ///
    /// # Errors
    /// [`FitError::Grid`] when the grid fails [`Grid::validate`].
    pub fn new(grid: Grid) -> Result<Self, FitError> {
        grid.validate()?;
        Ok(Self {
            grid,
            path: SearchPath::DEFAULT,
            pool: None,
            progress: None,
            analysis: Analysis::FULL,
            objective: Objective::default(),
            precision: Precision::F64,
            noise: Noise::Given,
        })
    }

    /// The objective every fit minimises (default [`Objective::Free`], on
    /// [`Grid::user`]'s box; [`Objective::Paper`] on [`Grid::paper`]
    /// reproduces the paper).
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

    /// The arithmetic of the free objective's grid stage for the layered
    /// models (default [`Precision::F64`]; [`Precision::F32`] computes the
    /// grid's model side in `f32x8` lanes, the refinement and everything
    /// after it still in `f64`; its measured effect on the fits:
    /// docs/speed.md). The paper objective's arithmetic is its
    /// [`Fitter::path`]'s.
    pub fn grid_precision(mut self, precision: Precision) -> Self {
        self.precision = precision;
        self
    }

    /// The free objective's noise model, how each measurement is weighted
    /// (default [`Noise::Given`]; [`crate::noise`]).
    ///
    /// # Errors
    /// [`FitError::Noise`] for a relative floor outside (0, 1].
    pub fn noise(mut self, noise: Noise) -> Result<Self, FitError> {
        self.noise = noise.validate()?;
        Ok(self)
    }

    /// The noise model of the fits.
    pub fn noise_of_fits(&self) -> Noise {
        self.noise
    }

    /// The search path of the layered models (default [`SearchPath::DEFAULT`]).
    pub fn path(mut self, path: SearchPath) -> Self {
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
    pub fn search_path(&self) -> SearchPath {
        self.path
    }

    /// Progress calls per fit of `model`: one per σ/T value for the layered
    /// models, one for a baseline.
    pub fn shards(&self, model: Model) -> u64 {
        match self.objective {
            Objective::Free => 1,
            Objective::Paper => self.paper(&|| ()).shards(model),
        }
    }

    /// The paper pipeline of this fitter, calling `tick` per search shard.
    fn paper<'a>(&'a self, tick: &'a (dyn Fn() + Sync)) -> paper::driver::Driver<'a> {
        paper::driver::Driver {
            grid: &self.grid,
            path: self.path,
            analysis: self.analysis,
            tick,
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

    /// Fits `model` to `scene` by the fitter's objective: the free
    /// objective's pipeline (`crate::free::driver`) or the paper's
    /// (`crate::paper::driver`: layered models search the grid on the
    /// fitter's path, a fixed at 0 for the Ragheb–Hancock variants; the
    /// baselines their own grids, [`crate::model::baseline_grid`]).
    pub fn fit(&self, scene: &Scene, model: Model) -> Fit {
        self.fit_with(scene, model, self.analysis.alone())
    }

    /// [`Fitter::fit`] with `analysis` (the fitter's, with or without the
    /// folds of a model comparison).
    fn fit_with(&self, scene: &Scene, model: Model, analysis: Analysis) -> Fit {
        let tick = || self.tick();
        self.run(|| match self.objective {
            Objective::Free => {
                let scene = &self.weighed(std::slice::from_ref(scene))[0];
                let fit = free::driver::fit(scene, model, (&self.grid, self.precision), analysis);
                tick();
                fit
            }
            Objective::Paper => self.paper(&tick).fit(scene, model),
        })
    }

    /// Fits every model of `models` to every scene, scene-major (the order
    /// of `laminar fit`'s output): what `laminar fit` does. Layered models
    /// go through one batch per model ([`Fitter::fit_batch`]: scenes that
    /// share their geometry share the search; the results are bit for bit
    /// those of fitting each scene alone). Where `given(scene, model)`
    /// supplies parameters, they are assessed ([`Fitter::assess`]) instead
    /// of searched: a data set's own Oren–Nayar parameters, for example.
    /// With several models, each set's fits are ranked by their
    /// information criteria ([`Fit::rank`], [`crate::choice`]) and, under
    /// the free objective, cross-validated ([`Fit::cross_validation`],
    /// [`Analysis::folds`] folds).
    ///
    /// # Errors
    /// [`FitError::Model`] when given parameters are outside their domain or
    /// not the model's; [`FitError::ModelTwice`] when `models` names a model
    /// twice; [`FitError::UntiedUnderPaper`] for an untied model under
    /// [`Objective::Paper`].
    pub fn fit_all(
        &self,
        scenes: &[Scene],
        models: &[Model],
        given: impl Fn(usize, Model) -> Option<ModelParams>,
    ) -> Result<Vec<Fit>, FitError> {
        for &model in models {
            self.objective.takes(model)?;
        }
        let twice = (models.iter().enumerate()).find(|&(i, m)| models[..i].contains(m));
        if let Some((_, &model)) = twice {
            return Err(FitError::ModelTwice {
                model: model.name(),
            });
        }
        let analysis = match models.len() {
            0 | 1 => self.analysis.alone(),
            _ => self.analysis,
        };
        let mut by_model = Vec::with_capacity(models.len());
        for &model in models {
            let params: Vec<Option<ModelParams>> =
                (0..scenes.len()).map(|j| given(j, model)).collect();
            by_model.push(
                if model.is_layered() && params.iter().all(Option::is_none) {
                    self.fit_batch_with(scenes, model, analysis)
                } else {
                    scenes
                        .iter()
                        .zip(params)
                        .map(|(scene, params)| match params {
                            Some(params) => self.assess(scene, model, params),
                            None => Ok(self.fit_with(scene, model, analysis)),
                        })
                        .collect::<Result<Vec<_>, _>>()?
                },
            );
        }
        let mut fits = Vec::with_capacity(scenes.len() * models.len());
        for j in 0..scenes.len() {
            let mut set: Vec<Fit> = by_model.iter().map(|f| f[j].clone()).collect();
            // The models of one set ranked by their information criteria.
            let criteria: Vec<_> = set.iter().map(|f| f.information).collect();
            if criteria.iter().flatten().count() > 1 {
                for (fit, rank) in set.iter_mut().zip(choice::rank(&criteria)) {
                    fit.rank = rank;
                }
            }
            fits.extend(set);
        }
        Ok(fits)
    }

    /// The progress calls [`Fitter::fit_all`] makes (for a progress bar's length).
    pub fn fit_all_shards(&self, scenes: &[Scene], models: &[Model]) -> u64 {
        models.iter().map(|&m| self.batch_shards(scenes, m)).sum()
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
            ..paper::driver::record(scene, model, best, None, 1)
        })
    }

    /// Progress calls of [`Fitter::fit_batch`] on `scenes` with `model`.
    pub fn batch_shards(&self, scenes: &[Scene], model: Model) -> u64 {
        match self.objective {
            Objective::Paper if self.paper(&|| ()).batches(scenes, model) => self.shards(model),
            Objective::Paper | Objective::Free => scenes.len() as u64 * self.shards(model),
        }
    }

    /// Fits `model` to every scene of `scenes`. Under the free objective the
    /// scenes are fitted in parallel, sharing the grid stage's model side
    /// when they are on one geometry without uncertainties
    /// (`crate::free::driver::fit_batch`); under the paper's: when the scenes share their
    /// geometry ([`crate::paper::search::batch::share_geometry`]), the model is layered and the path is
    /// the envelope method, one batch search does the model-side work once
    /// for all of them ([`crate::paper::search::batch`]); otherwise each scene is
    /// fitted alone. Either way every fit is bit for bit [`Fitter::fit`]'s.
    /// Progress: [`Fitter::shards`] calls for the whole batch, or per scene
    /// when fitted alone. Memory grows with the number of scenes: pass large
    /// collections (pixels of a texture) in blocks.
    ///
    /// ```
    /// use laminar_brdf_core::{Correlation, Params};
    /// use laminar_brdf_fit::{synthetic, Axis, Fitter, Grid, Model, Objective};
    /// let scenes: Vec<_> = (0..3)
    ///     .map(|seed| synthetic::scene(Correlation::Exponential, &Params::new(1.48, 0.39, 1.44, 0.2).unwrap(), 0.01, seed))
    ///     .collect();
    /// let grid = Grid { slope: Axis::stepped(1.32, 0.08, 5), a: Axis::stepped(0.0, 0.1, 5), ..Grid::paper() };
    /// let fitter = Fitter::new(grid)?.objective(Objective::Paper);
    /// let batch = fitter.fit_batch(&scenes, Model::Exp);
    /// for (scene, fit) in scenes.iter().zip(&batch) {
    ///     assert_eq!(fit, &fitter.fit(scene, Model::Exp));
    /// }
    /// # Ok::<(), laminar_brdf_fit::FitError>(())
    /// ```
    pub fn fit_batch(&self, scenes: &[Scene], model: Model) -> Vec<Fit> {
        self.fit_batch_with(scenes, model, self.analysis.alone())
    }

    /// [`Fitter::fit_batch`] with `analysis` (the fitter's, with or without
    /// the folds of a model comparison).
    fn fit_batch_with(&self, scenes: &[Scene], model: Model, analysis: Analysis) -> Vec<Fit> {
        let tick = || self.tick();
        self.run(|| match self.objective {
            Objective::Free => free::driver::fit_batch(
                &self.weighed(scenes),
                model,
                (&self.grid, self.precision),
                analysis,
                &tick,
            ),
            Objective::Paper => self.paper(&tick).fit_batch(scenes, model),
        })
    }

    /// One fit of `model` (a layered model) across `scenes`, the channels
    /// of one sample on one geometry: σ/T, σ′/T′ (untied models) and n
    /// shared, a, β and the amplitude per channel, weighted by the fitter's
    /// noise model, in its box, with the analysis's bootstrap resamples
    /// (none when the uncertainty is off) for the percentile intervals and
    /// its folds for each channel's error on held-out geometries
    /// (`crate::free::joint`).
    ///
    /// # Errors
    /// [`FitError::Joint`] for a baseline, fewer than two channels,
    /// channels on different geometries, or the paper objective.
    pub fn fit_joint(&self, scenes: &[Scene], model: Model) -> Result<JointFit, FitError> {
        let refuse = |e: JointError| Err(FitError::Joint(e));
        if self.objective == Objective::Paper {
            return refuse(JointError::PaperObjective);
        }
        if !model.is_layered() {
            return refuse(JointError::NotLayered {
                model: model.name(),
            });
        }
        let Some(first) = scenes.first().filter(|_| scenes.len() >= 2) else {
            return refuse(JointError::TooFewChannels {
                count: scenes.len(),
            });
        };
        if let Some(other) = scenes.iter().find(|s| s.angles() != first.angles()) {
            return refuse(JointError::GeometryDiffers {
                channel: other.channel().to_string(),
                first: first.channel().to_string(),
            });
        }
        let scenes = self.weighed(scenes);
        Ok(self
            .run(|| free::joint::fit(&scenes, model, (&self.grid, self.precision), self.analysis)))
    }

    /// `scenes` weighted by the noise model (copies only when it changes them).
    fn weighed<'a>(&self, scenes: &'a [Scene]) -> std::borrow::Cow<'a, [Scene]> {
        match self.noise {
            Noise::Given => std::borrow::Cow::Borrowed(scenes),
            noise => scenes.iter().map(|s| noise.weigh(s)).collect(),
        }
    }

    /// The profile of each parameter of `fit` (a fit of a layered model to
    /// `scene` by this fitter, with profile intervals) for a figure: the
    /// grid's profile and the continuous one at `points` values
    /// ([`ProfileCurve`]). Empty for the baselines, the free objective, or
    /// without intervals.
    pub fn profiles(&self, scene: &Scene, fit: &Fit, points: usize) -> Vec<ProfileCurve> {
        match fit.objective {
            Objective::Free => Vec::new(),
            Objective::Paper => self.run(|| self.paper(&|| ()).profiles(scene, fit, points)),
        }
    }
}
