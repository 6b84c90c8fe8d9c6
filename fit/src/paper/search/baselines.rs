//! The baselines' search (docs/conventions.md §7): an exhaustive 2-D grid
//! in f64 of the max-normalised Jensen or Oren–Nayar radiance, and the
//! grid's profile read from the whole surface.

use super::GridProfile;
use crate::baseline::BaselineGeometry;
use crate::grid::Axis;
use crate::scene::Scene;
use laminar_brdf_core::{normalise_by_max, rms_error};
use rayon::prelude::*;

/// Exhaustive 2-D search in f64 of a max-normalised baseline; ties keep the
/// first point in row-major order. The best (Δ_RMS, x, y) and every
/// point's Δ_RMS in row-major order.
pub(crate) fn grid2(
    scene: &Scene,
    outer: &Axis,
    inner: &Axis,
    geometry: &BaselineGeometry,
) -> ((f64, f64, f64), Vec<f64>) {
    let rows: Vec<Vec<f64>> = outer
        .values
        .par_iter()
        .map(|&x| {
            inner
                .values
                .iter()
                .map(|&y| {
                    let mut p = geometry
                        .radiance([x, y])
                        .expect("the baselines' grids lie inside their domains");
                    normalise_by_max(&mut p);
                    rms_error(&scene.data, &p).unwrap_or(f64::INFINITY)
                })
                .collect()
        })
        .collect();
    let surface: Vec<f64> = rows.concat();
    // Starting from the first point keeps the result a grid point even if
    // no error is finite.
    let mut best = (surface[0], 0);
    for (i, &rms) in surface.iter().enumerate() {
        if rms < best.0 {
            best = (rms, i);
        }
    }
    let (x, y) = (
        outer.values[best.1 / inner.len()],
        inner.values[best.1 % inner.len()],
    );
    ((best.0, x, y), surface)
}

/// The [`GridProfile`] of a full surface of Δ_RMS over axes of lengths
/// `lens` (row-major), on `k` measurements, to the cutoffs `(profile, near)`
/// on the objective `Σ (D − P)²`.
pub(crate) fn profile_of(
    surface: &[f64],
    lens: [usize; 2],
    k: usize,
    (cutoff, near): (f64, f64),
) -> GridProfile {
    let mut axes: Vec<Vec<(f64, usize)>> = lens
        .iter()
        .map(|&len| vec![(f64::INFINITY, usize::MAX); len])
        .collect();
    let mut near_points = Vec::new();
    for (flat, &rms) in surface.iter().enumerate() {
        let e = sum_of_rms(rms, k);
        if e > cutoff {
            continue;
        }
        for (axis, i) in axes.iter_mut().zip([flat / lens[1], flat % lens[1]]) {
            if e < axis[i].0 {
                axis[i] = (e, flat);
            }
        }
        if e <= near {
            near_points.push((flat, e));
        }
    }
    GridProfile {
        axes,
        near: near_points,
        cutoff,
    }
}

/// `Σ (D − P)²` from `Δ_RMS = 100·sqrt(Σ(D − P)²)/K` (eq. 15).
pub(crate) fn sum_of_rms(rms: f64, k: usize) -> f64 {
    let root = rms * k as f64 / 100.0;
    root * root
}
