//! Measurement sets: any source's measurements in one type, and the one place
//! where they become something to fit (docs/conventions.md §1, §4, §8).
//!
//! A [`MeasurementSet`] holds, per measurement, the illumination and view
//! angles ([`MeasurementAngles`]: the lab frame with outward azimuths, as
//! CUReT and MERL give them, or the paper's frame directly), one value per
//! channel (1 to N named channels), optionally a standard uncertainty per
//! value, and what the values are ([`Quantity`]). [`MeasurementSet::scene`]
//! then, for one channel, drops the specular measurements (detected from the
//! angles), maps the angles to the paper frame, converts BRDF to radiance and
//! normalises by the maximum: the [`Scene`] that every search path fits.

use crate::error::{find_named, MeasurementError, UnknownName};
use crate::scene::Scene;
use laminar_brdf_core::measures::{check_data, DataFault};
use laminar_brdf_core::{wrap_pi, Angle, Angles, Input, InputError};
use std::f64::consts::PI;
use std::fmt;
use std::str::FromStr;

/// Default tolerance of the specular test, radians (docs/conventions.md §1).
pub const SPECULAR_TOLERANCE: f64 = 1e-4;

pub use laminar_brdf_core::measures::MIN_RELATIVE_VALUE;

/// What a measured value is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Quantity {
    /// Bidirectional reflectance distribution function (sr⁻¹): the radiance
    /// fitted is `value · cos θi` (docs/conventions.md §4).
    #[default]
    Brdf,
    /// Reflected radiance for unit incident radiance: fitted as given.
    Radiance,
}

impl Quantity {
    /// The command-line name (`brdf`, `radiance`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Brdf => "brdf",
            Self::Radiance => "radiance",
        }
    }
}

impl fmt::Display for Quantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Quantity {
    type Err = UnknownName;
    fn from_str(s: &str) -> Result<Self, UnknownName> {
        find_named("quantity", &[Self::Brdf, Self::Radiance], Self::name, s)
    }
}

/// The angles of one measurement, radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MeasurementAngles {
    /// Lab frame: polar angles from the surface normal and azimuths of the
    /// directions *towards* the light and the viewer (outward), as CUReT and
    /// MERL give them.
    Lab {
        /// Illumination polar angle θi.
        theta_i: f64,
        /// Illumination azimuth φi.
        phi_i: f64,
        /// View polar angle θv.
        theta_v: f64,
        /// View azimuth φv.
        phi_v: f64,
    },
    /// The paper's Beckmann frame: incident azimuth π, forward specular at φs = 0.
    Paper {
        /// Incident polar angle θi.
        theta_i: f64,
        /// Scattering polar angle θs.
        theta_s: f64,
        /// Scattering azimuth φs.
        phi_s: f64,
    },
}

impl MeasurementAngles {
    /// The paper-frame angles: `θs = θv`, `φs = φv − φi − π` wrapped to
    /// `(−π, π]` (docs/conventions.md §1). Errors name the angle out of its domain.
    ///
    /// # Errors
    /// [`InputError::OutOfRange`] naming the polar angle outside `[0, π/2]` or
    /// the azimuth that is not finite.
    pub fn paper(&self) -> Result<Angles, InputError> {
        match self.written() {
            Ok([theta_i, phi_i, theta_v, phi_v]) => {
                for (angle, v) in [(Angle::PhiI, phi_i), (Angle::PhiV, phi_v)] {
                    if !v.is_finite() {
                        return Err(InputError::OutOfRange {
                            input: Input::Angle(angle),
                            value: v,
                            allowed: "a finite angle",
                        });
                    }
                }
                Angles::new(theta_i, theta_v, wrap_pi(phi_v - phi_i - PI)).map_err(|e| match e {
                    InputError::OutOfRange {
                        input: Input::Angle(Angle::ThetaS),
                        value,
                        allowed,
                    } => InputError::OutOfRange {
                        input: Input::Angle(Angle::ThetaV),
                        value,
                        allowed,
                    },
                    other => other,
                })
            }
            Err([theta_i, theta_s, phi_s]) => Angles::new(theta_i, theta_s, phi_s),
        }
    }

    /// The angles as written: `Ok([θi, φi, θv, φv])` in the lab frame,
    /// `Err([θi, θs, φs])` in the paper frame.
    fn written(&self) -> Result<[f64; 4], [f64; 3]> {
        match *self {
            Self::Lab {
                theta_i,
                phi_i,
                theta_v,
                phi_v,
            } => Ok([theta_i, phi_i, theta_v, phi_v]),
            Self::Paper {
                theta_i,
                theta_s,
                phi_s,
            } => Err([theta_i, theta_s, phi_s]),
        }
    }

    /// The lab frame's `[θi, φi, θv, φv]` (`None` for a paper-frame
    /// measurement).
    pub fn lab(&self) -> Option<[f64; 4]> {
        self.written().ok()
    }

    /// The incident polar angle θi.
    pub fn theta_i(&self) -> f64 {
        match *self {
            Self::Lab { theta_i, .. } | Self::Paper { theta_i, .. } => theta_i,
        }
    }

    /// True for a mirror configuration, within `tolerance` radians on each
    /// angle: `θv = θi` and `|φv − φi| = π` in the lab frame, `θs = θi` and
    /// `φs = 0` in the paper frame (docs/conventions.md §1).
    pub fn is_specular(&self, tolerance: f64) -> bool {
        match self.written() {
            Ok([theta_i, phi_i, theta_v, phi_v]) => {
                (theta_v - theta_i).abs() <= tolerance
                    && (wrap_pi(phi_v - phi_i).abs() - PI).abs() <= tolerance
            }
            Err([theta_i, theta_s, phi_s]) => {
                (theta_s - theta_i).abs() <= tolerance && wrap_pi(phi_s).abs() <= tolerance
            }
        }
    }
}

/// One channel: a value per measurement and, optionally, its standard uncertainty.
#[derive(Debug, Clone, PartialEq)]
pub struct Channel {
    /// The channel's name (e.g. `avg`, `r`, `value`).
    pub name: String,
    /// One value per measurement, in the set's order.
    pub values: Vec<f64>,
    /// One standard uncertainty per value, in the values' unit.
    pub sigma: Option<Vec<f64>>,
}

/// Measurements from any source: angles, named channels, what the values are.
///
/// ```
/// use laminar_brdf_fit::{MeasurementAngles, MeasurementSet, Quantity};
/// let angles = vec![
///     MeasurementAngles::Paper { theta_i: 0.2, theta_s: 0.4, phi_s: 0.1 },
///     MeasurementAngles::Paper { theta_i: 0.5, theta_s: 0.5, phi_s: 0.0 }, // specular
///     MeasurementAngles::Paper { theta_i: 0.6, theta_s: 0.1, phi_s: 2.0 },
/// ];
/// let set = MeasurementSet::new("example", angles, Quantity::Radiance)?
///     .with_channel("value", vec![0.5, 9.0, 0.25], None)?;
/// let scene = set.scene("value")?;
/// assert_eq!(scene.len(), 2); // the specular measurement is dropped
/// assert_eq!(scene.data(), [1.0, 0.5]); // normalised by the max
/// assert_eq!(scene.rows(), [1, 3]);
/// # Ok::<(), laminar_brdf_fit::MeasurementError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct MeasurementSet {
    name: String,
    angles: Vec<MeasurementAngles>,
    rows: Vec<usize>,
    channels: Vec<Channel>,
    quantity: Quantity,
    specular_tolerance: f64,
}

impl MeasurementSet {
    /// A set named `name` (the sample label in every output) of measurements
    /// at `angles`, without channels yet. Rows are numbered 1, 2, … unless
    /// [`MeasurementSet::with_rows`] says otherwise. Every angle is checked:
    /// polar angles in `[0, π/2]`, azimuths finite.
    ///
    /// # Errors
    /// [`MeasurementError::Angle`] naming the row and the angle.
    pub fn new(
        name: impl Into<String>,
        angles: Vec<MeasurementAngles>,
        quantity: Quantity,
    ) -> Result<Self, MeasurementError> {
        let name = name.into();
        for (i, a) in angles.iter().enumerate() {
            a.paper().map_err(|error| MeasurementError::Angle {
                set: name.clone(),
                row: i + 1,
                error,
            })?;
        }
        let rows = (1..=angles.len()).collect();
        Ok(Self {
            name,
            angles,
            rows,
            channels: Vec::new(),
            quantity,
            specular_tolerance: SPECULAR_TOLERANCE,
        })
    }

    /// Numbers the measurements by their rows in the source (used in errors
    /// and in [`Scene::rows`]).
    ///
    /// # Errors
    /// [`MeasurementError::Length`] when there is not one row per measurement.
    pub fn with_rows(mut self, rows: Vec<usize>) -> Result<Self, MeasurementError> {
        self.check_len("the row list", rows.len())?;
        self.rows = rows;
        Ok(self)
    }

    /// Sets the specular test's tolerance (radians; default [`SPECULAR_TOLERANCE`]).
    ///
    /// # Errors
    /// [`MeasurementError::BadTolerance`] for a negative or non-finite tolerance.
    pub fn with_specular_tolerance(mut self, tolerance: f64) -> Result<Self, MeasurementError> {
        if !(tolerance >= 0.0 && tolerance.is_finite()) {
            return Err(MeasurementError::BadTolerance(tolerance));
        }
        self.specular_tolerance = tolerance;
        Ok(self)
    }

    /// Adds a channel: one finite value per measurement and optionally one
    /// positive finite uncertainty per value.
    ///
    /// # Errors
    /// [`MeasurementError::DuplicateChannel`], [`MeasurementError::Length`],
    /// [`MeasurementError::NotFinite`] or [`MeasurementError::BadSigma`], naming the row.
    pub fn with_channel(
        mut self,
        name: impl Into<String>,
        values: Vec<f64>,
        sigma: Option<Vec<f64>>,
    ) -> Result<Self, MeasurementError> {
        let name = name.into();
        if self.channels.iter().any(|c| c.name == name) {
            return Err(MeasurementError::DuplicateChannel {
                set: self.name.clone(),
                channel: name,
            });
        }
        self.check_len(&format!("channel `{name}`"), values.len())?;
        let not_finite = |what, row, value| MeasurementError::NotFinite {
            set: self.name.clone(),
            row,
            channel: name.clone(),
            what,
            value,
        };
        for (&v, &row) in values.iter().zip(&self.rows) {
            if !v.is_finite() {
                return Err(not_finite("value", row, v));
            }
        }
        if let Some(sigma) = &sigma {
            self.check_len(&format!("the uncertainties of `{name}`"), sigma.len())?;
            for (&s, &row) in sigma.iter().zip(&self.rows) {
                if !s.is_finite() {
                    return Err(not_finite("sigma", row, s));
                }
                if s <= 0.0 {
                    return Err(MeasurementError::BadSigma {
                        set: self.name.clone(),
                        row,
                        channel: name.clone(),
                        value: s,
                    });
                }
            }
        }
        self.channels.push(Channel {
            name,
            values,
            sigma,
        });
        Ok(self)
    }

    fn check_len(&self, what: &str, found: usize) -> Result<(), MeasurementError> {
        if found != self.angles.len() {
            return Err(MeasurementError::Length {
                set: self.name.clone(),
                what: what.to_string(),
                found,
                expected: self.angles.len(),
            });
        }
        Ok(())
    }

    /// The set's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// What the values are.
    pub fn quantity(&self) -> Quantity {
        self.quantity
    }

    /// Number of measurements (specular ones included).
    pub fn len(&self) -> usize {
        self.angles.len()
    }

    /// True when the set has no measurement.
    pub fn is_empty(&self) -> bool {
        self.angles.is_empty()
    }

    /// The measurements' angles, in order.
    pub fn angles(&self) -> &[MeasurementAngles] {
        &self.angles
    }

    /// The channels, in the order they were added.
    pub fn channels(&self) -> &[Channel] {
        &self.channels
    }

    /// The channel names, in order.
    pub fn channel_names(&self) -> Vec<&str> {
        self.channels.iter().map(|c| c.name.as_str()).collect()
    }

    /// Indices of the measurements kept for fitting (the non-specular ones).
    pub fn kept(&self) -> Vec<usize> {
        (0..self.len())
            .filter(|&k| !self.angles[k].is_specular(self.specular_tolerance))
            .collect()
    }

    /// The scene of channel `channel`: specular measurements dropped, angles
    /// in the paper frame, radiance `D = v cos θi` for BRDF values (`D = v`
    /// for radiance), divided by its max over the kept measurements
    /// (docs/conventions.md §1, §4). Uncertainties are scaled alike.
    ///
    /// # Errors
    /// [`MeasurementError::NoChannel`], [`MeasurementError::NothingToFit`] (every
    /// measurement specular), [`MeasurementError::NoPositiveValue`] or
    /// [`MeasurementError::OutOfScale`] (a value that would overflow an error measure).
    pub fn scene(&self, channel: &str) -> Result<Scene, MeasurementError> {
        let c = self
            .channels
            .iter()
            .find(|c| c.name == channel)
            .ok_or_else(|| MeasurementError::NoChannel {
                set: self.name.clone(),
                channel: channel.to_string(),
                available: self.channel_names().join(", "),
            })?;
        let kept = self.kept();
        if kept.is_empty() {
            return Err(MeasurementError::NothingToFit {
                set: self.name.clone(),
                measurements: self.len(),
                specular: self.len(),
            });
        }
        let factor = |k: usize| match self.quantity {
            Quantity::Brdf => self.angles[k].theta_i().cos(),
            Quantity::Radiance => 1.0,
        };
        let angles = kept
            .iter()
            .map(|&k| {
                self.angles[k]
                    .paper()
                    .expect("validated by MeasurementSet::new")
            })
            .collect();
        let radiance: Vec<f64> = kept.iter().map(|&k| c.values[k] * factor(k)).collect();
        let sigma = c
            .sigma
            .as_ref()
            .map(|s| kept.iter().map(|&k| s[k] * factor(k)).collect());
        let nonpositive = kept.iter().filter(|&&k| c.values[k] <= 0.0).count();
        // The data rule every front end shares (the C ABI's small fit too).
        match check_data(&radiance) {
            Ok(()) => {}
            Err((_, DataFault::NoPositiveValue)) => {
                return Err(MeasurementError::NoPositiveValue {
                    set: self.name.clone(),
                    channel: c.name.clone(),
                    kept: kept.len(),
                })
            }
            Err((i, fault)) => {
                return Err(MeasurementError::OutOfScale {
                    set: self.name.clone(),
                    row: self.rows[kept[i]],
                    channel: c.name.clone(),
                    value: c.values[kept[i]],
                    why: fault.why(),
                })
            }
        }
        let max = radiance.iter().copied().fold(0.0, f64::max);
        // The free objective weighs by 1/σ²: an uncertainty below 1e-100 of
        // the max would make a weight overflow.
        if let (Some(sigma), Some(given)) = (&sigma, &c.sigma) {
            let sigma: &Vec<f64> = sigma;
            for (&s, &k) in sigma.iter().zip(&kept) {
                if s < max * MIN_RELATIVE_VALUE {
                    return Err(MeasurementError::OutOfScale {
                        set: self.name.clone(),
                        row: self.rows[k],
                        channel: format!("sigma of {}", c.name),
                        value: given[k],
                        why: "an uncertainty below 1e-100 of the max radiance (its weight 1/σ² would overflow)",
                    });
                }
            }
        }
        let rows = kept.iter().map(|&k| self.rows[k]).collect();
        Ok(
            Scene::from_radiance(angles, radiance, rows, nonpositive, sigma)
                .labelled(&self.name, &c.name),
        )
    }

    /// The scene of every channel, in order.
    ///
    /// # Errors
    /// As [`MeasurementSet::scene`].
    pub fn scenes(&self) -> Result<Vec<Scene>, MeasurementError> {
        self.channels.iter().map(|c| self.scene(&c.name)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lab(theta_i: f64, phi_i: f64, theta_v: f64, phi_v: f64) -> MeasurementAngles {
        MeasurementAngles::Lab {
            theta_i,
            phi_i,
            theta_v,
            phi_v,
        }
    }

    #[test]
    fn lab_and_paper_frames_agree() {
        let l = lab(0.3, 0.2, 0.5, 0.2 + PI + 0.7);
        let p = l.paper().unwrap();
        assert_eq!((p.theta_i(), p.theta_s()), (0.3, 0.5));
        assert!((p.phi_s() - 0.7).abs() < 1e-12);
        assert!(lab(0.4, 1.0, 0.4, 1.0 - PI).is_specular(1e-4));
        assert!(!lab(0.4, 1.0, 0.4, 1.0 - PI + 2e-4).is_specular(1e-4));
        assert!(lab(0.4, 1.0, 0.4, 1.0 - PI + 2e-4).is_specular(3e-4));
        let paper = MeasurementAngles::Paper {
            theta_i: 0.4,
            theta_s: 0.4,
            phi_s: 2.0 * PI,
        };
        assert!(paper.is_specular(1e-4));
    }

    #[test]
    fn brdf_is_converted_to_radiance_and_radiance_is_not() {
        let angles = vec![lab(0.0, 0.0, 0.3, 1.0), lab(1.0, 0.0, 0.3, 1.0)];
        for (q, second) in [(Quantity::Brdf, 1.0f64.cos()), (Quantity::Radiance, 1.0)] {
            let s = MeasurementSet::new("s", angles.clone(), q)
                .unwrap()
                .with_channel("v", vec![1.0, 1.0], Some(vec![0.1, 0.1]))
                .unwrap()
                .scene("v")
                .unwrap();
            assert_eq!(s.data, vec![1.0, second]);
            assert_eq!(s.sigma.unwrap(), vec![0.1, 0.1 * second]);
        }
    }

    #[test]
    fn an_uncertainty_whose_weight_would_overflow_is_refused() {
        // σ = 1e-200 of the max: its weight 1/σ² would be infinite.
        let angles = vec![lab(0.2, 0.0, 0.3, 1.0), lab(0.4, 0.0, 0.3, 1.0)];
        let e = MeasurementSet::new("s", angles, Quantity::Radiance)
            .unwrap()
            .with_channel("v", vec![1.0, 1.0], Some(vec![0.1, 1e-200]))
            .unwrap()
            .scene("v")
            .unwrap_err();
        assert!(
            e.to_string().contains("row 2: channel `sigma of v`")
                && e.to_string().contains("below 1e-100 of the max radiance"),
            "{e}"
        );
    }

    #[test]
    fn bad_input_is_named() {
        let e =
            MeasurementSet::new("s", vec![lab(2.0, 0.0, 0.3, 0.0)], Quantity::Brdf).unwrap_err();
        assert_eq!(e.to_string(), "s: row 1: theta_i = 2 is outside [0, π/2]");
        let set = MeasurementSet::new("s", vec![lab(0.2, 0.0, 0.3, 0.0)], Quantity::Brdf)
            .unwrap()
            .with_rows(vec![7])
            .unwrap();
        let e = set
            .clone()
            .with_channel("v", vec![f64::NAN], None)
            .unwrap_err();
        assert_eq!(
            e.to_string(),
            "s: row 7: channel `v`: value NaN is not a finite number"
        );
        let e = set
            .clone()
            .with_channel("v", vec![1.0, 2.0], None)
            .unwrap_err();
        assert!(
            e.to_string().contains("has 2 entries for 1 measurements"),
            "{e}"
        );
        let e = set
            .clone()
            .with_channel("v", vec![-1.0], None)
            .unwrap()
            .scene("v")
            .unwrap_err();
        assert!(matches!(e, MeasurementError::NoPositiveValue { .. }), "{e}");
        // Values that would overflow an error measure are refused, named.
        for (values, needle) in [
            (vec![1e-300, -0.5], "row 2: channel `v`: value -0.5"),
            (vec![1e308, 0.5], "row 2: channel `v`: value 0.5"),
        ] {
            let two = MeasurementSet::new(
                "s",
                vec![lab(0.2, 0.0, 0.3, 0.0), lab(0.3, 0.0, 0.3, 1.0)],
                Quantity::Radiance,
            )
            .unwrap()
            .with_channel("v", values, None)
            .unwrap();
            let e = two.scene("v").unwrap_err().to_string();
            assert!(e.contains(needle), "{e}");
        }
        let e = set
            .with_channel("v", vec![1.0], None)
            .unwrap()
            .scene("w")
            .unwrap_err();
        assert_eq!(e.to_string(), "s: no channel `w` (channels: v)");
    }
}
