//! The paper pipeline's driver (docs/conventions.md §11): the grid search
//! ([`super::search`]; the baselines by their own grids, §7), then the
//! refinement and intervals ([`super::record`]), into a [`Fit`]. The free
//! objective's driver is [`crate::free::driver`]; [`crate::Fitter`]
//! dispatches to one or the other.

use super::intervals::cutoffs;
use super::profiles::{profile_curves, ProfileCurve};
use super::record::{analyse, Analysed};
use super::search::baselines::{grid2, profile_of, sum_of_rms};
use super::search::batch::{search_batch, share_geometry};
use super::search::{
    grid_profile, point, search, GridProfile, Method, SearchPath, SearchResult, Searched,
};
use crate::analysis::Analysis;
use crate::baseline::BaselineGeometry;
use crate::estimate::Estimate;
use crate::fitted::ModelParams;
use crate::grid::{Axis, Grid};
use crate::model::{baseline_grid, Baseline, Family, Model, Param};
use crate::objective::Objective;
use crate::report::Fit;
use crate::scene::Scene;
use rayon::prelude::*;

/// The paper pipeline of one [`crate::Fitter`]: its grid, search path and
/// analysis, and the progress call after each search shard.
pub(crate) struct Driver<'a> {
    /// The grid (validated by [`crate::Fitter::new`]).
    pub grid: &'a Grid,
    /// The layered models' search path.
    pub path: SearchPath,
    /// What follows the search.
    pub analysis: Analysis,
    /// Called once per finished search shard.
    pub tick: &'a (dyn Fn() + Sync),
}

impl Driver<'_> {
    /// Progress calls per fit of `model`: one per σ/T value for the layered
    /// models, one for a baseline.
    pub(crate) fn shards(&self, model: Model) -> u64 {
        match model.family() {
            Family::Layered { .. } => self.grid.slope.len() as u64,
            Family::Baseline(_) => 1,
        }
    }

    /// True when [`Driver::fit_batch`] runs one batch search.
    pub(crate) fn batches(&self, scenes: &[Scene], model: Model) -> bool {
        model.is_layered() && self.path.method == Method::Envelope && share_geometry(scenes)
    }

    /// Fits `model` to every scene of `scenes`: one batch search when they
    /// share their geometry ([`Driver::batches`]), else each alone; every
    /// fit bit for bit [`Driver::fit`]'s.
    pub(crate) fn fit_batch(&self, scenes: &[Scene], model: Model) -> Vec<Fit> {
        match model.correlation() {
            Some(corr) if self.batches(scenes, model) => {
                let grid = self.model_grid(model);
                let results = search_batch(scenes, &grid, corr, self.path.arith, self.tick)
                    .expect("the grid was validated by Fitter::new");
                scenes
                    .par_iter()
                    .zip(&results)
                    .map(|(scene, r)| self.layered_fit(scene, model, &grid, r))
                    .collect()
            }
            Some(_) | None => scenes.iter().map(|s| self.fit(s, model)).collect(),
        }
    }

    /// Fits `model` to `scene`: layered models by the grid search on the
    /// driver's path (a fixed at 0 for the Ragheb–Hancock variants), the
    /// baselines by their own grids ([`baseline_grid`]).
    pub(crate) fn fit(&self, scene: &Scene, model: Model) -> Fit {
        let tick = self.tick;
        match model.family() {
            Family::Layered { correlation, .. } => {
                let grid = self.model_grid(model);
                let r = search(scene, &grid, correlation, self.path, tick)
                    .expect("the grid was validated by Fitter::new");
                self.layered_fit(scene, model, &grid, &r)
            }
            Family::Baseline(baseline) => self.baseline(scene, model, baseline),
        }
    }

    /// A baseline's fit: its geometry once per measurement, then the 2-D
    /// grid search of its max-normalised radiance (docs/conventions.md §7).
    fn baseline(&self, scene: &Scene, model: Model, baseline: Baseline) -> Fit {
        let (outer, inner) = baseline_grid(baseline);
        let geometry = BaselineGeometry::new(baseline, &scene.angles);
        let ((rms, x, y), surface) = grid2(scene, &outer, &inner, &geometry);
        let best = Estimate::new(scene, model, ModelParams::baseline(baseline, [x, y]))
            .expect("grid values are in the domain");
        let names = model.params();
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
        (self.tick)();
        fit
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
            ..record(scene, model, best, rh, evaluated)
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
            // The paper's search ties σ′/T′ to σ/T.
            let sub_slope = model.is_untied().then_some(slope);
            ModelParams::Layered {
                slope,
                beta,
                n,
                a,
                sub_slope,
            }
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
    pub(crate) fn profiles(&self, scene: &Scene, fit: &Fit, points: usize) -> Vec<ProfileCurve> {
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
        {
            let profile = grid_profile(scene, &grid, corr, self.path, cutoff, near)
                .expect("the grid was validated by Fitter::new");
            profile_curves(scene, fit, &searched, &profile, points)
        }
    }
}

/// The record of a paper-objective fit of `model` to `scene` with grid
/// best `best`, before its analysis.
pub(crate) fn record(
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
        adequacy: None,
        information: None,
        rank: None,
        cross_validation: None,
    }
}

/// The flat index of a layered model's grid point.
fn grid_index(grid: &Grid, params: &ModelParams) -> Option<usize> {
    let ModelParams::Layered {
        slope, beta, n, a, ..
    } = *params
    else {
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
        (0, Param::Slope, slope, &grid.slope),
        (1, Param::N, n, &grid.n),
        (2, Param::A, a, &grid.a),
        (3, Param::Beta, beta, &grid.beta),
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
