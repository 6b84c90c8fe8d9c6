//! Choosing one fitted model from a fitted-model file (`--fit`, `--select`).

use clap::Args;
use laminar_brdf::usage::UsageError;
use laminar_brdf::CliError;
use laminar_brdf_io::fits::read_fits;
use laminar_brdf_io::selection::SelectError;
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

pub use laminar_brdf_io::selection::Selected;

impl FitFileArgs {
    /// Reads the file and picks the fit ([`laminar_brdf_io::fits::FitsFile::select`]).
    pub fn selected(&self) -> Result<Selected, CliError> {
        let file = read_fits(&self.file)?;
        let selected = file.select(self.select.as_deref()).map_err(|e| {
            let file = self.file.clone();
            match e {
                SelectError::Empty => UsageError::NoFit(file),
                SelectError::Ambiguous { count, labels } => UsageError::SelectOne {
                    file,
                    count,
                    labels,
                },
                source @ (SelectError::NoMatch { .. } | SelectError::NoMaterial { .. }) => {
                    UsageError::NoMatch { file, source }
                }
            }
        })?;
        // The model's parameters are checked here, once, for every command
        // that predicts with it: an error names the file and the fit.
        selected
            .fitted
            .predict(&[])
            .map_err(|source| self.model_error(&selected.label, source))?;
        Ok(selected)
    }

    /// `source`, a failure of the fit `label` of this file to predict.
    pub fn model_error(&self, label: &str, source: laminar_brdf_fit::ModelError) -> CliError {
        CliError::Read(laminar_brdf_io::ReadError::Model {
            file: self.file.clone(),
            fit: label.to_string(),
            source,
        })
    }
}
