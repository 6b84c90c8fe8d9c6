//! What a fit reports (docs/conventions.md §11): the last stage of the
//! pipeline. A [`Fit`] holds the search's best, the refined estimate, each
//! searched parameter ([`Parameter`]: grid and refined value, intervals,
//! flags, box) and the Jacobian's covariance. Both objectives fill it
//! (`crate::paper::driver`, `crate::free::driver`); every writer reads it.

use crate::adequacy::Adequacy;
use crate::choice::{CrossValidation, Information, Rank};
use crate::covariance::Covariance;
use crate::edges::Edge;
use crate::estimate::Estimate;
use crate::model::{Model, Param};
use crate::objective::Objective;
use crate::profile::Interval;
use serde::{Deserialize, Serialize};
use std::fmt;

/// The result of fitting one (sample, channel, model).
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    /// Sample label ([`crate::Scene::sample`]).
    pub sample: String,
    /// Channel name ([`crate::Scene::channel`]).
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
    /// The refined estimate (`crate::paper::refine`,
    /// `crate::free::refine`), when refined: never a larger Δ_RMS than `best`, the grid's.
    pub refined: Option<Estimate>,
    /// Each searched parameter: grid value, refined value, intervals and
    /// edge flags (`crate::edges`); empty when nothing was searched
    /// ([`crate::Fitter::assess`]).
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
    /// Free-amplitude fits: whether the residuals say the model fits
    /// ([`crate::adequacy`]).
    pub adequacy: Option<Adequacy>,
    /// Free-amplitude fits: the information criteria of the estimate
    /// ([`crate::choice`]).
    pub information: Option<Information>,
    /// Its place among the models fitted to the same set
    /// ([`crate::Fitter::fit_all`] with several models; [`crate::choice::rank`]).
    pub rank: Option<Rank>,
    /// Free-amplitude fits compared with other models on the same set: the
    /// K-fold cross-validated error ([`crate::choice::CrossValidation`];
    /// [`crate::Analysis::folds`]).
    pub cross_validation: Option<CrossValidation>,
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

    /// True when the data do not determine parameter `name`
    /// ([`Edge::NotIdentified`], e.g. Oren–Nayar's ρ under a free
    /// amplitude, a pure scale): every output then says so instead of a
    /// value. The fitted model keeps a value, which predicts the same.
    pub fn not_identified(&self, name: Param) -> bool {
        self.parameters
            .iter()
            .any(|p| p.name == name && p.flags.contains(&Edge::NotIdentified))
    }

    /// The reported estimate's `name=value` pairs joined by `;` (the
    /// `params` column), [`NOT_IDENTIFIED`] for a value the data do not
    /// determine.
    pub fn params_text(&self) -> String {
        self.reported()
            .fitted
            .params
            .text_masked(|k| self.not_identified(k), NOT_IDENTIFIED)
    }
}

/// What every output says in place of a parameter's value when the data do
/// not determine it ([`Fit::not_identified`]).
pub const NOT_IDENTIFIED: &str = "not_identified";

/// Where an interval comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "typescript", derive(ts_rs::TS))]
#[serde(rename_all = "snake_case")]
pub enum Source {
    /// The profile of the error surface ([`crate::profile`]).
    Profile,
    /// The Jacobian at the refined optimum (`crate::covariance`).
    Jacobian,
    /// The profile's interval with its width scaled by the sandwich
    /// (misfit-robust) to model-based standard deviation ratio: it holds
    /// when the model does not fit the data exactly (docs/estimation.md).
    Robust,
    /// The percentiles of a pairs bootstrap's refits (free objective,
    /// `uncertainty = bootstrap`).
    Bootstrap,
}

impl Source {
    /// Every source, in the order outputs list them.
    pub const ALL: [Source; 4] = [
        Source::Profile,
        Source::Robust,
        Source::Bootstrap,
        Source::Jacobian,
    ];
}

impl fmt::Display for Source {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Profile => "profile",
            Self::Jacobian => "jacobian",
            Self::Robust => "robust",
            Self::Bootstrap => "bootstrap",
        })
    }
}

/// One searched parameter of a fit.
#[derive(Debug, Clone, PartialEq)]
pub struct Parameter {
    /// The parameter.
    pub name: Param,
    /// The chosen grid value.
    pub grid: f64,
    /// The refined value (when refined).
    pub refined: Option<f64>,
    /// The 68.27% interval.
    pub interval68: Option<Interval>,
    /// The 95% interval.
    pub interval95: Option<Interval>,
    /// Where both intervals come from: the headline.
    pub source: Option<Source>,
    /// The other intervals computed, kept beside the headline (free
    /// objective: the profile's and the Jacobian's when the headline is
    /// the robust one).
    pub alternatives: Vec<Alternative>,
    /// The sandwich standard deviation over the model-based one (free
    /// objective): about 1 when the model fits, far from it when the
    /// residuals are misfit rather than noise.
    pub misfit_ratio: Option<f64>,
    /// With a bootstrap: the largest Monte Carlo standard deviation of its
    /// four interval ends (how far another seed could move them).
    pub bootstrap_error: Option<f64>,
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

/// An interval kept beside a parameter's headline.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Alternative {
    /// Where it comes from.
    pub source: Source,
    /// Its 68.27% interval.
    pub interval68: Interval,
    /// Its 95% interval.
    pub interval95: Interval,
}

/// What releasing a bound of the box gives: a diagnostic, not an estimate.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "typescript", derive(ts_rs::TS))]
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
    pub fn new(name: Param, grid: f64) -> Self {
        Self {
            name,
            grid,
            refined: None,
            interval68: None,
            interval95: None,
            source: None,
            alternatives: Vec::new(),
            misfit_ratio: None,
            bootstrap_error: None,
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

    /// The 68.27% and 95% intervals of `source` (the headline's or an
    /// alternative's; `None` when not computed).
    pub fn intervals(&self, source: Source) -> [Option<Interval>; 2] {
        if self.source == Some(source) {
            return [self.interval68, self.interval95];
        }
        self.alternatives
            .iter()
            .find(|a| a.source == source)
            .map_or([None, None], |a| [Some(a.interval68), Some(a.interval95)])
    }

    /// Records the 68% and 95% intervals and where they came from, the 95%
    /// interval's open ends as flags: the step both pipelines end with.
    pub(crate) fn set_intervals(&mut self, [i68, i95]: [Interval; 2], source: Source) {
        if i95.open_below {
            self.flags.push(Edge::OpenBelow);
        }
        if i95.open_above {
            self.flags.push(Edge::OpenAbove);
        }
        self.interval68 = Some(i68);
        self.interval95 = Some(i95);
        self.source = Some(source);
    }
}
