//! The grid stage of the free-amplitude fit: the objective at every grid
//! point of the nonlinear parameters, with the linear part (β and the
//! amplitude) in closed form at each, and the grid's basins as the starts
//! of the refinement.
//!
//! Layered models: per (σ/T, n) the weighted inner products of the data,
//! the surface term `S` and the three coefficients of `U` as a quadratic in
//! a (`U = B0 + a B1 + a² B2`, `B0 = B`, `B1 = −B (cos²θi + cos²θs)`,
//! `B2 = B cos²θi cos²θs`) are formed once; every a of the axis is then a
//! 2×2 solve from polynomials in a, with no pass over the measurements.

use super::basis::Packed;
use super::boundary::BoundaryGroup;
use super::linear::Quadratic;
use super::problem::Problem;
use super::sums::{dots, total};
use crate::scene::Scene;
use laminar_core::{f32x8, f64x4, Lane};
use rayon::prelude::*;

/// The grid axes of the nonlinear parameters, in the model's values (σ/T,
/// not its logarithm).
#[derive(Debug, Clone, PartialEq)]
pub struct GridAxes {
    /// One axis per nonlinear parameter.
    pub axes: Vec<Vec<f64>>,
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
}

/// The objective at every a of `a_axis` from one (σ/T, n)'s quadratic,
/// four at a time (the last group padded with its last a): bit for bit
/// one at a time, as the core's `f64x4` is its `f64` lane by lane.
fn objectives(q: &Quadratic<f64>, a_axis: &[f64], beta: (f64, f64), out: &mut [f64]) {
    for (group, out) in a_axis.chunks(4).zip(out.chunks_mut(4)) {
        let a = f64x4::from_f64_lanes(|i| group[i.min(group.len() - 1)]);
        let sse = q.moments(a).solve(beta).sse.to_array();
        out.copy_from_slice(&sse[..group.len()]);
    }
}

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
    fn new(
        groups: impl Iterator<Item = f64x4>,
        len: usize,
        coefficients: (&[[f64x4; 6]], &[[f64; 6]]),
        ws: (&[[f64; 4]], &[f64]),
        wd: Option<(&[[f64; 4]], &[f64])>,
    ) -> Self {
        let mut groups = groups;
        let mut base = Vec::with_capacity(if wd.is_none() {
            len.next_multiple_of(4)
        } else {
            0
        });
        // Σ w B² against [1, g1, g2, g11, g12, g22]; Σ w S B against [1, g1, g2].
        let mut bb = [f64x4::ZERO; 6];
        let mut sb = [f64x4::ZERO; 3];
        let mut db = [f64x4::ZERO; 3];
        // The coefficients lead the zip, so that it stops before taking the
        // last, partial group from `groups`.
        let whole = coefficients.0.iter().zip(ws.0).zip(groups.by_ref());
        match wd {
            None => {
                for ((c, ws), b) in whole {
                    base.extend_from_slice(&b.to_array());
                    accumulate(&mut bb, &mut sb, (b, f64x4::from(*ws)), c);
                }
            }
            Some((wd, _)) => {
                for (((c, ws), b), wd) in whole.zip(wd) {
                    accumulate(&mut bb, &mut sb, (b, f64x4::from(*ws)), c);
                    accumulate_data(&mut db, (b, f64x4::from(*wd)), [c[1], c[2]]);
                }
            }
        }
        // The last, partial group's measurements.
        let body = len - coefficients.1.len();
        let mut rest = [0.0; 4];
        for (r, b) in rest
            .iter_mut()
            .zip(groups.flat_map(|b| b.to_array()).take(len - body))
        {
            *r = b;
        }
        let rest = &rest[..len - body];
        let mut bb = bb.map(total);
        let mut sb = sb.map(total);
        let mut db = db.map(total);
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

/// One term of [`ColumnSums::new`]'s sums: `w B²` times each of `[1, g1,
/// g2, g1², g1 g2, g2²]` into `bb`, `w S B` times each of `[1, g1, g2]`
/// into `sb`, from the base `b`, the weighted surface term `ws` and the
/// coefficients `[w, g1, g2, g1², g1 g2, g2²]`.
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

/// The arithmetic of the grid stage's model side: each column's base `B`
/// (eqs. 3–7) at every grid point of σ/T and n. Its sums, the data's and
/// every later stage run in `f64` either way.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Precision {
    /// `f64x4` lanes (the default): the grid values are the objective
    /// evaluated in `f64` at each grid point.
    #[default]
    F64,
    /// `f32x8` lanes (the core's single-precision path, bitwise its scalar
    /// `f32` on every target), widened exactly to `f64` for the sums: each
    /// `B` within a few `f32` ulps, so a grid value moves by about 10⁻⁷ of
    /// `Σ w D²`, which can change the grid's best point only among
    /// near-ties; the refinement then runs in `f64` from the grid's basins
    /// (the measured differences: docs/speed.md).
    F32,
}

impl Precision {
    /// Both, the default first.
    pub const ALL: [Precision; 2] = [Self::F64, Self::F32];
}

impl std::fmt::Display for Precision {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::F64 => "f64",
            Self::F32 => "f32",
        })
    }
}

impl std::str::FromStr for Precision {
    type Err = crate::error::UnknownName;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        crate::error::find_named("precision", &Self::ALL, |p| p.to_string(), s)
    }
}

impl ModelSide {
    /// The model side of `problem` (a layered model) on `axes`, its bases
    /// in `precision`.
    pub fn new(problem: &Problem, axes: &GridAxes, precision: Precision) -> Self {
        Self::formed(problem, axes, precision, false)
    }

    /// [`ModelSide::new`] for `problem`'s set alone: each column's data's
    /// sums formed in its pass, bit for bit those of a shared model side,
    /// and no base kept (one pass over the measurements per column where
    /// sharing takes two).
    fn for_one_set(problem: &Problem, axes: &GridAxes, precision: Precision) -> Self {
        Self::formed(problem, axes, precision, true)
    }

    fn formed(problem: &Problem, axes: &GridAxes, precision: Precision, one_set: bool) -> Self {
        let basis = &problem.basis;
        let (ci, cs) = basis.cosines();
        let k = problem.data.len();
        // Per measurement, the factors that turn B into B1 and B2, and the
        // products of the quadratic's coefficients: B_i B_j = B² g_ij.
        let g1: Vec<f64> = (0..k).map(|i| -(ci[i] + cs[i])).collect();
        let g2: Vec<f64> = (0..k).map(|i| ci[i] * cs[i]).collect();
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
        problem: &Problem,
        axes: &GridAxes,
        g: [&[f64]; 5],
        one_set: bool,
    ) -> Vec<SlopeRow> {
        let basis = &problem.basis;
        let k = problem.data.len();
        let boundaries: Vec<Vec<BoundaryGroup<L>>> = axes.axes[1]
            .par_iter()
            .map(|&n| basis.boundary(n))
            .collect();
        let w = &problem.weight;
        let [g1, g2, g11, g12, g22] = g;
        // What every σ/T row shares, interleaved once.
        let (coefficients, tail) = interleave([w, g1, g2, g11, g12, g22]);
        axes.axes[0]
            .par_iter()
            .map(|&slope| {
                let s = basis.surface(slope);
                let ws: Vec<f64> = w.iter().zip(&s).map(|(w, s)| w * s).collect();
                let [ss] = dots(&s, [&ws]);
                let ws_groups = ws.as_chunks::<4>();
                let columns = boundaries
                    .iter()
                    .map(|b| {
                        let groups = L::widened(basis.base_groups(slope, b));
                        let wd = one_set.then(|| problem.weighted_data.as_chunks::<4>());
                        ColumnSums::new(groups, k, (&coefficients, &tail), ws_groups, wd)
                    })
                    .collect();
                SlopeRow { s, ss, columns }
            })
            .collect()
    }

    /// True when `problem`'s model side serves `scene` (on its geometry):
    /// a layered model, and no uncertainties (weights 1).
    pub fn shareable(problem: &Problem, scene: &Scene) -> bool {
        problem.basis.has_balance() && !problem.weighted && scene.sigma().is_none()
    }
}

/// The objective at every grid point of `axes` (layered: σ/T, n and, for
/// the absorptive models, a, their bases in `precision`; baselines: their
/// two parameters, in `f64`).
pub fn grid_values(problem: &Problem, axes: &GridAxes, precision: Precision) -> GridValues {
    if problem.basis.has_balance() {
        let side = ModelSide::for_one_set(problem, axes, precision);
        let mut values = grid_values_many(&[problem], axes, &side);
        values.pop().expect("one set, one grid")
    } else {
        let lens: Vec<usize> = axes.axes.iter().map(Vec::len).collect();
        let (outer, inner) = (&axes.axes[0], &axes.axes[1]);
        let rows: Vec<Vec<f64>> = outer
            .par_iter()
            .map(|&x| {
                inner
                    .iter()
                    .map(|&y| {
                        let columns = problem.basis.columns(&[x, y]);
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
}

/// Measurements per block of the data's sums ([`data_sums`]): a block of
/// `B` and of its factors (6 KB) stays in the first-level cache while each
/// set of a pass runs over it.
const BLOCK: usize = 256;

/// Sets whose data's sums one pass over the model side forms
/// ([`grid_values_many`]): the model side (K × 440 values with the default
/// grid, 80 MB at K = 22,801) is read from memory once per this many sets.
pub const SETS_PER_PASS: usize = 8;

/// `[Σ w D B, Σ w D B g1, Σ w D B g2]` of each set's weighted data `wds`
/// against one column `B` with the factors `g` of B1 and B2, in blocks of
/// [`BLOCK`] measurements. Per set, four partial sums per product over
/// groups of four in measurement order, combined as [`super::sums::dots`]
/// does: the same bits whatever the number of sets.
fn data_sums(
    base: &[f64],
    [g1, g2]: [&[f64]; 2],
    wds: &[&[f64]],
    acc: &mut [[f64x4; 3]],
    out: &mut [[f64; 3]],
) {
    let len = base.len();
    let (b4, _) = base.as_chunks::<4>();
    let (x1, _) = g1[..len].as_chunks::<4>();
    let (x2, _) = g2[..len].as_chunks::<4>();
    acc.fill([f64x4::ZERO; 3]);
    for start in (0..b4.len()).step_by(BLOCK / 4) {
        let end = (start + BLOCK / 4).min(b4.len());
        let (b, x1, x2) = (&b4[start..end], &x1[start..end], &x2[start..end]);
        for (acc, wd) in acc.iter_mut().zip(wds) {
            let w = &wd[..len].as_chunks::<4>().0[start..end];
            for i in 0..b.len() {
                let (x1, x2) = (f64x4::from(x1[i]), f64x4::from(x2[i]));
                accumulate_data(acc, (f64x4::from(b[i]), f64x4::from(w[i])), [x1, x2]);
            }
        }
    }
    let body = 4 * b4.len();
    for ((out, acc), wd) in out.iter_mut().zip(acc.iter()).zip(wds) {
        *out = acc.map(total);
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
    problems: &[&Problem],
    axes: &GridAxes,
    model: &ModelSide,
) -> Vec<GridValues> {
    assert!(
        !model.one_set || problems.len() == 1,
        "a model side formed for one set serves that set alone"
    );
    let lens: Vec<usize> = axes.axes.iter().map(Vec::len).collect();
    let a_axis: Vec<f64> = axes.axes.get(2).cloned().unwrap_or_else(|| vec![0.0]);
    let g = [&model.g[0][..], &model.g[1][..]];
    let wds: Vec<&[f64]> = problems.iter().map(|p| &p.weighted_data[..]).collect();
    let row_len = lens[1] * a_axis.len();
    let mut sse = vec![vec![0.0; lens[0] * row_len]; problems.len()];
    // Per σ/T row, each set's objectives along (n, a).
    let mut rows: Vec<Vec<&mut [f64]>> = model.rows.iter().map(|_| Vec::new()).collect();
    for set in &mut sse {
        for (row, out) in rows.iter_mut().zip(set.chunks_mut(row_len)) {
            row.push(out);
        }
    }
    rows.into_par_iter()
        .zip(&model.rows)
        .for_each(|(mut out, row)| {
            let ds: Vec<f64> = wds.iter().map(|wd| dots(&row.s, [wd])[0]).collect();
            let mut acc = vec![[f64x4::ZERO; 3]; problems.len()];
            let mut sums = vec![[0.0; 3]; problems.len()];
            for (n, c) in row.columns.iter().enumerate() {
                match c.db {
                    Some(db) => sums[0] = db,
                    None => data_sums(&c.base, g, &wds, &mut acc, &mut sums),
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
                    objectives(
                        &q,
                        &a_axis,
                        problem.beta,
                        &mut out[set][at..at + a_axis.len()],
                    );
                }
            }
        });
    sse.into_iter()
        .map(|sse| GridValues {
            lens: lens.clone(),
            sse,
        })
        .collect()
}

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coverage::{noisy_sets, NoiseModel};
    use crate::model::Model;
    use crate::objective::Objective;
    use crate::synthetic;

    /// Several sets' grids from one pass over the model side are, bit for
    /// bit, each set's grid alone, over several blocks of measurements and a
    /// tail shorter than four.
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
        let problems: Vec<Problem> = scenes
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
        let axes = GridAxes {
            axes: vec![
                vec![0.05, 0.4, 3.0],
                vec![1.0, 1.5, 2.5],
                vec![0.0, 0.3, 1.0],
            ],
        };
        let refs: Vec<&Problem> = problems.iter().collect();
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
            for (flat, &sse) in values.sse.iter().enumerate() {
                let at = values.indices(flat);
                let theta: Vec<f64> = (0..3).map(|p| axes.axes[p][at[p]]).collect();
                let theta = [libm::log(theta[0]), theta[1], theta[2]];
                let direct = problem.evaluate(&theta, problem.beta).0.sse;
                assert!(
                    (sse - direct).abs() <= 1e-10 * problem.dd,
                    "at {at:?}: grid {sse}, direct {direct}"
                );
            }
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
        use super::super::layout::Layout;
        use crate::grid::Grid;
        let mut angles = synthetic::geometries();
        angles.truncate(angles.len() / 8 * 8 - 3);
        for model in [Model::Exp, Model::Gauss] {
            let layout = Layout::new(model, &Grid::user());
            let scene = &noisy_sets(
                &angles,
                model,
                Objective::Free,
                NoiseModel::Every(0.01),
                1,
                3,
            )[0];
            let problem = Problem::new(
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
