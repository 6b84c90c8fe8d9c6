//! Properties of the model core: SIMD/scalar bit parity, physical invariants,
//! symmetry, Ragheb–Hancock equivalence, hard cases and hand-computed values.

mod common;

use core::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
use laminar_brdf_core::baselines::jensen::{jensen_radiance, JensenCoefficients, JensenGeometry};
use laminar_brdf_core::baselines::oren_nayar::{
    oren_nayar_radiance, OrenNayarCoefficients, OrenNayarGeometry,
};
use laminar_brdf_core::exp::exp;
use laminar_brdf_core::{
    components, energy_budget, fresnel, subsurface_base, total_radiance, Angles, Components,
    Correlation, Geometry, Interface, Lane, Params,
};
use laminar_brdf_core::{f32x8, f64x4, inverse_slope_squared};
use proptest::prelude::*;

fn fields<L: Copy>(c: &Components<L>) -> [L; 7] {
    c.to_array()
}

const NAMES: [&str; 7] = Components::<f32>::NAMES;

/// Asserts lane `i` of a vector equals the scalar, bit for bit.
fn same_bits(v: f32x8, i: usize, s: f32) -> bool {
    v.lane(i).to_bits() == s.to_bits()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn simd_components_equal_scalar_bit_for_bit(
        angles in common::angles8(),
        corr in common::correlation(),
        p in common::params(),
    ) {
        let gv = Geometry::<f32x8>::from_lanes(|i| angles[i]);
        let cv = fields(&components(&gv, corr, &p));
        let tv = total_radiance(&gv, corr, &p);
        for (i, a) in angles.iter().enumerate() {
            let gs = Geometry::<f32>::splat(a);
            let cs = fields(&components(&gs, corr, &p));
            for k in 0..7 {
                prop_assert!(same_bits(cv[k], i, cs[k]), "{} lane {i}: {} vs {}", NAMES[k], cv[k].lane(i), cs[k]);
            }
            prop_assert!(same_bits(tv, i, total_radiance(&gs, corr, &p)));
        }
    }

    #[test]
    fn simd_baselines_and_exp_equal_scalar_bit_for_bit(
        angles in common::angles8(),
        sa in 0.01..=1.0f64, ss in 0.01..=1.0f64,
        sigma in 0.0..=1.0f64, rho in 0.02..=1.0f64,
        xs in proptest::array::uniform8(-120.0f32..=1.0),
    ) {
        let jk = JensenCoefficients::<f32>::new(sa, ss).unwrap();
        let ok = OrenNayarCoefficients::<f32>::new(sigma, rho).unwrap();
        let jv = jensen_radiance(&JensenGeometry::<f32x8>::from_lanes(|i| angles[i]), &jk);
        let ov = oren_nayar_radiance(&OrenNayarGeometry::<f32x8>::from_lanes(|i| angles[i]), &ok);
        let ev = exp(f32x8::new(xs));
        for (i, a) in angles.iter().enumerate() {
            let js = jensen_radiance(&JensenGeometry::<f32>::from_lanes(|_| *a), &jk);
            let os = oren_nayar_radiance(&OrenNayarGeometry::<f32>::from_lanes(|_| *a), &ok);
            prop_assert!(same_bits(jv, i, js), "jensen lane {i}");
            prop_assert!(same_bits(ov, i, os), "oren-nayar lane {i}");
            prop_assert!(same_bits(ev, i, exp(xs[i])), "exp lane {i}");
            prop_assert!(js.is_finite() && js >= 0.0 && os.is_finite());
        }
    }

    /// The f64x4 lanes (the host fits' four measurements at a time) against
    /// scalar f64: the components, the interface and subsurface base at
    /// any n, both baselines and exp.
    #[test]
    fn f64x4_equals_scalar_f64_bit_for_bit(
        angles in common::angles8(),
        corr in common::correlation(),
        p in common::params(),
        n in 1.0f64..=10.0, slope in 1e-3f64..=1e3,
        sa in 0.01..=1.0f64, ss in 0.01..=1.0f64,
        sigma in 0.0..=1.0f64, rho in 0.02..=1.0f64,
        xs in proptest::array::uniform4(-745.0f64..=709.0),
    ) {
        let same = |v: f64x4, i: usize, s: f64| v.lane(i).to_bits() == s.to_bits();
        let gv = Geometry::<f64x4>::from_lanes(|i| angles[i]);
        let cv = fields(&components(&gv, corr, &p));
        let t = inverse_slope_squared(slope);
        let iv = Interface::new(&gv, f64x4::splat(n));
        let bv = subsurface_base(&iv, corr, f64x4::splat(t));
        let jk = JensenCoefficients::<f64>::new(sa, ss).unwrap();
        let ok = OrenNayarCoefficients::<f64>::new(sigma, rho).unwrap();
        let jv = jensen_radiance(&JensenGeometry::<f64x4>::from_lanes(|i| angles[i]), &jk);
        let ov = oren_nayar_radiance(&OrenNayarGeometry::<f64x4>::from_lanes(|i| angles[i]), &ok);
        let ev = exp(f64x4::new(xs));
        for (i, a) in angles.iter().take(4).enumerate() {
            let gs = Geometry::<f64>::splat(a);
            let cs = fields(&components(&gs, corr, &p));
            for k in 0..7 {
                prop_assert!(same(cv[k], i, cs[k]), "{} lane {i}: {} vs {}", NAMES[k], cv[k].lane(i), cs[k]);
            }
            let is = Interface::new(&gs, n);
            for (v, s) in [
                (iv.transmit_in, is.transmit_in),
                (iv.transmit_out, is.transmit_out),
                (iv.fresnel_in, is.fresnel_in),
                (iv.fresnel_out, is.fresnel_out),
                (iv.solid_angle, is.solid_angle),
                (iv.refracted.cos_i, is.refracted.cos_i),
                (iv.refracted.cos_s, is.refracted.cos_s),
                (iv.refracted.ratio, is.refracted.ratio),
            ] {
                prop_assert!(same(v, i, s), "interface lane {i}: {} vs {s}", v.lane(i));
            }
            prop_assert!(same(bv, i, subsurface_base(&is, corr, t)), "base lane {i}");
            let js = jensen_radiance(&JensenGeometry::<f64>::from_lanes(|_| *a), &jk);
            let os = oren_nayar_radiance(&OrenNayarGeometry::<f64>::from_lanes(|_| *a), &ok);
            prop_assert!(same(jv, i, js), "jensen lane {i}");
            prop_assert!(same(ov, i, os), "oren-nayar lane {i}");
            prop_assert!(same(ev, i, exp(xs[i])), "exp lane {i}");
        }
    }

    #[test]
    fn simd_fresnel_and_energy_budget_equal_scalar(
        cos in proptest::array::uniform8(0.0f32..=1.0),
        n in 0.3f32..=3.0, a in 0.0f32..=1.0,
    ) {
        let cv = f32x8::new(cos);
        let fv = fresnel(cv, f32x8::splat(n));
        let bv = energy_budget(cv, f32x8::splat(n.max(1.0)), f32x8::splat(a));
        for (i, &c) in cos.iter().enumerate() {
            prop_assert!(same_bits(fv, i, fresnel(c, n)));
            let bs = energy_budget(c, n.max(1.0), a);
            prop_assert!(same_bits(bv.reflected, i, bs.reflected));
            prop_assert!(same_bits(bv.transmitted, i, bs.transmitted));
            prop_assert!(same_bits(bv.absorbed, i, bs.absorbed));
        }
    }

    #[test]
    fn fresnel_and_absorption_are_physical(
        a in common::angles(), p in common::params(), corr in common::correlation(),
    ) {
        for c in [fields(&components(&Geometry::<f64>::splat(&a), corr, &p)).map(|v| v as f32),
                  fields(&components(&Geometry::<f32>::splat(&a), corr, &p))] {
            for v in c {
                prop_assert!(v.is_finite() && v >= 0.0, "{c:?}");
            }
            prop_assert!(c[0] <= 1.0 && c[1] <= 1.0);
            prop_assert!(c[2] <= 1.0 - c[0] + 1e-7 && c[3] <= 1.0 - c[1] + 1e-7);
        }
    }

    #[test]
    fn reflected_transmitted_absorbed_sum_to_one(
        theta in 0.0..=FRAC_PI_2, n in 1.0..=3.0f64, a in 0.0..=1.0f64,
    ) {
        let b = energy_budget(libm::cos(theta), n, a);
        prop_assert!((b.reflected + b.transmitted + b.absorbed - 1.0).abs() <= 4.0 * f64::EPSILON);
        prop_assert!(b.absorbed <= 1.0 - b.reflected);
        let b = energy_budget(libm::cos(theta) as f32, n as f32, a as f32);
        prop_assert!((b.reflected + b.transmitted + b.absorbed - 1.0).abs() <= 4.0 * f32::EPSILON);
    }

    #[test]
    fn zero_absorption_is_ragheb_hancock_bit_for_bit(
        a in common::angles(), p in common::params(), corr in common::correlation(),
    ) {
        let p0 = Params::new(p.slope(), p.beta(), p.n(), 0.0).unwrap();
        let g = Geometry::<f32>::splat(&a);
        let rh = subsurface_base(&Interface::new(&g, p.n() as f32), corr, inverse_slope_squared(p.slope() as f32));
        let c = components(&g, corr, &p0);
        prop_assert_eq!(c.subsurface.to_bits(), rh.to_bits());
        prop_assert_eq!(total_radiance(&g, corr, &p0).to_bits(), c.total.to_bits());
        prop_assert_eq!(c.absorb_in, 0.0);
        prop_assert_eq!(c.absorb_out, 0.0);
    }

    #[test]
    fn skipping_zero_weight_terms_changes_no_bits(
        a in common::angles(), p in common::params(), corr in common::correlation(),
        beta in prop_oneof![Just(0.0), Just(1.0)],
    ) {
        let p = Params::new(p.slope(), beta, p.n(), p.a()).unwrap();
        let gv = Geometry::<f32x8>::splat(&a);
        prop_assert_eq!(total_radiance(&gv, corr, &p).lane(0).to_bits(), components(&gv, corr, &p).total.lane(0).to_bits());
        let g = Geometry::<f64>::splat(&a);
        prop_assert_eq!(total_radiance(&g, corr, &p).to_bits(), components(&g, corr, &p).total.to_bits());
    }

    #[test]
    fn mirrored_azimuth_gives_identical_radiance(
        a in common::angles(), p in common::params(), corr in common::correlation(),
    ) {
        let c = fields(&components(&Geometry::<f32>::splat(&a), corr, &p));
        let m = fields(&components(&Geometry::<f32>::splat(&a.mirrored()), corr, &p));
        for k in 0..7 {
            prop_assert_eq!(c[k].to_bits(), m[k].to_bits(), "{}", NAMES[k]);
        }
    }

    #[test]
    fn fresnel_from_air_is_monotone_in_theta(
        t1 in 0.0..=FRAC_PI_2, t2 in 0.0..=FRAC_PI_2, n in 1.0..=3.0f64,
    ) {
        let (lo, hi) = if t1 <= t2 { (t1, t2) } else { (t2, t1) };
        prop_assert!(fresnel(libm::cos(lo), n) <= fresnel(libm::cos(hi), n) + 2.0 * f64::EPSILON);
        let (fl, fh) = (fresnel(libm::cos(lo) as f32, n as f32), fresnel(libm::cos(hi) as f32, n as f32));
        prop_assert!(fl <= fh + 2.0 * f32::EPSILON);
    }
}

#[test]
fn fresnel_fixed_cases() {
    assert!((fresnel(1.0f64, 1.5) - 0.04).abs() < 1e-17);
    for n in [1.1f64, 1.33, 1.5, 1.7, 2.0, 2.42] {
        let want = ((n - 1.0) / (n + 1.0)).powi(2);
        assert!(
            (fresnel(1.0f64, n) - want).abs() <= f64::EPSILON * want,
            "n = {n}"
        );
    }
    assert_eq!(fresnel(0.0f64, 1.5), 1.0);
    assert_eq!(fresnel(0.0f32, 1.5), 1.0);
    assert_eq!(fresnel(libm::cos(FRAC_PI_4), 1.0 / 1.5), 1.0);
    assert_eq!(fresnel(libm::cosf(FRAC_PI_4 as f32), 1.0f32 / 1.5), 1.0);
    for c in [0.0f64, 0.1, 0.5, 0.99, 1.0] {
        assert_eq!(fresnel(c, 1.0), 0.0);
        assert_eq!(fresnel(c as f32, 1.0), 0.0);
    }
}

/// Values computed independently (Python, float64, the formulas of
/// docs/conventions.md §2–3 written with asin/sin/cos, not from this crate).
#[test]
fn hand_computed_radiance() {
    type Case = ((f64, f64, f64), (f64, f64, f64, f64), Correlation, [f64; 7]);
    let cases: [Case; 3] = [
        (
            (0.3, 0.9, 2.1),
            (0.5, 0.4, 1.45, 0.3),
            Correlation::Gaussian,
            [
                0.03386603754258827,
                0.053402267284524386,
                0.26452780956709854,
                0.10972931175161887,
                0.26380918838736594,
                0.07039193768857523,
                0.18644228810784966,
            ],
        ),
        (
            (1.1, 0.2, -0.7),
            (1.3, 0.7, 1.36, 0.0),
            Correlation::Exponential,
            [
                0.08013262243303534,
                0.023289030204543322,
                0.0,
                0.0,
                0.17617362685682844,
                0.0664089973254783,
                0.09933838618488333,
            ],
        ),
        (
            (0.0, 1e-6, 0.0),
            (0.12, 0.01, 1.3, 1.0),
            Correlation::Gaussian,
            [
                0.0170132325141777,
                0.01701323251417771,
                0.9829867674858223,
                0.9829867674848392,
                0.24999999999903993,
                0.0,
                0.24749999999904954,
            ],
        ),
    ];
    for ((ti, ts, ps), (s, b, n, a), corr, want) in cases {
        let g = Geometry::<f64>::splat(&Angles::new(ti, ts, ps).unwrap());
        let got = fields(&components(&g, corr, &Params::new(s, b, n, a).unwrap()));
        for k in 0..7 {
            let tol = 1e-13 * want[k].abs().max(1e-3);
            assert!(
                (got[k] - want[k]).abs() <= tol,
                "{}: {} vs {}",
                NAMES[k],
                got[k],
                want[k]
            );
        }
    }
}

/// Every hard case of docs/conventions.md §9 gives finite, non-negative values on
/// every path.
#[test]
fn hard_cases_are_finite() {
    let thetas = [0.0, 1e-6, 0.5, FRAC_PI_2 - 1e-6, FRAC_PI_2];
    let phis = [0.0, PI, -PI, 1e-9, PI - 1e-9, 3.0 * PI];
    let params = [
        Params::new(0.12, 0.5, 1.3, 0.0).unwrap(),
        Params::new(1e-3, 0.5, 1.5, 0.5).unwrap(),
        Params::new(1e3, 0.5, 1.5, 0.5).unwrap(),
        Params::new(0.5, 0.5, 1.0, 0.5).unwrap(),
        Params::new(0.5, 1.0, 1.5, 1.0).unwrap(),
        Params::new(0.5, 0.0, 10.0, 1.0).unwrap(),
    ];
    let jk = JensenCoefficients::<f32>::new(0.01, 1.0).unwrap();
    let ok = OrenNayarCoefficients::<f32>::new(1.0, 1.0).unwrap();
    for &ti in &thetas {
        for &ts in &thetas {
            for &ps in &phis {
                let a = Angles::new(ti, ts, ps).unwrap();
                for corr in [Correlation::Gaussian, Correlation::Exponential] {
                    for p in &params {
                        let c64 = fields(&components(&Geometry::<f64>::splat(&a), corr, p));
                        let c32 = fields(&components(&Geometry::<f32>::splat(&a), corr, p));
                        for k in 0..7 {
                            assert!(
                                c64[k].is_finite() && c64[k] >= 0.0,
                                "{} f64 {a:?} {p:?}: {}",
                                NAMES[k],
                                c64[k]
                            );
                            assert!(
                                c32[k].is_finite() && c32[k] >= 0.0,
                                "{} f32 {a:?} {p:?}: {}",
                                NAMES[k],
                                c32[k]
                            );
                        }
                    }
                }
                let j = jensen_radiance(&JensenGeometry::<f32>::from_lanes(|_| a), &jk);
                let o = oren_nayar_radiance(&OrenNayarGeometry::<f32>::from_lanes(|_| a), &ok);
                assert!(
                    j.is_finite() && o.is_finite(),
                    "{a:?}: jensen {j}, oren-nayar {o}"
                );
            }
        }
    }
    // a = 1 at normal incidence: the transmission, and so the subsurface term, is exactly 0.
    let g = Geometry::<f32>::splat(&Angles::new(0.0, 0.0, 0.0).unwrap());
    let c = components(
        &g,
        Correlation::Gaussian,
        &Params::new(0.5, 1.0, 1.5, 1.0).unwrap(),
    );
    assert_eq!(c.subsurface, 0.0);
    // Very small slope away from the mirror: the Gaussian factor underflows to exactly 0.
    let g = Geometry::<f32>::splat(&Angles::new(0.2, 1.0, 2.0).unwrap());
    assert_eq!(
        components(
            &g,
            Correlation::Gaussian,
            &Params::new(1e-3, 0.0, 1.3, 0.0).unwrap()
        )
        .surface,
        0.0
    );
}
