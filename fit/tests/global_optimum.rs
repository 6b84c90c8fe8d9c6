//! Is the free-amplitude fit the best point of the box it searched, not
//! only of its grid? Checked against an independent multi-start optimiser
//! written here: 20 seeded starts spread over the box, each a bounded
//! Nelder–Mead (argmin's, every vertex clamped into the box) over
//! (σ/T, β, n, a) on the model as the core evaluates it (eq. 8's raw mix),
//! the amplitude by its one-variable least squares, then a restart from
//! the best. The fit must never be beaten: on the paper's 13 CUReT samples
//! with exp and gauss (26 fits; `CURET_DIR`) and on synthetic sets.

use argmin::core::{CostFunction, Executor, State};
use argmin::solver::neldermead::NelderMead;
use laminar_brdf_core::{components, Correlation, Geometry, Params};
use laminar_brdf_fit::coverage::{draw, noisy_scene, NoiseModel};
use laminar_brdf_fit::synthetic::Noise;
use laminar_brdf_fit::{Fitter, Grid, Model, Objective, Scene};
use rayon::prelude::*;

mod common;

/// The weighted objective `Σ w (D − c M)²` at (σ/T, β, n, a), with the best
/// `c ≥ 0` for those.
struct Independent {
    geometry: Vec<Geometry<f64>>,
    data: Vec<f64>,
    weight: Vec<f64>,
    corr: Correlation,
}

impl Independent {
    fn new(scene: &Scene, corr: Correlation) -> Self {
        Self {
            geometry: scene.angles().iter().map(Geometry::<f64>::splat).collect(),
            data: scene.data().to_vec(),
            weight: match scene.sigma() {
                Some(s) => s.iter().map(|s| 1.0 / (s * s)).collect(),
                None => vec![1.0; scene.len()],
            },
            corr,
        }
    }

    fn objective(&self, x: &[f64]) -> f64 {
        let Ok(p) = Params::new(x[0], x[1], x[2], x[3]) else {
            return f64::INFINITY;
        };
        let m: Vec<f64> = self
            .geometry
            .iter()
            .map(|g| components(g, self.corr, &p).total)
            .collect();
        let (mut dm, mut mm) = (0.0, 0.0);
        for ((w, d), m) in self.weight.iter().zip(&self.data).zip(&m) {
            dm += w * d * m;
            mm += w * m * m;
        }
        let c = if mm > 0.0 { (dm / mm).max(0.0) } else { 0.0 };
        (0..m.len())
            .map(|k| self.weight[k] * (self.data[k] - c * m[k]).powi(2))
            .sum()
    }
}

struct Cost<'a> {
    f: &'a Independent,
    bounds: [(f64, f64); 4],
}

impl Cost<'_> {
    fn clamp(&self, x: &[f64]) -> Vec<f64> {
        x.iter()
            .zip(&self.bounds)
            .map(|(v, (lo, hi))| v.clamp(*lo, *hi))
            .collect()
    }
}

impl CostFunction for Cost<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, x: &Vec<f64>) -> Result<f64, argmin::core::Error> {
        Ok(self.f.objective(&self.clamp(x)))
    }
}

/// Nelder–Mead from `start` with a simplex of `step` × the box's width.
fn nelder_mead(cost: &Cost, start: &[f64], step: f64) -> (Vec<f64>, f64) {
    let mut simplex = vec![start.to_vec()];
    for (i, (lo, hi)) in cost.bounds.iter().enumerate() {
        let mut v = start.to_vec();
        let d = step * (hi - lo);
        v[i] = if v[i] + d <= *hi { v[i] + d } else { v[i] - d };
        simplex.push(v);
    }
    let solver = NelderMead::new(simplex).with_sd_tolerance(1e-14).unwrap();
    let result = Executor::new(
        Cost {
            f: cost.f,
            bounds: cost.bounds,
        },
        solver,
    )
    .configure(|s| s.max_iters(3000))
    .run()
    .unwrap();
    let x = cost.clamp(result.state().get_best_param().unwrap());
    let e = cost.f.objective(&x);
    (x, e)
}

/// The independent multi-start's best objective in `bounds`.
fn multistart(f: &Independent, bounds: [(f64, f64); 4], seed: u64) -> f64 {
    let cost = Cost { f, bounds };
    let mut rng = Noise::new(seed);
    let starts: Vec<Vec<f64>> = (0..20)
        .map(|_| {
            let (s0, s1) = (bounds[0].0.ln(), bounds[0].1.ln());
            let mut v = vec![(s0 + (s1 - s0) * rng.uniform()).exp()];
            for b in &bounds[1..] {
                v.push(b.0 + (b.1 - b.0) * rng.uniform());
            }
            v
        })
        .collect();
    let runs: Vec<(Vec<f64>, f64)> = starts
        .par_iter()
        .map(|s| nelder_mead(&cost, s, 0.1))
        .collect();
    let best = runs.into_iter().min_by(|a, b| a.1.total_cmp(&b.1)).unwrap();
    let again = nelder_mead(&cost, &best.0, 0.01);
    best.1.min(again.1)
}

/// Our fit's objective, recomputed from its fitted model's prediction.
fn ours(scene: &Scene, fit: &laminar_brdf_fit::Fit) -> f64 {
    let p = fit.estimate().fitted.predict(scene.angles()).unwrap();
    let w = |k: usize| scene.sigma().map_or(1.0, |s| 1.0 / (s[k] * s[k]));
    (0..scene.len())
        .map(|k| w(k) * (scene.data()[k] - p[k]).powi(2))
        .sum()
}

/// The box of the default grid, (σ/T, β, n, a).
fn bounds(grid: &Grid) -> [(f64, f64); 4] {
    [
        grid.slope.range(),
        grid.beta.range(),
        grid.n.range(),
        grid.a.range(),
    ]
}

/// Fits every scene with exp and gauss and checks each against the
/// multi-start; returns the printed table's rows.
fn check(scenes: &[Scene]) -> Vec<String> {
    let grid = Grid::user();
    let fitter = Fitter::new(grid.clone())
        .unwrap()
        .objective(Objective::Free);
    let mut rows = Vec::new();
    let mut beaten = Vec::new();
    for scene in scenes {
        for (model, corr) in [
            (Model::Exp, Correlation::Exponential),
            (Model::Gauss, Correlation::Gaussian),
        ] {
            let fit = fitter.fit(scene, model);
            let mine = ours(scene, &fit);
            let theirs = multistart(&Independent::new(scene, corr), bounds(&grid), 21);
            let row = format!(
                "{} {model}: laminar {mine:.9e}, multi-start {theirs:.9e} ({})",
                scene.sample(),
                fit.estimate().params_text()
            );
            eprintln!("global optimum | {row}");
            if mine > theirs * (1.0 + 1e-7) + 1e-15 {
                beaten.push(row.clone());
            }
            rows.push(row);
        }
    }
    assert!(
        beaten.is_empty(),
        "the multi-start found lower optima: {beaten:#?}"
    );
    rows
}

#[test]
fn no_multistart_beats_the_fit_on_synthetic_sets() {
    let mut rng = Noise::new(77);
    let scenes: Vec<Scene> = (0..4)
        .flat_map(|i| {
            let model = if i % 2 == 0 { Model::Exp } else { Model::Gauss };
            let truth = draw(model, Objective::Free, &mut rng);
            let noise = if i < 2 {
                NoiseModel::Every(0.01)
            } else {
                NoiseModel::Heteroscedastic {
                    floor: 0.003,
                    relative: 0.03,
                }
            };
            [noisy_scene(model, Objective::Free, truth, noise, &mut rng)
                .labelled(&format!("synthetic-{i}"), "value")]
        })
        .collect();
    check(&scenes);
}

#[test]
fn no_multistart_beats_the_fit_on_the_26_curet_paper_fits() {
    let Some(scenes) = common::paper_scenes("CUReT global-optimum test") else {
        return;
    };
    assert_eq!(check(&scenes).len(), 26);
}

/// The corner where n meets 1 (docs/conventions.md §11b): at n = 1 and
/// a = 0 the layer's term is the surface's own, and just above n = 1 it
/// moves faster the nearer a measurement is to grazing, so a narrow
/// valley runs from the face n = 1 with β near 1. Set 92 of the
/// coverage runs' heteroscedastic exp sets on the built-in geometry
/// (seed 2016) has its lowest point there (n = 1.0013, β = 1, a = 0.004,
/// χ² 0.35% below the estimate's: by 0.61 in `Σ w r²`, inside the
/// 68.27% level), where the grid's columns at n = 1 and n = 1.15 and
/// the refinement from the grid's basins did not reach; the fit reported
/// n = 2.5 (n's intervals, [1, 2.5], held the lower point; β's 95%
/// interval, [0, 0.56], did not). Fitting the same set on the box cut to
/// n ≤ 1.01 finds the lower point; the fit on the whole box must not be
/// above it (the refinement's start just above the face n = 1 reaches it).
#[test]
fn the_fit_is_not_beaten_where_n_meets_1() {
    use laminar_brdf_fit::coverage::{noisy_sets, SETTINGS};
    let set = noisy_sets(
        &laminar_brdf_fit::synthetic::geometries(),
        Model::Exp,
        Objective::Free,
        SETTINGS[1],
        200,
        2016,
    )
    .swap_remove(92);
    let fit = |grid: Grid| {
        let fit = Fitter::new(grid)
            .unwrap()
            .objective(Objective::Free)
            .fit(&set, Model::Exp);
        (ours(&set, &fit), fit.estimate().params_text())
    };
    let mut corner = Grid::user();
    corner.n = laminar_brdf_fit::Axis::linspace(1.0, 1.01, 11);
    let (mine, at) = fit(Grid::user());
    let (theirs, there) = fit(corner);
    assert!(
        mine <= theirs * (1.0 + 1e-9),
        "the box's fit {mine:.9e} at {at} is beaten by {theirs:.9e} at {there}"
    );
}
