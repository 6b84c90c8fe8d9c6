//! Surface radiance of a rough boundary (eqs. 1–2, docs/conventions.md §2).

use crate::exp::exp;
use crate::geometry::Geometry;
use crate::lane::Lane;

/// The correlation function of the boundary roughness.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Correlation {
    /// Gaussian correlation: eq. 1 (and eq. 12 below the surface).
    Gaussian,
    /// Exponential correlation: eq. 2 (and eq. 13 below the surface).
    Exponential,
}

impl Correlation {
    /// Every correlation function, in the order of the C ABI's codes (0, 1, …).
    pub const ALL: [Correlation; 2] = [Correlation::Exponential, Correlation::Gaussian];

    /// The name of its absorptive model in every interface (`exp`, `gauss`).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Exponential => "exp",
            Self::Gaussian => "gauss",
        }
    }

    /// The correlation of a name ([`Correlation::name`]).
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|c| c.name() == name)
    }

    /// The correlation of a C ABI code: its index in [`Correlation::ALL`].
    #[must_use]
    pub fn from_code(code: u32) -> Option<Self> {
        Self::ALL.get(code as usize).copied()
    }

    /// `∂ ln shape(x)/∂ ln σ/T` (eqs. 1–2 with `x ∝ (σ/T)⁻²`, `x ≥ 0`):
    /// Exponential `3x/(1 + x)`, Gaussian `x/2`; 0 where the term vanishes
    /// (`x = ∞`). The free objective's Jacobian uses it.
    #[cfg_attr(target_arch = "x86_64", inline(always))] // inside `simd` kernels
    #[cfg_attr(not(target_arch = "x86_64"), inline)]
    #[must_use]
    pub fn log_slope_derivative<L: Lane>(self, x: L) -> L {
        let value = match self {
            Self::Exponential => L::c(3.0) * x / (L::c(1.0) + x),
            Self::Gaussian => L::c(0.5) * x,
        };
        L::select(x.lt(L::c(f64::INFINITY)), value, L::c(0.0))
    }

    /// The roughness factor of eqs. 1–2 as a function of
    /// `x = (T/σ)² v_xy² / v_z²`: Gaussian `exp(−x/4)`, Exponential
    /// `(1 + x)^(−3/2)` (computed as `y·sqrt(y)`, `y = 1/(1 + x)`, so large
    /// `x` gives 0, never ∞ or NaN).
    #[cfg_attr(target_arch = "x86_64", inline(always))] // inside `simd` kernels
    #[cfg_attr(not(target_arch = "x86_64"), inline)]
    #[must_use]
    pub fn shape<L: Lane>(self, x: L) -> L {
        // Times 1, exactly: the same bits as the unscaled formulas.
        self.scaled_shape(L::c(1.0), x)
    }

    /// `scale · shape(x)` ([`Correlation::shape`]), the Exponential one as
    /// `(scale · y) · sqrt(y)`: `y · sqrt(y)` alone can fall below the
    /// normal range (losing bits) while the product is still normal.
    #[cfg_attr(target_arch = "x86_64", inline(always))] // inside `simd` kernels
    #[cfg_attr(not(target_arch = "x86_64"), inline)]
    #[must_use]
    pub fn scaled_shape<L: Lane>(self, scale: L, x: L) -> L {
        match self {
            Self::Gaussian => scale * exp(x * L::c(-0.25)),
            Self::Exponential => {
                let y = L::c(1.0) / (L::c(1.0) + x);
                (scale * y) * y.sqrt()
            }
        }
    }
}

/// `(T/σ)²` for an RMS slope `σ/T`; a search computes it once per slope.
#[cfg_attr(target_arch = "x86_64", inline(always))] // inside `simd` kernels
#[cfg_attr(not(target_arch = "x86_64"), inline)]
#[must_use]
pub fn inverse_slope_squared<L: Lane>(slope: L) -> L {
    L::c(1.0) / (slope * slope)
}

/// Surface radiance `L^sf` (eq. 1 Gaussian, eq. 2 Exponential) with
/// `K = k = 1`: `cos θi / v_z² · shape((T/σ)² v_xy² / v_z²)`.
/// `inv_slope2` is [`inverse_slope_squared`] of σ/T.
/// Accuracy (crate docs, Accuracy): within 9.8 ulps (f64) and 3.5 (f32),
/// plus up to `2x` ulps in the Gaussian tail.
#[cfg_attr(target_arch = "x86_64", inline(always))] // inside `simd` kernels
#[cfg_attr(not(target_arch = "x86_64"), inline)]
#[must_use]
pub fn surface_radiance<L: Lane>(g: &Geometry<L>, corr: Correlation, inv_slope2: L) -> L {
    corr.scaled_shape(g.lead, g.ratio * inv_slope2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Angles;

    #[test]
    fn huge_x_gives_zero() {
        for corr in [Correlation::Gaussian, Correlation::Exponential] {
            assert_eq!(corr.shape(f32::INFINITY), 0.0);
            assert!(corr.shape(1.0e30f32) < 1.0e-44);
            assert_eq!(corr.shape(0.0f64), 1.0);
        }
    }

    #[test]
    fn mirror_direction_has_no_roughness_loss() {
        let g = Geometry::<f64>::splat(&Angles::new(0.4, 0.4, 0.0).unwrap());
        let l = surface_radiance(&g, Correlation::Gaussian, inverse_slope_squared(0.5));
        let c = libm::cos(0.4);
        assert!((l - c / (4.0 * c * c)).abs() < 1e-15);
    }
}
