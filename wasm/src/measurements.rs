//! Measurement sets from CSV and CUReT files given as bytes, and the
//! built-in example.

use crate::error;
use laminar_brdf_fit::{synthetic, MeasurementSet, Quantity};
use laminar_brdf_io::{astm, csv_file::parse_csv, curet, nist, rgl, AngleUnit};
use std::fmt::Write;
use std::path::Path;
use wasm_bindgen::prelude::*;

/// A measurement set: geometries and one or more named channels.
#[wasm_bindgen]
pub struct Measurements {
    pub(crate) set: MeasurementSet,
}

/// The library's own parser of an option's text, its error naming the option.
fn option<T>(name: &str, text: &str) -> Result<T, JsError>
where
    T: std::str::FromStr,
    T::Err: std::fmt::Display,
{
    text.parse().map_err(|e| error(format_args!("{name}: {e}")))
}

/// The CUReT geometry table and BRDF rows of two files' bytes.
fn curet_rows(
    table: &[u8],
    brdf_name: &str,
    brdf: &[u8],
) -> Result<(Vec<curet::TableRow>, Vec<curet::BrdfRow>), JsError> {
    let table = curet::parse_table(Path::new("table.txt"), table).map_err(error)?;
    let rows = curet::parse_brdf(Path::new(brdf_name), brdf, table.len()).map_err(error)?;
    Ok((table, rows))
}

/// The sample numbers of a CUReT BRDF file (`abrdf.dat`, `rbrdf.dat`, …)
/// on its geometry table (`table.txt`).
///
/// # Errors
/// When either file has a defect (the message names file, line, column and value).
pub fn curet_samples(table: &[u8], brdf_name: &str, brdf: &[u8]) -> Result<Vec<u32>, JsError> {
    Ok(curet_rows(table, brdf_name, brdf)?
        .1
        .iter()
        .map(|r| r.sample)
        .collect())
}

/// The Rust side of the constructors; JavaScript calls them through
/// [`crate::js`], which checks the arguments' types.
impl Measurements {
    /// A long-format CSV (the `laminar fit --measurements` format: geometry
    /// columns `theta_i, phi_i, theta_v, phi_v` or `theta_i, theta_s,
    /// phi_s`, every other numeric column a channel, `sigma`/`sigma_<channel>`
    /// uncertainties, `#` comments). `name` names the set and the errors;
    /// `angles` is `rad` or `deg`, `quantity` `brdf` or `radiance`.
    ///
    /// # Errors
    /// For a defect, naming the file, line, column and value.
    pub fn from_csv(
        name: &str,
        bytes: &[u8],
        angles: &str,
        quantity: &str,
    ) -> Result<Measurements, JsError> {
        let set = parse_csv(
            Path::new(name),
            bytes,
            option::<AngleUnit>("angles", angles)?,
            option::<Quantity>("quantity", quantity)?,
        )
        .map_err(error)?;
        Ok(Self { set })
    }

    /// A measurement file of any format the CLI reads on its own, by its
    /// name: ASTM E1392 (`.astm`), RGL's tensor files (`.bsdf`), NIST's
    /// BRDF CSV (a `.csv` whose header starts `lambda,`), else the
    /// long-format CSV ([`Measurements::from_csv`], with `angles` and
    /// `quantity`; the other formats state their own).
    ///
    /// # Errors
    /// For a defect, naming the file and the line (or byte), column and value.
    pub fn from_file(
        name: &str,
        bytes: &[u8],
        angles: &str,
        quantity: &str,
    ) -> Result<Measurements, JsError> {
        let file = Path::new(name);
        let extension = file
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        let set = match extension.as_deref() {
            Some("astm") => astm::parse_astm(file, bytes),
            Some("bsdf") => rgl::parse_rgl(file, bytes),
            _ if is_nist(bytes) => nist::parse_nist(file, bytes),
            _ => return Self::from_csv(name, bytes, angles, quantity),
        }
        .map_err(error)?;
        Ok(Self { set })
    }

    /// One sample of a CUReT BRDF file on its geometry table: lab-frame
    /// angles, BRDF values, one channel named after the file (`avg` for
    /// `abrdf.dat`, `r`, `g`, `b`).
    ///
    /// # Errors
    /// For a defect in either file, or a sample the file lacks.
    pub fn from_curet(
        table: &[u8],
        brdf_name: &str,
        brdf: &[u8],
        sample: u32,
    ) -> Result<Measurements, JsError> {
        let (table, rows) = curet_rows(table, brdf_name, brdf)?;
        let row = rows.iter().find(|r| r.sample == sample).ok_or_else(|| {
            error(format_args!(
                "{brdf_name}: no sample {sample} (it has {} samples, {} to {})",
                rows.len(),
                rows.first().map_or(0, |r| r.sample),
                rows.last().map_or(0, |r| r.sample)
            ))
        })?;
        let file = Path::new(brdf_name);
        let set = curet::measurement_set(file, &table, row, curet::Channel::from_file(file))
            .map_err(error)?;
        Ok(Self { set })
    }

    /// What a fit of `channel` sees: the kept (non-specular) measurements'
    /// paper-frame angles and their radiance divided by its max (§4).
    ///
    /// # Errors
    /// For a channel the set lacks, or one that cannot be fitted (no positive value).
    pub fn scene(&self, channel: &str) -> Result<SceneData, JsError> {
        let scene = self.set.scene(channel).map_err(error)?;
        Ok(SceneData {
            angles: scene
                .angles()
                .iter()
                .flat_map(|a| [a.theta_i(), a.theta_s(), a.phi_s()])
                .collect(),
            data: scene.data().to_vec(),
            data_scale: scene.data_scale(),
        })
    }
}

#[wasm_bindgen]
impl Measurements {
    /// The set's name (the file's stem, or the CUReT sample number).
    #[wasm_bindgen(getter)]
    pub fn name(&self) -> String {
        self.set.name().into()
    }

    /// The channel names, in file order.
    #[wasm_bindgen(getter)]
    pub fn channels(&self) -> Vec<String> {
        self.set
            .channel_names()
            .into_iter()
            .map(String::from)
            .collect()
    }

    /// The number of measurements (specular ones included).
    #[wasm_bindgen(getter)]
    pub fn length(&self) -> usize {
        self.set.len()
    }
}

/// One channel as fitted: geometries and normalised data.
#[wasm_bindgen]
pub struct SceneData {
    angles: Vec<f64>,
    data: Vec<f64>,
    data_scale: f64,
}

#[wasm_bindgen]
impl SceneData {
    /// Paper-frame (θi, θs, φs) triples, radians.
    #[wasm_bindgen(getter)]
    pub fn angles(&self) -> Vec<f64> {
        self.angles.clone()
    }
    /// The measured radiance divided by its max over these measurements.
    #[wasm_bindgen(getter)]
    pub fn data(&self) -> Vec<f64> {
        self.data.clone()
    }
    /// The max the radiance was divided by, in the input's units.
    #[wasm_bindgen(getter, js_name = dataScale)]
    pub fn data_scale(&self) -> f64 {
        self.data_scale
    }
}

/// The built-in example as a CSV in the `fromCsv` format: the `laminar
/// fit` command's synthetic scene (exp model at known parameters, with noise),
/// paper-frame angles in radians, values as radiance. Every number is
/// written so that it reads back exactly, so `laminar fit --measurements
/// example.csv --quantity radiance` fits the very same data.
#[wasm_bindgen(js_name = exampleCsv)]
pub fn example_csv() -> String {
    let scene = synthetic::default_scene();
    let (s, b, n, a) = synthetic::TRUE_PARAMS;
    let mut out = format!(
        "# laminar's built-in synthetic scene: exp model at slope={s}, beta={b}, n={n}, a={a}, \
         Gaussian noise sd {} of the max; paper frame, radians; radiance\n\
         theta_i,theta_s,phi_s,value\n",
        synthetic::NOISE
    );
    for (g, d) in scene.angles().iter().zip(scene.data()) {
        let _ = writeln!(out, "{},{},{},{}", g.theta_i(), g.theta_s(), g.phi_s(), d);
    }
    out
}

/// True when `bytes` start (after white space) with NIST's BRDF header,
/// `lambda,`.
fn is_nist(bytes: &[u8]) -> bool {
    let start = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(bytes.len());
    bytes[start..]
        .get(..7)
        .is_some_and(|h| h.eq_ignore_ascii_case(b"lambda,"))
}

#[cfg(test)]
mod tests {
    use super::is_nist;

    /// NIST's BRDF CSV is told from the long CSV by its header.
    #[test]
    fn nist_files_are_told_by_their_header() {
        assert!(is_nist(b"lambda,thetai,phi,thetar,phir,f_r11\r\n0.351,"));
        assert!(is_nist(b"\n  LAMBDA,thetai"));
        assert!(!is_nist(b"theta_i,phi_i,theta_v,phi_v,r\n"));
        assert!(!is_nist(b"lambda"));
        assert!(!is_nist(b""));
    }
}
