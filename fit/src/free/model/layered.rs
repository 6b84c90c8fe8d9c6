//! The layered models' columns (eqs. 1–8, 12–13) under the free
//! amplitude: `S` and `U` at (σ/T, n, a) — and σ′/T′ for the untied
//! models, whose `U` is at the lower boundary's own slope —, four
//! measurements at a time, and their derivatives, analytic in every
//! parameter. Its grid stage is [`crate::free::search::quadratic`].

use super::table::{Nonlinear, Table};
use super::{Columns, Evaluated, FreeModel};
use crate::free::boundary::BoundaryGroup;
use crate::free::pool::{self, Free};
use crate::free::search::quadratic::Bases;
use crate::grid::{Axis, Grid};
use crate::model::{Family, Model, Param};
use crate::simd;
use laminar_brdf_core::radiance::{SLOPE_MAX, SLOPE_MIN};
use laminar_brdf_core::simd::{Kernel, Lane4};
use laminar_brdf_core::{
    f32x8, f64x4, inverse_slope_squared, surface_radiance, Angles, Correlation, Geometry, Lane,
};
use std::sync::OnceLock;

/// Where each parameter of a layered model is in θ.
#[derive(Debug, Clone, Copy)]
struct Positions {
    slope: usize,
    /// `None` for the tied models (σ′/T′ = σ/T).
    sub_slope: Option<usize>,
    n: usize,
    /// `None` for Ragheb–Hancock (a = 0).
    a: Option<usize>,
}

/// A layered model at the measurements' directions.
#[derive(Debug, Clone)]
pub struct LayeredModel {
    model: Model,
    table: Table,
    at: Positions,
    /// The correlation function (eqs. 1–2).
    corr: Correlation,
    /// Their geometry four at a time (`pack`, the last group padded),
    /// which the columns are computed from: lane by lane the same bits as
    /// one at a time (the core's f64x4 path is bitwise its scalar f64
    /// path).
    packed: Vec<Geometry<f64x4>>,
    /// The same eight at a time in single precision (the last group padded
    /// likewise), for the grid stage's `f32x8` path: built from `angles`
    /// when first asked for.
    packed8: OnceLock<Vec<Geometry<f32x8>>>,
    /// The measurements' directions.
    angles: Vec<Angles>,
    /// `cos²θi` of each measurement.
    cos2_i: Vec<f64>,
    /// `cos²θs` of each measurement.
    cos2_s: Vec<f64>,
}

/// What a minimisation keeps while some parameters are held: the boundary
/// (eqs. 5–7, [`crate::free::boundary`]) at a held n, which the columns at
/// every σ/T and a reuse.
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
    /// The terms of the measurements `g` on `boundary` at `(T/σ)²` `t` and
    /// `(T′/σ′)²` `t_sub`, computed in a kernel's lanes `L`.
    /// Inlined into the loop that collects them, so that each group is
    /// written in place in its Vec, not returned and then copied (a
    /// `memcpy` per group: 7.7% of the defaults' profile at K = 22,801, and
    /// 3.5% more sets per second without it).
    #[inline(always)]
    fn new<L: Lane4>(
        g: &Geometry<L>,
        boundary: BoundaryGroup<L>,
        corr: Correlation,
        [t, t_sub]: [L; 2],
    ) -> Self {
        Self {
            surface: surface_radiance(g, corr, t).store(),
            base: boundary.base(corr, t_sub).store(),
            boundary: boundary.store(),
        }
    }
}

/// The pass of [`LayeredModel::boundary`].
struct BoundaryPass<'a, P> {
    packed: &'a [Geometry<P>],
    n: f64,
}

impl<P: Packed> Kernel for BoundaryPass<'_, P> {
    type Output = Vec<BoundaryGroup<P>>;

    #[inline(always)]
    fn run<L: Lane4>(self) -> Vec<BoundaryGroup<P>> {
        let inv_n = 1.0 / self.n;
        let mut out = Vec::with_capacity(self.packed.len());
        for g in self.packed {
            out.push(P::boundary_group::<L>(g, self.n, inv_n));
        }
        out
    }
}

/// The pass of [`LayeredModel::surface`]: the surface term of every
/// group, appended to `out`.
struct SurfacePass<'a> {
    packed: &'a [Geometry<f64x4>],
    corr: Correlation,
    /// `(T/σ)²`.
    t: f64,
    out: &'a mut Vec<f64>,
}

impl Kernel for SurfacePass<'_> {
    type Output = ();

    #[inline(always)]
    fn run<L: Lane4>(self) {
        let t = L::splat(self.t);
        for g in self.packed {
            let s = surface_radiance(&g.map(L::load), self.corr, t);
            self.out.extend_from_slice(&s.to_array());
        }
    }
}

/// The pass of [`LayeredModel::base`]: the first `groups` groups of
/// `bases`, appended to `out`.
struct BasePass<'a, B> {
    bases: &'a B,
    groups: usize,
    out: &'a mut Vec<f64>,
}

impl<B: Bases> Kernel for BasePass<'_, B> {
    type Output = ();

    #[inline(always)]
    fn run<L: Lane4>(self) {
        for i in 0..self.groups {
            self.out
                .extend_from_slice(&self.bases.group::<L>(i).to_array());
        }
    }
}

/// The pass of [`LayeredModel::terms`]: each group's terms, its boundary
/// taken from `held` or built.
struct TermsPass<'a> {
    packed: &'a [Geometry<f64x4>],
    held: Option<&'a [BoundaryGroup]>,
    n: f64,
    corr: Correlation,
    /// `(T/σ)²` and `(T′/σ′)²`.
    t: [f64; 2],
    /// Empty, with room for every group.
    groups: Vec<LayerGroup>,
}

impl Kernel for TermsPass<'_> {
    type Output = Vec<LayerGroup>;

    #[inline(always)]
    fn run<L: Lane4>(self) -> Vec<LayerGroup> {
        let Self {
            packed,
            held,
            n,
            corr,
            t,
            mut groups,
        } = self;
        let t = t.map(L::splat);
        match held {
            Some(boundaries) => {
                for (g, b) in packed.iter().zip(boundaries) {
                    groups.push(LayerGroup::new(&g.map(L::load), b.load(), corr, t));
                }
            }
            None => {
                let inv_n = 1.0 / n;
                for g in packed {
                    let g = g.map(L::load);
                    groups.push(LayerGroup::new(
                        &g,
                        BoundaryGroup::new(&g, n, inv_n),
                        corr,
                        t,
                    ));
                }
            }
        }
        groups
    }
}

/// A layered model's terms at one (σ/T, σ′/T′, n), four measurements at a
/// time (the packing), with what their derivatives need.
#[derive(Debug, Clone)]
pub struct LayeredTerms {
    groups: Vec<LayerGroup>,
    /// `(T/σ)²`: the surface term's argument is `x = (T/σ)² v_xy²/v_z²`.
    t: f64,
    /// `(T′/σ′)²` (`t` when tied): the base's `x′ = (T′/σ′)² · ratio`.
    t_sub: f64,
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
#[inline(always)]
fn log_n_derivative<L: Lane4>(
    corr: Correlation,
    g: &Geometry<L>,
    b: &BoundaryGroup<L>,
    n: f64,
    x_refracted: L,
) -> L {
    let c = L::c;
    let (n, inv_n) = (L::splat(n), L::splat(1.0 / n));
    let (ci, cs) = (b.cos_i, b.cos_s);
    // `∂cos θ′/∂n / cos θ′ = sin²θ/(n³ cos²θ′)`, and the derivative itself.
    let (ri, rs) = (
        g.sin2_i * inv_n * inv_n * inv_n / (ci * ci),
        g.sin2_s * inv_n * inv_n * inv_n / (cs * cs),
    );
    let (dci, dcs) = (ri * ci, rs * cs);
    let ell = c(-2.0) * inv_n - c(2.0) * (dci + dcs) / (ci + cs);
    // The elasticity of the shape in x′ is half that in σ/T with the sign
    // turned, as x ∝ (σ/T)⁻².
    let elasticity = c(-0.5) * corr.log_slope_derivative(x_refracted);
    (c(1.0) + elasticity) * ell
        + log_transmission_derivative([n, inv_n], g.cos_i, [ci, dci, ri])
        + log_transmission_derivative([n, inv_n], g.cos_s, [cs, dcs, rs])
}

/// `∂ ln t/∂n` of one direction's transmission (eq. 7), `c1` its cosine
/// above the boundary, `c2` below, `dc2 = ∂c2/∂n` and `rel2 = dc2/c2`:
/// `1/n + ∂ ln c′/∂n − 2 (s_n/s³ + p_n/p³)/(1/s² + 1/p²)`, the last term as
/// `2 (s_n p³ + p_n s³)/(s p (s² + p²))`. A function, not a closure, so
/// that a kernel surely inlines it.
#[inline(always)]
fn log_transmission_derivative<L: Lane>([n, inv_n]: [L; 2], c1: L, [c2, dc2, rel2]: [L; 3]) -> L {
    let (s, p) = (c1 + n * c2, n * c1 + c2);
    let (ds, dp) = (c2 + n * dc2, c1 + dc2);
    let (s2, p2) = (s * s, p * p);
    inv_n + rel2 - L::c(2.0) * (ds * p2 * p + dp * s2 * s) / (s * p * (s2 + p2))
}

/// The subsurface column `U = B (1 − a cos²θi)(1 − a cos²θs)` of every
/// group (eqs. 12–14), appended to `out`.
struct AttenuatedPass<'a> {
    terms: &'a LayeredTerms,
    packed: &'a [Geometry<f64x4>],
    a: f64,
    out: &'a mut Vec<f64>,
}

impl Kernel for AttenuatedPass<'_> {
    type Output = ();

    #[inline(always)]
    fn run<L: Lane4>(self) {
        let a = L::splat(self.a);
        for (l, g) in self.terms.groups.iter().zip(self.packed) {
            let u = L::load(l.base) * attenuation(&g.map(L::load), a).0;
            self.out.extend_from_slice(&u.to_array());
        }
    }
}

/// The pass of [`LayeredModel::derivative_vectors`]: each wanted
/// derivative (`out`'s non-empty vectors) per group of measurements.
struct DerivativePass<'a> {
    terms: &'a LayeredTerms,
    packed: &'a [Geometry<f64x4>],
    corr: Correlation,
    n_a: (f64, f64),
    /// `[∂S/∂ ln σ/T, ∂U/∂ ln σ′/T′, ∂U/∂n, ∂U/∂a]`, empty when unwanted.
    out: [&'a mut [[f64; 4]]; 4],
}

impl Kernel for DerivativePass<'_> {
    type Output = ();

    #[inline(always)]
    fn run<L: Lane4>(self) {
        let Self {
            terms,
            packed,
            corr,
            n_a: (n, a),
            out: [d_s, d_u, d_n, d_a],
        } = self;
        let [slope, sub_slope, index, absorption] = [&d_s, &d_u, &d_n, &d_a].map(|d| !d.is_empty());
        let (t, t_sub) = (L::splat(terms.t), L::splat(terms.t_sub));
        let a = L::splat(a);
        let zero = L::zero();
        for (i, (l, g)) in terms.groups.iter().zip(packed).enumerate() {
            let g = g.map(L::load);
            let (surface, base) = (L::load(l.surface), L::load(l.base));
            let boundary = l.boundary.load::<L>();
            // U again (the same bits as the column).
            let (attenuation, [ci, cs]) = attenuation(&g, a);
            let u = base * attenuation;
            let x_refracted = boundary.ratio * t_sub;
            if slope {
                let ds = surface * corr.log_slope_derivative(g.ratio * t);
                d_s[i] = ds.to_array();
            }
            if sub_slope {
                d_u[i] = (u * corr.log_slope_derivative(x_refracted)).to_array();
            }
            if index {
                let log = log_n_derivative(corr, &g, &boundary, n, x_refracted);
                d_n[i] = L::select(u.eq(zero), zero, u * log).to_array();
            }
            if absorption {
                let da = base * (L::c(2.0) * a * ci * cs - ci - cs);
                d_a[i] = da.to_array();
            }
        }
    }
}

/// σ/T (or σ′/T′) of its logarithm: exp(ln x) can miss x by an ulp, so
/// it is kept inside the model's domain.
fn slope_of(log: f64) -> f64 {
    libm::exp(log).clamp(SLOPE_MIN, SLOPE_MAX)
}

/// `angles` a lane's width at a time, the last group padded with its last
/// measurement (whose lanes [`unpack`] drops).
fn pack<L: Lane>(angles: &[Angles]) -> Vec<Geometry<L>> {
    angles
        .chunks(L::LANES)
        .map(|group| Geometry::from_lanes(|i| group[i.min(group.len() - 1)]))
        .collect()
}

/// A lane type the layered model keeps the measurements' geometry packed
/// in: `f64x4` (every stage) and `f32x8` (the grid stage in single
/// precision).
pub trait Packed: Lane {
    /// The packed geometry of `model`.
    fn packed(model: &LayeredModel) -> &[Geometry<Self>];

    /// Groups of this lane's values as groups of four `f64`, exactly and in
    /// order (the grid stage's sums run in `f64x4`).
    fn widened(groups: impl Iterator<Item = Self>) -> impl Iterator<Item = f64x4>;

    /// The base `B` ([`LayeredModel::base_groups`]) at `slope` on
    /// `boundary`, as groups of four in a kernel's lanes.
    fn bases<'a>(
        model: &LayeredModel,
        slope: f64,
        boundary: &'a [BoundaryGroup<Self>],
    ) -> impl Bases + 'a;

    /// The boundary of the group `g` at `n` (`inv_n` its reciprocal),
    /// computed in a kernel's lanes `L` where the packing is four `f64`.
    fn boundary_group<L: Lane4>(g: &Geometry<Self>, n: f64, inv_n: f64) -> BoundaryGroup<Self>;

    /// `kernel` on the lanes this packing's grid stage runs with: the
    /// dispatched ones ([`crate::simd`]) for `f64x4`, the portable ones for
    /// `f32x8` (whose bases are `wide`'s).
    fn run<K: Kernel>(kernel: K) -> K::Output;
}

impl Packed for f64x4 {
    fn packed(model: &LayeredModel) -> &[Geometry<Self>] {
        &model.packed
    }

    fn widened(groups: impl Iterator<Item = Self>) -> impl Iterator<Item = f64x4> {
        groups
    }

    fn bases<'a>(
        model: &LayeredModel,
        slope: f64,
        boundary: &'a [BoundaryGroup<Self>],
    ) -> impl Bases + 'a {
        BasesOnBoundary {
            boundary,
            corr: model.corr,
            t: inverse_slope_squared(slope),
        }
    }

    #[inline(always)]
    fn boundary_group<L: Lane4>(g: &Geometry<Self>, n: f64, inv_n: f64) -> BoundaryGroup<Self> {
        BoundaryGroup::new(&g.map(L::load), n, inv_n).store()
    }

    fn run<K: Kernel>(kernel: K) -> K::Output {
        simd::run(kernel)
    }
}

impl Packed for f32x8 {
    fn packed(model: &LayeredModel) -> &[Geometry<Self>] {
        model.packed8.get_or_init(|| pack(&model.angles))
    }

    fn widened(groups: impl Iterator<Item = Self>) -> impl Iterator<Item = f64x4> {
        groups.flat_map(|v| {
            let v = v.to_array();
            [0, 4].map(|h| f64x4::from_f64_lanes(|i| f64::from(v[h + i])))
        })
    }

    fn bases<'a>(
        model: &LayeredModel,
        slope: f64,
        boundary: &'a [BoundaryGroup<Self>],
    ) -> impl Bases + 'a {
        BasesWidened(Self::widened(model.base_groups(slope, boundary)).collect())
    }

    /// In `f32x8`, whatever `L`.
    #[inline(always)]
    fn boundary_group<L: Lane4>(g: &Geometry<Self>, n: f64, inv_n: f64) -> BoundaryGroup<Self> {
        BoundaryGroup::new(g, n, inv_n)
    }

    fn run<K: Kernel>(kernel: K) -> K::Output {
        laminar_brdf_core::simd::run_portable(kernel)
    }
}

/// The base on a boundary in `f64x4`, computed group by group in the
/// kernel's lanes.
struct BasesOnBoundary<'a> {
    boundary: &'a [BoundaryGroup],
    corr: Correlation,
    /// `(T/σ)²` (or `(T′/σ′)²`).
    t: f64,
}

impl Bases for BasesOnBoundary<'_> {
    #[inline(always)]
    fn group<L: Lane4>(&self, i: usize) -> L {
        self.boundary[i]
            .load::<L>()
            .base(self.corr, L::splat(self.t))
    }
}

/// The base computed in `f32x8` lanes and widened, in groups of four.
struct BasesWidened(Vec<f64x4>);

impl Bases for BasesWidened {
    #[inline(always)]
    fn group<L: Lane4>(&self, i: usize) -> L {
        L::load(self.0[i])
    }
}

/// The first `len` lanes of `groups`, in measurement order.
fn unpack(groups: impl Iterator<Item = f64x4>, len: usize) -> Vec<f64> {
    let mut out = pool::vector(len.next_multiple_of(4));
    groups.for_each(|v| out.extend_from_slice(&v.to_array()));
    out.truncate(len);
    out
}

/// The absorption factor `(1 − a cos²θi)(1 − a cos²θs)` of four
/// measurements `g` (eqs. 10–14), and the two `cos²`.
#[inline(always)]
fn attenuation<L: Lane>(g: &Geometry<L>, a: L) -> (L, [L; 2]) {
    let one = L::c(1.0);
    let (ci, cs) = (one - g.sin2_i, one - g.sin2_s);
    ((one - a * ci) * (one - a * cs), [ci, cs])
}

impl LayeredModel {
    /// The boundary at refractive index `n` ([`crate::free::boundary`]), a
    /// lane's width of measurements at a time.
    pub fn boundary<P: Packed>(&self, n: f64) -> Vec<BoundaryGroup<P>> {
        P::run(BoundaryPass {
            packed: P::packed(self),
            n,
        })
    }

    /// The raw surface term at σ/T.
    pub fn surface(&self, slope: f64) -> Vec<f64> {
        let mut out = pool::vector(self.packed.len() * 4);
        simd::run(SurfacePass {
            packed: &self.packed,
            corr: self.corr,
            t: inverse_slope_squared(slope),
            out: &mut out,
        });
        out.truncate(self.len());
        out
    }

    /// The Ragheb–Hancock base `B_k` (eqs. 3–4) at the lower boundary's
    /// slope (σ/T when tied, σ′/T′ untied) on the boundary at one n ([`LayeredModel::boundary`]), a lane's width of measurements
    /// at a time (the last group padded as the boundary's is).
    pub fn base_groups<'a, L: Lane + 'a>(
        &self,
        slope: f64,
        boundary: &'a [BoundaryGroup<L>],
    ) -> impl Iterator<Item = L> + 'a {
        let (corr, t) = (self.corr, L::c(inverse_slope_squared(slope)));
        boundary.iter().map(move |b| b.base(corr, t))
    }

    /// [`LayeredModel::base_groups`] as one value per measurement.
    pub fn base<P: Packed>(&self, slope: f64, boundary: &[BoundaryGroup<P>]) -> Vec<f64> {
        let bases = P::bases(self, slope, boundary);
        let groups = self.len().div_ceil(4);
        let mut out = pool::vector(4 * groups);
        P::run(BasePass {
            bases: &bases,
            groups,
            out: &mut out,
        });
        out.truncate(self.len());
        out
    }

    /// The factors that turn the base `B` into `B1` and `B2` of `U`'s
    /// quadratic in a (`U = B + a B1 + a² B2`), per measurement:
    /// `−(cos²θi + cos²θs)` and `cos²θi cos²θs`.
    pub fn factors(&self) -> [Vec<f64>; 2] {
        let (ci, cs) = (&self.cos2_i, &self.cos2_s);
        [
            ci.iter().zip(cs).map(|(i, s)| -(i + s)).collect(),
            ci.iter().zip(cs).map(|(i, s)| i * s).collect(),
        ]
    }

    /// `cos²θi` and `cos²θs` of each measurement.
    pub fn cosines(&self) -> (&[f64], &[f64]) {
        (&self.cos2_i, &self.cos2_s)
    }

    /// σ/T, n and a at the nonlinear values `theta` (a = 0 for
    /// Ragheb–Hancock).
    pub fn slope_n_a(&self, theta: &[f64]) -> (f64, f64, f64) {
        let a = self.at.a.map_or(0.0, |j| theta[j]);
        (slope_of(theta[self.at.slope]), theta[self.at.n], a)
    }

    /// σ′/T′ at the nonlinear values `theta` (σ/T when tied).
    pub fn sub_slope(&self, theta: &[f64]) -> f64 {
        slope_of(theta[self.at.sub_slope.unwrap_or(self.at.slope)])
    }

    /// The [`LayeredTerms`] at (σ/T, σ′/T′, n): one pass over the
    /// measurements, each group's boundary built (or taken from `held`) and
    /// used at once.
    fn terms(&self, [slope, sub_slope]: [f64; 2], n: f64, held: &Held) -> LayeredTerms {
        let t = inverse_slope_squared(slope);
        let t_sub = if self.at.sub_slope.is_some() {
            inverse_slope_squared(sub_slope)
        } else {
            t
        };
        let groups = simd::run(TermsPass {
            packed: &self.packed,
            held: held.at(n),
            n,
            corr: self.corr,
            t: [t, t_sub],
            groups: GROUPS.with(|f| f.take(self.packed.len())),
        });
        LayeredTerms { groups, t, t_sub }
    }

    /// Each wanted derivative of the columns from the terms at one point:
    /// `[∂S/∂ ln σ/T, ∂U/∂ ln σ′/T′, ∂U/∂n, ∂U/∂a]` (tied, σ′/T′ is σ/T),
    /// each a group of four written in place per group of measurements (an
    /// unwanted one empty).
    fn derivative_vectors(
        &self,
        terms: &LayeredTerms,
        (n, a): (f64, f64),
        [slope, sub_slope, index, absorption]: [bool; 4],
    ) -> [Vec<f64>; 4] {
        let filled = [slope, sub_slope, index, absorption];
        let mut d: [Vec<f64>; 4] = filled.map(|f| {
            if !f {
                return Vec::new();
            }
            let mut v = pool::vector(4 * terms.groups.len());
            v.resize(4 * terms.groups.len(), 0.0);
            v
        });
        simd::run(DerivativePass {
            terms,
            packed: &self.packed,
            corr: self.corr,
            n_a: (n, a),
            out: d.each_mut().map(|v| v.as_chunks_mut::<4>().0),
        });
        let len = self.len();
        d.map(|mut v| {
            v.truncate(len);
            v
        })
    }
}

impl FreeModel for LayeredModel {
    type Kept = LayeredTerms;
    type Held = Held;

    fn new(model: Model, angles: &[Angles]) -> Self {
        let Family::Layered {
            correlation,
            absorption,
            untied,
        } = model.family()
        else {
            panic!("{model} is not a layered model");
        };
        let mut entries = vec![Nonlinear::log(Param::Slope)];
        if untied {
            entries.push(Nonlinear::log(Param::SubSlope));
        }
        entries.push(Nonlinear::linear(Param::N));
        if absorption {
            entries.push(Nonlinear::linear(Param::A));
        }
        let table = Table::new(entries);
        let position = |p: Param| table.position(p).expect("a layered model's parameter");
        let at = Positions {
            slope: position(Param::Slope),
            sub_slope: table.position(Param::SubSlope),
            n: position(Param::N),
            a: table.position(Param::A),
        };
        let geometry: Vec<Geometry<f64>> = angles.iter().map(Geometry::<f64>::splat).collect();
        Self {
            model,
            table,
            at,
            corr: correlation,
            packed: pack(angles),
            packed8: OnceLock::new(),
            angles: angles.to_vec(),
            cos2_i: geometry.iter().map(|g| 1.0 - g.sin2_i).collect(),
            cos2_s: geometry.iter().map(|g| 1.0 - g.sin2_s).collect(),
        }
    }

    fn model(&self) -> Model {
        self.model
    }

    fn table(&self) -> &Table {
        &self.table
    }

    fn axes(&self, grid: &Grid) -> Vec<Axis> {
        let axis = |p: Param| {
            grid.axis(p)
                .expect("the grid has every layered parameter's axis")
        };
        self.table
            .entries()
            .iter()
            .map(|e| axis(e.name).clone())
            .collect()
    }

    fn has_balance(&self) -> bool {
        true
    }

    fn len(&self) -> usize {
        self.angles.len()
    }

    /// The boundary when n is held (a profile of n).
    fn held(&self, theta: &[f64], free: &[bool]) -> Held {
        let n = theta[self.at.n];
        Held {
            boundary: (!free[self.at.n]).then(|| (n, self.boundary::<f64x4>(n))),
        }
    }

    fn evaluate(&self, theta: &[f64], held: &Held) -> Evaluated<LayeredTerms> {
        let (slope, n, a) = self.slope_n_a(theta);
        let terms = self.terms([slope, self.sub_slope(theta)], n, held);
        let s = unpack(terms.groups.iter().map(|l| l.surface), self.len());
        let mut u = pool::vector(terms.groups.len() * 4);
        simd::run(AttenuatedPass {
            terms: &terms,
            packed: &self.packed,
            a,
            out: &mut u,
        });
        u.truncate(self.len());
        Evaluated {
            columns: Columns { s, u },
            kept: terms,
        }
    }

    /// Analytic in every parameter (`ln σ/T`, `ln σ′/T′`, n, a).
    fn derivatives_at(
        &self,
        theta: &[f64],
        _domain: &[(f64, f64)],
        _central: bool,
        at: Evaluated<LayeredTerms>,
        wanted: &[bool],
    ) -> (Columns, Vec<Option<Columns>>) {
        let (_, n, a) = self.slope_n_a(theta);
        let wanted_a = self.at.a.is_some_and(|j| wanted[j]);
        let wanted_slope = wanted[self.at.slope];
        // Tied, `∂U/∂ ln σ/T` is wanted with `∂S`; untied, with σ′/T′.
        let wanted_sub = self.at.sub_slope.map_or(wanted_slope, |j| wanted[j]);
        let which = [wanted_slope, wanted_sub, wanted[self.at.n], wanted_a];
        let [s_slope, u_slope, u_n, u_a] = self.derivative_vectors(&at.kept, (n, a), which);
        let mut out: Vec<Option<Columns>> = vec![None; self.table.len()];
        match self.at.sub_slope {
            None => {
                out[self.at.slope] = wanted_slope.then_some(Columns {
                    s: s_slope,
                    u: u_slope,
                })
            }
            Some(j) => {
                out[self.at.slope] = wanted_slope.then_some(Columns {
                    s: s_slope,
                    u: Vec::new(),
                });
                out[j] = wanted_sub.then_some(Columns {
                    s: Vec::new(),
                    u: u_slope,
                });
            }
        }
        out[self.at.n] = which[2].then_some(Columns {
            s: Vec::new(),
            u: u_n,
        });
        if let Some(j) = self.at.a {
            out[j] = wanted_a.then_some(Columns {
                s: Vec::new(),
                u: u_a,
            });
        }
        (at.columns, out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Model;
    use crate::synthetic;

    /// The analytic derivatives of both columns against central
    /// differences, for the tied models (ln σ/T, n, a) and the untied ones
    /// (ln σ/T, ln σ′/T′, n, a).
    #[test]
    fn derivatives_agree_with_differences() {
        let angles = synthetic::geometries();
        // n near 1 (refraction barely bends), typical, and large.
        let tied = [
            vec![libm::log(0.7), 1.45, 0.3],
            vec![libm::log(0.2), 1.01, 0.0],
            vec![libm::log(3.0), 2.4, 0.9],
        ];
        let untied = [
            vec![libm::log(0.7), libm::log(0.15), 1.45, 0.3],
            vec![libm::log(0.2), libm::log(2.0), 1.01, 0.0],
            vec![libm::log(3.0), libm::log(0.4), 2.4, 0.9],
        ];
        for model in [Model::Exp, Model::Gauss, Model::Exp2, Model::Gauss2] {
            let basis = LayeredModel::new(model, &angles);
            let (points, domain) = if model.is_untied() {
                let domain = vec![(-7.0, 7.0), (-7.0, 7.0), (1.0, 10.0), (0.0, 1.0)];
                (&untied, domain)
            } else {
                (&tied, vec![(-7.0, 7.0), (1.0, 10.0), (0.0, 1.0)])
            };
            for theta in points {
                let (at, d) = basis.derivatives(theta, &domain, true);
                assert_eq!(at, basis.columns(theta));
                assert_eq!(d.len(), theta.len());
                for j in 0..theta.len() {
                    let h = 1e-6;
                    let mut up = theta.clone();
                    up[j] += h;
                    let mut down = theta.clone();
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
                        let d_u = d[j].u.get(k).copied().unwrap_or(0.0);
                        assert!((d_s - fd_s).abs() <= 1e-8 * scale, "{model} {j} {k}");
                        assert!(
                            (d_u - fd_u).abs() <= 1e-6 * scale,
                            "{model} {j} {k} {theta:?}"
                        );
                    }
                }
            }
        }
    }
}
