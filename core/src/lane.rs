//! The lane trait: one numeric interface for `f32`, `f64`, `wide::f32x8`,
//! `wide::f64x4` and the AVX2 lanes of [`crate::simd`].
//!
//! Every equation of the model is written once against [`Lane`]. The trait
//! exposes only operations whose results are defined bit for bit by IEEE 754
//! in every implementation: `+ − × ÷`, `sqrt`, comparisons, `select` and
//! exact power-of-two scaling. It deliberately has no `mul_add` (fused only on
//! some targets), no vendor `exp` and no horizontal reduction (their rounding
//! differs between SIMD widths). That is what makes the `f32x8` path bitwise
//! identical to the scalar `f32` path, and the `f64x4` path to the scalar
//! `f64` path, lane by lane, on every target.

use core::ops::{Add, BitAnd, BitOr, Div, Mul, Sub};
use wide::{f32x8, f64x4, i32x8};

/// A lane mask produced by comparisons and consumed by [`Lane::select`].
pub trait Mask: Copy + BitAnd<Output = Self> + BitOr<Output = Self> {
    /// True when every lane is set (a branch that skips work no lane
    /// needs; it never changes a lane's result).
    fn all(self) -> bool;
}

impl Mask for bool {
    fn all(self) -> bool {
        self
    }
}

impl Mask for f32x8 {
    fn all(self) -> bool {
        f32x8::all(self)
    }
}

impl Mask for f64x4 {
    fn all(self) -> bool {
        f64x4::all(self)
    }
}

/// Seals [`Lane`]: its five implementations are the whole determinism
/// policy, so no other type may join them.
pub(crate) mod sealed {
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
    impl Sealed for wide::f32x8 {}
    impl Sealed for wide::f64x4 {}
}

/// A vector of one or more floating-point lanes (see the module docs).
/// Sealed: implemented for `f32`, `f64`, `wide::f32x8`, `wide::f64x4` and
/// the AVX2 lanes of [`crate::simd`] only.
pub trait Lane:
    sealed::Sealed
    + Copy
    + core::fmt::Debug
    + Send
    + Sync
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
{
    /// The type of one lane (`f32` for `f32` and `f32x8`, `f64` for `f64`
    /// and `f64x4`).
    type Scalar: Real;
    /// The mask type returned by comparisons.
    type Mask: Mask;
    /// Number of lanes.
    const LANES: usize;

    /// Every lane set to `s`.
    fn splat(s: Self::Scalar) -> Self;
    /// Lane `i` set to `f(i)`, rounded to the lane precision.
    fn from_f64_lanes(f: impl FnMut(usize) -> f64) -> Self;
    /// Lane `i` (`i < LANES`; other indices read the last lane).
    fn lane(self, i: usize) -> Self::Scalar;

    /// Every lane set to the constant `v`, rounded to the lane precision.
    #[inline]
    fn c(v: f64) -> Self {
        Self::splat(Self::Scalar::from_f64(v))
    }

    /// Correctly rounded square root (IEEE 754).
    fn sqrt(self) -> Self;
    /// Lane-wise `self < rhs`.
    fn lt(self, rhs: Self) -> Self::Mask;
    /// Lane-wise `self <= rhs`.
    fn le(self, rhs: Self) -> Self::Mask;
    /// Lane-wise `self == rhs`.
    fn eq(self, rhs: Self) -> Self::Mask;
    /// Lane-wise `if mask { t } else { f }`.
    fn select(mask: Self::Mask, t: Self, f: Self) -> Self;
    /// `2^n` for lanes holding integers `n` in the normal exponent range
    /// (`[−126, 127]` for `f32`, `[−1022, 1023]` for `f64`); exact.
    fn pow2i(n: Self) -> Self;

    /// Lane-wise maximum written as compare + select (so ±0 and ties resolve
    /// the same way in every implementation).
    #[inline]
    fn max(self, rhs: Self) -> Self {
        Self::select(self.lt(rhs), rhs, self)
    }
    /// Lane-wise minimum written as compare + select.
    #[inline]
    fn min(self, rhs: Self) -> Self {
        Self::select(rhs.lt(self), rhs, self)
    }
}

/// `1/k!` for `k = 0..16`, each from the previous by one `f64` division
/// (evaluated at compile time; rounded to the lane precision by
/// [`Real::INV_FACTORIALS`]).
const INV_FACTORIALS_F64: [f64; 16] = {
    let mut t = [0.0f64; 16];
    t[0] = 1.0;
    let mut k = 1;
    while k < 16 {
        t[k] = t[k - 1] / k as f64;
        k += 1;
    }
    t
};

/// A scalar lane type (`f32` or `f64`): a [`Lane`] of width one that is its
/// own scalar, with the constants of the generic `exp` (its polynomial degree,
/// factorials, range and argument reduction).
pub trait Real: Lane<Scalar = Self, Mask = bool> + PartialOrd + Default {
    /// `v` rounded to this precision.
    fn from_f64(v: f64) -> Self;
    /// The value widened to `f64` (exact).
    fn to_f64(self) -> f64;
    /// Degree of the Taylor polynomial of `exp` on its reduced argument.
    const EXP_DEGREE: usize;
    /// Its coefficients `1/k!` in this precision (a compile-time table).
    const INV_FACTORIALS: [Self; 16];
    /// Below this argument `exp` returns exactly 0 (a flush: `exp(EXP_MIN)`
    /// is just above the smallest normal number).
    const EXP_MIN: f64;
    /// Above this argument `exp` returns +∞.
    const EXP_MAX: f64;
    /// High part of ln 2 with trailing zero bits, so `n · LN2_HI` is exact.
    const LN2_HI: f64;
    /// `ln 2 − LN2_HI`.
    const LN2_LO: f64;
    /// `1.5 · 2^(mantissa bits)`: adding and subtracting it rounds to an integer.
    const ROUND_MAGIC: f64;
    /// Below this multiple of `⟨S, S⟩⟨U, U⟩` the determinant of two columns'
    /// normal matrix is rounding, and [`crate::linear::Moments::solve`]
    /// treats them as parallel: about 4,500 ε of the precision (10⁻¹² in
    /// f64, 5 × 10⁻⁴ in f32).
    const COLLINEAR: f64;
}

impl Lane for f32 {
    type Scalar = f32;
    type Mask = bool;
    const LANES: usize = 1;
    #[inline]
    fn splat(s: f32) -> Self {
        s
    }
    #[inline]
    fn from_f64_lanes(mut f: impl FnMut(usize) -> f64) -> Self {
        f(0) as f32
    }
    #[inline]
    fn lane(self, _i: usize) -> f32 {
        self
    }
    #[inline]
    fn sqrt(self) -> Self {
        crate::sqrt::sqrtf(self)
    }
    #[inline]
    fn lt(self, rhs: Self) -> bool {
        self < rhs
    }
    #[inline]
    fn le(self, rhs: Self) -> bool {
        self <= rhs
    }
    #[inline]
    fn eq(self, rhs: Self) -> bool {
        self == rhs
    }
    #[inline]
    fn select(mask: bool, t: Self, f: Self) -> Self {
        if mask {
            t
        } else {
            f
        }
    }
    #[inline]
    fn pow2i(n: Self) -> Self {
        f32::from_bits(((n as i32 + 127) as u32) << 23)
    }
}

impl Real for f32 {
    #[inline]
    fn from_f64(v: f64) -> Self {
        v as f32
    }
    #[inline]
    fn to_f64(self) -> f64 {
        self as f64
    }
    const EXP_DEGREE: usize = 7;
    const INV_FACTORIALS: [f32; 16] = {
        let mut t = [0.0f32; 16];
        let mut k = 0;
        while k < 16 {
            t[k] = INV_FACTORIALS_F64[k] as f32;
            k += 1;
        }
        t
    };
    const EXP_MIN: f64 = -87.0;
    const EXP_MAX: f64 = 88.0;
    const LN2_HI: f64 = 0.693_359_375;
    const LN2_LO: f64 = -2.121_944_4e-4;
    const ROUND_MAGIC: f64 = 12_582_912.0;
    const COLLINEAR: f64 = 5e-4;
}

impl Lane for f64 {
    type Scalar = f64;
    type Mask = bool;
    const LANES: usize = 1;
    #[inline]
    fn splat(s: f64) -> Self {
        s
    }
    #[inline]
    fn from_f64_lanes(mut f: impl FnMut(usize) -> f64) -> Self {
        f(0)
    }
    #[inline]
    fn lane(self, _i: usize) -> f64 {
        self
    }
    #[inline]
    fn sqrt(self) -> Self {
        libm::sqrt(self)
    }
    #[inline]
    fn lt(self, rhs: Self) -> bool {
        self < rhs
    }
    #[inline]
    fn le(self, rhs: Self) -> bool {
        self <= rhs
    }
    #[inline]
    fn eq(self, rhs: Self) -> bool {
        self == rhs
    }
    #[inline]
    fn select(mask: bool, t: Self, f: Self) -> Self {
        if mask {
            t
        } else {
            f
        }
    }
    #[inline]
    fn pow2i(n: Self) -> Self {
        f64::from_bits(((n as i64 + 1023) as u64) << 52)
    }
}

impl Real for f64 {
    #[inline]
    fn from_f64(v: f64) -> Self {
        v
    }
    #[inline]
    fn to_f64(self) -> f64 {
        self
    }
    const EXP_DEGREE: usize = 13;
    const INV_FACTORIALS: [f64; 16] = INV_FACTORIALS_F64;
    const EXP_MIN: f64 = -708.0;
    const EXP_MAX: f64 = 709.0;
    const LN2_HI: f64 = 6.931_471_803_691_238e-1;
    const LN2_LO: f64 = 1.908_214_929_270_587_7e-10;
    const ROUND_MAGIC: f64 = 6_755_399_441_055_744.0;
    const COLLINEAR: f64 = 1e-12;
}

impl Lane for f32x8 {
    type Scalar = f32;
    type Mask = f32x8;
    const LANES: usize = 8;
    #[inline]
    fn splat(s: f32) -> Self {
        f32x8::splat(s)
    }
    #[inline]
    fn from_f64_lanes(mut f: impl FnMut(usize) -> f64) -> Self {
        let mut a = [0.0f32; 8];
        for (i, v) in a.iter_mut().enumerate() {
            *v = f(i) as f32;
        }
        f32x8::new(a)
    }
    #[inline]
    fn lane(self, i: usize) -> f32 {
        self.to_array()[i.min(7)]
    }
    #[inline]
    fn sqrt(self) -> Self {
        f32x8::sqrt(self)
    }
    #[inline]
    fn lt(self, rhs: Self) -> f32x8 {
        self.simd_lt(rhs)
    }
    #[inline]
    fn le(self, rhs: Self) -> f32x8 {
        self.simd_le(rhs)
    }
    #[inline]
    fn eq(self, rhs: Self) -> f32x8 {
        self.simd_eq(rhs)
    }
    #[inline]
    fn select(mask: f32x8, t: Self, f: Self) -> Self {
        mask.select(t, f)
    }
    #[inline]
    fn pow2i(n: Self) -> Self {
        let bits: i32x8 = (n.round_int() + i32x8::splat(127)) << 23;
        f32x8::from_bits(bits.cast_unsigned())
    }
    /// On x86 one `maxps`: `rhs.fast_max(self)` is `rhs > self ? rhs : self`,
    /// which is the trait's `self < rhs ? rhs : self` for every input, ±0
    /// and NaN included (both comparisons are false on NaN and on ties).
    #[cfg(all(
        any(target_arch = "x86", target_arch = "x86_64"),
        target_feature = "sse"
    ))]
    #[inline]
    #[allow(clippy::disallowed_methods)] // the one sanctioned use (clippy.toml)
    fn max(self, rhs: Self) -> Self {
        rhs.fast_max(self)
    }
    /// On x86 one `minps`: `rhs.fast_min(self)` is `rhs < self ? rhs : self`,
    /// exactly the trait's definition.
    #[cfg(all(
        any(target_arch = "x86", target_arch = "x86_64"),
        target_feature = "sse"
    ))]
    #[inline]
    #[allow(clippy::disallowed_methods)] // the one sanctioned use (clippy.toml)
    fn min(self, rhs: Self) -> Self {
        rhs.fast_min(self)
    }
}

/// Four `f64` lanes (the host's f64 fits, four measurements at a time).
/// `max` and `min` are the trait's compare + select.
impl Lane for f64x4 {
    type Scalar = f64;
    type Mask = f64x4;
    const LANES: usize = 4;
    #[inline]
    fn splat(s: f64) -> Self {
        f64x4::splat(s)
    }
    #[inline]
    fn from_f64_lanes(mut f: impl FnMut(usize) -> f64) -> Self {
        f64x4::new([f(0), f(1), f(2), f(3)])
    }
    #[inline]
    fn lane(self, i: usize) -> f64 {
        self.to_array()[i.min(3)]
    }
    #[inline]
    fn sqrt(self) -> Self {
        f64x4::sqrt(self)
    }
    #[inline]
    fn lt(self, rhs: Self) -> f64x4 {
        self.simd_lt(rhs)
    }
    #[inline]
    fn le(self, rhs: Self) -> f64x4 {
        self.simd_le(rhs)
    }
    #[inline]
    fn eq(self, rhs: Self) -> f64x4 {
        self.simd_eq(rhs)
    }
    #[inline]
    fn select(mask: f64x4, t: Self, f: Self) -> Self {
        mask.select(t, f)
    }
    /// Lane by lane through the scalar `f64` bits (`exp` calls it once per
    /// evaluation; wide has no f64 ↔ u64 bit cast without `bytemuck`).
    #[inline]
    fn pow2i(n: Self) -> Self {
        f64x4::new(n.to_array().map(<f64 as Lane>::pow2i))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pow2i_is_exact_over_the_normal_range() {
        for n in -126..=127 {
            let want = libm::ldexpf(1.0, n);
            assert_eq!(<f32 as Lane>::pow2i(n as f32).to_bits(), want.to_bits());
            let v = <f32x8 as Lane>::pow2i(f32x8::splat(n as f32));
            assert!(v.to_array().iter().all(|x| x.to_bits() == want.to_bits()));
        }
        for n in -1022..=1023 {
            assert_eq!(<f64 as Lane>::pow2i(n as f64), libm::ldexp(1.0, n));
        }
    }

    #[test]
    fn min_max_resolve_signed_zero_identically() {
        let (p, m) = (0.0f32, -0.0f32);
        let v = <f32x8 as Lane>::max(f32x8::splat(p), f32x8::splat(m));
        assert_eq!(v.lane(3).to_bits(), Lane::max(p, m).to_bits());
        let v = <f32x8 as Lane>::min(f32x8::splat(m), f32x8::splat(p));
        assert_eq!(v.lane(0).to_bits(), Lane::min(m, p).to_bits());
    }

    #[test]
    fn min_max_agree_with_scalar_on_every_special_pair() {
        let specials = [
            0.0f32,
            -0.0,
            1.0,
            -1.0,
            f32::NAN,
            -f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MIN_POSITIVE,
            3.5,
        ];
        for &x in &specials {
            for &y in &specials {
                let (vx, vy) = (f32x8::splat(x), f32x8::splat(y));
                let max = <f32x8 as Lane>::max(vx, vy).lane(5);
                let min = <f32x8 as Lane>::min(vx, vy).lane(2);
                assert_eq!(max.to_bits(), Lane::max(x, y).to_bits(), "max({x}, {y})");
                assert_eq!(min.to_bits(), Lane::min(x, y).to_bits(), "min({x}, {y})");
            }
        }
    }
}
