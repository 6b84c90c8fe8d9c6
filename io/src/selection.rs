//! Choosing one fitted model from a fitted-model file by its label
//! `sample/channel/model`: one rule for every front end (the CLI's
//! `--select`, the wasm `predict`, Python's `FittedModel.from_file`).

use crate::fits::{FitEntry, FitsFile};
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
    /// The fitted model's own Δ_RMS (the refined one when refined).
    pub rms: f64,
}

/// Why no fit was picked.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SelectError {
    /// The file holds no fit.
    #[error("holds no fit")]
    Empty,
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
            rms: e.rms_refined.unwrap_or(e.rms),
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
                rms,
            });
        }
    }
    out
}

impl FitsFile {
    /// The fit labelled `select` ([`candidates`]), or the file's only fit
    /// when `select` is `None`.
    ///
    /// # Errors
    /// [`SelectError`]: no fit, several and no label, or no fit of the label.
    pub fn select(&self, select: Option<&str>) -> Result<Selected, SelectError> {
        if self.fits.is_empty() {
            return Err(SelectError::Empty);
        }
        let mut all = candidates(&self.fits);
        let labels = || all.iter().map(|c| c.label.clone()).collect::<Vec<_>>();
        let index = match select {
            None if self.fits.len() == 1 => 0,
            None => {
                return Err(SelectError::Ambiguous {
                    count: self.fits.len(),
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
}
