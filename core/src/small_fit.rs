//! The grid search of the fitting library for small measurement sets
//! (K ≤ [`MAX_MEASUREMENTS`]), allocation-free in caller-provided
//! [`Scratch`]: what a device with a few LEDs and photodiodes runs to fit
//! its own measurements.
//!
//! It is the library's `onepass-f32` path (docs/conventions.md §4–§6): the
//! same hoisting (the normalised surface term once per σ/T, refraction per
//! (σ/T, n), absorption per (σ/T, n, a)), the same kernel
//! ([`crate::onepass::sweep`]), the same packing and order of sums, so the
//! same objective at every grid point, bit for bit, and the same
//! tie-break: the smallest flat index (loop order σ/T, n, a, β) among
//! equal minima. Only the memory differs: the library keeps per-(scene, n)
//! and per-(scene, a) tables; this recomputes them per σ/T and per
//! (σ/T, n) (per grid point, a few tens of instructions against the
//! sweep's thousands on a Cortex-M4F) and needs no more than `Scratch`
//! (5 KB).

use crate::error::InputError;
use crate::geometry::Geometry;
use crate::measures::{check_data, DataFault};
use crate::onepass::{self, normalise, DataSums, Layout, Terms, Widened};
use crate::param::Param;
use crate::radiance::Params;
use crate::subsurface::{absorption_factor, subsurface_base, Interface};
use crate::surface::{inverse_slope_squared, surface_radiance, Correlation};

/// Most measurements a small fit takes.
pub const MAX_MEASUREMENTS: usize = 64;

/// Working memory of a small fit, owned by the caller (a `static` or the
/// stack); its contents between calls do not matter.
#[derive(Clone, Debug)]
pub struct Scratch {
    geometry: [Geometry<f32>; MAX_MEASUREMENTS],
    data: [f32; MAX_MEASUREMENTS],
    valid: [f32; MAX_MEASUREMENTS],
    surface: [f32; MAX_MEASUREMENTS],
    base: [f32; MAX_MEASUREMENTS],
    subsurface: [f32; MAX_MEASUREMENTS],
    delta: [f32; MAX_MEASUREMENTS],
    s: [f64; MAX_MEASUREMENTS],
    d: [f64; MAX_MEASUREMENTS],
    delta_f64: [f64; MAX_MEASUREMENTS],
}

impl Scratch {
    /// Zeroed scratch (`const`, so it can be a `static`).
    pub const fn new() -> Self {
        Self {
            geometry: [Geometry::filled(0.0); MAX_MEASUREMENTS],
            data: [0.0; MAX_MEASUREMENTS],
            valid: [0.0; MAX_MEASUREMENTS],
            surface: [0.0; MAX_MEASUREMENTS],
            base: [0.0; MAX_MEASUREMENTS],
            subsurface: [0.0; MAX_MEASUREMENTS],
            delta: [0.0; MAX_MEASUREMENTS],
            s: [0.0; MAX_MEASUREMENTS],
            d: [0.0; MAX_MEASUREMENTS],
            delta_f64: [0.0; MAX_MEASUREMENTS],
        }
    }
}

impl Default for Scratch {
    fn default() -> Self {
        Self::new()
    }
}

/// The paper's grid (docs/conventions.md §6) as `(start, step, count)`
/// per axis in the order of [`Axes`] (σ/T, n, a, β); value `i` of an axis
/// is [`stepped`]`(start, step, i)`.
pub const PAPER: [(f64, f64, usize); 4] = [
    (0.12, 0.08, 50),
    (1.30, 0.02, 11),
    (0.0, 0.01, 101),
    (0.01, 0.01, 100),
];

/// `start + step·i`, the paper's construction of an axis value.
#[must_use]
pub fn stepped(start: f64, step: f64, i: usize) -> f64 {
    start + step * i as f64
}

/// A grid axis outside what a search takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AxisError {
    /// The axis (σ/T, n, a or β) has no value.
    Empty {
        /// The axis.
        axis: Param,
    },
    /// A value of the axis is outside the model's domain.
    OutOfDomain {
        /// The axis.
        axis: Param,
        /// The value and its domain.
        error: InputError,
    },
}

/// The grid: each axis's values, searched in loop order σ/T, n, a, β
/// (the paper's: [`PAPER`]).
#[derive(Clone, Copy, Debug)]
pub struct Axes<'a> {
    /// σ/T values.
    pub slope: &'a [f64],
    /// n values.
    pub n: &'a [f64],
    /// a values.
    pub a: &'a [f64],
    /// β values.
    pub beta: &'a [f64],
}

impl Axes<'_> {
    /// Flattened index of a grid point in loop order.
    #[must_use]
    pub fn flat(&self, s: usize, n: usize, a: usize, b: usize) -> usize {
        ((s * self.n.len() + n) * self.a.len() + a) * self.beta.len() + b
    }

    /// The axis indices (σ/T, n, a, β) of a flattened index ([`Axes::flat`]).
    /// An empty axis counts as one value (no division by zero: the small
    /// fit has no panic path).
    #[must_use]
    pub fn indices(&self, flat: usize) -> (usize, usize, usize, usize) {
        let len = |axis: &[f64]| axis.len().max(1);
        let b = flat % len(self.beta);
        let rest = flat / len(self.beta);
        let a = rest % len(self.a);
        let rest = rest / len(self.a);
        (rest / len(self.n), rest % len(self.n), a, b)
    }

    /// The point of flattened index `flat` as (σ/T, β, n, a); NaN for an
    /// index past an axis's end (or an empty axis).
    #[must_use]
    pub fn point(&self, flat: usize) -> (f64, f64, f64, f64) {
        let (s, n, a, b) = self.indices(flat);
        let at = |axis: &[f64], i: usize| axis.get(i).copied().unwrap_or(f64::NAN);
        (
            at(self.slope, s),
            at(self.beta, b),
            at(self.n, n),
            at(self.a, a),
        )
    }

    /// Checks that no axis is empty and every value lies in the model's
    /// domain ([`Params::new`]; the domain is a box, so each axis is
    /// checked on its own, around a point inside it), axis by axis in
    /// loop order.
    ///
    /// # Errors
    /// The first [`AxisError`].
    pub fn validate(&self) -> Result<(), AxisError> {
        // A point inside the domain as (σ/T, β, n, a), to vary one axis at a time.
        let inside = [1.0, 0.5, 1.5, 0.5];
        // Each axis with its place in that point.
        let axes = [
            (Param::Slope, self.slope, 0),
            (Param::N, self.n, 2),
            (Param::A, self.a, 3),
            (Param::Beta, self.beta, 1),
        ];
        for (axis, values, place) in axes {
            if values.is_empty() {
                return Err(AxisError::Empty { axis });
            }
            for &v in values {
                let mut p = inside;
                p[place] = v;
                Params::new(p[0], p[1], p[2], p[3])
                    .map_err(|error| AxisError::OutOfDomain { axis, error })?;
            }
        }
        Ok(())
    }
}

/// What a small fit found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmallFit {
    /// Flattened index of the best grid point (smallest on ties).
    pub best: usize,
    /// Its sum of squared residuals `Σ (D − P)²`.
    pub objective: f64,
    /// Its `Δ_RMS` (eq. 15).
    pub rms: f64,
    /// The best grid point with a = 0 (Ragheb–Hancock) and its objective,
    /// when the a axis holds 0.
    pub rh_best: Option<(usize, f64)>,
}

/// Why a small fit did not run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SmallFitError {
    /// No measurement, more than [`MAX_MEASUREMENTS`], or data and
    /// geometry of different lengths.
    Count {
        /// Geometries given.
        geometries: usize,
        /// Data values given.
        data: usize,
    },
    /// Data that break the library's data rule ([`check_data`]).
    Data {
        /// Index of the bad datum (the first one, or 0 when none is positive).
        index: usize,
        /// What is wrong with it.
        fault: DataFault,
    },
    /// An empty axis, or a value outside the model's domain.
    Axis(AxisError),
    /// A standard uncertainty that is not positive and finite, or so small
    /// against the data's max that its weight passes `f32`'s range
    /// ([`crate::small_free_fit`]).
    Sigma {
        /// Index of the uncertainty.
        index: usize,
    },
}

/// Fits the `f32` geometries `geometry` (built as the library builds them,
/// e.g. [`Geometry::splat`], or anything that converts into one, such as
/// the C ABI's mirror of it: no copy is made) to the un-normalised data `data` over `axes`
/// with correlation `corr`. The data are divided by their max in `f64`,
/// as the library does (docs/conventions.md §4).
///
/// # Errors
/// [`SmallFitError`] for a bad count, datum or grid.
pub fn fit<G: Copy + Into<Geometry<f32>>>(
    corr: Correlation,
    geometry: &[G],
    data: &[f64],
    axes: &Axes<'_>,
    scratch: &mut Scratch,
) -> Result<SmallFit, SmallFitError> {
    let k = geometry.len();
    if k == 0 || k > MAX_MEASUREMENTS || data.len() != k {
        return Err(SmallFitError::Count {
            geometries: k,
            data: data.len(),
        });
    }
    check_data(data).map_err(|(index, fault)| SmallFitError::Data { index, fault })?;
    let max = data.iter().fold(0.0f64, |m, &d| m.max(d));
    axes.validate().map_err(SmallFitError::Axis)?;
    let layout = Layout::new(k);
    // At most MAX_MEASUREMENTS chunks (one lane each at worst), which also
    // tells the compiler every index below is in bounds: no panic path.
    let chunks = layout.chunks::<f32>().min(MAX_MEASUREMENTS);
    // Pack: padding lanes repeat the last geometry with weight and datum 0.
    for c in 0..chunks {
        let m = layout.measurement::<f32>(c, 0);
        let real = m < k;
        scratch.geometry[c] = geometry[m.min(k - 1)].into();
        scratch.data[c] = if real { (data[m] / max) as f32 } else { 0.0 };
        scratch.valid[c] = if real { 1.0 } else { 0.0 };
    }
    layout.widen(&scratch.data[..chunks], &mut scratch.d[..k]);
    let zero_a = axes.a.iter().position(|&a| a == 0.0);
    // The best (flat index, objective) overall and on the a = 0 slice.
    let mut best: Option<(usize, f64)> = None;
    let mut rh: Option<(usize, f64)> = None;
    for (i_s, &slope) in axes.slope.iter().enumerate() {
        let inv_s2 = inverse_slope_squared(slope as f32);
        for c in 0..chunks {
            let g = &scratch.geometry[c];
            scratch.surface[c] = surface_radiance(g, corr, inv_s2) * scratch.valid[c];
        }
        normalise(&mut scratch.surface[..chunks]);
        layout.widen(&scratch.surface[..chunks], &mut scratch.s[..k]);
        let (s, d) = (&scratch.s[..k], &scratch.d[..k]);
        let wide = Widened {
            s,
            ss: onepass::dot(s, s),
            d,
            data: DataSums::new(s, d),
        };
        for (i_n, &n) in axes.n.iter().enumerate() {
            for c in 0..chunks {
                let iface = Interface::new(&scratch.geometry[c], n as f32);
                scratch.base[c] = subsurface_base(&iface, corr, inv_s2) * scratch.valid[c];
            }
            for (i_a, &a) in axes.a.iter().enumerate() {
                for c in 0..chunks {
                    let att = absorption_factor(&scratch.geometry[c], a as f32);
                    scratch.subsurface[c] = scratch.base[c] * att;
                }
                normalise(&mut scratch.subsurface[..chunks]);
                let terms = Terms {
                    layout: &layout,
                    data: &scratch.data[..chunks],
                    surface: &scratch.surface[..chunks],
                    subsurface: &scratch.subsurface[..chunks],
                };
                let scratch_delta = (&mut scratch.delta[..chunks], &mut scratch.delta_f64[..k]);
                onepass::sweep(terms, &wide, axes.beta, scratch_delta, |i_b, e| {
                    let flat = axes.flat(i_s, i_n, i_a, i_b);
                    if best.is_none_or(|(_, b)| e < b) {
                        best = Some((flat, e));
                    }
                    if zero_a == Some(i_a) && rh.is_none_or(|(_, b)| e < b) {
                        rh = Some((flat, e));
                    }
                });
            }
        }
    }
    let (best, objective) = best.unwrap_or((0, f64::INFINITY));
    Ok(SmallFit {
        best,
        objective,
        rms: onepass::rms_of_sum(objective, k),
        rh_best: rh,
    })
}
