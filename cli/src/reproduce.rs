//! `laminar reproduce`: the paper's experiment (§IV) end to end — every model
//! on every job, Tables II–V as Markdown and CSV, Fig. 2 and the
//! data-against-model figures as SVG.

use crate::figures::{data_vs_model_svg, energy_budget_svg, profile_svg};
use crate::selection::{material, Job};
use crate::tables::paper_tables;
use crate::usage::UsageError;
use crate::CliError;
use laminar_brdf_fit::preview::{render, Stage};
use laminar_brdf_fit::{Baseline, Fit, Fitter, Model, ModelParams};
use laminar_brdf_io::fits::csv as fit_csv;
use laminar_brdf_io::write_atomic;
use std::path::{Path, PathBuf};

/// Samples drawn as data against model (the paper's Figs. 3–4).
pub const FIGURE_SAMPLES: [&str; 4] = ["21", "48", "25", "19"];
/// The model whose parameters' profiles are drawn for the figure samples.
pub const PROFILE_MODEL: Model = Model::Exp;
/// Values on each drawn continuous profile.
pub const PROFILE_POINTS: usize = 25;

/// Models fitted: the Ragheb–Hancock fits come from the a = 0 slices of the
/// absorptive searches, so Tables II and V need one search per absorptive model.
pub const FITTED: [Model; 4] = [Model::Exp, Model::Gauss, Model::Jensen, Model::OrenNayar];

/// What a reproduction did.
#[derive(Debug)]
pub struct Reproduction {
    /// One record per (job, fitted model).
    pub records: Vec<Fit>,
    /// Files written, in order.
    pub files: Vec<PathBuf>,
    /// Figures of an earlier run in the directory that this run did not
    /// write (other samples or channels): gone, since the directory now
    /// holds exactly this run.
    pub removed: Vec<PathBuf>,
    /// (parameter set, measurement) pairs evaluated.
    pub pairs: f64,
}

fn write(out: &Path, name: &str, text: &str, files: &mut Vec<PathBuf>) -> Result<(), CliError> {
    let path = out.join(name);
    write_atomic(&path, text)?;
    files.push(path);
    Ok(())
}

/// Pixels on a side of the figure samples' previews.
const PREVIEW_SIZE: usize = 192;

/// True for a file name that `reproduce` writes (figures, previews, tables, fits, summary).
fn is_ours(name: &str) -> bool {
    (name.starts_with("fig") && (name.ends_with(".svg") || name.ends_with(".png")))
        || (name.starts_with("table") && (name.ends_with(".md") || name.ends_with(".csv")))
        || name == "fits.csv"
        || name == "summary.md"
}

/// The names of the files in `out` (none if it does not exist), which must
/// all be files a reproduction writes: the directory is replaced whole.
fn previous_files(out: &Path) -> Result<Vec<String>, CliError> {
    let io = |e| laminar_brdf_io::ReadError::io(out, "read", e);
    if !out.exists() {
        return Ok(Vec::new());
    }
    let mut names = Vec::new();
    let mut foreign = Vec::new();
    for entry in std::fs::read_dir(out).map_err(io)? {
        let entry = entry.map_err(io)?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if is_ours(&name) && entry.file_type().map(|t| t.is_file()).unwrap_or(false) {
            names.push(name);
        } else {
            foreign.push(name);
        }
    }
    if !foreign.is_empty() {
        foreign.sort();
        return Err(UsageError::ForeignEntries {
            dir: out.to_path_buf(),
            entries: foreign,
        }
        .into());
    }
    Ok(names)
}

/// Fits one job with `model`: a CUReT directory's own Oren–Nayar parameters
/// when it has them (docs/conventions.md §7), else the fitter's search.
///
/// # Errors
/// [`CliError`] when the given parameters are outside their domain.
pub fn fit_job(fitter: &Fitter, job: &Job, model: Model) -> Result<Fit, CliError> {
    Ok(match given(job, model) {
        Some(params) => fitter.assess(&job.scene, model, params)?,
        None => fitter.fit(&job.scene, model),
    })
}

/// Fits every model of `models` to every job, in job-major order (the order
/// of `fit`'s output). Layered models on jobs that share their geometry go
/// through one batch search per model ([`Fitter::fit_batch`]); the results
/// are bit for bit those of fitting each job alone.
///
/// # Errors
/// As [`fit_job`].
pub fn fit_jobs(fitter: &Fitter, jobs: &[Job], models: &[Model]) -> Result<Vec<Fit>, CliError> {
    let scenes: Vec<laminar_brdf_fit::Scene> = jobs.iter().map(|j| j.scene.clone()).collect();
    Ok(fitter.fit_all(&scenes, models, |j, model| given(&jobs[j], model))?)
}

/// The parameters a job gives for `model` instead of a search: its data
/// set's own Oren–Nayar parameters.
fn given(job: &Job, model: Model) -> Option<ModelParams> {
    match (model, job.oren_nayar) {
        (Model::OrenNayar, Some(g)) => {
            Some(ModelParams::baseline(Baseline::OrenNayar, [g.sigma, g.rho]))
        }
        _ => None,
    }
}

/// Progress calls of [`fit_jobs`].
pub fn fit_jobs_shards(fitter: &Fitter, jobs: &[Job], models: &[Model]) -> u64 {
    let scenes: Vec<laminar_brdf_fit::Scene> = jobs.iter().map(|j| j.scene.clone()).collect();
    fitter.fit_all_shards(&scenes, models)
}

/// Checks before any work that `out` can be replaced by a reproduction: it
/// is missing, or holds only files a reproduction writes, and its parent
/// accepts new entries (the parent and its own parents are created when
/// missing, as `mkdir -p` would).
///
/// # Errors
/// [`CliError::Usage`] for a directory with other entries, [`CliError::Read`]
/// when the parent cannot be created or written.
pub fn prepare_out_dir(out: &Path) -> Result<(), CliError> {
    previous_files(out)?;
    if let Some(parent) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)
            .map_err(|e| laminar_brdf_io::ReadError::io(parent, "create", e))?;
    }
    laminar_brdf_io::check_writable(&laminar_brdf_io::staging::sibling(out, "probe"))?;
    Ok(())
}

/// Moves the finished `staging` directory to `out`, replacing an earlier
/// run as a whole (two renames; the earlier run is then deleted).
fn replace_dir(staging: &Path, out: &Path) -> Result<(), CliError> {
    let io = |p: &Path, e| CliError::Read(laminar_brdf_io::ReadError::io(p, "rename", e));
    if out.exists() {
        let old = laminar_brdf_io::staging::sibling(out, "old");
        std::fs::rename(out, &old).map_err(|e| io(out, e))?;
        std::fs::rename(staging, out).map_err(|e| io(staging, e))?;
        std::fs::remove_dir_all(&old)
            .map_err(|e| CliError::Read(laminar_brdf_io::ReadError::io(&old, "remove", e)))?;
    } else {
        std::fs::rename(staging, out).map_err(|e| io(staging, e))?;
    }
    Ok(())
}

/// Fits [`FITTED`] on every job with `fitter` and writes the tables and
/// figures into `out` as one set: everything is written into a fresh
/// sibling directory that then replaces `out` whole, so an interrupted run
/// leaves the earlier set untouched and a finished one never mixes with it.
///
/// # Errors
/// [`CliError`] when a fit, a figure or a file write fails.
pub fn reproduce(fitter: &Fitter, jobs: &[Job], out: &Path) -> Result<Reproduction, CliError> {
    // Staging directories of earlier killed runs go; this run's are kept
    // from a concurrent run's sweep while it lives.
    let _claim = laminar_brdf_io::staging::claim(out)?;
    let previous = previous_files(out)?;
    let records = fit_jobs(fitter, jobs, &FITTED)?;
    let pairs = records
        .iter()
        .map(|r| r.evaluated as f64 * r.measurements as f64)
        .sum();
    let staging = laminar_brdf_io::staging::sibling(out, "partial");
    std::fs::create_dir_all(&staging)
        .map_err(|e| laminar_brdf_io::ReadError::io(&staging, "create", e))?;
    let written = write_set(fitter, jobs, &records, &staging);
    let files = match written.and_then(|files| replace_dir(&staging, out).map(|_| files)) {
        Ok(files) => files,
        Err(e) => {
            let _ = std::fs::remove_dir_all(&staging);
            return Err(e);
        }
    };
    let files: Vec<PathBuf> = files
        .iter()
        .map(|f| out.join(f.file_name().expect("a file")))
        .collect();
    let mut removed: Vec<PathBuf> = previous
        .iter()
        .map(|name| out.join(name))
        .filter(|p| !files.contains(p))
        .collect();
    removed.sort();
    Ok(Reproduction {
        records,
        files,
        removed,
        pairs,
    })
}

/// Writes the tables, figures, fits and summary of `records` into `out`.
fn write_set(
    fitter: &Fitter,
    jobs: &[Job],
    records: &[Fit],
    out: &Path,
) -> Result<Vec<PathBuf>, CliError> {
    let grid = fitter.grid();
    let path = fitter.search_path();
    let mut files = Vec::new();
    let tables = paper_tables(records);
    let mut summary = String::from("# Reproduction of Dahlan & Hancock (2016), §IV\n\n");
    summary += &format!("Search grid: {grid}; search path `{path}`.\n\n");
    for t in &tables {
        write(out, &format!("{}.md", t.name), &t.markdown(), &mut files)?;
        write(out, &format!("{}.csv", t.name), &t.csv(), &mut files)?;
        summary += &t.markdown();
        summary += "\n";
    }
    write(out, "fits.csv", &fit_csv(records), &mut files)?;
    write(
        out,
        "fig2_transmission_absorption.svg",
        &energy_budget_svg().map_err(CliError::Figure)?,
        &mut files,
    )?;
    for job in jobs
        .iter()
        .filter(|j| FIGURE_SAMPLES.contains(&j.scene.sample()))
    {
        for r in records
            .iter()
            .filter(|r| r.sample == job.scene.sample() && r.channel == job.scene.channel())
        {
            let mut shown = vec![(r.model, &r.best)];
            if let (Some(rh), Some(rh_model)) = (&r.rh, r.model.ragheb_hancock()) {
                shown.push((rh_model, rh));
            }
            if r.model == PROFILE_MODEL {
                // A preview of the fitted material (docs/conventions.md §12).
                let scene = Stage {
                    size: PREVIEW_SIZE,
                    ..Stage::default()
                };
                let image = render(&[r.estimate().fitted], &scene)?;
                let path = out.join(format!(
                    "fig_preview_sample{}_{}_{}.png",
                    job.scene.sample(),
                    r.model.name(),
                    job.scene.channel()
                ));
                let side = PREVIEW_SIZE as u32;
                laminar_brdf_io::image::write_png(&path, side, side, &image.to_srgb8())?;
                files.push(path);
                for curve in fitter.profiles(&job.scene, r, PROFILE_POINTS) {
                    let title = format!(
                        "sample {} ({}), {}: profile of {}",
                        job.scene.sample(),
                        job.scene.channel(),
                        r.model,
                        curve.name
                    );
                    let name = format!(
                        "fig_profile_sample{}_{}_{}_{}.svg",
                        job.scene.sample(),
                        r.model.name(),
                        job.scene.channel(),
                        curve.name
                    );
                    write(
                        out,
                        &name,
                        &profile_svg(&title, &curve).map_err(CliError::Figure)?,
                        &mut files,
                    )?;
                }
            }
            for (model, estimate) in shown {
                let p = estimate.fitted.predict(job.scene.angles())?;
                let title = format!(
                    "sample {} {} ({}), {model}: Δ_RMS {:.3}",
                    job.scene.sample(),
                    material(job.scene.sample()),
                    job.scene.channel(),
                    estimate.rms
                );
                let name = format!(
                    "fig_sample{}_{}_{}.svg",
                    job.scene.sample(),
                    model.name(),
                    job.scene.channel()
                );
                write(
                    out,
                    &name,
                    &data_vs_model_svg(&title, job.scene.data(), &p).map_err(CliError::Figure)?,
                    &mut files,
                )?;
            }
        }
    }
    write(out, "summary.md", &summary, &mut files)?;
    Ok(files)
}
