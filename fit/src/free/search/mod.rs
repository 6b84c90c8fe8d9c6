//! The grid stage of the free-amplitude fit: the objective at every grid
//! point of the nonlinear parameters, with the linear part (β and the
//! amplitude) in closed form at each ([`FreeModel::grid_values`]: point by
//! point, or the layered models' [`quadratic`] stage), and the grid's
//! basins as the starts of the refinement ([`grid_starts`]).

pub mod corner;
pub(crate) mod objectives;
pub mod quadratic;
pub mod untied;

use super::model::{BaselineModel, FreeModel, Nonlinear, Table};
use super::problem::Problem;
use crate::grid::Axis;
use crate::model::Param;
use crate::settings::precision::Precision;
use rayon::prelude::*;

/// A model's grid stage: the objective at every point of its grid, the
/// work sets on one geometry share, and a start of the refinement beside
/// the grid's basins.
pub trait GridStage: FreeModel {
    /// The grid stage's work that sets on one geometry without
    /// uncertainties share ([`GridStage::shared`]).
    type Shared: Send + Sync;

    /// The objective at every grid point of `axes`, the model's terms in
    /// `precision` where the model has a single-precision path.
    fn grid_values(problem: &Problem<Self>, axes: &GridAxes, precision: Precision) -> GridValues;

    /// The grid stage's work that the sets on `problem`'s geometry share
    /// when none has uncertainties (`None` when the model shares none).
    fn shared(
        problem: &Problem<Self>,
        axes: &GridAxes,
        precision: Precision,
    ) -> Option<Self::Shared>;

    /// [`GridStage::grid_values`] of each of `problems` from `shared`
    /// ([`GridStage::shared`]): bit for bit each set's own.
    fn grid_values_shared(
        problems: &[&Problem<Self>],
        axes: &GridAxes,
        shared: &Self::Shared,
    ) -> Vec<GridValues>;

    /// A start of the refinement beside the grid's basins, where the
    /// model has one the grid misses (the layered models' [`corner`]).
    fn corner_start(
        _problem: &Problem<Self>,
        _axes: &GridAxes,
        _values: &GridValues,
    ) -> Option<Vec<f64>> {
        None
    }
}

/// A baseline's grid stage shares nothing between sets: there is no value
/// of this type.
#[derive(Debug)]
pub enum NothingShared {}

/// The baselines' grid stage: point by point, in `f64` whatever the
/// precision asked for.
impl GridStage for BaselineModel {
    type Shared = NothingShared;

    fn grid_values(problem: &Problem<Self>, axes: &GridAxes, _: Precision) -> GridValues {
        point_by_point(problem, axes)
    }

    fn shared(_: &Problem<Self>, _: &GridAxes, _: Precision) -> Option<NothingShared> {
        None
    }

    fn grid_values_shared(
        _: &[&Problem<Self>],
        _: &GridAxes,
        shared: &NothingShared,
    ) -> Vec<GridValues> {
        match *shared {}
    }
}

/// The grid axes of the nonlinear parameters, in the model's values (σ/T,
/// not its logarithm), in θ's order.
#[derive(Debug, Clone, PartialEq)]
pub struct GridAxes {
    /// The parameter of each axis.
    pub params: Vec<Nonlinear>,
    /// One axis per nonlinear parameter.
    pub axes: Vec<Vec<f64>>,
}

impl GridAxes {
    /// The axes `axes` of the parameters of `table` (θ's order).
    pub fn new(table: &Table, axes: Vec<Axis>) -> Self {
        Self {
            params: table.entries().to_vec(),
            axes: axes.into_iter().map(|axis| axis.values).collect(),
        }
    }

    /// Where parameter `p`'s axis is (`None` when the model has none).
    pub fn position(&self, p: Param) -> Option<usize> {
        self.params.iter().position(|e| e.name == p)
    }

    /// Parameter `p`'s axis (`None` when the model has none).
    pub fn of(&self, p: Param) -> Option<&[f64]> {
        self.position(p).map(|j| &self.axes[j][..])
    }

    /// The axes' lengths.
    pub fn lens(&self) -> Vec<usize> {
        self.axes.iter().map(Vec::len).collect()
    }

    /// The nonlinear parameters (internal coordinates) of grid indices.
    pub fn theta(&self, indices: &[usize]) -> Vec<f64> {
        (self.params.iter().zip(&self.axes).zip(indices))
            .map(|((p, axis), &i)| p.scale.internal(axis[i]))
            .collect()
    }
}

/// The grid's objective in row-major order over [`GridAxes`].
#[derive(Debug, Clone, PartialEq)]
pub struct GridValues {
    /// Axis lengths.
    pub lens: Vec<usize>,
    /// Objective at each grid point (moments form).
    pub sse: Vec<f64>,
}

impl GridValues {
    /// The axis indices of a flat index.
    pub fn indices(&self, flat: usize) -> Vec<usize> {
        let mut out = vec![0; self.lens.len()];
        let mut rest = flat;
        for (i, &len) in self.lens.iter().enumerate().rev() {
            out[i] = rest % len;
            rest /= len;
        }
        out
    }

    /// The flat index of axis indices.
    pub fn flat(&self, indices: &[usize]) -> usize {
        (indices.iter().zip(&self.lens)).fold(0, |flat, (&i, &len)| flat * len + i)
    }

    /// The flat indices of the grid points whose axis `axis` is at `index`
    /// (a slice of the grid), in increasing order.
    pub fn slice(&self, axis: usize, index: usize) -> impl Iterator<Item = usize> + '_ {
        let stride: usize = self.lens[axis + 1..].iter().product();
        let block = self.lens[axis] * stride;
        (0..self.sse.len())
            .step_by(block)
            .flat_map(move |start| (0..stride).map(move |i| start + index * stride + i))
    }

    /// The best grid point (the first on ties).
    pub fn best(&self) -> usize {
        let mut best = 0;
        for (i, &e) in self.sse.iter().enumerate() {
            if e < self.sse[best] {
                best = i;
            }
        }
        best
    }
}

/// The objective of `problem` at every grid point of `axes`, each point's
/// columns evaluated in `f64` (the grid stage of a model without a
/// structure to exploit): the points of each value of the first axis
/// in parallel.
pub fn point_by_point<M: FreeModel>(problem: &Problem<M>, axes: &GridAxes) -> GridValues {
    let lens = axes.lens();
    let (&outer_len, inner) = lens.split_first().expect("at least one axis");
    let row: usize = inner.iter().product();
    let rows: Vec<Vec<f64>> = (0..outer_len)
        .into_par_iter()
        .map(|outer| {
            let mut at = vec![0; lens.len()];
            (0..row)
                .map(|i| {
                    let mut rest = i;
                    for (a, &len) in at.iter_mut().zip(&lens).skip(1).rev() {
                        *a = rest % len;
                        rest /= len;
                    }
                    if let Some(first) = at.first_mut() {
                        *first = outer;
                    }
                    let columns = problem.model.columns(&axes.theta(&at));
                    problem.moments(&columns).solve(problem.beta).sse
                })
                .collect()
        })
        .collect();
    GridValues {
        lens,
        sse: rows.concat(),
    }
}

/// Most starts of a refinement: the best point of each of the grid's
/// best basins.
pub const MOST_STARTS: usize = 8;

/// The best point of each of the grid's basins (no axis neighbour lower;
/// on ties the smaller flat index is lower), best first, at most `most`,
/// as axis indices with their objective.
pub fn grid_starts(values: &GridValues, most: usize) -> Vec<(Vec<usize>, f64)> {
    let lens = &values.lens;
    let e = &values.sse;
    let strides: Vec<usize> = (0..lens.len())
        .map(|i| lens[i + 1..].iter().product())
        .collect();
    let lower = |g: usize, f: usize| e[g] < e[f] || (e[g] == e[f] && g < f);
    // A point's neighbours along the last axis are beside it in memory and
    // rule out most points; the survivors are checked along every axis.
    let last = lens.last().copied().unwrap_or(1).max(1);
    let mut minima: Vec<(usize, f64)> = Vec::new();
    for (row, values_of_row) in e.chunks(last).enumerate() {
        for (j, &value) in values_of_row.iter().enumerate() {
            let f = row * last + j;
            if !value.is_finite()
                || (j > 0 && lower(f - 1, f))
                || (j + 1 < values_of_row.len() && lower(f + 1, f))
            {
                continue;
            }
            let basin = lens.iter().zip(&strides).all(|(&len, &stride)| {
                let i = (f / stride) % len;
                let below = i > 0 && lower(f - stride, f);
                let above = i + 1 < len && lower(f + stride, f);
                !(below || above)
            });
            if basin {
                minima.push((f, value));
            }
        }
    }
    minima.sort_by(|p, q| p.1.total_cmp(&q.1).then(p.0.cmp(&q.0)));
    minima.truncate(most);
    minima
        .into_iter()
        .map(|(flat, e)| (values.indices(flat), e))
        .collect()
}

/// Asserts that every grid value of `values` is `problem`'s objective
/// evaluated directly at that point, from the residuals, to 10⁻¹⁰ of
/// `Σ w D²` (the moments form cancels digits of it).
#[cfg(test)]
pub(crate) fn assert_grid_is_the_objective<M: FreeModel>(
    problem: &Problem<M>,
    axes: &GridAxes,
    values: &GridValues,
) {
    for (flat, &sse) in values.sse.iter().enumerate() {
        let at = values.indices(flat);
        let direct = problem.evaluate(&axes.theta(&at), problem.beta).0.sse;
        assert!(
            (sse - direct).abs() <= 1e-10 * problem.dd,
            "at {at:?}: grid {sse}, direct {direct}"
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The basins are the points no axis neighbour is lower than (on ties
    /// the smaller flat index is lower), best first: against that
    /// definition checked point by point, on grids of one to three axes
    /// whose values are drawn from a few levels (so ties are common) with
    /// some not finite.
    #[test]
    fn the_starts_are_the_grids_basins_best_first() {
        let mut rng = crate::synthetic::Noise::new(11);
        for trial in 0..300 {
            let dims = 1 + trial % 3;
            let lens: Vec<usize> = (0..dims)
                .map(|_| 1 + (rng.uniform() * 6.0) as usize)
                .collect();
            let total: usize = lens.iter().product();
            let sse: Vec<f64> = (0..total)
                .map(|_| match (rng.uniform() * 8.0) as usize {
                    0 => f64::NAN,
                    1 => f64::INFINITY,
                    level => level as f64,
                })
                .collect();
            let values = GridValues { lens, sse };
            let lower = |g: usize, f: usize| {
                let e = &values.sse;
                e[g] < e[f] || (e[g] == e[f] && g < f)
            };
            let mut want: Vec<(usize, f64)> = (0..total)
                .filter(|&f| values.sse[f].is_finite())
                .filter(|&f| {
                    let at = values.indices(f);
                    (0..dims).all(|axis| {
                        [-1i64, 1].iter().all(|&step| {
                            let i = at[axis] as i64 + step;
                            if i < 0 || i >= values.lens[axis] as i64 {
                                return true;
                            }
                            let mut moved = at.clone();
                            moved[axis] = i as usize;
                            let g = moved
                                .iter()
                                .zip(&values.lens)
                                .fold(0, |flat, (&i, &len)| flat * len + i);
                            !lower(g, f)
                        })
                    })
                })
                .map(|f| (f, values.sse[f]))
                .collect();
            want.sort_by(|p, q| p.1.total_cmp(&q.1).then(p.0.cmp(&q.0)));
            for most in [1, 3, 100] {
                let got = grid_starts(&values, most);
                let expected: Vec<(Vec<usize>, f64)> = want
                    .iter()
                    .take(most)
                    .map(|&(f, e)| (values.indices(f), e))
                    .collect();
                assert_eq!(got, expected, "trial {trial}, {values:?}");
            }
        }
    }
}
