//! A scene packed for the search: measurements in chunks of `L::LANES`, laid
//! out so that every path sees each measurement at the same *global lane*,
//! and the hoisted terms of the model (geometry once per scene, [`Interface`]
//! once per (scene, n), absorption factor once per (scene, a)).

use crate::grid::Grid;
use crate::scene::Scene;
use laminar_brdf_core::onepass::Layout;
pub use laminar_brdf_core::onepass::{lane_max, lane_sum, normalise, WIDTH};
use laminar_brdf_core::{
    absorption_factor, inverse_slope_squared, subsurface_base, surface_radiance, Correlation,
    Geometry, Interface, Lane,
};

/// Measurement `k` sits in chunk `k / WIDTH`, at global lane `k % WIDTH` =
/// `stream · L::LANES + lane`. Chunks are stream-major: flat chunk index
/// `stream · per_stream + chunk`. With `f32x8` there is one stream; with a
/// scalar type there are eight, one per global lane.
pub struct Packed<L> {
    /// Geometry of each chunk (padding lanes repeat the last measurement).
    pub geom: Vec<Geometry<L>>,
    /// Normalised data `D` (0 in padding lanes).
    pub data: Vec<L>,
    /// 1 for a real measurement, 0 for padding.
    pub valid: Vec<L>,
    /// Chunks per stream.
    pub per_stream: usize,
    /// Number of measurements K.
    pub k: usize,
}

impl<L: Lane> Packed<L> {
    /// Packs `scene`.
    pub fn new(scene: &Scene) -> Self {
        let layout = Layout::new(scene.len());
        let last = scene.len().saturating_sub(1);
        let geom = (0..layout.chunks::<L>())
            .map(|c| {
                Geometry::from_lanes(|lane| {
                    scene.angles[layout.measurement::<L>(c, lane).min(last)]
                })
            })
            .collect();
        Self {
            geom,
            data: Self::pack(layout, |i| scene.data[i]),
            valid: Self::pack(layout, |_| 1.0),
            per_stream: layout.per_stream,
            k: layout.k,
        }
    }

    /// The packing of `scene`, whose kept geometry is this one's: its data,
    /// this packing's geometry (bit for bit what [`Packed::new`] would give).
    pub fn with_data(&self, scene: &Scene) -> Self {
        Self {
            geom: self.geom.clone(),
            data: Self::pack(self.layout(), |i| scene.data[i]),
            valid: self.valid.clone(),
            per_stream: self.per_stream,
            k: self.k,
        }
    }

    /// `value(k)` for the measurements in packing order, 0 in padding lanes.
    fn pack(layout: Layout, value: impl Fn(usize) -> f64) -> Vec<L> {
        (0..layout.chunks::<L>())
            .map(|c| {
                L::from_f64_lanes(|lane| {
                    let i = layout.measurement::<L>(c, lane);
                    if i < layout.k {
                        value(i)
                    } else {
                        0.0
                    }
                })
            })
            .collect()
    }

    /// Where each measurement sits.
    pub fn layout(&self) -> Layout {
        Layout {
            k: self.k,
            per_stream: self.per_stream,
        }
    }

    /// Number of streams (`WIDTH / L::LANES`).
    pub fn streams(&self) -> usize {
        self.layout().streams::<L>()
    }

    /// The flat chunk indices of stream `stream`.
    pub fn stream(&self, stream: usize) -> std::ops::Range<usize> {
        self.layout().stream(stream)
    }

    /// The lane values of `values` widened to `f64`, in measurement order.
    pub fn widen(&self, values: &[L], out: &mut [f64]) {
        self.layout().widen(values, out)
    }

    /// The sum of squared residuals `e` clamped at 0 and widened to `f64`:
    /// what every method hands to the search.
    pub fn objective(e: L::Scalar) -> f64 {
        laminar_brdf_core::onepass::objective(e)
    }
}

/// Per-scene tables shared by every σ/T shard of the hoisted paths.
pub struct Tables<L> {
    /// The packed scene.
    pub packed: Packed<L>,
    /// `interfaces[n][flat chunk]`.
    interfaces: Vec<Vec<Interface<L>>>,
    /// `absorption[a][flat chunk]`.
    absorption: Vec<Vec<L>>,
}

impl<L: Lane> Tables<L> {
    /// Hoists the per-scene, per-(scene, n) and per-(scene, a) terms.
    pub fn new(scene: &Scene, grid: &Grid) -> Self {
        let packed = Packed::<L>::new(scene);
        let interfaces = grid
            .n
            .values
            .iter()
            .map(|&n| {
                packed
                    .geom
                    .iter()
                    .map(|g| Interface::new(g, L::c(n)))
                    .collect()
            })
            .collect();
        let absorption = grid
            .a
            .values
            .iter()
            .map(|&a| {
                packed
                    .geom
                    .iter()
                    .map(|g| absorption_factor(g, L::c(a)))
                    .collect()
            })
            .collect();
        Self {
            packed,
            interfaces,
            absorption,
        }
    }

    /// The normalised surface term `S` (eqs. 1–2, docs/conventions.md §4) at σ/T = `slope`.
    pub fn surface(&self, corr: Correlation, slope: f64) -> Vec<L> {
        let inv_s2 = inverse_slope_squared(L::c(slope));
        let mut s: Vec<L> = (self.packed.geom.iter().zip(&self.packed.valid))
            .map(|(g, v)| surface_radiance(g, corr, inv_s2) * *v)
            .collect();
        normalise(&mut s);
        s
    }

    /// Calls `visit(i_n, B)` with the subsurface base `B` (eqs. 3–5, the
    /// subsurface term before absorption, 0 in padding lanes) of every n at
    /// σ/T = `slope`, in loop order.
    pub fn for_each_base(&self, corr: Correlation, slope: f64, mut visit: impl FnMut(usize, &[L])) {
        let mut base = Vec::with_capacity(self.packed.geom.len());
        for i_n in 0..self.interfaces.len() {
            self.base(corr, slope, i_n, &mut base);
            visit(i_n, &base);
        }
    }

    /// The subsurface base of n index `i_n` at σ/T = `slope`, into `out`.
    pub fn base(&self, corr: Correlation, slope: f64, i_n: usize, out: &mut Vec<L>) {
        let inv_s2 = inverse_slope_squared(L::c(slope));
        out.clear();
        out.extend(
            (self.interfaces[i_n].iter().zip(&self.packed.valid))
                .map(|(f, v)| subsurface_base(f, corr, inv_s2) * *v),
        );
    }

    /// Calls `visit(i_n, i_a, U)` with the normalised subsurface term `U`
    /// (eqs. 3–5, 12–14) of every (n, a) at σ/T = `slope`, in loop order.
    pub fn for_each_subsurface(
        &self,
        corr: Correlation,
        slope: f64,
        mut visit: impl FnMut(usize, usize, &[L]),
    ) {
        let mut u = vec![L::c(0.0); self.packed.geom.len()];
        self.for_each_base(corr, slope, |i_n, base| {
            for (i_a, att) in self.absorption.iter().enumerate() {
                for ((u, b), f) in u.iter_mut().zip(base).zip(att) {
                    *u = *b * *f;
                }
                normalise(&mut u);
                visit(i_n, i_a, &u);
            }
        });
    }
}
