//! The result schema of a fit: one typed entry per fit ([`FitEntry`]),
//! written by one module per format: CSV (`csv_rows.rs`: [`csv()`],
//! [`CsvRows`]), the JSON fitted-model file, written and read back
//! (`json_file.rs`: [`json()`], [`JsonFits`], [`read_fits`]), and Markdown
//! (`markdown.rs`: [`markdown()`]), and the numeric row of a batch fit
//! (`batch_row.rs`: [`BatchRow`], [`BatchCsv`]); whole-or-nothing writes are
//! [`crate::staging`]'s.
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
//! normalisation, see [`laminar_brdf_fit::FittedModel`]).

use laminar_brdf_fit::adequacy::Adequacy;
use laminar_brdf_fit::choice::{CrossValidation, Information, Rank};
use laminar_brdf_fit::fitted::format_value;
use laminar_brdf_fit::graphics_metrics::GraphicsMetrics;
use laminar_brdf_fit::model::Param;
use laminar_brdf_fit::profile::Interval;
use laminar_brdf_fit::report::{Released, Source, NOT_IDENTIFIED};
use laminar_brdf_fit::{Edge, Estimate, Fit, FittedModel, Model, Objective, Parameter};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

mod batch_row;
mod csv_rows;
mod json_file;
mod markdown;

pub use batch_row::{BatchCsv, BatchRow, FieldKind, CSV_KEY, FIT_FIELDS, PARAMETER_FIELDS};
pub use csv_rows::{csv, csv_header, CsvRows, CSV_HEADER, FIT_COLUMNS, PARAMETER_COLUMNS};
pub use json_file::{json, json_entries, json_materials, parse_fits, read_fits, JsonFits};
pub use markdown::{markdown, markdown_table};

fn paper() -> Objective {
    Objective::Paper
}

/// The format name in every fitted-model file.
pub const FORMAT: &str = "laminar-fits";
/// The version of the fitted-model file. Version 2 added the objective, the
/// amplitude, the weighted χ²/ν and each parameter's box; version 3 names
/// the weighted χ²/ν `chi2_weighted` (version 2's `chi2w_dof`), as the
/// batch fields do; version 4 adds the materials (joint fits). Version 1
/// to 3 files are still read.
pub const VERSION: u32 = 4;

/// The versions [`read_fits`] reads.
pub const READ_VERSIONS: [u32; 4] = [1, 2, 3, 4];

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
    /// Free objective: the weighted χ²/ν of the estimate (`chi2w_dof` in
    /// version 2 files).
    #[serde(default, alias = "chi2w_dof")]
    pub chi2_weighted: Option<f64>,
    /// Each searched parameter under its name. Absent in files written
    /// before it existed.
    #[serde(default)]
    pub parameters: BTreeMap<String, ParameterEntry>,
    /// Free objective: whether the residuals say the model fits
    /// ([`laminar_brdf_fit::adequacy`]).
    #[serde(default)]
    pub adequacy: Option<Adequacy>,
    /// Free objective: the information criteria ([`laminar_brdf_fit::choice`]).
    #[serde(default)]
    pub information: Option<Information>,
    /// The model's place among those fitted to the same set (several models).
    #[serde(default)]
    pub rank: Option<Rank>,
    /// Free objective, several models: the K-fold cross-validated error
    /// ([`laminar_brdf_fit::choice::CrossValidation`]).
    #[serde(default)]
    pub cross_validation: Option<CrossValidation>,
    /// The graphics literature's error measures of the reported estimate
    /// ([`laminar_brdf_fit::graphics_metrics`]).
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

    /// The albedo table of `fitted` (tolerance 10⁻⁶, [`laminar_brdf_fit::albedo`]).
    ///
    /// # Errors
    /// When the model cannot predict.
    pub fn of(fitted: &FittedModel, units: Units) -> Result<Self, laminar_brdf_fit::ModelError> {
        let radians: Vec<f64> = Self::THETA_V.iter().map(|t| t.to_radians()).collect();
        let table = laminar_brdf_fit::albedo::albedo_table(
            fitted,
            &radians,
            laminar_brdf_fit::albedo::Tolerance::DEFAULT,
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
    /// The materials: joint fits across a sample's channels (`laminar
    /// fit-joint --fits`). Absent from files without one.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub materials: Vec<MaterialEntry>,
}

/// One material: a joint fit across a sample's channels
/// ([`laminar_brdf_fit::JointFit`], docs/conventions.md §4c), its shared
/// parameters once and each channel's own with its fitted model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
pub struct MaterialEntry {
    /// Sample label.
    pub sample: String,
    /// The layered model.
    pub model: Model,
    /// The shared parameters (σ/T, σ′/T′ for an untied model, n) by name:
    /// the estimate and the pairs bootstrap's percentile intervals.
    pub shared: BTreeMap<String, JointEntry>,
    /// Each channel, in the order fitted.
    pub channels: Vec<MaterialChannel>,
    /// Measurements per channel.
    pub measurements: usize,
    /// Fitted parameters in all.
    pub parameters: usize,
    /// Bootstrap resamples behind the intervals (0: none).
    pub resamples: usize,
    /// `J = Σ_c F_c` at the estimate.
    pub sse: f64,
    /// The p-value of one a for every channel, when tested.
    pub chromatic_p: Option<f64>,
    /// The p-value of one σ/T for every channel, when tested.
    pub roughness_p: Option<f64>,
    /// Each variant fitted (`joint`, `roughness_per_channel`, `separate`)
    /// by name: its AICc above the best variant's.
    pub variants: BTreeMap<String, f64>,
}

/// One channel of a [`MaterialEntry`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
pub struct MaterialChannel {
    /// Channel name.
    pub channel: String,
    /// Its absorption a (absent for a model without one).
    pub a: Option<JointEntry>,
    /// Eq. 8's β.
    pub beta: f64,
    /// The amplitude of the data divided by `data_scale`.
    pub amplitude: f64,
    /// The max the channel's data were divided by.
    pub data_scale: f64,
    /// The channel's weighted objective at the joint estimate.
    pub sse: f64,
    /// Whether its residuals say the model does not fit.
    pub lack_of_fit: bool,
    /// The channel's fitted model at the joint estimate: what `predict`,
    /// `render`, `export` and the renderers take (its label
    /// `sample/channel/model` selects it).
    pub fitted: FittedModel,
}

/// A jointly fitted value and its bootstrap percentile intervals.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
pub struct JointEntry {
    /// The estimate.
    pub value: f64,
    /// The 68.27% and 95% intervals, when bootstrapped.
    pub intervals: Option<IntervalEntry>,
}

impl MaterialEntry {
    /// The entry of `fit`.
    pub fn new(fit: &laminar_brdf_fit::JointFit) -> Self {
        let entry = |v: &laminar_brdf_fit::JointValue| JointEntry {
            value: v.value,
            intervals: v.intervals.map(|[i68, i95]| IntervalEntry {
                interval: Source::Bootstrap,
                lo68: i68.lo,
                hi68: i68.hi,
                lo95: i95.lo,
                hi95: i95.hi,
            }),
        };
        let p_value = |t: &laminar_brdf_fit::ChannelTest| match t {
            laminar_brdf_fit::ChannelTest::Tested { p_value, .. } => Some(*p_value),
            _ => None,
        };
        Self {
            sample: fit.sample.clone(),
            model: fit.model,
            shared: (fit.shared.iter())
                .map(|v| (v.name.to_string(), entry(v)))
                .collect(),
            channels: (fit.channels.iter().enumerate())
                .filter_map(|(c, ch)| {
                    Some(MaterialChannel {
                        channel: ch.channel.clone(),
                        a: ch.a.as_ref().map(entry),
                        beta: ch.beta,
                        amplitude: ch.amplitude,
                        data_scale: ch.data_scale,
                        sse: ch.sse,
                        lack_of_fit: ch.adequacy.lack_of_fit,
                        fitted: fit.fitted(c)?,
                    })
                })
                .collect(),
            measurements: fit.measurements,
            parameters: fit.parameter_count,
            resamples: fit.resamples,
            sse: fit.sse,
            chromatic_p: p_value(&fit.chromatic),
            roughness_p: p_value(&fit.shared_roughness),
            variants: (fit.variants.iter())
                .filter_map(|v| Some((v.variant.name().to_string(), v.rank?.delta)))
                .collect(),
        }
    }

    /// The label `sample/model`.
    pub fn label(&self) -> String {
        format!("{}/{}", self.sample, self.model)
    }

    /// Channel `channel`'s label `sample/channel/model`.
    pub fn channel_label(&self, channel: &MaterialChannel) -> String {
        format!("{}/{}/{}", self.sample, channel.channel, self.model)
    }
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
            chi2_weighted: r.chi2_weighted,
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

#[cfg(test)]
mod tests {
    use super::json_file::empty_file;
    use super::*;
    use laminar_brdf_fit::{synthetic, Fitter, Grid, NormalisationConstants};
    use std::path::Path;

    /// A material written and read back whole; its channels are selected
    /// by their labels as fits are, the material by `sample/model`.
    #[test]
    fn a_material_round_trips_and_its_channels_are_selected() {
        use crate::selection::SelectError;
        use laminar_brdf_fit::{Analysis, Uncertainty};
        let scenes: Vec<_> = [(0.1, "r"), (0.5, "b")]
            .into_iter()
            .enumerate()
            .map(|(seed, (a, name))| {
                let truth = laminar_brdf_core::Params::new(0.4, 0.3, 1.45, a).unwrap();
                let correlation = laminar_brdf_core::Correlation::Exponential;
                synthetic::scene(correlation, &truth, 0.01, 5 + seed as u64).labelled("paint", name)
            })
            .collect();
        let fitter = Fitter::new(Grid::user()).unwrap().analysis(Analysis {
            uncertainty: Uncertainty::Off,
            folds: 0,
            ..Analysis::FULL
        });
        let joint = fitter.fit_joint(&scenes, Model::Exp).unwrap();
        let entry = MaterialEntry::new(&joint);
        assert_eq!(entry.channels.len(), 2);
        assert_eq!(entry.variants.len(), 2, "joint and separate");
        let file = parse_fits(
            Path::new("m.json"),
            &json_materials(std::slice::from_ref(&entry)),
        )
        .unwrap();
        assert_eq!(file.version, VERSION);
        assert!(file.fits.is_empty());
        assert_eq!(file.materials, std::slice::from_ref(&entry));
        let blue = file.select(Some("paint/b/exp")).unwrap();
        assert_eq!(blue.fitted, entry.channels[1].fitted);
        assert_eq!(blue.fitted, joint.fitted(1).unwrap());
        assert_eq!(blue.rms, None);
        assert!(matches!(
            file.select(None),
            Err(SelectError::Ambiguous { count: 2, .. })
        ));
        assert_eq!(file.select_material(None).unwrap().label(), "paint/exp");
        assert_eq!(file.select_material(Some("paint/exp")).unwrap(), &entry);
        let missing = file.select_material(Some("paint/gauss")).unwrap_err();
        assert_eq!(
            missing.to_string(),
            "no material `paint/gauss`; the file holds paint/exp"
        );
        // A file of fits alone has no `materials` key and no material.
        let plain = json_entries(&[]);
        assert!(!plain.contains("materials"));
        let none = parse_fits(Path::new("f.json"), &plain).unwrap();
        assert!(matches!(
            none.select_material(None),
            Err(SelectError::NoMaterial { .. })
        ));
    }

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
            slope: laminar_brdf_fit::Axis::stepped(1.32, 0.08, 5),
            a: laminar_brdf_fit::Axis::stepped(0.0, 0.05, 5),
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
        assert_eq!(rh.rms, one.fits[0].rh_rms);
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
        assert_eq!(both.select(Some(&rh_label)).unwrap().rms, Some(123.0));
    }

    fn fit(objective: Objective) -> Fit {
        let grid = Grid {
            slope: laminar_brdf_fit::Axis::stepped(1.32, 0.08, 5),
            a: laminar_brdf_fit::Axis::stepped(0.13, 0.01, 9),
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
    fn the_current_version_round_trips_and_older_files_are_read() {
        let free = json(&[fit(Objective::Free)]);
        let back = parse_fits(Path::new("f.json"), &free).unwrap();
        assert_eq!((back.version, VERSION), (4, 4));
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
        for key in ["objective", "amplitude", "chi2_weighted"] {
            v1["fits"][0].as_object_mut().unwrap().remove(key);
        }
        let back = parse_fits(Path::new("old.json"), &v1.to_string()).unwrap();
        assert_eq!(back.fits[0].objective, Objective::Paper);
        // A version 2 file names the weighted χ²/ν `chi2w_dof`.
        let mut v2: serde_json::Value =
            serde_json::from_str(&json(&[fit(Objective::Free)])).unwrap();
        let weighted = v2["fits"][0]["chi2_weighted"].clone();
        assert!(weighted.is_number(), "{weighted}");
        let entry = v2["fits"][0].as_object_mut().unwrap();
        entry.remove("chi2_weighted");
        entry.insert("chi2w_dof".into(), weighted.clone());
        v2["version"] = 2.into();
        let back = parse_fits(Path::new("v2.json"), &v2.to_string()).unwrap();
        assert_eq!(back.fits[0].chi2_weighted, weighted.as_f64());
        // A later version is refused with a message naming both.
        // Version 3 (before the materials) is read.
        v1["version"] = 3.into();
        assert!(parse_fits(Path::new("v3.json"), &v1.to_string()).is_ok());
        v1["version"] = 5.into();
        let e = parse_fits(Path::new("new.json"), &v1.to_string()).unwrap_err();
        assert!(
            e.to_string()
                .contains("version 5, expected `laminar-fits` version 1 to 4"),
            "{e}"
        );
    }
}
