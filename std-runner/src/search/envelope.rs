//! Path 3, the closed-form β sweep. For the paper normalisation (conventions
//! §4), with `X = (1 − β) S + β U = S + β Δ` (`Δ = U − S`) and
//! `M(β) = max_k X_k`,
//!
//! `Σ (D − X/M)² = Σ D² + (Σ X² / M − 2 Σ X D) / M`, where
//! `Σ X D = Σ S D + β Σ Δ D` and `Σ X² = Σ S² + β (2 Σ S Δ + β Σ Δ²)`,
//!
//! so six sums over the measurements (three per σ/T, three per (σ/T, n, a))
//! give the error of every β. `M(β)` is the upper envelope of the lines
//! `β ↦ (1 − β) S_k + β U_k`; on β ∈ [0, 1] only measurements on the Pareto
//! front of `(S_k, U_k)` can attain it (a dominated point's mix is never
//! larger, even after rounding, since every operation rounds monotonically),
//! and the front is found from the order of `S`, which is sorted once per
//! σ/T; the walk stops at the first `U_k = 1` (U is normalised, so no later
//! point can join). Along the front the slopes `U_k − S_k` increase, so the
//! upper hull of its lines is one monotone-stack pass, and a pointer walked
//! along the hull gives `M(β)` in amortised O(1) per β (instead of O(K)). The
//! hull drops lines that are never the maximum in exact arithmetic; after
//! rounding `M` is the full max to within an ulp or two, which the tests
//! against the direct path bound.
//!
//! `S` and `U` are computed in the lane precision of the path (that is what
//! the f32 variants trade for speed); they are widened exactly, and the sums,
//! the envelope and the error are evaluated in `f64` in measurement order, so
//! the `f32x8` path and its scalar twin agree bit for bit. The sums over `Δ`
//! are formed from `Δ` itself, not as differences of sums over `U` and `S`,
//! and the remaining cancellation in the formula above (about 100× on CUReT
//! fits) costs nothing visible in `f64`.

use super::packed::Packed;
use laminar_core::{mix, Lane};

/// Per-σ/T quantities: the widened surface term, its order, its sums.
pub struct SurfaceSums {
    s: Vec<f64>,
    d: Vec<f64>,
    /// Measurements by decreasing `S` (ties: increasing index).
    order: Vec<usize>,
    ss: f64,
    sd: f64,
    dd: f64,
}

impl SurfaceSums {
    /// Widens `surface` and computes `Σ S²`, `Σ S D`, `Σ D²`.
    pub fn new<L: Lane>(packed: &Packed<L>, surface: &[L]) -> Self {
        let mut s = vec![0.0; packed.k];
        let mut d = vec![0.0; packed.k];
        packed.widen(surface, &mut s);
        packed.widen(&packed.data, &mut d);
        let mut order: Vec<usize> = (0..packed.k).collect();
        order.sort_by(|&a, &b| s[b].total_cmp(&s[a]).then(a.cmp(&b)));
        let ss = s.iter().map(|v| v * v).sum();
        let sd = s.iter().zip(&d).map(|(a, b)| a * b).sum();
        let dd = d.iter().map(|v| v * v).sum();
        Self {
            s,
            d,
            order,
            ss,
            sd,
            dd,
        }
    }
}

/// Reusable per-shard buffers.
#[derive(Default)]
pub struct Scratch {
    u: Vec<f64>,
    /// The Pareto front as `(S_k, U_k)`, by decreasing `S` and increasing `U`.
    front: Vec<(f64, f64)>,
    /// The upper hull of the front's lines, as `(S_k, U_k)`.
    hull: Vec<(f64, f64)>,
    /// Total front size over the sweeps (for the report).
    pub front_total: usize,
    /// Number of sweeps.
    pub sweeps: usize,
}

/// Calls `visit(i_b, Σ (D − P)²)` for every β of `betas`, in order, for one
/// (σ/T, n, a) with normalised subsurface `subsurface`.
pub fn sweep<L: Lane>(
    packed: &Packed<L>,
    surface: &SurfaceSums,
    subsurface: &[L],
    betas: &[f64],
    scratch: &mut Scratch,
    mut visit: impl FnMut(usize, f64),
) {
    let k = packed.k;
    scratch.u.resize(k, 0.0);
    packed.widen(subsurface, &mut scratch.u);
    let u = &scratch.u;
    // Σ Δ², Σ S Δ, Σ D Δ.
    let (mut del_del, mut s_del, mut d_del) = (0.0, 0.0, 0.0);
    for ((u, s), d) in u.iter().zip(&surface.s).zip(&surface.d) {
        let del = u - s;
        del_del += del * del;
        s_del += s * del;
        d_del += d * del;
    }
    scratch.front.clear();
    let mut top = f64::NEG_INFINITY;
    for &i in &surface.order {
        if u[i] > top {
            top = u[i];
            scratch.front.push((surface.s[i], u[i]));
            if top >= 1.0 {
                // U is normalised (no value above 1): no later point, with
                // its smaller S, can join the front.
                break;
            }
        }
    }
    scratch.front_total += scratch.front.len();
    scratch.sweeps += 1;
    upper_hull(&scratch.front, &mut scratch.hull);
    let hull = &scratch.hull;
    let mut p = 0;
    for (i_b, &beta) in betas.iter().enumerate() {
        let value = |i: usize| mix(beta, hull[i].1, hull[i].0);
        while p + 1 < hull.len() && value(p + 1) >= value(p) {
            p += 1;
        }
        while p > 0 && value(p - 1) > value(p) {
            p -= 1;
        }
        let m = value(p);
        let e = if m > 0.0 {
            let inv = 1.0 / m;
            let xd = surface.sd + beta * d_del;
            let xx = surface.ss + beta * (2.0 * s_del + beta * del_del);
            surface.dd + inv * (inv * xx - 2.0 * xd)
        } else {
            surface.dd
        };
        visit(i_b, e.max(0.0));
    }
}

/// The upper envelope of the lines `β ↦ S + β (U − S)` of `front` (slopes
/// strictly increasing), by the monotone-stack convex-hull pass: the middle of
/// three lines goes when the outer two meet at or before where it meets the first.
fn upper_hull(front: &[(f64, f64)], hull: &mut Vec<(f64, f64)>) {
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
