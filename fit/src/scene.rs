//! A scene: one channel of a measurement set, ready to fit (kept geometries
//! in the paper frame and normalised measured radiance; docs/conventions.md §1, §4, §8).

use laminar_core::{normalise_by_max, Angles};

/// Kept measurements of one channel with their normalised measured radiance.
/// Built by [`crate::MeasurementSet::scene`] (or [`Scene::from_radiance`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Label of the measurement set (the `sample` column of every output).
    pub sample: String,
    /// The channel's name (the `channel` column).
    pub channel: String,
    /// Geometry of each kept measurement, in the paper's Beckmann frame.
    pub angles: Vec<Angles>,
    /// Normalised measured radiance `D_k` (max 1).
    pub data: Vec<f64>,
    /// Standard uncertainty of each `D_k`, on the same scale, when the input gave them.
    pub sigma: Option<Vec<f64>>,
    /// Source row (1-based) of each kept measurement.
    pub rows: Vec<usize>,
    /// Kept measurements whose value is zero or negative (docs/conventions.md §8).
    pub nonpositive: usize,
    /// The max of the un-normalised radiance that `data` was divided by
    /// (multiply a normalised prediction by it to get the input's units).
    pub data_scale: f64,
}

impl Scene {
    /// A scene from paper-frame angles and un-normalised radiance, divided by
    /// its max (a max ≤ 0 leaves all zeros and `data_scale` 0). Labelled
    /// `synthetic`/`value` until [`Scene::labelled`].
    pub fn from_radiance(
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

    /// True when no measurement is kept.
    pub fn is_empty(&self) -> bool {
        self.angles.is_empty()
    }
}
