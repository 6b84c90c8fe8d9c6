//! Lower bounds on the errors of a triple ([`Projection`]) and of every
//! triple of a (σ/T, n) ([`Span`]), from sums alone: least-squares
//! residuals of the data, less a rounding margin. A search skips what its
//! bound puts above the best error found so far.

use super::SceneData;
use crate::paper::search::sums::{dot, DataSums, SurfaceSums};

/// Relative margin of every lower bound: a bound is the exact residual it
/// stands for minus `MARGIN · Σ D²`, which covers the rounding of the bound
/// and of the errors the sweep computes (see [`Projection`] and [`Span`]).
const MARGIN: f64 = 1e-8;

/// The lower bound on a triple's error over every β, from the sums alone.
///
/// For every β the prediction `X/M = ((1 − β)/M) S + (β/M) U` is a point
/// of the cone of non-negative combinations of `S` and `U`, so its error is
/// at least the least-squares residual of `D` on that cone (which does not
/// depend on the scale of `U`, so the unnormalised sums serve). On the plane
/// it is `R = Σ D² − (Σ S D)² / Σ S² − t² / q` with
/// `q = Σ U² − (Σ S U)² / Σ S²` (the part of `U` orthogonal to `S`) and
/// `t = Σ D U − Σ S U Σ S D / Σ S²`, attained at `c_U = t / q`,
/// `c_S = (Σ S D − c_U Σ S U) / Σ S²`; when either is negative the cone's
/// minimum is on one of its edges, `S` or `U` alone. The model side (`q`,
/// `Σ S U / Σ S²`) is per triple, the rest per scene.
///
/// Rounding: with `q ≥ 10⁻⁶ Σ U²` (otherwise there is no bound) the
/// computed `R` is within about `10⁻⁹ Σ D²` of the exact one, and the error
/// the sweep computes is within about `10⁻¹³ Σ D²` of the exact error. The
/// bound is `R − MARGIN Σ D²`, so every computed error of the triple is at
/// least the bound: a triple is skipped only if none of its values could
/// reach the threshold.
#[derive(Clone, Copy)]
pub struct Projection {
    pub(super) su: f64,
    pub(super) uu: f64,
    pub(super) su_over_ss: f64,
    pub(super) inv_q: f64,
}

impl Projection {
    /// The model side of the bound of a triple with `Σ S²`, `Σ S U` and
    /// `Σ U²` (unnormalised; [`super::basis::At`]); `None` when `U` is
    /// (nearly) a multiple of `S` or either is 0.
    pub fn new(ss: f64, su: f64, uu: f64) -> Option<Self> {
        if ss <= 0.0 || uu <= 0.0 {
            return None;
        }
        let su_over_ss = su / ss;
        let q = uu - su * su_over_ss;
        (q >= 1e-6 * uu).then(|| Self {
            su,
            uu,
            su_over_ss,
            inv_q: 1.0 / q,
        })
    }

    /// The bound for a scene with `Σ S D`, `Σ D²` in `fit` and (unnormalised)
    /// `Σ D U = ud`.
    #[inline]
    pub fn bound(&self, fit: &SurfaceFit, ud: f64) -> f64 {
        let sd = fit.sums.sd;
        let t = ud - self.su_over_ss * sd;
        let c_u = t * self.inv_q;
        if c_u >= 0.0 && sd >= c_u * self.su {
            return fit.residual - t * t * self.inv_q;
        }
        // On an edge: S alone (fit.residual when its coefficient Σ S D / Σ S²
        // is positive) or U alone.
        let floor = fit.sums.dd - MARGIN * fit.sums.dd;
        let on_s = if sd > 0.0 { fit.residual } else { floor };
        let on_u = if ud > 0.0 {
            floor - ud * ud / self.uu
        } else {
            floor
        };
        on_s.min(on_u)
    }
}

/// The lower bound on the error of every (a, β) of one (σ/T, n) at once:
/// `U(a)` lies in the span of `w0, w1, w2` for every `a`, so every
/// prediction lies in the span of `S, w0, w1, w2`, and its error is at
/// least the least-squares residual of `D` on that span, `Σ D² − |L⁻¹ b|²`
/// with `L Lᵀ` the Cholesky factorisation of the vectors' Gram matrix and
/// `b = (Σ S D, Σ w0 D, Σ w1 D, Σ w2 D)`. The model side (`L`) is per
/// (σ/T, n), the rest per scene.
///
/// Rounding: each vector must keep at least 10⁻⁴ of its squared norm
/// outside the span of the ones before it (else there is no bound), which
/// keeps the computed residual within about `10⁻¹⁰ Σ D²` of the exact one
/// for K up to thousands; the bound is the residual minus `MARGIN Σ D²`.
#[derive(Clone, Copy)]
pub struct Span {
    pub(super) l: [[f64; 4]; 4],
}

impl Span {
    pub(super) fn new(gram: &[[f64; 4]; 4]) -> Option<Self> {
        let mut l = [[0.0; 4]; 4];
        for i in 0..4 {
            for j in 0..=i {
                let sum = gram[i][j] - dot(&l[i][..j], &l[j][..j]);
                if i == j {
                    // Also refuses NaN.
                    if !(sum >= 1e-4 * gram[i][i] && gram[i][i] > 0.0) {
                        return None;
                    }
                    l[i][i] = sum.sqrt();
                } else {
                    l[i][j] = sum / l[j][j];
                }
            }
        }
        Some(Self { l })
    }

    /// The bound for a scene with sums `fit` and [`super::QuadraticBasis::data`] `data`.
    #[inline]
    pub fn bound(&self, fit: &SurfaceFit, data: &[f64; 3]) -> f64 {
        let b = [fit.sums.sd, data[0], data[1], data[2]];
        let mut y = [0.0; 4];
        let mut projected = 0.0;
        for i in 0..4 {
            y[i] = (b[i] - dot(&self.l[i][..i], &y[..i])) / self.l[i][i];
            projected += y[i] * y[i];
        }
        fit.sums.dd - MARGIN * fit.sums.dd - projected
    }
}

/// A scene's data against the surface term of one σ/T: its sums and the part
/// of the bound that does not depend on `U`, `Σ D² − (Σ S D)² / Σ S² − MARGIN Σ D²`.
#[derive(Clone, Copy)]
pub struct SurfaceFit {
    pub(super) sums: DataSums,
    pub(super) residual: f64,
}

impl SurfaceFit {
    /// The fit of `scene` to `surface`.
    pub fn new(surface: &SurfaceSums, scene: &SceneData) -> Self {
        let sums = DataSums {
            sd: dot(&surface.s, &scene.d),
            dd: scene.dd,
        };
        let projected = if surface.ss > 0.0 {
            sums.sd * sums.sd / surface.ss
        } else {
            0.0
        };
        Self {
            sums,
            residual: sums.dd - projected - MARGIN * sums.dd,
        }
    }
}
