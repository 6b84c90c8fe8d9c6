//! The bounds against the values the sweep computes.

use super::*;
use crate::grid::{Axis, Grid};
use crate::synthetic;
use laminar_brdf_core::{f32x8, Correlation, Params};

/// A test grid: the paper's β axis, `slope = (first, last, count)` σ/T
/// values, and `n`, `a` values spread over their whole domain.
fn grid(slope: (f64, f64, usize), n: usize, a: usize) -> Grid {
    Grid {
        slope: Axis::linspace(slope.0, slope.1, slope.2),
        n: Axis::linspace(1.0, 2.0, n),
        a: Axis::linspace(0.0, 1.0, a),
        ..Grid::paper()
    }
}

/// A visitor that sweeps the triples whose bound is at most
/// `threshold[i_a]` (and the (σ/T, n) whose bound is at most the largest
/// of them), recording every value swept and every bound seen.
struct Record<'g> {
    grid: &'g Grid,
    i_s: usize,
    threshold: Vec<f64>,
    values: Vec<Option<f64>>,
    triple_bounds: Vec<f64>,
    n_bounds: Vec<f64>,
}

impl<'g> Record<'g> {
    fn new(grid: &'g Grid, threshold: Vec<f64>) -> Self {
        Self {
            grid,
            i_s: 0,
            threshold,
            values: vec![None; grid.size()],
            triple_bounds: vec![f64::NAN; grid.size() / grid.beta.len()],
            n_bounds: vec![f64::NAN; grid.slope.len() * grid.n.len()],
        }
    }
}

impl Visitor for Record<'_> {
    fn wants_n(&mut self, _: usize, i_n: usize, bound: f64) -> bool {
        self.n_bounds[self.i_s * self.grid.n.len() + i_n] = bound;
        bound
            <= self
                .threshold
                .iter()
                .copied()
                .fold(f64::NEG_INFINITY, f64::max)
    }

    fn wants(&mut self, _: usize, i_n: usize, i_a: usize, bound: f64) -> bool {
        let triple = self.grid.flat(self.i_s, i_n, i_a, 0) / self.grid.beta.len();
        self.triple_bounds[triple] = bound;
        bound <= self.threshold[i_a]
    }

    fn sweep(&mut self, _: usize, i_n: usize, i_a: usize, values: &[f64]) {
        for (i_b, &e) in values.iter().enumerate() {
            self.values[self.grid.flat(self.i_s, i_n, i_a, i_b)] = Some(e);
        }
    }
}

/// Runs every shard of `grid` on a noisy synthetic scene made by `corr`
/// at `truth`, with `threshold` per a index.
fn record<'g, L: Lane>(
    corr: Correlation,
    truth: &Params,
    grid: &'g Grid,
    threshold: Vec<f64>,
) -> Record<'g> {
    let scene = synthetic::scene(corr, truth, 0.01, 3);
    let tables = Tables::<L>::new(&scene, grid);
    let sines = sines(&tables.packed);
    let model = Shard {
        tables: &tables,
        sines: &sines,
        grid,
        corr,
    };
    let data = [SceneData::new(&tables.packed)];
    let mut record = Record::new(grid, threshold);
    for i_s in 0..grid.slope.len() {
        record.i_s = i_s;
        shard(
            &model,
            i_s,
            &data,
            &mut record,
            &mut [SweepStats::default()],
        );
    }
    record
}

/// The smallest value of each triple, in loop order.
fn minima(values: &[Option<f64>], per_triple: usize) -> Vec<f64> {
    values
        .chunks(per_triple)
        .map(|t| {
            t.iter()
                .map(|v| v.expect("swept"))
                .fold(f64::INFINITY, f64::min)
        })
        .collect()
}

/// Every (σ/T, n, a) of a grid that includes n = 1, a = 0 and poor fits
/// far from the truth: with nothing skipped, no triple's bound exceeds
/// any value its sweep computes, no (σ/T, n) bound exceeds any value of
/// its triples, and neither bound is vacuous.
#[test]
fn lower_bounds_are_below_every_computed_error() {
    for corr in [Correlation::Exponential, Correlation::Gaussian] {
        let truth = Params::new(1.48, 0.39, 1.44, 0.2).unwrap();
        let grid = grid((0.12, 4.04, 9), 6, 6);
        let all = record::<f32x8>(corr, &truth, &grid, vec![f64::INFINITY; 6]);
        let min = minima(&all.values, grid.beta.len());
        let (mut useful, mut useful_n) = (0, 0);
        for (bound, min) in all.triple_bounds.iter().zip(&min) {
            assert!(bound <= min, "{corr:?}: triple bound {bound} > min {min}");
            useful += usize::from(*bound > 0.5 * min);
        }
        for (bound, triples) in all.n_bounds.iter().zip(min.chunks(grid.a.len())) {
            let min = triples.iter().copied().fold(f64::INFINITY, f64::min);
            assert!(
                *bound <= min,
                "{corr:?}: (σ/T, n) bound {bound} > min {min}"
            );
            useful_n += usize::from(*bound > 0.5 * min);
        }
        assert!(
            useful > min.len() / 2,
            "triple bound useful on {useful} of {}",
            min.len()
        );
        assert!(useful_n > 0, "(σ/T, n) bound never useful");
    }
}

/// A threshold at or above a triple's minimum never skips it; one below
/// its bound does.
#[test]
fn thresholds_skip_only_triples_that_cannot_reach_them() {
    let corr = Correlation::Gaussian;
    let truth = Params::new(0.68, 0.5, 1.3, 0.4).unwrap();
    // One n and one σ/T, so the a index names the triple.
    let grid = Grid {
        slope: Axis::linspace(0.68, 0.68, 1),
        n: Axis::linspace(1.3, 1.3, 1),
        ..grid((0.2, 3.0, 1), 1, 8)
    };
    let all = record::<f32>(corr, &truth, &grid, vec![f64::INFINITY; 8]);
    let min = minima(&all.values, grid.beta.len());
    let at_min = record::<f32>(corr, &truth, &grid, min.clone());
    assert!(
        at_min.values.iter().all(Option::is_some),
        "skipped a triple reaching its threshold"
    );
    let below: Vec<f64> = all
        .triple_bounds
        .iter()
        .map(|b| b - 1e-3 * b.abs())
        .collect();
    let skipped = record::<f32>(corr, &truth, &grid, below.clone());
    let mut checked = 0;
    for (i_a, bound) in all.triple_bounds.iter().enumerate() {
        if bound.is_finite() {
            checked += 1;
            let swept = skipped.values[i_a * grid.beta.len()].is_some();
            assert!(!swept, "swept a triple whose bound exceeds its threshold");
        }
    }
    assert!(checked > 0, "no triple had a bound");
}
