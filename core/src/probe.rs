//! The cases at which the cross-target parity tests probe the core: the
//! wasm32 probe (`core/wasm-probe`) and the Cortex-M firmware test
//! (`ffi/firmware`) evaluate the model at these geometries and parameter
//! sets on the target and compare with the host bit for bit.

use core::f64::consts::{FRAC_PI_2, PI};

/// Geometries probed (a multiple of 8).
pub const GEOMETRIES: u32 = 64;
/// Parameter sets probed.
pub const PARAMS: u32 = 6;

/// Geometry `g` as (θi, θs, φs), inside the domain of
/// [`crate::Angles::new`]: hard cases first (normal, grazing, φs wrap),
/// then a deterministic spread over the hemisphere.
pub fn angles(g: u32) -> (f64, f64, f64) {
    let hard = [
        (0.0, 0.0, 0.0),
        (0.0, 1e-6, 0.0),
        (FRAC_PI_2, FRAC_PI_2, 0.0),
        (FRAC_PI_2, 0.3, PI),
        (0.7, 0.7, 0.0),
        (0.7, 0.7, -PI),
        (1.2, FRAC_PI_2, 2.0),
        (1e-6, 1.4, -3.0),
    ];
    if let Some(&h) = hard.get(g as usize) {
        return h;
    }
    let t = g as f64;
    (
        FRAC_PI_2 * ((t * 0.618_033_988_75) % 1.0),
        FRAC_PI_2 * ((t * 0.414_213_562_37) % 1.0),
        PI * (2.0 * ((t * 0.732_050_807_57) % 1.0) - 1.0),
    )
}

/// Parameter set `j` (taken modulo [`PARAMS`]) as (σ/T, β, n, a), inside the
/// domain of [`crate::Params::new`]: the ends of the paper grid and of the
/// domain, and interior points.
pub fn params(j: u32) -> (f64, f64, f64, f64) {
    [
        (0.12, 0.01, 1.3, 0.0),
        (0.52, 0.39, 1.42, 0.17),
        (4.04, 1.0, 1.5, 1.0),
        (1e-3, 0.5, 1.0, 0.5),
        (1e3, 0.0, 2.5, 0.9),
        (1.48, 0.73, 1.44, 0.05),
    ][(j % PARAMS) as usize]
}
