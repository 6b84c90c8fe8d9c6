//! `exp`, written once for every [`Lane`] from `+ − × ÷`, `select` and exact
//! power-of-two scaling, so the `f32x8` result is bitwise the scalar `f32` one.
//!
//! Algorithm (Cody–Waite): `n = round(x / ln 2)` by the add-and-subtract
//! magic-number trick, `r = (x − n·ln2_hi) − n·ln2_lo` with `|r| ≤ ln 2 / 2`,
//! `exp(r)` by the Taylor polynomial of degree [`Real::EXP_DEGREE`] in Horner
//! form (7 for `f32`, 13 for `f64`: truncation error below a quarter ulp), and
//! `exp(x) = 2^n · exp(r)`.

use crate::lane::{Lane, Real};

/// `e^x` for every lane (see the module docs).
///
/// Measured error against `libm::exp` in `f64` (test
/// `exp_error_is_within_its_budget`: every 7th `f32` bit pattern in the range,
/// every one with `LAMINAR_EXTENSIVE=1`; 2²⁰ evenly spaced and random points
/// for `f64`). Budget checked by the test: max ≤ 1.5 ulp, mean < 0.1 ulp.
///
/// | lanes | range of `x` | max error | mean error |
/// |---|---|---|---|
/// | `f32`, `f32x8` | `[−87, 88]` | 1.22 ulp | 0.064 ulp |
/// | `f64` | `[−708, 709]` | 1.00 ulp | 0.066 ulp |
///
/// Below `EXP_MIN` (−87 for `f32`, −708 for `f64`) the result is flushed to
/// exactly `+0.0` (true values below about 1.6e-38 and 3.3e-308, the last
/// few of them still normal); above `EXP_MAX` it is `+∞`;
/// `−∞` gives `+0.0`. The model only uses `x ≤ 0`. NaN in gives NaN out.
#[cfg_attr(target_arch = "x86_64", inline(always))] // inside `simd` kernels
#[cfg_attr(not(target_arch = "x86_64"), inline)]
#[must_use]
pub fn exp<L: Lane>(x: L) -> L {
    let lo = L::c(L::Scalar::EXP_MIN);
    let hi = L::c(L::Scalar::EXP_MAX);
    let underflow = x.lt(lo);
    let overflow = hi.lt(x);
    let xc = x.max(lo).min(hi);

    let magic = L::c(L::Scalar::ROUND_MAGIC);
    let n = (xc * L::c(core::f64::consts::LOG2_E) + magic) - magic;
    let r = (xc - n * L::c(L::Scalar::LN2_HI)) - n * L::c(L::Scalar::LN2_LO);

    // Horner form of Σ r^k / k!, k = 0..=EXP_DEGREE, from a table built at
    // compile time (built at run time, it cost 4,554 instructions per model
    // evaluation on a Cortex-M4 at opt-level "s", in soft f64).
    let c = &L::Scalar::INV_FACTORIALS;
    let degree = L::Scalar::EXP_DEGREE;
    let mut p = L::splat(c[degree]);
    for k in (0..degree).rev() {
        p = p * r + L::splat(c[k]);
    }

    let y = p * L::pow2i(n);
    let y = L::select(underflow, L::c(0.0), y);
    L::select(overflow, L::c(f64::INFINITY), y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use wide::f32x8;

    /// Distance in ulps of `got` from the `f64` reference, measured in units
    /// of the target precision at the reference value.
    fn ulps_f32(got: f32, want: f64) -> f64 {
        let w = want as f32;
        let ulp = (f32::from_bits(w.to_bits() + 1) - w) as f64;
        (got as f64 - want).abs() / ulp
    }

    #[test]
    fn exp_error_is_within_its_budget() {
        // f32: every representable value in [-87, 88], stepping through bit patterns.
        let (mut max, mut sum, mut count) = (0.0f64, 0.0f64, 0u64);
        let mut check = |x: f32| {
            let e = ulps_f32(exp(x), libm::exp(x as f64));
            max = max.max(e);
            sum += e;
            count += 1;
        };
        let stride = if std::env::var_os("LAMINAR_EXTENSIVE").is_some() {
            1
        } else {
            7
        };
        // Negative values from -87 up to -0 (bit patterns descend), then positives up to 88.
        let mut bits = (-87.0f32).to_bits();
        while bits > 0x8000_0000 {
            check(f32::from_bits(bits));
            bits -= stride.min(bits - 0x8000_0000);
        }
        let mut bits = 0u32;
        while f32::from_bits(bits) <= 88.0 {
            check(f32::from_bits(bits));
            bits += stride;
        }
        std::println!(
            "f32 exp: max {max:.3} ulp, mean {:.4} ulp",
            sum / count as f64
        );
        assert!(max <= 1.5, "f32 exp max error {max} ulp");
        assert!(
            sum / (count as f64) < 0.1,
            "f32 exp mean error {}",
            sum / count as f64
        );

        // f64: evenly spaced and pseudo-random points.
        let (mut max, mut sum) = (0.0f64, 0.0f64);
        let mut seed = 0x9E37_79B9_7F4A_7C15u64;
        let n = 1 << 20;
        for i in 0..n {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let x = if i % 2 == 0 {
                -708.0 + 1417.0 * (i as f64 / n as f64)
            } else {
                -708.0 + 1417.0 * ((seed >> 11) as f64 / (1u64 << 53) as f64)
            };
            let want = libm::exp(x);
            let ulp = f64::from_bits(want.to_bits() + 1) - want;
            let e = (exp(x) - want).abs() / ulp;
            max = max.max(e);
            sum += e;
        }
        std::println!("f64 exp: max {max:.3} ulp, mean {:.4} ulp", sum / n as f64);
        assert!(max <= 1.5, "f64 exp max error {max} ulp");
        assert!(
            sum / (n as f64) < 0.1,
            "f64 exp mean error {}",
            sum / n as f64
        );
    }

    #[test]
    fn exp_edges() {
        assert_eq!(exp(0.0f32), 1.0);
        assert_eq!(exp(0.0f64), 1.0);
        assert_eq!(exp(-100.0f32), 0.0);
        assert_eq!(exp(f32::NEG_INFINITY), 0.0);
        assert_eq!(exp(f64::NEG_INFINITY), 0.0);
        assert_eq!(exp(100.0f32), f32::INFINITY);
        assert!(exp(f32::NAN).is_nan());
    }

    #[test]
    fn f32x8_exp_is_bitwise_scalar() {
        let xs = [-87.5f32, -87.0, -20.25, -1.0e-7, 0.0, 0.5, 42.0, 88.5];
        let v = exp(f32x8::new(xs)).to_array();
        for (x, got) in xs.iter().zip(v) {
            assert_eq!(got.to_bits(), exp(*x).to_bits(), "x = {x}");
        }
    }
}
