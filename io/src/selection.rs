//! Choosing one fitted model from a fitted-model file by its label
//! `sample/channel/model` (a fit, or one channel of a material): one rule
//! for every front end (the CLI's `--select`, the wasm `predict`, Python's
//! `FittedModel.from_file`); and a material by its label `sample/model`.

use crate::fits::{FitEntry, FitsFile, MaterialEntry};
use laminar_brdf_fit::FittedModel;

/// A fit picked from a fitted-model file.
#[derive(Debug, Clone, PartialEq)]
pub struct Selected {
    /// `sample/channel/model`.
    pub label: String,
    /// The sample.
    pub sample: String,
    /// The channel.
    pub channel: String,
    /// The fitted model.
    pub fitted: FittedModel,
    /// The fitted model's own Δ_RMS (the refined one when refined); none
    /// for a material's channel (the file holds its weighted objective).
    pub rms: Option<f64>,
}

/// Why no fit was picked.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SelectError {
    /// The file holds no fit.
    #[error("holds no fit")]
    Empty,
    /// No material has the label given, or none was given among several.
    #[error("no material `{}`; the file holds {}", select.as_deref().unwrap_or("(none named)"), if labels.is_empty() { "none (write one with `laminar fit-joint --fits`)".to_string() } else { labels.join(", ") })]
    NoMaterial {
        /// The label given.
        select: Option<String>,
        /// Every material's label.
        labels: Vec<String>,
    },
    /// No label was given and the file holds several fits.
    #[error("holds {count} fits; choose one: {}", labels.join(", "))]
    Ambiguous {
        /// Fits in the file.
        count: usize,
        /// Every label that can be selected.
        labels: Vec<String>,
    },
    /// No fit has the label given.
    #[error("no fit `{select}`; the file holds {}", labels.join(", "))]
    NoMatch {
        /// The label given.
        select: String,
        /// Every label that can be selected.
        labels: Vec<String>,
    },
}

/// Every fit of `entries`, and the Ragheb–Hancock best of each exp or
/// gauss fit under its `rh-` label unless the file holds a fit of that
/// label itself (which is then the one selected).
pub fn candidates(entries: &[FitEntry]) -> Vec<Selected> {
    let mut out = Vec::new();
    let own: Vec<String> = entries.iter().map(FitEntry::label).collect();
    for e in entries {
        out.push(Selected {
            label: e.label(),
            sample: e.sample.clone(),
            channel: e.channel.clone(),
            fitted: e.fitted,
            rms: Some(e.rms_refined.unwrap_or(e.rms)),
        });
        if let (Some(rh), Some(rh_model), Some(rms)) =
            (e.rh_fitted, e.model.ragheb_hancock(), e.rh_rms)
        {
            let label = format!("{}/{}/{rh_model}", e.sample, e.channel);
            if own.contains(&label) {
                continue;
            }
            out.push(Selected {
                label,
                sample: e.sample.clone(),
                channel: e.channel.clone(),
                fitted: rh,
                rms: Some(rms),
            });
        }
    }
    out
}

/// Each channel of `materials` under its label `sample/channel/model`,
/// unless a fit of `own` labels has that label.
fn material_channels(materials: &[MaterialEntry], own: &[String]) -> Vec<Selected> {
    let mut out = Vec::new();
    for m in materials {
        for c in &m.channels {
            let label = m.channel_label(c);
            if own.contains(&label) {
                continue;
            }
            out.push(Selected {
                label,
                sample: m.sample.clone(),
                channel: c.channel.clone(),
                fitted: c.fitted,
                rms: None,
            });
        }
    }
    out
}

impl FitsFile {
    /// The fit labelled `select` ([`candidates`], then each material's
    /// channels), or the file's only fit when `select` is `None`.
    ///
    /// # Errors
    /// [`SelectError`]: no fit, several and no label, or no fit of the label.
    pub fn select(&self, select: Option<&str>) -> Result<Selected, SelectError> {
        let own: Vec<String> = self.fits.iter().map(FitEntry::label).collect();
        let mut all = candidates(&self.fits);
        all.extend(material_channels(&self.materials, &own));
        if all.is_empty() {
            return Err(SelectError::Empty);
        }
        let labels = || all.iter().map(|c| c.label.clone()).collect::<Vec<_>>();
        let count = self.fits.len()
            + self
                .materials
                .iter()
                .map(|m| m.channels.len())
                .sum::<usize>();
        let index = match select {
            None if count == 1 => 0,
            None => {
                return Err(SelectError::Ambiguous {
                    count,
                    labels: labels(),
                })
            }
            Some(s) => {
                all.iter()
                    .position(|c| c.label == s)
                    .ok_or_else(|| SelectError::NoMatch {
                        select: s.to_string(),
                        labels: labels(),
                    })?
            }
        };
        Ok(all.swap_remove(index))
    }

    /// The material labelled `select` (`sample/model`), or the file's only
    /// material when `select` is `None`.
    ///
    /// # Errors
    /// [`SelectError::NoMaterial`]: none of that label, or several and no
    /// label.
    pub fn select_material(&self, select: Option<&str>) -> Result<&MaterialEntry, SelectError> {
        let found = match select {
            None if self.materials.len() == 1 => self.materials.first(),
            None => None,
            Some(s) => self.materials.iter().find(|m| m.label() == s),
        };
        found.ok_or_else(|| SelectError::NoMaterial {
            select: select.map(str::to_string),
            labels: self.materials.iter().map(MaterialEntry::label).collect(),
        })
    }
}
