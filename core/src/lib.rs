//! # laminar-core
//!
//! `no_std` evaluation of the absorptive scattering model for rough laminar
//! surfaces (H. A. Dahlan and E. R. Hancock, ICPR 2016), the Ragheb–Hancock
//! model it extends (`a = 0`), and the Jensen and Oren–Nayar baselines.
//! Equation numbers refer to the paper; "docs/conventions.md §N" to the
//! repository's statement of what the paper leaves open, which also indexes
//! each equation to the function that computes it.
//!
//! ## One implementation, three lane types
//! Every equation is written once against [`Lane`], implemented for `f32`,
//! `f64` and `wide::f32x8` (eight measurement geometries per vector).
//!
//! ## Determinism policy
//! * The `f32x8` path is **bitwise identical** to the scalar `f32` path, lane
//!   by lane, on every target: only IEEE-exact operations are used
//!   (`+ − × ÷ sqrt`, comparisons, selects, exact power-of-two scaling), never
//!   `mul_add`, vendor `exp` or horizontal reductions. [`exp`](exp::exp) is our
//!   own, written once generically. The workspace's `clippy.toml` forbids
//!   `wide`'s fused, approximate and horizontal operations, so this is a lint.
//! * The `f64` path is the accuracy reference. The `f32` path is checked
//!   against it by `core/tests/error_budgets.rs`, in the scaled measure that
//!   file states (absolute for Fresnel and absorption, relative to a leading
//!   factor for the radiances); per-function error bounds in plain relative
//!   ulps are not stated yet.
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
#![forbid(unsafe_code)]

#[cfg(test)]
extern crate std;

pub mod absorption;
pub mod baselines;
pub mod error;
pub mod exp;
pub mod fresnel;
pub mod geometry;
pub mod lane;
pub mod measures;
pub mod radiance;
pub mod subsurface;
pub mod surface;

pub use absorption::{absorbed, attenuation, energy_budget, transmitted, EnergyBudget};
pub use error::InputError;
pub use fresnel::{fresnel, fresnel_from_cosines, refract_cos, solid_angle};
pub use geometry::{wrap_pi, Angles, Geometry};
pub use lane::{Lane, Mask, Real};
pub use measures::{chi_square_per_dof, normalise_by_max, rms_error, ChiSquare, Normalisation};
pub use radiance::{components, mix, total_radiance, Components, Params};
pub use subsurface::{absorption_factor, subsurface_base, subsurface_radiance, Interface};
pub use surface::{inverse_slope_squared, surface_radiance, Correlation};
pub use wide::f32x8;
