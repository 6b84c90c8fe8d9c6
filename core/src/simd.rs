//! Kernels run with the widest lanes the processor has, chosen when the
//! program runs.
//!
//! A kernel is a pass over packed measurements written once, generic over
//! a four-`f64` lane type ([`Lane4`]), as a [`Kernel`]. [`run`] with
//! [`Path::Portable`] runs it with `wide::f64x4` (two SSE halves in a build
//! for every x86-64 processor; one register on aarch64 and in a build for
//! AVX); with [`Path::Avx2`], on an x86-64 processor that has AVX2 and FMA
//! ([`avx2_available`]), with AVX2 lanes, inside a function compiled for
//! AVX2 and FMA. The two give the same bits: both lane types are the IEEE
//! operations of the scalar `f64` path.
//!
//! The fitting library chooses the path (`LAMINAR_SIMD`, else what the
//! processor has). A kernel's `run` and everything it
//! calls with the lane type must be inlined into it (`#[inline(always)]`):
//! a generic function compiled on its own is compiled for every x86-64
//! processor, and each AVX instruction in it would become a call.

use crate::lane::Lane;
use core::ops::AddAssign;
use wide::f64x4;

/// Four `f64` lanes: `wide::f64x4`, or on x86-64 the AVX2 lanes of
/// [`Path::Avx2`]. Storage stays `wide::f64x4` (or `[f64; 4]`); a kernel
/// loads from it and stores to it.
pub trait Lane4: Lane<Scalar = f64> + AddAssign {
    /// The four values in order.
    fn from_array(a: [f64; 4]) -> Self;
    /// The four lanes in order.
    fn to_array(self) -> [f64; 4];
    /// The lanes of a stored `f64x4`.
    fn load(v: f64x4) -> Self;
    /// The lanes as an `f64x4` to store.
    fn store(self) -> f64x4;
    /// Every lane 0.
    #[inline(always)]
    fn zero() -> Self {
        Self::splat(0.0)
    }
}

impl Lane4 for f64x4 {
    #[inline(always)]
    fn from_array(a: [f64; 4]) -> Self {
        f64x4::new(a)
    }
    #[inline(always)]
    fn to_array(self) -> [f64; 4] {
        f64x4::to_array(self)
    }
    #[inline(always)]
    fn load(v: f64x4) -> Self {
        v
    }
    #[inline(always)]
    fn store(self) -> f64x4 {
        self
    }
}

/// A pass written once for any [`Lane4`] (see the module docs).
pub trait Kernel {
    /// What the pass returns.
    type Output;
    /// The pass with lanes `L`. Implementations mark it
    /// `#[inline(always)]`.
    fn run<L: Lane4>(self) -> Self::Output;
}

/// The lanes a kernel runs with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Path {
    /// `wide::f64x4`: every processor.
    Portable,
    /// 256-bit AVX2 lanes (x86-64 processors with AVX2 and FMA: Intel since
    /// 2013, AMD since 2015).
    Avx2,
}

impl Path {
    /// The name the front ends take and report.
    pub const fn name(self) -> &'static str {
        match self {
            Self::Portable => "portable",
            Self::Avx2 => "avx2",
        }
    }
}

/// True when this processor can run [`Path::Avx2`]: it has AVX2 and FMA and
/// the system saves their registers (asked once, then remembered).
pub fn avx2_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        crate::avx2::detected()
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// `kernel` on `path`'s lanes; [`Path::Avx2`] falls back to the portable
/// lanes where [`avx2_available`] is false (the same bits either way).
#[inline]
pub fn run<K: Kernel>(path: Path, kernel: K) -> K::Output {
    match path {
        #[cfg(target_arch = "x86_64")]
        Path::Avx2 if avx2_available() => {
            #[target_feature(enable = "avx2,fma")]
            fn with_avx2<K: Kernel>(kernel: K) -> K::Output {
                kernel.run::<crate::avx2::F64x4>()
            }
            // SAFETY: the processor has AVX2 and FMA (just checked).
            #[allow(unsafe_code)]
            unsafe {
                with_avx2(kernel)
            }
        }
        _ => run_portable(kernel),
    }
}

/// `kernel` with `wide::f64x4` lanes.
#[inline]
pub fn run_portable<K: Kernel>(kernel: K) -> K::Output {
    kernel.run::<f64x4>()
}
