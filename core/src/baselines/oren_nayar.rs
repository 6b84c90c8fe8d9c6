//! The full Oren–Nayar model (1994): direct term with C1, C2, C3 plus the
//! interreflection term, radiance with E0 = 1 (docs/conventions.md §7).
//!
//! In the Beckmann geometry the source azimuth is π, so `cos(φr − φi) = −cos φs`.

use crate::error::{check_param, InputError};
use crate::geometry::Angles;
use crate::lane::{Lane, Real};
use crate::param::Param;
use core::f64::consts::{FRAC_PI_2, PI};

/// Per-geometry terms of the Oren–Nayar model, computed once per scene
/// (α = max(θi, θs), β = min(θi, θs), Δφ = φr − φi).
#[derive(Clone, Copy, Debug)]
pub struct OrenNayarGeometry<L> {
    /// `cos θi`.
    pub cos_i: L,
    /// `cos Δφ · tan β · (sin α if cos Δφ ≥ 0 else sin α − (2β/π)³)`: multiplies C2's σ factor.
    pub c2_term: L,
    /// `(1 − |cos Δφ|) · (4αβ/π²)² · tan((α+β)/2)`: multiplies C3's σ factor.
    pub c3_term: L,
    /// `1 − cos Δφ (2β/π)²`: the interreflection factor.
    pub inter_term: L,
}

impl<L: Lane> OrenNayarGeometry<L> {
    /// Lane `i` from `angles(i)`; trigonometry in `f64` (libm), rounded once.
    pub fn from_lanes(mut angles: impl FnMut(usize) -> Angles) -> Self {
        let mut t = [[0.0f64; 4]; 8];
        for (i, slot) in t.iter_mut().enumerate().take(L::LANES) {
            *slot = Self::terms(&angles(i));
        }
        Self {
            cos_i: L::from_f64_lanes(|i| t[i][0]),
            c2_term: L::from_f64_lanes(|i| t[i][1]),
            c3_term: L::from_f64_lanes(|i| t[i][2]),
            inter_term: L::from_f64_lanes(|i| t[i][3]),
        }
    }

    fn terms(g: &Angles) -> [f64; 4] {
        let (ti, ts) = (g.theta_i(), g.theta_s());
        let alpha = ti.max(ts);
        // Keep tan finite at grazing: β and (α+β)/2 stay a hair below π/2.
        let beta = ti.min(ts).min(FRAC_PI_2 - 1e-7);
        let cos_dphi = -libm::cos(g.phi_s());
        let b2 = 2.0 * beta / PI;
        let c2 = if cos_dphi >= 0.0 {
            libm::sin(alpha)
        } else {
            libm::sin(alpha) - b2 * b2 * b2
        };
        let mid = ((alpha + beta) / 2.0).min(FRAC_PI_2 - 1e-7);
        let ab = 4.0 * alpha * beta / (PI * PI);
        [
            libm::cos(ti).clamp(0.0, 1.0),
            cos_dphi * c2 * libm::tan(beta),
            (1.0 - cos_dphi.abs()) * ab * ab * libm::tan(mid),
            1.0 - cos_dphi * b2 * b2,
        ]
    }
}

/// Parameter-only coefficients of the Oren–Nayar model for roughness σ
/// (radians) and albedo ρ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrenNayarCoefficients<S> {
    /// `(ρ/π) C1`, `C1 = 1 − 0.5 σ²/(σ² + 0.33)`.
    pub c1: S,
    /// `(ρ/π) 0.45 σ²/(σ² + 0.09)`.
    pub c2: S,
    /// `(ρ/π) 0.125 σ²/(σ² + 0.09)`.
    pub c3: S,
    /// `0.17 (ρ²/π) σ²/(σ² + 0.13)`.
    pub inter: S,
}

impl<S: Real> OrenNayarCoefficients<S> {
    /// Validates `σ ∈ [0, π/2]` and `ρ ∈ [0, 1]` and computes the coefficients.
    ///
    /// # Errors
    /// [`InputError::OutOfRange`] naming `sigma` or `rho` when it is outside
    /// its domain or NaN.
    pub fn new(sigma: f64, rho: f64) -> Result<Self, InputError> {
        check_param(Param::Sigma, sigma)?;
        check_param(Param::Rho, rho)?;
        let (s, r) = (S::from_f64(sigma), S::from_f64(rho));
        let c = S::c;
        let s2 = s * s;
        let rp = r / c(PI);
        Ok(Self {
            c1: rp * (c(1.0) - c(0.5) * s2 / (s2 + c(0.33))),
            c2: rp * (c(0.45) * s2 / (s2 + c(0.09))),
            c3: rp * (c(0.125) * s2 / (s2 + c(0.09))),
            inter: c(0.17) * r * rp * (s2 / (s2 + c(0.13))),
        })
    }
}

/// Oren–Nayar radiance (E0 = 1), un-normalised:
/// `cos θi [(ρ/π)(C1 + C2 … + C3 …) + 0.17 (ρ²/π) σ²/(σ²+0.13) (1 − cos Δφ (2β/π)²)]`.
#[inline]
#[must_use]
pub fn oren_nayar_radiance<L: Lane>(
    g: &OrenNayarGeometry<L>,
    k: &OrenNayarCoefficients<L::Scalar>,
) -> L {
    let direct = L::splat(k.c1) + L::splat(k.c2) * g.c2_term + L::splat(k.c3) * g.c3_term;
    g.cos_i * (direct + L::splat(k.inter) * g.inter_term)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_surface_is_lambertian() {
        let k = OrenNayarCoefficients::<f64>::new(0.0, 0.8).unwrap();
        for &(ti, ts, p) in &[(0.1, 0.7, 0.3), (1.2, 0.2, -2.0), (0.0, 0.0, 0.0)] {
            let g = OrenNayarGeometry::<f64>::from_lanes(|_| Angles::new(ti, ts, p).unwrap());
            let want = 0.8 / PI * libm::cos(ti);
            assert!((oren_nayar_radiance(&g, &k) - want).abs() < 1e-15);
        }
    }

    #[test]
    fn rough_backscatter_is_brighter_than_forward() {
        let k = OrenNayarCoefficients::<f64>::new(0.5, 0.8).unwrap();
        // Backscatter in Beckmann geometry: φs = π (view on the source side).
        let back = OrenNayarGeometry::<f64>::from_lanes(|_| Angles::new(0.8, 0.8, PI).unwrap());
        let fwd = OrenNayarGeometry::<f64>::from_lanes(|_| Angles::new(0.8, 0.8, 0.0).unwrap());
        assert!(oren_nayar_radiance(&back, &k) > oren_nayar_radiance(&fwd, &k));
    }
}
