//! The linear part of the free-amplitude objective in closed form
//! (variable projection; docs/conventions.md §4b), written once over
//! [`Lane`] for the host's f64 fits (`f64`, `f64x4`) and the device's f32
//! grid ([`crate::small_free_fit::fit_free`]): for fixed nonlinear
//! parameters, the amplitude `c ≥ 0` and the balance `β ∈ [β_lo, β_hi]` of
//! eq. 8 minimise
//!
//! `Σ w (D − p S − q U)²`, with `p = c (1 − β)`, `q = c β`.
//!
//! The constraints make `(p, q)` a convex cone (between the rays of β_lo
//! and β_hi), and the objective is a convex quadratic in `(p, q)`: its
//! minimum is the unconstrained one when that lies in the cone, and
//! otherwise the better of the two rays' one-variable minima (each
//! `c = max(0, ⟨D, m⟩/⟨m, m⟩)` along `m = (1 − β) S + β U`).

use crate::lane::{Lane, Mask, Real};

/// The weighted inner products a solve needs: `⟨D, D⟩`, `⟨D, S⟩`, `⟨D, U⟩`,
/// `⟨S, S⟩`, `⟨S, U⟩`, `⟨U, U⟩`. Generic over [`Lane`] so that the host's
/// grid stage solves four points at once (`f64x4`), bit for bit as one at a
/// time (`f64`, the default), and the device's in `f32`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Moments<L = f64> {
    /// `Σ w D²`.
    pub dd: L,
    /// `Σ w D S`.
    pub ds: L,
    /// `Σ w D U`.
    pub du: L,
    /// `Σ w S²`.
    pub ss: L,
    /// `Σ w S U`.
    pub su: L,
    /// `Σ w U²`.
    pub uu: L,
}

/// The linear coefficients at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Linear<L = f64> {
    /// Coefficient of `S`: `c (1 − β)`.
    pub p: L,
    /// Coefficient of `U`: `c β`.
    pub q: L,
    /// The objective there from the moments (loses the digits that
    /// `⟨D, D⟩` has over the residual; the refinement recomputes it from
    /// the residuals).
    pub sse: L,
}

impl<R: Real> Linear<R> {
    /// The amplitude `c = p + q`.
    pub fn amplitude(&self) -> R {
        self.p + self.q
    }

    /// The balance `β = q / (p + q)` (`fallback` when `c = 0`).
    pub fn beta(&self, fallback: R) -> R {
        let c = self.amplitude();
        if R::c(0.0) < c {
            self.q / c
        } else {
            fallback
        }
    }
}

impl<L: Lane> Linear<L> {
    /// `if mask { t } else { f }`, lane by lane.
    #[cfg_attr(target_arch = "x86_64", inline(always))] // inside `simd` kernels
    #[cfg_attr(not(target_arch = "x86_64"), inline)]
    fn select(mask: L::Mask, t: Self, f: Self) -> Self {
        Self {
            p: L::select(mask, t.p, f.p),
            q: L::select(mask, t.q, f.q),
            sse: L::select(mask, t.sse, f.sse),
        }
    }
}

impl<L: Lane> Moments<L> {
    /// The objective at `(p, q)`.
    #[cfg_attr(target_arch = "x86_64", inline(always))] // inside `simd` kernels
    #[cfg_attr(not(target_arch = "x86_64"), inline)]
    pub fn objective(&self, p: L, q: L) -> L {
        let two = L::c(2.0);
        (self.dd - two * (p * self.ds + q * self.du)
            + p * p * self.ss
            + two * p * q * self.su
            + q * q * self.uu)
            .max(L::c(0.0))
    }

    /// The best point on the ray of balance `beta`.
    #[cfg_attr(target_arch = "x86_64", inline(always))] // inside `simd` kernels
    #[cfg_attr(not(target_arch = "x86_64"), inline)]
    fn ray(&self, beta: L) -> Linear<L> {
        let zero = L::c(0.0);
        let (w0, w1) = (L::c(1.0) - beta, beta);
        let two = L::c(2.0);
        let mm = w0 * w0 * self.ss + two * w0 * w1 * self.su + w1 * w1 * self.uu;
        let dm = w0 * self.ds + w1 * self.du;
        let c = L::select(zero.lt(mm) & zero.lt(dm), dm / mm, zero);
        let (p, q) = (c * w0, c * w1);
        Linear {
            p,
            q,
            sse: self.objective(p, q),
        }
    }

    /// The minimum over `c ≥ 0`, `β ∈ [lo, hi]` (`0 ≤ lo ≤ hi ≤ 1`): the
    /// unconstrained minimum when it lies in the cone, else the better ray
    /// (the lower one on ties; one ray when `lo = hi`).
    #[cfg_attr(target_arch = "x86_64", inline(always))] // inside `simd` kernels
    #[cfg_attr(not(target_arch = "x86_64"), inline)]
    pub fn solve(&self, (lo, hi): (f64, f64)) -> Linear<L> {
        let (zero, lo_l, hi_l) = (L::c(0.0), L::c(lo), L::c(hi));
        if lo == hi {
            return self.ray(lo_l);
        }
        let det = self.ss * self.uu - self.su * self.su;
        let p = (self.ds * self.uu - self.du * self.su) / det;
        let q = (self.du * self.ss - self.ds * self.su) / det;
        let c = p + q;
        let beta = q / c;
        // Relative to the product: below it the two columns are parallel
        // to rounding and the rays decide ([`Real::COLLINEAR`]).
        let collinear = L::c(<L::Scalar as Real>::COLLINEAR);
        let inside = (collinear * self.ss * self.uu).lt(det)
            & zero.le(p)
            & zero.le(q)
            & zero.lt(c)
            & lo_l.le(beta)
            & beta.le(hi_l);
        let free = Linear {
            p,
            q,
            sse: self.objective(p, q),
        };
        if inside.all() {
            // No lane needs the rays.
            return free;
        }
        let (first, second) = (self.ray(lo_l), self.ray(hi_l));
        let rays = Linear::select(second.sse.lt(first.sse), second, first);
        Linear::select(inside, free, rays)
    }
}

/// The moments of an absorptive layered model as polynomials in the
/// absorption a, for one (σ/T, n): with `U = B (1 − a cos²θi)(1 − a cos²θs)
/// = B0 + a B1 + a² B2` (`B0 = B`, `B1 = −B (cos²θi + cos²θs)`,
/// `B2 = B cos²θi cos²θs`; eqs. 12–14), every a's [`Moments`] come from
/// these weighted inner products with no pass over the measurements.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Quadratic<R> {
    /// `Σ w D²`.
    pub dd: R,
    /// `Σ w D S`.
    pub ds: R,
    /// `Σ w S²`.
    pub ss: R,
    /// `Σ w D B_i`.
    pub db: [R; 3],
    /// `Σ w S B_i`.
    pub sb: [R; 3],
    /// `bb[i][j] = Σ w B_i B_j`.
    pub bb: [[R; 3]; 3],
}

impl<R: Real> Quadratic<R> {
    /// The moments at the absorptions `a` (one per lane).
    #[cfg_attr(target_arch = "x86_64", inline(always))] // inside `simd` kernels
    #[cfg_attr(not(target_arch = "x86_64"), inline)]
    pub fn moments<L: Lane<Scalar = R>>(&self, a: L) -> Moments<L> {
        let pow = [L::c(1.0), a, a * a];
        let c = L::splat;
        let mut uu = L::c(0.0);
        for (i, &pi) in pow.iter().enumerate() {
            for (j, &pj) in pow.iter().enumerate() {
                uu = uu + pi * pj * c(self.bb[i][j]);
            }
        }
        Moments {
            dd: c(self.dd),
            ds: c(self.ds),
            du: c(self.db[0]) + a * c(self.db[1]) + a * a * c(self.db[2]),
            ss: c(self.ss),
            su: c(self.sb[0]) + a * c(self.sb[1]) + a * a * c(self.sb[2]),
            uu,
        }
    }
}
