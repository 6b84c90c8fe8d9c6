//! The probe cases of the firmware test (`ffi/firmware`, run on an
//! emulated Cortex-M4 by `ffi/tests/firmware.rs`): the core's parity cases
//! ([`laminar_core::probe`]) in the C ABI's types.

use crate::{LaminarAngles, LaminarParams};
pub use laminar_core::probe::{GEOMETRIES, PARAMS};

/// Geometry `g` ([`laminar_core::probe::angles`]).
pub fn angles(g: u32) -> LaminarAngles {
    let (theta_i, theta_s, phi_s) = laminar_core::probe::angles(g);
    LaminarAngles {
        theta_i,
        theta_s,
        phi_s,
    }
}

/// Parameter set `j` ([`laminar_core::probe::params`]).
pub fn params(j: u32) -> LaminarParams {
    let (slope, beta, n, a) = laminar_core::probe::params(j);
    LaminarParams { slope, beta, n, a }
}
