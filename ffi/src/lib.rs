//! # laminar-ffi
//!
//! The C ABI of `laminar-core`: the absorptive scattering model (Dahlan &
//! Hancock, ICPR 2016) evaluated at arrays of geometries in caller-owned
//! buffers. `no_std`, no allocation, no panics on any input: every function
//! returns a [`Status`], and writes its outputs only when it returns
//! [`Status::Ok`]. The header `include/laminar.h` is generated from this
//! file by cbindgen (`ffi/tests/header.rs` fails when it is stale);
//! `examples/evaluate.c` is a C program that uses it.
//!
//! Angles are in the paper's frame, in radians (θi, θs ∈ [0, π/2],
//! φs ∈ [−π, π]; the repository's docs/conventions.md §1). Parameters are
//! checked as `laminar_core::Params::new` checks them.
//!
//! On targets without SIMD (Cortex-M) the scalar f32 path is the one to
//! use: it gives the same bits as every other target's.

#![no_std]

// On a hosted target the standard library provides the panic handler (no
// function here can panic; the handler is never reached). On bare metal
// this crate provides one, so that a C firmware can link the static library.
#[cfg(not(target_os = "none"))]
extern crate std;

mod buffers;

use laminar_core::{components, total_radiance, Angles, Correlation, Geometry, InputError, Params};

/// What a call did. `Ok` is 0; every other value names what was wrong.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// Done: the outputs are written.
    Ok = 0,
    /// A pointer was null while its count was positive.
    NullPointer = 1,
    /// The correlation was neither 0 (exponential) nor 1 (Gaussian).
    BadCorrelation = 2,
    /// σ/T outside [1e-3, 1e3] or not finite.
    BadSlope = 3,
    /// β outside [0, 1] or not finite.
    BadBeta = 4,
    /// n outside [1, 10] or not finite.
    BadN = 5,
    /// a outside [0, 1] or not finite.
    BadA = 6,
    /// θi outside [0, π/2] or not finite.
    BadThetaI = 7,
    /// θs outside [0, π/2] or not finite.
    BadThetaS = 8,
    /// φs outside [−π, π] or not finite.
    BadPhiS = 9,
}

/// The model's parameters: RMS slope σ/T, balance β (eq. 8), refractive
/// index n, absorption a.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaminarParams {
    /// σ/T.
    pub slope: f64,
    /// β.
    pub beta: f64,
    /// n.
    pub n: f64,
    /// a (0: the Ragheb–Hancock model).
    pub a: f64,
}

/// A geometry in the paper's frame (radians).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaminarAngles {
    /// Incidence angle θi.
    pub theta_i: f64,
    /// Scattering angle θs.
    pub theta_s: f64,
    /// Scattering azimuth φs.
    pub phi_s: f64,
}

/// Components per geometry written by [`laminar_components_f64`], in this
/// order: Fresnel in, Fresnel out, absorption in, absorption out, surface
/// term, subsurface term, total (eq. 8).
pub const LAMINAR_COMPONENTS: usize = 7;

fn status_of(e: InputError) -> Status {
    match e {
        InputError::OutOfRange { name, .. } => match name {
            "slope" => Status::BadSlope,
            "beta" => Status::BadBeta,
            "n" => Status::BadN,
            "a" => Status::BadA,
            "theta_i" => Status::BadThetaI,
            "theta_s" => Status::BadThetaS,
            _ => Status::BadPhiS,
        },
        _ => Status::NullPointer,
    }
}

fn correlation(code: u32) -> Result<Correlation, Status> {
    match code {
        0 => Ok(Correlation::Exponential),
        1 => Ok(Correlation::Gaussian),
        _ => Err(Status::BadCorrelation),
    }
}

fn params(p: &LaminarParams) -> Result<Params, Status> {
    Params::new(p.slope, p.beta, p.n, p.a).map_err(status_of)
}

fn angles(a: &LaminarAngles) -> Result<Angles, Status> {
    Angles::new(a.theta_i, a.theta_s, a.phi_s).map_err(status_of)
}

fn status(result: Result<(), Status>) -> Status {
    result.err().unwrap_or(Status::Ok)
}

/// Evaluates `total` into `out[k]` for each of the `count` geometries
/// `angles[k]` (eq. 8 in `L` precision, as `laminar_core::total_radiance`).
fn evaluate<L: laminar_core::Lane>(
    corr: u32,
    p: &LaminarParams,
    angles_in: *const LaminarAngles,
    count: usize,
    out: *mut L,
    each: impl Fn(&Geometry<L>, Correlation, &Params) -> L,
) -> Result<(), Status> {
    let corr = correlation(corr)?;
    let p = params(p)?;
    let input = buffers::input(angles_in, count)?;
    // Every geometry is checked before anything is written.
    for a in input {
        angles(a)?;
    }
    let out = buffers::output(out, count)?;
    for (slot, a) in out.iter_mut().zip(input) {
        let g = Geometry::<L>::splat(&angles(a)?);
        *slot = each(&g, corr, &p);
    }
    Ok(())
}

/// The exported functions. `#[no_mangle]` counts as unsafe code (two
/// libraries exporting one name is undefined behaviour at link time); the
/// names all start with `laminar_`.
#[allow(unsafe_code)]
mod exports {
    use super::*;

    /// Checks parameters: [`Status::Ok`] or the first one out of its domain.
    #[no_mangle]
    pub extern "C" fn laminar_validate_params(p: LaminarParams) -> Status {
        status(params(&p).map(|_| ()))
    }

    /// Checks a geometry: [`Status::Ok`] or the first angle out of range.
    #[no_mangle]
    pub extern "C" fn laminar_validate_angles(a: LaminarAngles) -> Status {
        status(angles(&a).map(|_| ()))
    }

    /// The total radiance (eq. 8) in f32 at `count` geometries into `out`
    /// (`count` floats). `corr`: 0 exponential, 1 Gaussian.
    #[no_mangle]
    pub extern "C" fn laminar_total_radiance_f32(
        corr: u32,
        p: LaminarParams,
        angles: *const LaminarAngles,
        count: usize,
        out: *mut f32,
    ) -> Status {
        status(evaluate(
            corr,
            &p,
            angles,
            count,
            out,
            total_radiance::<f32>,
        ))
    }

    /// The total radiance (eq. 8) in f64 at `count` geometries into `out`.
    #[no_mangle]
    pub extern "C" fn laminar_total_radiance_f64(
        corr: u32,
        p: LaminarParams,
        angles: *const LaminarAngles,
        count: usize,
        out: *mut f64,
    ) -> Status {
        status(evaluate(
            corr,
            &p,
            angles,
            count,
            out,
            total_radiance::<f64>,
        ))
    }

    /// Every component (in the order of [`LAMINAR_COMPONENTS`]) in f64 at
    /// `count` geometries into `out` (`7 · count` doubles, geometry-major).
    #[no_mangle]
    pub extern "C" fn laminar_components_f64(
        corr: u32,
        p: LaminarParams,
        angles_in: *const LaminarAngles,
        count: usize,
        out: *mut f64,
    ) -> Status {
        let run = || -> Result<(), Status> {
            let corr = correlation(corr)?;
            let p = params(&p)?;
            let input = buffers::input(angles_in, count)?;
            for a in input {
                angles(a)?;
            }
            let slots = count
                .checked_mul(LAMINAR_COMPONENTS)
                .ok_or(Status::NullPointer)?;
            let out = buffers::output(out, slots)?;
            for (chunk, a) in out.chunks_exact_mut(LAMINAR_COMPONENTS).zip(input) {
                let g = Geometry::<f64>::splat(&angles(a)?);
                chunk.copy_from_slice(&components(&g, corr, &p).to_array());
            }
            Ok(())
        };
        status(run())
    }
}

pub use exports::*;

#[cfg(target_os = "none")]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    // Unreachable: no function of this crate panics (checked by linking
    // the firmware image without a panic path).
    loop {}
}
