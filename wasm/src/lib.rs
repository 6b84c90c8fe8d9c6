//! # laminar-wasm
//!
//! laminar for the web and node: the absorptive scattering model for rough
//! laminar surfaces (H. A. Dahlan and E. R. Hancock, ICPR 2016) compiled to
//! WebAssembly with `wasm-bindgen`. The same library as the `laminar`
//! command, single-threaded:
//!
//! * [`evaluate`]: eq. 8 and its components at arrays of geometries, in f64
//!   and in f32 (the `f32x8` lanes, bitwise the native scalar f32 path);
//!   parameter checks whose errors name the parameter.
//! * [`measurements`]: CSV and CUReT files from bytes, and the built-in
//!   example (the CLI's synthetic scene).
//! * [`fitting`]: the fitting library's fit (the free-amplitude objective
//!   on its grid unless told), refinement and uncertainty, returning the
//!   fitted-model file of `laminar fit --format json`; one fit across a
//!   file's channels (`laminar fit-joint --fits`'s material); prediction
//!   with a fitted model.
//!
//! * [`js`]: the exports, each argument's type checked first (a
//!   `TypeError` naming it).
//!
//! Angles are in the paper's frame (θi, θs, φs) in radians, passed as one
//! flat array of triples. An argument of the wrong type is a `TypeError`;
//! every other error is a JavaScript `Error` whose message names the
//! parameter, the geometry, or the file's line and column.
//! "§N" refers to the repository's `docs/conventions.md`.
//!
//! The exports are plain Rust functions too (JavaScript names in the
//! generated glue are camelCase: `fromCsv`, `totalRadianceF32`, …):
//!
//! ```
//! use laminar_brdf_fit::Settings;
//! use laminar_wasm::{fitting, measurements::{example_csv, Measurements}};
//! let m = Measurements::from_csv("example.csv", example_csv().as_bytes(), "rad", "radiance")?;
//! // The default: the free-amplitude objective, refined, with intervals.
//! let json = fitting::fit(&m, "value", "exp", &Settings::default(), None)?;
//! assert!(json.contains(r#""objective": "free""#), "{json}");
//! // The paper's grid search alone, as `laminar fit --objective paper --refine off --uncertainty off`:
//! // the example was made at a point of the paper grid.
//! let settings = Settings {
//!     objective: laminar_brdf_fit::Objective::Paper,
//!     analysis: laminar_brdf_fit::Analysis::NONE,
//!     ..Default::default()
//! };
//! let json = fitting::fit(&m, "value", "exp", &settings, None)?;
//! assert!(json.contains(r#""slope": 1.48"#), "{json}");
//! let scene = m.scene("value")?;
//! let p = fitting::predict(&json, None, &scene.angles())?;
//! assert_eq!(p.len(), scene.data().len());
//! # Ok::<(), wasm_bindgen::JsError>(())
//! ```

pub mod evaluate;
#[cfg(feature = "fit")]
pub mod fitting;
pub mod js;
#[cfg(feature = "fit")]
pub mod measurements;

use laminar_brdf_core::{Angles, Correlation};
use wasm_bindgen::JsError;

/// A JavaScript `Error` with `e`'s message.
fn error(e: impl std::fmt::Display) -> JsError {
    JsError::new(&e.to_string())
}

/// The correlation of an absorptive model's name ([`Correlation::name`]).
fn correlation(model: &str) -> Result<Correlation, JsError> {
    Correlation::from_name(model)
        .ok_or_else(|| error(format_args!("model `{model}`: give {}", Names)))
}

/// The names of [`Correlation::ALL`], quoted, joined by "or":
/// `` `exp` or `gauss` ``.
struct Names;

impl std::fmt::Display for Names {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut sep = "";
        for c in Correlation::ALL {
            f.write_str(sep)?;
            f.write_str("`")?;
            f.write_str(c.name())?;
            f.write_str("`")?;
            sep = " or ";
        }
        Ok(())
    }
}

/// Geometries from a flat array of (θi, θs, φs) triples, each checked.
fn geometries(angles: &[f64]) -> Result<Vec<Angles>, JsError> {
    if !angles.len().is_multiple_of(3) {
        return Err(error(format_args!(
            "angles has {} numbers: give (theta_i, theta_s, phi_s) triples, radians",
            angles.len()
        )));
    }
    angles
        .chunks_exact(3)
        .enumerate()
        .map(|(k, t)| {
            Angles::new(t[0], t[1], t[2]).map_err(|e| error(format_args!("geometry {k}: {e}")))
        })
        .collect()
}

/// The names the evaluation functions take as `model`: one absorptive
/// model per correlation function (`["exp", "gauss"]`), from the core's
/// descriptor ([`Correlation::ALL`]).
#[wasm_bindgen::prelude::wasm_bindgen]
pub fn correlations() -> Vec<wasm_bindgen::JsValue> {
    Correlation::ALL
        .iter()
        .map(|c| wasm_bindgen::JsValue::from_str(c.name()))
        .collect()
}

/// The version of the package (the crate's).
#[wasm_bindgen::prelude::wasm_bindgen]
pub fn version() -> String {
    env!("CARGO_PKG_VERSION").into()
}
