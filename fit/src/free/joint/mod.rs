//! One fit across a material's channels (docs/conventions.md §4c): the
//! channels share their geometry (σ/T, σ′/T′ of an untied model, n) and
//! each has its own absorption a and its own linear coefficients
//! (amplitude and β), so C channels have `s + 3C` parameters (s shared)
//! where C separate fits have `C (s + 3)`.
//!
//! The objective is `J = Σ_c F_c`, each channel's free objective. At a
//! point of the shared parameters each `F_c` is a quadratic in its own a
//! (the grid stage's form, [`Column::quadratic`]), so each a is found
//! alone: a scan of [`A_SCAN`] values, then Brent's method between the
//! scan's neighbours of the best. The grid stage is each channel's
//! (the model's terms formed once for all, [`grid_values_many`]) with
//! every channel's best a per
//! shared point summed; each basin of that sum starts a Nelder–Mead
//! search of `J` over the shared parameters in the box (the paper
//! objective's, [`crate::paper::refine`]), the lowest end is the estimate
//! and the other minima near it are rival valleys; each channel's fit is
//! then evaluated exactly there. Intervals: a pairs bootstrap over the
//! geometries (the same resampled geometries in every channel, so the
//! channels' correlation is kept), each resample refined from the
//! estimate and from each rival valley by Levenberg–Marquardt
//! ([`newton`]), the lowest kept; the percentile
//! intervals hold under misfit as the single fits' do (docs/estimation.md,
//! docs/conventions.md §4c). Is the absorption chromatic: the contrasts
//! `a_c − a_1` against their bootstrap covariance ([`ChannelTest`]). Is
//! the roughness shared: a robust score test at the joint estimate
//! ([`score_test`]; untied models). How
//! well it predicts geometries it was not fitted to: a K-fold
//! cross-validation over the geometries (the same folds in every
//! channel), each fold held out in turn while the others are refitted
//! from the estimate, and each channel's held-out residuals predicted with
//! the training fit's own amplitude and β.

mod newton;

use super::driver::fit_from;
use super::layout::Layout;
use super::model::{FreeModel, LayeredModel, Table};
use super::problem::{Point, Problem};
use super::search::objectives::objectives;
use super::search::untied::{grid_values_many, surface_sums, Column};
use super::search::{grid_starts, GridStage, GridValues, MOST_STARTS};
use super::statistics::bootstrap::{percentile_intervals, resample_counts, reweighted};
use super::statistics::cross_validation::assignment;
use super::statistics::score_test::{self, Hotelling};
use crate::adequacy::{Adequacy, RunsOrder};
use crate::analysis::{Analysis, Uncertainty};
use crate::choice::{self, CrossValidation, Information, Rank};
use crate::fitted::{FittedModel, ModelParams};
use crate::free::linear::Quadratic;
use crate::grid::Grid;
use crate::model::{attainable_domain, Model, Param};
use crate::paper::refine::{nelder_mead, TOLERANCE};
use crate::profile::Interval;
use crate::scene::Scene;
use crate::settings::Precision;
use argmin::core::{CostFunction, Executor};
use argmin::solver::brent::BrentOpt;
use laminar_brdf_core::f64x4;
use nalgebra::DVector;
use rayon::prelude::*;
use std::sync::{Arc, OnceLock};

/// Values of a in each channel's scan before Brent's method.
pub const A_SCAN: usize = 21;

/// Brent's relative tolerance on a (√ε, its least useful value) and its
/// absolute one as a fraction of a's box: an a within 3·10⁻¹⁰ of the box
/// moves a quadratic objective by ~10⁻¹⁹ of its curvature.
const BRENT_EPS: f64 = 1.5e-8;
const BRENT_T: f64 = 1e-10;

/// The estimate's Nelder–Mead passes (first steps as fractions of each
/// box): a tenth from the grid's point, then a hundredth from the best.
const ESTIMATE_STEPS: [f64; 2] = [0.1, 0.01];

/// How far above the lowest minimum (in units of the scale `s²`) another
/// valley's minimum may lie and still be a start of every bootstrap
/// resample's refinement: a resample of the data can move two valleys'
/// objectives by several `s²` against each other, and a percentile
/// interval then holds both valleys in proportion.
const RIVAL_HEIGHT: f64 = 25.0;

/// Two minima are distinct when some shared value differs by more than
/// this fraction of its box.
const DISTINCT: f64 = 1e-3;

/// Most iterations of Brent's method (it takes 10–20 on these objectives).
const BRENT_ITERATIONS: u64 = 100;

/// One parameter of a joint fit: its value and percentile intervals.
#[derive(Debug, Clone, PartialEq)]
pub struct JointValue {
    /// The parameter.
    pub name: Param,
    /// Its estimate.
    pub value: f64,
    /// The bootstrap's 68.27% and 95% percentile intervals (none without
    /// resamples).
    pub intervals: Option<[Interval; 2]>,
}

/// One channel of a joint fit.
#[derive(Debug, Clone, PartialEq)]
pub struct JointChannel {
    /// The channel's name.
    pub channel: String,
    /// Its absorption a (`None` for a Ragheb–Hancock model, a = 0).
    pub a: Option<JointValue>,
    /// β of eq. 8.
    pub beta: f64,
    /// The amplitude `c` (of the data divided by their max).
    pub amplitude: f64,
    /// Its weighted objective `F_c` at the joint estimate.
    pub sse: f64,
    /// Its measurements' normalisation (the max it was divided by).
    pub data_scale: f64,
    /// Whether its residuals at the joint estimate say the model fits
    /// ([`crate::adequacy`]; the χ² test counts the shared parameters in
    /// full for each channel).
    pub adequacy: Adequacy,
    /// Its error on held-out geometries (`None` with fewer than two
    /// folds, or too few measurements per training set): the module doc.
    pub cross_validation: Option<CrossValidation>,
}

/// A test of one value of a parameter for every channel against one per
/// channel (module doc): is the absorption chromatic (a), is the
/// roughness shared (σ/T).
#[derive(Debug, Clone, PartialEq)]
pub enum ChannelTest {
    /// Hotelling's T² and its p-value from `F(df1, df2)`: of the contrasts
    /// `a_c − a_1` with the bootstrap's covariance (chromatic), or of the
    /// channels' σ/T scores over the geometries (shared roughness, a
    /// robust score test: docs/conventions.md §4c).
    Tested {
        /// T².
        statistic: f64,
        /// `C − 1`.
        df1: usize,
        /// `B − C + 1` (B resamples), or `G − C + 1` (G geometries).
        df2: usize,
        /// The p-value of one value for all channels.
        p_value: f64,
    },
    /// Not tested: the parameter on a face of its box in these channels
    /// (the test's F calibration holds inside the box only).
    AtAFace(Vec<String>),
    /// Not tested: no such parameter (a Ragheb–Hancock model's a, a tied
    /// model's σ/T), too few resamples for the channels (B ≤ C − 1), or
    /// a singular covariance or design.
    Untestable(&'static str),
}

/// A fit of one model to several channels on one geometry, the geometry's
/// parameters shared ([`crate::Fitter::fit_joint`]).
#[derive(Debug, Clone, PartialEq)]
pub struct JointFit {
    /// The set's sample label.
    pub sample: String,
    /// The model.
    pub model: Model,
    /// The shared parameters (σ/T, σ′/T′ for an untied model, n).
    pub shared: Vec<JointValue>,
    /// Each channel, in the order given.
    pub channels: Vec<JointChannel>,
    /// `J = Σ_c F_c` at the estimate.
    pub sse: f64,
    /// Measurements per channel.
    pub measurements: usize,
    /// Fitted parameters in all: the shared ones and 3 per channel (a, β,
    /// amplitude; 2 without a).
    pub parameter_count: usize,
    /// Bootstrap resamples behind the intervals.
    pub resamples: usize,
    /// Is the absorption chromatic: one a for every channel against one
    /// per channel ([`ChannelTest`]).
    pub chromatic: ChannelTest,
    /// Is the roughness shared: one σ/T for every channel against one per
    /// channel, σ′/T′ and n shared in both (untied models; the module doc).
    pub shared_roughness: ChannelTest,
    /// The variants fitted, ranked by AICc: this joint fit, σ/T per
    /// channel (untied models) and each channel alone.
    pub variants: Vec<VariantFit>,
}

/// A way of fitting a material's channels, ranked against the others by
/// information criteria on one likelihood ([`JointFit::variants`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variant {
    /// σ/T, σ′/T′ and n shared; a, β and the amplitude per channel.
    Joint,
    /// σ/T per channel, σ′/T′ and n shared (the shared-roughness test's
    /// alternative; untied models).
    RoughnessPerChannel,
    /// Each channel fitted alone.
    Separate,
}

impl Variant {
    /// The variant's name in the CSV and Python.
    pub fn name(self) -> &'static str {
        match self {
            Self::Joint => "joint",
            Self::RoughnessPerChannel => "roughness_per_channel",
            Self::Separate => "separate",
        }
    }
}

/// One variant's fit: its objective summed over the channels, its
/// parameters, its criteria and its place among the variants.
#[derive(Debug, Clone, PartialEq)]
pub struct VariantFit {
    /// The variant.
    pub variant: Variant,
    /// `Σ_c F_c` at its estimate (the same weights in every variant).
    pub sse: f64,
    /// Its fitted parameters over all channels.
    pub parameters: usize,
    /// Its criteria over all channels' measurements (one noise scale for
    /// all, estimated unless the uncertainties are known).
    pub information: Option<Information>,
    /// Its place (1 the best by AICc).
    pub rank: Option<Rank>,
}

impl VariantFit {
    /// The variant with objective `sse` and `parameters` over `measurements`
    /// (all channels'), unranked.
    pub(crate) fn new(
        variant: Variant,
        sse: f64,
        (parameters, measurements): (usize, usize),
        weighted: bool,
    ) -> Self {
        Self {
            variant,
            sse,
            parameters,
            information: Information::new(sse, measurements, parameters, weighted),
            rank: None,
        }
    }
}

impl JointFit {
    /// Adds `variant` and ranks every variant again ([`choice::rank`]).
    pub(crate) fn add_variant(&mut self, variant: VariantFit) {
        self.variants.push(variant);
        let criteria: Vec<Option<Information>> =
            self.variants.iter().map(|v| v.information).collect();
        for (v, rank) in self.variants.iter_mut().zip(choice::rank(&criteria)) {
            v.rank = rank;
        }
    }

    /// Channel `c`'s fitted model at the joint estimate (the shared
    /// parameters, its a, β and amplitude): what `predict`, `render` and the
    /// renderers take. `None` for a channel it does not have.
    pub fn fitted(&self, c: usize) -> Option<FittedModel> {
        let channel = self.channels.get(c)?;
        let value = |p: Param| self.shared.iter().find(|v| v.name == p).map(|v| v.value);
        let params = ModelParams::Layered {
            slope: value(Param::Slope)?,
            beta: channel.beta,
            n: value(Param::N)?,
            a: channel.a.as_ref().map_or(0.0, |a| a.value),
            sub_slope: value(Param::SubSlope),
        };
        Some(FittedModel::with_amplitude(
            self.model,
            params,
            channel.amplitude,
            channel.data_scale,
        ))
    }
}

/// The joint objective of the channels' problems on one layered model.
struct Joint<'a> {
    model: &'a LayeredModel,
    /// θ's positions of the shared parameters, in table order (σ/T first).
    shared: Vec<usize>,
    /// σ/T one per channel (the shared-roughness test's alternative):
    /// then `x` holds the channels' σ/T, then the other shared ones.
    slope_per_channel: Option<usize>,
    /// θ's position of a, when the model has it.
    a_at: Option<usize>,
    a_box: (f64, f64),
    factors: [Vec<f64>; 2],
}

impl<'a> Joint<'a> {
    /// Every parameter but a shared by the channels.
    fn all_shared(model: &'a LayeredModel, layout: &Layout) -> Self {
        let table = model.table();
        let a_at = table.position(Param::A);
        let shared: Vec<usize> = (0..table.entries().len())
            .filter(|&j| Some(j) != a_at)
            .collect();
        Joint {
            model,
            a_box: a_at.map_or((0.0, 0.0), |j| layout.bounds[j]),
            shared,
            slope_per_channel: None,
            a_at,
            factors: model.factors(),
        }
    }
}

impl Joint<'_> {
    /// The θ position of each value of `x`.
    fn positions(&self) -> Vec<usize> {
        match self.slope_per_channel {
            None => self.shared.clone(),
            Some(channels) => std::iter::repeat_n(self.shared[0], channels)
                .chain(self.shared[1..].iter().copied())
                .collect(),
        }
    }

    /// Where θ position `j` of channel `c` is in `x`: `None` for a.
    fn x_index(&self, c: usize, j: usize) -> Option<usize> {
        let k = self.shared.iter().position(|&s| s == j)?;
        Some(match self.slope_per_channel {
            None => k,
            Some(_) if k == 0 => c,
            Some(channels) => channels + k - 1,
        })
    }

    /// The box of each value of `x`.
    fn bounds(&self, problems: &[Problem<LayeredModel>]) -> Vec<(f64, f64)> {
        (self.positions().iter())
            .map(|&j| problems[0].bounds[j])
            .collect()
    }

    /// Channel `c`'s full θ at values `x` and absorption `a`.
    fn theta_of(&self, x: &[f64], c: usize, a: f64) -> Vec<f64> {
        let mut theta = vec![0.0; self.shared.len() + usize::from(self.a_at.is_some())];
        match self.slope_per_channel {
            None => {
                for (&j, &v) in self.shared.iter().zip(x) {
                    theta[j] = v;
                }
            }
            Some(channels) => {
                theta[self.shared[0]] = x[c];
                for (&j, &v) in self.shared[1..].iter().zip(&x[channels..]) {
                    theta[j] = v;
                }
            }
        }
        if let Some(j) = self.a_at {
            theta[j] = a;
        }
        theta
    }

    /// The full θ of shared values `x` and absorption `a` (σ/T shared).
    fn theta(&self, x: &[f64], a: f64) -> Vec<f64> {
        self.theta_of(x, 0, a)
    }

    /// `J` at values `x` and each channel's best a there.
    fn at(&self, problems: &[Problem<LayeredModel>], x: &[f64]) -> (f64, Vec<f64>) {
        let theta = self.theta_of(x, 0, 0.0);
        let (slope, n, _) = self.model.slope_n_a(&theta);
        let shared_surface = self
            .slope_per_channel
            .is_none()
            .then(|| self.model.surface(slope));
        let boundary = self.model.boundary::<f64x4>(n);
        let b = self
            .model
            .base::<f64x4>(self.model.sub_slope(&theta), &boundary);
        let mut total = 0.0;
        let mut best = Vec::with_capacity(problems.len());
        for (c, problem) in problems.iter().enumerate() {
            let own;
            let s = match &shared_surface {
                Some(s) => s,
                None => {
                    let (slope, _, _) = self.model.slope_n_a(&self.theta_of(x, c, 0.0));
                    own = self.model.surface(slope);
                    &own
                }
            };
            let q = Column::new(problem, &b, &self.factors).quadratic(
                problem,
                s,
                surface_sums(problem, s),
            );
            let (a, value) = match self.a_at {
                Some(_) => minimise_in(&q, problem.beta, self.a_box),
                None => (0.0, objective_at(&q, problem.beta, 0.0)),
            };
            total += value;
            best.push(a);
        }
        (total, best)
    }
}

/// The smallest objective of quadratic `q` over a in `[lo, hi]`: the best
/// of [`A_SCAN`] values, then Brent's method (argmin's [`BrentOpt`])
/// between the scan's neighbours of the best; its a and value.
fn minimise_in(q: &Quadratic<f64>, beta: (f64, f64), (lo, hi): (f64, f64)) -> (f64, f64) {
    let step = (hi - lo) / (A_SCAN - 1) as f64;
    let scan: [f64; A_SCAN] = std::array::from_fn(|i| lo + step * i as f64);
    let mut values = [0.0; A_SCAN];
    objectives(q, &scan, beta, &mut values);
    let mut best = (scan[0], values[0]);
    for (&a, &v) in scan.iter().zip(&values).skip(1) {
        if v < best.1 {
            best = (a, v);
        }
    }
    let bracket = ((best.0 - step).max(lo), (best.0 + step).min(hi));
    let cost = AtA { q, beta };
    let solver = BrentOpt::new(bracket.0, bracket.1).set_tolerance(BRENT_EPS, BRENT_T * (hi - lo));
    let found = Executor::new(cost, solver)
        .configure(|state| state.max_iters(BRENT_ITERATIONS))
        .timer(false)
        .run()
        .ok()
        .and_then(|r| Some((r.state.best_param?, r.state.best_cost)));
    match found {
        Some((a, v)) if v < best.1 => (a, v),
        _ => best,
    }
}

/// One channel's objective as a function of its a, for [`BrentOpt`].
struct AtA<'a> {
    q: &'a Quadratic<f64>,
    beta: (f64, f64),
}

impl CostFunction for AtA<'_> {
    type Param = f64;
    type Output = f64;
    fn cost(&self, a: &f64) -> Result<f64, argmin::core::Error> {
        Ok(objective_at(self.q, self.beta, *a))
    }
}

/// One channel's objective at absorption `a` from its quadratic `q`.
fn objective_at(q: &Quadratic<f64>, beta: (f64, f64), a: f64) -> f64 {
    let mut out = [0.0];
    objectives(q, &[a], beta, &mut out);
    out[0]
}

/// The joint fit of `model` (a layered model) to `scenes` (channels of one
/// sample on one geometry, already weighted by the noise model) in the box
/// of `grid`, the grid stage in `precision`, with `analysis`'s bootstrap
/// resamples (none when its uncertainty is off), seed and folds; and the
/// variants ranked beside it.
pub fn fit(
    scenes: &[Scene],
    model: Model,
    (grid, precision): (&Grid, Precision),
    analysis: Analysis,
) -> JointFit {
    let resamples = match analysis.uncertainty {
        Uncertainty::Off => 0,
        _ => analysis.resamples,
    };
    let (seed, folds) = (analysis.seed, analysis.folds);
    let built = Arc::new(LayeredModel::new(model, scenes[0].angles()));
    let layout = Layout::new(&*built, grid);
    let problems = channel_problems(scenes, model, &built, &layout);
    let joint = Joint::all_shared(&built, &layout);
    let grids = channel_grids(&problems, &layout, precision);
    let own: Vec<usize> = joint.a_at.into_iter().collect();
    let starts = channel_grid_starts(&grids, &layout, &own, |thetas| {
        joint.shared.iter().map(|&j| thetas[0][j]).collect()
    });
    let per_channel = 2 + usize::from(joint.a_at.is_some());
    let parameters = joint.shared.len() + per_channel * scenes.len();
    let Minima { x, a, rivals, .. } =
        refine_all(&joint, &problems, (&starts, Method::NelderMead), parameters);
    let evaluated: Vec<_> = problems
        .iter()
        .zip(&a)
        .map(|(p, &a)| p.evaluate(&joint.theta(&x, a), p.beta))
        .collect();
    let runs_order = RunsOrder::new(scenes[0].angles());
    let adequacy: Vec<Adequacy> = (problems.iter().zip(&evaluated))
        .map(|(p, (point, columns))| {
            let e = p.residuals(columns, &point.linear);
            let fitted = joint.shared.len() + per_channel;
            Adequacy::in_order(&runs_order, &e, fitted, p.weighted)
        })
        .collect();
    let estimate: Vec<_> = evaluated.into_iter().map(|(point, _)| point).collect();
    let bootstrapped = bootstrap(&joint, &problems, (&x, &rivals), (resamples, seed));
    let sse: Vec<f64> = estimate.iter().map(|p| p.sse).collect();
    let validated = cross_validate(&joint, &problems, (&x, &sse), parameters, (folds, seed));
    let reporter = Reporter {
        layout: &layout,
        table: built.table(),
        bootstrapped: bootstrapped.as_deref(),
    };
    let shared: Vec<JointValue> = (joint.shared.iter().enumerate())
        .map(|(i, &j)| reporter.value(j, reporter.in_units(j, x[i]), i))
        .collect();
    let channels = (scenes.iter().zip(&estimate).enumerate())
        .map(|(c, (scene, point))| JointChannel {
            channel: scene.channel().to_string(),
            a: (joint.a_at).map(|j| reporter.value(j, a[c], joint.shared.len() + c)),
            beta: point.linear.beta(layout.beta.0),
            amplitude: point.linear.amplitude(),
            sse: point.sse,
            data_scale: scene.data_scale(),
            adequacy: adequacy[c],
            cross_validation: validated.as_ref().map(|v| v[c]),
        })
        .collect();
    let chromatic = match joint.a_at {
        Some(_) => channel_test(
            &a,
            joint.a_box,
            (bootstrapped.as_deref(), joint.shared.len()),
            scenes,
        ),
        None => ChannelTest::Untestable("the model has no absorption"),
    };
    let (shared_roughness, nested_sse) = shared_roughness(
        &joint,
        (&problems, &grids, &layout),
        (&x, &estimate),
        scenes,
    );
    let all = scenes.len() * scenes[0].len();
    let weighted = problems[0].weighted;
    let mut fit = JointFit {
        sample: scenes[0].sample().to_string(),
        model,
        shared,
        channels,
        sse: sse.iter().sum(),
        measurements: scenes[0].len(),
        parameter_count: parameters,
        resamples: if bootstrapped.is_some() { resamples } else { 0 },
        chromatic,
        shared_roughness,
        variants: Vec::new(),
    };
    let joint_variant = (Variant::Joint, fit.sse, parameters);
    // σ/T once per channel instead of once.
    let nested = nested_sse.map(|j| {
        (
            Variant::RoughnessPerChannel,
            j,
            parameters + scenes.len() - 1,
        )
    });
    for (variant, sse, p) in std::iter::once(joint_variant).chain(nested) {
        fit.add_variant(VariantFit::new(variant, sse, (p, all), weighted));
    }
    fit.add_variant(separately(scenes, (problems, grids), &layout, analysis));
    fit
}

/// The variant that fits each channel alone ([`Variant::Separate`]): each
/// channel's single fit (refined, without intervals) from its grid values
/// `grids` on its own `problems`, the channels' objectives summed; each
/// fit the same bits as [`crate::Fitter::fit`]'s (the grid values are,
/// [`grid_values_many`]).
fn separately(
    scenes: &[Scene],
    (problems, grids): (Vec<Problem<LayeredModel>>, Vec<GridValues>),
    layout: &Layout,
    analysis: Analysis,
) -> VariantFit {
    let estimate_only = Analysis {
        refine: true,
        uncertainty: Uncertainty::Off,
        folds: 0,
        ..analysis
    };
    // Each channel's nonlinear parameters, β and amplitude.
    let per_channel = problems[0].parameter_count();
    let sse: f64 = (scenes.par_iter().zip(problems).zip(grids))
        .map(|((scene, problem), values)| {
            let fit = fit_from(
                scene,
                layout,
                problem,
                &OnceLock::new(),
                values,
                estimate_only,
            );
            let nu = scene.len().saturating_sub(per_channel);
            fit.chi2_weighted.map_or(f64::NAN, |chi2| chi2 * nu as f64)
        })
        .collect::<Vec<f64>>()
        .iter()
        .sum();
    let weighted = scenes[0].weights().is_some_and(|(_, known)| known);
    let all = scenes.len() * scenes[0].len();
    VariantFit::new(
        Variant::Separate,
        sse,
        (per_channel * scenes.len(), all),
        weighted,
    )
}

/// Each channel's problem on the one built model, in `layout`'s box.
fn channel_problems(
    scenes: &[Scene],
    model: Model,
    built: &Arc<LayeredModel>,
    layout: &Layout,
) -> Vec<Problem<LayeredModel>> {
    scenes
        .iter()
        .map(|scene| {
            Problem::new(
                scene,
                (model, Some(Arc::clone(built))),
                (layout.bounds.clone(), layout.reported.clone()),
                layout.domain.clone(),
                layout.beta,
            )
        })
        .collect()
}

/// A joint estimate's values in the user's units with their bootstrap
/// percentile intervals.
struct Reporter<'a> {
    layout: &'a Layout,
    table: &'a Table,
    /// Per resample, the shared values then each channel's a.
    bootstrapped: Option<&'a [Vec<f64>]>,
}

impl Reporter<'_> {
    /// θ position `j`'s internal value `v` in the user's units; on a face
    /// of the box, the face as the user gave it (`ln` and `exp` do not
    /// round-trip).
    fn in_units(&self, j: usize, v: f64) -> f64 {
        let ((lo, hi), (ilo, ihi)) = (self.layout.reported[j], self.layout.bounds[j]);
        match v {
            v if v <= ilo => lo,
            v if v >= ihi => hi,
            v => self.table.entries()[j].scale.external(v).clamp(lo, hi),
        }
    }

    /// θ position `j`'s `value` with the interval of the resamples'
    /// `column`.
    fn value(&self, j: usize, value: f64, column: usize) -> JointValue {
        let name = self.table.entries()[j].name;
        JointValue {
            name,
            value,
            intervals: self.bootstrapped.map(|values| {
                let mut sorted: Vec<f64> = values.iter().map(|v| v[column]).collect();
                sorted.sort_by(f64::total_cmp);
                let reported = self.layout.reported[j];
                percentile_intervals(&sorted, value, reported, attainable_domain(name)).0
            }),
        }
    }
}

/// The test of one value for every channel ([`ChannelTest`]): each
/// channel's estimate `v` (in `box`'s units) and, per bootstrap resample,
/// the channels' values from column `first` on; the contrasts
/// `d_c = v_c − v_1`, their covariance
/// `S` over the resamples, `T² = dᵀ S⁻¹ d`, and `(B − p) T² / (p (B − 1))`
/// against `F(p, B − p)`, `p = C − 1` (Hotelling's, for a covariance
/// estimated from B draws). Not made with a value on a face of `box`.
fn channel_test(
    v: &[f64],
    (lo, hi): (f64, f64),
    (bootstrapped, first): (Option<&[Vec<f64>]>, usize),
    scenes: &[Scene],
) -> ChannelTest {
    let faces: Vec<String> = (scenes.iter().zip(v))
        .filter(|(_, &v)| v <= lo || v >= hi)
        .map(|(s, _)| s.channel().to_string())
        .collect();
    if !faces.is_empty() {
        return ChannelTest::AtAFace(faces);
    }
    let p = v.len() - 1;
    let Some(values) = bootstrapped.filter(|v| v.len() > p + 1) else {
        return ChannelTest::Untestable("too few bootstrap resamples for the channels");
    };
    let contrasts =
        |v: &[f64]| -> DVector<f64> { DVector::from_iterator(p, (1..=p).map(|c| v[c] - v[0])) };
    let d = contrasts(v);
    let draws: Vec<DVector<f64>> = values.iter().map(|v| contrasts(&v[first..])).collect();
    let (_, covariance) = score_test::mean_and_covariance(&draws);
    let Some(cholesky) = covariance.cholesky() else {
        return ChannelTest::Untestable(
            "the bootstrap's covariance of the channels' values is singular",
        );
    };
    let statistic = d.dot(&cholesky.solve(&d));
    let (df1, df2, p_value) = score_test::f_calibrated(statistic, p, values.len());
    ChannelTest::Tested {
        statistic,
        df1,
        df2,
        p_value: p_value.unwrap_or(f64::NAN),
    }
}

/// Is the roughness shared ([`JointFit::shared_roughness`]): the robust
/// score test of one σ/T for every channel at the joint estimate
/// ([`score_test::shared_value`]; each channel's fit there, `estimate`),
/// and the objective of the nested fit with σ/T per channel (σ′/T′ and n
/// shared) for the ranking of the variants, refined from the shared
/// estimate `x` and from each basin of the nested grid. Untied models only
/// (a tied model's σ/T is also its subsurface's).
fn shared_roughness(
    joint: &Joint<'_>,
    (problems, grids, layout): (&[Problem<LayeredModel>], &[GridValues], &Layout),
    (x, estimate): (&[f64], &[Point]),
    scenes: &[Scene],
) -> (ChannelTest, Option<f64>) {
    if !joint.model.model().is_untied() {
        let why = "σ/T is the subsurface's too in a tied model";
        return (ChannelTest::Untestable(why), None);
    }
    let channels = problems.len();
    let nested = Joint {
        model: joint.model,
        shared: joint.shared.clone(),
        slope_per_channel: Some(channels),
        a_at: joint.a_at,
        a_box: joint.a_box,
        factors: joint.factors.clone(),
    };
    // From the shared estimate and from each basin of the nested grid.
    let shared_start: Vec<f64> = std::iter::repeat_n(x[0], channels)
        .chain(x[1..].iter().copied())
        .collect();
    let slope_at = joint.shared[0];
    let own: Vec<usize> = std::iter::once(slope_at).chain(joint.a_at).collect();
    let grid_starts = channel_grid_starts(grids, layout, &own, |thetas| {
        (thetas.iter().map(|theta| theta[slope_at]))
            .chain(joint.shared[1..].iter().map(|&j| thetas[0][j]))
            .collect()
    });
    let starts: Vec<Vec<f64>> = std::iter::once(shared_start).chain(grid_starts).collect();
    let nested_sse =
        refine_all(&nested, problems, (&starts, Method::LevenbergMarquardt), 0).objective;
    let (lo, hi) = layout.bounds[slope_at];
    if x[0] <= lo || x[0] >= hi {
        let faces = scenes.iter().map(|s| s.channel().to_string()).collect();
        return (ChannelTest::AtAFace(faces), Some(nested_sse));
    }
    let own_a: Vec<usize> = joint.a_at.into_iter().collect();
    let test = match score_test::shared_value(problems, estimate, (slope_at, &joint.shared, &own_a))
    {
        Ok(Hotelling {
            statistic,
            df1,
            df2,
            p_value,
        }) => ChannelTest::Tested {
            statistic,
            df1,
            df2,
            p_value,
        },
        Err(why) => ChannelTest::Untestable(why),
    };
    (test, Some(nested_sse))
}

/// Each channel's grid values on the layout's axes, the model's side (its
/// terms at the grid's points) formed once for all the channels.
fn channel_grids(
    problems: &[Problem<LayeredModel>],
    layout: &Layout,
    precision: Precision,
) -> Vec<GridValues> {
    let channels: Vec<&Problem<LayeredModel>> = problems.iter().collect();
    match LayeredModel::shared(&problems[0], &layout.axes, precision) {
        Some(side) => LayeredModel::grid_values_shared(&channels, &layout.axes, &side),
        None => grid_values_many(&channels, &layout.axes, precision),
    }
}

/// The starts of a search over the channels whose grid axes `own` (θ
/// positions) each channel takes for itself (a; σ/T too in the nested
/// fit) and the others are shared: per point of the shared axes, each
/// channel's grid minimum over its own axes, summed over the channels;
/// the basins of that sum ([`grid_starts`]), the lowest first, at most
/// [`MOST_STARTS`] (one start alone, the best point, missed the lowest
/// valley of the untied models' σ′/T′–n trade in 5% of synthetic sets).
/// Each start as `x_of` makes it from each channel's θ at its minimum.
fn channel_grid_starts(
    values: &[GridValues],
    layout: &Layout,
    own: &[usize],
    x_of: impl Fn(&[Vec<f64>]) -> Vec<f64>,
) -> Vec<Vec<f64>> {
    let lens = &values[0].lens;
    let shared_axes: Vec<usize> = (0..lens.len()).filter(|j| !own.contains(j)).collect();
    let own_lens: Vec<usize> = own.iter().map(|&j| lens[j]).collect();
    let own_grid = GridValues {
        sse: Vec::new(),
        lens: own_lens.clone(),
    };
    let summed_grid = GridValues {
        sse: Vec::new(),
        lens: shared_axes.iter().map(|&j| lens[j]).collect(),
    };
    let points: usize = summed_grid.lens.iter().product();
    // Per shared point, each channel's flat index of its minimum.
    let full_index = |shared: &[usize], mine: &[usize]| {
        let mut indices = vec![0; lens.len()];
        for (&j, &i) in shared_axes.iter().zip(shared) {
            indices[j] = i;
        }
        for (&j, &i) in own.iter().zip(mine) {
            indices[j] = i;
        }
        values[0].flat(&indices)
    };
    let (sums, argmins): (Vec<f64>, Vec<Vec<usize>>) = (0..points)
        .map(|point| {
            let shared = summed_grid.indices(point);
            let flats: Vec<usize> = (0..own_lens.iter().product())
                .map(|k| full_index(&shared, &own_grid.indices(k)))
                .collect();
            let best: Vec<(f64, usize)> = (values.iter())
                .map(|v| {
                    flats.iter().fold((f64::INFINITY, flats[0]), |best, &f| {
                        if v.sse[f] < best.0 {
                            (v.sse[f], f)
                        } else {
                            best
                        }
                    })
                })
                .collect();
            (
                best.iter().map(|b| b.0).sum::<f64>(),
                best.iter().map(|b| b.1).collect(),
            )
        })
        .unzip();
    let summed = GridValues {
        sse: sums,
        ..summed_grid
    };
    let mut starts = grid_starts(&summed, MOST_STARTS);
    if starts.is_empty() {
        // No finite value on the grid: its first best point.
        starts.push((summed.indices(summed.best()), f64::NAN));
    }
    starts
        .into_iter()
        .map(|(indices, _)| {
            let thetas: Vec<Vec<f64>> = (argmins[summed.flat(&indices)].iter())
                .map(|&flat| layout.axes.theta(&values[0].indices(flat)))
                .collect();
            x_of(&thetas)
        })
        .collect()
}

/// How [`refine_all`] refines from each start.
#[derive(Debug, Clone, Copy)]
enum Method {
    /// Nelder–Mead, two passes ([`refine`]): the estimate's, over the
    /// shared values (three or four), from the grid's basins.
    NelderMead,
    /// Levenberg–Marquardt ([`newton::refine`]): the nested fit's, whose
    /// σ/T per channel makes `C + 2` values (33 for 31 wavelengths, where
    /// Nelder–Mead took 1.4 s and stopped short).
    LevenbergMarquardt,
}

/// The joint estimate and the valleys that rival it.
struct Minima {
    /// The shared values of the lowest minimum.
    x: Vec<f64>,
    /// Each channel's a there.
    a: Vec<f64>,
    /// `J` there.
    objective: f64,
    /// Other valleys' shared values ([`refine_all`]).
    rivals: Vec<Vec<f64>>,
}

/// The refinements from each of `starts`: the lowest (the first on ties),
/// its shared values and each channel's a; then the distinct other minima
/// whose objective is within [`RIVAL_HEIGHT`] of the scale `s² = J/ν`
/// above it (`ν` the measurements less the `parameters`), lowest first:
/// the valleys a resample of the data could prefer.
fn refine_all(
    joint: &Joint<'_>,
    problems: &[Problem<LayeredModel>],
    (starts, method): (&[Vec<f64>], Method),
    parameters: usize,
) -> Minima {
    let mut refined: Vec<(Vec<f64>, Vec<f64>, f64)> = starts
        .par_iter()
        .map(|start| match method {
            Method::NelderMead => refine(joint, problems, start, &ESTIMATE_STEPS),
            Method::LevenbergMarquardt => newton::refine(joint, problems, start),
        })
        .collect();
    // Stable: the first start on ties.
    refined.sort_by(|p, q| p.2.total_cmp(&q.2));
    let mut minima = refined.into_iter();
    let (x, a, lowest) = minima.next().expect("at least one start");
    let measurements: usize = problems.iter().map(|p| p.data.len()).sum();
    let s2 = lowest / measurements.saturating_sub(parameters).max(1) as f64;
    let bounds = joint.bounds(problems);
    let mut rivals: Vec<Vec<f64>> = Vec::new();
    for (xr, _, objective) in minima {
        let distinct = |other: &Vec<f64>| {
            (xr.iter().zip(other).zip(&bounds))
                .any(|((u, v), (lo, hi))| (u - v).abs() > DISTINCT * (hi - lo))
        };
        if objective - lowest <= RIVAL_HEIGHT * s2 && distinct(&x) && rivals.iter().all(distinct) {
            rivals.push(xr);
        }
    }
    Minima {
        x,
        a,
        objective: lowest,
        rivals,
    }
}

/// Nelder–Mead on `J` over the shared parameters in their box from
/// `start`, once per fraction of `steps` (each a pass's first steps, as
/// fractions of each box; each pass from the last one's best); the shared
/// values, each channel's a and `J` there.
fn refine(
    joint: &Joint<'_>,
    problems: &[Problem<LayeredModel>],
    start: &[f64],
    steps: &[f64],
) -> (Vec<f64>, Vec<f64>, f64) {
    let bounds = joint.bounds(problems);
    let cost = |x: &[f64]| joint.at(problems, x).0;
    let mut x = start.to_vec();
    for &fraction in steps {
        let first: Vec<f64> = bounds.iter().map(|(lo, hi)| fraction * (hi - lo)).collect();
        x = nelder_mead(cost, &bounds, (&x, &first), TOLERANCE).x;
    }
    let (objective, a) = joint.at(problems, &x);
    (x, a, objective)
}

/// Each channel's K-fold cross-validation (module doc) around the
/// estimate `x` (each channel's objective there `sse`), the folds dealt by
/// `seed` over the geometries; `None` with fewer than two folds or when a
/// training set would not outnumber the `parameters` fitted in all.
fn cross_validate(
    joint: &Joint<'_>,
    problems: &[Problem<LayeredModel>],
    (x, sse): (&[f64], &[f64]),
    parameters: usize,
    (folds, seed): (usize, u64),
) -> Option<Vec<CrossValidation>> {
    let k = problems[0].data.len();
    let training = k - k.div_ceil(folds.max(1));
    if folds < 2 || training * problems.len() <= parameters {
        return None;
    }
    let fold = assignment(k, folds, seed);
    // Per fold, each channel's held-out Σ w r².
    let held_out: Vec<Vec<f64>> = (0..folds)
        .into_par_iter()
        .map(|f| {
            let keep: Vec<f64> = fold.iter().map(|&g| f64::from(g != f)).collect();
            let train: Vec<_> = problems.iter().map(|p| reweighted(p, &keep)).collect();
            let (xf, af, _) = newton::refine(joint, &train, x);
            (problems.iter().zip(&train).zip(&af))
                .map(|((problem, trained), &a)| {
                    // The training fit's amplitude and β, the whole
                    // problem's weights.
                    let (point, columns) = trained.evaluate(&joint.theta(&xf, a), trained.beta);
                    let r = problem.residuals(&columns, &point.linear);
                    (0..k).filter(|&i| fold[i] == f).map(|i| r[i] * r[i]).sum()
                })
                .collect()
        })
        .collect();
    (0..problems.len())
        .map(|c| {
            let total: f64 = held_out.iter().map(|per_channel| per_channel[c]).sum();
            total.is_finite().then(|| CrossValidation {
                folds,
                rms: (total / k as f64).sqrt(),
                in_sample: (sse[c] / k as f64).sqrt(),
            })
        })
        .collect()
}

/// Each resample's shared values (model units) then each channel's a:
/// the geometries resampled alike in every channel, each refined from the
/// estimate `x` and from each of the `rivals` (other valleys' minima), the
/// lowest kept. `None` with fewer than two resamples.
fn bootstrap(
    joint: &Joint<'_>,
    problems: &[Problem<LayeredModel>],
    (x, rivals): (&[f64], &[Vec<f64>]),
    (resamples, seed): (usize, u64),
) -> Option<Vec<Vec<f64>>> {
    if resamples < 2 {
        return None;
    }
    let entries = joint.model.table().entries();
    let values = (0..resamples)
        .into_par_iter()
        .map(|b| {
            let counts = resample_counts(problems[0].data.len(), seed, b);
            let resampled: Vec<_> = problems.iter().map(|p| reweighted(p, &counts)).collect();
            // From the estimate, and from each rival valley: the lowest.
            let mut best = newton::refine(joint, &resampled, x);
            for rival in rivals {
                let other = newton::refine(joint, &resampled, rival);
                if other.2 < best.2 {
                    best = other;
                }
            }
            let (xb, ab, _) = best;
            let mut v: Vec<f64> = (joint.positions().iter().zip(&xb))
                .map(|(&j, &v)| entries[j].scale.external(v))
                .collect();
            v.extend(ab);
            v
        })
        .collect();
    Some(values)
}
