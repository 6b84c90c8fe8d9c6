//! The β sweep of one triple: the normalising max of `U`, the Pareto front
//! of `(S_k, U_k)` and the upper hull of its lines, and the closed-form
//! error of every β from six sums.

use super::basis::{At, QuadraticBasis};
use super::bounds::SurfaceFit;
use crate::paper::search::sums::SurfaceSums;
use laminar_brdf_core::mix;

/// Reusable per-shard buffers.
#[derive(Default)]
pub struct Scratch {
    /// The Pareto front as `(S_k, U_k)`, by decreasing `S` and increasing `U`.
    pub(super) front: Vec<(f64, f64)>,
    /// The upper hull of the front's lines, as `(S_k, U_k)`.
    pub(super) hull: Vec<(f64, f64)>,
    pub(super) sweep: Sweep,
}

/// The normalising max of `at`'s subsurface term, the Pareto front of
/// `(S_k, U_k)` with `U` normalised by it, and the upper hull of the front's
/// lines (into `scratch`). Returns the max.
pub(super) fn build_hull(
    surface: &SurfaceSums,
    basis: &QuadraticBasis,
    at: &At,
    scratch: &mut Scratch,
) -> f64 {
    let [w0, w1, w2] = &basis.w;
    let [b0, b1, b2] = at.b;
    let max = (w0.iter().zip(w1).zip(w2))
        .map(|((w0, w1), w2)| b0 * w0 + b1 * w1 + b2 * w2)
        .fold(0.0, |m: f64, v| if v > m { v } else { m });
    let normalised = |k: usize| {
        if max > 0.0 {
            at.value(basis, k) / max
        } else {
            0.0
        }
    };
    scratch.front.clear();
    let mut top = f64::NEG_INFINITY;
    for &i in &surface.order {
        let u = normalised(i);
        if u > top {
            top = u;
            scratch.front.push((surface.s[i], u));
            if top >= 1.0 {
                // U is normalised (no value above 1): no later point, with
                // its smaller S, can join the front.
                break;
            }
        }
    }
    upper_hull(&scratch.front, &mut scratch.hull);
    max
}

/// The six sums of the β sweep (module docs), `U` normalised.
#[derive(Clone, Copy)]
pub(super) struct Mix {
    pub(super) ss: f64,
    pub(super) su: f64,
    pub(super) uu: f64,
    pub(super) sd: f64,
    pub(super) ud: f64,
    pub(super) dd: f64,
}

impl Mix {
    /// The sums with `U` normalised by `max` (all zero when `max` is 0).
    pub(super) fn new(surface: &SurfaceSums, at: &At, fit: &SurfaceFit, ud: f64, max: f64) -> Self {
        let scale = if max > 0.0 { 1.0 / max } else { 0.0 };
        Self {
            ss: surface.ss,
            su: at.su * scale,
            uu: at.uu * scale * scale,
            sd: fit.sums.sd,
            ud: ud * scale,
            dd: fit.sums.dd,
        }
    }

    /// `(Σ X D, Σ X²)` at `β`.
    #[inline]
    pub(super) fn at(&self, beta: f64) -> (f64, f64) {
        let t = 1.0 - beta;
        (
            t * self.sd + beta * self.ud,
            t * (t * self.ss + 2.0 * beta * self.su) + beta * beta * self.uu,
        )
    }
}

/// Buffers of a β sweep.
#[derive(Default)]
pub(super) struct Sweep {
    /// `M(β)` per β.
    pub(super) max: Vec<f64>,
    /// `Σ (D − P)²` per β.
    pub(super) values: Vec<f64>,
}

impl Sweep {
    /// Fills `values` with `Σ (D − P)²` for every β: `M(β)` as the max of
    /// the hull's lines, then the closed form, each a branch-free loop over
    /// β (which the compiler vectorises).
    pub(super) fn run(&mut self, hull: &[(f64, f64)], sums: &Mix, betas: &[f64]) {
        self.max.clear();
        self.max.resize(betas.len(), 0.0);
        for &(s, u) in hull {
            for (m, &beta) in self.max.iter_mut().zip(betas) {
                let v = mix(beta, u, s);
                *m = if v > *m { v } else { *m };
            }
        }
        self.values.clear();
        self.values
            .extend(betas.iter().zip(&self.max).map(|(&beta, &m)| {
                // M = 0 makes every prediction 0, and the error Σ D².
                let inv = if m > 0.0 { 1.0 / m } else { 0.0 };
                let (xd, xx) = sums.at(beta);
                (sums.dd + inv * (inv * xx - 2.0 * xd)).max(0.0)
            }));
    }
}

/// The upper envelope of the lines `β ↦ S + β (U − S)` of `front` (slopes
/// strictly increasing), by the monotone-stack convex-hull pass: the middle of
/// three lines goes when the outer two meet at or before where it meets the first.
pub(super) fn upper_hull(front: &[(f64, f64)], hull: &mut Vec<(f64, f64)>) {
    hull.clear();
    for &(s, u) in front {
        while let [.., (s1, u1), (s2, u2)] = hull[..] {
            let (b1, b2, b3) = (u1 - s1, u2 - s2, u - s);
            if (s1 - s) * (b2 - b1) <= (s1 - s2) * (b3 - b1) {
                hull.pop();
            } else {
                break;
            }
        }
        hull.push((s, u));
    }
}
