//! The free-amplitude grid search for small measurement sets (K ≤
//! [`MAX_MEASUREMENTS`]) in `f32`, allocation-free in caller-provided
//! [`FreeScratch`]: the default objective of the fitting library
//! (docs/conventions.md §4b), `Σ w (D − c ((1 − β) S + β U))²`, on a
//! device with a single-precision FPU.
//!
//! Over a grid of the nonlinear parameters (σ/T, n, a), with β and the
//! amplitude `c ≥ 0` in closed form at every point
//! ([`crate::linear::Moments::solve`], the host's own solve). Per σ/T the
//! surface term `S`; per (σ/T, n) the Ragheb–Hancock base `B` (eqs. 3–7)
//! and the weighted inner products of [`Quadratic`]; then every a of the
//! axis is a 2×2 solve from polynomials in a (`U = B (1 − a cos²θi)(1 − a
//! cos²θs)`, eqs. 12–14), and its objective one pass of residuals over the
//! measurements (the moments' form of it cancels in f32; see
//! `weighted_residuals`). Every operation is `f32` but the data's
//! normalisation and the final Δ_RMS: no `f64` software routine runs per
//! grid point on a Cortex-M4F.
//!
//! The result is the same, bit for bit, on every target (IEEE operations
//! only, sums in a fixed order): the host runs this function as the
//! library's f32 search of the free objective, and the device test
//! compares the two.

use crate::geometry::Geometry;
use crate::lane::Real;
use crate::linear::{Linear, Quadratic};
use crate::measures::check_data;
use crate::onepass::rms_of_sum;
use crate::param::Param;
use crate::small_fit::{Axes, AxisError, SmallFitError, MAX_MEASUREMENTS};
use crate::subsurface::{absorption_factor, subsurface_base, Interface};
use crate::surface::{inverse_slope_squared, surface_radiance, Correlation};

/// Working memory of a free small fit, owned by the caller (a `static` or
/// the stack; 4 KB); its contents between calls do not matter.
#[derive(Clone, Debug)]
pub struct FreeScratch<R = f32> {
    geometry: [Geometry<R>; MAX_MEASUREMENTS],
    /// `D / max`.
    data: [R; MAX_MEASUREMENTS],
    /// `w = (max / σ)²`, or 1.
    weight: [R; MAX_MEASUREMENTS],
    /// `w D`.
    wd: [R; MAX_MEASUREMENTS],
    /// `S` at the current σ/T.
    surface: [R; MAX_MEASUREMENTS],
    /// `w S`.
    ws: [R; MAX_MEASUREMENTS],
    /// `B` at the current (σ/T, n).
    base: [R; MAX_MEASUREMENTS],
    /// `−(cos²θi + cos²θs)`: `B1 = g1 B`.
    g1: [R; MAX_MEASUREMENTS],
    /// `cos²θi cos²θs`: `B2 = g2 B`.
    g2: [R; MAX_MEASUREMENTS],
}

impl<R: Copy> FreeScratch<R> {
    /// Every value set to `z`.
    const fn filled(z: R) -> Self {
        let z_k = [z; MAX_MEASUREMENTS];
        Self {
            geometry: [Geometry::filled(z); MAX_MEASUREMENTS],
            data: z_k,
            weight: z_k,
            wd: z_k,
            surface: z_k,
            ws: z_k,
            base: z_k,
            g1: z_k,
            g2: z_k,
        }
    }
}

impl FreeScratch<f32> {
    /// Zeroed scratch (`const`, so it can be a `static`).
    pub const fn new() -> Self {
        Self::filled(0.0)
    }
}

impl<R: Real> Default for FreeScratch<R> {
    /// Zeroed scratch in any precision (the f64 twin is the tests'
    /// reference).
    fn default() -> Self {
        Self::filled(R::c(0.0))
    }
}

/// The grid of a free small fit: σ/T, n and a values (searched in that
/// loop order) and the box of β, `[lo, hi]` within `[0, 1]`.
#[derive(Clone, Copy, Debug)]
pub struct FreeAxes<'a> {
    /// σ/T values.
    pub slope: &'a [f64],
    /// n values.
    pub n: &'a [f64],
    /// a values.
    pub a: &'a [f64],
    /// The box of β.
    pub beta: (f64, f64),
}

impl FreeAxes<'_> {
    /// Flattened index of a grid point in loop order σ/T, n, a.
    #[must_use]
    pub fn flat(&self, s: usize, n: usize, a: usize) -> usize {
        (s * self.n.len() + n) * self.a.len() + a
    }

    /// The (σ/T, n, a) of a flattened index; NaN past an axis's end.
    #[must_use]
    pub fn point(&self, flat: usize) -> (f64, f64, f64) {
        let len = |axis: &[f64]| axis.len().max(1);
        let a = flat % len(self.a);
        let rest = flat / len(self.a);
        let at = |axis: &[f64], i: usize| axis.get(i).copied().unwrap_or(f64::NAN);
        (
            at(self.slope, rest / len(self.n)),
            at(self.n, rest % len(self.n)),
            at(self.a, a),
        )
    }

    /// Checks the axes as [`Axes::validate`] does (β's box ends as its
    /// axis), and that the box is not empty (`lo ≤ hi`).
    ///
    /// # Errors
    /// The first [`AxisError`]; an empty box is [`AxisError::Empty`] of
    /// [`Param::Beta`].
    pub fn validate(&self) -> Result<(), AxisError> {
        let (lo, hi) = self.beta;
        Axes {
            slope: self.slope,
            n: self.n,
            a: self.a,
            beta: &[lo, hi],
        }
        .validate()?;
        if lo <= hi {
            Ok(())
        } else {
            Err(AxisError::Empty { axis: Param::Beta })
        }
    }
}

/// What a free small fit found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FreeFit<R = f32> {
    /// Flattened index of the best grid point ([`FreeAxes::flat`];
    /// smallest on ties).
    pub best: usize,
    /// Its weighted objective `Σ w (D − c M)²`, on the max-normalised data
    /// (summed over the residuals).
    pub objective: R,
    /// The amplitude `c` there (on the max-normalised data).
    pub amplitude: R,
    /// β there (eq. 8; β's box's lower end when `c = 0`).
    pub beta: R,
    /// Its `Δ_RMS` (eq. 15) on the max-normalised data, with the fitted
    /// prediction `c M`.
    pub rms: f64,
    /// The best grid point with a = 0 (Ragheb–Hancock) and its objective,
    /// when the a axis holds 0.
    pub rh_best: Option<(usize, R)>,
}

/// Fits the geometries `geometry` to the un-normalised data `data`
/// (standard uncertainties `sigma`, on the data's scale, or none for
/// weights of 1) over `axes` with correlation `corr`, by the
/// free-amplitude objective (module docs). The data and uncertainties
/// are divided by the data's max in `f64`, then rounded to the precision
/// `R` (`f32` on a device; the same code in `f64` is the tests'
/// reference).
///
/// # Errors
/// [`SmallFitError`] for a bad count, datum, uncertainty or grid.
pub fn fit_free<R: Real, G: Copy + Into<Geometry<R>>>(
    corr: Correlation,
    geometry: &[G],
    (data, sigma): (&[f64], Option<&[f64]>),
    axes: &FreeAxes<'_>,
    scratch: &mut FreeScratch<R>,
) -> Result<FreeFit<R>, SmallFitError> {
    let k = geometry.len();
    if k == 0 || k > MAX_MEASUREMENTS || data.len() != k || sigma.is_some_and(|s| s.len() != k) {
        return Err(SmallFitError::Count {
            geometries: k,
            data: data.len(),
        });
    }
    check_data(data).map_err(|(index, fault)| SmallFitError::Data { index, fault })?;
    let max = data.iter().fold(0.0f64, |m, &d| m.max(d));
    axes.validate().map_err(SmallFitError::Axis)?;
    // Every slice below is the first k of a MAX_MEASUREMENTS array, and
    // every index below k: in bounds, as the compiler sees (no panic path).
    let k = k.min(MAX_MEASUREMENTS);
    for (i, (&g, &d)) in geometry.iter().zip(data).enumerate().take(k) {
        if i >= MAX_MEASUREMENTS {
            break;
        }
        let weight = match sigma.map(|s| s.get(i).copied().unwrap_or(f64::NAN)) {
            None => R::c(1.0),
            Some(s) => {
                let root = max / s;
                let w = R::from_f64(root * root);
                // Also refuses σ ≤ 0, NaN and a weight past R's range.
                if !(s > 0.0 && w.to_f64().is_finite() && w.to_f64() > 0.0) {
                    return Err(SmallFitError::Sigma { index: i });
                }
                w
            }
        };
        let g: Geometry<R> = g.into();
        let d = R::from_f64(d / max);
        let (ci, cs) = (R::c(1.0) - g.sin2_i, R::c(1.0) - g.sin2_s);
        scratch.geometry[i] = g;
        scratch.data[i] = d;
        scratch.weight[i] = weight;
        scratch.wd[i] = weight * d;
        scratch.g1[i] = R::c(0.0) - (ci + cs);
        scratch.g2[i] = ci * cs;
    }
    let dd = dot(&scratch.wd[..k], &scratch.data[..k]);
    let zero_a = axes.a.iter().position(|&a| a == 0.0);
    let mut best: Option<(usize, Linear<R>)> = None;
    let mut rh: Option<(usize, R)> = None;
    for (i_s, &slope) in axes.slope.iter().enumerate() {
        let inv_s2 = inverse_slope_squared(R::from_f64(slope));
        for i in 0..k {
            let s = surface_radiance(&scratch.geometry[i], corr, inv_s2);
            scratch.surface[i] = s;
            scratch.ws[i] = scratch.weight[i] * s;
        }
        let ss = dot(&scratch.ws[..k], &scratch.surface[..k]);
        let ds = dot(&scratch.wd[..k], &scratch.surface[..k]);
        for (i_n, &n) in axes.n.iter().enumerate() {
            let q = quadratic(scratch, k, (corr, inv_s2, R::from_f64(n)), (dd, ds, ss));
            for (i_a, &a) in axes.a.iter().enumerate() {
                let a = R::from_f64(a);
                let solved = q.moments(a).solve(axes.beta);
                let solved = Linear {
                    sse: weighted_residuals(scratch, k, a, &solved),
                    ..solved
                };
                let flat = axes.flat(i_s, i_n, i_a);
                if best.is_none_or(|(_, b)| solved.sse < b.sse) {
                    best = Some((flat, solved));
                }
                if zero_a == Some(i_a) && rh.is_none_or(|(_, b)| solved.sse < b) {
                    rh = Some((flat, solved.sse));
                }
            }
        }
    }
    let (best, solved) = best.unwrap_or((
        0,
        Linear {
            p: R::c(0.0),
            q: R::c(0.0),
            sse: R::c(f64::INFINITY),
        },
    ));
    let (slope, n, a) = axes.point(best);
    let prediction = Prediction {
        corr,
        inv_s2: inverse_slope_squared(R::from_f64(slope)),
        n: R::from_f64(n),
        a: R::from_f64(a),
        linear: solved,
    };
    let residual = (0..k).fold(0.0f64, |e, i| {
        let r = (scratch.data[i] - prediction.at(&scratch.geometry[i])).to_f64();
        e + r * r
    });
    Ok(FreeFit {
        best,
        objective: solved.sse,
        amplitude: solved.amplitude(),
        beta: solved.beta(R::from_f64(axes.beta.0)),
        rms: rms_of_sum(residual, k),
        rh_best: rh,
    })
}

/// The fitted prediction `p S + q U` at one point of the grid.
struct Prediction<R> {
    corr: Correlation,
    inv_s2: R,
    n: R,
    a: R,
    linear: Linear<R>,
}

impl<R: Real> Prediction<R> {
    fn at(&self, g: &Geometry<R>) -> R {
        let s = surface_radiance(g, self.corr, self.inv_s2);
        let base = subsurface_base(&Interface::new(g, self.n), self.corr, self.inv_s2);
        self.linear.p * s + self.linear.q * (base * absorption_factor(g, self.a))
    }
}

/// `Σ w (D − p S − q U)²` at absorption `a`, from the surface term and
/// base in `scratch`, summed in measurement order: the objective to the
/// precision of the residuals (the moments' `Σ w D² − …` would lose what
/// `Σ w D²` has over it, in f32 about 10⁻⁷ of `Σ w D²`: more than a good
/// fit's whole objective).
fn weighted_residuals<R: Real>(scratch: &FreeScratch<R>, k: usize, a: R, linear: &Linear<R>) -> R {
    let mut sum = R::c(0.0);
    for i in 0..k.min(MAX_MEASUREMENTS) {
        let u = scratch.base[i] * absorption_factor(&scratch.geometry[i], a);
        let r = scratch.data[i] - (linear.p * scratch.surface[i] + linear.q * u);
        sum = sum + scratch.weight[i] * (r * r);
    }
    sum
}

/// The weighted inner products of one (σ/T, n), and the base `B` of every
/// measurement into `scratch`, in one pass, summed in measurement order.
fn quadratic<R: Real>(
    scratch: &mut FreeScratch<R>,
    k: usize,
    (corr, inv_s2, n): (Correlation, R, R),
    (dd, ds, ss): (R, R, R),
) -> Quadratic<R> {
    let z = R::c(0.0);
    let mut db = [z; 3];
    let mut sb = [z; 3];
    let mut bb = [z; 6];
    for i in 0..k.min(MAX_MEASUREMENTS) {
        let g = &scratch.geometry[i];
        let base = subsurface_base(&Interface::new(g, n), corr, inv_s2);
        scratch.base[i] = base;
        let (g1, g2) = (scratch.g1[i], scratch.g2[i]);
        let (wdb, wsb) = (scratch.wd[i] * base, scratch.ws[i] * base);
        let wbb = scratch.weight[i] * base * base;
        db = [db[0] + wdb, db[1] + wdb * g1, db[2] + wdb * g2];
        sb = [sb[0] + wsb, sb[1] + wsb * g1, sb[2] + wsb * g2];
        bb = [
            bb[0] + wbb,
            bb[1] + wbb * g1,
            bb[2] + wbb * g2,
            bb[3] + wbb * (g1 * g1),
            bb[4] + wbb * (g1 * g2),
            bb[5] + wbb * (g2 * g2),
        ];
    }
    let [b00, b01, b02, b11, b12, b22] = bb;
    Quadratic {
        dd,
        ds,
        ss,
        db,
        sb,
        bb: [[b00, b01, b02], [b01, b11, b12], [b02, b12, b22]],
    }
}

/// `Σ x y` in measurement order.
fn dot<R: Real>(x: &[R], y: &[R]) -> R {
    x.iter().zip(y).fold(R::c(0.0), |s, (&x, &y)| s + x * y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Angles;
    use crate::radiance::{total_radiance, Params};
    use crate::small_fit::{stepped, PAPER};
    use std::vec::Vec;

    fn paper_axis(i: usize) -> Vec<f64> {
        let (start, step, count) = PAPER[i];
        (0..count).map(|j| stepped(start, step, j)).collect()
    }

    /// 30 spread geometries in `R`.
    fn geometries<R: Real>() -> Vec<Geometry<R>> {
        let mut out = Vec::new();
        for t in 0..6 {
            for s in 0..5 {
                let angles =
                    Angles::new(0.1 + 0.2 * t as f64, 0.05 + 0.25 * s as f64, 0.3 * s as f64)
                        .unwrap();
                out.push(Geometry::<R>::splat(&angles));
            }
        }
        out
    }

    /// The model at a grid point times 3, with a fixed ±`ripple` pattern.
    fn data(corr: Correlation, p: &Params, ripple: f64) -> Vec<f64> {
        geometries::<f64>()
            .iter()
            .enumerate()
            .map(|(i, g)| {
                let pattern = ((i * 7) % 5) as f64 - 2.0;
                3.0 * total_radiance(g, corr, p) * (1.0 + ripple * pattern / 2.0)
            })
            .collect()
    }

    /// The f32 search against the same code in f64 on the paper's
    /// nonlinear grid: noise-free data are fitted to f32's rounding at β,
    /// and on rippled data the f32 pick is the f64 minimum or, where the
    /// f64 objective of the two differs by less than f32 resolves (the
    /// moments' `Σ w D²` cancels), within 10⁻³ of it.
    #[test]
    fn the_f32_search_finds_the_f64_minimum() {
        let (slope, n, a) = (paper_axis(0), paper_axis(1), paper_axis(2));
        let axes = FreeAxes {
            slope: &slope,
            n: &n,
            a: &a,
            beta: (0.0, 1.0),
        };
        let (g32, g64) = (geometries::<f32>(), geometries::<f64>());
        let mut s32 = FreeScratch::new();
        let mut s64 = FreeScratch::<f64>::default();
        // The f64 objective at one grid point: the grid of that point alone.
        let mut objective_at = |corr, data: &[f64], flat: usize| {
            let (sl, nn, aa) = axes.point(flat);
            let one = FreeAxes {
                slope: &[sl],
                n: &[nn],
                a: &[aa],
                beta: axes.beta,
            };
            fit_free(corr, &g64, (data, None), &one, &mut s64)
                .unwrap()
                .objective
        };
        for corr in [Correlation::Exponential, Correlation::Gaussian] {
            let p = Params::new(slope[10], 0.35, n[6], a[25]).unwrap();
            let exact = data(corr, &p, 0.0);
            let fit = fit_free(corr, &g32, (&exact, None), &axes, &mut s32).unwrap();
            // Eq. 15's Δ_RMS is 100 √(Σ r²)/K: 1e-4 is residuals of about
            // 2e-7 of the max, f32's rounding.
            assert!(fit.rms < 1e-4, "{corr:?}: rms {}", fit.rms);
            for (truth, ripple) in [
                ((0.9, 0.4, 1.42, 0.3), 0.01),
                ((3.1, 0.7, 1.33, 0.05), 0.03),
            ] {
                let p = Params::new(truth.0, truth.1, truth.2, truth.3).unwrap();
                let rippled = data(corr, &p, ripple);
                let fit = fit_free(corr, &g32, (&rippled, None), &axes, &mut s32).unwrap();
                let reference = {
                    let mut s = FreeScratch::<f64>::default();
                    fit_free(corr, &g64, (&rippled, None), &axes, &mut s).unwrap()
                };
                let picked = objective_at(corr, &rippled, fit.best);
                assert!(
                    picked <= reference.objective * (1.0 + 1e-3),
                    "{corr:?} {truth:?}: f32 pick {picked} against the f64 minimum {}",
                    reference.objective
                );
                let (rel, f32_rel) = (
                    (fit.objective.to_f64() - reference.objective).abs() / reference.objective,
                    1e-2,
                );
                assert!(rel < f32_rel, "{corr:?} {truth:?}: objective off by {rel}");
            }
            // Uncertainties that weight all alike change nothing but the scale.
            let sigma = [0.25 * exact[0]; 30];
            let weighted = fit_free(corr, &g32, (&exact, Some(&sigma)), &axes, &mut s32).unwrap();
            assert!(weighted.rms < 1e-3);
        }
    }

    #[test]
    fn bad_counts_data_sigma_and_boxes_are_errors() {
        let g = [Geometry::<f32>::splat(&Angles::new(0.3, 0.4, 1.0).unwrap()); 3];
        let (slope, n, a) = ([0.5], [1.4], [0.0, 0.2]);
        let axes = FreeAxes {
            slope: &slope,
            n: &n,
            a: &a,
            beta: (0.0, 1.0),
        };
        let mut scratch = FreeScratch::new();
        let mut run = |data: &[f64], sigma: Option<&[f64]>, axes: &FreeAxes| {
            fit_free(
                Correlation::Exponential,
                &g,
                (data, sigma),
                axes,
                &mut scratch,
            )
        };
        assert!(matches!(
            run(&[1.0, 2.0], None, &axes),
            Err(SmallFitError::Count { .. })
        ));
        assert!(matches!(
            run(&[1.0, 2.0, 1.0], Some(&[1.0]), &axes),
            Err(SmallFitError::Count { .. })
        ));
        assert!(matches!(
            run(&[1.0, f64::NAN, 1.0], None, &axes),
            Err(SmallFitError::Data { index: 1, .. })
        ));
        for bad in [0.0, -1.0, f64::NAN, 1e-30] {
            assert_eq!(
                run(&[1.0, 2.0, 1.0], Some(&[0.1, bad, 0.1]), &axes),
                Err(SmallFitError::Sigma { index: 1 }),
                "σ = {bad}"
            );
        }
        let empty = FreeAxes {
            beta: (0.6, 0.4),
            ..axes
        };
        assert_eq!(
            run(&[1.0, 2.0, 1.0], None, &empty),
            Err(SmallFitError::Axis(AxisError::Empty { axis: Param::Beta }))
        );
        let outside = FreeAxes {
            beta: (0.0, 1.5),
            ..axes
        };
        assert!(matches!(
            run(&[1.0, 2.0, 1.0], None, &outside),
            Err(SmallFitError::Axis(AxisError::OutOfDomain {
                axis: Param::Beta,
                ..
            }))
        ));
        let fit = run(&[1.0, 2.0, 1.5], None, &axes).unwrap();
        assert!(fit.rh_best.is_some() && fit.objective.is_finite());
    }
}
