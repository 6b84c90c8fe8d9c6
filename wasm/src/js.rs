//! The JavaScript boundary: every export of the package, each argument
//! checked for its type before anything reaches WebAssembly memory. A wrong
//! type is a `TypeError` naming the argument and what it got (a number for
//! a model name trapped with "memory access out of bounds"; the string
//! `'1.2'` for a number was silently coerced); every other error is an
//! `Error` from the library. The work is done by the Rust functions of
//! [`crate::evaluate`], [`crate::measurements`] and [`crate::fitting`],
//! which a Rust caller uses directly.

use crate::evaluate::{self, Components};
use crate::fitting::{self, FitOptions, Settings};
use crate::measurements::{self, Measurements, SceneData};
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

/// What `value` is, for a message: `the number 3`, `the string "1.2"`,
/// `undefined`, `an object`, ….
fn describe(value: &JsValue) -> String {
    if let Some(s) = value.as_string() {
        let shown: String = s.chars().take(40).collect();
        return format!("the string {shown:?}");
    }
    if let Some(x) = value.as_f64() {
        return format!("the number {x}");
    }
    if let Some(b) = value.as_bool() {
        return format!("{b}");
    }
    if value.is_undefined() {
        return "undefined".into();
    }
    if value.is_null() {
        return "null".into();
    }
    match value.js_typeof().as_string().as_deref() {
        Some("object") if js_sys::Array::is_array(value) => "an array".into(),
        Some(kind @ ("object" | "undefined")) => format!("an {kind}"),
        Some(kind) => format!("a {kind}"),
        None => "a value".into(),
    }
}

/// A `TypeError`: argument `name` wants `want`.
fn type_error(name: &str, want: &str, got: &JsValue) -> JsValue {
    js_sys::TypeError::new(&format!("{name}: give {want} (got {})", describe(got))).into()
}

/// Argument `name` as a string.
fn string(value: &JsValue, name: &str) -> Result<String, JsValue> {
    value
        .as_string()
        .ok_or_else(|| type_error(name, "a string", value))
}

/// Argument `name` as a string, or `None` for `undefined` or `null`.
fn optional_string(value: &JsValue, name: &str) -> Result<Option<String>, JsValue> {
    if value.is_undefined() || value.is_null() {
        return Ok(None);
    }
    string(value, name).map(Some)
}

/// Argument `name` as a number (a JavaScript number, not a string holding one).
fn number(value: &JsValue, name: &str) -> Result<f64, JsValue> {
    value
        .as_f64()
        .ok_or_else(|| type_error(name, "a number", value))
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

/// Argument `name` as numbers: a `Float64Array`, or an array of numbers.
fn numbers(value: &JsValue, name: &str) -> Result<Vec<f64>, JsValue> {
    if let Some(a) = value.dyn_ref::<js_sys::Float64Array>() {
        return Ok(a.to_vec());
    }
    if js_sys::Array::is_array(value) {
        return js_sys::Array::from(value)
            .iter()
            .enumerate()
            .map(|(i, x)| number(&x, &format!("{name}[{i}]")))
            .collect();
    }
    Err(type_error(
        name,
        "a Float64Array (or an array of numbers)",
        value,
    ))
}

/// Argument `name` as bytes: a `Uint8Array`.
fn bytes(value: &JsValue, name: &str) -> Result<Vec<u8>, JsValue> {
    value
        .dyn_ref::<js_sys::Uint8Array>()
        .map(js_sys::Uint8Array::to_vec)
        .ok_or_else(|| type_error(name, "a Uint8Array", value))
}

/// The four parameters σ/T, β, n, a.
fn params(values: [&JsValue; 4]) -> Result<[f64; 4], JsValue> {
    let [s, b, n, a] = values;
    Ok([
        number(s, "slope")?,
        number(b, "beta")?,
        number(n, "n")?,
        number(a, "a")?,
    ])
}

/// The arguments every evaluation takes: the model name, the flat angles
/// and the four parameters, each type-checked.
fn evaluation(
    model: &JsValue,
    angles: &JsValue,
    values: [&JsValue; 4],
) -> Result<(String, Vec<f64>, [f64; 4]), JsValue> {
    Ok((
        string(model, "model")?,
        numbers(angles, "angles")?,
        params(values)?,
    ))
}

/// Checks the parameters: σ/T > 0, β and a in [0, 1], n ≥ 1 (finite).
///
/// # Errors
/// A `TypeError` for an argument that is not a number; an `Error` naming
/// the first parameter out of its domain and its value, e.g.
/// `beta = 1.5 is outside [0, 1]`.
#[wasm_bindgen(js_name = validateParams)]
pub fn validate_params(
    #[wasm_bindgen(unchecked_param_type = "number")] slope: JsValue,
    #[wasm_bindgen(unchecked_param_type = "number")] beta: JsValue,
    #[wasm_bindgen(unchecked_param_type = "number")] n: JsValue,
    #[wasm_bindgen(unchecked_param_type = "number")] a: JsValue,
) -> Result<(), JsValue> {
    let [s, b, n, a] = params([&slope, &beta, &n, &a])?;
    Ok(evaluate::validate_params(s, b, n, a)?)
}

/// Eq. 8's total radiance in f64 at each geometry of `angles` (flat
/// (θi, θs, φs) triples, radians) for `model` (`exp` or `gauss`).
///
/// # Errors
/// A `TypeError` for an argument of the wrong type; an `Error` for an
/// unknown model, parameters out of their domain, or a geometry out of
/// range (the message names it).
#[wasm_bindgen(js_name = totalRadiance)]
pub fn total_radiance(
    #[wasm_bindgen(unchecked_param_type = "string")] model: JsValue,
    #[wasm_bindgen(unchecked_param_type = "Float64Array")] angles: JsValue,
    #[wasm_bindgen(unchecked_param_type = "number")] slope: JsValue,
    #[wasm_bindgen(unchecked_param_type = "number")] beta: JsValue,
    #[wasm_bindgen(unchecked_param_type = "number")] n: JsValue,
    #[wasm_bindgen(unchecked_param_type = "number")] a: JsValue,
) -> Result<Vec<f64>, JsValue> {
    let (model, angles, [s, b, n, a]) = evaluation(&model, &angles, [&slope, &beta, &n, &a])?;
    Ok(evaluate::total_radiance_f64(&model, &angles, s, b, n, a)?)
}

/// Eq. 8's total radiance in f32, eight geometries at a time (`f32x8`;
/// SIMD in the `+simd128` build). Each value is bitwise the native scalar
/// f32 path's.
///
/// # Errors
/// As `totalRadiance`.
#[wasm_bindgen(js_name = totalRadianceF32)]
pub fn total_radiance_f32(
    #[wasm_bindgen(unchecked_param_type = "string")] model: JsValue,
    #[wasm_bindgen(unchecked_param_type = "Float64Array")] angles: JsValue,
    #[wasm_bindgen(unchecked_param_type = "number")] slope: JsValue,
    #[wasm_bindgen(unchecked_param_type = "number")] beta: JsValue,
    #[wasm_bindgen(unchecked_param_type = "number")] n: JsValue,
    #[wasm_bindgen(unchecked_param_type = "number")] a: JsValue,
) -> Result<Vec<f32>, JsValue> {
    let (model, angles, [s, b, n, a]) = evaluation(&model, &angles, [&slope, &beta, &n, &a])?;
    Ok(evaluate::total_radiance_f32(&model, &angles, s, b, n, a)?)
}

/// The seven quantities of eqs. 1–14 and 8 at each geometry, in f64.
///
/// # Errors
/// As `totalRadiance`.
#[wasm_bindgen]
pub fn components(
    #[wasm_bindgen(unchecked_param_type = "string")] model: JsValue,
    #[wasm_bindgen(unchecked_param_type = "Float64Array")] angles: JsValue,
    #[wasm_bindgen(unchecked_param_type = "number")] slope: JsValue,
    #[wasm_bindgen(unchecked_param_type = "number")] beta: JsValue,
    #[wasm_bindgen(unchecked_param_type = "number")] n: JsValue,
    #[wasm_bindgen(unchecked_param_type = "number")] a: JsValue,
) -> Result<Components, JsValue> {
    let (model, angles, [s, b, n, a]) = evaluation(&model, &angles, [&slope, &beta, &n, &a])?;
    Ok(evaluate::components(&model, &angles, s, b, n, a)?)
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
        let name = string(&name, "name")?;
        let data = self::bytes(&bytes, "bytes")?;
        let (angles, quantity) = (string(&angles, "angles")?, string(&quantity, "quantity")?);
        Ok(Self::from_csv(&name, &data, &angles, &quantity)?)
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
    let (settings, progress) = match options {
        Some(o) => Settings::from_js(&o)?,
        None => (Settings::default(), None),
    };
    Ok(fitting::fit(
        measurements,
        &channel,
        &model,
        &settings,
        progress,
    )?)
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
