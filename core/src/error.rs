//! Errors returned by the validating constructors. The hot path trusts
//! validated values and never checks again.

use crate::lane::Real;
use crate::param::{Input, Param};
use core::fmt;

/// An input value outside the model's domain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum InputError {
    /// `input` had `value`, outside `allowed`.
    OutOfRange {
        /// The parameter or angle.
        input: Input,
        /// The value given.
        value: f64,
        /// The allowed domain, in words.
        allowed: &'static str,
    },
    /// Two slices that must have the same length did not.
    LengthMismatch {
        /// Length of the data slice.
        data: usize,
        /// Length of the prediction slice.
        prediction: usize,
    },
    /// An error measure had nothing to measure (no terms, or ν = d − p ≤ 0).
    NoDegreesOfFreedom {
        /// Terms used.
        terms: usize,
        /// Model parameters.
        params: usize,
    },
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::OutOfRange {
                input,
                value,
                allowed,
            } => {
                let name = input.name();
                // Very large or small values in scientific notation, not
                // hundreds of digits.
                let a = value.abs();
                if a != 0.0 && a.is_finite() && !(1e-4..1e15).contains(&a) {
                    write!(f, "{name} = {value:e} is outside {allowed}")
                } else {
                    write!(f, "{name} = {value} is outside {allowed}")
                }
            }
            Self::LengthMismatch { data, prediction } => write!(
                f,
                "data has {data} values but the prediction has {prediction}"
            ),
            Self::NoDegreesOfFreedom { terms, params } => write!(
                f,
                "{terms} usable terms leave no degrees of freedom for {params} parameters"
            ),
        }
    }
}

impl core::error::Error for InputError {}

/// Checks `lo ≤ v ≤ hi` (false for NaN) in `v`'s precision, the ends
/// rounded to it. Inlined always, so that a caller that maps the error to
/// a code (the C ABI) drops its strings and the widening of `v`.
#[inline(always)]
pub(crate) fn check_range<S: Real>(
    input: Input,
    v: S,
    lo: f64,
    hi: f64,
    allowed: &'static str,
) -> Result<S, InputError> {
    if v >= S::from_f64(lo) && v <= S::from_f64(hi) {
        Ok(v)
    } else {
        Err(InputError::OutOfRange {
            input,
            value: v.to_f64(),
            allowed,
        })
    }
}

/// [`check_range`] on parameter `p`'s domain ([`Param::domain`]; an open
/// lower end is the smallest positive normal number).
#[inline(always)]
pub(crate) fn check_param<S: Real>(p: Param, v: S) -> Result<S, InputError> {
    let (lo, hi) = p.domain();
    let lo = if p.lower_open() {
        f64::MIN_POSITIVE
    } else {
        lo
    };
    check_range(Input::Param(p), v, lo, hi, p.allowed())
}
