//! The on-device fits of the C ABI, over a grid the caller gives, in
//! scratch memory the caller owns: the paper objective's small fit
//! (`laminar_brdf_core::small_fit`, the library's `onepass-f32` search) and the
//! free amplitude's (`laminar_brdf_core::small_free_fit`).

use crate::scratch::LaminarFitScratch;
use crate::{buffers, correlation, status_of, LaminarGeometry, Status};
use laminar_brdf_core::onepass::rms_of_sum;
use laminar_brdf_core::small_fit::{self, Axes, AxisError, SmallFitError, MAX_MEASUREMENTS};
use laminar_brdf_core::small_free_fit::{fit_free as core_fit_free, FreeAxes, FreeScratch};

/// Most measurements `laminar_fit` takes: a literal, so that the header's
/// macro is a number C can use (equal to the core's `MAX_MEASUREMENTS`,
/// checked at compile time).
pub const LAMINAR_FIT_MAX_MEASUREMENTS: usize = 64;

const _: () = assert!(LAMINAR_FIT_MAX_MEASUREMENTS == MAX_MEASUREMENTS);

/// The grid: each axis's values (`f64`) and count, searched in loop order
/// σ/T, n, a, β (ties go to the first). The paper's grid: σ/T = 0.12 +
/// 0.08 i (50 values), n = 1.30 + 0.02 m (11), a = 0.01 l (101), β = 0.01 +
/// 0.01 j (100), each computed in `double` as written.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct LaminarGrid {
    /// σ/T values.
    pub slope: *const f64,
    /// Number of σ/T values.
    pub slope_count: usize,
    /// n values.
    pub n: *const f64,
    /// Number of n values.
    pub n_count: usize,
    /// a values.
    pub a: *const f64,
    /// Number of a values.
    pub a_count: usize,
    /// β values.
    pub beta: *const f64,
    /// Number of β values.
    pub beta_count: usize,
}

/// What a fit found: the best grid point's parameters, its Δ_RMS (eq. 15)
/// and flat index, and the same for the best point with a = 0 (the
/// Ragheb–Hancock model; `rh_found` is false when the a axis lacks 0).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LaminarFitResult {
    /// σ/T.
    pub slope: f64,
    /// β.
    pub beta: f64,
    /// n.
    pub n: f64,
    /// a.
    pub a: f64,
    /// Δ_RMS (eq. 15) at the best point.
    pub rms: f64,
    /// Flat index of the best point (loop order σ/T, n, a, β).
    pub index: usize,
    /// Whether the a axis holds 0.
    pub rh_found: bool,
    /// Flat index of the best point with a = 0.
    pub rh_index: usize,
    /// Its Δ_RMS.
    pub rh_rms: f64,
}

/// The fit behind [`crate::laminar_fit`].
pub fn fit(
    corr: u32,
    (geometries, data, count): (*const LaminarGeometry, *const f64, usize),
    grid: &LaminarGrid,
    scratch: *mut LaminarFitScratch,
    out: *mut LaminarFitResult,
) -> Result<(), Status> {
    let corr = correlation(corr)?;
    if count == 0 || count > MAX_MEASUREMENTS {
        return Err(Status::BadCount);
    }
    let g = buffers::input(geometries, count)?;
    let data = buffers::input(data, count)?;
    let axes = Axes {
        slope: buffers::input(grid.slope, grid.slope_count)?,
        n: buffers::input(grid.n, grid.n_count)?,
        a: buffers::input(grid.a, grid.a_count)?,
        beta: buffers::input(grid.beta, grid.beta_count)?,
    };
    let scratch = buffers::scratch(scratch)?;
    let out = buffers::output(out, 1)?;
    let found = small_fit::fit(corr, g, data, &axes, scratch).map_err(status_of_fit)?;
    let (slope, beta, n, a) = axes.point(found.best);
    let (rh_index, rh_objective) = found.rh_best.unwrap_or((0, 0.0));
    out[0] = LaminarFitResult {
        slope,
        beta,
        n,
        a,
        rms: found.rms,
        index: found.best,
        rh_found: found.rh_best.is_some(),
        rh_index,
        rh_rms: rms_of_sum(rh_objective, count),
    };
    Ok(())
}

/// The status of a small fit's error.
fn status_of_fit(e: SmallFitError) -> Status {
    match e {
        SmallFitError::Count { .. } => Status::BadCount,
        SmallFitError::Data { .. } => Status::BadData,
        SmallFitError::Axis(AxisError::Empty { .. }) => Status::EmptyAxis,
        SmallFitError::Axis(AxisError::OutOfDomain { error, .. }) => status_of(error),
        SmallFitError::Sigma { .. } => Status::BadSigma,
    }
}

/// The grid of a free fit: σ/T, n and a values (`f64`) and counts,
/// searched in loop order σ/T, n, a (ties go to the first), and β's box
/// `[beta_lo, beta_hi]` (within [0, 1]). The paper-sized grid: σ/T =
/// 0.12 + 0.08 i (50 values), n = 1.30 + 0.02 m (11), a = 0.01 l (101),
/// β in [0, 1].
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct LaminarFreeGrid {
    /// σ/T values.
    pub slope: *const f64,
    /// Number of σ/T values.
    pub slope_count: usize,
    /// n values.
    pub n: *const f64,
    /// Number of n values.
    pub n_count: usize,
    /// a values.
    pub a: *const f64,
    /// Number of a values.
    pub a_count: usize,
    /// Lower end of β's box.
    pub beta_lo: f64,
    /// Upper end of β's box.
    pub beta_hi: f64,
}

/// What a free fit found: the best grid point's σ/T, n and a with β and
/// the amplitude there, its weighted objective and Δ_RMS (eq. 15, on the
/// data divided by their max, with the fitted prediction), its flat index
/// (loop order σ/T, n, a), and the best point with a = 0 (Ragheb–Hancock;
/// `rh_found` is false when the a axis lacks 0).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LaminarFreeFitResult {
    /// σ/T.
    pub slope: f64,
    /// β (eq. 8).
    pub beta: f64,
    /// n.
    pub n: f64,
    /// a.
    pub a: f64,
    /// The amplitude c, in the data's units: the fitted model is
    /// `c · ((1 − β) L^sf + β L^sb)`.
    pub amplitude: f64,
    /// `Σ w (D − c M)²` on the data divided by their max (`float`, widened).
    pub objective: f64,
    /// Δ_RMS (eq. 15) at the best point.
    pub rms: f64,
    /// Flat index of the best point.
    pub index: usize,
    /// Whether the a axis holds 0.
    pub rh_found: bool,
    /// Flat index of the best point with a = 0.
    pub rh_index: usize,
    /// Its objective.
    pub rh_objective: f64,
}

/// The fit behind [`crate::laminar_fit_free`].
pub fn fit_free(
    corr: u32,
    (geometries, data, sigma, count): (*const LaminarGeometry, *const f64, *const f64, usize),
    grid: &LaminarFreeGrid,
    scratch: *mut LaminarFitScratch,
    out: *mut LaminarFreeFitResult,
) -> Result<(), Status> {
    let corr = correlation(corr)?;
    if count == 0 || count > MAX_MEASUREMENTS {
        return Err(Status::BadCount);
    }
    let g = buffers::input(geometries, count)?;
    let data = buffers::input(data, count)?;
    let sigma = if sigma.is_null() {
        None
    } else {
        Some(buffers::input(sigma, count)?)
    };
    let axes = FreeAxes {
        slope: buffers::input(grid.slope, grid.slope_count)?,
        n: buffers::input(grid.n, grid.n_count)?,
        a: buffers::input(grid.a, grid.a_count)?,
        beta: (grid.beta_lo, grid.beta_hi),
    };
    let scratch = buffers::scratch::<FreeScratch<f32>>(scratch)?;
    let out = buffers::output(out, 1)?;
    let found = core_fit_free(corr, g, (data, sigma), &axes, scratch).map_err(status_of_fit)?;
    let (slope, n, a) = axes.point(found.best);
    let max = data.iter().fold(0.0f64, |m, &d| m.max(d));
    let (rh_index, rh_objective) = found.rh_best.unwrap_or((0, 0.0));
    out[0] = LaminarFreeFitResult {
        slope,
        beta: f64::from(found.beta),
        n,
        a,
        amplitude: f64::from(found.amplitude) * max,
        objective: f64::from(found.objective),
        rms: found.rms,
        index: found.best,
        rh_found: found.rh_best.is_some(),
        rh_index,
        rh_objective: f64::from(rh_objective),
    };
    Ok(())
}
