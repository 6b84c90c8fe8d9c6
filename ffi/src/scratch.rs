//! The working memory of the on-device fits ([`crate::fit`]), which the
//! caller owns: sized and aligned for every scratch memory of the core's
//! fits (checked at compile time).

use laminar_brdf_core::small_fit::Scratch;
use laminar_brdf_core::small_free_fit::FreeScratch;

/// 64-bit words of [`LaminarFitScratch`].
pub const LAMINAR_FIT_SCRATCH_WORDS: usize = 640;

/// Working memory of a fit (5 KB), owned by the caller: a `static` or a
/// local. Its contents between calls do not matter.
#[repr(C)]
pub struct LaminarFitScratch {
    /// Opaque.
    pub words: [u64; LAMINAR_FIT_SCRATCH_WORDS],
}

impl LaminarFitScratch {
    /// Zeroed scratch (`const`, so it can be a `static`).
    pub const fn new() -> Self {
        Self {
            words: [0; LAMINAR_FIT_SCRATCH_WORDS],
        }
    }
}

impl Default for LaminarFitScratch {
    fn default() -> Self {
        Self::new()
    }
}

const _: () = assert!(core::mem::size_of::<Scratch>() <= 8 * LAMINAR_FIT_SCRATCH_WORDS);
const _: () = assert!(core::mem::size_of::<FreeScratch<f32>>() <= 8 * LAMINAR_FIT_SCRATCH_WORDS);
// `u64` words are aligned as `f64` is, on every target.
const _: () =
    assert!(core::mem::align_of::<Scratch>() <= core::mem::align_of::<LaminarFitScratch>());
const _: () = assert!(
    core::mem::align_of::<FreeScratch<f32>>() <= core::mem::align_of::<LaminarFitScratch>()
);
