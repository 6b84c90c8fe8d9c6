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
// this crate provides one, so that a C firmware can link the static library
// (and a Rust firmware uses it too).
#[cfg(not(target_os = "none"))]
extern crate std;

mod buffers;
pub mod probe;

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

/// The correlation, the parameters and the `count` geometries at
/// `angles_in`, every one of them checked (before anything is written).
fn checked<'a>(
    corr: u32,
    p: &LaminarParams,
    angles_in: *const LaminarAngles,
    count: usize,
) -> Result<(Correlation, Params, &'a [LaminarAngles]), Status> {
    let corr = correlation(corr)?;
    let p = params(p)?;
    let input = buffers::input(angles_in, count)?;
    for a in input {
        angles(a)?;
    }
    Ok((corr, p, input))
}

/// Writes `width` values per geometry into `out` (`width · count` slots):
/// `each(geometry, correlation, parameters, slots)` for each of the
/// `count` checked geometries at `angles_in`.
fn evaluate<L: laminar_core::Lane>(
    (corr, p): (u32, &LaminarParams),
    (angles_in, count): (*const LaminarAngles, usize),
    (out, width): (*mut L, usize),
    each: impl Fn(&Geometry<L>, Correlation, &Params, &mut [L]),
) -> Result<(), Status> {
    let (corr, p, input) = checked(corr, p, angles_in, count)?;
    let slots = count.checked_mul(width).ok_or(Status::NullPointer)?;
    let out = buffers::output(out, slots)?;
    for (chunk, a) in out.chunks_exact_mut(width).zip(input) {
        let g = Geometry::<L>::splat(&angles(a)?);
        each(&g, corr, &p, chunk);
    }
    Ok(())
}

/// The total radiance (eq. 8) in `L` precision at `count` geometries.
fn total<L: laminar_core::Lane>(
    corr: u32,
    p: &LaminarParams,
    input: (*const LaminarAngles, usize),
    out: *mut L,
) -> Status {
    status(evaluate((corr, p), input, (out, 1), |g, c, p, slot| {
        slot[0] = total_radiance(g, c, p)
    }))
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
        total(corr, &p, (angles, count), out)
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
        total(corr, &p, (angles, count), out)
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
        let width = LAMINAR_COMPONENTS;
        status(evaluate(
            (corr, &p),
            (angles_in, count),
            (out, width),
            |g, c, p, chunk| chunk.copy_from_slice(&components(g, c, p).to_array()),
        ))
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

#[cfg(test)]
mod tests {
    use super::*;

    const P: LaminarParams = LaminarParams {
        slope: 0.8,
        beta: 0.3,
        n: 1.45,
        a: 0.2,
    };

    #[test]
    fn components_are_the_cores_and_bad_input_writes_nothing() {
        let geometries = [
            LaminarAngles {
                theta_i: 0.4,
                theta_s: 0.7,
                phi_s: 2.5,
            },
            LaminarAngles {
                theta_i: 1.2,
                theta_s: 0.1,
                phi_s: -1.0,
            },
        ];
        let mut out = [0.0f64; 2 * LAMINAR_COMPONENTS];
        let s = laminar_components_f64(1, P, geometries.as_ptr(), 2, out.as_mut_ptr());
        assert_eq!(s, Status::Ok);
        let p = Params::new(0.8, 0.3, 1.45, 0.2).unwrap();
        for (k, a) in geometries.iter().enumerate() {
            let g = Geometry::<f64>::splat(&angles(a).unwrap());
            let want = components(&g, Correlation::Gaussian, &p).to_array();
            let got = &out[k * LAMINAR_COMPONENTS..(k + 1) * LAMINAR_COMPONENTS];
            assert_eq!(got, &want[..]);
        }
        // The last component is the total.
        let mut total = [0.0f64; 2];
        laminar_total_radiance_f64(1, P, geometries.as_ptr(), 2, total.as_mut_ptr());
        assert_eq!(total[1], out[2 * LAMINAR_COMPONENTS - 1]);
        // Bad input: a status, and the output untouched.
        let mut untouched = [7.0f64; LAMINAR_COMPONENTS];
        let bad = LaminarParams { beta: 1.5, ..P };
        let s = laminar_components_f64(0, bad, geometries.as_ptr(), 1, untouched.as_mut_ptr());
        assert_eq!((s, untouched), (Status::BadBeta, [7.0; LAMINAR_COMPONENTS]));
        let s = laminar_components_f64(0, P, core::ptr::null(), 1, untouched.as_mut_ptr());
        assert_eq!(s, Status::NullPointer);
        let nan = LaminarAngles {
            phi_s: f64::NAN,
            ..geometries[0]
        };
        assert_eq!(laminar_validate_angles(nan), Status::BadPhiS);
        assert_eq!(laminar_validate_params(P), Status::Ok);
    }
}
