//! The model at arrays of geometries (eqs. 1–14, total eq. 8); exported
//! to JavaScript by [`crate::js`], which checks the arguments' types.

use crate::{correlation, error, geometries};
use laminar_brdf_core::{
    components as components_of, f32x8, total_radiance, total_radiance_in, Angles, Geometry, Lane,
    Params, Scaling,
};
use wasm_bindgen::prelude::*;

/// Checks the parameters: σ/T > 0, β and a in [0, 1], n ≥ 1 (finite).
///
/// # Errors
/// An `Error` naming the first parameter out of its domain and its value,
/// e.g. `beta = 1.5 is outside [0, 1]`.
pub fn validate_params(slope: f64, beta: f64, n: f64, a: f64) -> Result<(), JsError> {
    params(slope, beta, n, a).map(|_| ())
}

fn params(slope: f64, beta: f64, n: f64, a: f64) -> Result<Params, JsError> {
    Params::new(slope, beta, n, a).map_err(error)
}

/// Eq. 8's total radiance in f64 at each geometry of `angles` (flat
/// (θi, θs, φs) triples, radians) for `model` (`exp` or `gauss`).
///
/// # Errors
/// For an unknown model, parameters out of their domain, or a geometry out
/// of range (the message names it).
pub fn total_radiance_f64(
    model: &str,
    angles: &[f64],
    slope: f64,
    beta: f64,
    n: f64,
    a: f64,
) -> Result<Vec<f64>, JsError> {
    let (corr, p) = (correlation(model)?, params(slope, beta, n, a)?);
    Ok(geometries(angles)?
        .iter()
        .map(|g| total_radiance(&Geometry::<f64>::splat(g), corr, &p))
        .collect())
}

/// Eq. 8's total radiance in f32, eight geometries at a time (`f32x8`;
/// SIMD in the `+simd128` build). Each value is bitwise the native scalar
/// f32 path's (`laminar_brdf_core::total_radiance::<f32>`).
///
/// # Errors
/// As [`total_radiance_f64`].
pub fn total_radiance_f32(
    model: &str,
    angles: &[f64],
    slope: f64,
    beta: f64,
    n: f64,
    a: f64,
) -> Result<Vec<f32>, JsError> {
    let (corr, p) = (correlation(model)?, params(slope, beta, n, a)?);
    let p = p.in_precision::<f32>();
    let all = geometries(angles)?;
    let mut out = Vec::with_capacity(all.len());
    for chunk in all.chunks(f32x8::LANES) {
        let g = Geometry::<f32x8>::from_lanes(|i| lane_angles(chunk, i));
        let v = total_radiance_in(&g, corr, &p);
        out.extend((0..chunk.len()).map(|i| v.lane(i)));
    }
    Ok(out)
}

/// Lane `i` of a chunk; the last geometry fills the lanes past its end.
fn lane_angles(chunk: &[Angles], i: usize) -> Angles {
    chunk[i.min(chunk.len() - 1)]
}

/// The seven quantities of eqs. 1–14 and 8 at each geometry, in f64.
#[wasm_bindgen]
pub struct Components {
    values: [Vec<f64>; 7],
}

#[wasm_bindgen]
impl Components {
    /// The Fresnel reflectance `f(θi, n)` at the boundary, coming in (eq. 6).
    #[wasm_bindgen(getter, js_name = fresnelIn)]
    pub fn fresnel_in(&self) -> Vec<f64> {
        self.values[0].clone()
    }
    /// The Fresnel reflectance `f(θs′, 1/n)`, going out (eq. 6).
    #[wasm_bindgen(getter, js_name = fresnelOut)]
    pub fn fresnel_out(&self) -> Vec<f64> {
        self.values[1].clone()
    }
    /// The absorbed fraction `A1 = a cos²θi (1 − f(θi, n))` (eq. 10).
    #[wasm_bindgen(getter, js_name = absorbIn)]
    pub fn absorb_in(&self) -> Vec<f64> {
        self.values[2].clone()
    }
    /// The absorbed fraction `A2 = a cos²θs2 (1 − f(θs′, 1/n))` (eqs. 11, 14).
    #[wasm_bindgen(getter, js_name = absorbOut)]
    pub fn absorb_out(&self) -> Vec<f64> {
        self.values[3].clone()
    }
    /// The surface radiance `L^sf` (eq. 1 or 2).
    #[wasm_bindgen(getter)]
    pub fn surface(&self) -> Vec<f64> {
        self.values[4].clone()
    }
    /// The subsurface radiance `L^sb` (eq. 12 or 13).
    #[wasm_bindgen(getter)]
    pub fn subsurface(&self) -> Vec<f64> {
        self.values[5].clone()
    }
    /// The total radiance `β L^sb + (1 − β) L^sf` (eq. 8).
    #[wasm_bindgen(getter)]
    pub fn total(&self) -> Vec<f64> {
        self.values[6].clone()
    }
}

/// The components of the model at each geometry, in f64.
///
/// # Errors
/// As [`total_radiance_f64`].
pub fn components(
    model: &str,
    angles: &[f64],
    slope: f64,
    beta: f64,
    n: f64,
    a: f64,
) -> Result<Components, JsError> {
    let (corr, p) = (correlation(model)?, params(slope, beta, n, a)?);
    let mut values: [Vec<f64>; 7] = Default::default();
    for g in geometries(angles)? {
        let c = components_of(&Geometry::<f64>::splat(&g), corr, &p).to_array();
        for (column, v) in values.iter_mut().zip(c) {
            column.push(v);
        }
    }
    Ok(Components { values })
}

/// The prediction of a fitted layered model (`exp`, `gauss`, `rh-exp`,
/// `rh-gauss`) at each geometry, from the parameters and normalisation
/// constants of its fitted-model file (`fitted.params`,
/// `fitted.normalisation`): the same numbers as the fitting package's
/// `predict`, bit for bit (both are `laminar_brdf_core::Scaling::predict` of the
/// core's raw terms). `constants` are `[amplitude]` (the free objective) or
/// `[surface_max, subsurface_max, mix_max]` (the paper's).
///
/// # Errors
/// For an unknown model, a Ragheb–Hancock model with `a ≠ 0`, parameters out
/// of their domain, a constant that is negative or not finite, a geometry
/// out of range, or a prediction that is not finite (each message names it).
pub fn predict_fitted(
    model: &str,
    angles: &[f64],
    [slope, beta, n, a]: [f64; 4],
    constants: &[(&str, f64)],
) -> Result<Vec<f64>, JsError> {
    let (corr, rh) = match model.strip_prefix("rh-") {
        Some(base) => (correlation(base)?, true),
        None => (correlation(model)?, false),
    };
    if rh && a != 0.0 {
        return Err(error(format_args!("model `{model}` has a = 0, not {a}")));
    }
    let p = params(slope, beta, n, a)?;
    for &(name, value) in constants {
        if !(value >= 0.0 && value.is_finite()) {
            return Err(error(format_args!(
                "normalisation constant {name} = {value}: a finite number ≥ 0 is needed"
            )));
        }
    }
    let scaling = match constants {
        [(_, amplitude)] => Scaling::Amplitude(*amplitude),
        [(_, surface), (_, subsurface), (_, mix)] => Scaling::Maxima {
            surface: *surface,
            subsurface: *subsurface,
            mix: *mix,
        },
        _ => {
            return Err(error(
                "normalisation: give amplitude, or surface_max, subsurface_max and mix_max",
            ))
        }
    };
    geometries(angles)?
        .iter()
        .enumerate()
        .map(|(k, g)| {
            let c = components_of(&Geometry::<f64>::splat(g), corr, &p);
            let v = scaling.predict(beta, c.surface, c.subsurface);
            if v.is_finite() {
                Ok(v)
            } else {
                Err(error(format_args!(
                    "prediction {v} at geometry {k} is not finite"
                )))
            }
        })
        .collect()
}
