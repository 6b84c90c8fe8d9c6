//! Choosing one fitted model from a fitted-model file (`--fit`, `--select`).

use clap::Args;
use laminar_cli::CliError;
use laminar_fit::FittedModel;
use laminar_io::fits::{read_fits, FitEntry};
use std::path::PathBuf;

/// A fitted model from a file written by `laminar fit --format json`.
#[derive(Args, Debug, Clone)]
pub struct FitFileArgs {
    /// Fitted-model file (`laminar fit --format json --out FIT.json`).
    #[arg(long = "fit")]
    pub file: PathBuf,
    /// Which fit: SAMPLE/CHANNEL/MODEL, e.g. 21/avg/exp; rh-exp and rh-gauss
    /// also select the Ragheb–Hancock best of an exp or gauss fit. Needed
    /// when the file holds more than one fit.
    #[arg(long)]
    pub select: Option<String>,
}

/// A selected fit: its label, sample, channel and model.
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

/// Every fit of the file, and the Ragheb–Hancock best of each exp or gauss
/// fit under its `rh-` label unless the file holds a fit of that label
/// itself (which is then the one selected).
fn candidates(entries: &[FitEntry]) -> Vec<Selected> {
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
            let label = format!("{}/{}/{}", e.sample, e.channel, rh_model);
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

impl FitFileArgs {
    /// Reads the file and picks the fit.
    pub fn selected(&self) -> Result<Selected, CliError> {
        let file = read_fits(&self.file)?;
        if file.fits.is_empty() {
            return Err(CliError::Usage(format!(
                "{}: holds no fit",
                self.file.display()
            )));
        }
        let mut all = candidates(&file.fits);
        let labels = || {
            all.iter()
                .map(|c| c.label.clone())
                .collect::<Vec<_>>()
                .join(", ")
        };
        let index = match &self.select {
            None if file.fits.len() == 1 => 0,
            None => {
                return Err(CliError::Usage(format!(
                    "{} holds {} fits; choose one with --select SAMPLE/CHANNEL/MODEL: {}",
                    self.file.display(),
                    file.fits.len(),
                    labels()
                )))
            }
            Some(s) => all.iter().position(|c| &c.label == s).ok_or_else(|| {
                CliError::Usage(format!(
                    "{}: no fit `{s}`; the file holds {}",
                    self.file.display(),
                    labels()
                ))
            })?,
        };
        let selected = all.swap_remove(index);
        // The model's parameters are checked here, once, for every command
        // that predicts with it: an error names the file and the fit.
        selected
            .fitted
            .predict(&[])
            .map_err(|source| self.model_error(&selected.label, source))?;
        Ok(selected)
    }

    /// `source`, a failure of the fit `label` of this file to predict.
    pub fn model_error(&self, label: &str, source: laminar_fit::ModelError) -> CliError {
        CliError::Read(laminar_io::ReadError::Model {
            file: self.file.clone(),
            fit: label.to_string(),
            source,
        })
    }
}
