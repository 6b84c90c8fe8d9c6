//! The baseline models the paper compares against (docs/conventions.md §7),
//! each behind one trait, [`BaselineModel`]: its per-geometry terms (built
//! once per measurement), its parameter-only coefficients (built once per
//! parameter pair, validated) and its radiance from the two. [`Baseline`]
//! names them at run time, and [`Baseline::with`] is the one place a name
//! becomes a type.
//!
//! A new baseline is a module here with a type implementing
//! [`BaselineModel`], a variant of [`Baseline`] (and its arm in
//! [`Baseline::with`]), its parameters in [`crate::param`], and its
//! descriptor in the fitting library.
//!
//! ```
//! use laminar_brdf_core::baselines::{Baseline, BaselineModel, OrenNayar};
//! use laminar_brdf_core::Angles;
//! let a = Angles::new(0.3, 0.5, 1.0)?;
//! let g = <OrenNayar as BaselineModel>::geometry::<f64>(|_| a);
//! let k = <OrenNayar as BaselineModel>::coefficients::<f64>([0.0, 0.8])?;
//! // A smooth Oren–Nayar surface is Lambertian: (ρ/π) cos θi.
//! let l = OrenNayar::radiance(&g, &k);
//! assert!((l - 0.8 / core::f64::consts::PI * libm::cos(0.3)).abs() < 1e-15);
//! assert_eq!(Baseline::OrenNayar.params(), OrenNayar::PARAMS);
//! # Ok::<(), laminar_brdf_core::InputError>(())
//! ```

use crate::error::InputError;
use crate::geometry::Angles;
use crate::lane::{Lane, Real};
use crate::param::Param;

pub mod jensen;
pub mod oren_nayar;

/// A baseline model: geometry → coefficients → radiance, written once
/// against [`Lane`] (so the f32x8 path is bitwise the scalar f32 one).
pub trait BaselineModel: 'static {
    /// The model's two parameters, in output order.
    const PARAMS: &'static [Param; 2];
    /// The per-geometry terms.
    type Geometry<L: Lane>: Copy + core::fmt::Debug + Send + Sync;
    /// The parameter-only coefficients, in the lanes' scalar precision.
    type Coefficients<S: Real>: Copy + core::fmt::Debug;

    /// The terms of lane `i` from `angles(i)`.
    fn geometry<L: Lane>(angles: impl FnMut(usize) -> Angles) -> Self::Geometry<L>;

    /// The coefficients at `params` (in [`BaselineModel::PARAMS`]' order).
    ///
    /// # Errors
    /// [`InputError::OutOfRange`] naming the parameter outside its domain.
    fn coefficients<S: Real>(params: [f64; 2]) -> Result<Self::Coefficients<S>, InputError>;

    /// The un-normalised radiance `f cos θi`.
    fn radiance<L: Lane>(g: &Self::Geometry<L>, k: &Self::Coefficients<L::Scalar>) -> L;
}

/// Jensen et al. 2001 (σa, σs′): [`jensen`].
#[derive(Debug, Clone, Copy)]
pub struct Jensen;

/// The full Oren–Nayar model (σ, ρ): [`oren_nayar`].
#[derive(Debug, Clone, Copy)]
pub struct OrenNayar;

impl BaselineModel for Jensen {
    const PARAMS: &'static [Param; 2] = &[Param::SigmaA, Param::SigmaS];
    type Geometry<L: Lane> = jensen::JensenGeometry<L>;
    type Coefficients<S: Real> = jensen::JensenCoefficients<S>;

    fn geometry<L: Lane>(angles: impl FnMut(usize) -> Angles) -> Self::Geometry<L> {
        jensen::JensenGeometry::from_lanes(angles)
    }

    fn coefficients<S: Real>(
        [sigma_a, sigma_s]: [f64; 2],
    ) -> Result<Self::Coefficients<S>, InputError> {
        jensen::JensenCoefficients::new(sigma_a, sigma_s)
    }

    #[inline]
    fn radiance<L: Lane>(g: &Self::Geometry<L>, k: &Self::Coefficients<L::Scalar>) -> L {
        jensen::jensen_radiance(g, k)
    }
}

impl BaselineModel for OrenNayar {
    const PARAMS: &'static [Param; 2] = &[Param::Sigma, Param::Rho];
    type Geometry<L: Lane> = oren_nayar::OrenNayarGeometry<L>;
    type Coefficients<S: Real> = oren_nayar::OrenNayarCoefficients<S>;

    fn geometry<L: Lane>(angles: impl FnMut(usize) -> Angles) -> Self::Geometry<L> {
        oren_nayar::OrenNayarGeometry::from_lanes(angles)
    }

    fn coefficients<S: Real>([sigma, rho]: [f64; 2]) -> Result<Self::Coefficients<S>, InputError> {
        oren_nayar::OrenNayarCoefficients::new(sigma, rho)
    }

    #[inline]
    fn radiance<L: Lane>(g: &Self::Geometry<L>, k: &Self::Coefficients<L::Scalar>) -> L {
        oren_nayar::oren_nayar_radiance(g, k)
    }
}

/// Work generic over a baseline's type, run by [`Baseline::with`].
pub trait WithBaseline {
    /// What the work gives.
    type Output;
    /// The work for the baseline `B`.
    fn run<B: BaselineModel>(self) -> Self::Output;
}

/// A baseline named at run time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Baseline {
    /// [`Jensen`].
    Jensen,
    /// [`OrenNayar`].
    OrenNayar,
}

impl Baseline {
    /// Every baseline.
    pub const ALL: [Baseline; 2] = [Baseline::Jensen, Baseline::OrenNayar];

    /// Runs `work` on this baseline's type: the one place a baseline's name
    /// becomes its [`BaselineModel`].
    pub fn with<W: WithBaseline>(self, work: W) -> W::Output {
        match self {
            Self::Jensen => work.run::<Jensen>(),
            Self::OrenNayar => work.run::<OrenNayar>(),
        }
    }

    /// The baseline's parameters ([`BaselineModel::PARAMS`]).
    #[must_use]
    pub fn params(self) -> &'static [Param; 2] {
        struct Params;
        impl WithBaseline for Params {
            type Output = &'static [Param; 2];
            fn run<B: BaselineModel>(self) -> &'static [Param; 2] {
                B::PARAMS
            }
        }
        self.with(Params)
    }
}
