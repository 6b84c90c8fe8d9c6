//! # laminar-brdf-ffi
//!
//! The C ABI of `laminar-brdf-core`: the absorptive scattering model (Dahlan &
//! Hancock, ICPR 2016) evaluated at arrays of geometries in caller-owned
//! buffers. `no_std`, no allocation, no panics on any input: every function
//! returns a [`Status`], and writes its outputs only when it returns
//! [`Status::Ok`]. The header `include/laminar.h` is generated from this
//! file by cbindgen (`ffi/tests/header.rs` fails when it is stale);
//! `examples/evaluate.c` is a C program that uses it.
//!
//! Angles are in the paper's frame, in radians (θi, θs ∈ [0, π/2]; φs any
//! finite value in `double`, in [−π, π] in `float`; the repository's
//! docs/conventions.md §1). The header's opening comment states the rules
//! for buffers, counts and aliasing. Parameters are
//! checked as `laminar_brdf_core::Params::new` checks them.
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
mod fit;
mod geometry;
/// Test fixture shared with the firmware and its tests: not part of the API.
#[doc(hidden)]
pub mod probe;
mod scratch;

pub use fit::{
    LaminarFitResult, LaminarFreeFitResult, LaminarFreeGrid, LaminarGrid,
    LAMINAR_FIT_MAX_MEASUREMENTS,
};
pub use geometry::{LaminarAnglesF32, LaminarDirections, LaminarGeometry};
use laminar_brdf_core::{
    components_in, total_radiance_in, Angle, Angles, Correlation, Geometry, Input, InputError,
    Lane, LaneParams, Param, Params,
};
pub use scratch::{LaminarFitScratch, LAMINAR_FIT_SCRATCH_WORDS};

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
    /// φs not finite (`LaminarAngles`, in `double`: any finite φs, it is
    /// periodic), or outside [−π, π] (`LaminarAnglesF32`).
    BadPhiS = 9,
    /// A fit's measurement count was 0 or above `LAMINAR_FIT_MAX_MEASUREMENTS`.
    BadCount = 10,
    /// A fit's data break the library's data rule: a datum that is not
    /// finite, no positive datum, a negative datum beyond the max in
    /// magnitude, or a positive datum below 1e-100 of the max.
    BadData = 11,
    /// A fit's grid had an axis with no value, or a free fit's β box was
    /// empty (`beta_lo > beta_hi`).
    EmptyAxis = 12,
    /// A count whose values span more bytes than any buffer can (count ×
    /// element size above `PTRDIFF_MAX`); refused before any pointer is read.
    BadLength = 13,
    /// A free fit's standard uncertainty was not positive and finite, or
    /// so small against the data's max that its weight `(max/σ)²` passes
    /// `float`'s range.
    BadSigma = 14,
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

/// The untied model's parameters (`exp2`, `gauss2`: eqs. 3–4 with the
/// subsurface's own roughness): σ/T of the surface term, σ′/T′ of the
/// subsurface term, β, n, a. At `sub_slope == slope` it is
/// [`LaminarParams`], bit for bit.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaminarParamsUntied {
    /// σ/T.
    pub slope: f64,
    /// σ′/T′.
    pub sub_slope: f64,
    /// β.
    pub beta: f64,
    /// n.
    pub n: f64,
    /// a.
    pub a: f64,
}

/// The model's parameters in `f32`, for the `f32` functions: validated
/// and used in `f32` without any `f64` operation.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaminarParamsF32 {
    /// σ/T.
    pub slope: f32,
    /// β.
    pub beta: f32,
    /// n.
    pub n: f32,
    /// a (0: the Ragheb–Hancock model).
    pub a: f32,
}

/// A geometry in the paper's frame (radians): θi, θs ∈ [0, π/2], φs any
/// finite value (periodic).
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

/// The status of each input the core checks. The C ABI takes the layered
/// models' parameters and the paper frame's angles; the baselines'
/// parameters and the lab frame's angles never reach it (their arms
/// keep the match total).
#[inline(always)] // the match folds away where the error is built inline
pub(crate) fn status_of(e: InputError) -> Status {
    match e {
        InputError::OutOfRange { input, .. } => match input {
            Input::Param(Param::Slope | Param::SubSlope) => Status::BadSlope,
            Input::Param(Param::Beta) => Status::BadBeta,
            Input::Param(Param::N) => Status::BadN,
            Input::Param(Param::A) => Status::BadA,
            Input::Param(Param::SigmaA | Param::SigmaS | Param::Sigma | Param::Rho) => {
                Status::BadSlope
            }
            Input::Angle(Angle::ThetaI) => Status::BadThetaI,
            Input::Angle(Angle::ThetaS | Angle::ThetaV) => Status::BadThetaS,
            Input::Angle(Angle::PhiS | Angle::PhiI | Angle::PhiV) => Status::BadPhiS,
        },
        _ => Status::NullPointer,
    }
}

fn correlation(code: u32) -> Result<Correlation, Status> {
    Correlation::from_code(code).ok_or(Status::BadCorrelation)
}

/// A C parameter struct: checked into the core's [`Params`].
trait ToParams {
    fn params(&self) -> Result<Params, Status>;
}

impl ToParams for LaminarParams {
    fn params(&self) -> Result<Params, Status> {
        Params::new(self.slope, self.beta, self.n, self.a).map_err(status_of)
    }
}

impl ToParams for LaminarParamsUntied {
    fn params(&self) -> Result<Params, Status> {
        Params::untied(self.slope, self.sub_slope, self.beta, self.n, self.a).map_err(status_of)
    }
}

fn params(p: &impl ToParams) -> Result<Params, Status> {
    p.params()
}

#[inline(always)] // built in place: no copy of the parameters (a memcpy at "s")
fn params_f32(p: &LaminarParamsF32) -> Result<LaneParams<f32>, Status> {
    LaneParams::new(p.slope, p.beta, p.n, p.a).map_err(status_of)
}

pub(crate) fn angles(a: &LaminarAngles) -> Result<Angles, Status> {
    Angles::new(a.theta_i, a.theta_s, a.phi_s).map_err(status_of)
}

fn status(result: Result<(), Status>) -> Status {
    result.err().unwrap_or(Status::Ok)
}

/// The correlation, the parameters and the `count` geometries at
/// `angles_in`, every one of them checked (before anything is written).
fn checked<'a>(
    corr: u32,
    p: &impl ToParams,
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

/// What an evaluation writes per geometry: `width` values from
/// `each(geometry, correlation, parameters, slots)`.
struct Writer<F> {
    width: usize,
    each: F,
}

/// Writes `writer.width` values per geometry into `out` for each of the
/// `count` checked geometries at `angles_in` (parameters rounded to the
/// lane precision once per call).
fn evaluate<L: Lane>(
    (corr, p): (u32, &impl ToParams),
    (angles_in, count): (*const LaminarAngles, usize),
    out: *mut L,
    writer: Writer<impl Fn(&Geometry<L>, Correlation, &LaneParams<L::Scalar>, &mut [L])>,
) -> Result<(), Status> {
    let (corr, p, input) = checked(corr, p, angles_in, count)?;
    let p = p.in_precision::<L::Scalar>();
    let out = buffers::output(out, slots(count, writer.width)?)?;
    for (chunk, a) in out.chunks_exact_mut(writer.width).zip(input) {
        let g = Geometry::<L>::splat(&angles(a)?);
        (writer.each)(&g, corr, &p, chunk);
    }
    Ok(())
}

/// `count · width` output slots, or [`Status::BadLength`] when that
/// overflows (no buffer can hold it).
fn slots(count: usize, width: usize) -> Result<usize, Status> {
    count.checked_mul(width).ok_or(Status::BadLength)
}

/// Evaluates `each` at the `count` prebuilt `f32` geometries at
/// `geometries`, `width` values per geometry, into `out`.
fn evaluate_geometries(
    (corr, p): (u32, &LaminarParamsF32),
    (geometries, count): (*const LaminarGeometry, usize),
    out: *mut f32,
    writer: Writer<impl Fn(&Geometry<f32>, Correlation, &LaneParams<f32>, &mut [f32])>,
) -> Result<(), Status> {
    let corr = correlation(corr)?;
    let p = params_f32(p)?;
    let input = buffers::input(geometries, count)?;
    let out = buffers::output(out, slots(count, writer.width)?)?;
    for (chunk, g) in out.chunks_exact_mut(writer.width).zip(input) {
        (writer.each)(&(*g).into(), corr, &p, chunk);
    }
    Ok(())
}

/// Builds `count` geometries from `input` into `out` with `build`, after
/// `check` has passed every input (so nothing is written on bad input,
/// and nothing is built twice).
fn build_geometries<T>(
    (input, count): (*const T, usize),
    out: *mut LaminarGeometry,
    (check, build): (
        impl Fn(&T) -> Result<(), Status>,
        impl Fn(&T) -> Result<LaminarGeometry, Status>,
    ),
) -> Result<(), Status> {
    let input = buffers::input(input, count)?;
    for x in input {
        check(x)?;
    }
    let out = buffers::output(out, count)?;
    for (slot, x) in out.iter_mut().zip(input) {
        *slot = build(x)?;
    }
    Ok(())
}

fn total<L: Lane>(g: &Geometry<L>, c: Correlation, p: &LaneParams<L::Scalar>, slot: &mut [L]) {
    slot[0] = total_radiance_in(g, c, p);
}

fn all_components<L: Lane>(
    g: &Geometry<L>,
    c: Correlation,
    p: &LaneParams<L::Scalar>,
    chunk: &mut [L],
) {
    chunk.copy_from_slice(&components_in(g, c, p).to_array());
}

/// Every component in `L` precision at `count` geometries
/// ([`LAMINAR_COMPONENTS`] per geometry).
fn components_at<L: Lane>(
    corr: u32,
    p: &impl ToParams,
    input: (*const LaminarAngles, usize),
    out: *mut L,
) -> Status {
    let writer = Writer {
        width: LAMINAR_COMPONENTS,
        each: all_components::<L>,
    };
    status(evaluate((corr, p), input, out, writer))
}

/// The total radiance (eq. 8) in `L` precision at `count` geometries.
fn total_at<L: Lane>(
    corr: u32,
    p: &impl ToParams,
    input: (*const LaminarAngles, usize),
    out: *mut L,
) -> Status {
    let writer = Writer {
        width: 1,
        each: total::<L>,
    };
    status(evaluate((corr, p), input, out, writer))
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
        total_at(corr, &p, (angles, count), out)
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
        total_at(corr, &p, (angles, count), out)
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
        components_at(corr, &p, (angles_in, count), out)
    }

    /// Checks the untied model's parameters: [`Status::Ok`] or the first
    /// one out of its domain (`sub_slope` as `slope`: [`Status::BadSlope`]).
    #[no_mangle]
    pub extern "C" fn laminar_validate_params_untied(p: LaminarParamsUntied) -> Status {
        status(params(&p).map(|_| ()))
    }

    /// [`laminar_total_radiance_f64`] of the untied model.
    #[no_mangle]
    pub extern "C" fn laminar_total_radiance_untied_f64(
        corr: u32,
        p: LaminarParamsUntied,
        angles: *const LaminarAngles,
        count: usize,
        out: *mut f64,
    ) -> Status {
        total_at(corr, &p, (angles, count), out)
    }

    /// [`laminar_components_f64`] of the untied model: the surface term at
    /// σ/T, the subsurface term at σ′/T′.
    #[no_mangle]
    pub extern "C" fn laminar_components_untied_f64(
        corr: u32,
        p: LaminarParamsUntied,
        angles_in: *const LaminarAngles,
        count: usize,
        out: *mut f64,
    ) -> Status {
        components_at(corr, &p, (angles_in, count), out)
    }

    /// Checks `f32` parameters: [`Status::Ok`] or the first one out of its
    /// domain (the same domains as [`laminar_validate_params`]).
    #[no_mangle]
    pub extern "C" fn laminar_validate_params_f32(p: LaminarParamsF32) -> Status {
        status(params_f32(&p).map(|_| ()))
    }

    /// Builds `count` geometries from `f64` angles with `f64`
    /// trigonometry (bitwise the fitting library's `f32` geometry; on a
    /// single-precision FPU about 19,000 instructions each, see docs/c.md).
    #[no_mangle]
    pub extern "C" fn laminar_geometry_from_angles(
        angles: *const LaminarAngles,
        count: usize,
        out: *mut LaminarGeometry,
    ) -> Status {
        let check = |a: &LaminarAngles| self::angles(a).map(drop);
        status(build_geometries(
            (angles, count),
            out,
            (check, geometry::from_angles),
        ))
    }

    /// Builds `count` geometries from `f32` angles in `f32` arithmetic
    /// (error budget: docs/conventions.md §2).
    #[no_mangle]
    pub extern "C" fn laminar_geometry_from_angles_f32(
        angles: *const LaminarAnglesF32,
        count: usize,
        out: *mut LaminarGeometry,
    ) -> Status {
        let check = |a: &LaminarAnglesF32| {
            Geometry::check_angles_f32(a.theta_i, a.theta_s, a.phi_s).map_err(status_of)
        };
        status(build_geometries(
            (angles, count),
            out,
            (check, geometry::from_angles_f32),
        ))
    }

    /// Builds `count` geometries from sensor directions (sines and
    /// cosines) in `f32` arithmetic.
    #[no_mangle]
    pub extern "C" fn laminar_geometry_from_directions(
        directions: *const LaminarDirections,
        count: usize,
        out: *mut LaminarGeometry,
    ) -> Status {
        status(build_geometries(
            (directions, count),
            out,
            (geometry::check_directions, geometry::from_directions),
        ))
    }

    /// The total radiance (eq. 8) in f32 at `count` prebuilt geometries
    /// into `out` (`count` floats): the fast path, no `f64` operation.
    /// `corr`: 0 exponential, 1 Gaussian.
    #[no_mangle]
    pub extern "C" fn laminar_evaluate_f32(
        corr: u32,
        p: LaminarParamsF32,
        geometries: *const LaminarGeometry,
        count: usize,
        out: *mut f32,
    ) -> Status {
        let writer = Writer {
            width: 1,
            each: total::<f32>,
        };
        status(evaluate_geometries(
            (corr, &p),
            (geometries, count),
            out,
            writer,
        ))
    }

    /// Fits the model (correlation `corr`) to `count` ≤
    /// [`LAMINAR_FIT_MAX_MEASUREMENTS`] measurements: `data[k]` measured at
    /// `geometries[k]` (un-normalised; divided by their max), by the
    /// library's exhaustive grid search over `grid` (the `onepass-f32`
    /// path: the same best point, bit for bit, as `laminar fit --path
    /// onepass-f32` at geometries built by [`laminar_geometry_from_angles`]).
    /// Allocation-free: `scratch` is the working memory. Writes `out`.
    #[no_mangle]
    pub extern "C" fn laminar_fit(
        corr: u32,
        geometries: *const LaminarGeometry,
        data: *const f64,
        count: usize,
        grid: LaminarGrid,
        scratch: *mut LaminarFitScratch,
        out: *mut LaminarFitResult,
    ) -> Status {
        status(fit::fit(
            corr,
            (geometries, data, count),
            &grid,
            scratch,
            out,
        ))
    }

    /// Fits the model (correlation `corr`) to `count` ≤
    /// [`LAMINAR_FIT_MAX_MEASUREMENTS`] measurements by the fitting
    /// library's default objective, the free amplitude (`Σ w (D − c M)²`,
    /// M eq. 8's mix; docs/conventions.md §4b): a search over the σ/T, n
    /// and a values of `grid`, with β (in `[grid.beta_lo, grid.beta_hi]`)
    /// and the amplitude `c ≥ 0` in closed form at every point, all in
    /// `float` (the core's `small_free_fit`; the same result, bit for bit,
    /// as on the host). `data[k]` was measured at `geometries[k]`;
    /// `sigma` is null (weights 1) or `count` standard uncertainties on
    /// the data's scale (weights `1/σ²`). Allocation-free: `scratch` is the
    /// working memory. Writes `out`.
    #[no_mangle]
    pub extern "C" fn laminar_fit_free(
        corr: u32,
        geometries: *const LaminarGeometry,
        data: *const f64,
        sigma: *const f64,
        count: usize,
        grid: LaminarFreeGrid,
        scratch: *mut LaminarFitScratch,
        out: *mut LaminarFreeFitResult,
    ) -> Status {
        status(fit::fit_free(
            corr,
            (geometries, data, sigma, count),
            &grid,
            scratch,
            out,
        ))
    }

    /// Every component (in the order of [`LAMINAR_COMPONENTS`]) in f32 at
    /// `count` prebuilt geometries into `out` (`7 · count` floats).
    #[no_mangle]
    pub extern "C" fn laminar_components_f32(
        corr: u32,
        p: LaminarParamsF32,
        geometries: *const LaminarGeometry,
        count: usize,
        out: *mut f32,
    ) -> Status {
        let writer = Writer {
            width: LAMINAR_COMPONENTS,
            each: all_components::<f32>,
        };
        status(evaluate_geometries(
            (corr, &p),
            (geometries, count),
            out,
            writer,
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

    use std::format;

    /// Each layered parameter and each paper-frame angle out of its domain
    /// gives the status named after it (`BadSlope` for `slope`, `BadThetaI`
    /// for `theta_i`, …), and each correlation's code is its index.
    #[test]
    fn every_parameter_angle_and_correlation_has_its_code() {
        let named = |s: Status, name: &str| {
            format!("{s:?}").to_lowercase() == format!("bad{}", name.replace('_', ""))
        };
        for (k, p) in [Param::Slope, Param::Beta, Param::N, Param::A]
            .into_iter()
            .enumerate()
        {
            let mut v = [P.slope, P.beta, P.n, P.a];
            v[k] = f64::NAN;
            let (slope, beta, n, a) = (v[0], v[1], v[2], v[3]);
            let s = laminar_validate_params(LaminarParams { slope, beta, n, a });
            assert!(named(s, p.name()), "{p}: {s:?}");
        }
        for (k, angle) in [Angle::ThetaI, Angle::ThetaS, Angle::PhiS]
            .into_iter()
            .enumerate()
        {
            let mut v = [0.3, 0.4, 0.5];
            v[k] = f64::NAN;
            let (theta_i, theta_s, phi_s) = (v[0], v[1], v[2]);
            let s = laminar_validate_angles(LaminarAngles {
                theta_i,
                theta_s,
                phi_s,
            });
            assert!(named(s, angle.name()), "{}: {s:?}", angle.name());
        }
        for (code, corr) in Correlation::ALL.into_iter().enumerate() {
            assert_eq!(correlation(code as u32), Ok(corr));
        }
        assert_eq!(
            correlation(Correlation::ALL.len() as u32),
            Err(Status::BadCorrelation)
        );
    }

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
        use laminar_brdf_core::components;
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

    /// The untied functions are the core's untied model, bit for bit, the
    /// tied ones at σ′/T′ = σ/T, and a bad σ′/T′ is `BadSlope` with nothing
    /// written.
    #[test]
    fn untied_components_are_the_cores() {
        let geometries = [probe::angles(3), probe::angles(40)];
        let untied = LaminarParamsUntied {
            slope: 0.2,
            sub_slope: 1.5,
            beta: 0.3,
            n: 1.45,
            a: 0.2,
        };
        let mut out = [0.0f64; 2 * LAMINAR_COMPONENTS];
        let s = laminar_components_untied_f64(0, untied, geometries.as_ptr(), 2, out.as_mut_ptr());
        assert_eq!(s, Status::Ok);
        let p = Params::untied(0.2, 1.5, 0.3, 1.45, 0.2).unwrap();
        for (k, a) in geometries.iter().enumerate() {
            let g = Geometry::<f64>::splat(&angles(a).unwrap());
            let want = laminar_brdf_core::components(&g, Correlation::Exponential, &p).to_array();
            assert_eq!(
                &out[k * LAMINAR_COMPONENTS..(k + 1) * LAMINAR_COMPONENTS],
                &want[..]
            );
        }
        let mut total = [0.0f64; 2];
        let s = laminar_total_radiance_untied_f64(
            0,
            untied,
            geometries.as_ptr(),
            2,
            total.as_mut_ptr(),
        );
        assert_eq!((s, total[1]), (Status::Ok, out[2 * LAMINAR_COMPONENTS - 1]));
        let tied = LaminarParamsUntied {
            slope: P.slope,
            sub_slope: P.slope,
            beta: P.beta,
            n: P.n,
            a: P.a,
        };
        let (mut a, mut b) = ([0.0f64; 2], [0.0f64; 2]);
        laminar_total_radiance_untied_f64(1, tied, geometries.as_ptr(), 2, a.as_mut_ptr());
        laminar_total_radiance_f64(1, P, geometries.as_ptr(), 2, b.as_mut_ptr());
        assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
        let mut untouched = [7.0f64; 2];
        let bad = LaminarParamsUntied {
            sub_slope: f64::NAN,
            ..untied
        };
        let s = laminar_total_radiance_untied_f64(
            0,
            bad,
            geometries.as_ptr(),
            2,
            untouched.as_mut_ptr(),
        );
        assert_eq!((s, untouched), (Status::BadSlope, [7.0; 2]));
        assert_eq!(laminar_validate_params_untied(bad), Status::BadSlope);
        assert_eq!(laminar_validate_params_untied(untied), Status::Ok);
    }

    #[test]
    fn prebuilt_f32_geometries_give_the_f32_paths_bits() {
        let angles: [LaminarAngles; 16] = core::array::from_fn(|k| probe::angles(k as u32 * 3));
        let mut geometries =
            [LaminarGeometry::from(Geometry::<f32>::splat(&Angles::new(0.0, 0.0, 0.0).unwrap()));
                16];
        let s = laminar_geometry_from_angles(angles.as_ptr(), 16, geometries.as_mut_ptr());
        assert_eq!(s, Status::Ok);
        for j in 0..probe::PARAMS {
            let p = probe::params(j);
            let p32 = LaminarParamsF32 {
                slope: p.slope as f32,
                beta: p.beta as f32,
                n: p.n as f32,
                a: p.a as f32,
            };
            for corr in 0..2 {
                let (mut want, mut got) = ([0.0f32; 16], [0.0f32; 16]);
                let mut parts = [0.0f32; 16 * LAMINAR_COMPONENTS];
                laminar_total_radiance_f32(corr, p, angles.as_ptr(), 16, want.as_mut_ptr());
                let s1 = laminar_evaluate_f32(corr, p32, geometries.as_ptr(), 16, got.as_mut_ptr());
                let s2 =
                    laminar_components_f32(corr, p32, geometries.as_ptr(), 16, parts.as_mut_ptr());
                assert_eq!((s1, s2), (Status::Ok, Status::Ok));
                for k in 0..16 {
                    assert_eq!(got[k].to_bits(), want[k].to_bits(), "geometry {k}");
                    let total = parts[(k + 1) * LAMINAR_COMPONENTS - 1];
                    assert_eq!(total.to_bits(), want[k].to_bits());
                }
            }
        }
        // The f32 constructors are the core's, and bad input names itself.
        let a32 = LaminarAnglesF32 {
            theta_i: 0.4,
            theta_s: 0.9,
            phi_s: -2.0,
        };
        let mut g = geometries[0];
        assert_eq!(
            laminar_geometry_from_angles_f32(&a32, 1, &mut g),
            Status::Ok
        );
        assert_eq!(g, Geometry::from_angles_f32(0.4, 0.9, -2.0).unwrap().into());
        let bad = LaminarAnglesF32 { phi_s: 4.0, ..a32 };
        assert_eq!(
            laminar_geometry_from_angles_f32(&bad, 1, &mut g),
            Status::BadPhiS
        );
        let d = LaminarDirections {
            cos_i: 0.6,
            sin_i: 0.8,
            cos_s: 1.0,
            sin_s: 0.0,
            cos_phi: 0.0,
            sin_phi: 0.9,
        };
        assert_eq!(
            laminar_geometry_from_directions(&d, 1, &mut g),
            Status::BadPhiS
        );
        let p32 = LaminarParamsF32 {
            slope: 0.5,
            beta: 0.5,
            n: 11.0,
            a: 0.0,
        };
        assert_eq!(laminar_validate_params_f32(p32), Status::BadN);
        let mut out = [0.0f32; 1];
        let s = laminar_evaluate_f32(0, p32, geometries.as_ptr(), 1, out.as_mut_ptr());
        assert_eq!(s, Status::BadN);
    }
}
