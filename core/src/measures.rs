//! Normalisation and error measures (eqs. 15–16, docs/conventions.md §4–§5) over
//! scalar slices (`f32` or `f64`), without allocation.

use crate::error::InputError;
use crate::lane::Real;

/// How model radiance is normalised before comparison with data (docs/conventions.md §4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Normalisation {
    /// Paper preset: surface and subsurface each divided by their own max,
    /// mixed with β, the mix divided by its max.
    #[default]
    Paper,
    /// Mix the raw components with β, then divide by the max.
    Global,
    /// Mix the raw components with β, then scale by the least-squares factor
    /// `Σ D P / Σ P²` against the data (no max).
    Lsq,
}

/// The smallest positive value accepted in a set of measured values,
/// relative to their max (docs/conventions.md §8): below it χ² (which
/// divides by the value) and the free objective's weights could overflow.
pub const MIN_RELATIVE_VALUE: f64 = 1e-100;

/// Why a set of measured values cannot be fitted ([`check_data`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DataFault {
    /// A value that is not a finite number.
    NotFinite,
    /// No value is positive (nothing to divide by the max).
    NoPositiveValue,
    /// A negative value larger in magnitude than the largest positive one.
    NegativeBeyondMax,
    /// A positive value below [`MIN_RELATIVE_VALUE`] of the max.
    TinyPositive,
}

impl DataFault {
    /// What is wrong, for a message.
    #[must_use]
    pub fn why(self) -> &'static str {
        match self {
            Self::NotFinite => "a value that is not a finite number",
            Self::NoPositiveValue => "no positive value",
            Self::NegativeBeyondMax => {
                "a negative value larger in magnitude than the largest positive one"
            }
            Self::TinyPositive => "a positive value below 1e-100 of the max (χ² divides by it)",
        }
    }
}

/// The data rule every front end shares (docs/conventions.md §8): the
/// measured radiance of one fit must be finite, have a positive value, no
/// negative value beyond the max in magnitude and no positive value below
/// [`MIN_RELATIVE_VALUE`] of it. The first fault, and the index of the value
/// (0 for [`DataFault::NoPositiveValue`]).
///
/// ```
/// use laminar_brdf_core::measures::{check_data, DataFault};
/// assert_eq!(check_data(&[0.5, 1.0, 0.0]), Ok(()));
/// assert_eq!(check_data(&[0.5, f64::NAN]), Err((1, DataFault::NotFinite)));
/// assert_eq!(check_data(&[0.0, -1.0]), Err((0, DataFault::NoPositiveValue)));
/// assert_eq!(check_data(&[1.0, -2.0]), Err((1, DataFault::NegativeBeyondMax)));
/// assert_eq!(check_data(&[1.0, 1e-101]), Err((1, DataFault::TinyPositive)));
/// ```
///
/// # Errors
/// The first fault found, with its index.
pub fn check_data(values: &[f64]) -> Result<(), (usize, DataFault)> {
    if let Some(k) = values.iter().position(|v| !v.is_finite()) {
        return Err((k, DataFault::NotFinite));
    }
    let max = values.iter().fold(0.0f64, |m, &v| m.max(v));
    if max <= 0.0 {
        return Err((0, DataFault::NoPositiveValue));
    }
    for (k, &v) in values.iter().enumerate() {
        if v < -max {
            return Err((k, DataFault::NegativeBeyondMax));
        }
        if v > 0.0 && v < max * MIN_RELATIVE_VALUE {
            return Err((k, DataFault::TinyPositive));
        }
    }
    Ok(())
}

/// The largest value of a slice (`−∞` for an empty slice; NaN is skipped).
#[must_use]
pub fn max_of<T: Real>(values: &[T]) -> T {
    values
        .iter()
        .fold(T::c(f64::NEG_INFINITY), |m, &v| if v > m { v } else { m })
}

/// Divides every value by the slice's max (docs/conventions.md §4). A slice whose max
/// is ≤ 0 (or empty) becomes all zeros: no division by zero, no NaN.
/// Returns the max used (0 when zeroed).
pub fn normalise_by_max<T: Real>(values: &mut [T]) -> T {
    let m = max_of(values);
    if m > T::c(0.0) {
        for v in values.iter_mut() {
            *v = *v / m;
        }
        m
    } else {
        values.iter_mut().for_each(|v| *v = T::c(0.0));
        T::c(0.0)
    }
}

/// The normalised model prediction `P` from raw surface and subsurface
/// radiance for balance β, written to `out` (docs/conventions.md §4). `surface` and
/// `subsurface` are normalised in place for [`Normalisation::Paper`].
/// `data` is used only by [`Normalisation::Lsq`].
///
/// # Errors
/// [`InputError::LengthMismatch`] when a slice's length differs from `out`'s.
pub fn normalised_prediction<T: Real>(
    norm: Normalisation,
    beta: T,
    surface: &mut [T],
    subsurface: &mut [T],
    data: &[T],
    out: &mut [T],
) -> Result<(), InputError> {
    let k = out.len();
    for len in [surface.len(), subsurface.len(), data.len()] {
        if len != k {
            return Err(InputError::LengthMismatch {
                data: len,
                prediction: k,
            });
        }
    }
    if norm == Normalisation::Paper {
        normalise_by_max(surface);
        normalise_by_max(subsurface);
    }
    let one = T::c(1.0);
    for ((o, &s), &u) in out.iter_mut().zip(surface.iter()).zip(subsurface.iter()) {
        *o = beta * u + (one - beta) * s;
    }
    match norm {
        Normalisation::Paper | Normalisation::Global => {
            normalise_by_max(out);
        }
        Normalisation::Lsq => {
            let (mut dp, mut pp) = (T::c(0.0), T::c(0.0));
            for (&d, &p) in data.iter().zip(out.iter()) {
                dp = dp + d * p;
                pp = pp + p * p;
            }
            let scale = if pp > T::c(0.0) { dp / pp } else { T::c(0.0) };
            out.iter_mut().for_each(|p| *p = *p * scale);
        }
    }
    Ok(())
}

fn check_lengths<T>(data: &[T], prediction: &[T]) -> Result<(), InputError> {
    if data.len() != prediction.len() || data.is_empty() {
        return Err(InputError::LengthMismatch {
            data: data.len(),
            prediction: prediction.len(),
        });
    }
    Ok(())
}

/// `Δ_RMS = 100 · sqrt(Σ_k (D_k − P_k)²) / K` (eq. 15 as printed, 1/K outside
/// the root; docs/conventions.md §5). Zero and negative data are kept.
///
/// # Errors
/// [`InputError::LengthMismatch`] for slices of different or zero length.
pub fn rms_error<T: Real>(data: &[T], prediction: &[T]) -> Result<T, InputError> {
    check_lengths(data, prediction)?;
    let mut sum = T::c(0.0);
    for (&d, &p) in data.iter().zip(prediction) {
        let e = d - p;
        sum = sum + e * e;
    }
    Ok(T::c(100.0) * sum.sqrt() / T::c(data.len() as f64))
}

/// Result of the χ² test (eq. 16, docs/conventions.md §5).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChiSquare<T> {
    /// `χ²/ν`.
    pub per_dof: T,
    /// Terms used (`d`, measurements with `D_k > 0`).
    pub used: usize,
    /// Measurements left out because `D_k ≤ 0`.
    pub left_out: usize,
}

/// `χ²/ν = Σ (P_k − D_k)² / D_k / (d − p)` over measurements with `D_k > 0`
/// (eq. 16; docs/conventions.md §5: `p = 4` absorptive, `p = 3` Ragheb–Hancock).
///
/// # Errors
/// [`InputError::LengthMismatch`] for slices of different or zero length;
/// [`InputError::NoDegreesOfFreedom`] when at most `params` terms have `D_k > 0`.
pub fn chi_square_per_dof<T: Real>(
    data: &[T],
    prediction: &[T],
    params: usize,
) -> Result<ChiSquare<T>, InputError> {
    check_lengths(data, prediction)?;
    let (mut sum, mut used) = (T::c(0.0), 0usize);
    for (&d, &p) in data.iter().zip(prediction) {
        if d > T::c(0.0) {
            let e = p - d;
            sum = sum + e * e / d;
            used += 1;
        }
    }
    if used <= params {
        return Err(InputError::NoDegreesOfFreedom {
            terms: used,
            params,
        });
    }
    Ok(ChiSquare {
        per_dof: sum / T::c((used - params) as f64),
        used,
        left_out: data.len() - used,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rms_matches_eq_15() {
        let d = [1.0f64, 0.5, 0.0];
        let p = [0.5f64, 0.5, 0.5];
        let got = rms_error(&d, &p).unwrap();
        assert!((got - 100.0 * (0.5f64).sqrt() / 3.0).abs() < 1e-13);
        assert!(rms_error(&d, &p[..2]).is_err());
        assert!(rms_error::<f64>(&[], &[]).is_err());
    }

    #[test]
    fn chi_square_skips_non_positive_data() {
        let d = [1.0f64, 0.5, 0.0, -0.1, 0.25, 1.0];
        let p = [0.5f64, 0.5, 0.5, 0.5, 0.5, 1.0];
        let c = chi_square_per_dof(&d, &p, 3).unwrap();
        assert_eq!((c.used, c.left_out), (4, 2));
        assert!((c.per_dof - (0.25 + 0.0 + 0.25) / 1.0).abs() < 1e-15);
        assert!(chi_square_per_dof(&d, &p, 4).is_err());
    }

    #[test]
    fn all_zero_component_normalises_to_zero() {
        let mut v = [0.0f32, 0.0, -1.0];
        assert_eq!(normalise_by_max(&mut v), 0.0);
        assert_eq!(v, [0.0, 0.0, 0.0]);
    }

    #[test]
    fn paper_normalisation_peaks_at_one() {
        let mut s = [1.0f64, 2.0, 4.0];
        let mut u = [3.0f64, 1.0, 0.0];
        let mut out = [0.0f64; 3];
        normalised_prediction(
            Normalisation::Paper,
            0.5,
            &mut s,
            &mut u,
            &[0.0; 3],
            &mut out,
        )
        .unwrap();
        assert_eq!(max_of(&out), 1.0);
        let mut s = [1.0f64, 2.0, 4.0];
        let mut u = [0.5f64, 1.0, 2.0];
        normalised_prediction(
            Normalisation::Lsq,
            0.0,
            &mut s,
            &mut u,
            &[2.0, 4.0, 8.0],
            &mut out,
        )
        .unwrap();
        assert_eq!(out, [2.0, 4.0, 8.0]);
    }
}
