//! The free pipeline's driver (docs/conventions.md §4b, §11b): it only
//! sequences the stages, each once, for the model's implementation
//! ([`dispatch`]): the layout ([`Layout`]), the grid stage
//! ([`GridStage::grid_values`]), the refinement from the grid's basins with
//! the model's corner start beside it ([`refinement`]), the statistics of
//! the solution ([`super::statistics`]) and the record ([`super::record`]).
//! The paper objective's driver is [`crate::paper::driver`];
//! [`crate::Fitter`] dispatches to one or the other.

use super::dispatch::{dispatch, WithModel};
use super::estimate::estimate_at;
use super::layout::Layout;
use super::model::FreeModel;
use super::problem::Problem;
use super::record::{correlations, parameters, Statistics};
use super::refine::refinement;
use super::search::{grid_starts, GridStage, GridValues, MOST_STARTS};
use super::slice::ragheb_hancock;
use super::statistics::adequacy::{adequacy, chi2_weighted, information};
use super::statistics::bootstrap::bootstrap;
use super::statistics::cross_validation::cross_validate;
use super::statistics::intervals::{intervals, Analysed};
use super::statistics::release::{releasable_face, release};
use super::statistics::Solution;
use crate::adequacy::RunsOrder;
use crate::analysis::{Analysis, Uncertainty};
use crate::estimate::Estimate;
use crate::grid::Grid;
use crate::model::Model;
use crate::objective::Objective;
use crate::report::{Fit, Parameter};
use crate::scene::Scene;
use crate::settings::Precision;
use rayon::prelude::*;
use std::sync::{Arc, OnceLock};

/// Sets whose grid stage one pass over a shared model side serves
/// ([`GridStage::grid_values_shared`]): the model side (K × 440 values
/// with the default grid, 80 MB at K = 22,801) is read from memory once
/// per this many sets.
pub const SETS_PER_PASS: usize = 8;

/// Fits `model` to `scene` under the free-amplitude objective in the box of
/// `grid` (its axes' ranges; the layered models' grid over σ/T, n and a,
/// the baselines' their own grids), the grid stage's terms in `precision`,
/// with `analysis` after the grid stage.
pub fn fit(
    scene: &Scene,
    model: Model,
    (grid, precision): (&Grid, Precision),
    analysis: Analysis,
) -> Fit {
    struct One<'a> {
        scene: &'a Scene,
        grid: &'a Grid,
        precision: Precision,
        analysis: Analysis,
    }
    impl WithModel for One<'_> {
        type Output = Fit;
        fn run<M: GridStage>(self, model: Model) -> Fit {
            let built = Arc::new(M::new(model, self.scene.angles()));
            let layout = Layout::new(&*built, self.grid);
            let problem = problem_of(self.scene, &layout, built);
            let values = M::grid_values(&problem, &layout.axes, self.precision);
            let runs_order = OnceLock::new();
            fit_from(
                self.scene,
                &layout,
                problem,
                &runs_order,
                values,
                self.analysis,
            )
        }
    }
    dispatch(
        model,
        One {
            scene,
            grid,
            precision,
            analysis,
        },
    )
}

/// The objective on `scene` in the box of `layout`, of `model` built at
/// the scene's measurements.
fn problem_of<M: FreeModel>(scene: &Scene, layout: &Layout, model: Arc<M>) -> Problem<M> {
    Problem::new(
        scene,
        (model.model(), Some(model)),
        (layout.bounds.clone(), layout.reported.clone()),
        layout.domain.clone(),
        layout.beta,
    )
}

/// [`fit`] of every scene of `scenes` (in order, in parallel), calling
/// `progress` after each. Scenes on one geometry share the model, and
/// without uncertainties the grid stage's model side
/// ([`GridStage::shared`]), which one pass serves [`SETS_PER_PASS`] of
/// them; every fit is bit for bit [`fit`]'s.
pub fn fit_batch(
    scenes: &[Scene],
    model: Model,
    (grid, precision): (&Grid, Precision),
    analysis: Analysis,
    progress: &(dyn Fn() + Sync),
) -> Vec<Fit> {
    struct Batch<'a> {
        scenes: &'a [Scene],
        grid: &'a Grid,
        precision: Precision,
        analysis: Analysis,
        progress: &'a (dyn Fn() + Sync),
    }
    impl WithModel for Batch<'_> {
        type Output = Vec<Fit>;
        fn run<M: GridStage>(self, model: Model) -> Vec<Fit> {
            let Some(first) = self.scenes.first() else {
                return Vec::new();
            };
            let built = Arc::new(M::new(model, first.angles()));
            let layout = Layout::new(&*built, self.grid);
            let one_geometry = self.scenes.iter().all(|s| s.angles() == first.angles());
            let model_of = |scene: &Scene| {
                if one_geometry {
                    Arc::clone(&built)
                } else {
                    Arc::new(M::new(model, scene.angles()))
                }
            };
            let unweighted = self.scenes.iter().all(|s| s.weights().is_none());
            let shared = (one_geometry && unweighted)
                .then(|| {
                    let first = problem_of(first, &layout, Arc::clone(&built));
                    M::shared(&first, &layout.axes, self.precision)
                })
                .flatten();
            let shared_runs_order = OnceLock::new();
            self.scenes
                .par_chunks(SETS_PER_PASS)
                .flat_map(|chunk| {
                    let problems: Vec<Problem<M>> = chunk
                        .iter()
                        .map(|scene| problem_of(scene, &layout, model_of(scene)))
                        .collect();
                    let values = match &shared {
                        Some(side) => {
                            let refs: Vec<&Problem<M>> = problems.iter().collect();
                            M::grid_values_shared(&refs, &layout.axes, side)
                        }
                        None => problems
                            .iter()
                            .map(|p| M::grid_values(p, &layout.axes, self.precision))
                            .collect(),
                    };
                    problems
                        .into_par_iter()
                        .zip(values)
                        .zip(chunk)
                        .map(|((problem, values), scene)| {
                            let own_runs_order = OnceLock::new();
                            let runs_order = if one_geometry {
                                &shared_runs_order
                            } else {
                                &own_runs_order
                            };
                            let fit = fit_from(
                                scene,
                                &layout,
                                problem,
                                runs_order,
                                values,
                                self.analysis,
                            );
                            (self.progress)();
                            fit
                        })
                        .collect::<Vec<Fit>>()
                })
                .collect()
        }
    }
    dispatch(
        model,
        Batch {
            scenes,
            grid,
            precision,
            analysis,
            progress,
        },
    )
}

/// A fit from its grid stage's values on; `runs_order`, the adequacy
/// test's order of the measurements, is formed at the first fit that
/// needs it (shared by the fits of a batch on one geometry).
pub(crate) fn fit_from<M: GridStage>(
    scene: &Scene,
    layout: &Layout,
    problem: Problem<M>,
    runs_order: &OnceLock<RunsOrder>,
    values: GridValues,
    analysis: Analysis,
) -> Fit {
    let grid_theta = layout.axes.theta(&values.indices(values.best()));
    let (grid_point, grid_columns) = problem.evaluate(&grid_theta, problem.beta);
    let model = (problem.model.model(), problem.parameter_count());
    let best = estimate_at(scene, (&problem, layout), model, &grid_point, &grid_columns);
    let grid = Solution {
        problem: &problem,
        layout,
        minimum: grid_point,
    };
    let grid_values: Vec<f64> = (0..layout.coordinates.len())
        .map(|i| grid.value(i))
        .collect();
    let mut record = record_of(scene, &grid, best, values.sse.len());
    if !analysis.refine {
        record.rh = ragheb_hancock(scene, (&problem, layout), &values, false);
        record.parameters = parameters(&grid, &grid_values, None);
        record.chi2_weighted = chi2_weighted(&problem, &grid.minimum);
        return record;
    }
    let starts: Vec<Vec<f64>> = grid_starts(&values, MOST_STARTS)
        .into_iter()
        .map(|(indices, _)| layout.axes.theta(&indices))
        .collect();
    let corner = M::corner_start(&problem, &layout.axes, &values);
    // The Ragheb–Hancock side result beside the refinement (independent).
    let (rh, refined) = rayon::join(
        || ragheb_hancock(scene, (&problem, layout), &values, true),
        || refinement(&problem, &starts, corner),
    );
    record.rh = rh;
    let analysed = if analysis.uncertainty == Uncertainty::Off {
        Analysed::none(refined)
    } else {
        let refined = Solution {
            problem: &problem,
            layout,
            minimum: refined,
        };
        intervals(refined, analysis)
    };
    let solution = Solution {
        problem: &problem,
        layout,
        minimum: analysed.minimum.clone(),
    };
    record_statistics(
        &mut record,
        scene,
        &solution,
        (&analysed, &grid_values),
        (analysis, runs_order),
    );
    record
}

/// The record of a fit of `scene` whose grid's best point is `grid`
/// (estimate `best`) among `evaluated` grid points; the analysis fills the
/// rest.
fn record_of<M: FreeModel>(
    scene: &Scene,
    grid: &Solution<'_, M>,
    best: Estimate,
    evaluated: usize,
) -> Fit {
    Fit {
        sample: scene.sample().to_string(),
        channel: scene.channel().to_string(),
        model: grid.problem.model.model(),
        search_rms: best.rms,
        rh: None,
        measurements: scene.len(),
        nonpositive: scene.nonpositive(),
        evaluated,
        refined: None,
        parameters: Vec::new(),
        covariance: None,
        objective: Objective::Free,
        amplitude: Some(grid.minimum.linear.amplitude()),
        chi2_weighted: None,
        adequacy: None,
        information: None,
        rank: None,
        cross_validation: None,
        best,
    }
}

/// The statistics of the refined `solution` (its intervals `analysed`; the
/// grid's values `grid_values`) in `record`: the parameters with their
/// intervals and released faces, the covariance, χ²/ν, adequacy,
/// information criteria and cross-validation.
fn record_statistics<M: FreeModel>(
    record: &mut Fit,
    scene: &Scene,
    solution: &Solution<'_, M>,
    (analysed, grid_values): (&Analysed, &[f64]),
    (analysis, runs_order): (Analysis, &OnceLock<RunsOrder>),
) {
    let (problem, layout, minimum) = (solution.problem, solution.layout, &solution.minimum);
    let columns = problem.model.columns(&minimum.theta);
    let model = (problem.model.model(), problem.parameter_count());
    let refined = estimate_at(scene, (problem, layout), model, minimum, &columns);
    let resampled = (analysis.uncertainty == Uncertainty::Bootstrap)
        .then(|| bootstrap(solution, (analysis.resamples, analysis.seed)))
        .flatten();
    let statistics = Statistics {
        analysed,
        uncertainty: analysis.uncertainty,
        bootstrap: resampled.as_ref(),
    };
    let mut parameters = parameters(solution, grid_values, Some(&statistics));
    release_faces(solution, scene, refined.rms, &mut parameters);
    record.covariance = analysed
        .covariance
        .as_ref()
        .filter(|_| analysis.uncertainty.jacobian())
        .and_then(|c| correlations(layout.names, c));
    record.amplitude = Some(minimum.linear.amplitude());
    record.chi2_weighted = chi2_weighted(problem, minimum);
    let runs_order = runs_order.get_or_init(|| RunsOrder::new(scene.angles()));
    record.adequacy = Some(adequacy(solution, runs_order, &columns));
    record.information = information(solution);
    record.cross_validation = cross_validate(solution, (analysis.folds, analysis.seed));
    record.parameters = parameters;
    record.refined = Some(refined);
}

/// Each parameter on a face of the box that is not a bound of its domain
/// gets the fit with that bound released ([`release`]), a diagnostic
/// beside the estimate.
fn release_faces<M: FreeModel>(
    solution: &Solution<'_, M>,
    scene: &Scene,
    rms_in_box: f64,
    parameters: &mut [Parameter],
) {
    for (i, p) in parameters.iter_mut().enumerate() {
        if let Some(at_upper) = releasable_face(solution, i) {
            p.released = Some(release(solution, scene, (i, at_upper), rms_in_box));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coverage::{draw, noisy_scene, NoiseModel};
    use crate::free::coordinate::Coordinate;
    use crate::free::model::LayeredModel;
    use crate::free::refine::minimise;
    use crate::free::statistics::levels::Levels;
    use crate::model::Param;
    use crate::report::Source;
    use crate::synthetic::{self, Noise};

    /// The profile of `problem`'s nonlinear parameter `j` at `value`
    /// (internal coordinates): the least objective of the other parameters
    /// minimised to 10⁻¹² from every fourth σ/T and every n of the grid and
    /// from `minimum`.
    fn profile_at(
        problem: &Problem<LayeredModel>,
        layout: &Layout,
        minimum: &[f64],
        j: usize,
        value: f64,
    ) -> f64 {
        let axes = &layout.axes;
        let at = |p: Param| axes.position(p).expect("a layered parameter");
        let (slope_at, n_at) = (at(Param::Slope), at(Param::N));
        let mut starts = vec![minimum.to_vec()];
        for &slope in axes.axes[slope_at].iter().step_by(4) {
            for &n in &axes.axes[n_at] {
                let mut start = minimum.to_vec();
                (start[slope_at], start[n_at]) = (libm::log(slope), n);
                starts.push(start);
            }
        }
        let mut free = problem.all_free();
        free[j] = false;
        starts
            .par_iter_mut()
            .map(|start| {
                start[j] = value;
                minimise(problem, start, &free, problem.beta, 1e-12)
                    .point
                    .sse
            })
            .reduce(|| f64::INFINITY, f64::min)
    }

    /// Checks that each end of the `level` (0: 68.27%, 1: 95%) profile
    /// intervals of the nonlinear parameters of the coverage run's set
    /// `trial` (exp, σ = 0.01 estimated, seed 2016) lies where the profile
    /// ([`profile_at`]) reaches the level (within 10% in `sqrt(profile −
    /// min)`; below it at a face of the box), and that the profile stays
    /// below the level at a quarter, half, three quarters and 90% of the
    /// way from the estimate to the end.
    fn check_ends(trial: usize, level: usize) {
        let (model, grid) = (Model::Exp, Grid::user());
        let mut rng = Noise::new(2016);
        let scene = (0..=trial)
            .map(|_| {
                let truth = draw(model, Objective::Free, &mut rng);
                noisy_scene(
                    model,
                    Objective::Free,
                    truth,
                    NoiseModel::Every(0.01),
                    &mut rng,
                )
            })
            .last()
            .unwrap();
        let built = Arc::new(LayeredModel::new(model, scene.angles()));
        let layout = Layout::new(&*built, &grid);
        let fit = fit(&scene, model, (&grid, Precision::F64), Analysis::FULL);
        let problem = problem_of(&scene, &layout, built);
        let mut minimum = vec![0.0; problem.dim()];
        for (p, c) in fit.parameters.iter().zip(&layout.coordinates) {
            if let Coordinate::Nonlinear { j, log } = *c {
                minimum[j] = if log { libm::log(p.value()) } else { p.value() };
            }
        }
        let sse_min = problem.evaluate(&minimum, problem.beta).0.sse;
        let target = Levels::new(&problem, sse_min).unwrap().heights[level].sqrt();
        for (p, c) in fit.parameters.iter().zip(&layout.coordinates) {
            let Coordinate::Nonlinear { j, log } = *c else {
                continue;
            };
            let height = |v: f64| {
                let internal = if log { libm::log(v) } else { v };
                let profile = profile_at(&problem, &layout, &minimum, j, internal);
                (profile - sse_min).max(0.0).sqrt()
            };
            let (lo, hi) = layout.reported[j];
            let interval = p.intervals(Source::Profile)[level].unwrap();
            for end in [interval.lo, interval.hi] {
                let h = height(end);
                let reached = if end <= lo || end >= hi {
                    h <= 1.1 * target
                } else {
                    (h - target).abs() <= 0.1 * target
                };
                assert!(
                    reached,
                    "trial {trial} {}: the end {end}: sqrt(profile - min) {h}, the level {target}",
                    p.name
                );
                for t in [0.25, 0.5, 0.75, 0.9] {
                    let v = p.value() + t * (end - p.value());
                    let h = height(v);
                    assert!(
                        h < target,
                        "trial {trial} {}: {v}, inside, at {h} above the level {target}",
                        p.name
                    );
                }
            }
        }
    }

    /// A walk whose bracket of the level narrows without a probe near it
    /// minimises the far side again from the near side's parameters before
    /// it ends at a jump of the profile: in these three sets of the coverage
    /// run a minimisation had stopped in another valley there, and the walk
    /// ended its 95% intervals short (trial 3's a at 0.821, where
    /// `sqrt(profile − min)` is 17% below the level, and trial 100's at
    /// 0.100; they now end at 0.839 and 0.406).
    #[test]
    fn a_walk_ends_at_a_jump_only_where_the_profile_jumps() {
        for trial in [3, 100, 147] {
            check_ends(trial, 1);
        }
    }

    /// Known bug (docs/conventions.md §11b): trial 100's 68.27% interval of
    /// a ends at 0.0717, where the walk's minimisations, following the
    /// profile's valley at n ≈ 1.01 from the estimate, find
    /// `sqrt(profile − min)` at the level; the valley at the face n = 2.5 is
    /// lower there (13% below the level).
    #[test]
    #[ignore = "known bug: the profile's walk follows one valley where another is lower"]
    fn profile_ends_follow_the_lowest_valley() {
        check_ends(100, 0);
    }

    /// Each estimate's Δ_RMS, which a fit forms from its own columns, is
    /// that of its fitted model's prediction.
    #[test]
    fn reported_errors_are_the_fitted_models_own() {
        let scene = synthetic::default_scene();
        let grid = Grid::user();
        for model in Model::ALL {
            let fit = fit(&scene, model, (&grid, Precision::F64), Analysis::FULL);
            let estimates = [Some(&fit.best), fit.refined.as_ref(), fit.rh.as_ref()];
            for (which, e) in estimates.into_iter().enumerate() {
                let Some(e) = e else { continue };
                let again = Estimate::of_fitted(&scene, e.fitted, 0).unwrap();
                assert!(
                    (again.rms - e.rms).abs() <= 1e-12 * e.rms,
                    "{model} estimate {which}: {} against {}",
                    again.rms,
                    e.rms
                );
            }
        }
    }
}
