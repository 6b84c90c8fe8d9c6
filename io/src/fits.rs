//! Fits as CSV, JSON (the fitted-model file) or Markdown, the fitted-model
//! file read back, and whole-or-nothing file writes.
//!
//! A fit's result is one typed entry ([`FitEntry`], with [`ParameterEntry`]
//! and [`ParamValue`]), serde-derived: the JSON is its serialisation, and
//! the CSV row and the Markdown row are written from it, one writer per
//! format. The TypeScript declarations of these types
//! (`wasm/npm/fits.d.ts`) are generated from them (`io/src/typescript.rs`).
//!
//! Quantities: `rms` is Δ_RMS (eq. 15, `100·sqrt(Σ(D−P)²)/K`, D the
//! measured radiance divided by its max, P the fitted prediction, K the kept
//! measurements); `chi2_dof` is χ²/ν (eq. 16, `Σ(P−D)²/D / (d − p)` over the
//! d measurements with D > 0, p the fitted parameter count); `params` are
//! the fitted parameters. Each fit names its `objective`: `free` (β is eq.
//! 8's, P = amplitude · eq. 8's mix) or `paper` (β of the paper
//! normalisation, see [`laminar_fit::FittedModel`]).

use crate::error::ReadError;
use laminar_fit::adequacy::Adequacy;
use laminar_fit::choice::{CrossValidation, Information, Rank};
use laminar_fit::fitted::format_value;
use laminar_fit::graphics_metrics::GraphicsMetrics;
use laminar_fit::model::{all_params, Param};
use laminar_fit::profile::Interval;
use laminar_fit::report::{Released, Source, NOT_IDENTIFIED};
use laminar_fit::{Edge, Estimate, Fit, FittedModel, Model, Objective, Parameter};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};

fn paper() -> Objective {
    Objective::Paper
}

/// The first columns of the CSV (a contract: scripts read these columns);
/// [`csv_header`] adds the refinement's.
pub const CSV_HEADER: [&str; 15] = [
    "sample",
    "channel",
    "model",
    "rms",
    "chi2_dof",
    "chi2_used",
    "chi2_left_out",
    "params",
    "rh_rms",
    "rh_chi2_dof",
    "rh_params",
    "measurements",
    "nonpositive",
    "search_rms",
    "edges",
];

/// The columns each parameter gets, after its name and `_`.
pub const PARAMETER_COLUMNS: [&str; 12] = [
    "refined",
    "lo68",
    "hi68",
    "lo95",
    "hi95",
    "interval",
    "sd",
    "box_lo",
    "box_hi",
    "released",
    "released_rms",
    "misfit",
];

/// The columns after the parameters' (the objective's, last so that the
/// columns before them keep their places).
pub const FIT_COLUMNS: [&str; 14] = [
    "correlations",
    "trade_offs",
    "objective",
    "amplitude",
    "chi2w_dof",
    "chi2_p",
    "runs_p",
    "lack_of_fit",
    "aicc",
    "bic",
    "rank",
    "cv_rms",
    "cosine_rms",
    "cube_root",
];

/// The full CSV header for fits of `models`: [`CSV_HEADER`], then
/// `rms_grid`, `rms_refined`, then for each parameter of those models
/// `{name}_{column}` for each of [`PARAMETER_COLUMNS`], then [`FIT_COLUMNS`].
pub fn csv_header(models: &[Model]) -> Vec<String> {
    let mut header: Vec<String> = CSV_HEADER.iter().map(|c| c.to_string()).collect();
    header.extend(["rms_grid".to_string(), "rms_refined".to_string()]);
    for name in all_params(models.iter().copied()) {
        header.extend(PARAMETER_COLUMNS.iter().map(|c| format!("{name}_{c}")));
    }
    header.extend(FIT_COLUMNS.iter().map(|c| c.to_string()));
    header
}

fn opt(v: Option<f64>) -> String {
    v.map(|x| format!("{x:.6}")).unwrap_or_default()
}

/// A value to 10 significant decimals (parameters and interval ends).
fn value(v: Option<f64>) -> String {
    v.map(format_value).unwrap_or_default()
}

/// `map`'s entries in the order of `model`'s parameters (the maps are
/// sorted by name; the CSV lists parameters in the model's order).
fn in_model_order<V>(map: &BTreeMap<String, V>, model: Model) -> impl Iterator<Item = (Param, &V)> {
    model
        .params()
        .iter()
        .filter_map(move |&p| map.get(p.name()).map(|v| (p, v)))
}

/// `name=value` pairs joined by `;` in the model's order (the `params`
/// columns), each value as `text` writes it.
fn params_text<V>(map: &BTreeMap<String, V>, model: Model, text: impl Fn(&V) -> String) -> String {
    in_model_order(map, model)
        .map(|(p, v)| format!("{p}={}", text(v)))
        .collect::<Vec<_>>()
        .join(";")
}

/// The pairs `a~b=r` of `map` (correlations, trade-offs) in the model's
/// order of its parameters, r to 3 decimals, joined by `;`.
fn pairs_text(map: &BTreeMap<String, f64>, model: Model) -> String {
    let params = model.params();
    let mut out = Vec::new();
    for (i, a) in params.iter().enumerate() {
        for b in &params[i + 1..] {
            let key = pair_key(*a, *b);
            if let Some(r) = map.get(&key) {
                out.push(format!("{key}={r:.3}"));
            }
        }
    }
    out.join(";")
}

/// The flagged parameters as `name:flag[+flag]` joined by `;`, in the
/// model's order (the `edges` column).
fn edges_text(parameters: &BTreeMap<String, ParameterEntry>, model: Model) -> String {
    in_model_order(parameters, model)
        .filter(|(_, e)| !e.flags.is_empty())
        .map(|(p, e)| {
            let flags: Vec<String> = e.flags.iter().map(Edge::to_string).collect();
            format!("{p}:{}", flags.join("+"))
        })
        .collect::<Vec<_>>()
        .join(";")
}

/// The parameter columns of `p` ([`PARAMETER_COLUMNS`]).
fn parameter_cells(p: Option<&ParameterEntry>) -> Vec<String> {
    let Some(p) = p else {
        return vec![String::new(); PARAMETER_COLUMNS.len()];
    };
    let refined = if p.flags.contains(&Edge::NotIdentified) {
        NOT_IDENTIFIED.to_string()
    } else {
        value(p.refined.and_then(ParamValue::value))
    };
    vec![
        refined,
        value(p.lo68),
        value(p.hi68),
        value(p.lo95),
        value(p.hi95),
        p.interval.map(|s| s.to_string()).unwrap_or_default(),
        p.sd.map(|sd| format!("{sd:.6e}")).unwrap_or_default(),
        value(p.bounds.map(|b| b[0])),
        value(p.bounds.map(|b| b[1])),
        value(p.released.map(|r| r.value)),
        opt(p.released.map(|r| r.rms)),
        opt(p.misfit_ratio),
    ]
}

/// The CSV row of a fit's entry, parameters in the columns of `names`.
fn row(e: &FitEntry, names: &[Param]) -> Vec<String> {
    let mut out = vec![
        e.sample.clone(),
        e.channel.clone(),
        e.model.name().into(),
        format!("{:.6}", e.rms),
        opt(e.chi2_dof),
        e.chi2_used.map(|n| n.to_string()).unwrap_or_default(),
        e.chi2_left_out.map(|n| n.to_string()).unwrap_or_default(),
        params_text(&e.params, e.model, ParamValue::text),
        opt(e.rh_rms),
        opt(e.rh_chi2_dof),
        e.rh_params
            .as_ref()
            .map(|m| params_text(m, e.model, |v| format_value(*v)))
            .unwrap_or_default(),
        e.measurements.to_string(),
        e.nonpositive.to_string(),
        format!("{:.6}", e.search_rms),
        edges_text(&e.parameters, e.model),
        opt(e.rms_grid),
        opt(e.rms_refined),
    ];
    for name in names {
        out.extend(parameter_cells(e.parameters.get(name.name())));
    }
    out.push(pairs_text(&e.correlations, e.model));
    out.push(pairs_text(&e.trade_offs, e.model));
    out.push(e.objective.to_string());
    out.push(e.amplitude.map(|c| format!("{c:.9e}")).unwrap_or_default());
    out.push(opt(e.chi2w_dof));
    let p_value = |p: Option<f64>| p.map(|p| format!("{p:.4e}")).unwrap_or_default();
    out.push(p_value(e.adequacy.and_then(|a| a.chi2_p)));
    out.push(p_value(e.adequacy.and_then(|a| a.runs_p)));
    out.push(
        e.adequacy
            .map(|a| a.lack_of_fit.to_string())
            .unwrap_or_default(),
    );
    out.push(opt(e.information.and_then(|i| i.aicc)));
    out.push(opt(e.information.map(|i| i.bic)));
    out.push(e.rank.map(|r| r.rank.to_string()).unwrap_or_default());
    out.push(opt(e.cross_validation.map(|c| c.rms)));
    let measure = |m: Option<f64>| m.map(|m| format!("{m:.6e}")).unwrap_or_default();
    out.push(measure(e.graphics.map(|g| g.cosine_rms)));
    out.push(measure(e.graphics.map(|g| g.cube_root)));
    out
}

/// Records as CSV with the [`csv_header`] of their models.
pub fn csv(records: &[Fit]) -> String {
    let models: Vec<Model> = records.iter().map(|r| r.model).collect();
    let mut rows = CsvRows::new(Vec::new(), &models).expect("in-memory write");
    for r in records {
        rows.write(r).expect("in-memory write");
    }
    String::from_utf8(rows.into_inner().expect("in-memory flush")).expect("utf-8")
}

/// Records written as CSV rows one at a time (what [`csv()`] gives, without
/// holding every record): the header first, then [`CsvRows::write`] per fit.
pub struct CsvRows<W: Write> {
    writer: csv::Writer<W>,
    names: Vec<Param>,
}

impl<W: Write> CsvRows<W> {
    /// Writes the [`csv_header`] of fits of `models` to `out`.
    ///
    /// # Errors
    /// The writer's error.
    pub fn new(out: W, models: &[Model]) -> std::io::Result<Self> {
        let mut writer = csv::Writer::from_writer(out);
        writer.write_record(csv_header(models))?;
        Ok(Self {
            writer,
            names: all_params(models.iter().copied()),
        })
    }

    /// Writes one record.
    ///
    /// # Errors
    /// The writer's error.
    pub fn write(&mut self, record: &Fit) -> std::io::Result<()> {
        self.write_entry(&FitEntry::new(record))
    }

    /// Writes one fit's entry.
    ///
    /// # Errors
    /// The writer's error.
    pub fn write_entry(&mut self, entry: &FitEntry) -> std::io::Result<()> {
        self.writer
            .write_record(row(entry, &self.names))
            .map_err(std::io::Error::other)
    }

    /// Flushes and returns the writer.
    ///
    /// # Errors
    /// The writer's error.
    pub fn into_inner(self) -> std::io::Result<W> {
        self.writer.into_inner().map_err(|e| e.into_error())
    }
}

/// The format name in every fitted-model file.
pub const FORMAT: &str = "laminar-fits";
/// The version of the fitted-model file. Version 2 added the objective, the
/// amplitude, the weighted χ²/ν and each parameter's box; version 1 files
/// (paper objective) are still read.
pub const VERSION: u32 = 2;

/// The versions [`read_fits`] reads.
pub const READ_VERSIONS: [u32; 2] = [1, 2];

/// One fit in the fitted-model file: the CSV's columns (params as an
/// object) and the portable fitted models.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
pub struct FitEntry {
    /// Sample label.
    pub sample: String,
    /// Channel name.
    pub channel: String,
    /// Model.
    pub model: Model,
    /// The objective minimised (version 1 files: the paper's).
    #[serde(default = "paper")]
    pub objective: Objective,
    /// Δ_RMS (eq. 15) of the reported estimate ([`Fit::reported`]).
    pub rms: f64,
    /// χ²/ν (eq. 16).
    pub chi2_dof: Option<f64>,
    /// Terms used in χ².
    pub chi2_used: Option<usize>,
    /// Measurements left out of χ² (D ≤ 0).
    pub chi2_left_out: Option<usize>,
    /// Parameters by name, rounded to 10 decimals.
    pub params: BTreeMap<String, ParamValue>,
    /// Δ_RMS of the Ragheb–Hancock best (exp, gauss).
    pub rh_rms: Option<f64>,
    /// Its χ²/ν.
    pub rh_chi2_dof: Option<f64>,
    /// Its parameters.
    pub rh_params: Option<BTreeMap<String, f64>>,
    /// Kept measurements K.
    pub measurements: usize,
    /// Kept measurements with value ≤ 0.
    pub nonpositive: usize,
    /// The search's own Δ_RMS.
    pub search_rms: f64,
    /// The fitted model, to predict with: the refined one when the fit was
    /// refined, else the grid's.
    pub fitted: FittedModel,
    /// The grid's best as a fitted model, when `fitted` is the refined one.
    #[serde(default)]
    pub grid_fitted: Option<FittedModel>,
    /// Δ_RMS of the grid's best (the `rms` above).
    #[serde(default)]
    pub rms_grid: Option<f64>,
    /// Δ_RMS of the refined estimate (never above `rms_grid`).
    #[serde(default)]
    pub rms_refined: Option<f64>,
    /// Correlations of the refined estimate from the Jacobian, `"a~b": r`.
    #[serde(default)]
    pub correlations: BTreeMap<String, f64>,
    /// Pairs whose correlation is at least 0.9 in magnitude, `"a~b": r`.
    #[serde(default)]
    pub trade_offs: BTreeMap<String, f64>,
    /// The Ragheb–Hancock best as a fitted model.
    pub rh_fitted: Option<FittedModel>,
    /// Free objective: the fitted amplitude c of the estimate.
    #[serde(default)]
    pub amplitude: Option<f64>,
    /// Free objective: the weighted χ²/ν of the estimate.
    #[serde(default)]
    pub chi2w_dof: Option<f64>,
    /// Each searched parameter under its name. Absent in files written
    /// before it existed.
    #[serde(default)]
    pub parameters: BTreeMap<String, ParameterEntry>,
    /// Free objective: whether the residuals say the model fits
    /// ([`laminar_fit::adequacy`]).
    #[serde(default)]
    pub adequacy: Option<Adequacy>,
    /// Free objective: the information criteria ([`laminar_fit::choice`]).
    #[serde(default)]
    pub information: Option<Information>,
    /// The model's place among those fitted to the same set (several models).
    #[serde(default)]
    pub rank: Option<Rank>,
    /// Free objective, several models: the K-fold cross-validated error
    /// ([`laminar_fit::choice::CrossValidation`]).
    #[serde(default)]
    pub cross_validation: Option<CrossValidation>,
    /// The graphics literature's error measures of the reported estimate
    /// ([`laminar_fit::graphics_metrics`]).
    #[serde(default)]
    pub graphics: Option<GraphicsMetrics>,
    /// The fitted model's energy, when asked for (`laminar fit --albedo`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub energy: Option<Energy>,
}

/// The units of the fitted data, as the user states them: what `ρ ≤ 1`
/// means depends on them (docs/conventions.md §12).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
#[serde(rename_all = "lowercase")]
pub enum Units {
    /// A BRDF in absolute units (sr⁻¹): ρ > 1 is a gain of energy.
    Absolute,
    /// Any other scale (relative BRDF, a camera's counts): ρ has that
    /// scale and no bound.
    Relative,
}

/// A fitted model's directional albedo over view angles, in the file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
pub struct Energy {
    /// The fitted data's units, as stated.
    pub units: Units,
    /// View angles θv, degrees.
    pub theta_v: Vec<f64>,
    /// ρ(θv) in the fitted data's units.
    pub albedo: Vec<f64>,
    /// Each value's quadrature error.
    pub error: Vec<f64>,
    /// True when ρ > 1 at some θv and the units are absolute: the fitted
    /// model reflects more energy than it receives.
    pub energy_gain: bool,
}

impl Energy {
    /// View angles of the table, degrees: 0, 5, …, 85.
    pub const THETA_V: [f64; 18] = [
        0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0, 55.0, 60.0, 65.0, 70.0,
        75.0, 80.0, 85.0,
    ];

    /// The albedo table of `fitted` (tolerance 10⁻⁶, [`laminar_fit::albedo`]).
    ///
    /// # Errors
    /// When the model cannot predict.
    pub fn of(fitted: &FittedModel, units: Units) -> Result<Self, laminar_fit::ModelError> {
        let radians: Vec<f64> = Self::THETA_V.iter().map(|t| t.to_radians()).collect();
        let table = laminar_fit::albedo::albedo_table(
            fitted,
            &radians,
            laminar_fit::albedo::Tolerance::DEFAULT,
        )?;
        let albedo: Vec<f64> = table.iter().map(|a| a.albedo).collect();
        Ok(Self {
            units,
            theta_v: Self::THETA_V.to_vec(),
            energy_gain: units == Units::Absolute && albedo.iter().any(|&a| a > 1.0),
            error: table.iter().map(|a| a.error).collect(),
            albedo,
        })
    }
}

/// The fitted-model file: `laminar fit --format json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
pub struct FitsFile {
    /// Always [`FORMAT`].
    pub format: String,
    /// [`VERSION`].
    pub version: u32,
    /// What the numbers are, for a reader of the file.
    pub quantities: BTreeMap<String, String>,
    /// The fits.
    pub fits: Vec<FitEntry>,
}

/// A parameter's value in `params`: a number, or [`NOT_IDENTIFIED`] when
/// the data do not determine it ([`Fit::not_identified`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
#[serde(untagged)]
pub enum ParamValue {
    /// The value.
    Value(f64),
    /// The data do not determine it.
    Marker(NotIdentified),
}

/// The word [`NOT_IDENTIFIED`] in place of a value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
#[serde(rename_all = "snake_case")]
pub enum NotIdentified {
    /// `not_identified`.
    NotIdentified,
}

impl ParamValue {
    /// `v`, or the marker when `unidentified`.
    fn of(v: f64, unidentified: bool) -> Self {
        if unidentified {
            Self::Marker(NotIdentified::NotIdentified)
        } else {
            Self::Value(v)
        }
    }

    /// As the CSV writes it: the value to 10 decimals, or [`NOT_IDENTIFIED`].
    fn text(&self) -> String {
        match self {
            Self::Value(v) => format_value(*v),
            Self::Marker(_) => NOT_IDENTIFIED.to_string(),
        }
    }

    /// The number, when there is one.
    pub fn value(self) -> Option<f64> {
        match self {
            Self::Value(v) => Some(v),
            Self::Marker(_) => None,
        }
    }
}

/// `e`'s parameters by name, rounded to 10 decimals ([`format_value`]),
/// the marker in place of each parameter `unidentified` names.
fn params_map(e: &Estimate, unidentified: impl Fn(Param) -> bool) -> BTreeMap<String, ParamValue> {
    e.fitted
        .params
        .pairs()
        .into_iter()
        .map(|(k, v)| {
            (
                k.name().to_string(),
                ParamValue::of(rounded(v), unidentified(k)),
            )
        })
        .collect()
}

/// `v` to 10 decimals, as the `params` column prints it.
fn rounded(v: f64) -> f64 {
    format_value(v).parse::<f64>().unwrap_or(v)
}

/// One searched parameter of a fit in the fitted-model file
/// (docs/conventions.md §11, §11b).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
#[cfg_attr(test, ts(rename = "FitParameter"))]
pub struct ParameterEntry {
    /// The best grid point's value.
    pub grid: f64,
    /// After refinement (absent when not refined); [`NOT_IDENTIFIED`] when
    /// the data do not determine the parameter (its flags say so).
    pub refined: Option<ParamValue>,
    /// The 68.27% interval's lower end (absent when not computed).
    pub lo68: Option<f64>,
    /// Its upper end.
    pub hi68: Option<f64>,
    /// The 95% interval's lower end.
    pub lo95: Option<f64>,
    /// Its upper end.
    pub hi95: Option<f64>,
    /// Where the interval ends come from (the headline).
    pub interval: Option<Source>,
    /// The other intervals computed, kept beside the headline.
    #[serde(default)]
    pub alternatives: Vec<IntervalEntry>,
    /// Free objective: the sandwich standard deviation over the
    /// model-based one (about 1 when the model fits).
    #[serde(default)]
    pub misfit_ratio: Option<f64>,
    /// With a bootstrap: the largest Monte Carlo standard deviation of its
    /// interval ends.
    #[serde(default)]
    pub bootstrap_error: Option<f64>,
    /// The Jacobian's standard deviation (absent at a domain bound).
    pub sd: Option<f64>,
    /// Edge flags (empty for an interior value).
    pub flags: Vec<Edge>,
    /// The box searched (free objective; absent for the paper's).
    #[serde(rename = "box", default, serialize_with = "pair_as_list")]
    #[cfg_attr(test, ts(type = "[number, number] | null"))]
    pub bounds: Option<[f64; 2]>,
    /// For an estimate on a face of the box that is not a bound of the
    /// model's domain: one local fit with that bound released.
    #[serde(default)]
    pub released: Option<Released>,
}

/// An interval kept beside a parameter's headline.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
pub struct IntervalEntry {
    /// Where it comes from.
    pub interval: Source,
    /// The 68.27% interval's lower end.
    pub lo68: f64,
    /// Its upper end.
    pub hi68: f64,
    /// The 95% interval's lower end.
    pub lo95: f64,
    /// Its upper end.
    pub hi95: f64,
}

/// A pair as a list, not a tuple: the same JSON, and a Python list too
/// (a serde tuple becomes a Python tuple).
fn pair_as_list<S: serde::Serializer>(pair: &Option<[f64; 2]>, s: S) -> Result<S::Ok, S::Error> {
    match pair {
        Some(pair) => s.collect_seq(pair),
        None => s.serialize_none(),
    }
}

impl ParameterEntry {
    /// The entry of a fit's parameter.
    pub fn new(p: &Parameter) -> Self {
        let ends = |i: Option<Interval>| (i.map(|i| i.lo), i.map(|i| i.hi));
        let (lo68, hi68) = ends(p.interval68);
        let (lo95, hi95) = ends(p.interval95);
        Self {
            grid: p.grid,
            refined: p
                .refined
                .map(|v| ParamValue::of(v, p.flags.contains(&Edge::NotIdentified))),
            lo68,
            hi68,
            lo95,
            hi95,
            interval: p.source,
            alternatives: p
                .alternatives
                .iter()
                .map(|a| IntervalEntry {
                    interval: a.source,
                    lo68: a.interval68.lo,
                    hi68: a.interval68.hi,
                    lo95: a.interval95.lo,
                    hi95: a.interval95.hi,
                })
                .collect(),
            misfit_ratio: p.misfit_ratio,
            bootstrap_error: p.bootstrap_error,
            sd: p.sd,
            flags: p.flags.clone(),
            bounds: p.bounds.map(|(lo, hi)| [lo, hi]),
            released: p.released,
        }
    }
}

/// The `"a~b"` key of a pair of parameters.
fn pair_key(a: Param, b: Param) -> String {
    format!("{a}~{b}")
}

impl FitEntry {
    /// The entry of a fit.
    pub fn new(r: &Fit) -> Self {
        let reported = r.reported();
        Self {
            sample: r.sample.clone(),
            channel: r.channel.clone(),
            model: r.model,
            objective: r.objective,
            rms: reported.rms,
            chi2_dof: reported.chi2.map(|c| c.per_dof),
            chi2_used: reported.chi2.map(|c| c.used),
            chi2_left_out: reported.chi2.map(|c| c.left_out),
            params: params_map(reported, |name| r.not_identified(name)),
            rh_rms: r.rh.as_ref().map(|e| e.rms),
            rh_chi2_dof: r.rh.as_ref().and_then(|e| e.chi2).map(|c| c.per_dof),
            rh_params: r.rh.as_ref().map(|e| {
                let pairs = e.fitted.params.pairs().into_iter();
                pairs
                    .map(|(k, v)| (k.name().to_string(), rounded(v)))
                    .collect()
            }),
            measurements: r.measurements,
            nonpositive: r.nonpositive,
            search_rms: r.search_rms,
            fitted: r.estimate().fitted,
            grid_fitted: r.refined.as_ref().map(|_| r.best.fitted),
            rms_grid: Some(r.best.rms),
            rms_refined: r.refined.as_ref().map(|e| e.rms),
            rh_fitted: r.rh.as_ref().map(|e| e.fitted),
            amplitude: r.amplitude,
            chi2w_dof: r.chi2_weighted,
            correlations: r
                .covariance
                .as_ref()
                .map(|c| {
                    let mut out = BTreeMap::new();
                    for i in 0..c.names.len() {
                        for j in i + 1..c.names.len() {
                            out.insert(pair_key(c.names[i], c.names[j]), c.correlation(i, j));
                        }
                    }
                    out
                })
                .unwrap_or_default(),
            trade_offs: r
                .covariance
                .as_ref()
                .map(|c| {
                    c.trade_offs()
                        .into_iter()
                        .map(|(a, b, r)| (pair_key(a, b), r))
                        .collect()
                })
                .unwrap_or_default(),
            parameters: r
                .parameters
                .iter()
                .map(|p| (p.name.to_string(), ParameterEntry::new(p)))
                .collect(),
            adequacy: r.adequacy,
            information: r.information,
            rank: r.rank,
            cross_validation: r.cross_validation,
            graphics: reported.graphics,
            energy: None,
        }
    }

    /// The label `sample/channel/model`.
    pub fn label(&self) -> String {
        format!("{}/{}/{}", self.sample, self.channel, self.model)
    }
}

/// Fits as the fitted-model file (pretty JSON): [`JsonFits`] into memory.
pub fn json(records: &[Fit]) -> String {
    json_entries(&records.iter().map(FitEntry::new).collect::<Vec<_>>())
}

/// Entries as the fitted-model file (pretty JSON).
pub fn json_entries(entries: &[FitEntry]) -> String {
    let mut out = JsonFits::new(Vec::new()).expect("in-memory write");
    for e in entries {
        out.write_entry(e).expect("in-memory write");
    }
    String::from_utf8(out.finish().expect("in-memory write")).expect("utf-8")
}

/// The fitted-model file's fields before its fits.
fn empty_file() -> FitsFile {
    FitsFile {
        format: FORMAT.into(),
        version: VERSION,
        quantities: [
            ("objective", "free: weighted least squares Σ w(D − c·M)² with a free amplitude c ≥ 0, M eq. 8's raw mix (beta is eq. 8's β, solved with c in closed form), w = 1/σ² from the input's uncertainties (else 1), every estimate and interval inside the box searched; paper: the paper's objective, data and model each divided by their max over the measurements"),
            ("rms", "Δ_RMS (eq. 15) = 100·sqrt(Σ(D−P)²)/K: D measured radiance (BRDF·cos θi) divided by its max over the K kept measurements, P the fitted prediction; of the refined estimate (free) or of the best grid point (paper, as in the paper's tables)"),
            ("chi2_dof", "χ²/ν (eq. 16) = Σ(P−D)²/D over the chi2_used measurements with D > 0, divided by chi2_used − p"),
            ("chi2w_dof", "free: the weighted χ²/ν = Σ w(D−P)²/(K − p) of the estimate, p counting the amplitude (about 1 when the input's σ are right)"),
            ("amplitude", "free: the fitted amplitude c (P = c·M on the data divided by their max)"),
            ("adequacy", "free: does the model fit? chi2_p = P(χ²_ν ≥ Σ w r²) with the input's σ; runs_z, runs_p: the runs of residual signs ordered by the half vector's zenith θh (then θi), standardised, and the one-sided p-value of too few runs; lack_of_fit when either p-value is below 0.01"),
            ("information", "free: aic, aicc, bic on the weighted objective (with σ: χ² + 2k, …, k = p; without: K ln(Σr²/K) + 2k, k = p + 1); lower is better, differences between models fitted to one set count"),
            ("rank", "the model's place among those fitted to the same set by AICc (1 best), delta = its AICc above the best's, weight = its Akaike weight"),
            ("params", "fitted parameters rounded to 10 decimals; beta is eq. 8's β (free) or the balance of the paper normalisation (paper); not_identified in place of a value the data do not determine (the parameter's flags hold not_identified; fitted keeps a value, which predicts the same)"),
            ("fitted", "the model to predict with: full-precision params; normalisation = {amplitude} (free: P = amplitude·(beta·L_sb + (1−beta)·L_sf)), or the maxima over the fit's geometries of the raw surface term, raw subsurface term and the normalised mix (paper; baselines: of the raw radiance; P = (beta·L_sb/subsurface_max + (1−beta)·L_sf/surface_max)/mix_max)"),
            ("beta_eq8", "the balance of eq. 8 giving the fitted lobe: P = eq8_scale·(beta_eq8·L_sb + (1−beta_eq8)·L_sf)"),
            ("data_scale", "the max of the measured radiance the data were divided by: P·data_scale is radiance in the input's units"),
            ("fitted_note", "fitted is the refined model when the fit was refined (grid_fitted is then the grid's best); laminar predict uses fitted"),
            ("rms_grid", "Δ_RMS of the best grid point (= rms for the paper objective)"),
            ("rms_refined", "Δ_RMS after refinement (free: Levenberg–Marquardt from the grid's basins inside the box, which lowers the weighted objective; paper: Nelder–Mead in f64 within the model's domain, never above rms_grid)"),
            ("parameters", "each searched parameter: grid (the grid value), refined, lo68/hi68 and lo95/hi95 (68.27% and 95% intervals), interval (where the headline comes from: robust = the profile's interval with its distances from the estimate scaled by the sandwich (HC3) to model-based standard deviation ratio, the free objective's default, which holds when the model does not fit exactly; profile = the profile of the objective at Δχ² = 1 and 3.84 (free without uncertainties: F(1, K − p)'s quantiles) with the noise variance from the residuals, Σ(D−P)²/(K−p), or from the input's uncertainties; jacobian = refined ± 1 and 1.96 sd), sd (the Jacobian's standard deviation, only when no parameter is at a domain bound), flags: range_edge (paper: the grid value is first or last of its axis, the optimum may lie outside the range searched; free: the estimate is on a face of the box), domain_bound (grid or refined value at a bound of the model's domain, e.g. a = 0 or 1, n = 1), open_below/open_above (the 95% profile interval does not close within the range searched on that side), not_identified (free: the 95% interval is the whole box), not_determined (free: the 68.27% interval is the whole box), misfit_sensitive (free: misfit_ratio beyond 1.5 or below 1/1.5); alternatives: the other intervals computed ({interval, lo68, hi68, lo95, hi95}); misfit_ratio: the sandwich sd over the model-based sd; box: [lo, hi], the box the free objective searched, refined and bounded the intervals in; released: for an estimate on a face of the box that is not a bound of the model's domain, the value and Δ_RMS of one local fit with that bound released (a diagnostic, not an estimate)"),
            ("correlations", "correlations of the refined parameters from the Jacobian covariance s²(JᵀJ)⁻¹"),
            ("trade_offs", "pairs of parameters whose correlation is at least 0.9 in magnitude: the data constrain their combination, not each one"),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect(),
        fits: Vec::new(),
    }
}

/// The fitted-model file written one fit at a time, byte for byte what
/// [`json`] gives, without holding every record (`fit-batch` of any N in
/// constant memory): the document's head, then [`JsonFits::write`] per fit,
/// then [`JsonFits::finish`].
pub struct JsonFits<W: Write> {
    out: W,
    written: usize,
}

/// Indentation of a fit inside the document (`serde_json`'s pretty
/// printer indents by two spaces; fits are at depth 2).
const FIT_INDENT: &str = "    ";

impl<W: Write> JsonFits<W> {
    /// Writes the document's head (format, version, quantities) to `out`.
    ///
    /// # Errors
    /// The writer's error.
    pub fn new(mut out: W) -> std::io::Result<Self> {
        let head = serde_json::to_string_pretty(&empty_file()).map_err(std::io::Error::other)?;
        // The empty document ends in `"fits": []\n}`: keep up to the `[`.
        let open = head.strip_suffix("[]\n}").ok_or_else(|| {
            std::io::Error::other("the fitted-model file's head has an unexpected form")
        })?;
        out.write_all(open.as_bytes())?;
        out.write_all(b"[")?;
        Ok(Self { out, written: 0 })
    }

    /// Writes one fit.
    ///
    /// # Errors
    /// The writer's error.
    pub fn write(&mut self, record: &Fit) -> std::io::Result<()> {
        self.write_entry(&FitEntry::new(record))
    }

    /// Writes one fit's entry.
    ///
    /// # Errors
    /// The writer's error.
    pub fn write_entry(&mut self, entry: &FitEntry) -> std::io::Result<()> {
        let entry = serde_json::to_string_pretty(entry).map_err(std::io::Error::other)?;
        self.out
            .write_all(if self.written == 0 { b"\n" } else { b",\n" })?;
        for (k, line) in entry.lines().enumerate() {
            if k > 0 {
                self.out.write_all(b"\n")?;
            }
            self.out.write_all(FIT_INDENT.as_bytes())?;
            self.out.write_all(line.as_bytes())?;
        }
        self.written += 1;
        Ok(())
    }

    /// Closes the document and returns the writer, flushed.
    ///
    /// # Errors
    /// The writer's error.
    pub fn finish(mut self) -> std::io::Result<W> {
        let close: &[u8] = if self.written == 0 {
            b"]\n}\n"
        } else {
            b"\n  ]\n}\n"
        };
        self.out.write_all(close)?;
        self.out.flush()?;
        Ok(self.out)
    }
}

/// Reads a fitted-model file written by [`json`].
///
/// # Errors
/// [`ReadError`] when the file cannot be read or is not a fitted-model file of this version.
pub fn read_fits(file: &Path) -> Result<FitsFile, ReadError> {
    let text = std::fs::read_to_string(file).map_err(|e| ReadError::io(file, "read", e))?;
    parse_fits(file, &text)
}

/// [`read_fits`] on contents already in memory (`file` names them in errors).
///
/// # Errors
/// As [`read_fits`].
pub fn parse_fits(file: &Path, text: &str) -> Result<FitsFile, ReadError> {
    let fits: FitsFile = serde_json::from_str(text).map_err(|e| {
        ReadError::format(
            file,
            e.line(),
            format!(
                "column {}: not a laminar fitted-model file ({e}); write one with `laminar fit --format json`",
                e.column()
            ),
        )
    })?;
    if fits.format != FORMAT || !READ_VERSIONS.contains(&fits.version) {
        return Err(ReadError::format(
            file,
            0,
            format!(
                "format `{}` version {}, expected `{FORMAT}` version 1 or {VERSION}",
                fits.format, fits.version
            ),
        ));
    }
    Ok(fits)
}

/// A Markdown table from a header and rows.
pub fn markdown_table(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut s = format!(
        "| {} |\n|{}\n",
        header.join(" | "),
        " --- |".repeat(header.len())
    );
    for r in rows {
        s += &format!("| {} |\n", r.join(" | "));
    }
    s
}

/// Records as a Markdown table: each fit's reported Δ_RMS and χ²/ν (as
/// the CSV's `rms` and `chi2_dof`), parameters, adequacy (`fit`: `ok` or
/// `lack of fit` with the p-value that says so) and, for the models fitted
/// to one set, their ranking by AICc (`rank`, `ΔAICc`, Akaike `weight`)
/// and cross-validated error (`cv_rms`).
pub fn markdown(records: &[Fit]) -> String {
    let header = [
        "sample", "channel", "model", "rms", "chi2_dof", "params", "fit", "rank", "ΔAICc",
        "weight", "cv_rms",
    ];
    let rows: Vec<Vec<String>> = records
        .iter()
        .map(|r| {
            let e = FitEntry::new(r);
            vec![
                e.sample.clone(),
                e.channel.clone(),
                e.model.name().into(),
                format!("{:.4}", e.rms),
                opt(e.chi2_dof),
                params_text(&e.params, e.model, ParamValue::text),
                e.adequacy.map(adequacy_text).unwrap_or_default(),
                e.rank.map(|k| k.rank.to_string()).unwrap_or_default(),
                e.rank
                    .map(|k| format!("{:.2}", k.delta))
                    .unwrap_or_default(),
                e.rank
                    .map(|k| format!("{:.3}", k.weight))
                    .unwrap_or_default(),
                opt(e.cross_validation.map(|c| c.rms)),
            ]
        })
        .collect();
    markdown_table(&header, &rows)
}

/// `ok`, or `lack of fit` with the smallest p-value below the threshold.
fn adequacy_text(a: Adequacy) -> String {
    if !a.lack_of_fit {
        return "ok".into();
    }
    let p = [a.chi2_p.map(|p| ("χ²", p)), a.runs_p.map(|p| ("runs", p))]
        .into_iter()
        .flatten()
        .min_by(|x, y| x.1.total_cmp(&y.1));
    match p {
        Some((test, p)) => format!("lack of fit ({test} p = {p:.1e})"),
        None => "lack of fit".into(),
    }
}

/// Writes `contents` to `path` whole or not at all (temporary file, then rename).
///
/// # Errors
/// [`ReadError::Io`] when the file cannot be written.
pub fn write_atomic(path: &Path, contents: &str) -> Result<(), ReadError> {
    write_atomic_bytes(path, contents.as_bytes())
}

/// Writes `contents` to `path` whole or not at all (temporary file, then rename).
///
/// # Errors
/// [`ReadError::Io`] when the file cannot be written.
pub fn write_atomic_bytes(path: &Path, contents: &[u8]) -> Result<(), ReadError> {
    let mut file = AtomicFile::create(path)?;
    file.write_all(contents)
        .map_err(|e| ReadError::io(path, "write", e))?;
    file.commit()
}

/// A file written whole or not at all, streamed: a temporary file beside
/// `path` that [`AtomicFile::commit`] renames over it. Dropped without a
/// commit (an error on the way), it removes the temporary file and leaves
/// `path` as it was.
pub struct AtomicFile {
    path: PathBuf,
    tmp: PathBuf,
    file: Option<std::io::BufWriter<std::fs::File>>,
}

impl AtomicFile {
    /// Creates the temporary file for `path`.
    ///
    /// # Errors
    /// [`ReadError::Io`] when it cannot be created.
    pub fn create(path: &Path) -> Result<Self, ReadError> {
        // Temporary files of earlier runs that were killed go first.
        crate::staging::sweep(path);
        let tmp = crate::staging::sibling(path, "tmp");
        let file = std::fs::File::create(&tmp).map_err(|e| ReadError::io(path, "write", e))?;
        // Held while this process lives ([`crate::staging`]); a file system
        // without locks still gets the file.
        let _ = file.try_lock();
        Ok(Self {
            path: path.to_path_buf(),
            tmp,
            file: Some(std::io::BufWriter::new(file)),
        })
    }

    /// Flushes, syncs and renames the file into place.
    ///
    /// # Errors
    /// [`ReadError::Io`] when any of those fails (the temporary file is removed).
    pub fn commit(mut self) -> Result<(), ReadError> {
        let file = self.file.take().expect("committed once");
        let result = file
            .into_inner()
            .map_err(|e| e.into_error())
            .and_then(|f| f.sync_all())
            .and_then(|()| std::fs::rename(&self.tmp, &self.path));
        result.map_err(|e| ReadError::io(&self.path, "write", e))
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.file.as_mut().expect("not committed").write(buf)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.file.as_mut().expect("not committed").flush()
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        // Not committed, or the rename failed: nothing of it stays.
        if self.file.is_some() || self.tmp.exists() {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// Refuses `out` when it is the same file as one of `inputs`, however the
/// paths are spelled (`./v.csv` and `v.csv`, symbolic or hard links): the
/// file's identity is compared, not its name. An `out` that does not exist
/// yet is none of them.
///
/// ```
/// # let dir = std::env::temp_dir().join(format!("laminar-doc-{}", std::process::id()));
/// # std::fs::create_dir_all(&dir).unwrap();
/// let input = dir.join("values.csv");
/// std::fs::write(&input, "1,2\n").unwrap();
/// let spelled = dir.join(".").join("values.csv");
/// assert!(laminar_io::check_not_an_input(&spelled, &[&input]).is_err());
/// assert!(laminar_io::check_not_an_input(&dir.join("out.csv"), &[&input]).is_ok());
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
///
/// # Errors
/// [`ReadError::OutputIsInput`] naming both paths.
pub fn check_not_an_input<P: AsRef<Path>>(out: &Path, inputs: &[P]) -> Result<(), ReadError> {
    match inputs
        .iter()
        .find(|input| same_file::is_same_file(out, input).unwrap_or(false))
    {
        Some(input) => Err(ReadError::OutputIsInput {
            out: out.to_path_buf(),
            input: input.as_ref().to_path_buf(),
        }),
        None => Ok(()),
    }
}

/// Checks before any work that `path` can be written: its directory exists
/// and accepts a new file (a probe file is created and removed; an existing
/// `path` is left untouched).
///
/// # Errors
/// [`ReadError::Io`] when `path` is a directory or its directory refuses a new file.
pub fn check_writable(path: &Path) -> Result<(), ReadError> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if path.is_dir() {
        return Err(ReadError::io(
            path,
            "write",
            std::io::Error::other("it is a directory"),
        ));
    }
    let probe = dir.join(format!(".laminar-probe-{}", std::process::id()));
    std::fs::File::create(&probe).map_err(|e| ReadError::io(path, "write", e))?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use laminar_fit::{synthetic, Fitter, Grid, NormalisationConstants};

    /// The streamed file is byte for byte the whole document serialised
    /// at once, for no, one and several fits.
    #[test]
    fn streamed_json_is_the_document_serialised_whole() {
        let records = [
            fit(Objective::Free),
            fit(Objective::Paper),
            fit(Objective::Free),
        ];
        for n in 0..=records.len() {
            let whole = FitsFile {
                fits: records[..n].iter().map(FitEntry::new).collect(),
                ..empty_file()
            };
            let want = serde_json::to_string_pretty(&whole).unwrap() + "\n";
            assert_eq!(json(&records[..n]), want, "{n} fits");
            assert_eq!(
                parse_fits(Path::new("f.json"), &want).unwrap().fits.len(),
                n
            );
        }
    }

    /// One selection rule for every front end: a fit by its label, the
    /// Ragheb–Hancock best of an exp fit under its rh- label (unless the
    /// file holds that fit itself), the only fit without a label, and each
    /// way of picking none.
    #[test]
    fn a_fit_is_selected_by_label_and_rh_labels_pick_the_a0_best() {
        use crate::selection::SelectError;
        // A grid whose a axis holds 0, so the fit has an a = 0 best.
        let grid = Grid {
            slope: laminar_fit::Axis::stepped(1.32, 0.08, 5),
            a: laminar_fit::Axis::stepped(0.0, 0.05, 5),
            ..Objective::Free.default_grid()
        };
        let record = Fitter::new(grid)
            .unwrap()
            .objective(Objective::Paper)
            .fit(&synthetic::default_scene(), Model::Exp);
        let one = FitsFile {
            fits: vec![FitEntry::new(&record)],
            ..empty_file()
        };
        let label = one.fits[0].label();
        assert_eq!(one.select(None).unwrap().label, label);
        assert_eq!(one.select(Some(&label)).unwrap().fitted, one.fits[0].fitted);
        let rh_label = label.replace("/exp", "/rh-exp");
        let rh = one.select(Some(&rh_label)).unwrap();
        assert_eq!(Some(rh.fitted), one.fits[0].rh_fitted);
        assert_eq!(Some(rh.rms), one.fits[0].rh_rms);
        let two = FitsFile {
            fits: vec![FitEntry::new(&record), FitEntry::new(&record)],
            ..empty_file()
        };
        assert!(matches!(
            two.select(None),
            Err(SelectError::Ambiguous { count: 2, .. })
        ));
        let e = one.select(Some("x/y/exp")).unwrap_err();
        assert!(e.to_string().contains(&rh_label), "{e}");
        assert_eq!(empty_file().select(None), Err(SelectError::Empty));
        // The file's own rh-exp fit wins over an exp fit's a = 0 best.
        let mut own = FitEntry::new(&record);
        own.model = Model::RhExp;
        own.rms = 123.0;
        own.rms_refined = None;
        let both = FitsFile {
            fits: vec![FitEntry::new(&record), own],
            ..empty_file()
        };
        assert_eq!(both.select(Some(&rh_label)).unwrap().rms, 123.0);
    }

    fn fit(objective: Objective) -> Fit {
        let grid = Grid {
            slope: laminar_fit::Axis::stepped(1.32, 0.08, 5),
            a: laminar_fit::Axis::stepped(0.13, 0.01, 9),
            ..objective.default_grid()
        };
        Fitter::new(grid)
            .unwrap()
            .objective(objective)
            .fit(&synthetic::default_scene(), Model::Exp)
    }

    /// A fitted model holding two normalisations' constants (which would
    /// predict?) or an unknown one is refused, naming the file, where and
    /// the constants.
    #[test]
    fn ambiguous_normalisations_are_refused() {
        let file: serde_json::Value = serde_json::from_str(&json(&[fit(Objective::Free)])).unwrap();
        for (extra, needle) in [
            ("surface_max", "normalisation holds surface_max, amplitude"),
            ("scale", "unknown field `scale`"),
        ] {
            let mut bad = file.clone();
            bad["fits"][0]["fitted"]["normalisation"][extra] = 2.0.into();
            let text = serde_json::to_string_pretty(&bad).unwrap();
            let e = parse_fits(Path::new("f.json"), &text)
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("f.json") && e.contains("line") && e.contains(needle),
                "{e}"
            );
        }
    }

    #[test]
    fn version_2_round_trips_and_version_1_files_are_read_as_paper_fits() {
        let free = json(&[fit(Objective::Free)]);
        let back = parse_fits(Path::new("f.json"), &free).unwrap();
        assert_eq!(back.version, 2);
        let entry = &back.fits[0];
        assert_eq!(entry.objective, Objective::Free);
        assert!(matches!(
            entry.fitted.normalisation,
            NormalisationConstants::Amplitude { .. }
        ));
        assert_eq!(entry.parameters["n"].bounds, Some([1.0, 2.5]));
        // A version 1 file: no objective, amplitude or box.
        let mut v1: serde_json::Value =
            serde_json::from_str(&json(&[fit(Objective::Paper)])).unwrap();
        v1["version"] = 1.into();
        for key in ["objective", "amplitude", "chi2w_dof"] {
            v1["fits"][0].as_object_mut().unwrap().remove(key);
        }
        let back = parse_fits(Path::new("old.json"), &v1.to_string()).unwrap();
        assert_eq!(back.fits[0].objective, Objective::Paper);
        // A later version is refused with a message naming both.
        v1["version"] = 3.into();
        let e = parse_fits(Path::new("new.json"), &v1.to_string()).unwrap_err();
        assert!(
            e.to_string()
                .contains("version 3, expected `laminar-fits` version 1 or 2"),
            "{e}"
        );
    }
}
