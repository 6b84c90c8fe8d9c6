//! The grid stage in `f32` against `f64` (`Precision`): the same sets
//! fitted with the defaults both ways, and per (model, noise) how many
//! fits' best grid point moved and the largest change of a refined value
//! and of an interval's end, as a fraction of that parameter's 68.27%
//! interval (the `f64` fit's headline). The table of docs/speed.md. Run:
//! `cargo run --release -p laminar-brdf-fit --example grid_precision -- [SETS]`
//! (with `CURET_DIR` set, CUReT sample 21's geometry is used besides the
//! built-in one).

use laminar_brdf_fit::coverage::{noisy_sets, NoiseModel, SETTINGS};
use laminar_brdf_fit::{Fitter, Grid, Model, Objective, Precision};

mod common;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let count: usize = std::env::args().nth(1).map_or(Ok(200), |a| a.parse())?;
    let geometries = common::geometries()?;
    let noises = [
        SETTINGS[0],
        SETTINGS[1],
        NoiseModel::Every(1e-3),
        NoiseModel::Every(0.0),
    ];
    let fitter = Fitter::new(Grid::user())?.objective(Objective::Free);
    let single = fitter.clone().grid_precision(Precision::F32);
    println!("| geometry | model | noise | sets | grid point moved | largest refined change | largest end change |");
    println!("|---|---|---|---|---|---|---|");
    for (label, angles) in &geometries {
        for model in [Model::Exp, Model::Gauss, Model::RhExp, Model::RhGauss] {
            for noise in noises {
                let sets = noisy_sets(angles, model, Objective::Free, noise, count, 2016);
                let wide = fitter.fit_batch(&sets, model);
                let narrow = single.fit_batch(&sets, model);
                let (mut moved, mut value, mut end) = (0, 0.0f64, 0.0f64);
                for (a, b) in wide.iter().zip(&narrow) {
                    let (m, v, e) = common::changes(a, b);
                    moved += usize::from(m);
                    value = value.max(v);
                    end = end.max(e);
                }
                println!(
                    "| {label} | {model} | {} | {count} | {moved} | {value:.1e} | {end:.1e} |",
                    noise.label()
                );
            }
        }
    }
    Ok(())
}
