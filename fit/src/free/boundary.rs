//! The upper boundary at one refractive index n, as the free objective
//! uses it (docs/conventions.md §3, §4b): per measurement, the factor of
//! the Ragheb–Hancock base `B` (eqs. 3–7) that depends on n only, the
//! argument of the shape below the boundary and the refracted cosines.
//!
//! `B = L^sf(θi′, θs′) · (1 − f(θi, n)) · (1 − f(θs′, 1/n)) · dω′` with
//! `L^sf′ = cos θi′/v_z′² · shape(x′)` (eqs. 1–2) and `dω′ = cos θi/(n² cos θi′)`
//! (eq. 5), so `B = P · shape(x′)` with
//!
//! `P = cos θi · t_i · t_s / (n² v_z′²)`, `x′ = (T/σ)² v_xy² / (n² v_z′²)`,
//!
//! and each transmission (eq. 7) `t = 2 n c c′ (s² + p²)/(s² p²)`,
//! `s = c + n c′`, `p = n c + c′` (a product of positive terms: no
//! cancellation). The core's [`laminar_brdf_core::Interface`] forms the same
//! terms one by one (18 divisions per measurement, and `1 − f` for the
//! larger of `f` and `t`, which the paper objective keeps bit for bit);
//! here n's reciprocal is taken once and each measurement costs two square
//! roots and two divisions. The two agree to a few ulps (tested below).

use laminar_brdf_core::simd::Lane4;
use laminar_brdf_core::{f64x4, Correlation, Geometry, Lane};

/// One group of measurements at one n: four in `f64x4` lanes (the
/// refinement's and, by default, the grid stage's), eight in `f32x8`
/// lanes (the grid stage's in single precision, [`super::search`]).
#[derive(Debug, Clone, Copy)]
pub struct BoundaryGroup<L = f64x4> {
    /// `P`: `B = P · shape(x′)`.
    pub factor: L,
    /// `v_xy² / (n² v_z′²)`: `x′ = ratio · (T/σ)²`; +∞ where `v_z′ = 0`.
    pub ratio: L,
    /// `cos θi′`.
    pub cos_i: L,
    /// `cos θs′`.
    pub cos_s: L,
}

impl<L: Lane> BoundaryGroup<L> {
    /// The boundary of the measurements `g` at index `n ≥ 1` (`inv_n` its
    /// reciprocal; both rounded once to the lane precision). Inlined, as
    /// inside a [`laminar_brdf_core::simd`] kernel it must be.
    #[inline(always)]
    pub fn new(g: &Geometry<L>, n: f64, inv_n: f64) -> Self {
        if n == 1.0 {
            // No boundary: the layer's terms are the surface's own, bit for
            // bit (`U ≡ S` at a = 0, as in the core, so that β's tie there
            // is broken the same way every time).
            return Self {
                factor: g.lead,
                ratio: g.ratio,
                cos_i: g.cos_i,
                cos_s: g.cos_s,
            };
        }
        let (n, inv_n) = (L::c(n), L::c(inv_n));
        let (zero, one) = (L::c(0.0), L::c(1.0));
        let n2m1 = (n - one) * (n + one);
        let ci = refracted(n2m1, inv_n, g.cos_i);
        let cs = refracted(n2m1, inv_n, g.cos_s);
        let (sum_i, prod_i) = transmission_parts(n, g.cos_i, ci);
        let (sum_s, prod_s) = transmission_parts(n, g.cos_s, cs);
        let vz = ci + cs;
        let vz2 = vz * vz;
        // Both vanish only with a grazing direction at n = 1, where the
        // numerator has the factor `cos θ′ = 0` too: no light, as in the core.
        let lit = zero.lt(vz2);
        let den = prod_i * prod_s;
        let passes = zero.lt(den) & lit;
        let inv_vz2 = one / L::select(lit, vz2, one);
        // `cos θi · t_i t_s / n²` with `t_i t_s = 4 n² ci ci′ cs cs′ Σi Σs/(Πi Πs)`.
        let numerator = L::c(4.0) * g.cos_i * g.cos_i * ci * g.cos_s * cs * sum_i * sum_s;
        let factor = L::select(
            passes,
            numerator / L::select(passes, den, one) * inv_vz2,
            zero,
        );
        let ratio = L::select(lit, g.vxy2 * (inv_n * inv_n) * inv_vz2, L::c(f64::INFINITY));
        Self {
            factor,
            ratio,
            cos_i: ci,
            cos_s: cs,
        }
    }

    /// `B` at `(T/σ)² = t` (eqs. 3–4).
    #[inline(always)]
    pub fn base(&self, corr: Correlation, t: L) -> L {
        corr.scaled_shape(self.factor, self.ratio * t)
    }
}

impl BoundaryGroup<f64x4> {
    /// The stored group in a kernel's lanes.
    #[inline(always)]
    pub fn load<L: Lane4>(&self) -> BoundaryGroup<L> {
        BoundaryGroup {
            factor: L::load(self.factor),
            ratio: L::load(self.ratio),
            cos_i: L::load(self.cos_i),
            cos_s: L::load(self.cos_s),
        }
    }
}

impl<L: Lane4> BoundaryGroup<L> {
    /// The group as stored.
    #[inline(always)]
    pub fn store(&self) -> BoundaryGroup<f64x4> {
        BoundaryGroup {
            factor: self.factor.store(),
            ratio: self.ratio.store(),
            cos_i: self.cos_i.store(),
            cos_s: self.cos_s.store(),
        }
    }
}

/// Snell: `cos θ′ = √(n² − 1 + cos²θ)/n` from `n2m1 = n² − 1` (no total
/// internal reflection from air into the layer; the max guards n < 1). A
/// function, not a closure, so that a kernel surely inlines it.
#[inline(always)]
fn refracted<L: Lane>(n2m1: L, inv_n: L, c: L) -> L {
    (n2m1 + c * c).max(L::c(0.0)).sqrt() * inv_n
}

/// `t · s² p² / (2 n c c′) = s² + p²` and `s² p²` of one direction (eq. 7),
/// `c` its cosine above the boundary and `c2` below.
#[inline(always)]
fn transmission_parts<L: Lane>(n: L, c: L, c2: L) -> (L, L) {
    let (s, p) = (c + n * c2, n * c + c2);
    let (s2, p2) = (s * s, p * p);
    (s2 + p2, s2 * p2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synthetic;
    use laminar_brdf_core::{inverse_slope_squared, subsurface_base, Angles, Interface};

    /// `P · shape(x′)` is the core's `B` (the paper objective's terms one by
    /// one) to a few ulps, across n from 1 to the domain's top, grazing
    /// directions included; the refracted cosines and `x′` likewise.
    #[test]
    fn the_base_is_the_cores_to_a_few_ulps() {
        use std::f64::consts::{FRAC_PI_2, PI};
        let mut angles = synthetic::geometries();
        // Grazing (θ = π/2), normal, and the mirror direction.
        for (ti, ts, phi) in [
            (FRAC_PI_2, 0.3, 0.5),
            (0.0, FRAC_PI_2, 2.0),
            (FRAC_PI_2, FRAC_PI_2, 0.0),
            (0.0, 0.0, 0.0),
            (1.2, 1.2, PI),
        ] {
            angles.push(Angles::new(ti, ts, phi).unwrap());
        }
        // The largest difference where x′ ≤ 1 (outside the Gaussian tail).
        let mut worst: f64 = 0.0;
        for corr in [Correlation::Exponential, Correlation::Gaussian] {
            for n in [1.0, 1.0 + 1e-9, 1.001, 1.33, 1.5, 2.5, 10.0] {
                for slope in [0.02, 0.3, 2.0, 20.0] {
                    let t = inverse_slope_squared(slope);
                    for a in &angles {
                        let g = Geometry::<f64>::splat(a);
                        let want = subsurface_base(&Interface::new(&g, n), corr, t);
                        let group = BoundaryGroup::new(&Geometry::<f64x4>::splat(a), n, 1.0 / n);
                        let here = group.base(corr, f64x4::splat(t)).to_array()[0];
                        let refracted = g.refracted(n);
                        for (mine, core) in [
                            (group.cos_i, refracted.cos_i),
                            (group.cos_s, refracted.cos_s),
                            (group.ratio, refracted.ratio),
                        ] {
                            let mine = mine.to_array()[0];
                            assert!(
                                mine == core || (mine - core).abs() <= 4.0 * f64::EPSILON * core,
                                "n {n} {a:?}: {mine} against {core}"
                            );
                        }
                        if want == 0.0 {
                            assert_eq!(here, 0.0, "{corr:?} n {n} {a:?}");
                            continue;
                        }
                        let ulps = ((here - want) / want).abs() / f64::EPSILON;
                        // The Gaussian tail's `exp(−x′/4)` turns x′'s
                        // rounding (up to 4 ulps apart on the two paths)
                        // into up to `x′` ulps of B.
                        let x = g.refracted(n).ratio * t;
                        let allowed = 8.0
                            + if matches!(corr, Correlation::Gaussian) {
                                x
                            } else {
                                0.0
                            };
                        assert!(
                            ulps <= allowed,
                            "{corr:?} n {n} slope {slope} {a:?}: {ulps} ulps at x′ = {x}"
                        );
                        if x <= 1.0 {
                            worst = worst.max(ulps);
                        }
                    }
                }
            }
        }
        eprintln!("largest difference from the core's B (x′ ≤ 1): {worst:.1} ulps");
        assert!(worst > 0.0, "the two paths round differently somewhere");
    }
}
