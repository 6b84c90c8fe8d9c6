//! The probe cases of the firmware test (`ffi/firmware`, run on an
//! emulated Cortex-M4 by `ffi/tests/firmware.rs`): the core's parity cases
//! ([`laminar_brdf_core::probe`]) in the C ABI's types, and the values the
//! device and the host both compute from them through the C ABI.

use crate::{
    laminar_components_f64, laminar_evaluate_f32, laminar_geometry_from_angles_f32,
    laminar_geometry_from_directions, laminar_total_radiance_f32, LaminarAngles, LaminarAnglesF32,
    LaminarDirections, LaminarGeometry, LaminarParams, LaminarParamsF32, Status,
    LAMINAR_COMPONENTS,
};
pub use laminar_brdf_core::probe::{GEOMETRIES, PARAMS};

/// Geometry `g` ([`laminar_brdf_core::probe::angles`]).
pub fn angles(g: u32) -> LaminarAngles {
    let (theta_i, theta_s, phi_s) = laminar_brdf_core::probe::angles(g);
    LaminarAngles {
        theta_i,
        theta_s,
        phi_s,
    }
}

/// Parameter set `j` ([`laminar_brdf_core::probe::params`]).
pub fn params(j: u32) -> LaminarParams {
    let (slope, beta, n, a) = laminar_brdf_core::probe::params(j);
    LaminarParams { slope, beta, n, a }
}

/// Values per (geometry, parameters, correlation) case: the f32 total,
/// the seven f64 components, and the f32 total at the geometry built
/// from `f32` angles ([`f32_geometries`]).
pub const CASE_VALUES: usize = 2 + LAMINAR_COMPONENTS;

/// The bit patterns of case (`g`, `j`, `corr`), widened to `u64`; a call
/// that fails gives its status code in place of its values.
pub fn case_values(g: u32, j: u32, corr: u32) -> [u64; CASE_VALUES] {
    let (a, p) = (angles(g), params(j));
    let mut out = [0u64; CASE_VALUES];
    let mut total = [0.0f32];
    let mut parts = [0.0f64; LAMINAR_COMPONENTS];
    let s1 = laminar_total_radiance_f32(corr, p, &a, 1, total.as_mut_ptr());
    let s2 = laminar_components_f64(corr, p, &a, 1, parts.as_mut_ptr());
    out[0] = or_status(s1, total[0].to_bits() as u64);
    for (slot, v) in out[1..=LAMINAR_COMPONENTS].iter_mut().zip(parts) {
        *slot = or_status(s2, v.to_bits());
    }
    let p32 = LaminarParamsF32 {
        slope: p.slope as f32,
        beta: p.beta as f32,
        n: p.n as f32,
        a: p.a as f32,
    };
    let (geometry, _) = f32_geometries(g);
    let s3 = match geometry {
        Ok(geometry) => laminar_evaluate_f32(corr, p32, &geometry, 1, total.as_mut_ptr()),
        Err(s) => s,
    };
    out[CASE_VALUES - 1] = or_status(s3, total[0].to_bits() as u64);
    out
}

/// `bits` when the call returned OK, else its status code.
fn or_status(status: Status, bits: u64) -> u64 {
    if status == Status::Ok {
        bits
    } else {
        status as u64
    }
}

/// Geometry `g` built in `f32` arithmetic from its angles rounded to
/// `f32` (pulled inside the `f32` domain), and from its sines and
/// cosines (libm `f64`, rounded to `f32`, as a sensor would give them).
pub fn f32_geometries(
    g: u32,
) -> (
    Result<LaminarGeometry, Status>,
    Result<LaminarGeometry, Status>,
) {
    let a = angles(g);
    // The f32 nearest π/2 (π) is above it: take the one below.
    let below = |x: f32| f32::from_bits(x.to_bits() - 1);
    let zenith = |t: f64| (t as f32).min(below(core::f32::consts::FRAC_PI_2));
    let pi = below(core::f32::consts::PI);
    let a32 = LaminarAnglesF32 {
        theta_i: zenith(a.theta_i),
        theta_s: zenith(a.theta_s),
        phi_s: (a.phi_s as f32).clamp(-pi, pi),
    };
    let d = LaminarDirections {
        cos_i: libm::cos(a.theta_i) as f32,
        sin_i: libm::sin(a.theta_i) as f32,
        cos_s: libm::cos(a.theta_s) as f32,
        sin_s: libm::sin(a.theta_s) as f32,
        cos_phi: libm::cos(a.phi_s) as f32,
        sin_phi: libm::sin(a.phi_s) as f32,
    };
    let build = |s: Status, g: LaminarGeometry| if s == Status::Ok { Ok(g) } else { Err(s) };
    let mut from_angles = LaminarGeometry::default();
    let s = laminar_geometry_from_angles_f32(&a32, 1, &mut from_angles);
    let mut from_directions = LaminarGeometry::default();
    let t = laminar_geometry_from_directions(&d, 1, &mut from_directions);
    (build(s, from_angles), build(t, from_directions))
}

/// The bit patterns of both [`f32_geometries`] of `g` (eight fields each;
/// a status code in each field when the constructor failed).
pub fn geometry_values(g: u32) -> [u32; 16] {
    let (a, d) = f32_geometries(g);
    let mut out = [0u32; 16];
    for (half, built) in out.chunks_exact_mut(8).zip([a, d]) {
        let fields = match built {
            Ok(g) => [
                g.cos_i, g.cos_s, g.sin2_i, g.sin2_s, g.vxy2, g.vz2, g.lead, g.ratio,
            ]
            .map(f32::to_bits),
            Err(s) => [s as u32; 8],
        };
        half.copy_from_slice(&fields);
    }
    out
}

/// The paper's grid (σ/T, n, a, β): [`laminar_brdf_core::small_fit::PAPER`].
pub fn paper_axes() -> ([f64; 50], [f64; 11], [f64; 101], [f64; 100]) {
    use laminar_brdf_core::small_fit::{stepped, PAPER};
    let axis = |(start, step, _): (f64, f64, usize)| move |i| stepped(start, step, i);
    (
        core::array::from_fn(axis(PAPER[0])),
        core::array::from_fn(axis(PAPER[1])),
        core::array::from_fn(axis(PAPER[2])),
        core::array::from_fn(axis(PAPER[3])),
    )
}

/// The fit probe with `k` ≤ 64 measurements: the spread probe geometries
/// (from index 8 on), and data from the exponential model at σ/T = 0.9,
/// β = 0.4, n = 1.42, a = 0.3 with a fixed ±1% ripple (a stand-in for
/// noise that every target computes alike).
pub fn fit_case(k: usize) -> ([LaminarGeometry; 64], [f64; 64]) {
    let mut geometry = [LaminarGeometry::default(); 64];
    let mut data = [0.0f64; 64];
    let p = LaminarParams {
        slope: 0.9,
        beta: 0.4,
        n: 1.42,
        a: 0.3,
    };
    for i in 0..k.min(64) {
        let a = angles(8 + i as u32);
        let mut total = 0.0f64;
        crate::laminar_geometry_from_angles(&a, 1, &mut geometry[i]);
        crate::laminar_total_radiance_f64(0, p, &a, 1, &mut total);
        data[i] = total * (1.0 + 0.01 * (((i * 7) % 5) as f64 - 2.0) / 2.0);
    }
    (geometry, data)
}

/// [`crate::laminar_fit`] of [`fit_case`] `k` on the paper grid: the
/// status, and the result's index and Δ_RMS bits.
pub fn fit_values(k: usize) -> (Status, usize, u64) {
    let (slope, n, a, beta) = paper_axes();
    let grid = crate::LaminarGrid {
        slope: slope.as_ptr(),
        slope_count: slope.len(),
        n: n.as_ptr(),
        n_count: n.len(),
        a: a.as_ptr(),
        a_count: a.len(),
        beta: beta.as_ptr(),
        beta_count: beta.len(),
    };
    let (geometry, data) = fit_case(k);
    let mut scratch = crate::LaminarFitScratch::new();
    let mut out = crate::LaminarFitResult::default();
    let s = crate::laminar_fit(
        0,
        geometry.as_ptr(),
        data.as_ptr(),
        k,
        grid,
        &mut scratch,
        &mut out,
    );
    (s, out.index, out.rms.to_bits())
}

/// [`crate::laminar_fit_free`] of [`fit_case`] `k` on the paper-sized
/// nonlinear grid (σ/T, n, a of [`paper_axes`]; β in [0, 1]): the status,
/// and the result's index, objective bits and Δ_RMS bits.
pub fn free_fit_values(k: usize) -> (Status, usize, u64, u64) {
    let (slope, n, a, _) = paper_axes();
    let grid = crate::LaminarFreeGrid {
        slope: slope.as_ptr(),
        slope_count: slope.len(),
        n: n.as_ptr(),
        n_count: n.len(),
        a: a.as_ptr(),
        a_count: a.len(),
        beta_lo: 0.0,
        beta_hi: 1.0,
    };
    let (geometry, data) = fit_case(k);
    let mut scratch = crate::LaminarFitScratch::new();
    let mut out = crate::LaminarFreeFitResult::default();
    let s = crate::laminar_fit_free(
        0,
        geometry.as_ptr(),
        data.as_ptr(),
        core::ptr::null(),
        k,
        grid,
        &mut scratch,
        &mut out,
    );
    (s, out.index, out.objective.to_bits(), out.rms.to_bits())
}
