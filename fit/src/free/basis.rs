//! The basis functions of each model under the free amplitude
//! (docs/conventions.md §4b): the columns that the linear coefficients
//! multiply, at given nonlinear parameters, and their derivatives.
//!
//! * Layered models (eqs. 1–2, 12–13): two columns, the raw surface term
//!   `S_k = L^sf_k` and the raw subsurface term `U_k = L^sb_k(a)`; eq. 8's mix
//!   is `(1 − β) S + β U`, times the amplitude. The nonlinear parameters are
//!   `(ln σ/T, n, a)` (a fixed at 0 for Ragheb–Hancock); σ/T enters through
//!   its logarithm so that steps are relative, as its box is log-spaced.
//!   `U` is a quadratic in a: `U = B (1 − a cos²θi)(1 − a cos²θs)` with `B`
//!   the Ragheb–Hancock base (eqs. 3–4), which the grid search uses.
//! * Baselines (§7): one column, the raw radiance `L_k` (Jensen's at
//!   (σa, σs′), Oren–Nayar's at (σ, ρ)).

use super::boundary::{boundary, BoundaryGroup};
use super::pool::{self, Free};
use crate::baseline::BaselineGeometry;
use crate::model::{Family, Model};
use laminar_core::radiance::{SLOPE_MAX, SLOPE_MIN};
use laminar_core::{
    f32x8, f64x4, inverse_slope_squared, surface_radiance, Angles, Correlation, Geometry, Lane,
};
use std::sync::OnceLock;

/// The columns of a model at one point: `s` always, `u` for the layered
/// models (empty for a baseline). Of a derivative, an empty column is zero
/// (the surface term's in n and a).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Columns {
    /// `S_k` (layered) or `L_k` (baseline).
    pub s: Vec<f64>,
    /// `U_k` (layered), empty for a baseline.
    pub u: Vec<f64>,
}

impl Drop for Columns {
    /// The vectors go back to the thread's pool ([`pool`]).
    fn drop(&mut self) {
        pool::release(std::mem::take(&mut self.s));
        pool::release(std::mem::take(&mut self.u));
    }
}

/// Central difference step of the parameters without an analytic derivative
/// (n, and the baselines' parameters): relative error about `h²` from the
/// truncation and `ε/h` from rounding, both near 10⁻¹⁰.
const STEP: f64 = 1e-5;

/// The measurements' geometry in the form each model evaluates it.
#[derive(Debug, Clone)]
pub enum Basis {
    /// A layered model.
    Layered {
        /// The correlation function (eqs. 1–2).
        corr: Correlation,
        /// The number of measurements.
        len: usize,
        /// Their geometry four at a time (`pack`, the last group padded),
        /// which the columns are computed from: lane by lane the same bits
        /// as one at a time (the core's f64x4 path is bitwise its scalar
        /// f64 path).
        packed: Vec<Geometry<f64x4>>,
        /// The same eight at a time in single precision (the last group
        /// padded likewise), for the grid stage's `f32x8` path: built from
        /// `angles` when first asked for.
        packed8: OnceLock<Vec<Geometry<f32x8>>>,
        /// The measurements' directions.
        angles: Vec<Angles>,
        /// `cos²θi` of each measurement.
        cos2_i: Vec<f64>,
        /// `cos²θs` of each measurement.
        cos2_s: Vec<f64>,
        /// True for Ragheb–Hancock (a = 0, two nonlinear parameters).
        rh: bool,
    },
    /// A baseline (two parameters, one column).
    Baseline(BaselineGeometry),
}

/// The columns at one point, with what their derivatives there need
/// (so that a minimisation that accepts a trial point reuses its work).
#[derive(Debug, Clone)]
pub struct Evaluated {
    /// The columns.
    pub columns: Columns,
    terms: Option<LayeredTerms>,
}

/// What a minimisation keeps while some parameters are held
/// ([`Basis::held`]): the boundary (eqs. 5–7, [`super::boundary`]) at a
/// held n, which the columns at every σ/T and a reuse.
#[derive(Debug, Clone, Default)]
pub struct Held {
    boundary: Option<(f64, Vec<BoundaryGroup>)>,
}

impl Held {
    /// The held boundary, when it is the one at `n`.
    fn at(&self, n: f64) -> Option<&[BoundaryGroup]> {
        match &self.boundary {
            Some((at, groups)) if *at == n => Some(groups),
            _ => None,
        }
    }
}

/// The surface term, the boundary and the Ragheb–Hancock base `B` of four
/// measurements at one (σ/T, n).
#[derive(Debug, Clone, Copy)]
struct LayerGroup {
    surface: f64x4,
    boundary: BoundaryGroup,
    base: f64x4,
}

impl LayerGroup {
    /// The terms of the measurements `g` on `boundary` at `(T/σ)²` `t`.
    /// Inlined into the loop that collects them, so that each group is
    /// written in place in its Vec, not returned and then copied (a
    /// `memcpy` per group: 7.7% of the defaults' profile at K = 22,801, and
    /// 3.5% more sets per second without it).
    #[inline(always)]
    fn new(g: &Geometry<f64x4>, boundary: BoundaryGroup, corr: Correlation, t: f64x4) -> Self {
        Self {
            surface: surface_radiance(g, corr, t),
            base: boundary.base(corr, t),
            boundary,
        }
    }
}

/// A layered model's terms at one (σ/T, n), four measurements at a time
/// (the basis's packing), with what their derivatives need.
#[derive(Debug, Clone)]
struct LayeredTerms {
    groups: Vec<LayerGroup>,
    /// `(T/σ)²`: the surface term's argument is `x = (T/σ)² v_xy²/v_z²`,
    /// the base's `x′ = (T/σ)² · ratio`.
    t: f64,
}

thread_local! {
    /// The vectors of [`LayeredTerms`] released on this thread ([`pool`]).
    static GROUPS: Free<LayerGroup, 3> = const { Free::new() };
}

impl Drop for LayeredTerms {
    fn drop(&mut self) {
        let groups = std::mem::take(&mut self.groups);
        let _ = GROUPS.try_with(|f| f.give(groups));
    }
}

/// `∂ ln B/∂n` of the Ragheb–Hancock base at four measurements `g` (eqs.
/// 3–7), analytically, from the refracted cosines of their boundary `b`;
/// `x_refracted` is eq. 1–2's argument below the boundary.
///
/// Snell's `cos θ′ = √(n² − sin²θ)/n` gives `∂cos θ′/∂n = sin²θ/(n³ cos θ′)`.
/// The leading factor `cos θi′/v_z′²`, the solid angle
/// `cos θi/(n² cos θi′)` (eq. 5) and the shape's argument
/// `x′ ∝ v_xy²/(n² v_z′²)` all vary as `n⁻² v_z′⁻²` (the `cos θi′` cancel),
/// whose logarithmic derivative is `ℓ = −2/n − 2 ∂v_z′/∂n / v_z′`; the shape
/// adds its elasticity `∂ ln shape/∂ ln x′` times `ℓ`. Each transmission
/// (eq. 7) is `t = 2 n c c′ (1/s² + 1/p²)` with `s = c + n c′`,
/// `p = n c + c′`. Where `B = 0` the caller uses 0.
fn log_n_derivative(
    corr: Correlation,
    g: &Geometry<f64x4>,
    b: &BoundaryGroup,
    n: f64,
    x_refracted: f64x4,
) -> f64x4 {
    let c = f64x4::c;
    let (n, inv_n) = (f64x4::splat(n), f64x4::splat(1.0 / n));
    let (ci, cs) = (b.cos_i, b.cos_s);
    // `∂cos θ′/∂n / cos θ′ = sin²θ/(n³ cos²θ′)`, and the derivative itself.
    let rel = |sin2: f64x4, c: f64x4| sin2 * inv_n * inv_n * inv_n / (c * c);
    let (ri, rs) = (rel(g.sin2_i, ci), rel(g.sin2_s, cs));
    let (dci, dcs) = (ri * ci, rs * cs);
    let ell = c(-2.0) * inv_n - c(2.0) * (dci + dcs) / (ci + cs);
    // The elasticity of the shape in x′ is half that in σ/T with the sign
    // turned, as x ∝ (σ/T)⁻².
    let elasticity = c(-0.5) * corr.log_slope_derivative(x_refracted);
    // `∂ ln t/∂n = 1/n + ∂ ln c′/∂n − 2 (s_n/s³ + p_n/p³)/(1/s² + 1/p²)`,
    // the last term as `2 (s_n p³ + p_n s³)/(s p (s² + p²))`.
    let transmission = |c1: f64x4, c2: f64x4, dc2: f64x4, rel2: f64x4| {
        let (s, p) = (c1 + n * c2, n * c1 + c2);
        let (ds, dp) = (c2 + n * dc2, c1 + dc2);
        let (s2, p2) = (s * s, p * p);
        inv_n + rel2 - c(2.0) * (ds * p2 * p + dp * s2 * s) / (s * p * (s2 + p2))
    };
    (c(1.0) + elasticity) * ell
        + transmission(g.cos_i, ci, dci, ri)
        + transmission(g.cos_s, cs, dcs, rs)
}

/// `angles` a lane's width at a time, the last group padded with its last
/// measurement (whose lanes [`unpack`] drops).
fn pack<L: Lane>(angles: &[Angles]) -> Vec<Geometry<L>> {
    angles
        .chunks(L::LANES)
        .map(|group| Geometry::from_lanes(|i| group[i.min(group.len() - 1)]))
        .collect()
}

/// A lane type the basis keeps the measurements' geometry packed in:
/// `f64x4` (every stage) and `f32x8` (the grid stage in single precision).
pub trait Packed: Lane {
    /// The packed geometry of `basis` (empty for a baseline).
    fn packed(basis: &Basis) -> &[Geometry<Self>];

    /// Groups of this lane's values as groups of four `f64`, exactly and in
    /// order (the grid stage's sums run in `f64x4`).
    fn widened(groups: impl Iterator<Item = Self>) -> impl Iterator<Item = f64x4>;
}

impl Packed for f64x4 {
    fn packed(basis: &Basis) -> &[Geometry<Self>] {
        match basis {
            Basis::Layered { packed, .. } => packed,
            Basis::Baseline(_) => &[],
        }
    }

    fn widened(groups: impl Iterator<Item = Self>) -> impl Iterator<Item = f64x4> {
        groups
    }
}

impl Packed for f32x8 {
    fn packed(basis: &Basis) -> &[Geometry<Self>] {
        match basis {
            Basis::Layered {
                packed8, angles, ..
            } => packed8.get_or_init(|| pack(angles)),
            Basis::Baseline(_) => &[],
        }
    }

    fn widened(groups: impl Iterator<Item = Self>) -> impl Iterator<Item = f64x4> {
        groups.flat_map(|v| {
            let v = v.to_array();
            [0, 4].map(|h| f64x4::from_f64_lanes(|i| f64::from(v[h + i])))
        })
    }
}

/// The first `len` lanes of `groups`, in measurement order.
fn unpack(groups: impl Iterator<Item = f64x4>, len: usize) -> Vec<f64> {
    let mut out = pool::vector(len.next_multiple_of(4));
    groups.for_each(|v| out.extend_from_slice(&v.to_array()));
    out.truncate(len);
    out
}

impl Basis {
    /// The basis of `model` at the measurements `angles`.
    pub fn new(model: Model, angles: &[Angles]) -> Self {
        match model.family() {
            Family::Layered {
                correlation,
                absorption,
            } => {
                let geometry: Vec<Geometry<f64>> =
                    angles.iter().map(Geometry::<f64>::splat).collect();
                Self::Layered {
                    corr: correlation,
                    packed: pack(angles),
                    packed8: OnceLock::new(),
                    angles: angles.to_vec(),
                    cos2_i: geometry.iter().map(|g| 1.0 - g.sin2_i).collect(),
                    cos2_s: geometry.iter().map(|g| 1.0 - g.sin2_s).collect(),
                    len: angles.len(),
                    rh: !absorption,
                }
            }
            Family::Baseline(b) => Self::Baseline(BaselineGeometry::new(b, angles)),
        }
    }

    /// Number of nonlinear parameters.
    pub fn dim(&self) -> usize {
        match self {
            Self::Layered { rh: true, .. } => 2,
            Self::Layered { .. } => 3,
            Self::Baseline(_) => 2,
        }
    }

    /// True when the model has the second column `U` (and so β).
    pub fn has_balance(&self) -> bool {
        matches!(self, Self::Layered { .. })
    }

    /// Number of measurements.
    pub fn len(&self) -> usize {
        match self {
            Self::Layered { len, .. } => *len,
            Self::Baseline(g) => g.len(),
        }
    }

    /// The boundary at refractive index `n` ([`super::boundary`]), a lane's
    /// width of measurements at a time (layered models only).
    pub fn boundary<L: Packed>(&self, n: f64) -> Vec<BoundaryGroup<L>> {
        boundary(L::packed(self), n)
    }

    /// The raw surface term at σ/T (layered models only).
    pub fn surface(&self, slope: f64) -> Vec<f64> {
        match self {
            Self::Layered { corr, packed, .. } => {
                let t = f64x4::splat(inverse_slope_squared(slope));
                let groups = packed.iter().map(|g| surface_radiance(g, *corr, t));
                unpack(groups, self.len())
            }
            Self::Baseline(_) => Vec::new(),
        }
    }

    /// The Ragheb–Hancock base `B_k` (eqs. 3–4) at σ/T on the boundary at
    /// one n ([`Basis::boundary`]), a lane's width of measurements at a time
    /// (the last group padded as [`Basis::boundary`]'s is); empty for a
    /// baseline.
    pub fn base_groups<'a, L: Lane + 'a>(
        &self,
        slope: f64,
        boundary: &'a [BoundaryGroup<L>],
    ) -> impl Iterator<Item = L> + 'a {
        let corr = match self {
            Self::Layered { corr, .. } => Some(*corr),
            Self::Baseline(_) => None,
        };
        let t = L::c(inverse_slope_squared(slope));
        corr.into_iter()
            .flat_map(move |corr| boundary.iter().map(move |b| b.base(corr, t)))
    }

    /// `cos²θi` and `cos²θs` of each measurement (layered models).
    pub fn cosines(&self) -> (&[f64], &[f64]) {
        match self {
            Self::Layered { cos2_i, cos2_s, .. } => (cos2_i, cos2_s),
            Self::Baseline(_) => (&[], &[]),
        }
    }

    /// The absorption factor `(1 − a cos²θi)(1 − a cos²θs)` of four
    /// measurements `g` (eqs. 10–14), and the two `cos²`.
    fn attenuation(g: &Geometry<f64x4>, a: f64x4) -> (f64x4, [f64x4; 2]) {
        let one = f64x4::c(1.0);
        let (ci, cs) = (one - g.sin2_i, one - g.sin2_s);
        ((one - a * ci) * (one - a * cs), [ci, cs])
    }

    /// The [`LayeredTerms`] at (σ/T, n): one pass over the measurements,
    /// each group's boundary built (or taken from `held`) and used at once.
    fn layered_terms(&self, slope: f64, n: f64, held: &Held) -> LayeredTerms {
        let Self::Layered { corr, packed, .. } = self else {
            unreachable!("layered models only")
        };
        let t = inverse_slope_squared(slope);
        let t4 = f64x4::splat(t);
        let group =
            |g: &Geometry<f64x4>, boundary: BoundaryGroup| LayerGroup::new(g, boundary, *corr, t4);
        let mut groups = GROUPS.with(|f| f.take(packed.len()));
        match held.at(n) {
            Some(boundaries) => {
                groups.extend(packed.iter().zip(boundaries).map(|(g, b)| group(g, *b)))
            }
            None => {
                let inv_n = 1.0 / n;
                groups.extend(
                    packed
                        .iter()
                        .map(|g| group(g, BoundaryGroup::new(g, n, inv_n))),
                )
            }
        }
        LayeredTerms { groups, t }
    }

    /// The model's parameters from the nonlinear values `theta` (internal
    /// coordinates: `ln σ/T` first for the layered models).
    pub fn slope_n_a(&self, theta: &[f64]) -> (f64, f64, f64) {
        let a = if self.dim() == 3 { theta[2] } else { 0.0 };
        // exp(ln x) can miss x by an ulp: kept inside the model's domain.
        let slope = libm::exp(theta[0]).clamp(SLOPE_MIN, SLOPE_MAX);
        (slope, theta[1], a)
    }

    /// The columns at `theta`.
    pub fn columns(&self, theta: &[f64]) -> Columns {
        self.evaluate(theta).columns
    }

    /// The columns at `theta`, keeping what [`Basis::derivatives_at`] needs.
    pub fn evaluate(&self, theta: &[f64]) -> Evaluated {
        self.evaluate_held(theta, &Held::default())
    }

    /// What stays fixed while the parameters marked `free` move from
    /// `theta`: the boundary when n is held (a profile of n).
    pub fn held(&self, theta: &[f64], free: &[bool]) -> Held {
        let boundary = match self {
            Self::Layered { .. } if !free[1] => Some((theta[1], self.boundary::<f64x4>(theta[1]))),
            _ => None,
        };
        Held { boundary }
    }

    /// [`Basis::evaluate`], reusing what `held` keeps when it applies.
    pub fn evaluate_held(&self, theta: &[f64], held: &Held) -> Evaluated {
        match self {
            Self::Layered { packed, .. } => {
                let (slope, n, a) = self.slope_n_a(theta);
                let terms = self.layered_terms(slope, n, held);
                let a = f64x4::splat(a);
                let s = unpack(terms.groups.iter().map(|l| l.surface), self.len());
                let u = unpack(
                    (terms.groups.iter().zip(packed))
                        .map(|(l, g)| l.base * Self::attenuation(g, a).0),
                    self.len(),
                );
                Evaluated {
                    columns: Columns { s, u },
                    terms: Some(terms),
                }
            }
            Self::Baseline(_) => Evaluated {
                columns: self.baseline_columns(theta),
                terms: None,
            },
        }
    }

    fn baseline_columns(&self, theta: &[f64]) -> Columns {
        match self {
            Self::Layered { .. } => unreachable!("baselines only"),
            Self::Baseline(geometry) => Columns {
                s: geometry
                    .radiance([theta[0], theta[1]])
                    .expect("inside the box, which is inside the domain"),
                u: Vec::new(),
            },
        }
    }

    /// The columns at `theta` and their derivatives with respect to each
    /// nonlinear parameter: analytic for the layered models (`ln σ/T`, n,
    /// a), differences for the baselines: central when `central`
    /// (one-sided at an end of `domain`),
    /// else forward (one evaluation less, for the steps of a minimisation).
    pub fn derivatives(
        &self,
        theta: &[f64],
        domain: &[(f64, f64)],
        central: bool,
    ) -> (Columns, Vec<Columns>) {
        let wanted = vec![true; theta.len()];
        let (columns, derivatives) =
            self.derivatives_at(theta, domain, central, self.evaluate(theta), &wanted);
        (columns, derivatives.into_iter().flatten().collect())
    }

    /// [`Basis::derivatives`] at a point already evaluated ([`Basis::evaluate`]
    /// at `theta`), with respect to the parameters marked `wanted` only
    /// (`None` for the others: a held parameter costs nothing).
    pub fn derivatives_at(
        &self,
        theta: &[f64],
        domain: &[(f64, f64)],
        central: bool,
        at: Evaluated,
        wanted: &[bool],
    ) -> (Columns, Vec<Option<Columns>>) {
        match (self, at.terms) {
            (Self::Layered { corr, packed, .. }, Some(terms)) => {
                let (_, n, a) = self.slope_n_a(theta);
                let (len, t, a) = (self.len(), f64x4::splat(terms.t), f64x4::splat(a));
                let zero = f64x4::ZERO;
                // Per group, U again (the same bits as the column) and each
                // wanted derivative: ∂/∂ ln σ/T of S and U, ∂U/∂n, ∂U/∂a.
                let wanted_a = self.dim() == 3 && wanted[2];
                // Each wanted derivative's vector, a group of four written
                // in place per group of measurements (the others empty).
                let filled = [wanted[0], wanted[0], wanted[1], wanted_a];
                let mut d: [Vec<f64>; 4] = filled.map(|f| {
                    if !f {
                        return Vec::new();
                    }
                    let mut v = pool::vector(4 * terms.groups.len());
                    v.resize(4 * terms.groups.len(), 0.0);
                    v
                });
                {
                    let [d_s, d_u, d_n, d_a] = d.each_mut().map(|v| v.as_chunks_mut::<4>().0);
                    for (i, (l, g)) in terms.groups.iter().zip(packed).enumerate() {
                        let (attenuation, [ci, cs]) = Self::attenuation(g, a);
                        let u = l.base * attenuation;
                        let x_refracted = l.boundary.ratio * t;
                        if wanted[0] {
                            let ds = l.surface * corr.log_slope_derivative(g.ratio * t);
                            d_s[i] = ds.to_array();
                            d_u[i] = (u * corr.log_slope_derivative(x_refracted)).to_array();
                        }
                        if wanted[1] {
                            let log = log_n_derivative(*corr, g, &l.boundary, n, x_refracted);
                            d_n[i] = f64x4::select(u.eq(zero), zero, u * log).to_array();
                        }
                        if wanted_a {
                            let da = l.base * (f64x4::c(2.0) * a * ci * cs - ci - cs);
                            d_a[i] = da.to_array();
                        }
                    }
                }
                let [s_slope, u_slope, u_n, u_a] = d.map(|mut v| {
                    v.truncate(len);
                    v
                });
                let mut out = vec![
                    wanted[0].then_some(Columns {
                        s: s_slope,
                        u: u_slope,
                    }),
                    wanted[1].then_some(Columns {
                        s: Vec::new(),
                        u: u_n,
                    }),
                ];
                if self.dim() == 3 {
                    out.push(wanted_a.then_some(Columns {
                        s: Vec::new(),
                        u: u_a,
                    }));
                }
                (at.columns, out)
            }
            _ => {
                let at = at.columns;
                let out = (0..theta.len())
                    .map(|j| {
                        if !wanted[j] {
                            return None;
                        }
                        let (h, lo, hi) = difference(theta[j], domain[j], central);
                        let moved = |v: f64| {
                            if v == theta[j] {
                                return at.s.clone();
                            }
                            let mut t = theta.to_vec();
                            t[j] = v;
                            std::mem::take(&mut self.columns(&t).s)
                        };
                        let (up, down) = (moved(hi), moved(lo));
                        Some(Columns {
                            s: up.iter().zip(&down).map(|(u, d)| (u - d) / h).collect(),
                            u: Vec::new(),
                        })
                    })
                    .collect();
                (at, out)
            }
        }
    }
}

/// The points `(width, lower, upper)` of a difference quotient at `v`
/// inside `[lo, hi]`: central where both fit (when `central`), else
/// one-sided.
fn difference(v: f64, (lo, hi): (f64, f64), central: bool) -> (f64, f64, f64) {
    let h = STEP * v.abs().max(1e-2);
    let (down, up) = match (v - h >= lo, v + h <= hi) {
        (true, true) if central => (v - h, v + h),
        (_, true) => (v, v + h),
        (true, false) => (v - h, v),
        (false, false) => (v, v + h),
    };
    (up - down, down, up)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synthetic;

    #[test]
    fn derivatives_agree_with_differences() {
        let angles = synthetic::geometries();
        for model in [Model::Exp, Model::Gauss] {
            let basis = Basis::new(model, &angles);
            // n near 1 (refraction barely bends), typical, and large.
            for theta in [
                [libm::log(0.7), 1.45, 0.3],
                [libm::log(0.2), 1.01, 0.0],
                [libm::log(3.0), 2.4, 0.9],
            ] {
                let domain = [(-7.0, 7.0), (1.0, 10.0), (0.0, 1.0)];
                let (at, d) = basis.derivatives(&theta, &domain, true);
                assert_eq!(at, basis.columns(&theta));
                for j in 0..3 {
                    let h = 1e-6;
                    let mut up = theta;
                    up[j] += h;
                    let mut down = theta;
                    down[j] -= h;
                    let (cu, cd) = (basis.columns(&up), basis.columns(&down));
                    for k in 0..angles.len() {
                        let fd_s = (cu.s[k] - cd.s[k]) / (2.0 * h);
                        let fd_u = (cu.u[k] - cd.u[k]) / (2.0 * h);
                        // Relative to the column or its derivative, whichever
                        // is larger (a Gaussian tail changes ~x′ times faster
                        // than its size).
                        let scale = at.s[k]
                            .abs()
                            .max(at.u[k].abs())
                            .max(fd_s.abs())
                            .max(fd_u.abs())
                            .max(1e-300);
                        let d_s = d[j].s.get(k).copied().unwrap_or(0.0);
                        assert!((d_s - fd_s).abs() <= 1e-8 * scale, "{model} {j} {k}");
                        assert!(
                            (d[j].u[k] - fd_u).abs() <= 1e-6 * scale,
                            "{model} {j} {k} {theta:?}"
                        );
                    }
                }
            }
        }
    }
}
