//! The free pipeline's driver (docs/conventions.md §4b, §11b): the box
//! and grid from the [`Grid`] ([`super::layout`]), the grid stage, the
//! refinement from the grid's basins, the intervals (restarted from any
//! lower point they find), what releasing a face of the box gives, and the
//! record ([`super::record`]). The paper objective's driver is
//! [`crate::paper::driver`]; [`crate::Fitter`] dispatches to one or the other.

use super::basis::{Basis, Columns};
use super::bootstrap::bootstrap;
use super::cross_validation::cross_validate;
use super::intervals::{Coordinate, JacobianCovariance, Levels, Side, Walk};
use super::layout::{domain_of, estimate, params_of, raw_terms, Layout};
use super::problem::{Point, Problem};
use super::record::{correlations, parameters};
use super::refine::{minimise, refine, SCREENING, TOLERANCE};
use super::search::{
    grid_starts, grid_values, grid_values_many, GridValues, ModelSide, Precision, SETS_PER_PASS,
};
use crate::adequacy::{Adequacy, RunsOrder};
use crate::analysis::{Analysis, Uncertainty};
use crate::choice::Information;
use crate::estimate::Estimate;
use crate::fitted::FittedModel;
use crate::grid::Grid;
use crate::model::Model;
use crate::objective::Objective;
use crate::report::{Fit, Parameter, Released};
use crate::scene::Scene;
use rayon::prelude::*;
use std::sync::{Arc, OnceLock};

/// Most starts of the refinement: the best point of each of the grid's
/// best basins.
pub const MOST_STARTS: usize = 8;

/// Most restarts of the refinement from a lower point an interval's walk
/// found.
pub const MOST_RESTARTS: usize = 3;

/// The best grid point (the first on ties).
fn grid_best(values: &GridValues) -> usize {
    let mut best = 0;
    for (i, &e) in values.sse.iter().enumerate() {
        if e < values.sse[best] {
            best = i;
        }
    }
    best
}

/// One parameter's profile ends, `[below, above]`, each at the 68.27% and
/// 95% levels as (value, stopped at the face of the box).
pub(super) type Ends = [[(f64, bool); 2]; 2];

/// Intervals and covariance at a minimum.
pub(super) struct Analysed {
    pub(super) minimum: Point,
    pub(super) levels: Option<Levels>,
    pub(super) covariance: Option<JacobianCovariance>,
    /// Per reported parameter, `[below, above]` ends of both levels.
    pub(super) profile: Option<Vec<Ends>>,
    /// True when the data are fitted to rounding: the residuals say
    /// nothing of the noise, so no misfit-robust interval is formed.
    pub(super) rounding: bool,
}

/// Intervals at `minimum`, refining again from any lower point a walk
/// finds (at most [`MOST_RESTARTS`] times).
fn analyse(problem: &Problem, layout: &Layout, mut minimum: Point, analysis: Analysis) -> Analysed {
    let free = vec![true; problem.dim()];
    let mut restarts = 0;
    loop {
        let Some(levels) = Levels::new(problem, minimum.sse) else {
            return Analysed {
                minimum,
                levels: None,
                covariance: None,
                profile: None,
                rounding: false,
            };
        };
        let covariance = JacobianCovariance::new(problem, &minimum, &layout.coordinates, levels.s2);
        let wants_profile = analysis.uncertainty.profile();
        let rounding = fitted_to_rounding(problem, &levels);
        if !wants_profile || rounding {
            return Analysed {
                minimum,
                levels: Some(levels),
                covariance,
                profile: None,
                rounding,
            };
        }
        let sides: Vec<(usize, f64)> = (0..layout.coordinates.len())
            .flat_map(|i| [(i, -1.0), (i, 1.0)])
            .collect();
        let walks: Vec<Walk> = sides
            .par_iter()
            .map(|&(index, direction)| {
                Side {
                    problem,
                    minimum: &minimum,
                    coordinate: layout.coordinates[index],
                    index,
                    covariance: covariance.as_ref(),
                    coordinates: &layout.coordinates,
                    direction,
                    levels,
                }
                .walk()
            })
            .collect();
        let lower = walks
            .iter()
            .filter_map(|w| match w {
                Walk::NewMinimum(p) => Some(p),
                Walk::Ends(_) => None,
            })
            .min_by(|a, b| a.sse.total_cmp(&b.sse));
        if let Some(lower) = lower {
            if restarts < MOST_RESTARTS {
                restarts += 1;
                let again = minimise(problem, &lower.theta, &free, problem.beta, TOLERANCE).point;
                if again.sse < minimum.sse {
                    minimum = again;
                    continue;
                }
            }
        }
        let mut profile = Vec::new();
        for pair in walks.chunks(2) {
            let end = |w: &Walk| match w {
                Walk::Ends(e) => *e,
                // A lower point that refinement could not improve on: the
                // walk's ends are unknown on this side, the face closes it.
                Walk::NewMinimum(_) => [(f64::NAN, true); 2],
            };
            profile.push([end(&pair[0]), end(&pair[1])]);
        }
        return Analysed {
            minimum,
            levels: Some(levels),
            covariance,
            profile: Some(profile),
            rounding,
        };
    }
}

/// One local fit from `minimum` with the box's bound on the side where
/// `value` sits released to the model's domain.
fn release(
    scene: &Scene,
    problem: &Problem,
    model: Model,
    layout: &Layout,
    (index, at_upper): (usize, bool),
    minimum: &Point,
    rms_in_box: f64,
) -> Released {
    let coordinate = layout.coordinates[index];
    let mut wider = problem.clone();
    match coordinate {
        Coordinate::Nonlinear { j, .. } => {
            let (dlo, dhi) = layout.domain[j];
            let (rlo, rhi) = domain_of(layout, index);
            if at_upper {
                wider.bounds[j].1 = dhi;
                wider.reported[j].1 = rhi;
            } else {
                wider.bounds[j].0 = dlo;
                wider.reported[j].0 = rlo;
            }
        }
        Coordinate::Beta => {
            if at_upper {
                wider.beta.1 = 1.0;
            } else {
                wider.beta.0 = 0.0;
            }
        }
    }
    let free = vec![true; problem.dim()];
    let point = minimise(&wider, &minimum.theta, &free, wider.beta, SCREENING).point;
    let e = estimate(
        scene,
        &wider,
        model,
        &point,
        &wider.basis.columns(&point.theta),
    );
    Released {
        value: coordinate.value(&point, &wider),
        rms: e.rms,
        rms_in_box,
    }
}

/// Fits `model` to `scene` under the free-amplitude objective in the box of
/// `grid` (its axes' ranges; the layered models' grid over σ/T, n and a,
/// the baselines' their own grids), the grid stage's bases in `precision`,
/// with `analysis` after the grid stage.
pub fn fit(
    scene: &Scene,
    model: Model,
    (grid, precision): (&Grid, Precision),
    analysis: Analysis,
) -> Fit {
    let layout = Layout::new(model, grid);
    let problem = problem_of(scene, model, &layout, None);
    let values = grid_values(&problem, &layout.axes, precision);
    let runs_order = OnceLock::new();
    fit_from(
        scene,
        model,
        &layout,
        problem,
        &runs_order,
        values,
        analysis,
    )
}

/// The objective of `model` on `scene` in the box of `layout`, on `basis`
/// (the model's at the scene's measurements; `None` to build it).
fn problem_of(scene: &Scene, model: Model, layout: &Layout, basis: Option<Arc<Basis>>) -> Problem {
    Problem::new(
        scene,
        (model, basis),
        (layout.bounds.clone(), layout.reported.clone()),
        layout.domain.clone(),
        layout.beta,
    )
}

/// [`fit`] of every scene of `scenes` (in order, in parallel), calling
/// `progress` after each. Scenes on one geometry without uncertainties
/// share the model side of the grid stage ([`ModelSide`]), which one pass
/// serves [`SETS_PER_PASS`] of them; every fit is bit for bit [`fit`]'s.
pub fn fit_batch(
    scenes: &[Scene],
    model: Model,
    (grid, precision): (&Grid, Precision),
    analysis: Analysis,
    progress: &(dyn Fn() + Sync),
) -> Vec<Fit> {
    let layout = Layout::new(model, grid);
    let Some(first) = scenes.first() else {
        return Vec::new();
    };
    // Scenes on one geometry share the basis, and without uncertainties
    // the model side of the grid stage too.
    let one_geometry = scenes.iter().all(|s| s.angles() == first.angles());
    let basis = one_geometry.then(|| Arc::new(Basis::new(model, first.angles())));
    let shared_runs_order = OnceLock::new();
    let first = problem_of(first, model, &layout, basis.clone());
    let shared = (one_geometry && scenes.iter().all(|s| ModelSide::shareable(&first, s)))
        .then(|| ModelSide::new(&first, &layout.axes, precision));
    // [`SETS_PER_PASS`] sets at a time: their grid stage in one pass over
    // the shared model side, then each set's fit.
    scenes
        .par_chunks(SETS_PER_PASS)
        .flat_map(|chunk| {
            let problems: Vec<Problem> = chunk
                .iter()
                .map(|scene| problem_of(scene, model, &layout, basis.clone()))
                .collect();
            let values = match &shared {
                Some(side) => {
                    let refs: Vec<&Problem> = problems.iter().collect();
                    grid_values_many(&refs, &layout.axes, side)
                }
                None => problems
                    .iter()
                    .map(|p| grid_values(p, &layout.axes, precision))
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
                    let fit =
                        fit_from(scene, model, &layout, problem, runs_order, values, analysis);
                    progress();
                    fit
                })
                .collect::<Vec<Fit>>()
        })
        .collect()
}

/// A fit from its grid stage's values on; `runs_order`, the adequacy
/// test's order of the measurements, is formed at the first fit that
/// needs it (shared by the fits of a batch on one geometry).
fn fit_from(
    scene: &Scene,
    model: Model,
    layout: &Layout,
    problem: Problem,
    runs_order: &OnceLock<RunsOrder>,
    values: GridValues,
    analysis: Analysis,
) -> Fit {
    let grid_flat = grid_best(&values);
    let grid_theta = layout.theta(&values.indices(grid_flat));
    let (grid_point, grid_columns) = problem.evaluate(&grid_theta, problem.beta);
    let best = estimate(scene, &problem, model, &grid_point, &grid_columns);

    let rh = ragheb_hancock(scene, &problem, layout, &values, model, analysis.refine);

    let mut record = Fit {
        sample: scene.sample().to_string(),
        channel: scene.channel().to_string(),
        model,
        search_rms: best.rms,
        rh,
        measurements: scene.len(),
        nonpositive: scene.nonpositive(),
        evaluated: values.sse.len(),
        refined: None,
        parameters: Vec::new(),
        covariance: None,
        objective: Objective::Free,
        amplitude: Some(grid_point.linear.amplitude()),
        chi2_weighted: None,
        adequacy: None,
        information: None,
        rank: None,
        cross_validation: None,
        best: best.clone(),
    };
    let grid_values_of: Vec<f64> = layout
        .coordinates
        .iter()
        .map(|c| c.value(&grid_point, &problem))
        .collect();
    if !analysis.refine {
        record.parameters = parameters(
            layout,
            &problem,
            &grid_values_of,
            None,
            &grid_point,
            None,
            None,
        );
        record.chi2_weighted = chi2_weighted(&problem, &grid_point);
        return record;
    }
    let starts: Vec<Vec<f64>> = grid_starts(&values, MOST_STARTS)
        .into_iter()
        .map(|(indices, _)| layout.theta(&indices))
        .collect();
    // The grid's basins and the corner at n = 1 (`corner_start`), side by
    // side; the corner's minimum is taken only when lower by more than the
    // screening tolerance, so a fit whose corner leads back to its own
    // basin is unchanged.
    let free = vec![true; problem.dim()];
    let (refined, corner) = rayon::join(
        || refine(&problem, &starts).point,
        || {
            corner_start(&problem, layout, &values)
                .map(|start| minimise(&problem, &start, &free, problem.beta, SCREENING).point)
        },
    );
    let refined = match corner {
        Some(c) if c.sse < refined.sse * (1.0 - SCREENING) => {
            minimise(&problem, &c.theta, &free, problem.beta, TOLERANCE).point
        }
        _ => refined,
    };
    let analysed = if analysis.uncertainty == Uncertainty::Off {
        Analysed {
            minimum: refined,
            levels: None,
            covariance: None,
            profile: None,
            rounding: false,
        }
    } else {
        analyse(&problem, layout, refined, analysis)
    };
    let minimum = &analysed.minimum;
    let minimum_columns = problem.basis.columns(&minimum.theta);
    let refined_estimate = estimate(scene, &problem, model, minimum, &minimum_columns);
    let resampled = (analysis.uncertainty == Uncertainty::Bootstrap)
        .then(|| {
            bootstrap(
                &problem,
                layout,
                minimum,
                (analysis.resamples, analysis.seed),
                |i| domain_of(layout, i),
            )
        })
        .flatten();
    let mut parameters = parameters(
        layout,
        &problem,
        &grid_values_of,
        Some(&analysed),
        minimum,
        Some(analysis.uncertainty),
        resampled.as_ref(),
    );
    release_faces(
        scene,
        &problem,
        model,
        layout,
        (minimum, refined_estimate.rms),
        &mut parameters,
    );
    record.covariance = analysed
        .covariance
        .as_ref()
        .filter(|_| analysis.uncertainty.jacobian())
        .and_then(|c| correlations(layout, c));
    record.amplitude = Some(minimum.linear.amplitude());
    record.chi2_weighted = chi2_weighted(&problem, minimum);
    let runs_order = runs_order.get_or_init(|| RunsOrder::new(scene.angles()));
    record.adequacy = Some(adequacy(runs_order, &problem, minimum, &minimum_columns));
    record.information = Information::new(
        minimum.sse,
        problem.data.len(),
        problem.parameter_count(),
        problem.weighted,
    );
    record.cross_validation = cross_validate(&problem, minimum, (analysis.folds, analysis.seed));
    record.parameters = parameters;
    record.refined = Some(refined_estimate);
    record
}

/// The adequacy tests of the residuals at `point`, whose columns are
/// `columns` ([`crate::adequacy`]; `runs_order` the scene's measurements
/// in the runs test's order).
fn adequacy(
    runs_order: &RunsOrder,
    problem: &Problem,
    point: &Point,
    columns: &Columns,
) -> Adequacy {
    let e = problem.residuals(columns, &point.linear);
    Adequacy::in_order(runs_order, &e, problem.parameter_count(), problem.weighted)
}

/// How far above the face n = 1 [`corner_start`] starts, as a
/// fraction of the least `cos²` of the measurements' directions: the
/// refracted cosine `√(n² − 1 + cos²θ)/n` of that direction has moved by
/// about 1% of itself there. The lower points found in the valley lay at
/// 0.5% to 2.6% of it (docs/conventions.md §11b).
const CORNER: f64 = 0.01;

/// A start just above the face n = 1 (docs/conventions.md §11b), for the
/// layered models on a box whose n reaches 1. At n = 1 and a = 0 the
/// layer's term is the surface's own; just above, it moves fastest near
/// grazing, so a narrow valley with β near 1 runs from that face between
/// the grid's columns, and a minimisation that reaches the face stays
/// there. The start is the σ/T of the grid's best point on that face
/// (a at its lower face), a at its lower face and n at [`CORNER`] of the
/// least `cos²` above 1.
fn corner_start(problem: &Problem, layout: &Layout, values: &GridValues) -> Option<Vec<f64>> {
    let (lo, hi) = *problem.bounds.get(1)?;
    let (cos2_i, cos2_s) = problem.basis.cosines();
    let least = cos2_i
        .iter()
        .chain(cos2_s)
        .filter(|c| **c > 0.0)
        .fold(f64::INFINITY, |m, &c| m.min(c));
    if !problem.basis.has_balance() || lo != 1.0 || !least.is_finite() {
        return None;
    }
    let axes = &layout.axes.axes;
    let n_at = axes[1].iter().position(|&v| v == lo)?;
    let (a_len, a_at) = match (axes.get(2), problem.bounds.get(2)) {
        (Some(a), Some(&(a_lo, _))) => (a.len(), a.iter().position(|&v| v == a_lo)?),
        _ => (1, 0),
    };
    let face = (0..axes[0].len())
        .map(|s| (s * axes[1].len() + n_at) * a_len + a_at)
        .min_by(|&f, &g| values.sse[f].total_cmp(&values.sse[g]))?;
    let mut start = layout.theta(&values.indices(face));
    start[1] = (1.0 + CORNER * least).min(hi);
    Some(start)
}

/// The Ragheb–Hancock best of the box (a = 0), when 0 is on the a axis: the
/// a = 0 slice's best grid point, refined with a held at 0 when `refine`.
fn ragheb_hancock(
    scene: &Scene,
    problem: &Problem,
    layout: &Layout,
    values: &GridValues,
    model: Model,
    refine: bool,
) -> Option<Estimate> {
    let rh_model = model.ragheb_hancock()?;
    let zero_a = layout.axes.axes.get(2)?.iter().position(|&v| v == 0.0)?;
    let a_len = values.lens[2];
    let slice =
        (zero_a..values.sse.len())
            .step_by(a_len)
            .fold(None, |b: Option<usize>, f| match b {
                Some(g) if values.sse[g] <= values.sse[f] => Some(g),
                _ => Some(f),
            })?;
    let theta = layout.theta(&values.indices(slice));
    let (mut point, mut columns) = problem.evaluate(&theta, problem.beta);
    if refine {
        // A side result reported by its rms: the screening tolerance (10⁻⁶
        // of the objective) fixes that to about 5·10⁻⁷ of itself.
        point = minimise(
            problem,
            &point.theta,
            &[true, true, false],
            problem.beta,
            SCREENING,
        )
        .point;
        columns = problem.basis.columns(&point.theta);
    }
    let fitted = FittedModel::with_amplitude(
        rh_model,
        params_of(problem, model, &point),
        point.linear.amplitude(),
        scene.data_scale(),
    );
    Some(
        Estimate::of_raw(
            scene,
            fitted,
            &raw_terms(&columns),
            problem.parameter_count() - 1,
        )
        .expect("the box lies inside the model's domain"),
    )
}

/// For each estimate on a face of the box that is not a bound of the
/// model's domain: the fit with that bound released ([`release`]), a
/// diagnostic beside the estimate.
fn release_faces(
    scene: &Scene,
    problem: &Problem,
    model: Model,
    layout: &Layout,
    (minimum, rms_in_box): (&Point, f64),
    parameters: &mut [Parameter],
) {
    for (i, p) in parameters.iter_mut().enumerate() {
        let (lo, hi) = p.bounds.expect("free fits state their box");
        let v = p.value();
        let (dlo, dhi) = domain_of(layout, i);
        let side = if v <= lo && lo > dlo {
            Some(false)
        } else if v >= hi && hi < dhi {
            Some(true)
        } else {
            None
        };
        if let Some(at_upper) = side {
            p.released = Some(release(
                scene,
                problem,
                model,
                layout,
                (i, at_upper),
                minimum,
                rms_in_box,
            ));
        }
    }
}

/// `Σ w r² / (K − p)`, when there are degrees of freedom.
fn chi2_weighted(problem: &Problem, point: &Point) -> Option<f64> {
    let nu = problem.data.len().checked_sub(problem.parameter_count())?;
    (nu > 0).then(|| point.sse / nu as f64)
}

/// Below this fraction of `Σ w D²`, a level's height is too close to the
/// objective's rounding (about 10⁻¹⁶ of it) for a profile to resolve.
const RESOLVABLE_LEVEL: f64 = 1e-13;

/// True when the data are fitted to rounding (noise-free data): the 68%
/// level lies below [`RESOLVABLE_LEVEL`] of `Σ w D²`, where the profile's
/// heights are rounding noise (its walks would end at the box's faces). The
/// intervals then come from the Jacobian (docs/conventions.md §11b).
fn fitted_to_rounding(problem: &Problem, levels: &Levels) -> bool {
    levels.heights[0] < RESOLVABLE_LEVEL * problem.dd
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coverage::{draw, noisy_scene, NoiseModel};
    use crate::report::Source;
    use crate::synthetic::{self, Noise};

    /// The profile of `problem`'s nonlinear parameter `j` at `value`
    /// (internal coordinates): the least objective of the other parameters
    /// minimised to 10⁻¹² from every fourth σ/T and every n of the grid and
    /// from `minimum`.
    fn profile_at(
        problem: &Problem,
        layout: &Layout,
        minimum: &[f64],
        j: usize,
        value: f64,
    ) -> f64 {
        let axes = &layout.axes.axes;
        let mut starts = vec![minimum.to_vec()];
        for &slope in axes[0].iter().step_by(4) {
            for &n in &axes[1] {
                let mut start = minimum.to_vec();
                (start[0], start[1]) = (libm::log(slope), n);
                starts.push(start);
            }
        }
        let mut free = vec![true; problem.dim()];
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
        let layout = Layout::new(model, &grid);
        let fit = fit(&scene, model, (&grid, Precision::F64), Analysis::FULL);
        let problem = problem_of(&scene, model, &layout, None);
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
