//! `laminar reproduce`: the paper's experiment (§IV) end to end — every model
//! on every job, Tables II–V as Markdown and CSV, Fig. 2 and the
//! data-against-model figures as SVG.

use crate::figures::{data_vs_model_svg, energy_budget_svg};
use crate::fit::{fit, prediction, FitRecord};
use crate::grid::Grid;
use crate::model::Model;
use crate::report::{csv as fit_csv, write_atomic};
use crate::search::Path as SearchPath;
use crate::selection::{material, Job};
use crate::tables::paper_tables;
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
    pub records: Vec<FitRecord>,
    /// Files written, in order.
    pub files: Vec<PathBuf>,
    /// (parameter set, measurement) pairs evaluated.
    pub pairs: f64,
}

fn write(out: &Path, name: &str, text: &str, files: &mut Vec<PathBuf>) -> Result<(), String> {
    let path = out.join(name);
    write_atomic(&path, text).map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
    files.push(path);
    Ok(())
}

/// Fits [`FITTED`] on every job with `grid` on `path` and writes the tables
/// and figures into `out` (created if missing). `progress` is called once per
/// search shard.
pub fn reproduce(
    jobs: &[Job],
    grid: &Grid,
    path: SearchPath,
    out: &Path,
    progress: &(dyn Fn() + Sync),
) -> Result<Reproduction, String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: cannot create: {e}", out.display()))?;
    let mut records = Vec::new();
    let mut pairs = 0.0;
    for job in jobs {
        for model in FITTED {
            let r = fit(job, model, grid, path, progress);
            pairs += r.evaluated as f64 * r.measurements as f64;
            records.push(r);
        }
    }
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
        &energy_budget_svg()?,
        &mut files,
    )?;
    for job in jobs
        .iter()
        .filter(|j| FIGURE_SAMPLES.contains(&j.sample.as_str()))
    {
        for r in records
            .iter()
            .filter(|r| r.sample == job.sample && r.channel == job.channel)
        {
            let mut shown = vec![(r.model, &r.best)];
            if let Some(rh) = &r.rh {
                let rh_model = if r.model == Model::Exp {
                    Model::RhExp
                } else {
                    Model::RhGauss
                };
                shown.push((rh_model, rh));
            }
            for (model, estimate) in shown {
                let p = prediction(&job.scene, model, estimate);
                let title = format!(
                    "sample {} {} ({}), {model}: Δ_RMS {:.3}",
                    job.sample,
                    material(&job.sample),
                    job.channel.name(),
                    estimate.rms
                );
                let name = format!(
                    "fig_sample{}_{}_{}.svg",
                    job.sample,
                    model.name(),
                    job.channel.name()
                );
                write(
                    out,
                    &name,
                    &data_vs_model_svg(&title, &job.scene.data, &p)?,
                    &mut files,
                )?;
            }
        }
    }
    write(out, "summary.md", &summary, &mut files)?;
    Ok(Reproduction {
        records,
        files,
        pairs,
    })
}
