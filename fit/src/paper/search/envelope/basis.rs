//! The subsurface term of one (σ/T, n) as a quadratic in `a` ([`QuadraticBasis`]),
//! and its value at one `a` ([`At`]) (docs/conventions.md §6).

use super::bounds::Span;
use crate::paper::search::sums::{dot, dot4, SurfaceSums};

/// The unnormalised subsurface term of one (σ/T, n) as a quadratic in `a`
/// (module docs): `w0, w1, w2` over the measurements, the coefficients of
/// `Σ S U` and `Σ U²` in the basis `(1 − a)^(m−j) a^j`, and the bound of
/// every `a` at once ([`Span`]).
pub struct QuadraticBasis {
    pub(super) w: [Vec<f64>; 3],
    pub(super) su: [f64; 3],
    pub(super) uu: [f64; 5],
    pub(super) span: Option<Span>,
}

impl QuadraticBasis {
    /// The basis of the widened subsurface base `base` with the widened
    /// sines `sines`, and its sums against the surface term.
    pub fn new(surface: &SurfaceSums, base: &[f64], sines: &[[f64; 2]]) -> Self {
        let w = [
            base.to_vec(),
            base.iter()
                .zip(sines)
                .map(|(&b, &[si, ss])| b * (si + ss))
                .collect(),
            base.iter()
                .zip(sines)
                .map(|(&b, &[si, ss])| b * (si * ss))
                .collect(),
        ];
        let su = [0, 1, 2].map(|i| dot4(&surface.s, &w[i]));
        let mut ww = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in i..3 {
                ww[i][j] = dot4(&w[i], &w[j]);
            }
        }
        // (t² w0 + t a w1 + a² w2)², by powers of a.
        let uu = [
            ww[0][0],
            2.0 * ww[0][1],
            ww[1][1] + 2.0 * ww[0][2],
            2.0 * ww[1][2],
            ww[2][2],
        ];
        let gram = [
            [surface.ss, su[0], su[1], su[2]],
            [su[0], ww[0][0], ww[0][1], ww[0][2]],
            [su[1], ww[0][1], ww[1][1], ww[1][2]],
            [su[2], ww[0][2], ww[1][2], ww[2][2]],
        ];
        Self {
            w,
            su,
            uu,
            span: Span::new(&gram),
        }
    }

    /// `Σ D w_j` of the widened data `d`, for [`At::ud`].
    pub fn data(&self, d: &[f64]) -> [f64; 3] {
        [0, 1, 2].map(|i| dot4(&self.w[i], d))
    }

    /// The term at absorption `a`.
    pub fn at(&self, a: f64) -> At {
        let t = 1.0 - a;
        let (t2, ta, a2) = (t * t, t * a, a * a);
        let b = [t2, ta, a2];
        let b4 = [t2 * t2, t2 * ta, t2 * a2, ta * a2, a2 * a2];
        At {
            b,
            su: dot(&b, &self.su),
            uu: dot(&b4, &self.uu),
        }
    }
}

/// The unnormalised subsurface term of one (σ/T, n, a): its basis weights,
/// `Σ S U` and `Σ U²`.
#[derive(Clone, Copy)]
pub struct At {
    pub(super) b: [f64; 3],
    pub(super) su: f64,
    pub(super) uu: f64,
}

impl At {
    /// `U_k` (unnormalised) of measurement `k` of `basis`.
    #[inline]
    pub(super) fn value(&self, basis: &QuadraticBasis, k: usize) -> f64 {
        self.b[0] * basis.w[0][k] + self.b[1] * basis.w[1][k] + self.b[2] * basis.w[2][k]
    }

    /// `Σ D U` (unnormalised) from a scene's [`QuadraticBasis::data`].
    #[inline]
    pub fn ud(&self, data: &[f64; 3]) -> f64 {
        dot(&self.b, data)
    }
}
