//! The AVX2 lanes of `simd::run` against the scalar `f64` path and the
//! portable `wide::f64x4` lanes, bit for bit: the model's components, the
//! interface and subsurface base, both baselines, `exp`, and the lane
//! operations on every special pair (±0, NaN, ±∞).
//!
//! On a processor without AVX2 `Path::Avx2` runs the portable lanes; the
//! test then says so (CI's machines have AVX2, and `LAMINAR_REQUIRE_AVX2=1`
//! makes its absence a failure).

mod common;

use laminar_brdf_core::baselines::jensen::{jensen_radiance, JensenCoefficients, JensenGeometry};
use laminar_brdf_core::baselines::oren_nayar::{
    oren_nayar_radiance, OrenNayarCoefficients, OrenNayarGeometry,
};
use laminar_brdf_core::exp::exp;
use laminar_brdf_core::simd::{self, Kernel, Lane4, Path};
use laminar_brdf_core::{
    components, subsurface_base, Angles, Correlation, Geometry, Interface, Lane, Params,
};
use proptest::prelude::*;

/// Everything the property compares, for the geometries of `L`'s lanes.
struct Everything<'a> {
    angles: &'a [Angles; 4],
    corr: Correlation,
    p: &'a Params,
    n: f64,
    t: f64,
    jensen: &'a JensenCoefficients<f64>,
    oren_nayar: &'a OrenNayarCoefficients<f64>,
    xs: [f64; 4],
}

/// One row per quantity, one value per lane.
type Rows = Vec<(&'static str, Vec<f64>)>;

impl Everything<'_> {
    /// Every quantity in `L`'s lanes (lane `i` from `angles[i]`, `xs[i]`).
    fn rows<L: Lane<Scalar = f64>>(&self) -> Rows {
        let angles = self.angles;
        let lanes = |v: L| (0..L::LANES).map(|i| v.lane(i)).collect::<Vec<f64>>();
        let g = Geometry::<L>::from_lanes(|i| angles[i]);
        let c = components(&g, self.corr, self.p);
        let mut rows: Rows = laminar_brdf_core::Components::<f64>::NAMES
            .iter()
            .zip(c.to_array())
            .map(|(name, v)| (*name, lanes(v)))
            .collect();
        let i = Interface::new(&g, L::splat(self.n));
        let base = subsurface_base(&i, self.corr, L::splat(self.t));
        let j = jensen_radiance(&JensenGeometry::<L>::from_lanes(|i| angles[i]), self.jensen);
        let o = oren_nayar_radiance(
            &OrenNayarGeometry::<L>::from_lanes(|i| angles[i]),
            self.oren_nayar,
        );
        let xs = self.xs;
        let e = exp(L::from_f64_lanes(|i| xs[i]));
        for (name, v) in [
            ("transmit_in", i.transmit_in),
            ("transmit_out", i.transmit_out),
            ("fresnel_in", i.fresnel_in),
            ("fresnel_out", i.fresnel_out),
            ("solid_angle", i.solid_angle),
            ("refracted cos_i", i.refracted.cos_i),
            ("refracted ratio", i.refracted.ratio),
            ("base", base),
            ("jensen", j),
            ("oren-nayar", o),
            ("exp", e),
        ] {
            rows.push((name, lanes(v)));
        }
        rows
    }
}

impl Kernel for Everything<'_> {
    type Output = Rows;

    fn run<L: Lane4>(self) -> Rows {
        self.rows::<L>()
    }
}

/// Whether this processor runs `Path::Avx2` (else the test says it is
/// skipped, or fails under `LAMINAR_REQUIRE_AVX2=1`).
fn avx2_here() -> bool {
    let here = simd::avx2_available();
    if !here {
        assert!(
            std::env::var_os("LAMINAR_REQUIRE_AVX2").is_none(),
            "LAMINAR_REQUIRE_AVX2 is set, but this processor has no AVX2"
        );
        eprintln!("SKIPPED: this processor has no AVX2 (Path::Avx2 runs the portable lanes)");
    }
    here
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn avx2_lanes_equal_scalar_and_portable_bit_for_bit(
        angles in proptest::array::uniform4(common::angles()),
        corr in common::correlation(),
        p in common::params(),
        n in 1.0f64..=10.0, slope in 1e-3f64..=1e3,
        sa in 0.01..=1.0f64, ss in 0.01..=1.0f64,
        sigma in 0.0..=1.0f64, rho in 0.02..=1.0f64,
        xs in proptest::array::uniform4(-745.0f64..=709.0),
    ) {
        if !avx2_here() {
            return Ok(());
        }
        let jensen = JensenCoefficients::<f64>::new(sa, ss).unwrap();
        let oren_nayar = OrenNayarCoefficients::<f64>::new(sigma, rho).unwrap();
        let t = laminar_brdf_core::inverse_slope_squared(slope);
        let kernel = || Everything {
            angles: &angles, corr, p: &p, n, t,
            jensen: &jensen, oren_nayar: &oren_nayar, xs,
        };
        let avx2 = simd::run(Path::Avx2, kernel());
        let portable = simd::run(Path::Portable, kernel());
        // The scalar path, lane by lane.
        let scalar: Vec<Rows> = (0..4)
            .map(|i| {
                let one = [angles[i]; 4];
                Everything { angles: &one, xs: [xs[i]; 4], ..kernel() }.rows::<f64>()
            })
            .collect();
        for (k, ((name, v), (_, w))) in avx2.iter().zip(&portable).enumerate() {
            for i in 0..4 {
                let s = scalar[i][k].1[0];
                prop_assert_eq!(v[i].to_bits(), s.to_bits(), "{} lane {}: avx2 {} scalar {}", name, i, v[i], s);
                prop_assert_eq!(w[i].to_bits(), s.to_bits(), "{} lane {}: portable {} scalar {}", name, i, w[i], s);
            }
        }
    }
}

/// The lane operations on every special pair: comparisons, selects,
/// min/max and the four arithmetic operations, on ±0, NaN, ±∞, the
/// smallest normal and subnormal numbers.
#[test]
fn special_values_give_the_scalar_bits() {
    if !avx2_here() {
        return;
    }
    struct Pairs;
    impl Kernel for Pairs {
        type Output = Vec<[u64; 8]>;
        fn run<L: Lane4>(self) -> Vec<[u64; 8]> {
            let specials = specials();
            let mut out = Vec::new();
            for &x in &specials {
                for &y in &specials {
                    let (vx, vy) = (L::splat(x), L::splat(y));
                    let pick = |m| L::select(m, L::c(1.0), L::c(2.0)).lane(1);
                    out.push(
                        [
                            Lane::max(vx, vy).lane(0),
                            Lane::min(vx, vy).lane(3),
                            (vx + vy).lane(2),
                            (vx - vy).lane(1),
                            (vx * vy).lane(0),
                            (vx / vy).lane(3),
                            pick(vx.lt(vy)) + 4.0 * pick(vx.le(vy)) + 16.0 * pick(vx.eq(vy)),
                            vx.sqrt().lane(2),
                        ]
                        .map(f64::to_bits),
                    );
                }
            }
            out
        }
    }
    let avx2 = simd::run(Path::Avx2, Pairs);
    let portable = simd::run(Path::Portable, Pairs);
    assert_eq!(avx2.len(), portable.len());
    let specials = specials();
    for (k, row) in avx2.iter().enumerate() {
        let (x, y) = (specials[k / specials.len()], specials[k % specials.len()]);
        let pick = |m: bool| if m { 1.0 } else { 2.0 };
        let scalar = [
            Lane::max(x, y),
            Lane::min(x, y),
            x + y,
            x - y,
            x * y,
            x / y,
            pick(x < y) + 4.0 * pick(x <= y) + 16.0 * pick(x == y),
            Lane::sqrt(x),
        ]
        .map(f64::to_bits);
        // A NaN's sign and payload are not IEEE 754's to fix: the compiler
        // folds 0/0 to a positive NaN where the processor makes a negative
        // one, and may swap an addition's operands, so which NaN of two
        // propagates varies. Any NaN matches any NaN; all else to the bit.
        let same =
            |a: u64, b: u64| a == b || (f64::from_bits(a).is_nan() && f64::from_bits(b).is_nan());
        for (i, ((&got, &want), &wide)) in row.iter().zip(&scalar).zip(&portable[k]).enumerate() {
            assert!(
                same(got, wide),
                "({x}, {y}) operation {i}: avx2 {:e}, wide {:e}",
                f64::from_bits(got),
                f64::from_bits(wide)
            );
            assert!(
                same(got, want),
                "({x}, {y}) operation {i}: {:e} against {:e}",
                f64::from_bits(got),
                f64::from_bits(want)
            );
        }
    }
}

/// `exp` across its whole range and past both ends, and `pow2i` at every
/// exponent the range reaches.
#[test]
fn exp_and_its_scaling_give_the_scalar_bits_everywhere() {
    if !avx2_here() {
        return;
    }
    struct Exp(Vec<f64>);
    impl Kernel for Exp {
        type Output = Vec<f64>;
        fn run<L: Lane4>(self) -> Vec<f64> {
            self.0
                .chunks_exact(4)
                .flat_map(|x| exp(L::from_array([x[0], x[1], x[2], x[3]])).to_array())
                .collect()
        }
    }
    let xs: Vec<f64> = (0..40_000)
        .map(|i| -760.0 + 1480.0 * i as f64 / 40_000.0)
        .chain([f64::NEG_INFINITY, f64::INFINITY, f64::NAN, -0.0])
        .collect();
    let avx2 = simd::run(Path::Avx2, Exp(xs.clone()));
    for (k, x) in xs.iter().enumerate() {
        let got = avx2[k];
        let want = exp(*x);
        // exp(NaN) is a NaN; which one is not specified (see above).
        assert!(
            got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
            "exp({x}): {got:e} against {want:e}"
        );
    }
    struct Pow2(Vec<f64>);
    impl Kernel for Pow2 {
        type Output = Vec<f64>;
        fn run<L: Lane4>(self) -> Vec<f64> {
            self.0
                .chunks_exact(4)
                .flat_map(|n| L::pow2i(L::from_array([n[0], n[1], n[2], n[3]])).to_array())
                .collect()
        }
    }
    let ns: Vec<f64> = (-1022..=1023).map(f64::from).chain([0.0, 0.0]).collect();
    let got = simd::run(Path::Avx2, Pow2(ns.clone()));
    for (n, v) in ns.iter().zip(got) {
        assert_eq!(v, libm::ldexp(1.0, *n as i32), "2^{n}");
    }
}

fn specials() -> Vec<f64> {
    vec![
        0.0,
        -0.0,
        1.0,
        -1.0,
        f64::NAN,
        -f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::MIN_POSITIVE,
        5e-324,
        3.5,
    ]
}
