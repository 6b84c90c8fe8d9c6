//! Cube roots four at a time, for the cube-root distance of
//! [`crate::graphics_metrics`], which takes two per measurement.
//!
//! `libm::cbrt` is correctly rounded (CORE-MATH), but on a target compiled
//! without hardware FMA its two fused multiply-adds are emulated in
//! software: at K = 22,801 it was 12% of a search-only batch fit. Here a
//! positive `x` starts from a bit-level estimate of `r = x^(-1/3)`
//! (exponent and mantissa divided by three, within 3.4%), takes three
//! Newton steps `r ← r + r (1 − x r³) / 3` that need no division (3.4e-2
//! → 2.4e-3 → 1.1e-5 → 2.6e-10), and ends on one Newton step for the root
//! itself, `y = x r²`, `y ← y + (x / y² − y) / 3`: a small correction, so
//! the result's error is its own rounding's. Measured against `libm::cbrt`
//! (the `within_one_ulp_of_the_correctly_rounded_root` test): at most
//! 1 ulp, and 91.6% of a million values exactly the correctly rounded
//! root. Only IEEE-exact operations (+, −, ×, ÷) are used, so the bits are
//! the same on every target. No intermediate leaves the normal range for
//! `x` in [1e-300, 1e300]; lanes outside it (zero, negative, infinite, NaN
//! and the extremes) take `libm::cbrt`.

use laminar_brdf_core::f64x4;

/// The bits of `x^(-1/3)` as this minus `bits(x) / 3`: the exponent
/// bias's four thirds, tuned for the mantissa.
const INVERSE: u64 = 0x553E_F0FF_289D_D796;

/// The cube roots of four values (see the module docs; within 1 ulp).
pub fn cbrt4(x: [f64; 4]) -> [f64; 4] {
    let fast = |v: f64| (1e-300..=1e300).contains(&v);
    let safe = x.map(|v| if fast(v) { v } else { 1.0 });
    let xv = f64x4::from(safe);
    let mut r = f64x4::from(safe.map(|v| f64::from_bits(INVERSE - v.to_bits() / 3)));
    let (one, third) = (f64x4::splat(1.0), f64x4::splat(1.0 / 3.0));
    for _ in 0..3 {
        r += r * (one - xv * (r * r * r)) * third;
    }
    let mut y = xv * r * r;
    y += (xv / (y * y) - y) * third;
    let y = y.to_array();
    std::array::from_fn(|i| if fast(x[i]) { y[i] } else { libm::cbrt(x[i]) })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cube root of each of `values`, four at a time.
    fn cbrt_all(values: &[f64]) -> Vec<f64> {
        let mut out = Vec::with_capacity(values.len());
        let (fours, tail) = values.as_chunks::<4>();
        for four in fours {
            out.extend_from_slice(&cbrt4(*four));
        }
        if !tail.is_empty() {
            let mut last = [1.0; 4];
            last[..tail.len()].copy_from_slice(tail);
            out.extend_from_slice(&cbrt4(last)[..tail.len()]);
        }
        out
    }

    /// Distance in units in the last place between two positive finite
    /// values (or equal special values).
    fn ulps(a: f64, b: f64) -> u64 {
        if a == b || (a.is_nan() && b.is_nan()) {
            return 0;
        }
        (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs()
    }

    /// Over a million values spread log-uniformly across the normal range,
    /// every exponent residue mod 3, and near the powers of two, each root
    /// is within 1 ulp of `libm::cbrt`'s correctly rounded one; the special
    /// values are exactly `libm::cbrt`'s.
    #[test]
    fn within_one_ulp_of_the_correctly_rounded_root() {
        let mut state = 0x9E37_79B9_7F4A_7C15_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let mut values: Vec<f64> = (0..1_000_000)
            .map(|_| {
                // A random normal positive double: exponent field 1..=2046.
                let bits = next();
                let exponent = 1 + (bits >> 52) % 2046;
                f64::from_bits(exponent << 52 | (bits & ((1 << 52) - 1)))
            })
            .collect();
        values.extend((-40..40).flat_map(|e| {
            let p = libm::ldexp(1.0, e);
            [
                p,
                p * (1.0 + f64::EPSILON),
                p * (1.0 - f64::EPSILON / 2.0),
                p * 3.0,
            ]
        }));
        values.extend((1..2000).map(|i| i as f64 / 1000.0));
        let roots = cbrt_all(&values);
        let mut exact = 0;
        for (&x, &y) in values.iter().zip(&roots) {
            let d = ulps(y, libm::cbrt(x));
            assert!(d <= 1, "cbrt({x:e}) = {y:e}, libm {:e}", libm::cbrt(x));
            exact += usize::from(d == 0);
        }
        // Nearly all are the correctly rounded root itself.
        assert!(exact as f64 >= 0.9 * values.len() as f64, "{exact} exact");
        let special = [0.0, -0.0, -8.0, 1e-310, f64::INFINITY, f64::NAN, -1e-320];
        let roots = cbrt4([special[0], special[1], special[2], special[3]]);
        let more = cbrt4([special[4], special[5], special[6], 27.0]);
        for (&x, &y) in special.iter().zip(roots.iter().chain(&more)) {
            assert_eq!(ulps(y, libm::cbrt(x)), 0, "cbrt({x:e})");
        }
        assert_eq!(more[3], 3.0);
    }
}
