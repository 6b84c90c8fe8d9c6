//! The exports of the fitting package (feature `fit`): measurements from
//! files, fits, prediction with a fitted-model file; each argument's type
//! checked first, as the evaluation exports are ([`super`]).

use super::{number, numbers, string, type_error};
use crate::fitting::{self, settings_from_js, FitOptions};
use crate::measurements::{self, Measurements, SceneData};
use laminar_brdf_fit::Settings;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

/// Argument `name` as a string, or `None` for `undefined` or `null`.
fn optional_string(value: &JsValue, name: &str) -> Result<Option<String>, JsValue> {
    if value.is_undefined() || value.is_null() {
        return Ok(None);
    }
    string(value, name).map(Some)
}

/// Argument `name` as a whole number in `[0, 2³² − 1]`.
fn whole(value: &JsValue, name: &str) -> Result<u32, JsValue> {
    let x = number(value, name)?;
    if x.fract() == 0.0 && (0.0..=f64::from(u32::MAX)).contains(&x) {
        Ok(x as u32)
    } else {
        Err(js_sys::RangeError::new(&format!("{name}: give a whole number ≥ 0 (got {x})")).into())
    }
}

/// Argument `name` as bytes: a `Uint8Array`.
fn bytes(value: &JsValue, name: &str) -> Result<Vec<u8>, JsValue> {
    let a = value
        .dyn_ref::<js_sys::Uint8Array>()
        .ok_or_else(|| type_error(name, "a Uint8Array", value))?;
    let len = a.length() as usize;
    let mut v = super::room(len, name)?;
    v.resize(len, 0);
    a.copy_to(&mut v);
    Ok(v)
}

/// The settings and progress callback of `fit`'s and `compare`'s options
/// (the defaults without options).
fn settings_of(
    options: Option<FitOptions>,
) -> Result<(Settings, Option<js_sys::Function>), JsValue> {
    match options {
        Some(o) => Ok(settings_from_js(&o)?),
        None => Ok((Settings::default(), None)),
    }
}

/// Every model `fit` takes, from the model descriptor
/// (`laminar_brdf_fit::Model`): its name, description, parameters in output
/// order, and for a layered model its correlation's name (what the
/// evaluation functions take), else `null`.
#[wasm_bindgen(
    unchecked_return_type = "Array<{ name: string; description: string; params: string[]; correlation: string | null }>"
)]
pub fn models() -> Result<JsValue, JsValue> {
    let list = js_sys::Array::new();
    for m in laminar_brdf_fit::Model::ALL {
        let o = js_sys::Object::new();
        let set = |k: &str, v: JsValue| js_sys::Reflect::set(&o, &JsValue::from_str(k), &v);
        set("name", m.name().into())?;
        set("description", m.description().into())?;
        let params: js_sys::Array = m
            .params()
            .iter()
            .map(|p| JsValue::from_str(p.name()))
            .collect();
        set("params", params.into())?;
        set(
            "correlation",
            m.correlation().map_or(JsValue::NULL, |c| c.name().into()),
        )?;
        list.push(&o);
    }
    Ok(list.into())
}

/// The sample numbers of a CUReT BRDF file (`abrdf.dat`, `rbrdf.dat`, …)
/// on its geometry table (`table.txt`).
///
/// # Errors
/// A `TypeError` for an argument of the wrong type; an `Error` when either
/// file has a defect (the message names file, line, column and value).
#[wasm_bindgen(js_name = curetSamples)]
pub fn curet_samples(
    #[wasm_bindgen(unchecked_param_type = "Uint8Array")] table: JsValue,
    #[wasm_bindgen(js_name = brdfName, unchecked_param_type = "string")] brdf_name: JsValue,
    #[wasm_bindgen(unchecked_param_type = "Uint8Array")] brdf: JsValue,
) -> Result<Vec<u32>, JsValue> {
    let table = bytes(&table, "table")?;
    let name = string(&brdf_name, "brdfName")?;
    let brdf = bytes(&brdf, "brdf")?;
    Ok(measurements::curet_samples(&table, &name, &brdf)?)
}

#[wasm_bindgen]
impl Measurements {
    /// A long-format CSV (the `laminar fit --measurements` format: geometry
    /// columns `theta_i, phi_i, theta_v, phi_v` or `theta_i, theta_s,
    /// phi_s`, every other numeric column a channel, `sigma`/`sigma_<channel>`
    /// uncertainties, `#` comments). `name` names the set and the errors;
    /// `angles` is `rad` or `deg`, `quantity` `brdf` or `radiance`.
    ///
    /// # Errors
    /// A `TypeError` for an argument of the wrong type; an `Error` for a
    /// defect, naming the file, line, column and value.
    #[wasm_bindgen(js_name = fromCsv)]
    pub fn from_csv_js(
        #[wasm_bindgen(unchecked_param_type = "string")] name: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Uint8Array")] bytes: JsValue,
        #[wasm_bindgen(unchecked_param_type = "string")] angles: JsValue,
        #[wasm_bindgen(unchecked_param_type = "string")] quantity: JsValue,
    ) -> Result<Measurements, JsValue> {
        from_file_args([&name, &bytes, &angles, &quantity], Self::from_csv)
    }

    /// A measurement file of any format the CLI reads on its own, chosen by
    /// its name: ASTM E1392 (`.astm`), RGL's tensor files (`.bsdf`), NIST's
    /// BRDF CSV (a `.csv` whose header starts `lambda,`), else the
    /// long-format CSV of `fromCsv` (with `angles` and `quantity`).
    ///
    /// # Errors
    /// A `TypeError` for an argument of the wrong type; an `Error` for a
    /// defect, naming the file and the line (or byte), column and value.
    #[wasm_bindgen(js_name = fromFile)]
    pub fn from_file_js(
        #[wasm_bindgen(unchecked_param_type = "string")] name: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Uint8Array")] bytes: JsValue,
        #[wasm_bindgen(unchecked_param_type = "string")] angles: JsValue,
        #[wasm_bindgen(unchecked_param_type = "string")] quantity: JsValue,
    ) -> Result<Measurements, JsValue> {
        from_file_args([&name, &bytes, &angles, &quantity], Self::from_file)
    }

    /// One sample of a CUReT BRDF file on its geometry table: lab-frame
    /// angles, BRDF values, one channel named after the file (`avg` for
    /// `abrdf.dat`, `r`, `g`, `b`).
    ///
    /// # Errors
    /// A `TypeError` for an argument of the wrong type; an `Error` for a
    /// defect in either file, or a sample the file lacks.
    #[wasm_bindgen(js_name = fromCuret)]
    pub fn from_curet_js(
        #[wasm_bindgen(unchecked_param_type = "Uint8Array")] table: JsValue,
        #[wasm_bindgen(js_name = brdfName, unchecked_param_type = "string")] brdf_name: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Uint8Array")] brdf: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] sample: JsValue,
    ) -> Result<Measurements, JsValue> {
        let table = bytes(&table, "table")?;
        let name = string(&brdf_name, "brdfName")?;
        let brdf = bytes(&brdf, "brdf")?;
        let sample = whole(&sample, "sample")?;
        Ok(Self::from_curet(&table, &name, &brdf, sample)?)
    }

    /// What a fit of `channel` sees: the kept (non-specular) measurements'
    /// paper-frame angles and their radiance divided by its max (§4).
    ///
    /// # Errors
    /// A `TypeError` for a channel that is not a string; an `Error` for a
    /// channel the set lacks, or one that cannot be fitted.
    #[wasm_bindgen(js_name = scene)]
    pub fn scene_js(
        &self,
        #[wasm_bindgen(unchecked_param_type = "string")] channel: JsValue,
    ) -> Result<SceneData, JsValue> {
        Ok(self.scene(&string(&channel, "channel")?)?)
    }
}

/// Fits `model` (`exp`, `gauss`, `rh-exp`, `rh-gauss`, `jensen`,
/// `oren-nayar`) to `channel` of `measurements` as `laminar fit` does (the
/// free objective on its grid, refinement and both uncertainties, unless
/// `options` says otherwise) and returns the fitted-model file
/// (`laminar fit --format json`) of that one fit. `options.onProgress(done,
/// total)` is called after each grid shard (paper objective: one σ/T value;
/// free objective: once per fit); a `fit` called from it runs as its own
/// fit, with its own progress.
///
/// # Errors
/// A `TypeError` for an argument or option of the wrong type (named); an
/// `Error` for an unknown model, a wrong option value, or a channel the set
/// lacks or that cannot be fitted.
#[wasm_bindgen(js_name = fit)]
pub fn fit(
    measurements: &Measurements,
    #[wasm_bindgen(unchecked_param_type = "string")] channel: JsValue,
    #[wasm_bindgen(unchecked_param_type = "string")] model: JsValue,
    options: Option<FitOptions>,
) -> Result<String, JsValue> {
    let (channel, model) = (string(&channel, "channel")?, string(&model, "model")?);
    let (settings, progress) = settings_of(options)?;
    Ok(fitting::fit(
        measurements,
        &channel,
        &model,
        &settings,
        progress,
    )?)
}

/// Fits each model of `models` (names as `fit` takes them) to `channel` of
/// `measurements` and compares them, as `laminar fit --models` does: the
/// fitted-model file of every fit, in the order of `models`, each with its
/// `rank` (by AICc, with ΔAICc and the Akaike weight), `information` and
/// `cross_validation` (`options.folds` folds, default 5, dealt by
/// `options.seed`). `options` as `fit`'s; `onProgress` counts every
/// model's shards.
///
/// # Errors
/// A `TypeError` for an argument or option of the wrong type (named); an
/// `Error` for an unknown model, a wrong option value, or a channel the set
/// lacks or that cannot be fitted.
#[wasm_bindgen(js_name = compare)]
pub fn compare(
    measurements: &Measurements,
    #[wasm_bindgen(unchecked_param_type = "string")] channel: JsValue,
    #[wasm_bindgen(unchecked_param_type = "string[]")] models: JsValue,
    options: Option<FitOptions>,
) -> Result<String, JsValue> {
    let channel = string(&channel, "channel")?;
    let list = models
        .dyn_ref::<js_sys::Array>()
        .ok_or_else(|| type_error("models", "an array of model names", &models))?;
    let names = list
        .iter()
        .enumerate()
        .map(|(i, m)| string(&m, &format!("models[{i}]")))
        .collect::<Result<Vec<_>, _>>()?;
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let (settings, progress) = settings_of(options)?;
    Ok(fitting::compare(
        measurements,
        &channel,
        &names,
        &settings,
        progress,
    )?)
}

/// One fit of the layered `model` (`exp2` and `gauss2` free the
/// subsurface's σ′/T′) across every channel of `measurements`, as `laminar
/// fit-joint --fits` does: σ/T, σ′/T′ and n shared, a, β and the amplitude
/// per channel, with the pairs bootstrap's intervals (`options.resamples`,
/// `options.seed`), the tests of one a and of one σ/T for every channel, and
/// the variants' ΔAICc. Returns the fitted-model file of the one material
/// (`materials[0]`); `predict` selects a channel's fit by
/// `sample/channel/model`. `options` as `fit`'s (`options.noise:
/// 'relative'` for goniometer data); `onProgress` is not called.
///
/// # Errors
/// A `TypeError` for an argument or option of the wrong type (named); an
/// `Error` for an unknown or a baseline model, a wrong option value, fewer
/// than two channels, or a channel that cannot be fitted.
#[wasm_bindgen(js_name = fitJoint)]
pub fn fit_joint(
    measurements: &Measurements,
    #[wasm_bindgen(unchecked_param_type = "string")] model: JsValue,
    options: Option<FitOptions>,
) -> Result<String, JsValue> {
    let model = string(&model, "model")?;
    let (settings, _) = settings_of(options)?;
    Ok(fitting::fit_joint(measurements, &model, &settings)?)
}

/// The normalised prediction of a fitted model at each geometry of
/// `angles` (flat (θi, θs, φs) triples, radians): exactly what the fit
/// predicted at its own geometries (`laminar predict`). `fitsJson` is a
/// fitted-model file (from `fit` or `laminar fit --format json`); `select`
/// (`sample/channel/model`, or `undefined`) picks a fit when it holds
/// several.
///
/// # Errors
/// A `TypeError` for an argument of the wrong type; an `Error` when the
/// file is not a fitted-model file, `select` matches no fit (or is missing
/// with several fits), or a geometry is out of range.
#[wasm_bindgen]
pub fn predict(
    #[wasm_bindgen(js_name = fitsJson, unchecked_param_type = "string")] fits_json: JsValue,
    #[wasm_bindgen(unchecked_param_type = "string | undefined | null")] select: JsValue,
    #[wasm_bindgen(unchecked_param_type = "Float64Array")] angles: JsValue,
) -> Result<Vec<f64>, JsValue> {
    let json = string(&fits_json, "fitsJson")?;
    let select = optional_string(&select, "select")?;
    let angles = numbers(&angles, "angles")?;
    Ok(fitting::predict(&json, select.as_deref(), &angles)?)
}

/// A file's constructor (`fromCsv`, `fromFile`) on its arguments `name`,
/// `bytes`, `angles` and `quantity`, each checked by its name.
fn from_file_args(
    [name, bytes, angles, quantity]: [&JsValue; 4],
    make: fn(&str, &[u8], &str, &str) -> Result<Measurements, JsError>,
) -> Result<Measurements, JsValue> {
    let name = string(name, "name")?;
    let data = self::bytes(bytes, "bytes")?;
    let (angles, quantity) = (string(angles, "angles")?, string(quantity, "quantity")?);
    Ok(make(&name, &data, &angles, &quantity)?)
}
