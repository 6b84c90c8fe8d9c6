//! Sine and cosine in `f32` arithmetic alone, for the `f32` geometry
//! constructors ([`crate::Geometry::from_angles_f32`]): on an FPU without
//! double precision (Cortex-M4F) libm's `sinf`/`cosf`, which work in `f64`,
//! are software calls.
//!
//! Algorithm: `q = round(x · 2/π)` by the add-and-subtract magic-number
//! trick, `r = (x − q·P1) − q·P2` with `P1 + P2 = π/2` (`P1` the `f32`
//! nearest π/2; `q ∈ {−2, …, 2}` on `[−π, π]`, so `q·P1` is exact and
//! `x − q·P1` is exact by Sterbenz where it cancels), then the Taylor
//! polynomials of `sin r` (to `r⁹`) and `cos r` (to `r¹⁰`) on
//! `|r| ≤ π/4` (truncation below 2⁻²⁵ relative), and the quadrant's
//! rotation. Measured error (test `sin_cos_error_is_within_its_budget`,
//! every 16th `f32` in `[−π, π]` against `f64` libm): 1.39 ulp for `sin`,
//! 1.42 for `cos`; the test asserts 1.5.

/// The `f32` nearest π/2 (above it).
pub(crate) const P1: f32 = core::f32::consts::FRAC_PI_2;
/// `π/2 − P1`, rounded to `f32`.
pub(crate) const P2: f32 = (core::f64::consts::FRAC_PI_2 - P1 as f64) as f32;

/// `(sin x, cos x)` for `x ∈ [−π, π]` (wider arguments lose accuracy as
/// `x − q·P1` stops being exact; the result stays finite for finite `x`).
#[must_use]
pub fn sin_cos(x: f32) -> (f32, f32) {
    const MAGIC: f32 = 12_582_912.0; // 1.5 · 2²³
    let q = (x * core::f32::consts::FRAC_2_PI + MAGIC) - MAGIC;
    let r = (x - q * P1) - q * P2;
    let r2 = r * r;
    let sin =
        r + r * r2 * (-1.0 / 6.0 + r2 * (1.0 / 120.0 + r2 * (-1.0 / 5040.0 + r2 / 362_880.0)));
    // cos r = w + ((1 − w) − r²/2) + r⁴·…, with w = 1 − r²/2 rounded: the
    // parenthesis recovers the rounding of w exactly (fdlibm's kernel).
    let half = 0.5 * r2;
    let w = 1.0 - half;
    let tail =
        r2 * r2 * (1.0 / 24.0 + r2 * (-1.0 / 720.0 + r2 * (1.0 / 40_320.0 - r2 / 3_628_800.0)));
    let cos = w + (((1.0 - w) - half) + tail);
    match (q as i32) & 3 {
        0 => (sin, cos),
        1 => (cos, -sin),
        2 => (-sin, -cos),
        _ => (-cos, sin),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ulps(got: f32, want: f64) -> f64 {
        let w = (want as f32).abs();
        let ulp = if w == 0.0 {
            f32::from_bits(1) as f64
        } else {
            (f32::from_bits(w.to_bits() + 1) - w) as f64
        };
        (got as f64 - want).abs() / ulp
    }

    #[test]
    fn sin_cos_error_is_within_its_budget() {
        let (mut max_s, mut max_c) = (0.0f64, 0.0f64);
        let mut check = |x: f32| {
            let (s, c) = sin_cos(x);
            max_s = max_s.max(ulps(s, libm::sin(x as f64)));
            max_c = max_c.max(ulps(c, libm::cos(x as f64)));
        };
        let top = core::f32::consts::PI.to_bits() - 1; // the largest f32 below π
        let mut bits = 0u32;
        while bits <= top {
            check(f32::from_bits(bits));
            check(-f32::from_bits(bits));
            bits += 16;
        }
        for x in [
            0.0,
            P1,
            -P1,
            2.0 * P1,
            f32::from_bits(top),
            1e-30,
            core::f32::consts::FRAC_PI_4,
        ] {
            check(x);
        }
        std::println!("f32 sin_cos: sin {max_s:.3} ulp, cos {max_c:.3} ulp");
        assert!(max_s <= 1.5 && max_c <= 1.5, "sin {max_s} cos {max_c}");
    }
}
