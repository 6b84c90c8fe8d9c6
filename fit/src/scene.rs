//! A scene: one channel of a measurement set, ready to fit (kept geometries
//! in the paper frame and normalised measured radiance; docs/conventions.md §1, §4, §8).

use laminar_brdf_core::{normalise_by_max, Angles};

/// Kept measurements of one channel with their normalised measured radiance.
/// Built only by [`crate::MeasurementSet::scene`] and the synthetic scenes,
/// so every scene is valid: at least one measurement, one value per
/// geometry, finite values with a positive maximum.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    pub(crate) sample: String,
    pub(crate) channel: String,
    pub(crate) angles: Vec<Angles>,
    pub(crate) data: Vec<f64>,
    pub(crate) sigma: Option<Vec<f64>>,
    pub(crate) relative_sigma: Option<Vec<f64>>,
    pub(crate) rows: Vec<usize>,
    pub(crate) nonpositive: usize,
    pub(crate) data_scale: f64,
}

impl Scene {
    /// Label of the measurement set (the `sample` column of every output).
    pub fn sample(&self) -> &str {
        &self.sample
    }

    /// The channel's name (the `channel` column).
    pub fn channel(&self) -> &str {
        &self.channel
    }

    /// Geometry of each kept measurement, in the paper's Beckmann frame.
    pub fn angles(&self) -> &[Angles] {
        &self.angles
    }

    /// Normalised measured radiance `D_k` (max 1).
    pub fn data(&self) -> &[f64] {
        &self.data
    }

    /// Standard uncertainty of each `D_k`, on the same scale, when the input gave them.
    pub fn sigma(&self) -> Option<&[f64]> {
        self.sigma.as_deref()
    }

    /// Each `D_k`'s standard deviation up to a common unknown factor, when
    /// a noise model set them ([`crate::Noise::Relative`]).
    pub fn relative_sigma(&self) -> Option<&[f64]> {
        self.relative_sigma.as_deref()
    }

    /// The standard deviations the measurements are weighted by, and
    /// whether their scale is known: the file's ([`Scene::sigma`], known),
    /// else a noise model's ([`Scene::relative_sigma`]); `None` for equal
    /// weights.
    pub fn weights(&self) -> Option<(&[f64], bool)> {
        match (&self.sigma, &self.relative_sigma) {
            (Some(sigma), _) => Some((sigma, true)),
            (None, Some(relative)) => Some((relative, false)),
            (None, None) => None,
        }
    }

    /// Source row (1-based) of each kept measurement.
    pub fn rows(&self) -> &[usize] {
        &self.rows
    }

    /// Kept measurements whose value is zero or negative (docs/conventions.md §8).
    pub fn nonpositive(&self) -> usize {
        self.nonpositive
    }

    /// The max of the un-normalised radiance that the data were divided by
    /// (multiply a normalised prediction by it to get the input's units).
    pub fn data_scale(&self) -> f64 {
        self.data_scale
    }

    /// A scene from paper-frame angles and un-normalised radiance with a
    /// positive max, divided by it. Labelled `synthetic`/`value` until
    /// [`Scene::labelled`].
    pub(crate) fn from_radiance(
        angles: Vec<Angles>,
        mut radiance: Vec<f64>,
        rows: Vec<usize>,
        nonpositive: usize,
        sigma: Option<Vec<f64>>,
    ) -> Self {
        let data_scale = normalise_by_max(&mut radiance);
        let sigma = sigma.map(|s| {
            s.into_iter()
                .map(|x| if data_scale > 0.0 { x / data_scale } else { x })
                .collect()
        });
        Self {
            sample: "synthetic".into(),
            channel: "value".into(),
            angles,
            data: radiance,
            sigma,
            relative_sigma: None,
            rows,
            nonpositive,
            data_scale,
        }
    }

    /// The same scene with the given sample and channel labels.
    pub fn labelled(mut self, sample: &str, channel: &str) -> Self {
        self.sample = sample.to_string();
        self.channel = channel.to_string();
        self
    }

    /// Number of kept measurements K.
    pub fn len(&self) -> usize {
        self.angles.len()
    }

    /// True when no measurement is kept (never, for a scene built by this crate).
    pub fn is_empty(&self) -> bool {
        self.angles.is_empty()
    }
}
