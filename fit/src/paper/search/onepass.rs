//! SearchPath 2, the hoisted one-pass β sweep: the kernel is
//! [`laminar_brdf_core::onepass::sweep`] (its docs give the algebra), shared
//! with the on-device fit; this module gives it the packed scene and
//! growable scratch.

use super::packed::Packed;
use laminar_brdf_core::onepass::{self, Terms, Widened};
use laminar_brdf_core::Lane;

/// Reusable per-shard buffers: `Δ` in lanes and widened.
pub struct Scratch<L> {
    delta: Vec<L>,
    delta_f64: Vec<f64>,
}

impl<L> Default for Scratch<L> {
    fn default() -> Self {
        Self {
            delta: Vec::new(),
            delta_f64: Vec::new(),
        }
    }
}

/// Calls `visit(i_b, Σ (D − P)²)` for every β of `betas`, in order, for one
/// (σ/T, n, a) with normalised surface `surface` (widened in `wide`) and
/// subsurface `subsurface`.
pub fn sweep<L: Lane>(
    packed: &Packed<L>,
    (surface, subsurface): (&[L], &[L]),
    wide: &Widened<'_>,
    betas: &[f64],
    scratch: &mut Scratch<L>,
    visit: impl FnMut(usize, f64),
) {
    let layout = packed.layout();
    scratch.delta.resize(surface.len(), L::c(0.0));
    scratch.delta_f64.resize(packed.k, 0.0);
    let terms = Terms {
        layout: &layout,
        data: &packed.data,
        surface,
        subsurface,
    };
    onepass::sweep(
        terms,
        wide,
        betas,
        (&mut scratch.delta, &mut scratch.delta_f64),
        visit,
    );
}
