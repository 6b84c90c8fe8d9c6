//! The objective along the a axis of one (σ/T, n) column: from the
//! column's quadratic in a ([`Quadratic`]), the closed-form solve at every
//! a, four at a time. Used by both layered grid stages
//! ([`super::quadratic`], [`super::untied`]) and the joint fit's.

use crate::free::linear::Quadratic;
use crate::simd;
use laminar_brdf_core::simd::{Kernel, Lane4};

/// The objective at every a of `a_axis` from one (σ/T, n)'s quadratic,
/// four at a time (the last group padded with its last a): bit for bit
/// one at a time, as the core's `f64x4` is its `f64` lane by lane.
pub(crate) fn objectives(q: &Quadratic<f64>, a_axis: &[f64], beta: (f64, f64), out: &mut [f64]) {
    simd::run(Objectives {
        q,
        a_axis,
        beta,
        out,
    });
}

/// The pass of [`objectives`].
struct Objectives<'a> {
    q: &'a Quadratic<f64>,
    a_axis: &'a [f64],
    beta: (f64, f64),
    out: &'a mut [f64],
}

impl Kernel for Objectives<'_> {
    type Output = ();

    #[inline(always)]
    fn run<L: Lane4>(self) {
        objectives_in::<L>(self.q, self.a_axis, self.beta, self.out);
    }
}

/// [`objectives`] in a kernel's lanes.
#[inline(always)]
pub(super) fn objectives_in<L: Lane4>(
    q: &Quadratic<f64>,
    a_axis: &[f64],
    beta: (f64, f64),
    out: &mut [f64],
) {
    for (group, out) in a_axis.chunks(4).zip(out.chunks_mut(4)) {
        let last = group.len() - 1;
        let a = L::from_array([0, 1, 2, 3].map(|i| group[i.min(last)]));
        let sse = q.moments(a).solve(beta).sse.to_array();
        // Element by element: `copy_from_slice` of at most four values was
        // a call to the C library's memcpy (9% of an untied grid stage).
        for (o, v) in out.iter_mut().zip(sse) {
            *o = v;
        }
    }
}
