//! `laminar report scaling`: how the cost of a fit grows with the number of
//! measurements K and with the grid, for one set at a time and for a batch
//! of sets on one geometry, with the fitted power-law exponents.

use laminar_brdf_core::Correlation;
use laminar_brdf_fit::{
    synthetic, Analysis, Axis, FitError, Fitter, Grid, Model, Objective, Scene,
};
use laminar_brdf_io::fits::markdown_table;
use std::time::Instant;

/// One measured configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct ScalingRow {
    /// Measurements per set.
    pub k: usize,
    /// Points per axis relative to the base grid.
    pub scale: usize,
    /// Grid points.
    pub grid_points: usize,
    /// Seconds per fit, one set at a time (`Fitter::fit`).
    pub one_set: f64,
    /// Seconds per fit in one batch (`Fitter::fit_batch`).
    pub batch: f64,
}

/// The report: rows against K (base grid) and against the grid (first K).
#[derive(Debug, Clone, PartialEq)]
pub struct ScalingReport {
    /// Sets fitted one at a time per configuration.
    pub one_set_sets: usize,
    /// Sets per batch.
    pub batch_sets: usize,
    /// Against K at scale 1.
    pub by_k: Vec<ScalingRow>,
    /// Against the grid at the first K.
    pub by_grid: Vec<ScalingRow>,
}

/// `grid` with `scale` times as many points on every axis, same ends.
pub fn scaled(grid: &Grid, scale: usize) -> Grid {
    let axis = |a: &Axis| {
        let (first, last) = (a.values[0], a.values[a.len() - 1]);
        Axis::linspace(first, last, a.len() * scale)
    };
    Grid {
        slope: axis(&grid.slope),
        n: axis(&grid.n),
        a: axis(&grid.a),
        beta: axis(&grid.beta),
    }
}

/// Times the exp model's fits on synthetic sets (the model at random
/// parameters inside the paper grid's range, 1% noise, on
/// [`synthetic::spread`] geometries): for every K of `ks` on `grid`, and
/// for every scale of `scales` on the first K. `progress(label)` is called
/// as each configuration starts.
///
/// # Errors
/// [`FitError`] when a scaled grid is invalid.
pub fn scaling(
    grid: &Grid,
    ks: &[usize],
    scales: &[usize],
    one_set_sets: usize,
    batch_sets: usize,
    progress: &dyn Fn(&str),
) -> Result<ScalingReport, FitError> {
    let run = |k: usize, scale: usize| -> Result<ScalingRow, FitError> {
        progress(&format!("K = {k}, {scale}× points per axis"));
        let grid = scaled(grid, scale);
        // The search's cost: no refinement or uncertainty after it.
        let fitter = Fitter::new(grid.clone())?
            .objective(Objective::Paper)
            .analysis(Analysis::NONE);
        let sets: Vec<Scene> = synthetic::sets(
            Correlation::Exponential,
            &synthetic::spread(k),
            batch_sets.max(one_set_sets),
            0.01,
            k as u64,
        );
        let start = Instant::now();
        for set in &sets[..one_set_sets] {
            std::hint::black_box(fitter.fit(set, Model::Exp));
        }
        let one_set = start.elapsed().as_secs_f64() / one_set_sets.max(1) as f64;
        let start = Instant::now();
        std::hint::black_box(fitter.fit_batch(&sets[..batch_sets], Model::Exp));
        let batch = start.elapsed().as_secs_f64() / batch_sets.max(1) as f64;
        Ok(ScalingRow {
            k,
            scale,
            grid_points: grid.size(),
            one_set,
            batch,
        })
    };
    let by_k = ks.iter().map(|&k| run(k, 1)).collect::<Result<_, _>>()?;
    let k0 = ks.first().copied().unwrap_or(198);
    let by_grid = scales
        .iter()
        .map(|&s| run(k0, s))
        .collect::<Result<_, _>>()?;
    Ok(ScalingReport {
        one_set_sets,
        batch_sets,
        by_k,
        by_grid,
    })
}

/// The least-squares slope of `ln y` against `ln x` (the exponent of
/// `y ∝ x^p`); `None` for fewer than two distinct `x`.
pub fn exponent(points: &[(f64, f64)]) -> Option<f64> {
    let n = points.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = points.iter().map(|&(x, y)| (x.ln(), y.ln())).unzip();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxx: f64 = lx.iter().map(|x| (x - mx) * (x - mx)).sum();
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    (points.len() >= 2 && sxx > 0.0).then(|| sxy / sxx)
}

impl ScalingReport {
    /// The report as Markdown: two tables and the exponents.
    pub fn markdown(&self) -> String {
        let mut out = format!(
            "Exp model, synthetic sets (1% noise); one-set: mean of {} `fit` calls; batch: one `fit_batch` of {} sets on one geometry.\n\n",
            self.one_set_sets, self.batch_sets
        );
        let table = |rows: &[ScalingRow], out: &mut String| {
            let header = [
                "K",
                "points per axis",
                "grid points",
                "one-set ms/fit",
                "batch ms/fit",
                "batch fits/s",
            ];
            let cells: Vec<Vec<String>> = rows
                .iter()
                .map(|r| {
                    vec![
                        r.k.to_string(),
                        format!("{}×", r.scale),
                        r.grid_points.to_string(),
                        format!("{:.2}", 1e3 * r.one_set),
                        format!("{:.3}", 1e3 * r.batch),
                        format!("{:.0}", 1.0 / r.batch),
                    ]
                })
                .collect();
            out.push_str(&markdown_table(&header, &cells));
        };
        let fitted = |rows: &[ScalingRow], x: fn(&ScalingRow) -> f64, what: &str| {
            let p = |y: fn(&ScalingRow) -> f64| {
                exponent(&rows.iter().map(|r| (x(r), y(r))).collect::<Vec<_>>())
                    .map_or("n/a".into(), |p| format!("{p:.2}"))
            };
            format!(
                "Fitted exponent (time per fit ∝ {what}^p): one-set p = {}, batch p = {}.\n\n",
                p(|r| r.one_set),
                p(|r| r.batch)
            )
        };
        out.push_str("Against the number of measurements K (base grid):\n\n");
        table(&self.by_k, &mut out);
        out.push('\n');
        out.push_str(&fitted(&self.by_k, |r| r.k as f64, "K"));
        out.push_str("Against the grid (points per axis × 1, 2, 4 …; first K):\n\n");
        table(&self.by_grid, &mut out);
        out.push('\n');
        out.push_str(&fitted(
            &self.by_grid,
            |r| r.grid_points as f64,
            "grid points",
        ));
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exponent_of_a_power_law() {
        let p = exponent(&[(1.0, 3.0), (10.0, 30.0 * 10f64.sqrt()), (100.0, 3000.0)]).unwrap();
        assert!((p - 1.5).abs() < 1e-12, "{p}");
        assert_eq!(exponent(&[(2.0, 1.0)]), None);
    }

    #[test]
    fn scaled_grids_keep_their_ends() {
        let g = scaled(&Grid::paper(), 2);
        assert_eq!(g.slope.len(), 100);
        assert_eq!(g.size(), 100 * 22 * 202 * 200);
        assert_eq!(g.slope.values[0], 0.12);
        assert!((g.beta.values[199] - 1.0).abs() < 1e-12);
    }
}
