//! # laminar-brdf-core
//!
//! `no_std` evaluation of the absorptive scattering model for rough laminar
//! surfaces (H. A. Dahlan and E. R. Hancock, ICPR 2016), the Ragheb–Hancock
//! model it extends (`a = 0`), and the Jensen and Oren–Nayar baselines.
//! Equation numbers refer to the paper; "docs/conventions.md §N" to the
//! repository's statement of what the paper leaves open, which also indexes
//! each equation to the function that computes it.
//!
//! ```
//! use laminar_brdf_core::{components, total_radiance, Angles, Correlation, Geometry, Params};
//! // σ/T = 0.5, β = 0.4, n = 1.45, a = 0.2; θi = 30°, θs = 40°, φs = 1 rad.
//! let p = Params::new(0.5, 0.4, 1.45, 0.2)?;
//! let a = Angles::new(30f64.to_radians(), 40f64.to_radians(), 1.0)?;
//! let c = components(&Geometry::<f64>::splat(&a), Correlation::Exponential, &p);
//! // Eq. 8 mixes the two terms with β.
//! assert!((c.total - (0.4 * c.subsurface + 0.6 * c.surface)).abs() < 1e-15);
//! // The same in f32, and eight geometries at once in f32x8 (same bits per lane).
//! let one = total_radiance(&Geometry::<f32>::splat(&a), Correlation::Exponential, &p);
//! let eight = total_radiance(&Geometry::<laminar_brdf_core::f32x8>::splat(&a), Correlation::Exponential, &p);
//! assert_eq!(eight.to_array()[5].to_bits(), one.to_bits());
//! # Ok::<(), laminar_brdf_core::InputError>(())
//! ```
//!
//! ## One implementation, five lane types
//! Every equation is written once against [`Lane`], implemented for `f32`,
//! `f64`, `wide::f32x8` (eight measurement geometries per vector),
//! `wide::f64x4` (four, for the host's f64 fits) and, on x86-64, four
//! `f64` in an AVX register, which [`simd::run`] hands to a kernel when the
//! processor has AVX2 (chosen when the program runs; a build for every
//! x86-64 processor otherwise runs `wide::f64x4` as two SSE halves).
//!
//! ## Determinism policy
//! * The `f32x8` path is **bitwise identical** to the scalar `f32` path, and
//!   the `f64x4` and AVX2 paths to the scalar `f64` path, lane by lane, on
//!   every target: only IEEE-exact operations are used
//!   (`+ − × ÷ sqrt`, comparisons, selects, exact power-of-two scaling), never
//!   `mul_add`, vendor `exp` or horizontal reductions. [`exp`](exp::exp) is our
//!   own, written once generically. The workspace's `clippy.toml` forbids
//!   `wide`'s fused, approximate and horizontal operations, so this is a lint.
//! * Both paths are measured against a 256-bit reference (see Accuracy
//!   below); `core/tests/error_budgets.rs` also checks the f32 path against
//!   the f64 one.
//!
//! ## Accuracy
//! Every component against a 256-bit reference (`core/tests/accuracy.rs`,
//! `astro-float`), in plain relative ulps of the precision (below the normal
//! range an ulp is the subnormal spacing), over the whole accepted domain:
//! 60,154 cases (hard cases plus seeded random ones; the test runs 1,654 by
//! default and `LAMINAR_ACCURACY_CASES` more).
//!
//! | component | f64 | f32 |
//! |---|---|---|
//! | `fresnel_in` (eq. 6) | 7.10 | 6.43 |
//! | `fresnel_out` (eq. 6) | 6.39 | 6.95 |
//! | `absorb_in` (eq. 10) | 4.79 | 4.93 |
//! | `absorb_out` (eqs. 11, 14) | 4.41 | 4.25 |
//! | `surface` (eqs. 1–2) | 9.80 | 3.51 |
//! | `subsurface` (eqs. 12–13) | 8.42 | 6.80 |
//! | `total` (eq. 8) | 9.88 | 6.23 |
//!
//! The test asserts 16 ulps, with two stated exceptions: the Gaussian tail
//! `exp(−x/4)` has condition number `x/4` in `x = (T/σ)² v_xy²/v_z²`, which
//! carries six to eight roundings, so its error may reach `16 + 2x` ulps
//! (measured `1.40 x`); and [`exp`](exp::exp) flushes to 0 below its range,
//! so true values below about 5e-300 (f64) or 1e-25 (f32) may come out as 0.
//! The f32 path is measured at the f32-rounded parameters it evaluates.
//!
//! ## Validation and NaN policy
//! Validating constructors ([`Params::new`], [`Angles::new`], the baseline
//! coefficient constructors) reject out-of-domain input with an
//! [`InputError`] naming the value. The hot path then trusts its inputs: it
//! never panics, and for validated input it never returns NaN or ∞, including
//! the hard cases of docs/conventions.md §9 (normal and grazing incidence, `n = 1`,
//! total internal reflection, `a = 1`, extreme slopes, φs wrap).
//!
//! ## Compute only what is needed
//! [`total_radiance`] skips the subsurface term at β = 0, the surface term at
//! β = 1 and the absorption factor at a = 0. The building blocks
//! ([`Geometry`], [`Interface`], [`inverse_slope_squared`],
//! [`absorption_factor`]) let a search hoist terms that depend on geometry
//! only, on geometry and σ/T, on geometry and n, or on geometry and a.
#![no_std]
#![forbid(missing_docs)]
#![deny(unsafe_code)] // allowed in `sqrt` (one FPU instruction), `avx2` and `simd::run`

#[cfg(test)]
extern crate std;

pub mod absorption;
#[cfg(target_arch = "x86_64")]
mod avx2;
pub mod baselines;
pub mod error;
pub mod exp;
pub mod fresnel;
pub mod geometry;
pub mod lane;
pub mod linear;
pub mod measures;
pub mod onepass;
pub mod param;
pub mod prediction;
/// Test fixture shared with `laminar-brdf-ffi`, the firmware and the wasm probe:
/// not part of the API.
#[doc(hidden)]
pub mod probe;
pub mod radiance;
pub mod simd;
pub mod small_fit;
pub mod small_free_fit;
mod sqrt;
pub mod subsurface;
pub mod surface;
pub mod trig;

pub use absorption::{absorbed, attenuation, energy_budget, transmitted, EnergyBudget};
pub use error::InputError;
pub use fresnel::{
    fresnel, fresnel_from_cosines, fresnel_pair, refract_cos, solid_angle, transmittance,
    transmittance_from_cosines,
};
pub use geometry::{wrap_pi, Angles, Directions, Geometry};
pub use lane::{Lane, Mask, Real};
pub use measures::{chi_square_per_dof, normalise_by_max, rms_error, ChiSquare, Normalisation};
pub use param::{Angle, Input, Param};
pub use prediction::Scaling;
pub use radiance::{
    components, components_in, mix, total_radiance, total_radiance_in, Components, LaneParams,
    Params,
};
pub use subsurface::{absorption_factor, subsurface_base, subsurface_radiance, Interface};
pub use surface::{inverse_slope_squared, surface_radiance, Correlation};
pub use wide::{f32x8, f64x4};
