//! The free objective's default grid against another grid over (σ/T, n,
//! a): what one fit costs with each, and what the other grid changes. Per
//! (geometry, model, noise), the sets of `grid_precision` are fitted with
//! the defaults on both grids; a fit "moved" when a refined value changed
//! by more than 10⁻³ of its 68.27% interval, and each moved fit is counted
//! by which grid's estimate has the lower objective (`Σ w r²`, read as
//! χ²/ν). Then the median time of one fit on CUReT sample 21's geometry
//! (64 sets fitted one at a time, three rounds per grid). Run:
//! `cargo run --release -p laminar-brdf-fit --example grid_density -- SLOPES:NS:AS [SETS]`
//! (`SLOPES` log-spaced σ/T values over [0.02, 20], `NS` values of n over
//! [1, `N_MAX`], `AS` of a over [0, 1]; `N_MAX` 2.5 unless set in the
//! environment; the default grid is `40:11:21`). With `CURET_DIR` set,
//! CUReT sample 21's geometry is used besides the built-in one.

use laminar_brdf_fit::coverage::{noisy_sets, NoiseModel, SETTINGS};
use laminar_brdf_fit::{Axis, Fitter, Grid, Model, Objective};
use std::time::Instant;

mod common;

/// The grid of `SLOPES:NS:AS`, n's axis ending at `n_max`.
fn grid(spec: &str, n_max: f64) -> Result<Grid, Box<dyn std::error::Error>> {
    let counts: Vec<usize> = spec.split(':').map(str::parse).collect::<Result<_, _>>()?;
    let [slopes, ns, a_count] = counts[..] else {
        return Err(format!("expected SLOPES:NS:AS, got {spec}").into());
    };
    let mut grid = Grid::user();
    grid.slope = Axis::logspace(0.02, 20.0, slopes);
    grid.n = Axis::linspace(1.0, n_max, ns);
    grid.a = Axis::linspace(0.0, 1.0, a_count);
    grid.validate()?;
    Ok(grid)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let spec = args
        .next()
        .ok_or("usage: grid_density SLOPES:NS:AS [SETS]")?;
    let count: usize = args.next().map_or(Ok(200), |a| a.parse())?;
    let n_max = std::env::var("N_MAX").map_or(Ok(2.5), |v| v.parse())?;
    let other = Fitter::new(grid(&spec, n_max)?)?.objective(Objective::Free);
    let default = Fitter::new(Grid::user())?.objective(Objective::Free);

    let geometries = common::geometries()?;
    // Noise-free sets are left out: their intervals have no width.
    let noises = [SETTINGS[0], SETTINGS[1], NoiseModel::Every(1e-3)];
    println!("default grid 40:11:21 against {spec} (n up to {n_max}), {count} sets per row");
    println!("| geometry | model | noise | moved | lower on {spec} | lower on the default |");
    println!("|---|---|---|---|---|---|");
    for (label, angles) in &geometries {
        for model in [Model::Exp, Model::Gauss, Model::RhExp, Model::RhGauss] {
            for noise in noises {
                let sets = noisy_sets(angles, model, Objective::Free, noise, count, 2016);
                let first = default.fit_batch(&sets, model);
                let second = other.fit_batch(&sets, model);
                let (mut shifted, mut lower_other, mut lower_default) = (0, Vec::new(), 0);
                for (trial, (a, b)) in first.iter().zip(&second).enumerate() {
                    if common::changes(a, b).1 <= 1e-3 {
                        continue;
                    }
                    shifted += 1;
                    let (Some(ea), Some(eb)) = (a.chi2_weighted, b.chi2_weighted) else {
                        continue;
                    };
                    if eb < ea {
                        lower_other.push(format!("{trial} ({:.2e})", 1.0 - eb / ea));
                    } else if ea < eb {
                        lower_default += 1;
                    }
                }
                println!(
                    "| {label} | {model} | {} | {shifted} | {} {:?} | {lower_default} |",
                    noise.label(),
                    lower_other.len(),
                    lower_other,
                );
            }
        }
    }
    if let Some((_, angles)) = geometries.last() {
        let sets = noisy_sets(angles, Model::Exp, Objective::Free, SETTINGS[0], 64, 5);
        for (name, fitter) in [("40:11:21", &default), (spec.as_str(), &other)] {
            for round in 0..3 {
                let mut times: Vec<f64> = sets
                    .iter()
                    .map(|s| {
                        let start = Instant::now();
                        std::hint::black_box(fitter.fit(s, Model::Exp));
                        start.elapsed().as_secs_f64() * 1e3
                    })
                    .collect();
                times.sort_by(f64::total_cmp);
                println!(
                    "one exp fit, grid {name}, round {round}: median {:.3} ms",
                    times[times.len() / 2]
                );
            }
        }
    }
    Ok(())
}
