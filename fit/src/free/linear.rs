//! The linear part of the free-amplitude objective in closed form: the
//! core's [`laminar_brdf_core::linear`] (one implementation for the host's f64
//! fits and the device's f32 grid), tested here against brute force.

pub use laminar_brdf_core::linear::{Linear, Moments, Quadratic};

#[cfg(test)]
mod tests {
    use super::*;

    fn moments(d: &[f64], s: &[f64], u: &[f64]) -> Moments {
        let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(a, b)| a * b).sum::<f64>();
        Moments {
            dd: dot(d, d),
            ds: dot(d, s),
            du: dot(d, u),
            ss: dot(s, s),
            su: dot(s, u),
            uu: dot(u, u),
        }
    }

    #[test]
    fn exact_mixes_are_recovered_and_constraints_hold() {
        let s = [1.0, 0.5, 0.2, 0.1];
        let u = [0.2, 0.4, 0.6, 0.3];
        let d: Vec<f64> = s
            .iter()
            .zip(&u)
            .map(|(s, u)| 2.0 * (0.7 * s + 0.3 * u))
            .collect();
        let m = moments(&d, &s, &u);
        let l = m.solve((0.0, 1.0));
        assert!((l.amplitude() - 2.0).abs() < 1e-12 && (l.beta(0.0) - 0.3).abs() < 1e-12);
        assert!(l.sse < 1e-20);
        // A box that excludes 0.3: the nearer ray, β = 0.5.
        let l = m.solve((0.5, 1.0));
        assert_eq!(l.beta(0.0), 0.5);
        // Data the columns cannot reach with c ≥ 0: amplitude 0.
        let neg: Vec<f64> = d.iter().map(|v| -v).collect();
        let l = moments(&neg, &s, &u).solve((0.0, 1.0));
        assert_eq!(l.amplitude(), 0.0);
        // A fixed β is one ray.
        let l = m.solve((0.3, 0.3));
        assert!((l.amplitude() - 2.0).abs() < 1e-12);
    }

    #[test]
    fn four_lanes_solve_bit_for_bit_as_one() {
        use crate::synthetic::Noise;
        use laminar_brdf_core::f64x4;
        // Moments from random columns (some nearly parallel, some data the
        // cone cannot reach), each box: every lane's bits equal the scalar.
        let mut rng = Noise::new(0x2545_f491_4f6c_dd1d);
        let mut next = || rng.uniform();
        for trial in 0..2000 {
            let k = 6;
            let s: Vec<f64> = (0..k).map(|_| next()).collect();
            let tilt = if trial % 3 == 0 { 1e-9 } else { 1.0 };
            let u: Vec<f64> = s.iter().map(|v| v * (1.0 + tilt * next())).collect();
            let sign = if trial % 5 == 0 { -1.0 } else { 1.0 };
            let d: Vec<f64> = (0..k).map(|_| sign * next()).collect();
            let lanes: Vec<Moments> = (0..4).map(|_| moments(&d, &s, &u)).collect();
            let lanes: Vec<Moments> = lanes
                .iter()
                .enumerate()
                .map(|(i, m)| Moments {
                    du: m.du * (1.0 + 0.3 * i as f64),
                    ..*m
                })
                .collect();
            let pick = |f: fn(&Moments) -> f64| f64x4::new([0, 1, 2, 3].map(|i| f(&lanes[i])));
            let packed = Moments {
                dd: pick(|m| m.dd),
                ds: pick(|m| m.ds),
                du: pick(|m| m.du),
                ss: pick(|m| m.ss),
                su: pick(|m| m.su),
                uu: pick(|m| m.uu),
            };
            for beta in [(0.0, 1.0), (0.2, 0.4), (0.5, 0.5)] {
                let got = packed.solve(beta);
                let (p, q, sse) = (got.p.to_array(), got.q.to_array(), got.sse.to_array());
                for (i, m) in lanes.iter().enumerate() {
                    let want = m.solve(beta);
                    assert_eq!(
                        [p[i], q[i], sse[i]].map(f64::to_bits),
                        [want.p, want.q, want.sse].map(f64::to_bits),
                        "trial {trial}, lane {i}, box {beta:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_cone_minimum_is_never_above_a_brute_force_one() {
        let s = [1.0, 0.8, 0.1, 0.05, 0.3];
        let u = [0.1, 0.9, 0.7, 0.4, 0.35];
        let d = [0.4, 1.0, 0.5, 0.1, 0.2];
        let m = moments(&d, &s, &u);
        for (lo, hi) in [(0.0, 1.0), (0.2, 0.4), (0.9, 1.0), (0.0, 0.1)] {
            let l = m.solve((lo, hi));
            let mut best = f64::INFINITY;
            for i in 0..=400 {
                for j in 0..=200 {
                    let beta = lo + (hi - lo) * i as f64 / 400.0;
                    let c = 2.0 * j as f64 / 200.0;
                    best = best.min(m.objective(c * (1.0 - beta), c * beta));
                }
            }
            assert!(l.sse <= best + 1e-12, "{lo} {hi}: {} > {best}", l.sse);
            let beta = l.beta(lo);
            assert!(beta >= lo && beta <= hi && l.amplitude() >= 0.0);
        }
    }
}
