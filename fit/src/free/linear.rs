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

/// The weighted inner products a solve needs: `⟨D, D⟩`, `⟨D, S⟩`, `⟨D, U⟩`,
/// `⟨S, S⟩`, `⟨S, U⟩`, `⟨U, U⟩`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Moments {
    /// `Σ w D²`.
    pub dd: f64,
    /// `Σ w D S`.
    pub ds: f64,
    /// `Σ w D U`.
    pub du: f64,
    /// `Σ w S²`.
    pub ss: f64,
    /// `Σ w S U`.
    pub su: f64,
    /// `Σ w U²`.
    pub uu: f64,
}

/// The linear coefficients at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Linear {
    /// Coefficient of `S`: `c (1 − β)`.
    pub p: f64,
    /// Coefficient of `U`: `c β`.
    pub q: f64,
    /// The objective there from the moments (loses the digits that
    /// `⟨D, D⟩` has over the residual; the refinement recomputes it from
    /// the residuals).
    pub sse: f64,
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

impl Moments {
    /// The objective at `(p, q)`.
    pub fn objective(&self, p: f64, q: f64) -> f64 {
        (self.dd - 2.0 * (p * self.ds + q * self.du)
            + p * p * self.ss
            + 2.0 * p * q * self.su
            + q * q * self.uu)
            .max(0.0)
    }

    /// The best point on the ray of balance `beta`.
    fn ray(&self, beta: f64) -> Linear {
        let (w0, w1) = (1.0 - beta, beta);
        let mm = w0 * w0 * self.ss + 2.0 * w0 * w1 * self.su + w1 * w1 * self.uu;
        let dm = w0 * self.ds + w1 * self.du;
        let c = if mm > 0.0 && dm > 0.0 { dm / mm } else { 0.0 };
        let (p, q) = (c * w0, c * w1);
        Linear {
            p,
            q,
            sse: self.objective(p, q),
        }
    }

    /// The minimum over `c ≥ 0`, `β ∈ [lo, hi]` (`0 ≤ lo ≤ hi ≤ 1`).
    pub fn solve(&self, (lo, hi): (f64, f64)) -> Linear {
        if lo < hi {
            let det = self.ss * self.uu - self.su * self.su;
            // Relative to the product: below it the two columns are
            // parallel to rounding and the rays decide.
            if det > 1e-12 * self.ss * self.uu {
                let p = (self.ds * self.uu - self.du * self.su) / det;
                let q = (self.du * self.ss - self.ds * self.su) / det;
                let c = p + q;
                if p >= 0.0 && q >= 0.0 && c > 0.0 {
                    let beta = q / c;
                    if beta >= lo && beta <= hi {
                        return Linear {
                            p,
                            q,
                            sse: self.objective(p, q),
                        };
                    }
                }
            }
        }
        let first = self.ray(lo);
        if lo == hi {
            return first;
        }
        let second = self.ray(hi);
        if second.sse < first.sse {
            second
        } else {
            first
        }
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
