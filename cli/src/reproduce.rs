//! `laminar reproduce`: the paper's experiment (§IV) end to end — every model
//! on every job, Tables II–V as Markdown and CSV, Fig. 2 and the
//! data-against-model figures as SVG.

use crate::figures::{data_vs_model_svg, energy_budget_svg};
use crate::selection::{material, Job};
use crate::tables::paper_tables;
use crate::CliError;
use laminar_fit::{Fit, Fitter, Model, ModelParams};
use laminar_io::fits::csv as fit_csv;
use laminar_io::write_atomic;
use std::path::{Path, PathBuf};

/// Samples drawn as data against model (the paper's Figs. 3–4).
pub const FIGURE_SAMPLES: [&str; 4] = ["21", "48", "25", "19"];

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
    /// write (other samples or channels), removed so that the directory
    /// shows only this run.
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

/// True for a file name that `reproduce` writes (figures and tables).
fn is_ours(name: &str) -> bool {
    name.ends_with(".svg") && name.starts_with("fig")
}

/// Fits one job with `model`: a CUReT directory's own Oren–Nayar parameters
/// when it has them (docs/conventions.md §7), else the fitter's search.
///
/// # Errors
/// [`CliError`] when the given parameters are outside their domain.
pub fn fit_job(fitter: &Fitter, job: &Job, model: Model) -> Result<Fit, CliError> {
    match (model, job.oren_nayar) {
        (Model::OrenNayar, Some(given)) => Ok(fitter.assess(
            &job.scene,
            model,
            ModelParams::OrenNayar {
                sigma: given.sigma,
                rho: given.rho,
            },
        )?),
        _ => Ok(fitter.fit(&job.scene, model)),
    }
}

/// Creates `out` if missing and checks that files can be written in it.
///
/// # Errors
/// [`CliError::Read`] when the directory cannot be created or written.
pub fn prepare_out_dir(out: &Path) -> Result<(), CliError> {
    std::fs::create_dir_all(out).map_err(|e| laminar_io::ReadError::io(out, "create", e))?;
    laminar_io::check_writable(&out.join("summary.md"))?;
    Ok(())
}

/// Fits [`FITTED`] on every job with `fitter` and writes the tables and
/// figures into `out` (created if missing; figures of an earlier run that
/// this run does not write are removed and listed).
///
/// # Errors
/// [`CliError`] when a fit, a figure or a file write fails.
pub fn reproduce(fitter: &Fitter, jobs: &[Job], out: &Path) -> Result<Reproduction, CliError> {
    prepare_out_dir(out)?;
    let mut records = Vec::new();
    let mut pairs = 0.0;
    for job in jobs {
        for model in FITTED {
            let r = fit_job(fitter, job, model)?;
            pairs += r.evaluated as f64 * r.measurements as f64;
            records.push(r);
        }
    }
    let grid = fitter.grid();
    let path = fitter.search_path();
    let mut files = Vec::new();
    let tables = paper_tables(&records);
    let mut summary = String::from("# Reproduction of Dahlan & Hancock (2016), §IV\n\n");
    summary += &format!("Search grid: {grid}; search path `{path}`.\n\n");
    for t in &tables {
        write(out, &format!("{}.md", t.name), &t.markdown(), &mut files)?;
        write(out, &format!("{}.csv", t.name), &t.csv(), &mut files)?;
        summary += &t.markdown();
        summary += "\n";
    }
    write(out, "fits.csv", &fit_csv(&records), &mut files)?;
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
    let mut removed = Vec::new();
    let entries = std::fs::read_dir(out).map_err(|e| laminar_io::ReadError::io(out, "read", e))?;
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name().to_string_lossy().into_owned();
        if is_ours(&name) && !files.contains(&path) {
            std::fs::remove_file(&path)
                .map_err(|e| laminar_io::ReadError::io(&path, "remove", e))?;
            removed.push(path);
        }
    }
    removed.sort();
    Ok(Reproduction {
        records,
        files,
        removed,
        pairs,
    })
}
