//! Inner products in a fixed order: four partial sums per product, the
//! lanes of an `f64x4` (a single running sum is a chain of dependent
//! additions, which no compiler may reorder into vector code), combined the
//! same way on every target so that every fit gives the same bits
//! everywhere.

use crate::simd;
use laminar_brdf_core::simd::{Kernel, Lane4};

/// `Σ_k x_k y_k` over `k < x.len()` for each of the `N` vectors `ys` (each
/// at least as long as `x`), four partial sums per vector, one per lane of
/// an `f64x4` (a fixed order, so the same bits on every target).
pub fn dots<const N: usize>(x: &[f64], ys: [&[f64]; N]) -> [f64; N] {
    simd::run(Dots { x, ys })
}

/// The pass of [`dots`].
struct Dots<'a, const N: usize> {
    x: &'a [f64],
    ys: [&'a [f64]; N],
}

impl<const N: usize> Kernel for Dots<'_, N> {
    type Output = [f64; N];

    #[inline(always)]
    fn run<L: Lane4>(self) -> [f64; N] {
        let Self { x, ys } = self;
        let len = x.len();
        let (xs, x_tail) = x.as_chunks::<4>();
        let ys = ys.map(|y| &y[..len]);
        let fours = ys.map(|y| y.as_chunks::<4>().0);
        let mut acc = [L::zero(); N];
        for (k, &xk) in xs.iter().enumerate() {
            let xk = L::from_array(xk);
            for (a, y) in acc.iter_mut().zip(&fours) {
                *a += xk * L::from_array(y[k]);
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
}

/// [`dots`] of each of `R` vectors `xs` (of one length) against the same
/// `ys`: `out[r] = dots(xs[r], ys)`, bit for bit (each sum's partial sums
/// and order are [`dots`]'), `R` of them in one pass so that each `y` is
/// loaded once for all (the untied grid stage's cross sums of every σ/T's
/// surface term against a column).
pub fn dots_many<const R: usize, const N: usize>(
    xs: [&[f64]; R],
    ys: [&[f64]; N],
) -> [[f64; N]; R] {
    simd::run(DotsMany { xs, ys })
}

/// The pass of [`dots_many`].
struct DotsMany<'a, const R: usize, const N: usize> {
    xs: [&'a [f64]; R],
    ys: [&'a [f64]; N],
}

impl<const R: usize, const N: usize> Kernel for DotsMany<'_, R, N> {
    type Output = [[f64; N]; R];

    #[inline(always)]
    fn run<L: Lane4>(self) -> [[f64; N]; R] {
        let Self { xs, ys } = self;
        let len = xs[0].len();
        let xs = xs.map(|x| &x[..len]);
        let fours_x = xs.map(|x| x.as_chunks::<4>().0);
        let ys = ys.map(|y| &y[..len]);
        let fours_y = ys.map(|y| y.as_chunks::<4>().0);
        let mut acc = [[L::zero(); N]; R];
        for k in 0..fours_x[0].len() {
            let xk = fours_x.map(|x| L::from_array(x[k]));
            for (j, y) in fours_y.iter().enumerate() {
                let yk = L::from_array(y[k]);
                for (acc, &x) in acc.iter_mut().zip(&xk) {
                    acc[j] += x * yk;
                }
            }
        }
        let body = len - len % 4;
        let mut out = [[0.0; N]; R];
        for ((out, acc), x) in out.iter_mut().zip(&acc).zip(&xs) {
            for ((o, a), y) in out.iter_mut().zip(acc).zip(&ys) {
                *o = total(*a);
                for (xk, yk) in x[body..].iter().zip(&y[body..]) {
                    *o += xk * yk;
                }
            }
        }
        out
    }
}

/// The four partial sums of a lane accumulator added in the fixed order
/// of [`dots`].
#[inline(always)]
pub fn total<L: Lane4>(a: L) -> f64 {
    let a = a.to_array();
    (a[0] + a[1]) + (a[2] + a[3])
}

/// The weighted Gram matrix `G_ab = Σ_k w_k x_ak x_bk` of `vectors` (each
/// at least as long as `w`), row-major `n × n`: each entry's four partial
/// sums in the fixed order of [`dots`], `(w_k x_ak) x_bk` per term, and the
/// lower triangle the upper's mirror. Up to eight vectors (the layered
/// models' Jacobians) unrolled; more the same sums, bit for bit, in a loop.
pub fn gram(w: &[f64], vectors: &[&[f64]]) -> Vec<f64> {
    simd::run(Gram { w, vectors })
}

/// The pass of [`gram`].
struct Gram<'a> {
    w: &'a [f64],
    vectors: &'a [&'a [f64]],
}

impl Kernel for Gram<'_> {
    type Output = Vec<f64>;

    #[inline(always)]
    fn run<L: Lane4>(self) -> Vec<f64> {
        let Self { w, vectors } = self;
        match vectors.len() {
            0 => Vec::new(),
            1 => gram_of::<L, 1>(w, vectors),
            2 => gram_of::<L, 2>(w, vectors),
            3 => gram_of::<L, 3>(w, vectors),
            4 => gram_of::<L, 4>(w, vectors),
            5 => gram_of::<L, 5>(w, vectors),
            6 => gram_of::<L, 6>(w, vectors),
            7 => gram_of::<L, 7>(w, vectors),
            8 => gram_of::<L, 8>(w, vectors),
            _ => gram_any::<L>(w, vectors),
        }
    }
}

/// [`gram`] of any number of vectors: the same sums as [`gram_of`], in
/// the same order, with the accumulators on the heap.
#[inline(always)]
fn gram_any<L: Lane4>(w: &[f64], vectors: &[&[f64]]) -> Vec<f64> {
    let (len, n) = (w.len(), vectors.len());
    let (ws, w_tail) = w.as_chunks::<4>();
    let body = len - w_tail.len();
    let fours: Vec<&[[f64; 4]]> = vectors
        .iter()
        .map(|v| v[..len].as_chunks::<4>().0)
        .collect();
    let mut acc = vec![[0.0; 4]; n * n];
    let mut here = vec![L::zero(); n];
    for (k, &wk) in ws.iter().enumerate() {
        let wk = L::from_array(wk);
        for (h, four) in here.iter_mut().zip(&fours) {
            *h = L::from_array(four[k]);
        }
        for a in 0..n {
            let wxa = wk * here[a];
            for b in a..n {
                let sum = L::from_array(acc[a * n + b]) + wxa * here[b];
                acc[a * n + b] = sum.to_array();
            }
        }
    }
    let mut out = vec![0.0; n * n];
    for a in 0..n {
        for b in a..n {
            let mut sum = total(L::from_array(acc[a * n + b]));
            for k in body..len {
                sum += w[k] * vectors[a][k] * vectors[b][k];
            }
            out[a * n + b] = sum;
            out[b * n + a] = sum;
        }
    }
    out
}

/// [`gram`] of exactly `N` vectors (so that the products unroll).
#[inline(always)]
fn gram_of<L: Lane4, const N: usize>(w: &[f64], vectors: &[&[f64]]) -> Vec<f64> {
    let len = w.len();
    let (ws, w_tail) = w.as_chunks::<4>();
    let body = len - w_tail.len();
    let fours: [&[[f64; 4]]; N] = std::array::from_fn(|a| vectors[a][..len].as_chunks::<4>().0);
    let mut acc = [[L::zero(); N]; N];
    for (k, &wk) in ws.iter().enumerate() {
        let wk = L::from_array(wk);
        let mut here = [L::zero(); N];
        for (h, four) in here.iter_mut().zip(&fours) {
            *h = L::from_array(four[k]);
        }
        for a in 0..N {
            let wxa = wk * here[a];
            for b in a..N {
                acc[a][b] += wxa * here[b];
            }
        }
    }
    let mut out = vec![0.0; N * N];
    for a in 0..N {
        for b in a..N {
            let mut sum = total(acc[a][b]);
            for k in body..len {
                sum += w[k] * vectors[a][k] * vectors[b][k];
            }
            out[a * N + b] = sum;
            out[b * N + a] = sum;
        }
    }
    out
}

/// `Σ_k x_k y_k` ([`dots`] of one vector).
#[cfg(test)]
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

    /// Many vectors in one pass are each one [`dots`], bit for bit, on
    /// values whose sums round (so the order shows).
    #[test]
    fn many_dots_are_each_ones_bits() {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.3
        };
        for len in [0, 1, 3, 4, 5, 8, 11, 1439] {
            let mut vector = || -> Vec<f64> { (0..len).map(|_| next()).collect() };
            let xs: [Vec<f64>; 4] = std::array::from_fn(|_| vector());
            let ys: [Vec<f64>; 3] = std::array::from_fn(|_| vector());
            let ys = [&ys[0][..], &ys[1], &ys[2]];
            let many = dots_many([&xs[0][..], &xs[1], &xs[2], &xs[3]], ys);
            for (x, got) in xs.iter().zip(many) {
                assert_eq!(
                    got.map(f64::to_bits),
                    dots(x, ys).map(f64::to_bits),
                    "{len}"
                );
            }
        }
    }

    #[test]
    fn the_gram_matrix_holds_every_weighted_product() {
        // Small integers and halves again: every sum is exact.
        for len in [0, 1, 3, 4, 5, 8, 11] {
            let w: Vec<f64> = (0..len).map(|i| (i % 3) as f64 + 0.5).collect();
            let x: Vec<f64> = (0..len).map(|i| 1.0 + i as f64).collect();
            let y: Vec<f64> = (0..len).map(|i| 0.5 * i as f64 - 1.0).collect();
            let z: Vec<f64> = (0..len).map(|i| 3.0 - i as f64).collect();
            let vectors = [&x[..], &y, &z];
            let g = gram(&w, &vectors);
            for (a, va) in vectors.iter().enumerate() {
                for (b, vb) in vectors.iter().enumerate() {
                    let want: f64 = (0..len).map(|k| w[k] * va[k] * vb[k]).sum();
                    assert_eq!(g[a * 3 + b], want, "{len} ({a}, {b})");
                }
            }
        }
    }

    /// More than eight vectors (an untied or joint model's Jacobian) take
    /// the loop: bit for bit the unrolled sums, on values whose sums round.
    /// [`gram_any`] at any `n` (the loop the pass takes above eight).
    struct GramAny<'a>(&'a [f64], &'a [&'a [f64]]);

    impl Kernel for GramAny<'_> {
        type Output = Vec<f64>;
        fn run<L: Lane4>(self) -> Vec<f64> {
            gram_any::<L>(self.0, self.1)
        }
    }

    #[test]
    fn any_number_of_vectors_gives_the_unrolled_bits() {
        let mut rng = crate::synthetic::Noise::new(5);
        for len in [0, 3, 4, 13, 101] {
            let w: Vec<f64> = (0..len).map(|_| rng.uniform()).collect();
            let vectors: Vec<Vec<f64>> = (0..8)
                .map(|_| (0..len).map(|_| rng.uniform() - 0.3).collect())
                .collect();
            let refs: Vec<&[f64]> = vectors.iter().map(|v| &v[..]).collect();
            for n in 1..=8 {
                let unrolled = gram(&w, &refs[..n]);
                let looped = laminar_brdf_core::simd::run_portable(GramAny(&w, &refs[..n]));
                assert_eq!(
                    unrolled.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                    looped.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                    "{len} measurements, {n} vectors"
                );
            }
            let mut more = refs.clone();
            more.extend_from_slice(&refs[..3]);
            let g = gram(&w, &more);
            assert_eq!(g.len(), 121);
            assert_eq!(g[10 * 11 + 2].to_bits(), g[2 * 11 + 2].to_bits());
        }
    }
}
