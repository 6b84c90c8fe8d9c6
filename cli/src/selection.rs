//! What a command runs on: the built-in synthetic scene, samples of a CUReT
//! directory, or a measurement file (CSV, or MERL sampled at given
//! geometries), as scenes to fit.

use crate::usage::UsageError;
use crate::CliError;
use laminar_brdf_fit::{synthetic, MeasurementSet, Scene};
use laminar_brdf_io::curet::{CuretDir, OrenNayarRow};
use laminar_brdf_io::{merl, read_csv, read_geometry, AngleUnit, ReadError};
use std::path::{Path, PathBuf};

/// The paper's 13 samples (docs/conventions.md §8).
pub const PAPER_SAMPLES: [u32; 13] = [1, 3, 7, 18, 19, 21, 25, 48, 51, 52, 53, 55, 61];

/// One scene to fit, with a data set's own Oren–Nayar parameters if it has them.
#[derive(Debug, Clone)]
pub struct Job {
    /// The scene (its sample and channel labels name the output rows).
    pub scene: Scene,
    /// Oren–Nayar parameters given by a CUReT directory (`op.dat` and the
    /// per-channel files, docs/conventions.md §7), used instead of the
    /// Oren–Nayar grid search.
    pub oren_nayar: Option<OrenNayarRow>,
}

impl Job {
    /// A job without given Oren–Nayar parameters.
    pub fn new(scene: Scene) -> Self {
        Self {
            scene,
            oren_nayar: None,
        }
    }
}

/// Material names of the paper's samples (docs/conventions.md §8).
pub fn material(sample: &str) -> &'static str {
    match sample {
        "1" => "Felt",
        "3" => "Terry Cloth",
        "7" => "Velvet",
        "18" => "Rug-A",
        "19" => "Rug-B",
        "21" => "Sponge",
        "25" => "Quarry Tile",
        "48" => "Brown Bread",
        "51" => "Corn Husk",
        "52" => "White Bread",
        "53" => "Soleirolia Plant",
        "55" => "Orange Peel",
        "61" => "Moss",
        "synthetic" => "built-in synthetic scene",
        _ => "",
    }
}

/// Parses `--samples`: `all` or a comma-separated list of positive integers.
///
/// # Errors
/// A message naming the entry that is not a positive integer.
pub fn parse_samples(text: &str) -> Result<Option<Vec<u32>>, UsageError> {
    if text.trim() == "all" {
        return Ok(None);
    }
    text.split(',')
        .map(|s| {
            s.trim()
                .parse::<u32>()
                .ok()
                .filter(|&v| v > 0)
                .ok_or_else(|| UsageError::Sample(s.to_string()))
        })
        .collect::<Result<Vec<_>, _>>()
        .map(Some)
}

/// The built-in synthetic scene as the only job.
pub fn synthetic_jobs() -> Vec<Job> {
    vec![Job::new(synthetic::default_scene())]
}

/// The jobs of `samples` (`None`: all) of `brdf` files (default: every
/// CUReT BRDF file present) in the CUReT directory `dir`.
///
/// # Errors
/// [`CliError`] for a file defect, a missing sample, or a channel that cannot be fitted.
pub fn curet_jobs(
    dir: &Path,
    brdf: &[PathBuf],
    samples: Option<&[u32]>,
) -> Result<Vec<Job>, CliError> {
    let curet = CuretDir::open(dir)?;
    let files = if brdf.is_empty() {
        curet.brdf_files()
    } else {
        brdf.to_vec()
    };
    if files.is_empty() {
        return Err(UsageError::NoBrdfFile(dir.to_path_buf()).into());
    }
    let mut jobs = Vec::new();
    for s in curet.samples(&files, samples)? {
        let scene = s.set.scene(s.channel.name()).map_err(|source| {
            CliError::Read(ReadError::Measurements {
                file: s.file.clone(),
                source,
            })
        })?;
        jobs.push(Job {
            scene,
            oren_nayar: s.oren_nayar,
        });
    }
    Ok(jobs)
}

/// The format of a measurement file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum InputFormat {
    /// Long-format CSV (`.csv`).
    Csv,
    /// MERL isotropic binary (`.binary`), sampled at `--sample-at`.
    Merl,
    /// ASTM E1392 text (`.astm`: the Cornell gonioreflectometer's files),
    /// each column after the geometry a channel.
    Astm,
    /// NIST's Mueller-matrix BRDF CSV (Germer 2017: `lambda, thetai, phi,
    /// thetar, phir, f_r11, …`), each wavelength a channel.
    Nist,
    /// The RGL-EPFL database's isotropic RGB tensor files (`.bsdf`),
    /// channels `r`, `g`, `b`.
    Rgl,
}

/// How to read a measurement file.
#[derive(Debug, Clone)]
pub struct FileInput {
    /// The file.
    pub path: PathBuf,
    /// Its format (`None`: from the extension).
    pub format: Option<InputFormat>,
    /// Unit of the angles in CSV files.
    pub angles: AngleUnit,
    /// What the values are (CSV; MERL is always BRDF).
    pub quantity: laminar_brdf_fit::Quantity,
    /// Geometries to sample a MERL file at.
    pub sample_at: Option<PathBuf>,
    /// Tolerance of the specular test, radians (default: the library's).
    pub specular_tolerance: Option<f64>,
}

impl FileInput {
    /// The format, from the option or the extension.
    ///
    /// # Errors
    /// [`CliError::Usage`] when neither the option nor the extension names a format.
    pub fn format(&self) -> Result<InputFormat, CliError> {
        if let Some(f) = self.format {
            return Ok(f);
        }
        match self.path.extension().and_then(|e| e.to_str()) {
            Some("csv") => Ok(InputFormat::Csv),
            Some("binary") => Ok(InputFormat::Merl),
            Some("astm") => Ok(InputFormat::Astm),
            Some("bsdf") => Ok(InputFormat::Rgl),
            _ => Err(UsageError::UnknownFormat(self.path.clone()).into()),
        }
    }

    /// Reads the file as a measurement set.
    ///
    /// # Errors
    /// [`CliError`] for a file defect, or a MERL file without `--sample-at`.
    pub fn read(&self) -> Result<MeasurementSet, CliError> {
        let set = self.read_format()?;
        match self.specular_tolerance {
            Some(t) => Ok(set.with_specular_tolerance(t)?),
            None => Ok(set),
        }
    }

    fn read_format(&self) -> Result<MeasurementSet, CliError> {
        match self.format()? {
            InputFormat::Csv => Ok(read_csv(&self.path, self.angles, self.quantity)?),
            InputFormat::Astm => Ok(laminar_brdf_io::astm::read_astm(&self.path)?),
            InputFormat::Nist => Ok(laminar_brdf_io::nist::read_nist(&self.path)?),
            InputFormat::Rgl => Ok(laminar_brdf_io::rgl::read_rgl(&self.path)?),
            InputFormat::Merl => {
                let at = self
                    .sample_at
                    .as_ref()
                    .ok_or_else(|| UsageError::MerlWithoutSampleAt(self.path.clone()))?;
                let geometry = read_geometry(at, self.angles)?;
                let table = merl::read_merl(&self.path)?;
                let (set, missing) = merl::sample(&self.path, &table, &geometry)?;
                if missing > 0 {
                    crate::note!(
                        "{}: {missing} of {} geometries of {} fall in unmeasured bins and are left out",
                        self.path.display(),
                        geometry.len(),
                        at.display()
                    );
                }
                Ok(set)
            }
        }
    }

    /// The scenes of `channels` (`None`: every channel) of the file.
    ///
    /// # Errors
    /// As [`FileInput::read`], and for a channel the file lacks or cannot fit.
    pub fn jobs(&self, channels: Option<&[String]>) -> Result<Vec<Job>, CliError> {
        let set = self.read()?;
        let names: Vec<String> = match channels {
            Some(c) => c.to_vec(),
            None => set.channel_names().iter().map(|s| s.to_string()).collect(),
        };
        names
            .iter()
            .map(|c| {
                set.scene(c).map(Job::new).map_err(|source| {
                    CliError::Read(ReadError::Measurements {
                        file: self.path.clone(),
                        source,
                    })
                })
            })
            .collect()
    }
}
