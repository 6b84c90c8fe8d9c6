//! The robust score test of one value of a shared parameter for every
//! channel of a joint fit (docs/conventions.md §4c): is σ/T the same in
//! every channel.
//!
//! At the joint estimate (the null: one σ/T), the alternative gives each
//! channel `c` its own σ/T, whose score is channel `c`'s σ/T column `z_c`
//! against its weighted residuals `e_c`. The nuisance parameters are
//! projected out of the score (Neyman's C(α) form, so the estimate's own
//! error does not enter): each channel's own a, β and amplitude within
//! the channel, then the shared σ/T, σ′/T′ and n over all channels:
//!
//! `ž_c = z̃_c − Q Qᵀ z̃_c`, `z̃_c = (I − P_c) z_c`,
//!
//! with `P_c` the projection onto channel `c`'s own columns and `Q` an
//! orthonormal basis of the shared columns so projected. The score is a
//! sum over the geometries, `U = Σ_g u_g`, `u_g[c] = Σ_c′ ž_c[c′, g] e_c′[g]`
//! (a geometry's measurements in every channel together: the bootstrap's
//! unit, so the channels' correlation at a geometry is kept). A channel
//! whose prediction σ/T does not enter (β at 1: no surface term) has no
//! score and is left out. The `u_g` sum to zero over the channels (the
//! shared σ/T is projected out), so all but the first carry the test,
//! and it is Hotelling's one-sample test of their mean being zero:
//! `T² = G ūᵀ S⁻¹ ū` with `S` their covariance over the `G` geometries,
//! `(G − p) T² / (p (G − 1))` against `F(p, G − p)`, `p` one less than the
//! channels tested. The covariance is the residuals' own, so
//! the test holds when the model does not fit the data (Boos 1992,
//! "On generalized score tests"; Kent 1982).

use super::covariance::jacobian;
use crate::free::coordinate::Coordinate;
use crate::free::model::FreeModel;
use crate::free::problem::{Point, Problem};
use nalgebra::{DMatrix, DVector};
use statrs::distribution::{ContinuousCDF, FisherSnedecor};

/// Hotelling's test of a mean of zero ([`shared_value`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hotelling {
    /// `T²`.
    pub statistic: f64,
    /// `p`: the channels tested less one.
    pub df1: usize,
    /// `G − p`, `G` the geometries.
    pub df2: usize,
    /// The p-value from `F(df1, df2)`.
    pub p_value: f64,
}

/// The score test (module doc) of one value of the shared parameter at θ
/// position `tested` for every channel, at the joint estimate: each
/// channel's `problems[c]` and `points[c]` (its θ with the shared values
/// and its own a), `shared` the θ positions of the shared parameters
/// (`tested` among them), `own` the channel's own nonlinear positions (a).
/// A parameter on a face of its box is held, as the covariance holds it.
/// Why not, when the test cannot be made.
pub fn shared_value<M: FreeModel>(
    problems: &[Problem<M>],
    points: &[Point],
    (tested, shared, own): (usize, &[usize], &[usize]),
) -> Result<Hotelling, &'static str> {
    let channels = problems.len();
    let geometries = problems[0].data.len();
    let coordinates: Vec<Coordinate> = (shared.iter().chain(own))
        .map(|&j| Coordinate::Nonlinear { j, log: false })
        .chain([Coordinate::Beta])
        .collect();
    let at = shared
        .iter()
        .position(|&j| j == tested)
        .expect("the tested parameter is shared");
    // Per channel: its σ/T column and the shared columns, both with the
    // channel's own columns projected out, and its weighted residuals.
    let mut z = Vec::with_capacity(channels);
    let mut shared_columns: Vec<DMatrix<f64>> = Vec::with_capacity(channels);
    let mut residuals = Vec::with_capacity(channels);
    for (problem, point) in problems.iter().zip(points) {
        let (columns, on_face, e) = jacobian(problem, point, &coordinates);
        let weighted = |i: usize| {
            DVector::from_iterator(
                geometries,
                (columns[i].iter().zip(&problem.root_weight)).map(|(d, r)| d * r),
            )
        };
        let kept = |range: std::ops::Range<usize>| -> Vec<DVector<f64>> {
            range.filter(|&i| !on_face[i]).map(weighted).collect()
        };
        if on_face[at] {
            return Err("the shared value is on a face of its box");
        }
        let mine = kept(shared.len()..columns.len());
        let basis = match mine.is_empty() {
            true => None,
            false => Some(
                orthonormal(DMatrix::from_columns(&mine))
                    .ok_or("a channel's own columns are singular")?,
            ),
        };
        let projected = |v: DVector<f64>| match &basis {
            Some(q) => {
                let along = q * q.tr_mul(&v);
                v - along
            }
            None => v,
        };
        let s: Vec<DVector<f64>> = kept(0..shared.len()).into_iter().map(projected).collect();
        z.push(projected(weighted(at)));
        shared_columns.push(DMatrix::from_columns(&s));
        residuals.push(e);
    }
    // The channels whose prediction the value enters (with β at 1 a
    // layered model has no surface term, and σ/T enters only that).
    let largest = z.iter().map(|z| z.norm()).fold(0.0, f64::max);
    let entered: Vec<usize> = (0..channels)
        .filter(|&c| z[c].norm() > 1e-12 * largest)
        .collect();
    let p = entered.len().saturating_sub(1);
    if p == 0 {
        return Err("the value enters fewer than two channels' predictions");
    }
    if geometries <= p + 1 {
        return Err("too few geometries for the channels");
    }
    // The shared columns stacked over the channels, and an orthonormal
    // basis of them.
    let stacked = DMatrix::from_fn(channels * geometries, shared_columns[0].ncols(), |r, j| {
        shared_columns[r / geometries][(r % geometries, j)]
    });
    let q = orthonormal(stacked).ok_or("the shared columns are singular")?;
    // h_c = Qᵀ z̃_c (z̃_c in channel c's rows only); m_g = Σ_c Q[(c, g)] e_c[g].
    let rows = |c: usize| q.rows(c * geometries, geometries);
    let h: Vec<DVector<f64>> = (0..channels).map(|c| rows(c).tr_mul(&z[c])).collect();
    let draws: Vec<DVector<f64>> = (0..geometries)
        .map(|g| {
            let m = (0..channels).fold(DVector::zeros(q.ncols()), |m, c| {
                m + q.row(c * geometries + g).transpose() * residuals[c][g]
            });
            DVector::from_iterator(
                p,
                (entered[1..].iter()).map(|&c| z[c][g] * residuals[c][g] - h[c].dot(&m)),
            )
        })
        .collect();
    hotelling(&draws).ok_or("the score's covariance is singular")
}

/// An orthonormal basis of `a`'s columns (thin QR); `None` when they are
/// dependent to rounding.
fn orthonormal(a: DMatrix<f64>) -> Option<DMatrix<f64>> {
    let scale = a.column_iter().map(|c| c.norm()).fold(0.0, f64::max);
    let qr = a.qr();
    let r = qr.r();
    let independent = (0..r.nrows()).all(|i| r[(i, i)].abs() > 1e-10 * scale);
    (scale > 0.0 && independent).then(|| qr.q())
}

/// Hotelling's one-sample test of `draws` having mean zero.
fn hotelling(draws: &[DVector<f64>]) -> Option<Hotelling> {
    let (mean, covariance) = mean_and_covariance(draws);
    let statistic = draws.len() as f64 * mean.dot(&covariance.cholesky()?.solve(&mean));
    let (df1, df2, p_value) = f_calibrated(statistic, mean.len(), draws.len());
    Some(Hotelling {
        statistic,
        df1,
        df2,
        p_value: p_value?,
    })
}

/// The mean of `draws` and their covariance (divided by the draws less
/// one).
pub(crate) fn mean_and_covariance(draws: &[DVector<f64>]) -> (DVector<f64>, DMatrix<f64>) {
    let (g, p) = (draws.len(), draws[0].len());
    let mean = draws.iter().sum::<DVector<f64>>() / g as f64;
    let covariance = draws.iter().fold(DMatrix::zeros(p, p), |s, u| {
        let d = u - &mean;
        s + &d * d.transpose()
    }) / (g - 1) as f64;
    (mean, covariance)
}

/// Hotelling's `T²` of `p` values with a covariance estimated from `n`
/// draws, calibrated: `(n − p) T² / (p (n − 1))` against `F(p, n − p)`.
/// The degrees of freedom and the p-value (`None` when the distribution
/// cannot be formed).
pub(crate) fn f_calibrated(statistic: f64, p: usize, n: usize) -> (usize, usize, Option<f64>) {
    let (df1, df2) = (p, n - p);
    let f = df2 as f64 * statistic / (df1 as f64 * (n - 1) as f64);
    let p_value = FisherSnedecor::new(df1 as f64, df2 as f64)
        .ok()
        .map(|d| d.sf(f));
    (df1, df2, p_value)
}
