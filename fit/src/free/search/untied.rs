//! The untied layered models' grid stage (σ′/T′ free beside σ/T): the
//! structure of [`super::quadratic`] with the surface and the subsurface
//! at slopes of their own. `S` depends on σ/T alone and the base `B` on
//! (σ′/T′, n) alone, so each is formed once per value of its own axes;
//! per (σ/T, σ′/T′, n) only the three cross sums `Σ w S B [1, g1, g2]`
//! remain, and every a of the axis is a 2×2 solve from the quadratic in
//! a, as for the tied models.

use super::objectives::objectives;
use super::{GridAxes, GridValues};
use crate::free::linear::Quadratic;
use crate::free::model::{LayeredModel, Packed};
use crate::free::problem::Problem;
use crate::free::sums::{dots, dots_many};
use crate::model::Param;
use crate::settings::precision::Precision;
use laminar_brdf_core::{f32x8, f64x4};
use rayon::prelude::*;

/// One (σ′/T′, n) column: the weighted base against `[1, g1, g2]`, and the
/// sums that do not involve `S`.
pub(crate) struct Column {
    /// `w B`, `w B g1`, `w B g2`.
    weighted: [Vec<f64>; 3],
    /// `Σ w B² g_i g_j` (`g0 = 1`).
    bb: [[f64; 3]; 3],
    /// `Σ w D B g_i`.
    db: [f64; 3],
}

/// The objective of an untied model's `problem` at every grid point of
/// `axes` (σ/T, σ′/T′, n, a in the table's order), the bases in
/// `precision`.
pub fn grid_values(
    problem: &Problem<LayeredModel>,
    axes: &GridAxes,
    precision: Precision,
) -> GridValues {
    let mut values = grid_values_many(&[problem], axes, precision);
    values.pop().expect("one set, one grid")
}

/// [`grid_values`] of each of `problems`, sets of one model on one
/// geometry (a material's channels): the surface terms and the bases are
/// the model's alone, so they are formed once for all; each set's sums
/// then as for one, so each set's values are the same bits as alone.
pub fn grid_values_many(
    problems: &[&Problem<LayeredModel>],
    axes: &GridAxes,
    precision: Precision,
) -> Vec<GridValues> {
    match precision {
        Precision::F64 => values::<f64x4>(problems, axes),
        Precision::F32 => values::<f32x8>(problems, axes),
    }
}

/// `x_k y_k` for each k.
fn times(x: &[f64], y: &[f64]) -> Vec<f64> {
    x.iter().zip(y).map(|(a, b)| a * b).collect()
}

impl Column {
    /// The column of base `b` for `problem`'s weights and data, `g` its
    /// factors ([`LayeredModel::factors`]).
    pub(crate) fn new(
        problem: &Problem<LayeredModel>,
        b: &[f64],
        [g1, g2]: &[Vec<f64>; 2],
    ) -> Self {
        let (w, wd) = (&problem.weight[..], &problem.weighted_data[..]);
        let (bg1, bg2) = (times(b, g1), times(b, g2));
        let wb = times(w, b);
        let (wbg1, wbg2) = (times(&wb, g1), times(&wb, g2));
        let [b00, b01, b02] = dots(b, [&wb, &wbg1, &wbg2]);
        let [b11, b12] = dots(&bg1, [&wbg1, &wbg2]);
        let [b22] = dots(&bg2, [&wbg2]);
        Column {
            bb: [[b00, b01, b02], [b01, b11, b12], [b02, b12, b22]],
            db: dots(wd, [b, &bg1, &bg2]),
            weighted: [wb, wbg1, wbg2],
        }
    }

    /// The quadratic in a of this column against the surface term `s`
    /// (its sums `[Σ w S², Σ w D S]`: [`surface_sums`]).
    pub(crate) fn quadratic(
        &self,
        problem: &Problem<LayeredModel>,
        s: &[f64],
        sums: [f64; 2],
    ) -> Quadratic<f64> {
        let [x, y, z] = &self.weighted;
        self.quadratic_of(problem, dots(s, [x, y, z]), sums)
    }

    /// [`Column::quadratic`] from the cross sums `sb = Σ w S B [1, g1, g2]`.
    fn quadratic_of(
        &self,
        problem: &Problem<LayeredModel>,
        sb: [f64; 3],
        [ss, ds]: [f64; 2],
    ) -> Quadratic<f64> {
        Quadratic {
            dd: problem.dd,
            ds,
            ss,
            db: self.db,
            sb,
            bb: self.bb,
        }
    }

    /// The cross sums `Σ w S B [1, g1, g2]` of this column against each of
    /// the surface terms `surfaces` (as [`Column::quadratic`] forms them,
    /// bit for bit), four surface terms per pass over the column.
    fn cross_sums(&self, surfaces: &[Vec<f64>]) -> Vec<[f64; 3]> {
        let [x, y, z] = &self.weighted;
        let ys = [&x[..], y, z];
        let (fours, rest) = surfaces.as_chunks::<4>();
        let mut out = Vec::with_capacity(surfaces.len());
        for four in fours {
            out.extend(dots_many([&four[0][..], &four[1], &four[2], &four[3]], ys));
        }
        out.extend(rest.iter().map(|s| dots(s, ys)));
        out
    }
}

/// `[Σ w S², Σ w D S]` of the surface term `s`.
pub(crate) fn surface_sums(problem: &Problem<LayeredModel>, s: &[f64]) -> [f64; 2] {
    let ws = times(&problem.weight, s);
    dots(s, [&ws, &problem.weighted_data])
}

/// Columns of one grid-stage task: each task writes its columns' values
/// into one segment of every σ/T's row of the grid.
const COLUMNS_PER_TASK: usize = 8;

fn values<L: Packed>(problems: &[&Problem<LayeredModel>], axes: &GridAxes) -> Vec<GridValues> {
    let model = &problems[0].model;
    let axis = |p: Param| axes.of(p).expect("an untied model's grid has this axis");
    let (slopes, subs, ns) = (axis(Param::Slope), axis(Param::SubSlope), axis(Param::N));
    let a_axis = axis(Param::A);
    let g = model.factors();
    let boundaries: Vec<_> = ns.par_iter().map(|&n| model.boundary::<L>(n)).collect();
    let bases: Vec<Vec<f64>> = (0..subs.len() * ns.len())
        .into_par_iter()
        .map(|c| {
            let (sub, n) = (subs[c / ns.len()], c % ns.len());
            model.base::<L>(sub, &boundaries[n])
        })
        .collect();
    let surfaces: Vec<Vec<f64>> = slopes.par_iter().map(|&s| model.surface(s)).collect();
    problems
        .iter()
        .map(|problem| {
            let columns: Vec<Column> = (bases.par_iter())
                .map(|b| Column::new(problem, b, &g))
                .collect();
            let sums: Vec<[f64; 2]> = surfaces.iter().map(|s| surface_sums(problem, s)).collect();
            // Column by column (its three vectors stay in the first-level
            // cache while every σ/T's surface term passes over them), each
            // column's values per σ/T then a, written in place: the grid's
            // order is σ/T, then the column, then a, so a block of columns
            // owns one segment of each σ/T's row.
            let a_len = a_axis.len();
            let mut sse = vec![0.0; surfaces.len() * columns.len() * a_len];
            let blocks = columns.len().div_ceil(COLUMNS_PER_TASK);
            let mut segments: Vec<Vec<&mut [f64]>> = (0..blocks)
                .map(|_| Vec::with_capacity(surfaces.len()))
                .collect();
            for row in sse.chunks_mut(columns.len() * a_len) {
                for (block, segment) in row.chunks_mut(COLUMNS_PER_TASK * a_len).enumerate() {
                    segments[block].push(segment);
                }
            }
            (segments.into_par_iter())
                .zip(columns.par_chunks(COLUMNS_PER_TASK))
                .for_each(|(mut rows, block)| {
                    for (j, column) in block.iter().enumerate() {
                        let cross = column.cross_sums(&surfaces);
                        for ((&sb, &sums), row) in cross.iter().zip(&sums).zip(&mut rows) {
                            objectives(
                                &column.quadratic_of(problem, sb, sums),
                                a_axis,
                                problem.beta,
                                &mut row[j * a_len..(j + 1) * a_len],
                            );
                        }
                    }
                });
            GridValues {
                lens: axes.lens(),
                sse,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coverage::{noisy_sets, NoiseModel};
    use crate::free::model::FreeModel;
    use crate::model::Model;
    use crate::objective::Objective;
    use crate::synthetic;

    /// Every grid value of an untied model is its objective evaluated
    /// directly at that point, in both precisions' bases, and the two
    /// slopes enter apart (swapping the axes changes the values).
    #[test]
    fn grid_values_are_the_objective_at_each_point() {
        let angles = synthetic::geometries();
        for model in [Model::Exp2, Model::Gauss2] {
            let scene = noisy_sets(
                &angles,
                model,
                Objective::Free,
                NoiseModel::Every(0.01),
                1,
                7,
            )
            .remove(0);
            let slope = (libm::log(0.02), libm::log(20.0));
            let bounds = vec![slope, slope, (1.0, 2.5), (0.0, 1.0)];
            let problem = Problem::<LayeredModel>::new(
                &scene,
                (model, None),
                (bounds.clone(), bounds.clone()),
                vec![(-7.0, 7.0), (-7.0, 7.0), (1.0, 10.0), (0.0, 1.0)],
                (0.0, 1.0),
            );
            let table = LayeredModel::new(model, &angles).table().clone();
            let axes = GridAxes {
                params: table.entries().to_vec(),
                axes: vec![
                    vec![0.05, 0.4, 3.0],
                    vec![0.1, 1.0],
                    vec![1.0, 1.5, 2.5],
                    vec![0.0, 0.3, 1.0],
                ],
            };
            let values = grid_values(&problem, &axes, Precision::F64);
            assert_eq!(values.sse.len(), 3 * 2 * 3 * 3);
            super::super::assert_grid_is_the_objective(&problem, &axes, &values);
            let single = grid_values(&problem, &axes, Precision::F32);
            for (s, d) in single.sse.iter().zip(&values.sse) {
                assert!(
                    (s - d).abs() <= 1e-4 * problem.dd,
                    "{model}: {s} against {d}"
                );
            }
            let swapped = GridAxes {
                axes: vec![
                    vec![0.1, 1.0],
                    vec![0.05, 0.4, 3.0],
                    axes.axes[2].clone(),
                    axes.axes[3].clone(),
                ],
                ..axes.clone()
            };
            let other = grid_values(&problem, &swapped, Precision::F64);
            assert_ne!(other.sse[..9], values.sse[..9]);
            // Sets on one geometry share the model's side: each set's
            // values are its own alone, bit for bit.
            let scenes = noisy_sets(
                &angles,
                model,
                Objective::Free,
                NoiseModel::Every(0.02),
                2,
                8,
            );
            let others: Vec<_> = (scenes.iter())
                .map(|scene| {
                    Problem::new(
                        scene,
                        (model, None),
                        (bounds.clone(), bounds.clone()),
                        problem.domain.clone(),
                        (0.0, 1.0),
                    )
                })
                .collect();
            let sets = [&problem, &others[0], &others[1]];
            for precision in [Precision::F64, Precision::F32] {
                let many = grid_values_many(&sets, &axes, precision);
                for (set, values) in sets.iter().zip(&many) {
                    assert_eq!(values, &grid_values(set, &axes, precision));
                }
                assert_ne!(many[1], many[2]);
            }
        }
    }
}
