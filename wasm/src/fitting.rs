//! Fitting a measurement set in the browser, and predicting with the
//! fitted model: the fitting library's own code, single-threaded.

use crate::measurements::Measurements;
use crate::{error, geometries};
use laminar_brdf_fit::{Grid, Model, Param, Settings};
use laminar_brdf_io::fits;
use laminar_brdf_io::selection::SelectError;
use std::cell::RefCell;
use std::path::Path;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

thread_local! {
    /// The progress callback of the fit under way. The fitter wants a
    /// `Send + Sync` callback and a JavaScript function is neither; on
    /// wasm32 the whole fit runs on the calling thread (rayon falls back to
    /// it), so the callback is found through this thread's slot.
    static PROGRESS: RefCell<Option<(js_sys::Function, u64, u64)>> = const { RefCell::new(None) };
}

/// One shard done: counts it, then calls the callback with the slot
/// released (the callback may start a fit of its own, which takes the slot
/// for its duration; a borrow held across the call made that trap).
fn tick() {
    let call = PROGRESS.with(|slot| {
        slot.borrow_mut().as_mut().map(|(f, done, total)| {
            *done += 1;
            (f.clone(), *done, *total)
        })
    });
    if let Some((f, done, total)) = call {
        // A throwing callback must not stop the fit: its error is dropped.
        let _ = f.call2(
            &JsValue::NULL,
            &JsValue::from(done as f64),
            &JsValue::from(total as f64),
        );
    }
}

#[wasm_bindgen(typescript_custom_section)]
const FIT_OPTIONS: &str = r#"
/** Options of `fit`, each as the `laminar fit` flag of the same name. */
export interface FitOptions {
  /** 'free' (default): a free amplitude, β of eq. 8, weights 1/σ², inside
   * the box of the axes; 'paper': the paper's max-normalised objective. */
  objective?: 'free' | 'paper';
  /** Refine the best grid point (default true). */
  refine?: boolean;
  /** Intervals and standard deviations (default 'both': with the free
   * objective the robust interval is the headline; 'bootstrap' adds a pairs
   * bootstrap's percentile intervals as the headline). */
  uncertainty?: 'off' | 'profile' | 'jacobian' | 'both' | 'bootstrap';
  /** Resamples of the bootstrap, 2 to 100000 (default 200). */
  resamples?: number;
  /** Seed of the bootstrap's resamples and of the cross-validation's folds (default 0). */
  seed?: number;
  /** Folds of the cross-validation comparing models (0 for none, 2 to 100; default 5). */
  folds?: number;
  /** Grid axes (and the free objective's box) as `start:stop:count`,
   * `start:stop:count:log` or one value (default: the objective's grid). */
  slope?: string;
  beta?: string;
  n?: string;
  a?: string;
  /** Search path of the paper objective, e.g. 'envelope-f32x8' (the default). */
  path?: string;
  /** The free objective's grid stage: 'f64' (default) or 'f32' (the model's
   * terms at each grid point in f32x8 lanes; the refinement and intervals
   * still in f64). */
  precision?: 'f64' | 'f32';
  /** The free objective's noise model: 'given' (default: the file's
   * uncertainties, known; else equal weights), 'equal', or 'relative' (σ ∝
   * the value above a floor, the scale estimated: goniometer data). */
  noise?: 'given' | 'equal' | 'relative';
  /** Relative noise's floor, a fraction in (0, 1] of the median positive
   * value (default 1: relative above the median). */
  noise_floor?: number;
  /** Called after each grid shard (paper: one σ/T value; free: the whole
   * fit) with (done, total). */
  onProgress?: (done: number, total: number) => void;
}
"#;

#[wasm_bindgen]
extern "C" {
    /// The options object of [`fit`] (TypeScript `FitOptions`).
    #[wasm_bindgen(typescript_type = "FitOptions")]
    pub type FitOptions;
}

/// Settings and progress callback from a JavaScript options object
/// ([`FitOptions`]): each option is handed to the library's settings
/// ([`Settings::set`]) by its name; each wrong field is an error naming it.
pub(crate) fn settings_from_js(
    options: &JsValue,
) -> Result<(Settings, Option<js_sys::Function>), JsError> {
    let mut s = Settings::default();
    if options.is_undefined() || options.is_null() {
        return Ok((s, None));
    }
    let field = |name: &str| {
        js_sys::Reflect::get(options, &JsValue::from_str(name))
            .map_err(|_| error(format_args!("options: cannot read `{name}`")))
            .map(|v| (!v.is_undefined()).then_some(v))
    };
    let texts = ["objective", "uncertainty", "path", "noise"]
        .into_iter()
        .chain(Grid::PARAMS.map(Param::name));
    for name in texts {
        if let Some(v) = field(name)? {
            let text = v
                .as_string()
                .ok_or_else(|| error(format_args!("options.{name}: give a string")))?;
            s.set(name, &text)
                .map_err(|e| error(format_args!("options.{e}")))?;
        }
    }
    for name in ["resamples", "seed", "folds"] {
        if let Some(v) = field(name)? {
            let n = v
                .as_f64()
                .filter(|n| n.is_finite() && n.fract() == 0.0 && *n >= 0.0)
                .ok_or_else(|| error(format_args!("options.{name}: give a whole number")))?;
            s.set(name, &format!("{n:.0}"))
                .map_err(|e| error(format_args!("options.{e}")))?;
        }
    }
    if let Some(v) = field("noise_floor")? {
        let floor = v
            .as_f64()
            .ok_or_else(|| error("options.noise_floor: give a number"))?;
        s.set("noise_floor", &floor.to_string())
            .map_err(|e| error(format_args!("options.{e}")))?;
    }
    if let Some(v) = field("refine")? {
        s.analysis.refine = v
            .as_bool()
            .ok_or_else(|| error("options.refine: give true or false"))?;
    }
    let progress = field("onProgress")?
        .map(|f| {
            f.dyn_into::<js_sys::Function>()
                .map_err(|_| error("options.onProgress: give a function"))
        })
        .transpose()?;
    Ok((s, progress))
}

/// Fits `model` (`exp`, `gauss`, `rh-exp`, `rh-gauss`, `jensen`,
/// `oren-nayar`) to `channel` of `measurements` with `settings` (JavaScript:
/// [`crate::js::fitting::fit`]) and returns the fitted-model file of that one fit;
/// `progress(done, total)` is called after each grid shard.
///
/// # Errors
/// For an unknown model, or a channel the set lacks or that cannot be fitted.
pub fn fit(
    measurements: &Measurements,
    channel: &str,
    model: &str,
    settings: &Settings,
    progress: Option<js_sys::Function>,
) -> Result<String, JsError> {
    compare(measurements, channel, &[model], settings, progress)
}

/// Fits each of `models` to `channel` of `measurements` with `settings`, as
/// `laminar fit --models` does (several models: ranked and
/// cross-validated, [`laminar_brdf_fit::choice`]; JavaScript:
/// [`crate::js::fitting::compare`]), and returns the fitted-model file of
/// the fits in the order of `models`; `progress(done, total)` is called
/// after each grid shard.
///
/// # Errors
/// For an unknown model, or a channel the set lacks or that cannot be fitted.
pub fn compare(
    measurements: &Measurements,
    channel: &str,
    models: &[&str],
    settings: &Settings,
    progress: Option<js_sys::Function>,
) -> Result<String, JsError> {
    let models = models
        .iter()
        .map(|m| m.parse::<Model>().map_err(error))
        .collect::<Result<Vec<_>, _>>()?;
    let scenes = [measurements.set.scene(channel).map_err(error)?];
    let fitter = settings.fitter().map_err(error)?.on_progress(tick);
    let total = fitter.fit_all_shards(&scenes, &models);
    // A fit started from another fit's callback keeps the outer fit's
    // progress aside and gives it back when done.
    let outer = PROGRESS.with(|slot| slot.replace(progress.map(|f| (f, 0, total))));
    let fits = fitter.fit_all(&scenes, &models, |_, _| None);
    PROGRESS.with(|slot| *slot.borrow_mut() = outer);
    Ok(fits::json(&fits.map_err(error)?))
}

/// One fit of the layered `model` across every channel of `measurements`
/// (σ/T, σ′/T′ of an untied model and n shared; a, β and the amplitude per
/// channel), with `settings`, as `laminar fit-joint --fits` does
/// ([`laminar_brdf_fit::Fitter::fit_joint`]; JavaScript:
/// [`crate::js::fitting::fit_joint`]): the fitted-model file of the one
/// material, its channels in file order. Progress is not reported.
///
/// # Errors
/// For an unknown or a baseline model, fewer than two channels, a channel
/// that cannot be fitted, or the paper objective.
pub fn fit_joint(
    measurements: &Measurements,
    model: &str,
    settings: &Settings,
) -> Result<String, JsError> {
    let model = model.parse::<Model>().map_err(error)?;
    let scenes = (measurements.set.channel_names().into_iter())
        .map(|channel| measurements.set.scene(channel).map_err(error))
        .collect::<Result<Vec<_>, _>>()?;
    let fitter = settings.fitter().map_err(error)?;
    let joint = fitter.fit_joint(&scenes, model).map_err(error)?;
    Ok(fits::json_materials(&[fits::MaterialEntry::new(&joint)]))
}

/// The normalised prediction of a fitted model at each geometry of
/// `angles` (flat (θi, θs, φs) triples, radians): exactly what the fit
/// predicted at its own geometries (`laminar predict`). `fits_json` is a
/// fitted-model file (from [`fit`] or `laminar fit --format json`);
/// `select` (`sample/channel/model`) picks a fit when it holds several.
///
/// # Errors
/// When the file is not a fitted-model file, `select` matches no fit (or is
/// missing with several fits), or a geometry is out of range.
pub fn predict(fits_json: &str, select: Option<&str>, angles: &[f64]) -> Result<Vec<f64>, JsError> {
    let file = fits::parse_fits(Path::new("fitted-model file"), fits_json).map_err(error)?;
    let entry = file.select(select).map_err(|e| match e {
        SelectError::Ambiguous { count, labels } => error(format_args!(
            "the file holds {count} fits: give select, one of {}",
            labels.join(", ")
        )),
        SelectError::NoMatch { select, labels } => error(format_args!(
            "select `{select}` matches no fit; the file holds {}",
            labels.join(", ")
        )),
        SelectError::Empty | SelectError::NoMaterial { .. } => error(format_args!("the file {e}")),
    })?;
    entry.fitted.predict(&geometries(angles)?).map_err(error)
}

#[cfg(test)]
mod tests {
    use laminar_brdf_fit::{settings, Grid, Noise, Objective, Param, Precision, Uncertainty};

    /// The `FitOptions` declaration, read from this file (wasm-bindgen
    /// takes the constant over, so the test reads the source).
    fn fit_options() -> &'static str {
        let source = include_str!("fitting.rs");
        let start = source
            .find("export interface FitOptions")
            .expect("FitOptions");
        let end = start + source[start..].find("\"#;").expect("its end");
        &source[start..end]
    }

    /// The hand-written `FitOptions` declaration names every option the
    /// settings take and every value of the objective and uncertainty.
    #[test]
    fn fit_options_declare_every_setting_and_value() {
        let union = |names: Vec<String>| {
            names
                .iter()
                .map(|n| format!("'{n}'"))
                .collect::<Vec<_>>()
                .join(" | ")
        };
        let objectives = union(Objective::ALL.map(|o| o.to_string()).to_vec());
        let declared = fit_options();
        assert!(declared.contains(&format!("objective?: {objectives};")));
        let uncertainties = union(Uncertainty::ALL.map(|u| u.to_string()).to_vec());
        assert!(declared.contains(&format!("uncertainty?: {uncertainties};")));
        let precisions = union(Precision::ALL.map(|p| p.to_string()).to_vec());
        assert!(declared.contains(&format!("precision?: {precisions};")));
        let noises = union(Noise::NAMES.map(String::from).to_vec());
        assert!(declared.contains(&format!("noise?: {noises};")));
        let names = settings::NAMES
            .into_iter()
            .filter(|&n| n != "threads") // one thread in the browser
            .chain(Grid::PARAMS.map(Param::name));
        for name in names {
            assert!(declared.contains(&format!("  {name}?: ")), "{name}");
        }
    }
}
