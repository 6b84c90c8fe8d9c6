//! Which data a command runs on: the built-in synthetic scene, or samples and
//! channels of CUReT files in a directory.

use crate::data::{read_brdf, read_oren_nayar, read_table, Channel, OrenNayarRow};
use crate::scene::Scene;
use crate::synthetic;
use std::path::{Path, PathBuf};

/// The paper's 13 samples (conventions §8).
pub const PAPER_SAMPLES: [u32; 13] = [1, 3, 7, 18, 19, 21, 25, 48, 51, 52, 53, 55, 61];

/// One scene to fit.
#[derive(Debug, Clone)]
pub struct Job {
    /// Sample label.
    pub sample: String,
    /// Channel.
    pub channel: Channel,
    /// The scene.
    pub scene: Scene,
    /// Oren–Nayar parameters given by the data set (`op.dat` and per-channel
    /// files, conventions §7), used instead of the Oren–Nayar grid search.
    pub oren_nayar: Option<OrenNayarRow>,
}

impl Job {
    /// A job without given Oren–Nayar parameters.
    pub fn new(sample: impl Into<String>, channel: Channel, scene: Scene) -> Self {
        Self {
            sample: sample.into(),
            channel,
            scene,
            oren_nayar: None,
        }
    }
}

/// Material names of the paper's samples (conventions §8).
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
pub fn parse_samples(text: &str) -> Result<Option<Vec<u32>>, String> {
    if text.trim() == "all" {
        return Ok(None);
    }
    text.split(',')
        .map(|s| {
            s.trim()
                .parse::<u32>()
                .ok()
                .filter(|&v| v > 0)
                .ok_or_else(|| format!("sample `{s}` in --samples is not a positive integer"))
        })
        .collect::<Result<Vec<_>, _>>()
        .map(Some)
}

/// The jobs for `data` (or the synthetic scene when `None`), `brdf` files
/// (default: every CUReT BRDF file present) and `samples` (`None`: all in the file).
pub fn jobs(
    data: Option<&Path>,
    brdf: &[PathBuf],
    samples: Option<&[u32]>,
) -> Result<Vec<Job>, String> {
    let Some(dir) = data else {
        if !brdf.is_empty() {
            return Err("--brdf needs --data DIR (or CURET_DIR) for the geometry table".into());
        }
        return Ok(vec![Job::new(
            "synthetic",
            Channel::Avg,
            synthetic::default_scene(),
        )]);
    };
    let table = read_table(&dir.join("table.txt")).map_err(|e| e.to_string())?;
    let files: Vec<PathBuf> = if brdf.is_empty() {
        Channel::ALL
            .iter()
            .map(|c| dir.join(c.file_name()))
            .filter(|p| p.exists())
            .collect()
    } else {
        brdf.iter()
            .map(|p| {
                if p.exists() || p.is_absolute() {
                    p.clone()
                } else {
                    dir.join(p)
                }
            })
            .collect()
    };
    if files.is_empty() {
        return Err(format!(
            "{}: no BRDF file (abrdf.dat, rbrdf.dat, gbrdf.dat, bbrdf.dat) found",
            dir.display()
        ));
    }
    let mut jobs = Vec::new();
    for file in &files {
        let rows = read_brdf(file, table.len()).map_err(|e| e.to_string())?;
        let channel = Channel::from_file(file);
        let op_file = dir.join(channel.oren_nayar_file_name());
        let op_rows = if op_file.exists() {
            read_oren_nayar(&op_file).map_err(|e| e.to_string())?
        } else {
            Vec::new()
        };
        let wanted: Vec<u32> = match samples {
            Some(s) => s.to_vec(),
            None => rows.iter().map(|r| r.sample).collect(),
        };
        for sample in wanted {
            let row = rows
                .iter()
                .find(|r| r.sample == sample)
                .ok_or_else(|| format!("{}: sample {sample} not found", file.display()))?;
            let scene = Scene::from_curet(&table, &row.values);
            if scene.is_empty() {
                return Err(format!(
                    "{}: every row of the geometry table is specular; nothing to fit",
                    dir.display()
                ));
            }
            jobs.push(Job {
                sample: sample.to_string(),
                channel,
                scene,
                oren_nayar: op_rows.iter().find(|r| r.sample == sample).copied(),
            });
        }
    }
    Ok(jobs)
}
