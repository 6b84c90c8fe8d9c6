//! Inner products in a fixed order: four partial sums per product, which
//! the compiler keeps in vector registers (a single running sum is a chain
//! of dependent additions), combined the same way on every target so that
//! every fit gives the same bits everywhere.

/// `Σ_k x_k y_k` over `k < x.len()` for each of the `N` vectors `ys` (each
/// at least as long as `x`), four partial sums per vector (a fixed order,
/// so the same bits on every target) that the compiler keeps in vector
/// registers.
pub fn dots<const N: usize>(x: &[f64], ys: [&[f64]; N]) -> [f64; N] {
    let len = x.len();
    let body = len - len % 4;
    let mut acc = [[0.0f64; 4]; N];
    for k in (0..body).step_by(4) {
        for (a, y) in acc.iter_mut().zip(&ys) {
            for l in 0..4 {
                a[l] += x[k + l] * y[k + l];
            }
        }
    }
    let mut out = [0.0; N];
    for ((o, a), y) in out.iter_mut().zip(&acc).zip(&ys) {
        *o = (a[0] + a[1]) + (a[2] + a[3]);
        for k in body..len {
            *o += x[k] * y[k];
        }
    }
    out
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
