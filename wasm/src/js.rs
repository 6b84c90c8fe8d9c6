//! The JavaScript boundary: every export of the package, each argument
//! checked for its type before anything reaches WebAssembly memory. A wrong
//! type is a `TypeError` naming the argument and what it got (a number for
//! a model name trapped with "memory access out of bounds"; the string
//! `'1.2'` for a number was silently coerced); every other error is an
//! `Error` from the library. The work is done by the Rust functions of
//! [`crate::evaluate`], [`crate::measurements`] and [`crate::fitting`],
//! which a Rust caller uses directly.

use crate::evaluate::{self, Components};
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

/// What `value` is, for a message: `the number 3`, `the string "1.2"`,
/// `undefined`, `an object`, ….
fn describe(value: &JsValue) -> String {
    if let Some(s) = value.as_string() {
        // Quoted by hand: `{:?}` would bring Unicode's escaping tables
        // into the evaluation-only package (its size budget).
        let shown: String = s.chars().take(40).collect();
        return format!("the string \"{shown}\"");
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

/// Argument `name` as a number (a JavaScript number, not a string holding one).
fn number(value: &JsValue, name: &str) -> Result<f64, JsValue> {
    value
        .as_f64()
        .ok_or_else(|| type_error(name, "a number", value))
}

/// An empty vector with room for `len` values of argument `name`, or a
/// `RangeError` naming it when the module's memory (4 GiB at most, less
/// what it holds) cannot give that room: an allocation that fails would
/// abort the module instead.
pub(crate) fn room<T>(len: usize, name: &str) -> Result<Vec<T>, JsValue> {
    let mut v = Vec::new();
    if v.try_reserve_exact(len).is_err() {
        let mib = len.saturating_mul(core::mem::size_of::<T>()) >> 20;
        return Err(js_sys::RangeError::new(&format!(
            "{name}: {mib} MiB do not fit in the module's memory (4 GiB at most): give fewer values at a time"
        ))
        .into());
    }
    Ok(v)
}

/// Argument `name` as numbers: a `Float64Array`, or an array of numbers.
fn numbers(value: &JsValue, name: &str) -> Result<Vec<f64>, JsValue> {
    if let Some(a) = value.dyn_ref::<js_sys::Float64Array>() {
        let len = a.length() as usize;
        let mut v = room(len, name)?;
        v.resize(len, 0.0);
        a.copy_to(&mut v);
        return Ok(v);
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
/// and the four parameters, each type-checked; and room for the `outputs`
/// arrays of one f64 per geometry the evaluation returns (a `RangeError`
/// naming `angles` when the module cannot hold them).
fn evaluation(
    model: &JsValue,
    angles: &JsValue,
    values: [&JsValue; 4],
    outputs: usize,
) -> Result<(String, Vec<f64>, [f64; 4]), JsValue> {
    let (model, angles, params) = (
        string(model, "model")?,
        numbers(angles, "angles")?,
        params(values)?,
    );
    // The outputs' room, asked for and given back (the allocator keeps it).
    drop(room::<f64>(
        (angles.len() / 3).saturating_mul(outputs),
        "angles",
    )?);
    Ok((model, angles, params))
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
    let (model, angles, [s, b, n, a]) = evaluation(&model, &angles, [&slope, &beta, &n, &a], 1)?;
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
    let (model, angles, [s, b, n, a]) = evaluation(&model, &angles, [&slope, &beta, &n, &a], 1)?;
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
    let (model, angles, [s, b, n, a]) = evaluation(&model, &angles, [&slope, &beta, &n, &a], 7)?;
    Ok(evaluate::components(&model, &angles, s, b, n, a)?)
}

/// Property `key` of the object `value` (named `name` in messages).
fn field(value: &JsValue, key: &str, name: &str) -> Result<JsValue, JsValue> {
    if !value.is_object() {
        return Err(type_error(name, "an object", value));
    }
    js_sys::Reflect::get(value, &JsValue::from_str(key))
}

/// The prediction of a fitted layered model at each geometry of `angles`
/// (flat (θi, θs, φs) triples, radians), from the `fitted` object of a
/// fitted-model file (`{model, params: {slope, beta, n, a}, normalisation:
/// {amplitude} | {surface_max, subsurface_max, mix_max}}`): the same
/// numbers as the fitting package's `predict`, bit for bit.
///
/// # Errors
/// A `TypeError` for a missing field or one of the wrong type (named, e.g.
/// `fitted.params.beta`); an `Error` as the Rust `predict_fitted`.
#[wasm_bindgen(js_name = predictFitted)]
pub fn predict_fitted(
    #[wasm_bindgen(unchecked_param_type = "object")] fitted: JsValue,
    #[wasm_bindgen(unchecked_param_type = "Float64Array")] angles: JsValue,
) -> Result<Vec<f64>, JsValue> {
    let model = string(&field(&fitted, "model", "fitted")?, "fitted.model")?;
    let params = field(&fitted, "params", "fitted")?;
    let values: Vec<f64> = ["slope", "beta", "n", "a"]
        .iter()
        .map(|p| {
            let name = format!("fitted.params.{p}");
            number(&field(&params, p, "fitted.params")?, &name)
        })
        .collect::<Result<_, _>>()?;
    let normalisation = field(&fitted, "normalisation", "fitted")?;
    const LAYERED: [&str; 3] = ["surface_max", "subsurface_max", "mix_max"];
    let mut layered = 0;
    for c in LAYERED {
        layered += usize::from(!field(&normalisation, c, "fitted.normalisation")?.is_undefined());
    }
    let names: &[&str] = if field(&normalisation, "amplitude", "fitted.normalisation")?
        .is_undefined()
    {
        &LAYERED
    } else if layered == 0 {
        &["amplitude"]
    } else {
        return Err(js_sys::Error::new(
                "fitted.normalisation holds amplitude and the paper objective's maxima: give one normalisation's constants",
            )
            .into());
    };
    let constants = names
        .iter()
        .map(|c| {
            let name = format!("fitted.normalisation.{c}");
            Ok((
                *c,
                number(&field(&normalisation, c, "fitted.normalisation")?, &name)?,
            ))
        })
        .collect::<Result<Vec<_>, JsValue>>()?;
    let angles = numbers(&angles, "angles")?;
    drop(room::<f64>(angles.len() / 3, "angles")?);
    let p = [values[0], values[1], values[2], values[3]];
    Ok(evaluate::predict_fitted(&model, &angles, p, &constants)?)
}

#[cfg(feature = "fit")]
pub mod fitting;
