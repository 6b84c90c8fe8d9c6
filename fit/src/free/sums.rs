//! Inner products in a fixed order: four partial sums per product, the
//! lanes of an `f64x4` (a single running sum is a chain of dependent
//! additions, which no compiler may reorder into vector code), combined the
//! same way on every target so that every fit gives the same bits
//! everywhere.

use laminar_core::f64x4;

/// `Σ_k x_k y_k` over `k < x.len()` for each of the `N` vectors `ys` (each
/// at least as long as `x`), four partial sums per vector, one per lane of
/// an `f64x4` (a fixed order, so the same bits on every target).
pub fn dots<const N: usize>(x: &[f64], ys: [&[f64]; N]) -> [f64; N] {
    let len = x.len();
    let (xs, x_tail) = x.as_chunks::<4>();
    let ys = ys.map(|y| &y[..len]);
    let fours = ys.map(|y| y.as_chunks::<4>().0);
    let mut acc = [f64x4::ZERO; N];
    for (k, &xk) in xs.iter().enumerate() {
        let xk = f64x4::from(xk);
        for (a, y) in acc.iter_mut().zip(&fours) {
            *a += xk * f64x4::from(y[k]);
        }
    }
    let body = len - x_tail.len();
    let mut out = [0.0; N];
    for ((o, a), y) in out.iter_mut().zip(&acc).zip(&ys) {
        *o = total(*a);
        for (xk, yk) in x_tail.iter().zip(&y[body..]) {
            *o += xk * yk;
        }
    }
    out
}

/// The four partial sums of a lane accumulator added in the fixed order
/// of [`dots`].
pub fn total(a: f64x4) -> f64 {
    let a = a.to_array();
    (a[0] + a[1]) + (a[2] + a[3])
}

/// `Σ_k x_k y_k` ([`dots`] of one vector).
pub fn dot(x: &[f64], y: &[f64]) -> f64 {
    dots(x, [y])[0]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partial_sums_give_the_inner_product() {
        // Small integers and halves: every sum is exact, in any order.
        for len in [0, 1, 3, 4, 5, 8, 11] {
            let x: Vec<f64> = (0..len).map(|i| 1.0 + i as f64).collect();
            let y: Vec<f64> = (0..len).map(|i| 0.5 * i as f64 - 1.0).collect();
            let want: f64 = x.iter().zip(&y).map(|(a, b)| a * b).sum();
            assert_eq!(dot(&x, &y), want, "{len}");
            assert_eq!(dots(&x, [&y, &x]), [want, dot(&x, &x)]);
        }
    }
}
