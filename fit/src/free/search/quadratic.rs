//! The tied layered models' grid stage (the untied ones': [`super::untied`]): per (σ/T, n) the weighted inner
//! products of the data, the surface term `S` and the three coefficients
//! of `U` as a quadratic in a (`U = B0 + a B1 + a² B2`, `B0 = B`,
//! `B1 = −B (cos²θi + cos²θs)`, `B2 = B cos²θi cos²θs`) are formed once;
//! every a of the axis is then a 2×2 solve from polynomials in a, with no
//! pass over the measurements.

use super::corner::corner_start;
use super::objectives::objectives_in;
use super::{GridAxes, GridStage, GridValues};
use crate::free::boundary::BoundaryGroup;
use crate::free::linear::Quadratic;
use crate::free::model::{FreeModel, LayeredModel, Packed};
use crate::free::problem::Problem;
use crate::free::sums::{dots, total};
use crate::model::Param;
use crate::settings::precision::Precision;
use crate::simd;
use laminar_brdf_core::simd::{Kernel, Lane4};
use laminar_brdf_core::{f32x8, f64x4, Lane};
use rayon::prelude::*;

/// The layered objective of one set.
type Layered = Problem<LayeredModel>;

/// The model side of the layered grid stage: per σ/T the surface term and
/// `Σ w S²`, per (σ/T, n) the base `B` and the sums of the quadratic's
/// coefficients against each other and against `S`. It depends on the
/// geometry and the weights only, so sets on one geometry without
/// uncertainties share it ([`ModelSide::shareable`]); a set's own grid
/// values from it are bit for bit those of computing it for that set.
#[derive(Debug, Clone)]
pub struct ModelSide {
    /// Per σ/T value.
    rows: Vec<SlopeRow>,
    /// Per measurement: the factors turning B into B1 and B2.
    g: [Vec<f64>; 2],
    /// True when it holds one set's data's sums instead of the bases
    /// ([`ModelSide::for_one_set`]): it serves that set alone.
    one_set: bool,
}

#[derive(Debug, Clone)]
struct SlopeRow {
    s: Vec<f64>,
    ss: f64,
    /// Per n value.
    columns: Vec<ColumnSums>,
}

#[derive(Debug, Clone)]
struct ColumnSums {
    /// `B` (empty when the data's sums are kept instead, `db`).
    base: Vec<f64>,
    bb: [[f64; 3]; 3],
    sb: [f64; 3],
    /// `Σ w D B` against `[1, g1, g2]` of the one set the model side was
    /// formed for ([`ModelSide::for_one_set`]), as [`data_sums`] forms them.
    db: Option<[f64; 3]>,
}

impl ColumnSums {
    /// One column's base from its groups of four (`len` measurements) and
    /// its sums against the weights and the weighted surface term, in one
    /// pass. `coefficients` holds, per whole group of four measurements,
    /// `[w, g1, g2, g1², g1 g2, g2²]` (the same for every σ/T) and `ws` the
    /// weighted surface term `w S` (this row's), each with the whole groups
    /// in `.0` and the measurements of the last, partial group in `.1`.
    /// Each sum is, bit for bit, [`dots`] of `w B B` (or `w S B`) against
    /// the factor (and against ones): the same four partial sums per
    /// product, in measurement order, without the K-vectors. With one
    /// set's weighted data `wd` (split the same way), its sums `db` are
    /// formed in the same pass, bit for bit [`data_sums`]'s, and `B` is not
    /// kept.
    #[inline(always)]
    fn new<L: Lane4>(
        groups: &impl Bases,
        len: usize,
        coefficients: (&[[f64x4; 6]], &[[f64; 6]]),
        ws: (&[[f64; 4]], &[f64]),
        wd: Option<(&[[f64; 4]], &[f64])>,
    ) -> Self {
        let mut base = Vec::with_capacity(if wd.is_none() {
            len.next_multiple_of(4)
        } else {
            0
        });
        // Σ w B² against [1, g1, g2, g11, g12, g22]; Σ w S B against [1, g1, g2].
        let mut bb = [L::zero(); 6];
        let mut sb = [L::zero(); 3];
        let mut db = [L::zero(); 3];
        // Indexed, not zipped: an iterator adapter yielding lanes might not
        // be inlined into the kernel.
        let whole = coefficients.0.iter().zip(ws.0).enumerate();
        match wd {
            None => {
                for (i, (c, ws)) in whole {
                    let b = groups.group::<L>(i);
                    base.extend_from_slice(&b.to_array());
                    accumulate(&mut bb, &mut sb, (b, L::from_array(*ws)), &loaded(c));
                }
            }
            Some((wd, _)) => {
                for ((i, (c, ws)), wd) in whole.zip(wd) {
                    let (b, c) = (groups.group::<L>(i), loaded(c));
                    accumulate(&mut bb, &mut sb, (b, L::from_array(*ws)), &c);
                    accumulate_data(&mut db, (b, L::from_array(*wd)), [c[1], c[2]]);
                }
            }
        }
        // The last, partial group's measurements.
        let body = len - coefficients.1.len();
        let rest = if body < len {
            groups.group::<L>(coefficients.0.len()).to_array()
        } else {
            [0.0; 4]
        };
        let rest = &rest[..len - body];
        let mut bb = [0, 1, 2, 3, 4, 5].map(|i| total(bb[i]));
        let mut sb = [0, 1, 2].map(|i| total(sb[i]));
        let mut db = [0, 1, 2].map(|i| total(db[i]));
        for ((&b, c), &ws) in rest.iter().zip(coefficients.1).zip(ws.1) {
            accumulate(&mut bb, &mut sb, (b, ws), c);
        }
        let db = wd.map(|(_, wd_tail)| {
            for ((&b, c), &wd) in rest.iter().zip(coefficients.1).zip(wd_tail) {
                accumulate_data(&mut db, (b, wd), [c[1], c[2]]);
            }
            db
        });
        if db.is_none() {
            base.extend_from_slice(rest);
        }
        let [b00, b01, b02, b11, b12, b22] = bb;
        Self {
            base,
            bb: [[b00, b01, b02], [b01, b11, b12], [b02, b12, b22]],
            sb,
            db,
        }
    }
}

/// A column's base `B`, a group of four measurements at a time, in a
/// kernel's lanes ([`Packed::bases`]).
pub trait Bases {
    /// The `i`-th group of four.
    fn group<L: Lane4>(&self, i: usize) -> L;
}

/// Six stored groups in a kernel's lanes.
#[inline(always)]
fn loaded<L: Lane4>(c: &[f64x4; 6]) -> [L; 6] {
    [
        L::load(c[0]),
        L::load(c[1]),
        L::load(c[2]),
        L::load(c[3]),
        L::load(c[4]),
        L::load(c[5]),
    ]
}

/// One term of [`ColumnSums::new`]'s sums: `w B²` times each of `[1, g1,
/// g2, g1², g1 g2, g2²]` into `bb`, `w S B` times each of `[1, g1, g2]`
/// into `sb`, from the base `b`, the weighted surface term `ws` and the
/// coefficients `[w, g1, g2, g1², g1 g2, g2²]`.
#[inline(always)]
fn accumulate<L: Lane>(bb: &mut [L; 6], sb: &mut [L; 3], (b, ws): (L, L), [w, f @ ..]: &[L; 6]) {
    let wbb = *w * b * b;
    let wsb = ws * b;
    bb[0] = bb[0] + wbb;
    for (acc, f) in bb[1..].iter_mut().zip(f) {
        *acc = *acc + wbb * *f;
    }
    sb[0] = sb[0] + wsb;
    sb[1] = sb[1] + wsb * f[0];
    sb[2] = sb[2] + wsb * f[1];
}

/// One term of a set's data's sums: `w D B` times each of `[1, g1, g2]`
/// into `db`, from the base `b`, the weighted datum `wd` and the factors
/// `g1`, `g2` ([`data_sums`], and [`ColumnSums::new`] for one set).
#[inline(always)]
fn accumulate_data<L: Lane>(db: &mut [L; 3], (b, wd): (L, L), [g1, g2]: [L; 2]) {
    let t = b * wd;
    db[0] = db[0] + t;
    db[1] = db[1] + t * g1;
    db[2] = db[2] + t * g2;
}

/// `vectors` interleaved: per whole group of four measurements, the group
/// of each vector; then, per measurement of the last, partial group, its
/// value in each.
fn interleave<const N: usize>(vectors: [&[f64]; N]) -> (Vec<[f64x4; N]>, Vec<[f64; N]>) {
    let len = vectors.first().map_or(0, |v| v.len());
    let body = len / 4;
    let groups = (0..body)
        .map(|g| vectors.map(|v| f64x4::from_f64_lanes(|i| v[4 * g + i])))
        .collect();
    let tail = (4 * body..len).map(|k| vectors.map(|v| v[k])).collect();
    (groups, tail)
}

impl ModelSide {
    /// The model side of `problem` (a layered model) on `axes`, its bases
    /// in `precision`.
    pub fn new(problem: &Layered, axes: &GridAxes, precision: Precision) -> Self {
        Self::formed(problem, axes, precision, false)
    }

    /// [`ModelSide::new`] for `problem`'s set alone: each column's data's
    /// sums formed in its pass, bit for bit those of a shared model side,
    /// and no base kept (one pass over the measurements per column where
    /// sharing takes two).
    fn for_one_set(problem: &Layered, axes: &GridAxes, precision: Precision) -> Self {
        Self::formed(problem, axes, precision, true)
    }

    fn formed(problem: &Layered, axes: &GridAxes, precision: Precision, one_set: bool) -> Self {
        // Per measurement, the factors that turn B into B1 and B2, and the
        // products of the quadratic's coefficients: B_i B_j = B² g_ij.
        let [g1, g2] = problem.model.factors();
        let g11: Vec<f64> = g1.iter().map(|g| g * g).collect();
        let g12: Vec<f64> = g1.iter().zip(&g2).map(|(a, b)| a * b).collect();
        let g22: Vec<f64> = g2.iter().map(|g| g * g).collect();
        let coefficients = [&g1[..], &g2, &g11, &g12, &g22];
        let rows = match precision {
            Precision::F64 => Self::rows::<f64x4>(problem, axes, coefficients, one_set),
            Precision::F32 => Self::rows::<f32x8>(problem, axes, coefficients, one_set),
        };
        Self {
            rows,
            g: [g1, g2],
            one_set,
        }
    }

    /// The rows of [`ModelSide::new`], the bases in `L`'s lanes; `g` the
    /// factors `[g1, g2, g1², g1 g2, g2²]` of each measurement; with
    /// `one_set`, `problem`'s data's sums in place of the bases.
    fn rows<L: Packed>(
        problem: &Layered,
        axes: &GridAxes,
        g: [&[f64]; 5],
        one_set: bool,
    ) -> Vec<SlopeRow> {
        let model = &problem.model;
        let k = problem.data.len();
        let (slopes, ns) = (slope_axis(axes), n_axis(axes));
        let boundaries: Vec<Vec<BoundaryGroup<L>>> =
            ns.par_iter().map(|&n| model.boundary(n)).collect();
        let w = &problem.weight;
        let [g1, g2, g11, g12, g22] = g;
        // What every σ/T row shares, interleaved once.
        let (coefficients, tail) = interleave([w, g1, g2, g11, g12, g22]);
        let wd = one_set.then(|| problem.weighted_data.as_chunks::<4>());
        slopes
            .par_iter()
            .map(|&slope| {
                let s = model.surface(slope);
                let ws: Vec<f64> = w.iter().zip(&s).map(|(w, s)| w * s).collect();
                let [ss] = dots(&s, [&ws]);
                let columns = L::run(ColumnsPass {
                    model,
                    slope,
                    boundaries: &boundaries,
                    len: k,
                    coefficients: (&coefficients, &tail),
                    ws: ws.as_chunks::<4>(),
                    wd,
                });
                SlopeRow { s, ss, columns }
            })
            .collect()
    }
}

/// The layered models' grid stage: the model side per (σ/T, n), then a
/// closed-form solve per a.
impl GridStage for LayeredModel {
    type Shared = ModelSide;

    fn grid_values(problem: &Layered, axes: &GridAxes, precision: Precision) -> GridValues {
        if problem.model.model().is_untied() {
            return super::untied::grid_values(problem, axes, precision);
        }
        grid_values(problem, axes, precision)
    }

    /// The tied models' model side; the untied models share none.
    fn shared(problem: &Layered, axes: &GridAxes, precision: Precision) -> Option<ModelSide> {
        let tied = !problem.model.model().is_untied();
        tied.then(|| ModelSide::new(problem, axes, precision))
    }

    fn grid_values_shared(
        problems: &[&Layered],
        axes: &GridAxes,
        shared: &ModelSide,
    ) -> Vec<GridValues> {
        grid_values_many(problems, axes, shared)
    }

    fn corner_start(problem: &Layered, axes: &GridAxes, values: &GridValues) -> Option<Vec<f64>> {
        corner_start(problem, axes, values)
    }
}

/// The objective at every grid point of `axes` (σ/T, n and, for the
/// absorptive models, a, in the layered table's order), the bases in
/// `precision`: one set's model side, its data's sums formed in the same
/// pass.
pub fn grid_values(problem: &Layered, axes: &GridAxes, precision: Precision) -> GridValues {
    let side = ModelSide::for_one_set(problem, axes, precision);
    let mut values = grid_values_many(&[problem], axes, &side);
    values.pop().expect("one set, one grid")
}

/// The σ/T axis of a layered model's grid.
fn slope_axis(axes: &GridAxes) -> &[f64] {
    axes.of(Param::Slope)
        .expect("a layered model's grid has a σ/T axis")
}

/// The n axis of a layered model's grid.
fn n_axis(axes: &GridAxes) -> &[f64] {
    axes.of(Param::N)
        .expect("a layered model's grid has an n axis")
}

/// Measurements per block of the data's sums ([`data_sums`]): a block of
/// `B` and of its factors (6 KB) stays in the first-level cache while each
/// set of a pass runs over it.
const BLOCK: usize = 256;

/// `[Σ w D B, Σ w D B g1, Σ w D B g2]` of each set's weighted data `wds`
/// against one column `B` with the factors `g` of B1 and B2, in blocks of
/// [`BLOCK`] measurements. Per set, four partial sums per product over
/// groups of four in measurement order, combined as [`super::sums::dots`]
/// does: the same bits whatever the number of sets.
#[inline(always)]
fn data_sums<L: Lane4>(
    base: &[f64],
    [g1, g2]: [&[f64]; 2],
    wds: &[&[f64]],
    acc: &mut [[L; 3]],
    out: &mut [[f64; 3]],
) {
    let len = base.len();
    let (b4, _) = base.as_chunks::<4>();
    let (x1, _) = g1[..len].as_chunks::<4>();
    let (x2, _) = g2[..len].as_chunks::<4>();
    for acc in acc.iter_mut() {
        *acc = [L::zero(); 3];
    }
    for start in (0..b4.len()).step_by(BLOCK / 4) {
        let end = (start + BLOCK / 4).min(b4.len());
        let (b, x1, x2) = (&b4[start..end], &x1[start..end], &x2[start..end]);
        for (acc, wd) in acc.iter_mut().zip(wds) {
            let w = &wd[..len].as_chunks::<4>().0[start..end];
            for i in 0..b.len() {
                let (x1, x2) = (L::from_array(x1[i]), L::from_array(x2[i]));
                accumulate_data(acc, (L::from_array(b[i]), L::from_array(w[i])), [x1, x2]);
            }
        }
    }
    let body = 4 * b4.len();
    for ((out, acc), wd) in out.iter_mut().zip(acc.iter()).zip(wds) {
        *out = [total(acc[0]), total(acc[1]), total(acc[2])];
        for k in body..len {
            accumulate_data(out, (base[k], wd[k]), [g1[k], g2[k]]);
        }
    }
}

/// [`grid_values`] of a layered model for each of `problems` from the
/// model side they share (computed for one set, or shared:
/// [`ModelSide::shareable`]), in one pass over it; per grid point only the
/// data's sums remain, then each a is a closed-form solve. Each set's
/// values are bit for bit those of its own pass. A model side formed for
/// one set ([`ModelSide::for_one_set`]) serves that set alone.
pub fn grid_values_many(
    problems: &[&Layered],
    axes: &GridAxes,
    model: &ModelSide,
) -> Vec<GridValues> {
    assert!(
        !model.one_set || problems.len() == 1,
        "a model side formed for one set serves that set alone"
    );
    let lens = axes.lens();
    // Ragheb–Hancock's a is 0.
    let a_axis = axes.of(Param::A).map_or_else(|| vec![0.0], <[f64]>::to_vec);
    let g = [&model.g[0][..], &model.g[1][..]];
    let wds: Vec<&[f64]> = problems.iter().map(|p| &p.weighted_data[..]).collect();
    let row_len = n_axis(axes).len() * a_axis.len();
    let mut sse = vec![vec![0.0; slope_axis(axes).len() * row_len]; problems.len()];
    // Per σ/T row, each set's objectives along (n, a).
    let mut rows: Vec<Vec<&mut [f64]>> = model.rows.iter().map(|_| Vec::new()).collect();
    for set in &mut sse {
        for (row, out) in rows.iter_mut().zip(set.chunks_mut(row_len)) {
            row.push(out);
        }
    }
    rows.into_par_iter()
        .zip(&model.rows)
        .for_each(|(out, row)| {
            simd::run(RowValues {
                problems,
                row,
                g,
                wds: &wds,
                a_axis: &a_axis,
                out,
            });
        });
    sse.into_iter()
        .map(|sse| GridValues {
            lens: lens.clone(),
            sse,
        })
        .collect()
}

/// The columns of one σ/T row of the model side ([`ColumnSums::new`] at
/// each n), the bases packed in `P`'s lanes.
struct ColumnsPass<'a, P: Lane> {
    model: &'a LayeredModel,
    slope: f64,
    /// The boundary at each n.
    boundaries: &'a [Vec<BoundaryGroup<P>>],
    len: usize,
    coefficients: (&'a [[f64x4; 6]], &'a [[f64; 6]]),
    ws: (&'a [[f64; 4]], &'a [f64]),
    wd: Option<(&'a [[f64; 4]], &'a [f64])>,
}

impl<P: Packed> Kernel for ColumnsPass<'_, P> {
    type Output = Vec<ColumnSums>;

    #[inline(always)]
    fn run<L: Lane4>(self) -> Vec<ColumnSums> {
        let mut columns = Vec::with_capacity(self.boundaries.len());
        for b in self.boundaries {
            let groups = P::bases(self.model, self.slope, b);
            columns.push(ColumnSums::new::<L>(
                &groups,
                self.len,
                self.coefficients,
                self.ws,
                self.wd,
            ));
        }
        columns
    }
}

/// The pass of [`grid_values_many`] over one σ/T row: each set's
/// objectives along (n, a).
struct RowValues<'a, 'o> {
    problems: &'a [&'a Layered],
    row: &'a SlopeRow,
    /// The factors of B1 and B2.
    g: [&'a [f64]; 2],
    /// Each set's weighted data.
    wds: &'a [&'a [f64]],
    a_axis: &'a [f64],
    /// Each set's objectives along this row.
    out: Vec<&'o mut [f64]>,
}

impl Kernel for RowValues<'_, '_> {
    type Output = ();

    #[inline(always)]
    fn run<L: Lane4>(self) {
        let Self {
            problems,
            row,
            g,
            wds,
            a_axis,
            mut out,
        } = self;
        let ds: Vec<f64> = wds.iter().map(|wd| dots(&row.s, [wd])[0]).collect();
        let mut acc = vec![[L::zero(); 3]; problems.len()];
        let mut sums = vec![[0.0; 3]; problems.len()];
        for (n, c) in row.columns.iter().enumerate() {
            match c.db {
                Some(db) => sums[0] = db,
                None => data_sums(&c.base, g, wds, &mut acc, &mut sums),
            }
            let at = n * a_axis.len();
            for (set, problem) in problems.iter().enumerate() {
                let q = Quadratic {
                    dd: problem.dd,
                    ds: ds[set],
                    ss: row.ss,
                    db: sums[set],
                    sb: c.sb,
                    bb: c.bb,
                };
                let out = &mut out[set][at..at + a_axis.len()];
                objectives_in::<L>(&q, a_axis, problem.beta, out);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coverage::{noisy_sets, NoiseModel};
    use crate::free::layout::Layout;
    use crate::grid::Grid;
    use crate::model::Model;
    use crate::objective::Objective;
    use crate::synthetic;

    /// Several sets' grids from one pass over the model side are, bit for
    /// bit, each set's grid alone, over several blocks of measurements and a
    /// tail shorter than four.
    #[test]
    fn one_pass_over_several_sets_gives_each_sets_own_grid() {
        let mut angles = synthetic::geometries();
        angles.extend(synthetic::geometries());
        angles.pop();
        assert!(angles.len() > BLOCK && !angles.len().is_multiple_of(4));
        let scenes = noisy_sets(
            &angles,
            Model::Exp,
            Objective::Free,
            NoiseModel::Every(0.01),
            3,
            1,
        );
        let bounds = vec![(libm::log(0.02), libm::log(20.0)), (1.0, 2.5), (0.0, 1.0)];
        let problems: Vec<Layered> = scenes
            .iter()
            .map(|scene| {
                Problem::new(
                    scene,
                    (Model::Exp, None),
                    (bounds.clone(), bounds.clone()),
                    vec![(-7.0, 7.0), (1.0, 10.0), (0.0, 1.0)],
                    (0.0, 1.0),
                )
            })
            .collect();
        let table = LayeredModel::new(Model::Exp, &angles).table().clone();
        let axes = GridAxes {
            params: table.entries().to_vec(),
            axes: vec![
                vec![0.05, 0.4, 3.0],
                vec![1.0, 1.5, 2.5],
                vec![0.0, 0.3, 1.0],
            ],
        };
        let refs: Vec<&Layered> = problems.iter().collect();
        // One set's own grid stage forms its data's sums in the model
        // side's pass, a batch's in a pass of their own: the same bits.
        for precision in Precision::ALL {
            let side = ModelSide::new(&problems[0], &axes, precision);
            let together = grid_values_many(&refs, &axes, &side);
            for (problem, values) in problems.iter().zip(&together) {
                assert_eq!(values, &grid_values(problem, &axes, precision));
                assert!(values.sse.iter().all(|e| e.is_finite()));
            }
        }
        let side = ModelSide::new(&problems[0], &axes, Precision::F64);
        let together = grid_values_many(&refs, &axes, &side);
        assert_ne!(together[0], together[1]);
        // And each grid value is the objective evaluated directly there,
        // from the residuals (the moments form cancels digits of Σ w D²).
        for (problem, values) in problems.iter().zip(&together) {
            super::super::assert_grid_is_the_objective(problem, &axes, values);
        }
    }

    /// The grid stage in single precision ([`Precision::F32`]): every base
    /// `B` of at least 10⁻³ of its column's largest within 8 `f32` ulps of
    /// the `f64` one (exponential) or 20 (Gaussian: its tail's `exp`
    /// amplifies the rounding of its argument), every grid value within
    /// 2·10⁻⁷ of `Σ w D²` of the `f64` one; on the default grid, with a last
    /// group of eight that is partly padding.
    #[test]
    fn single_precision_grid_values_are_the_f64_ones_to_its_rounding() {
        let mut angles = synthetic::geometries();
        angles.truncate(angles.len() / 8 * 8 - 3);
        for model in [Model::Exp, Model::Gauss] {
            let layout = Layout::new(&LayeredModel::new(model, &angles), &Grid::user());
            let scene = &noisy_sets(
                &angles,
                model,
                Objective::Free,
                NoiseModel::Every(0.01),
                1,
                3,
            )[0];
            let problem = Layered::new(
                scene,
                (model, None),
                (layout.bounds.clone(), layout.reported.clone()),
                layout.domain.clone(),
                layout.beta,
            );
            let [wide, narrow] =
                [Precision::F64, Precision::F32].map(|p| ModelSide::new(&problem, &layout.axes, p));
            let mut worst_base: f64 = 0.0;
            for (a, b) in wide.rows.iter().zip(&narrow.rows) {
                for (a, b) in a.columns.iter().zip(&b.columns) {
                    assert_eq!(a.base.len(), b.base.len());
                    let top = a.base.iter().fold(0.0, |m: f64, x| m.max(*x));
                    for (x, y) in a.base.iter().zip(&b.base) {
                        if *x > 1e-3 * top {
                            worst_base = worst_base.max((x - y).abs() / x);
                        }
                    }
                }
            }
            let refs = [&problem];
            let [wide, narrow] =
                [wide, narrow].map(|side| grid_values_many(&refs, &layout.axes, &side).remove(0));
            let worst_value = wide
                .sse
                .iter()
                .zip(&narrow.sse)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max)
                / problem.dd;
            // Measured: 6.6 and 17.6 f32 ulps; 9.6e-8 and 5.2e-8 of Σ w D².
            let ulps = worst_base / f64::from(f32::EPSILON);
            let most = if model == Model::Exp { 8.0 } else { 20.0 };
            assert!(ulps <= most, "{model}: a base {ulps} f32 ulps off");
            assert!(
                worst_value <= 2e-7,
                "{model}: a grid value {worst_value:e} of Σ w D² off"
            );
        }
    }
}
