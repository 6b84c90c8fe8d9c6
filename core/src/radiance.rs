//! Validated parameters, the per-component breakdown and the total radiance
//! of eq. 8.

use crate::absorption::absorbed;
use crate::error::{check_param, InputError};
use crate::geometry::Geometry;
use crate::lane::{Lane, Real};
use crate::param::Param;
use crate::subsurface::{absorption_factor, subsurface_base, Interface};
use crate::surface::{inverse_slope_squared, surface_radiance, Correlation};

pub use crate::param::{INDEX_MAX, SLOPE_MAX, SLOPE_MIN};

/// Parameters of the absorptive model, validated once by [`Params::new`]:
/// RMS slope `σ/T ∈ [1e-3, 1e3]`, balance `β ∈ [0, 1]`, refractive index
/// `n ∈ [1, 10]`, absorption `a ∈ [0, 1]`, and the lower boundary's RMS
/// slope σ′/T′ (eqs. 3–4): equal to σ/T as the paper's search ties them
/// ([`Params::new`]), or its own ([`Params::untied`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    slope: f64,
    sub_slope: f64,
    beta: f64,
    n: f64,
    a: f64,
}

impl Params {
    /// Validates and builds a parameter set with σ′/T′ = σ/T; the error
    /// names the first parameter out of its domain (NaN is always out).
    ///
    /// # Errors
    /// [`InputError::OutOfRange`] naming the first parameter outside its domain.
    pub fn new(slope: f64, beta: f64, n: f64, a: f64) -> Result<Self, InputError> {
        Self::untied(slope, slope, beta, n, a)
    }

    /// [`Params::new`] with the lower boundary's own RMS slope σ′/T′
    /// (eqs. 3–4 as printed). At `sub_slope == slope` it is [`Params::new`].
    ///
    /// ```
    /// use laminar_brdf_core::{total_radiance, Angles, Correlation, Geometry, Params};
    /// let g = Geometry::<f64>::splat(&Angles::new(0.3, 0.9, 2.1)?);
    /// let smooth_top = Params::untied(0.1, 0.8, 0.5, 1.5, 0.3)?;
    /// let tied = Params::untied(0.1, 0.1, 0.5, 1.5, 0.3)?;
    /// let corr = Correlation::Exponential;
    /// assert_eq!(tied, Params::new(0.1, 0.5, 1.5, 0.3)?);
    /// assert_ne!(total_radiance(&g, corr, &smooth_top), total_radiance(&g, corr, &tied));
    /// # Ok::<(), laminar_brdf_core::InputError>(())
    /// ```
    ///
    /// # Errors
    /// [`InputError::OutOfRange`] naming the first parameter outside its domain.
    pub fn untied(
        slope: f64,
        sub_slope: f64,
        beta: f64,
        n: f64,
        a: f64,
    ) -> Result<Self, InputError> {
        let p = LaneParams::<f64>::untied(slope, sub_slope, beta, n, a)?;
        Ok(Self {
            slope: p.slope,
            sub_slope: p.sub_slope,
            beta: p.beta,
            n: p.n,
            a: p.a,
        })
    }
    /// RMS slope σ/T of the upper boundary.
    #[must_use]
    pub fn slope(&self) -> f64 {
        self.slope
    }
    /// RMS slope σ′/T′ of the lower boundary (σ/T when tied).
    #[must_use]
    pub fn sub_slope(&self) -> f64 {
        self.sub_slope
    }
    /// Balance β between subsurface and surface radiance.
    #[must_use]
    pub fn beta(&self) -> f64 {
        self.beta
    }
    /// Refractive index n of the upper layer.
    #[must_use]
    pub fn n(&self) -> f64 {
        self.n
    }
    /// Fractional absorption a (0: Ragheb–Hancock).
    #[must_use]
    pub fn a(&self) -> f64 {
        self.a
    }
    /// The parameters rounded once to the precision `S` (what the `S`
    /// lanes evaluate with).
    #[must_use]
    pub fn in_precision<S: Real>(&self) -> LaneParams<S> {
        LaneParams::rounded(
            S::from_f64(self.slope),
            S::from_f64(self.sub_slope),
            S::from_f64(self.beta),
            S::from_f64(self.n),
            S::from_f64(self.a),
        )
    }
}

/// Validated parameters in a lane's scalar precision `S` (`f32` or `f64`),
/// with `(T/σ)²` computed once: what [`total_radiance_in`] and
/// [`components_in`] evaluate with, so that an `f32` evaluation does no
/// `f64` work at all (on an FPU without double precision, such as the
/// Cortex-M4F's, every `f64` operation is a software call).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaneParams<S> {
    slope: S,
    sub_slope: S,
    beta: S,
    n: S,
    a: S,
    inv_slope2: S,
    inv_sub_slope2: S,
}

impl<S: Real> LaneParams<S> {
    /// Validates in `S` and builds a parameter set with σ′/T′ = σ/T: the
    /// domains of [`Params`] (whose ends are `f32` values or round up to
    /// one, so an `f32` value passes here exactly when its widened value
    /// passes in `f64`).
    ///
    /// # Errors
    /// [`InputError::OutOfRange`] naming the first parameter outside its domain.
    #[inline(always)] // so that a caller mapping the error to a code drops its strings
    pub fn new(slope: S, beta: S, n: S, a: S) -> Result<Self, InputError> {
        Self::untied(slope, slope, beta, n, a)
    }

    /// [`LaneParams::new`] with the lower boundary's own σ′/T′.
    ///
    /// # Errors
    /// [`InputError::OutOfRange`] naming the first parameter outside its domain.
    #[inline(always)]
    pub fn untied(slope: S, sub_slope: S, beta: S, n: S, a: S) -> Result<Self, InputError> {
        Ok(Self::rounded(
            check_param(Param::Slope, slope)?,
            check_param(Param::SubSlope, sub_slope)?,
            check_param(Param::Beta, beta)?,
            check_param(Param::N, n)?,
            check_param(Param::A, a)?,
        ))
    }

    fn rounded(slope: S, sub_slope: S, beta: S, n: S, a: S) -> Self {
        let inv_slope2 = inverse_slope_squared(slope);
        Self {
            slope,
            sub_slope,
            beta,
            n,
            a,
            inv_slope2,
            // Tied, the same value (and no second division).
            inv_sub_slope2: if sub_slope == slope {
                inv_slope2
            } else {
                inverse_slope_squared(sub_slope)
            },
        }
    }

    /// RMS slope σ/T.
    #[must_use]
    pub fn slope(&self) -> S {
        self.slope
    }
    /// RMS slope σ′/T′ of the lower boundary.
    #[must_use]
    pub fn sub_slope(&self) -> S {
        self.sub_slope
    }
    /// Balance β.
    #[must_use]
    pub fn beta(&self) -> S {
        self.beta
    }
    /// Refractive index n.
    #[must_use]
    pub fn n(&self) -> S {
        self.n
    }
    /// Fractional absorption a.
    #[must_use]
    pub fn a(&self) -> S {
        self.a
    }
}

/// Every term of the model at one geometry per lane (un-normalised, K = k = 1).
#[derive(Clone, Copy, Debug)]
pub struct Components<L> {
    /// `f(θi, n)` (eq. 6).
    pub fresnel_in: L,
    /// `f(θs′, 1/n)` (eq. 6).
    pub fresnel_out: L,
    /// `A1 = a cos²θi (1 − f(θi, n))` (eq. 10).
    pub absorb_in: L,
    /// `A2 = a cos²θs2 (1 − f(θs′, 1/n))` (eqs. 11, 14).
    pub absorb_out: L,
    /// Surface radiance `L^sf` (eq. 1 or 2).
    pub surface: L,
    /// Subsurface radiance `L^sb` (eq. 12 or 13).
    pub subsurface: L,
    /// Total radiance `β L^sb + (1 − β) L^sf` (eq. 8).
    pub total: L,
}

impl<L: Copy> Components<L> {
    /// Field names in [`Components::to_array`] order (the `laminar eval` CSV columns).
    pub const NAMES: [&'static str; 7] = [
        "fresnel_in",
        "fresnel_out",
        "absorb_in",
        "absorb_out",
        "surface",
        "subsurface",
        "total",
    ];

    /// The seven fields in [`Components::NAMES`] order.
    #[must_use]
    pub fn to_array(&self) -> [L; 7] {
        [
            self.fresnel_in,
            self.fresnel_out,
            self.absorb_in,
            self.absorb_out,
            self.surface,
            self.subsurface,
            self.total,
        ]
    }
}

/// Total radiance `β L^sb + (1 − β) L^sf` (eq. 8) from its two components.
#[inline]
#[must_use]
pub fn mix<L: Lane>(beta: L, subsurface: L, surface: L) -> L {
    beta * subsurface + (L::c(1.0) - beta) * surface
}

/// Evaluates every component of the model (eqs. 1–14) at `g`.
/// Accuracy per field: the table in the crate docs (Accuracy); `total`
/// within 9.9 ulps (f64) and 6.2 (f32), plus the Gaussian-tail allowance.
#[must_use]
pub fn components<L: Lane>(g: &Geometry<L>, corr: Correlation, p: &Params) -> Components<L> {
    components_in(g, corr, &p.in_precision())
}

/// [`components`] with the parameters already in the lane precision.
#[must_use]
pub fn components_in<L: Lane>(
    g: &Geometry<L>,
    corr: Correlation,
    p: &LaneParams<L::Scalar>,
) -> Components<L> {
    let iface = Interface::new(g, L::splat(p.n));
    let a = L::splat(p.a);
    let surface = surface_radiance(g, corr, L::splat(p.inv_slope2));
    let subsurface =
        subsurface_base(&iface, corr, L::splat(p.inv_sub_slope2)) * absorption_factor(g, a);
    Components {
        fresnel_in: iface.fresnel_in,
        fresnel_out: iface.fresnel_out,
        absorb_in: absorbed(a, g.cos_i, iface.transmit_in),
        absorb_out: absorbed(a, g.cos_s, iface.transmit_out),
        surface,
        subsurface,
        total: mix(L::splat(p.beta), subsurface, surface),
    }
}

/// Total radiance (eq. 8), computing only the terms with non-zero weight:
///
/// ```
/// use laminar_brdf_core::{components, total_radiance, Angles, Correlation, Geometry, Params};
/// let g = Geometry::<f64>::splat(&Angles::new(0.3, 0.9, 2.1)?);
/// let p = Params::new(0.5, 0.0, 1.45, 0.3)?; // β = 0: the surface term only
/// let t = total_radiance(&g, Correlation::Gaussian, &p);
/// assert_eq!(t.to_bits(), components(&g, Correlation::Gaussian, &p).total.to_bits());
/// # Ok::<(), laminar_brdf_core::InputError>(())
/// ```
///
/// no subsurface work at β = 0, no surface work at β = 1, no absorption
/// work at a = 0. Bitwise equal to [`components`]`.total`.
#[must_use]
pub fn total_radiance<L: Lane>(g: &Geometry<L>, corr: Correlation, p: &Params) -> L {
    total_radiance_in(g, corr, &p.in_precision())
}

/// [`total_radiance`] with the parameters already in the lane precision:
/// the `f32` path without any `f64` operation.
#[must_use]
pub fn total_radiance_in<L: Lane>(
    g: &Geometry<L>,
    corr: Correlation,
    p: &LaneParams<L::Scalar>,
) -> L {
    let zero = L::c(0.0);
    let (one, none) = (L::Scalar::c(1.0), L::Scalar::c(0.0));
    let surface = if p.beta < one {
        surface_radiance(g, corr, L::splat(p.inv_slope2))
    } else {
        zero
    };
    let subsurface = if p.beta > none {
        let iface = Interface::new(g, L::splat(p.n));
        let base = subsurface_base(&iface, corr, L::splat(p.inv_sub_slope2));
        if p.a > none {
            base * absorption_factor(g, L::splat(p.a))
        } else {
            base
        }
    } else {
        zero
    };
    mix(L::splat(p.beta), subsurface, surface)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::param::Input;

    #[test]
    fn invalid_parameters_are_rejected_by_name() {
        let e = Params::new(0.5, 0.5, 0.9, 0.0).unwrap_err();
        assert!(matches!(
            e,
            InputError::OutOfRange {
                input: Input::Param(Param::N),
                ..
            }
        ));
        assert!(Params::new(0.0, 0.5, 1.3, 0.0).is_err());
        assert!(Params::new(-1.0, 0.5, 1.3, 0.0).is_err());
        assert!(Params::new(0.5, 1.5, 1.3, 0.0).is_err());
        assert!(Params::new(0.5, 0.5, 1.3, -0.1).is_err());
        assert!(Params::new(0.5, 0.5, 1.3, 1.1).is_err());
        assert!(Params::new(f64::NAN, 0.5, 1.3, 0.0).is_err());
        assert!(Params::new(0.5, 0.5, f64::INFINITY, 0.0).is_err());
        assert!(Params::new(0.12, 0.01, 1.3, 0.0).is_ok());
    }

    #[test]
    fn f32_validation_accepts_what_f64_validation_accepts() {
        // Around every end of every domain, each f32 passes in f32 exactly
        // when its widened value passes in f64.
        let ends = [SLOPE_MIN, SLOPE_MAX, 0.0, 1.0, INDEX_MAX];
        for &end in &ends {
            let first = (end as f32).to_bits().saturating_sub(3);
            for v in first..first + 7 {
                let x = f32::from_bits(v);
                for k in 0..4 {
                    let mut f = [0.5f32, 0.5, 1.5, 0.5];
                    f[k] = x;
                    let p32 = LaneParams::<f32>::new(f[0], f[1], f[2], f[3]);
                    let p64 = Params::new(f[0] as f64, f[1] as f64, f[2] as f64, f[3] as f64);
                    assert_eq!(p32.is_ok(), p64.is_ok(), "parameter {k} = {x:e}");
                    if let (Ok(a), Ok(b)) = (p32, p64) {
                        assert_eq!(a, b.in_precision::<f32>());
                    }
                }
            }
        }
        assert!(LaneParams::<f32>::new(f32::NAN, 0.5, 1.5, 0.5).is_err());
    }

    #[test]
    fn lane_precision_evaluation_is_bitwise_the_f64_parameter_one() {
        use crate::geometry::Angles;
        let g = Geometry::<f32>::splat(&Angles::new(0.3, 0.9, 2.1).unwrap());
        for (s, b, n, a) in [
            (0.5, 0.4, 1.45, 0.2),
            (0.12, 0.0, 1.3, 0.0),
            (4.04, 1.0, 1.5, 1.0),
        ] {
            let p = Params::new(s, b, n, a).unwrap();
            let q = LaneParams::<f32>::new(s as f32, b as f32, n as f32, a as f32).unwrap();
            for corr in [Correlation::Gaussian, Correlation::Exponential] {
                let want = total_radiance(&g, corr, &p).to_bits();
                assert_eq!(total_radiance_in(&g, corr, &q).to_bits(), want);
                assert_eq!(components_in(&g, corr, &q).total.to_bits(), want);
            }
        }
    }

    /// Untied, the surface term is the tied model's at σ/T and the
    /// subsurface term the tied model's at σ′/T′, bit for bit, in every
    /// lane type; tied (σ′/T′ = σ/T) it is the tied model.
    #[test]
    fn untied_terms_are_the_tied_models_at_each_slope() {
        use crate::geometry::Angles;
        use crate::lane::Lane;
        use wide::{f32x8, f64x4};
        fn check<L: Lane>(g: &Geometry<L>, corr: Correlation, top: f64, sub: f64) {
            let (beta, n, a) = (0.4, 1.45, 0.3);
            let untied = Params::untied(top, sub, beta, n, a).unwrap();
            let at_top = components(g, corr, &Params::new(top, beta, n, a).unwrap());
            let at_sub = components(g, corr, &Params::new(sub, beta, n, a).unwrap());
            let c = components(g, corr, &untied);
            let bits = |x: L| -> [u64; 8] {
                core::array::from_fn(|i| {
                    if i < L::LANES {
                        x.lane(i).to_f64().to_bits()
                    } else {
                        0
                    }
                })
            };
            assert_eq!(bits(c.surface), bits(at_top.surface));
            assert_eq!(bits(c.subsurface), bits(at_sub.subsurface));
            assert_eq!(bits(total_radiance(g, corr, &untied)), bits(c.total));
        }
        let angles = Angles::new(0.3, 0.9, 2.1).unwrap();
        for corr in [Correlation::Gaussian, Correlation::Exponential] {
            for (top, sub) in [(0.12, 0.9), (2.0, 0.05), (0.5, 0.5)] {
                check(&Geometry::<f64>::splat(&angles), corr, top, sub);
                check(&Geometry::<f32>::splat(&angles), corr, top, sub);
                check(&Geometry::<f64x4>::splat(&angles), corr, top, sub);
                check(&Geometry::<f32x8>::splat(&angles), corr, top, sub);
            }
        }
        let e = Params::untied(0.5, 0.0, 0.5, 1.3, 0.0).unwrap_err();
        assert!(matches!(
            e,
            InputError::OutOfRange {
                input: Input::Param(Param::SubSlope),
                ..
            }
        ));
    }
}
