//! One `fit_batch` of the free objective with the defaults, on the sets of
//! `cargo bench --bench free` (CUReT sample 21's geometry when `CURET_DIR`
//! is set, else the built-in scene's): a workload for profilers
//! (`valgrind --tool=callgrind`, `perf record`). With `LAMINAR_ONE_AT_A_TIME`
//! set, each set is fitted on its own (`Fitter::fit`, no shared model side).
//! Run:
//! `cargo run --release -p laminar-brdf-fit --example free_batch -- [SETS] [THREADS]`.

use laminar_brdf_fit::coverage::{noisy_sets, NoiseModel};
use laminar_brdf_fit::synthetic;
use laminar_brdf_fit::{Analysis, Fitter, Grid, Model, Objective, Uncertainty};
use laminar_brdf_io::curet::CuretDir;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// `LAMINAR_ANALYSIS`: `none`, `refine`, `profile`, `jacobian` or `both`
/// (the default): what follows the grid stage.
fn analysis() -> Analysis {
    let (refine, uncertainty) = match std::env::var("LAMINAR_ANALYSIS").as_deref() {
        Ok("none") => (false, Uncertainty::Off),
        Ok("refine") => (true, Uncertainty::Off),
        Ok("profile") => (true, Uncertainty::Profile),
        Ok("jacobian") => (true, Uncertainty::Jacobian),
        _ => (true, Uncertainty::Both),
    };
    Analysis {
        refine,
        uncertainty,
        ..Analysis::FULL
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let count: usize = args.next().map_or(Ok(64), |a| a.parse())?;
    let threads: usize = args.next().map_or(Ok(1), |a| a.parse())?;
    let scene = match std::env::var_os("CURET_DIR") {
        Some(dir) => CuretDir::open(Path::new(&dir))?
            .samples(&[PathBuf::from("abrdf.dat")], Some(&[21]))?
            .remove(0)
            .set
            .scene("avg")?,
        None => synthetic::default_scene(),
    };
    // The sets of `cargo bench --bench free`.
    let sets = noisy_sets(
        scene.angles(),
        Model::Exp,
        Objective::Free,
        NoiseModel::Every(0.01),
        count,
        5,
    );
    // `LAMINAR_MODEL`: the model fitted (exp unless told).
    let model: Model = match std::env::var("LAMINAR_MODEL") {
        Ok(name) => name.parse()?,
        Err(_) => Model::Exp,
    };
    let fitter = Fitter::new(Grid::user())?
        .objective(Objective::Free)
        .analysis(analysis())
        .threads(threads)?;
    let start = Instant::now();
    let fits = if std::env::var_os("LAMINAR_ONE_AT_A_TIME").is_some() {
        sets.iter().map(|s| fitter.fit(s, model)).collect()
    } else {
        fitter.fit_batch(&sets, model)
    };
    let seconds = start.elapsed().as_secs_f64();
    let rms: f64 = fits.iter().map(|f| f.best.rms).sum::<f64>() / count as f64;
    println!(
        "{count} sets, K = {}, {threads} thread(s): {seconds:.3} s, {:.0} sets/s, mean Δ_RMS {rms:.4}",
        scene.angles().len(),
        count as f64 / seconds
    );
    Ok(())
}
