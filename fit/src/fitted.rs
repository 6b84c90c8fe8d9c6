//! Fitted models that predict anywhere (docs/conventions.md §4).
//!
//! The paper normalisation divides the surface term `L^sf` and the subsurface
//! term `L^sb` each by its own maximum over the fitted measurements, mixes
//! them with β and divides the mix by its maximum. Those three maxima depend
//! on the measured geometries, so a fitted β means nothing without them: a
//! [`FittedModel`] stores them, and predicts at any geometry exactly what the
//! fit predicted at its own. It also gives the equivalent balance of eq. 8,
//!
//! `beta_eq8 = (β/m_sb) / (β/m_sb + (1−β)/m_sf)`,
//!
//! with which the raw mix `beta_eq8 L^sb + (1 − beta_eq8) L^sf` (what
//! `laminar eval` prints) is the fitted prediction divided by `eq8_scale`.

use crate::baseline::BaselineGeometry;
use crate::error::ModelError;
use crate::model::{Baseline, Family};
use crate::model::{Model, Param};
use laminar_brdf_core::measures::max_of;
use laminar_brdf_core::prediction::scaled;
use laminar_brdf_core::{components, mix, Angles, Geometry, Params, Scaling};
use serde::{Deserialize, Serialize};

/// The parameters of a model, named as in every output.
///
/// Serialised as an object of the model's parameters by name
/// ([`Param::name`], in [`Model::params`]' order); read back as the
/// layered models' when all four of theirs are present, else as the first
/// baseline ([`Baseline::ALL`]) whose parameters all are. A baseline is one
/// variant for all of them, so a new one adds no code here.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ModelParams {
    /// The layered models: RMS slope σ/T, balance β, refractive index n, absorption a.
    Layered {
        /// σ/T.
        slope: f64,
        /// β (paper normalisation).
        beta: f64,
        /// n.
        n: f64,
        /// a (0 for Ragheb–Hancock).
        a: f64,
        /// σ′/T′ of the untied models (`None` when it is σ/T).
        sub_slope: Option<f64>,
    },
    /// A baseline's two parameters, in [`Baseline::params`]' order.
    Baseline {
        /// The baseline.
        baseline: Baseline,
        /// Its parameters' values.
        values: [f64; 2],
    },
}

impl Serialize for ModelParams {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let pairs = self.pairs();
        let mut map = s.serialize_map(Some(pairs.len()))?;
        for (p, v) in pairs {
            map.serialize_entry(p.name(), &v)?;
        }
        map.end()
    }
}

/// A `params` object as written, in order: each value by its name, each name once
/// (a name written twice is an error, as every other field of the file's
/// is); a value that is not a number is kept as absent.
struct WrittenParams(Vec<(String, Option<f64>)>);

impl<'de> Deserialize<'de> for WrittenParams {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = WrittenParams;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("an object of parameters by name")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut map: A,
            ) -> Result<Self::Value, A::Error> {
                #[derive(Deserialize)]
                #[serde(untagged)]
                enum Entry {
                    Number(f64),
                    Other(serde::de::IgnoredAny),
                }
                let mut out: Vec<(String, Option<f64>)> = Vec::new();
                while let Some((name, entry)) = map.next_entry::<String, Entry>()? {
                    if out.iter().any(|(n, _)| *n == name) {
                        return Err(serde::de::Error::custom(format!(
                            "params: parameter `{name}` is written twice"
                        )));
                    }
                    let value = match entry {
                        Entry::Number(v) => Some(v),
                        Entry::Other(_) => None,
                    };
                    out.push((name, value));
                }
                Ok(WrittenParams(out))
            }
        }
        d.deserialize_map(Visitor)
    }
}

impl WrittenParams {
    /// The number named as parameter `p`.
    fn number(&self, p: Param) -> Option<f64> {
        self.0
            .iter()
            .find(|(n, _)| n == p.name())
            .and_then(|(_, v)| *v)
    }

    /// The parameters of `model`: each of its own a number, and none of
    /// another model's (names no model has are ignored, as before the
    /// parameters were read by name).
    fn of(&self, model: Model) -> Result<ModelParams, String> {
        let own = model.params();
        // `names` (when any) refused, as `what` they are.
        let refuse = |names: Vec<Param>, what: &str| -> Result<(), String> {
            if names.is_empty() {
                return Ok(());
            }
            Err(format!(
                "params of {model}: {} {what} (its parameters: {})",
                param_names(&names),
                param_names(own)
            ))
        };
        let written = self.0.iter().filter_map(|(name, _)| Param::from_name(name));
        refuse(
            written.filter(|p| !own.contains(p)).collect(),
            &format!("not {model}'s"),
        )?;
        let missing = own.iter().copied().filter(|&p| self.number(p).is_none());
        refuse(missing.collect(), "without a number")?;
        Ok(ModelParams::from_values(model, |p| {
            self.number(p).unwrap_or(f64::NAN)
        }))
    }
}

impl<'de> Deserialize<'de> for ModelParams {
    /// Without its model: the untied models' when all five of theirs are
    /// present, the layered models' when all four of theirs are, else the
    /// first baseline's whose parameters all are.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let given = WrittenParams::deserialize(d)?;
        let all = |params: &[Param]| params.iter().all(|&p| given.number(p).is_some());
        let layered = Model::Exp.params();
        for model in [Model::Exp2, Model::Exp] {
            if all(model.params()) {
                return Ok(Self::from_values(model, |p| {
                    given.number(p).unwrap_or(f64::NAN)
                }));
            }
        }
        if let Some(b) = Baseline::ALL.into_iter().find(|b| all(b.params())) {
            return Ok(Self::baseline(
                b,
                b.params().map(|p| given.number(p).unwrap_or(f64::NAN)),
            ));
        }
        let sets: Vec<String> = [layered, Model::Exp2.params()]
            .into_iter()
            .chain(Baseline::ALL.iter().map(|b| &b.params()[..]))
            .map(|params| format!("{{{}}}", param_names(params)))
            .collect();
        Err(serde::de::Error::custom(format!(
            "params must hold numbers named as one model's parameters: {}",
            sets.join(" or ")
        )))
    }
}

#[cfg(feature = "typescript")]
impl ts_rs::TS for ModelParams {
    type WithoutGenerics = Self;
    type OptionInnerType = Self;

    fn docs() -> Option<String> {
        Some("/**\n * The parameters of a model, named as in every output.\n */\n".into())
    }

    fn name(_: &ts_rs::Config) -> String {
        "ModelParams".into()
    }

    fn decl(cfg: &ts_rs::Config) -> String {
        format!("type ModelParams = {};", Self::inline(cfg))
    }

    fn decl_concrete(cfg: &ts_rs::Config) -> String {
        Self::decl(cfg)
    }

    /// One object type per model family, from the descriptor.
    fn inline(_: &ts_rs::Config) -> String {
        let object = |params: &[Param]| {
            let fields: Vec<String> = params
                .iter()
                .map(|p| format!("\n/**\n * {}.\n */\n{}: number, ", p.symbol(), p.name()))
                .collect();
            format!("{{ {}}}", fields.concat())
        };
        [Model::Exp.params(), Model::Exp2.params()]
            .into_iter()
            .map(object)
            .chain(Baseline::ALL.iter().map(|b| object(&b.params()[..])))
            .collect::<Vec<_>>()
            .join(" | ")
    }
}

impl ModelParams {
    /// `model`'s parameters ([`Model::params`]), each taken from `value(p)`.
    pub fn from_values(model: Model, value: impl Fn(Param) -> f64) -> Self {
        match model.family() {
            Family::Baseline(b) => {
                let [x, y] = b.params().map(value);
                Self::baseline(b, [x, y])
            }
            Family::Layered { untied, .. } => Self::Layered {
                slope: value(Param::Slope),
                beta: value(Param::Beta),
                n: value(Param::N),
                a: value(Param::A),
                sub_slope: untied.then(|| value(Param::SubSlope)),
            },
        }
    }

    /// The parameters of `baseline` at `values` ([`Baseline::params`]' order).
    pub fn baseline(baseline: Baseline, values: [f64; 2]) -> Self {
        Self::Baseline { baseline, values }
    }

    /// A baseline's parameters and their values ([`Baseline::params`]'
    /// order); `None` for a layered model's.
    pub fn baseline_values(&self) -> Option<(Baseline, [f64; 2])> {
        match *self {
            Self::Layered { .. } => None,
            Self::Baseline { baseline, values } => Some((baseline, values)),
        }
    }

    /// The parameters these values are of, in output order.
    pub fn params(&self) -> &'static [Param] {
        match *self {
            Self::Layered {
                sub_slope: Some(_), ..
            } => Model::Exp2.params(),
            Self::Layered { .. } => Model::Exp.params(),
            Self::Baseline { baseline, .. } => baseline.params(),
        }
    }

    /// `(parameter, value)` pairs in output order.
    pub fn pairs(&self) -> Vec<(Param, f64)> {
        self.params()
            .iter()
            .map(|&p| (p, self.value(p).unwrap_or(f64::NAN)))
            .collect()
    }

    /// The value of parameter `p` (`None` when these are another model's).
    pub fn value(&self, p: Param) -> Option<f64> {
        // The position in [`ModelParams::params`], whichever family.
        let i = self.params().iter().position(|&q| q == p)?;
        Some(match *self {
            Self::Layered {
                slope,
                beta,
                n,
                a,
                sub_slope: None,
            } => [slope, beta, n, a][i],
            Self::Layered {
                slope,
                beta,
                n,
                a,
                sub_slope: Some(sub_slope),
            } => [slope, sub_slope, beta, n, a][i],
            Self::Baseline { values, .. } => values[i],
        })
    }

    /// The value of a parameter by its name ([`Param::name`]).
    pub fn get(&self, name: &str) -> Option<f64> {
        Param::from_name(name).and_then(|p| self.value(p))
    }

    /// `name=value` pairs joined by `;`, values rounded to 10 decimals
    /// (the `params` column).
    pub fn text(&self) -> String {
        self.text_masked(|_| false, "")
    }

    /// [`ModelParams::text`] with `mask` in place of the value of each
    /// parameter `masked` names.
    pub fn text_masked(&self, masked: impl Fn(Param) -> bool, mask: &str) -> String {
        self.pairs()
            .iter()
            .map(|&(k, v)| {
                if masked(k) {
                    format!("{k}={mask}")
                } else {
                    format!("{k}={}", format_value(v))
                }
            })
            .collect::<Vec<_>>()
            .join(";")
    }

    /// The core's validated parameters of a layered model.
    ///
    /// # Errors
    /// [`ModelError::WrongParameters`] for a baseline's parameters,
    /// [`ModelError::OutOfDomain`] for values outside [`Params::new`]'s domain.
    pub fn layered(&self) -> Result<Params, ModelError> {
        match *self {
            Self::Layered {
                slope,
                beta,
                n,
                a,
                sub_slope,
            } => Params::untied(slope, sub_slope.unwrap_or(slope), beta, n, a)
                .map_err(ModelError::OutOfDomain),
            Self::Baseline { .. } => Err(ModelError::WrongParameters {
                model: Model::layered()
                    .map(Model::name)
                    .collect::<Vec<_>>()
                    .join("/"),
                expected: param_names(Model::Exp.params()),
            }),
        }
    }
}

/// Parameters' names joined by `", "`.
pub fn param_names(params: &[Param]) -> String {
    params
        .iter()
        .map(|p| p.name())
        .collect::<Vec<_>>()
        .join(", ")
}

/// A value without float noise (rounded to 10 decimals), as printed in `params`.
pub fn format_value(v: f64) -> String {
    let r = (v * 1e10).round() / 1e10;
    format!("{}", if r == 0.0 { 0.0 } else { r })
}

/// The constants of the normalisation a fit used (docs/conventions.md §4).
/// A file's constants must be exactly one normalisation's: read with the
/// constants of two (`amplitude` beside `surface_max`), or an unknown
/// name, is an error naming them (which would the prediction use?).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[cfg_attr(feature = "typescript", derive(ts_rs::TS))]
#[serde(untagged)]
pub enum NormalisationConstants {
    /// Layered models: the maxima over the fit's kept measurements of the
    /// raw surface term, of the raw subsurface term, and of the mix of the
    /// two normalised terms. A maximum of 0 stands for a term that was all
    /// zeros (and is zero in every prediction).
    Layered {
        /// `m_sf = max_k L^sf_k`.
        surface_max: f64,
        /// `m_sb = max_k L^sb_k`.
        subsurface_max: f64,
        /// `max_k (β L^sb_k/m_sb + (1−β) L^sf_k/m_sf)`.
        mix_max: f64,
    },
    /// Baselines: the max of the raw radiance.
    Baseline {
        /// `max_k L_k`.
        radiance_max: f64,
    },
    /// The free-amplitude objective (docs/conventions.md §4b): the
    /// prediction is `amplitude · (β L^sb + (1 − β) L^sf)` (eq. 8's raw mix,
    /// β eq. 8's own), or `amplitude · L` for a baseline; no maximum enters.
    Amplitude {
        /// The fitted amplitude `c ≥ 0`.
        amplitude: f64,
    },
}

/// Every constant a file's normalisation may hold, to tell which one it is.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AnyConstants {
    surface_max: Option<f64>,
    subsurface_max: Option<f64>,
    mix_max: Option<f64>,
    radiance_max: Option<f64>,
    amplitude: Option<f64>,
}

impl<'de> Deserialize<'de> for NormalisationConstants {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let c = AnyConstants::deserialize(d)?;
        match c {
            AnyConstants {
                surface_max: Some(surface_max),
                subsurface_max: Some(subsurface_max),
                mix_max: Some(mix_max),
                radiance_max: None,
                amplitude: None,
            } => Ok(Self::Layered {
                surface_max,
                subsurface_max,
                mix_max,
            }),
            AnyConstants {
                surface_max: None,
                subsurface_max: None,
                mix_max: None,
                radiance_max: Some(radiance_max),
                amplitude: None,
            } => Ok(Self::Baseline { radiance_max }),
            AnyConstants {
                surface_max: None,
                subsurface_max: None,
                mix_max: None,
                radiance_max: None,
                amplitude: Some(amplitude),
            } => Ok(Self::Amplitude { amplitude }),
            _ => {
                let given: Vec<&str> = [
                    ("surface_max", c.surface_max),
                    ("subsurface_max", c.subsurface_max),
                    ("mix_max", c.mix_max),
                    ("radiance_max", c.radiance_max),
                    ("amplitude", c.amplitude),
                ]
                .into_iter()
                .filter_map(|(name, v)| v.map(|_| name))
                .collect();
                Err(serde::de::Error::custom(format!(
                    "normalisation holds {}: give one normalisation's constants, \
                     surface_max, subsurface_max and mix_max (a layered model, paper objective), \
                     radiance_max (a baseline, paper objective) or amplitude (free objective)",
                    if given.is_empty() {
                        "no constant".to_string()
                    } else {
                        given.join(", ")
                    }
                )))
            }
        }
    }
}

/// A fitted model: what is needed to predict anywhere.
///
/// ```
/// use laminar_brdf_core::Angles;
/// use laminar_brdf_fit::{FittedModel, Model, ModelParams};
/// let fitted_on: Vec<Angles> = (0..10)
///     .map(|i| Angles::new(0.1 * i as f64, 0.3, 1.0).unwrap())
///     .collect();
/// let params = ModelParams::Layered { slope: 0.6, beta: 0.4, n: 1.4, a: 0.2, sub_slope: None };
/// let m = FittedModel::normalised_on(Model::Exp, params, &fitted_on, 1.0)?;
/// // On its own geometries the prediction peaks at exactly 1.
/// let p = m.predict(&fitted_on)?;
/// assert_eq!(p.iter().cloned().fold(0.0, f64::max), 1.0);
/// // Anywhere else it predicts on the same scale.
/// let elsewhere = m.predict(&[Angles::new(1.2, 0.2, -2.0).unwrap()])?;
/// assert!(elsewhere[0] > 0.0);
/// # Ok::<(), laminar_brdf_fit::ModelError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[cfg_attr(feature = "typescript", derive(ts_rs::TS))]
pub struct FittedModel {
    /// The model.
    pub model: Model,
    /// Its parameters (full precision).
    pub params: ModelParams,
    /// The normalisation constants.
    pub normalisation: NormalisationConstants,
    /// Layered models: the balance β′ for which the raw eq. 8 mix
    /// `β′ L^sb + (1 − β′) L^sf` has the fitted lobe's shape
    /// (`None` for baselines, or when both terms are all zeros).
    pub beta_eq8: Option<f64>,
    /// Layered models: prediction = `eq8_scale · (β′ L^sb + (1 − β′) L^sf)`.
    pub eq8_scale: Option<f64>,
    /// The max of the measured radiance that the fit's data were divided by:
    /// a prediction times `data_scale` is radiance in the input's units.
    pub data_scale: f64,
}

impl<'de> Deserialize<'de> for FittedModel {
    /// Its `params` read as its `model`'s: each of
    /// the model's parameters once, none of another model's.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        struct Written {
            model: Model,
            params: WrittenParams,
            normalisation: NormalisationConstants,
            beta_eq8: Option<f64>,
            eq8_scale: Option<f64>,
            data_scale: f64,
        }
        let w = Written::deserialize(d)?;
        Ok(Self {
            model: w.model,
            params: w.params.of(w.model).map_err(serde::de::Error::custom)?,
            normalisation: w.normalisation,
            beta_eq8: w.beta_eq8,
            eq8_scale: w.eq8_scale,
            data_scale: w.data_scale,
        })
    }
}

/// The measurements' geometry in the form a model evaluates it, built once
/// (sines and cosines) and evaluated at any parameters.
#[derive(Debug, Clone)]
pub(crate) enum Geometries {
    /// The layered models' geometry.
    Layered(Vec<Geometry<f64>>),
    /// A baseline's.
    Baseline(BaselineGeometry),
}

impl Geometries {
    /// The geometry `model` needs at `angles`.
    pub(crate) fn new(model: Model, angles: &[Angles]) -> Self {
        match model.family() {
            Family::Baseline(b) => Self::Baseline(BaselineGeometry::new(b, angles)),
            Family::Layered { .. } => {
                Self::Layered(angles.iter().map(Geometry::<f64>::splat).collect())
            }
        }
    }

    /// Raw model radiance at each geometry: (surface, subsurface) for the
    /// layered models, (radiance, unused) for the baselines.
    pub(crate) fn raw(
        &self,
        model: Model,
        params: &ModelParams,
    ) -> Result<Vec<[f64; 2]>, ModelError> {
        let wrong = || ModelError::WrongParameters {
            model: model.name().into(),
            expected: param_names(model.params()),
        };
        match (self, model.family()) {
            (Self::Layered(geometry), Family::Layered { correlation, .. }) => {
                let ModelParams::Layered { a, .. } = *params else {
                    return Err(wrong());
                };
                if model.is_ragheb_hancock() && a != 0.0 {
                    return Err(ModelError::WrongParameters {
                        model: model.name().into(),
                        expected: format!("{} and a = 0", param_names(model.free_params())),
                    });
                }
                let p = params.layered()?;
                Ok(geometry
                    .iter()
                    .map(|g| {
                        let c = components(g, correlation, &p);
                        [c.surface, c.subsurface]
                    })
                    .collect())
            }
            (Self::Baseline(geometry), Family::Baseline(b)) => match params.baseline_values() {
                Some((of, values)) if of == b && geometry.baseline() == b => Ok(geometry
                    .radiance(values)
                    .map_err(ModelError::OutOfDomain)?
                    .into_iter()
                    .map(|l| [l, 0.0])
                    .collect()),
                _ => Err(wrong()),
            },
            (Self::Layered(_), Family::Baseline(_))
            | (Self::Baseline(_), Family::Layered { .. }) => Err(wrong()),
        }
    }
}

/// Raw model radiance at each geometry ([`Geometries::raw`]).
fn raw(model: Model, params: &ModelParams, angles: &[Angles]) -> Result<Vec<[f64; 2]>, ModelError> {
    Geometries::new(model, angles).raw(model, params)
}

/// `values`, or the first that is not a finite number as an error.
fn finite(values: Vec<f64>) -> Result<Vec<f64>, ModelError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(ModelError::NonFinitePrediction {
            index,
            value: values[index],
        }),
        None => Ok(values),
    }
}

/// A max as the normalisation stores it: the max if positive, else 0.
fn positive_max(values: impl Iterator<Item = f64>) -> f64 {
    let m = max_of(&values.collect::<Vec<_>>());
    if m > 0.0 {
        m
    } else {
        0.0
    }
}

impl FittedModel {
    /// The model `model` at `params`, normalised on the geometries `angles`
    /// (the fit's kept measurements) as the paper normalisation does;
    /// `data_scale` is the max the data were divided by.
    ///
    /// # Errors
    /// [`ModelError`] when the parameters are outside their domain or not the model's.
    pub fn normalised_on(
        model: Model,
        params: ModelParams,
        angles: &[Angles],
        data_scale: f64,
    ) -> Result<Self, ModelError> {
        Ok(Self::from_raw(
            model,
            params,
            &raw(model, &params, angles)?,
            data_scale,
        ))
    }

    /// The model `model` at `params` with the free amplitude `amplitude`
    /// (docs/conventions.md §4b): β is eq. 8's, so `beta_eq8 = β` and
    /// `eq8_scale = amplitude`.
    pub fn with_amplitude(
        model: Model,
        params: ModelParams,
        amplitude: f64,
        data_scale: f64,
    ) -> Self {
        let (beta_eq8, eq8_scale) = match params {
            ModelParams::Layered { beta, .. } => (Some(beta), Some(amplitude)),
            ModelParams::Baseline { .. } => (None, None),
        };
        Self {
            model,
            params,
            normalisation: NormalisationConstants::Amplitude { amplitude },
            beta_eq8,
            eq8_scale,
            data_scale,
        }
    }

    /// [`FittedModel::normalised_on`] from the raw terms at the geometries
    /// ([`Geometries::raw`]), with parameters already checked.
    pub(crate) fn from_raw(
        model: Model,
        params: ModelParams,
        raw: &[[f64; 2]],
        data_scale: f64,
    ) -> Self {
        let (normalisation, beta_eq8, eq8_scale) = match params {
            ModelParams::Layered { beta, .. } => {
                let surface_max = positive_max(raw.iter().map(|r| r[0]));
                let subsurface_max = positive_max(raw.iter().map(|r| r[1]));
                let mix_max = positive_max(raw.iter().map(|r| {
                    mix(
                        beta,
                        scaled(r[1], subsurface_max),
                        scaled(r[0], surface_max),
                    )
                }));
                let w_sb = scaled(beta, subsurface_max);
                let w_sf = scaled(1.0 - beta, surface_max);
                let sum = w_sb + w_sf;
                let (beq, scale) = if sum > 0.0 && mix_max > 0.0 {
                    (Some(w_sb / sum), Some(sum / mix_max))
                } else {
                    (None, None)
                };
                (
                    NormalisationConstants::Layered {
                        surface_max,
                        subsurface_max,
                        mix_max,
                    },
                    beq,
                    scale,
                )
            }
            ModelParams::Baseline { .. } => (
                NormalisationConstants::Baseline {
                    radiance_max: positive_max(raw.iter().map(|r| r[0])),
                },
                None,
                None,
            ),
        };
        Self {
            model,
            params,
            normalisation,
            beta_eq8,
            eq8_scale,
            data_scale,
        }
    }

    /// The normalised prediction `P` at each geometry (the quantity the fit
    /// compared with its normalised data). On the fit's own geometries it is
    /// bit for bit the prediction the fit's Δ_RMS was computed from.
    ///
    /// # Errors
    /// [`ModelError`] for parameters outside their domain or not the model's,
    /// [`ModelError::BadConstant`] for a negative or non-finite constant, and
    /// [`ModelError::NonFinitePrediction`] where the constants overflow the
    /// prediction (no NaN or infinity is ever returned).
    ///
    /// ```
    /// use laminar_brdf_fit::{FittedModel, Model, ModelParams};
    /// let params = ModelParams::Layered { slope: 1.2, beta: 0.4, n: 1.4, a: 0.2, sub_slope: None };
    /// let angles = [laminar_brdf_core::Angles::new(0.3, 0.4, 0.5).unwrap()];
    /// let fine = FittedModel::with_amplitude(Model::Exp, params, 1.0, 1.0);
    /// assert!(fine.predict(&angles).unwrap()[0].is_finite());
    /// let huge = FittedModel::with_amplitude(Model::Exp, params, 1e308, 1e10);
    /// assert!(huge.predict_radiance(&angles).unwrap_err().to_string().contains("not a finite number"));
    /// ```
    pub fn predict(&self, angles: &[Angles]) -> Result<Vec<f64>, ModelError> {
        self.check_constants()?;
        self.predict_raw(&raw(self.model, &self.params, angles)?)
    }

    /// [`FittedModel::predict`] from the raw terms ([`Geometries::raw`]).
    pub(crate) fn predict_raw(&self, raw: &[[f64; 2]]) -> Result<Vec<f64>, ModelError> {
        finite(self.predict_unchecked(raw)?)
    }

    fn predict_unchecked(&self, raw: &[[f64; 2]]) -> Result<Vec<f64>, ModelError> {
        // β of a layered model's parameters; `None` for a baseline's.
        let beta = match self.params {
            ModelParams::Layered { beta, .. } => Some(beta),
            ModelParams::Baseline { .. } => None,
        };
        Ok(match (self.normalisation, beta) {
            (
                NormalisationConstants::Layered {
                    surface_max,
                    subsurface_max,
                    mix_max,
                },
                Some(beta),
            ) => {
                let scaling = Scaling::Maxima {
                    surface: surface_max,
                    subsurface: subsurface_max,
                    mix: mix_max,
                };
                raw.iter()
                    .map(|r| scaling.predict(beta, r[0], r[1]))
                    .collect()
            }
            (NormalisationConstants::Baseline { radiance_max }, None) => {
                raw.iter().map(|r| scaled(r[0], radiance_max)).collect()
            }
            (NormalisationConstants::Amplitude { amplitude }, Some(beta)) => raw
                .iter()
                .map(|r| Scaling::Amplitude(amplitude).predict(beta, r[0], r[1]))
                .collect(),
            (NormalisationConstants::Amplitude { amplitude }, None) => {
                raw.iter().map(|r| amplitude * r[0]).collect()
            }
            (NormalisationConstants::Layered { .. }, None)
            | (NormalisationConstants::Baseline { .. }, Some(_)) => {
                return Err(ModelError::WrongParameters {
                    model: self.model.name().into(),
                    expected: "normalisation constants of its own kind".into(),
                })
            }
        })
    }

    /// The prediction in the input's radiance units (`P · data_scale`).
    ///
    /// # Errors
    /// As [`FittedModel::predict`].
    pub fn predict_radiance(&self, angles: &[Angles]) -> Result<Vec<f64>, ModelError> {
        finite(
            self.predict(angles)?
                .into_iter()
                .map(|p| p * self.data_scale)
                .collect(),
        )
    }

    fn check_constants(&self) -> Result<(), ModelError> {
        let constants: Vec<(&'static str, f64)> = match self.normalisation {
            NormalisationConstants::Layered {
                surface_max,
                subsurface_max,
                mix_max,
            } => vec![
                ("surface_max", surface_max),
                ("subsurface_max", subsurface_max),
                ("mix_max", mix_max),
            ],
            NormalisationConstants::Baseline { radiance_max } => {
                vec![("radiance_max", radiance_max)]
            }
            NormalisationConstants::Amplitude { amplitude } => vec![("amplitude", amplitude)],
        };
        for (name, value) in constants
            .into_iter()
            .chain(std::iter::once(("data_scale", self.data_scale)))
        {
            if !(value >= 0.0 && value.is_finite()) {
                return Err(ModelError::BadConstant { name, value });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every model's parameters are written by name and read back as
    /// themselves, whichever family; a set no model has is refused with the
    /// sets that would do.
    #[test]
    fn every_models_parameters_round_trip_by_name() {
        for model in Model::ALL {
            let params = ModelParams::from_values(model, |p| 0.25 + p as usize as f64);
            let json = serde_json::to_string(&params).unwrap();
            for p in model.params() {
                assert!(json.contains(&format!("\"{}\":", p.name())), "{json}");
            }
            let back: ModelParams = serde_json::from_str(&json).unwrap();
            assert_eq!(back, params, "{model}");
        }
        // Names no model has are ignored, as before; a non-number is not a value.
        let extra: ModelParams =
            serde_json::from_str(r#"{"sigma": 0.3, "rho": 0.6, "note": "x"}"#).unwrap();
        assert_eq!(
            extra,
            ModelParams::baseline(Baseline::OrenNayar, [0.3, 0.6])
        );
        let integers: ModelParams = serde_json::from_str(r#"{"sigma": 0, "rho": 1}"#).unwrap();
        assert_eq!(
            integers,
            ModelParams::baseline(Baseline::OrenNayar, [0.0, 1.0])
        );
        let err = serde_json::from_str::<ModelParams>(r#"{"sigma": 0.3, "rho": "0.6"}"#)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("{sigma, rho}") && err.contains("{slope, beta, n, a}"),
            "{err}"
        );
    }

    /// A fitted model's `params` are read as its model's: a parameter
    /// written twice is refused (as every other field written twice is),
    /// and so are another model's parameters, named, whatever the models'
    /// order (issue 55, items 4 and 5).
    #[test]
    fn a_fitted_models_params_are_its_models_once_each() {
        let fitted = FittedModel::with_amplitude(
            Model::Exp,
            ModelParams::Layered {
                slope: 0.4,
                beta: 0.3,
                n: 1.5,
                a: 0.2,
                sub_slope: None,
            },
            2.0,
            1.0,
        );
        let json = serde_json::to_string(&fitted).unwrap();
        let back: FittedModel = serde_json::from_str(&json).unwrap();
        assert_eq!(back, fitted);
        let with = |params: &str| {
            let text = json.replace(
                r#""params":{"slope":0.4,"beta":0.3,"n":1.5,"a":0.2}"#,
                params,
            );
            assert_ne!(text, json, "the fixture's params: {json}");
            serde_json::from_str::<FittedModel>(&text)
                .unwrap_err()
                .to_string()
        };
        let twice = with(r#""params":{"slope":0.4,"beta":0.3,"n":1.5,"n":1.7,"a":0.2}"#);
        assert!(twice.contains("`n` is written twice"), "{twice}");
        let foreign =
            with(r#""params":{"slope":0.4,"beta":0.3,"n":1.5,"a":0.2,"sigma":0.1,"rho":0.5}"#);
        assert!(
            foreign.contains("params of exp: sigma, rho not exp's (its parameters: slope,"),
            "{foreign}"
        );
        let missing = with(r#""params":{"slope":0.4,"beta":0.3,"n":1.5}"#);
        assert!(
            missing.contains("params of exp: a without a number"),
            "{missing}"
        );
        // An Oren–Nayar entry holding the layered parameters too: refused by
        // its own model, naming the layered ones.
        let on = FittedModel::with_amplitude(
            Model::OrenNayar,
            ModelParams::baseline(Baseline::OrenNayar, [0.3, 0.6]),
            1.0,
            1.0,
        );
        let text = serde_json::to_string(&on).unwrap().replace(
            r#""params":{"sigma":0.3,"rho":0.6}"#,
            r#""params":{"sigma":0.3,"rho":0.6,"slope":0.4,"beta":0.3,"n":1.5,"a":0.2}"#,
        );
        let err = serde_json::from_str::<FittedModel>(&text)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("params of oren-nayar: slope, beta, n, a not"),
            "{err}"
        );
    }
}
