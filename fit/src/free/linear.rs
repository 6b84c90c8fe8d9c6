//! The linear part of the free-amplitude objective in closed form
//! (variable projection; docs/conventions.md §4b): for fixed nonlinear
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

use laminar_core::Lane;

/// The weighted inner products a solve needs: `⟨D, D⟩`, `⟨D, S⟩`, `⟨D, U⟩`,
/// `⟨S, S⟩`, `⟨S, U⟩`, `⟨U, U⟩`. Generic over the core's [`Lane`] so that the
/// grid stage solves four points at once (`f64x4`), bit for bit as one at a
/// time (`f64`, the default).
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

impl Linear {
    /// The amplitude `c = p + q`.
    pub fn amplitude(&self) -> f64 {
        self.p + self.q
    }

    /// The balance `β = q / (p + q)` (`fallback` when `c = 0`).
    pub fn beta(&self, fallback: f64) -> f64 {
        let c = self.amplitude();
        if c > 0.0 {
            self.q / c
        } else {
            fallback
        }
    }
}

impl<L: Lane> Linear<L> {
    /// `if mask { t } else { f }`, lane by lane.
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
    pub fn objective(&self, p: L, q: L) -> L {
        let two = L::c(2.0);
        (self.dd - two * (p * self.ds + q * self.du)
            + p * p * self.ss
            + two * p * q * self.su
            + q * q * self.uu)
            .max(L::c(0.0))
    }

    /// The best point on the ray of balance `beta`.
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
    pub fn solve(&self, (lo, hi): (f64, f64)) -> Linear<L> {
        let (zero, lo_l, hi_l) = (L::c(0.0), L::c(lo), L::c(hi));
        let first = self.ray(lo_l);
        if lo == hi {
            return first;
        }
        let second = self.ray(hi_l);
        let rays = Linear::select(second.sse.lt(first.sse), second, first);
        let det = self.ss * self.uu - self.su * self.su;
        let p = (self.ds * self.uu - self.du * self.su) / det;
        let q = (self.du * self.ss - self.ds * self.su) / det;
        let c = p + q;
        let beta = q / c;
        // Relative to the product: below it the two columns are parallel
        // to rounding and the rays decide.
        let inside = (L::c(1e-12) * self.ss * self.uu).lt(det)
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
        Linear::select(inside, free, rays)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn moments(d: &[f64], s: &[f64], u: &[f64]) -> Moments {
        let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(a, b)| a * b).sum::<f64>();
        Moments {
            dd: dot(d, d),
            ds: dot(d, s),
            du: dot(d, u),
            ss: dot(s, s),
            su: dot(s, u),
            uu: dot(u, u),
        }
    }

    #[test]
    fn exact_mixes_are_recovered_and_constraints_hold() {
        let s = [1.0, 0.5, 0.2, 0.1];
        let u = [0.2, 0.4, 0.6, 0.3];
        let d: Vec<f64> = s
            .iter()
            .zip(&u)
            .map(|(s, u)| 2.0 * (0.7 * s + 0.3 * u))
            .collect();
        let m = moments(&d, &s, &u);
        let l = m.solve((0.0, 1.0));
        assert!((l.amplitude() - 2.0).abs() < 1e-12 && (l.beta(0.0) - 0.3).abs() < 1e-12);
        assert!(l.sse < 1e-20);
        // A box that excludes 0.3: the nearer ray, β = 0.5.
        let l = m.solve((0.5, 1.0));
        assert_eq!(l.beta(0.0), 0.5);
        // Data the columns cannot reach with c ≥ 0: amplitude 0.
        let neg: Vec<f64> = d.iter().map(|v| -v).collect();
        let l = moments(&neg, &s, &u).solve((0.0, 1.0));
        assert_eq!(l.amplitude(), 0.0);
        // A fixed β is one ray.
        let l = m.solve((0.3, 0.3));
        assert!((l.amplitude() - 2.0).abs() < 1e-12);
    }

    #[test]
    fn four_lanes_solve_bit_for_bit_as_one() {
        use crate::synthetic::Noise;
        use laminar_core::f64x4;
        // Moments from random columns (some nearly parallel, some data the
        // cone cannot reach), each box: every lane's bits equal the scalar.
        let mut rng = Noise::new(0x2545_f491_4f6c_dd1d);
        let mut next = || rng.uniform();
        for trial in 0..2000 {
            let k = 6;
            let s: Vec<f64> = (0..k).map(|_| next()).collect();
            let tilt = if trial % 3 == 0 { 1e-9 } else { 1.0 };
            let u: Vec<f64> = s.iter().map(|v| v * (1.0 + tilt * next())).collect();
            let sign = if trial % 5 == 0 { -1.0 } else { 1.0 };
            let d: Vec<f64> = (0..k).map(|_| sign * next()).collect();
            let lanes: Vec<Moments> = (0..4).map(|_| moments(&d, &s, &u)).collect();
            let lanes: Vec<Moments> = lanes
                .iter()
                .enumerate()
                .map(|(i, m)| Moments {
                    du: m.du * (1.0 + 0.3 * i as f64),
                    ..*m
                })
                .collect();
            let pick = |f: fn(&Moments) -> f64| f64x4::new([0, 1, 2, 3].map(|i| f(&lanes[i])));
            let packed = Moments {
                dd: pick(|m| m.dd),
                ds: pick(|m| m.ds),
                du: pick(|m| m.du),
                ss: pick(|m| m.ss),
                su: pick(|m| m.su),
                uu: pick(|m| m.uu),
            };
            for beta in [(0.0, 1.0), (0.2, 0.4), (0.5, 0.5)] {
                let got = packed.solve(beta);
                let (p, q, sse) = (got.p.to_array(), got.q.to_array(), got.sse.to_array());
                for (i, m) in lanes.iter().enumerate() {
                    let want = m.solve(beta);
                    assert_eq!(
                        [p[i], q[i], sse[i]].map(f64::to_bits),
                        [want.p, want.q, want.sse].map(f64::to_bits),
                        "trial {trial}, lane {i}, box {beta:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_cone_minimum_is_never_above_a_brute_force_one() {
        let s = [1.0, 0.8, 0.1, 0.05, 0.3];
        let u = [0.1, 0.9, 0.7, 0.4, 0.35];
        let d = [0.4, 1.0, 0.5, 0.1, 0.2];
        let m = moments(&d, &s, &u);
        for (lo, hi) in [(0.0, 1.0), (0.2, 0.4), (0.9, 1.0), (0.0, 0.1)] {
            let l = m.solve((lo, hi));
            let mut best = f64::INFINITY;
            for i in 0..=400 {
                for j in 0..=200 {
                    let beta = lo + (hi - lo) * i as f64 / 400.0;
                    let c = 2.0 * j as f64 / 200.0;
                    best = best.min(m.objective(c * (1.0 - beta), c * beta));
                }
            }
            assert!(l.sse <= best + 1e-12, "{lo} {hi}: {} > {best}", l.sse);
            let beta = l.beta(lo);
            assert!(beta >= lo && beta <= hi && l.amplitude() >= 0.0);
        }
    }
}
