// The fitted-model file's types (`laminar fit --format json`, wasm `fit`).
// Generated from the Rust types by laminar-brdf-io's test `typescript`
// (io/src/typescript.rs): do not edit; `LAMINAR_BLESS=1 cargo test -p
// laminar-brdf-io typescript` rewrites it.

/** A model's parameter, by name (laminar_brdf_fit::Param). */
export type Param = "slope" | "beta" | "n" | "a" | "sigma_a" | "sigma_s" | "sigma" | "rho" | "sub_slope";

/**
 * A model that laminar can fit.
 */
export type Model = "exp" | "gauss" | "exp2" | "gauss2" | "rh-exp" | "rh-gauss" | "jensen" | "oren-nayar";

/**
 * The objective of a fit.
 */
export type Objective = "free" | "paper";

/**
 * What an edge flag says.
 */
export type Edge = "range_edge" | "domain_bound" | "open_below" | "open_above" | "not_identified" | "misfit_sensitive" | "not_determined";

/**
 * Where an interval comes from.
 */
export type Source = "profile" | "jacobian" | "robust" | "bootstrap";

/**
 * What releasing a bound of the box gives: a diagnostic, not an estimate.
 */
export type Released = { 
/**
 * The parameter's value with its bound released (within the model's domain).
 */
value: number, 
/**
 * Δ_RMS (eq. 15) there.
 */
rms: number, 
/**
 * Δ_RMS of the fit in the box, to compare.
 */
rms_in_box: number, };

/**
 * The word `NOT_IDENTIFIED` in place of a value.
 */
export type NotIdentified = "not_identified";

/**
 * A parameter's value in `params`: a number, or `NOT_IDENTIFIED` when
 * the data do not determine it (`Fit::not_identified`).
 */
export type ParamValue = number | NotIdentified;

/**
 * An interval kept beside a parameter's headline.
 */
export type IntervalEntry = { 
/**
 * Where it comes from.
 */
interval: Source, 
/**
 * The 68.27% interval's lower end.
 */
lo68: number, 
/**
 * Its upper end.
 */
hi68: number, 
/**
 * The 95% interval's lower end.
 */
lo95: number, 
/**
 * Its upper end.
 */
hi95: number, };

/**
 * One searched parameter of a fit in the fitted-model file
 * (docs/conventions.md §11, §11b).
 */
export type FitParameter = { 
/**
 * The best grid point's value.
 */
grid: number, 
/**
 * After refinement (absent when not refined); `NOT_IDENTIFIED` when
 * the data do not determine the parameter (its flags say so).
 */
refined: ParamValue | null, 
/**
 * The 68.27% interval's lower end (absent when not computed).
 */
lo68: number | null, 
/**
 * Its upper end.
 */
hi68: number | null, 
/**
 * The 95% interval's lower end.
 */
lo95: number | null, 
/**
 * Its upper end.
 */
hi95: number | null, 
/**
 * Where the interval ends come from (the headline).
 */
interval: Source | null, 
/**
 * The other intervals computed, kept beside the headline.
 */
alternatives: Array<IntervalEntry>, 
/**
 * Free objective: the sandwich standard deviation over the
 * model-based one (about 1 when the model fits).
 */
misfit_ratio: number | null, 
/**
 * With a bootstrap: the largest Monte Carlo standard deviation of its
 * interval ends.
 */
bootstrap_error: number | null, 
/**
 * The Jacobian's standard deviation (absent at a domain bound).
 */
sd: number | null, 
/**
 * Edge flags (empty for an interior value).
 */
flags: Array<Edge>, 
/**
 * The box searched (free objective; absent for the paper's).
 */
box: [number, number] | null, 
/**
 * For an estimate on a face of the box that is not a bound of the
 * model's domain: one local fit with that bound released.
 */
released: Released | null, };

/**
 * The parameters of a model, named as in every output.
 */
export type ModelParams = { 
/**
 * σ/T.
 */
slope: number, 
/**
 * β.
 */
beta: number, 
/**
 * n.
 */
n: number, 
/**
 * a.
 */
a: number, } | { 
/**
 * σ/T.
 */
slope: number, 
/**
 * σ′/T′.
 */
sub_slope: number, 
/**
 * β.
 */
beta: number, 
/**
 * n.
 */
n: number, 
/**
 * a.
 */
a: number, } | { 
/**
 * σa.
 */
sigma_a: number, 
/**
 * σs′.
 */
sigma_s: number, } | { 
/**
 * σ.
 */
sigma: number, 
/**
 * ρ.
 */
rho: number, };

/**
 * The constants of the normalisation a fit used (docs/conventions.md §4).
 * A file's constants must be exactly one normalisation's: read with the
 * constants of two (`amplitude` beside `surface_max`), or an unknown
 * name, is an error naming them (which would the prediction use?).
 */
export type NormalisationConstants = { 
/**
 * `m_sf = max_k L^sf_k`.
 */
surface_max: number, 
/**
 * `m_sb = max_k L^sb_k`.
 */
subsurface_max: number, 
/**
 * `max_k (β L^sb_k/m_sb + (1−β) L^sf_k/m_sf)`.
 */
mix_max: number, } | { 
/**
 * `max_k L_k`.
 */
radiance_max: number, } | { 
/**
 * The fitted amplitude `c ≥ 0`.
 */
amplitude: number, };

/**
 * A fitted model: what is needed to predict anywhere.
 */
export type FittedModel = { 
/**
 * The model.
 */
model: Model, 
/**
 * Its parameters (full precision).
 */
params: ModelParams, 
/**
 * The normalisation constants.
 */
normalisation: NormalisationConstants, 
/**
 * Layered models: the balance β′ for which the raw eq. 8 mix
 * `β′ L^sb + (1 − β′) L^sf` has the fitted lobe's shape
 * (`None` for baselines, or when both terms are all zeros).
 */
beta_eq8: number | null, 
/**
 * Layered models: prediction = `eq8_scale · (β′ L^sb + (1 − β′) L^sf)`.
 */
eq8_scale: number | null, 
/**
 * The max of the measured radiance that the fit's data were divided by:
 * a prediction times `data_scale` is radiance in the input's units.
 */
data_scale: number, };

/**
 * The units of the fitted data, as the user states them: what `ρ ≤ 1`
 * means depends on them (docs/conventions.md §12).
 */
export type Units = "absolute" | "relative";

/**
 * A fitted model's directional albedo over view angles, in the file.
 */
export type Energy = { 
/**
 * The fitted data's units, as stated.
 */
units: Units, 
/**
 * View angles θv, degrees.
 */
theta_v: Array<number>, 
/**
 * ρ(θv) in the fitted data's units.
 */
albedo: Array<number>, 
/**
 * Each value's quadrature error.
 */
error: Array<number>, 
/**
 * True when ρ > 1 at some θv and the units are absolute: the fitted
 * model reflects more energy than it receives.
 */
energy_gain: boolean, };

/**
 * What the residuals say of a fit's adequacy.
 */
export type Adequacy = { 
/**
 * With σ given: `P(χ²_ν ≥ Σ w r²)` (absent without σ).
 */
chi2_p: number | null, 
/**
 * The runs test's standardised count of runs `(R + ½ − E R)/sd R`
 * (negative: fewer runs than independent residuals give).
 */
runs_z: number | null, 
/**
 * Its one-sided p-value `Φ(runs_z)`.
 */
runs_p: number | null, 
/**
 * True when either p-value is below `LACK_OF_FIT`.
 */
lack_of_fit: boolean, };

/**
 * A fit's information criteria.
 */
export type Information = { 
/**
 * Akaike's criterion.
 */
aic: number, 
/**
 * Akaike's with the small-sample correction (NaN-free: absent when
 * `K ≤ k + 1`).
 */
aicc: number | null, 
/**
 * Schwarz's Bayesian criterion.
 */
bic: number, };

/**
 * One model's place among the models fitted to a set.
 */
export type Rank = { 
/**
 * 1 for the best (lowest AICc).
 */
rank: number, 
/**
 * Its AICc above the best's (AIC when a fit of the set has no AICc:
 * every fit of a set is ranked by one criterion).
 */
delta: number, 
/**
 * Its Akaike weight among the models ranked.
 */
weight: number, };

/**
 * A fit's K-fold cross-validated error (`crate::free`'s
 * `cross_validation`): each measurement predicted by the fit to the folds
 * that hold it out.
 */
export type CrossValidation = { 
/**
 * Folds the measurements were dealt into.
 */
folds: number, 
/**
 * `sqrt(Σ w r²/K)` of the held-out residuals (w = 1/σ² with σ
 * given, else 1: then in units of the data divided by their max).
 */
rms: number, 
/**
 * The same measure of the full fit's own residuals, for comparison:
 * `rms` well above it says the model follows its training noise.
 */
in_sample: number, };

/**
 * A fit's graphics error measures (see the module docs).
 */
export type GraphicsMetrics = { 
/**
 * Ngan et al.'s cos θi-weighted RMS, in the input's units.
 */
cosine_rms: number, 
/**
 * Forés et al.'s cube-root distance, in the cube root of the input's units.
 */
cube_root: number, };

/**
 * One fit in the fitted-model file: the CSV's columns (params as an
 * object) and the portable fitted models.
 */
export type FitEntry = { 
/**
 * Sample label.
 */
sample: string, 
/**
 * Channel name.
 */
channel: string, 
/**
 * Model.
 */
model: Model, 
/**
 * The objective minimised (version 1 files: the paper's).
 */
objective: Objective, 
/**
 * Δ_RMS (eq. 15) of the reported estimate (`Fit::reported`).
 */
rms: number, 
/**
 * χ²/ν (eq. 16).
 */
chi2_dof: number | null, 
/**
 * Terms used in χ².
 */
chi2_used: number | null, 
/**
 * Measurements left out of χ² (D ≤ 0).
 */
chi2_left_out: number | null, 
/**
 * Parameters by name, rounded to 10 decimals.
 */
params: { [key in string]: ParamValue }, 
/**
 * Δ_RMS of the Ragheb–Hancock best (exp, gauss).
 */
rh_rms: number | null, 
/**
 * Its χ²/ν.
 */
rh_chi2_dof: number | null, 
/**
 * Its parameters.
 */
rh_params: { [key in string]: number } | null, 
/**
 * Kept measurements K.
 */
measurements: number, 
/**
 * Kept measurements with value ≤ 0.
 */
nonpositive: number, 
/**
 * The search's own Δ_RMS.
 */
search_rms: number, 
/**
 * The fitted model, to predict with: the refined one when the fit was
 * refined, else the grid's.
 */
fitted: FittedModel, 
/**
 * The grid's best as a fitted model, when `fitted` is the refined one.
 */
grid_fitted: FittedModel | null, 
/**
 * Δ_RMS of the grid's best (the `rms` above).
 */
rms_grid: number | null, 
/**
 * Δ_RMS of the refined estimate (never above `rms_grid`).
 */
rms_refined: number | null, 
/**
 * Correlations of the refined estimate from the Jacobian, `"a~b": r`.
 */
correlations: { [key in string]: number }, 
/**
 * Pairs whose correlation is at least 0.9 in magnitude, `"a~b": r`.
 */
trade_offs: { [key in string]: number }, 
/**
 * The Ragheb–Hancock best as a fitted model.
 */
rh_fitted: FittedModel | null, 
/**
 * Free objective: the fitted amplitude c of the estimate.
 */
amplitude: number | null, 
/**
 * Free objective: the weighted χ²/ν of the estimate (`chi2w_dof` in
 * version 2 files).
 */
chi2_weighted: number | null, 
/**
 * Each searched parameter under its name. Absent in files written
 * before it existed.
 */
parameters: { [key in string]: FitParameter }, 
/**
 * Free objective: whether the residuals say the model fits
 * (`laminar_brdf_fit::adequacy`).
 */
adequacy: Adequacy | null, 
/**
 * Free objective: the information criteria (`laminar_brdf_fit::choice`).
 */
information: Information | null, 
/**
 * The model's place among those fitted to the same set (several models).
 */
rank: Rank | null, 
/**
 * Free objective, several models: the K-fold cross-validated error
 * (`laminar_brdf_fit::choice::CrossValidation`).
 */
cross_validation: CrossValidation | null, 
/**
 * The graphics literature's error measures of the reported estimate
 * (`laminar_brdf_fit::graphics_metrics`).
 */
graphics: GraphicsMetrics | null, 
/**
 * The fitted model's energy, when asked for (`laminar fit --albedo`).
 */
energy?: Energy | null, };

/**
 * A jointly fitted value and its bootstrap percentile intervals.
 */
export type JointEntry = { 
/**
 * The estimate.
 */
value: number, 
/**
 * The 68.27% and 95% intervals, when bootstrapped.
 */
intervals: IntervalEntry | null, };

/**
 * One channel of a `MaterialEntry`.
 */
export type MaterialChannel = { 
/**
 * Channel name.
 */
channel: string, 
/**
 * Its absorption a (absent for a model without one).
 */
a: JointEntry | null, 
/**
 * Eq. 8's β.
 */
beta: number, 
/**
 * The amplitude of the data divided by `data_scale`.
 */
amplitude: number, 
/**
 * The max the channel's data were divided by.
 */
data_scale: number, 
/**
 * The channel's weighted objective at the joint estimate.
 */
sse: number, 
/**
 * Whether its residuals say the model does not fit.
 */
lack_of_fit: boolean, 
/**
 * The channel's fitted model at the joint estimate: what `predict`,
 * `render`, `export` and the renderers take (its label
 * `sample/channel/model` selects it).
 */
fitted: FittedModel, };

/**
 * One material: a joint fit across a sample's channels
 * (`laminar_brdf_fit::JointFit`, docs/conventions.md §4c), its shared
 * parameters once and each channel's own with its fitted model.
 */
export type MaterialEntry = { 
/**
 * Sample label.
 */
sample: string, 
/**
 * The layered model.
 */
model: Model, 
/**
 * The shared parameters (σ/T, σ′/T′ for an untied model, n) by name:
 * the estimate and the pairs bootstrap's percentile intervals.
 */
shared: { [key in string]: JointEntry }, 
/**
 * Each channel, in the order fitted.
 */
channels: Array<MaterialChannel>, 
/**
 * Measurements per channel.
 */
measurements: number, 
/**
 * Fitted parameters in all.
 */
parameters: number, 
/**
 * Bootstrap resamples behind the intervals (0: none).
 */
resamples: number, 
/**
 * `J = Σ_c F_c` at the estimate.
 */
sse: number, 
/**
 * The p-value of one a for every channel, when tested.
 */
chromatic_p: number | null, 
/**
 * The p-value of one σ/T for every channel, when tested.
 */
roughness_p: number | null, 
/**
 * Each variant fitted (`joint`, `roughness_per_channel`, `separate`)
 * by name: its AICc above the best variant's.
 */
variants: { [key in string]: number }, };

/**
 * The fitted-model file: `laminar fit --format json`.
 */
export type FitsFile = { 
/**
 * Always `FORMAT`.
 */
format: string, 
/**
 * `VERSION`.
 */
version: number, 
/**
 * What the numbers are, for a reader of the file.
 */
quantities: { [key in string]: string }, 
/**
 * The fits.
 */
fits: Array<FitEntry>, 
/**
 * The materials: joint fits across a sample's channels (`laminar
 * fit-joint --fits`). Absent from files without one.
 */
materials?: Array<MaterialEntry>, };
