//! Shared strategies and helpers for the workspace tests.
#![allow(dead_code)]

use core::f64::consts::{FRAC_PI_2, PI};
use laminar_brdf_core::{Angles, Correlation, Params};
use proptest::prelude::*;

/// Any valid measurement geometry, with the edges (0, π/2, ±π) over-represented.
pub fn angles() -> impl Strategy<Value = Angles> {
    let zenith = prop_oneof![
        1 => Just(0.0),
        1 => Just(FRAC_PI_2),
        1 => Just(1e-6),
        1 => Just(FRAC_PI_2 - 1e-6),
        8 => 0.0..=FRAC_PI_2,
    ];
    let azimuth = prop_oneof![
        1 => Just(0.0),
        1 => Just(PI),
        1 => Just(-PI),
        8 => -PI..=PI,
    ];
    (zenith.clone(), zenith, azimuth).prop_map(|(ti, ts, ps)| Angles::new(ti, ts, ps).unwrap())
}

/// Eight geometries: one `f32x8` worth.
pub fn angles8() -> impl Strategy<Value = [Angles; 8]> {
    proptest::array::uniform8(angles())
}

/// Any valid parameter set, with the edges (β, a ∈ {0, 1}, n = 1) over-represented.
pub fn params() -> impl Strategy<Value = Params> {
    let unit = prop_oneof![1 => Just(0.0), 1 => Just(1.0), 6 => 0.0..=1.0];
    let n = prop_oneof![1 => Just(1.0), 6 => 1.0..=2.5];
    let slope = prop_oneof![1 => Just(1e-3), 1 => Just(1e3), 8 => 0.05..=5.0];
    (slope, unit.clone(), n, unit).prop_map(|(s, b, n, a)| Params::new(s, b, n, a).unwrap())
}

/// Parameters inside the paper's search domain (docs/conventions.md §6), where the
/// f32 error budgets are stated.
pub fn paper_params() -> impl Strategy<Value = Params> {
    (0.12..=4.04f64, 0.0..=1.0f64, 1.0..=2.0f64, 0.0..=1.0f64)
        .prop_map(|(s, b, n, a)| Params::new(s, b, n, a).unwrap())
}

pub fn correlation() -> impl Strategy<Value = Correlation> {
    prop_oneof![Just(Correlation::Gaussian), Just(Correlation::Exponential)]
}
