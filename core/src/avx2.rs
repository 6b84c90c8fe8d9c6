//! Four `f64` lanes in one AVX register (`__m256d`), for kernels run
//! through [`crate::simd::run`] on a processor that has AVX2 and FMA.
//!
//! `wide::f64x4` fixes its layout when the crate is compiled: a build for
//! every x86-64 processor (what `cargo install` and `pip install` give)
//! runs it as two SSE halves, even inside a function compiled for AVX2.
//! This lane type uses the 256-bit instructions directly. Each operation is
//! the IEEE 754 operation of `wide::f64x4` and of the scalar `f64` path
//! (`+ − × ÷`, `sqrt`, ordered comparisons, blends, exact power-of-two
//! scaling): no fused multiply-add, so the same bits lane by lane.
//!
//! The type is not nameable outside the crate: a kernel receives it only as
//! the lane parameter of [`crate::simd::Kernel::run`], inside a function
//! compiled with AVX2 enabled, which [`crate::simd::run`] calls only when
//! [`detected`] found the instructions. Every method is
//! `#[inline(always)]`, so that it is compiled inside that function (called
//! out of line, each intrinsic would be a call). `load` and `store` are
//! bit casts: `wide::f64x4` and `__m256d` are both 32 bytes holding the
//! four lanes in order, whatever `wide`'s own layout.
//!
//! The intrinsics need `unsafe`; this module is, with `sqrt`, the only place
//! in the crate that has any.
#![allow(unsafe_code)]

use crate::lane::{Lane, Mask};
use crate::simd::Lane4;
use core::arch::x86_64::{
    __m256d, _mm256_add_epi64, _mm256_add_pd, _mm256_and_pd, _mm256_blendv_pd, _mm256_castsi256_pd,
    _mm256_cmp_pd, _mm256_cvtepi32_epi64, _mm256_cvtpd_epi32, _mm256_div_pd, _mm256_loadu_pd,
    _mm256_movemask_pd, _mm256_mul_pd, _mm256_or_pd, _mm256_set1_epi64x, _mm256_set1_pd,
    _mm256_setr_pd, _mm256_slli_epi64, _mm256_sqrt_pd, _mm256_storeu_pd, _mm256_sub_pd, _CMP_EQ_OQ,
    _CMP_LE_OQ, _CMP_LT_OQ,
};
use core::ops::{Add, AddAssign, BitAnd, BitOr, Div, Mul, Sub};
use wide::f64x4;

/// Four `f64` lanes in an AVX register (see the module docs).
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct F64x4(__m256d);

/// The mask of [`F64x4`]'s comparisons: all bits of a lane set or clear.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct Mask64x4(__m256d);

// SAFETY (every `unsafe` block below): the intrinsics need AVX (and AVX2 for
// the integer ones); a value of these types exists only inside a kernel run
// by `simd::run` after `detected()` found both. None reads memory other than
// the arrays passed to it.

macro_rules! binary {
    ($trait:ident, $method:ident, $intrinsic:ident, $ty:ty) => {
        impl $trait for $ty {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: Self) -> Self {
                Self(unsafe { $intrinsic(self.0, rhs.0) })
            }
        }
    };
}

binary!(Add, add, _mm256_add_pd, F64x4);
binary!(Sub, sub, _mm256_sub_pd, F64x4);
binary!(Mul, mul, _mm256_mul_pd, F64x4);
binary!(Div, div, _mm256_div_pd, F64x4);
binary!(BitAnd, bitand, _mm256_and_pd, Mask64x4);
binary!(BitOr, bitor, _mm256_or_pd, Mask64x4);

impl AddAssign for F64x4 {
    #[inline(always)]
    fn add_assign(&mut self, rhs: Self) {
        *self = *self + rhs;
    }
}

impl Mask for Mask64x4 {
    #[inline(always)]
    fn all(self) -> bool {
        unsafe { _mm256_movemask_pd(self.0) == 0b1111 }
    }
}

impl crate::lane::sealed::Sealed for F64x4 {}

impl Lane for F64x4 {
    type Scalar = f64;
    type Mask = Mask64x4;
    const LANES: usize = 4;
    #[inline(always)]
    fn splat(s: f64) -> Self {
        Self(unsafe { _mm256_set1_pd(s) })
    }
    #[inline(always)]
    fn from_f64_lanes(mut f: impl FnMut(usize) -> f64) -> Self {
        let (a, b, c, d) = (f(0), f(1), f(2), f(3));
        Self(unsafe { _mm256_setr_pd(a, b, c, d) })
    }
    #[inline(always)]
    fn lane(self, i: usize) -> f64 {
        self.to_array()[i.min(3)]
    }
    #[inline(always)]
    fn c(v: f64) -> Self {
        Self::splat(v)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Self(unsafe { _mm256_sqrt_pd(self.0) })
    }
    #[inline(always)]
    fn lt(self, rhs: Self) -> Mask64x4 {
        Mask64x4(unsafe { _mm256_cmp_pd::<_CMP_LT_OQ>(self.0, rhs.0) })
    }
    #[inline(always)]
    fn le(self, rhs: Self) -> Mask64x4 {
        Mask64x4(unsafe { _mm256_cmp_pd::<_CMP_LE_OQ>(self.0, rhs.0) })
    }
    #[inline(always)]
    fn eq(self, rhs: Self) -> Mask64x4 {
        Mask64x4(unsafe { _mm256_cmp_pd::<_CMP_EQ_OQ>(self.0, rhs.0) })
    }
    /// The blend reads each lane's sign bit, which a comparison's mask sets
    /// with all the others: `wide`'s and the scalar `if`.
    #[inline(always)]
    fn select(mask: Mask64x4, t: Self, f: Self) -> Self {
        Self(unsafe { _mm256_blendv_pd(f.0, t.0, mask.0) })
    }
    /// `(n + 1023) << 52` in 64-bit integer lanes, from `n`'s exact
    /// conversion to 32-bit integers (the scalar path's `n as i64`).
    #[inline(always)]
    fn pow2i(n: Self) -> Self {
        Self(unsafe {
            let n = _mm256_cvtepi32_epi64(_mm256_cvtpd_epi32(n.0));
            let biased = _mm256_add_epi64(n, _mm256_set1_epi64x(1023));
            _mm256_castsi256_pd(_mm256_slli_epi64::<52>(biased))
        })
    }
    #[inline(always)]
    fn max(self, rhs: Self) -> Self {
        Self::select(self.lt(rhs), rhs, self)
    }
    #[inline(always)]
    fn min(self, rhs: Self) -> Self {
        Self::select(rhs.lt(self), rhs, self)
    }
}

impl Lane4 for F64x4 {
    #[inline(always)]
    fn from_array(a: [f64; 4]) -> Self {
        Self(unsafe { _mm256_loadu_pd(a.as_ptr()) })
    }
    #[inline(always)]
    fn to_array(self) -> [f64; 4] {
        let mut a = [0.0; 4];
        unsafe { _mm256_storeu_pd(a.as_mut_ptr(), self.0) };
        a
    }
    #[inline(always)]
    fn load(v: f64x4) -> Self {
        Self(unsafe { core::mem::transmute::<f64x4, __m256d>(v) })
    }
    #[inline(always)]
    fn store(self) -> f64x4 {
        unsafe { core::mem::transmute::<__m256d, f64x4>(self.0) }
    }
}

/// True when the processor has AVX2 and FMA and the operating system saves
/// the 256-bit registers (CPUID and XGETBV, as `std`'s detection reads
/// them), asked once and remembered.
pub fn detected() -> bool {
    use core::sync::atomic::{AtomicU8, Ordering};
    // 0 unknown, 1 absent, 2 present.
    static STATE: AtomicU8 = AtomicU8::new(0);
    match STATE.load(Ordering::Relaxed) {
        0 => {
            let found = ask_the_processor();
            STATE.store(if found { 2 } else { 1 }, Ordering::Relaxed);
            found
        }
        state => state == 2,
    }
}

/// CPUID leaf 1: OSXSAVE (ECX 27), AVX (ECX 28), FMA (ECX 12); XGETBV: the
/// XMM and YMM state enabled (bits 1–2); leaf 7: AVX2 (EBX 5).
fn ask_the_processor() -> bool {
    use core::arch::x86_64::{__cpuid, __cpuid_count};
    let bit = |v: u32, b: u32| v & (1 << b) != 0;
    // SAFETY: CPUID exists on every x86-64 processor; XGETBV is executed
    // only when OSXSAVE says the system enabled it.
    unsafe {
        let max_leaf = __cpuid(0).eax;
        let leaf1 = __cpuid(1);
        if max_leaf < 7 || !bit(leaf1.ecx, 27) || !bit(leaf1.ecx, 28) || !bit(leaf1.ecx, 12) {
            return false;
        }
        if xgetbv0() & 0b110 != 0b110 {
            return false;
        }
        bit(__cpuid_count(7, 0).ebx, 5)
    }
}

/// XCR0, read by XGETBV (compiled with `xsave` enabled, which it needs).
#[target_feature(enable = "xsave")]
unsafe fn xgetbv0() -> u64 {
    unsafe { core::arch::x86_64::_xgetbv(0) }
}
