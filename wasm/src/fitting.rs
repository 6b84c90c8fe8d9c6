//! Fitting a measurement set in the browser, and predicting with the
//! fitted model: the fitting library's own code, single-threaded.

use crate::geometries;
use crate::measurements::Measurements;
use laminar_fit::{Analysis, Fitter, Grid, Model, Uncertainty};
use laminar_io::fits;
use std::cell::RefCell;
use std::path::Path;
use wasm_bindgen::prelude::*;

thread_local! {
    /// The progress callback of the fit under way. The fitter wants a
    /// `Send + Sync` callback and a JavaScript function is neither; on
    /// wasm32 the whole fit runs on the calling thread (rayon falls back to
    /// it), so the callback is found through this thread's slot.
    static PROGRESS: RefCell<Option<(js_sys::Function, u64, u64)>> = const { RefCell::new(None) };
}

fn tick() {
    PROGRESS.with(|slot| {
        if let Some((f, done, total)) = slot.borrow_mut().as_mut() {
            *done += 1;
            // A throwing callback must not stop the fit: its error is dropped.
            let _ = f.call2(
                &JsValue::NULL,
                &JsValue::from(*done as f64),
                &JsValue::from(*total as f64),
            );
        }
    });
}

fn error(e: impl std::fmt::Display) -> JsError {
    JsError::new(&e.to_string())
}

/// Fits `model` (`exp`, `gauss`, `rh-exp`, `rh-gauss`, `jensen`,
/// `oren-nayar`) to `channel` of `measurements` on the paper grid with the
/// default search path, as `laminar fit` does, and returns the fitted-model
/// file (`laminar fit --format json`) of that one fit: parameters, Δ_RMS,
/// χ²/ν, the refined parameters with their 68%/95% intervals, and the
/// fitted model that [`predict`] uses.
///
/// `refine` and `uncertainty` (`off`, `profile`, `jacobian`, `both`) are
/// `--refine` and `--uncertainty` (defaults on, both). `onProgress(done,
/// total)` is called after each grid shard (one σ/T value; 50 for a layered
/// model on the paper grid); refinement and uncertainty follow the last one.
///
/// # Errors
/// For an unknown model or uncertainty, or a channel the set lacks or that
/// cannot be fitted.
#[wasm_bindgen]
pub fn fit(
    measurements: &Measurements,
    channel: &str,
    model: &str,
    refine: Option<bool>,
    uncertainty: Option<String>,
    #[wasm_bindgen(js_name = onProgress)] on_progress: Option<js_sys::Function>,
) -> Result<String, JsError> {
    let model: Model = model.parse().map_err(error)?;
    let uncertainty: Uncertainty = uncertainty
        .as_deref()
        .unwrap_or("both")
        .parse()
        .map_err(|e: String| error(e))?;
    let scene = measurements.set.scene(channel).map_err(error)?;
    let fitter = Fitter::new(Grid::paper())
        .map_err(error)?
        .analysis(Analysis {
            refine: refine.unwrap_or(true),
            uncertainty,
        })
        .on_progress(tick);
    let total = fitter.shards(model);
    PROGRESS.with(|slot| *slot.borrow_mut() = on_progress.map(|f| (f, 0, total)));
    let fit = fitter.fit(&scene, model);
    PROGRESS.with(|slot| *slot.borrow_mut() = None);
    Ok(fits::json(&[fit]))
}

/// The normalised prediction of a fitted model at each geometry of
/// `angles` (flat (θi, θs, φs) triples, radians): exactly what the fit
/// predicted at its own geometries (`laminar predict`). `fitsJson` is a
/// fitted-model file (from [`fit`] or `laminar fit --format json`);
/// `select` (`sample/channel/model`) picks a fit when it holds several.
///
/// # Errors
/// When the file is not a fitted-model file, `select` matches no fit (or is
/// missing with several fits), or a geometry is out of range.
#[wasm_bindgen]
pub fn predict(
    #[wasm_bindgen(js_name = fitsJson)] fits_json: &str,
    select: Option<String>,
    angles: &[f64],
) -> Result<Vec<f64>, JsError> {
    let file = fits::parse_fits(Path::new("fitted-model file"), fits_json).map_err(error)?;
    let labels: Vec<String> = file.fits.iter().map(|e| e.label()).collect();
    let entry = match (select.as_deref(), file.fits.as_slice()) {
        (None, [one]) => one,
        (None, _) => {
            return Err(error(format_args!(
                "the file holds {} fits: give select, one of {}",
                labels.len(),
                labels.join(", ")
            )))
        }
        (Some(s), all) => all.iter().find(|e| e.label() == s).ok_or_else(|| {
            error(format_args!(
                "select `{s}` matches no fit; the file holds {}",
                labels.join(", ")
            ))
        })?,
    };
    entry.fitted.predict(&geometries(angles)?).map_err(error)
}
