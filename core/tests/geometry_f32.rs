//! Error budget of the `f32` geometry constructors
//! ([`Geometry::from_angles_f32`], [`Geometry::from_directions`]) against
//! the `f64` one, per field and for the total radiance they lead to, in
//! `f32` ulps relative to the `f64` value (docs/conventions.md §2).

use laminar_brdf_core::{total_radiance, Angles, Correlation, Directions, Geometry, Params};

/// Relative distance of `got` from `want` in `f32` ulps at `want`.
fn ulps(got: f32, want: f64) -> f64 {
    if got as f64 == want {
        return 0.0;
    }
    let w = (want as f32).abs();
    let ulp = if w < f32::MIN_POSITIVE {
        f32::from_bits(1) as f64
    } else {
        (f32::from_bits(w.to_bits() + 1) - w) as f64
    };
    (got as f64 - want).abs() / ulp
}

/// Seeded angles over the whole domain, and the hard cases of
/// docs/conventions.md §9 (normal, grazing, mirror, φs = ±π, near-mirror).
fn cases() -> Vec<(f32, f32, f32)> {
    let mut out = vec![
        (0.0, 0.0, 0.0),
        (1.570_796_2, 1.570_796_2, 0.0),
        (0.7, 0.7, 0.0),
        (0.7, 0.7, 3.141_592_5),
        (0.7, 0.700_001, 1e-5),
        (1e-6, 1.4, -3.0),
        (1.2, 0.3, -3.141_592_5),
    ];
    let mut seed = 0x2545_F491_4F6C_DD1Du64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 40) as f32 / (1u64 << 24) as f32
    };
    for i in 0..200_000 {
        let ti = 1.570_796_2 * next();
        // Every fourth case near the mirror direction, where v_xy² → 0.
        let (ts, ps) = if i % 4 == 0 {
            (ti + 1e-3 * (next() - 0.5), 1e-2 * (next() - 0.5))
        } else {
            (1.570_796_2 * next(), 3.141_592_5 * (2.0 * next() - 1.0))
        };
        out.push((ti, ts.clamp(0.0, 1.570_796_2), ps));
    }
    out
}

/// The largest error of each field: cos θi, cos θs, sin²θi, sin²θs, v_xy²,
/// lead, ratio.
fn field_errors(fast: &Geometry<f32>, want: &Geometry<f64>, max: &mut [f64; 7]) {
    let pairs = [
        (fast.cos_i, want.cos_i),
        (fast.cos_s, want.cos_s),
        (fast.sin2_i, want.sin2_i),
        (fast.sin2_s, want.sin2_s),
        (fast.vxy2, want.vxy2),
        (fast.lead, want.lead),
        (fast.ratio, want.ratio),
    ];
    for (m, (got, want)) in max.iter_mut().zip(pairs) {
        *m = m.max(ulps(got, want));
    }
}

const FIELDS: [&str; 7] = [
    "cos_i", "cos_s", "sin2_i", "sin2_s", "vxy2", "lead", "ratio",
];

#[test]
fn f32_geometry_is_within_its_budget() {
    let params = [
        Params::new(0.5, 0.4, 1.45, 0.2).unwrap(),
        Params::new(0.12, 0.9, 1.3, 0.9).unwrap(),
        Params::new(4.04, 0.1, 1.5, 0.0).unwrap(),
    ];
    let (mut angles_max, mut directions_max) = ([0.0f64; 7], [0.0f64; 7]);
    let (mut total_angles, mut total_directions) = (0.0f64, 0.0f64);
    for (ti, ts, ps) in cases() {
        let a = Angles::new(ti as f64, ts as f64, ps as f64).unwrap();
        let want = Geometry::<f64>::splat(&a);
        let fast = Geometry::<f32>::from_angles_f32(ti, ts, ps).unwrap();
        field_errors(&fast, &want, &mut angles_max);
        // A sensor's directions: the sines and cosines correctly rounded.
        let (si, ci) = (libm::sin(ti as f64), libm::cos(ti as f64));
        let (ss, cs) = (libm::sin(ts as f64), libm::cos(ts as f64));
        let (sp, cp) = (libm::sin(ps as f64), libm::cos(ps as f64));
        let d = Directions {
            cos_i: ci as f32,
            sin_i: si as f32,
            cos_s: cs as f32,
            sin_s: ss as f32,
            cos_phi: cp as f32,
            sin_phi: sp as f32,
        };
        let sensed = Geometry::<f32>::from_directions(&d).unwrap();
        // Against the exact geometry of those rounded directions' angles is
        // not defined; against the angles' geometry, away from the mirror
        // direction (where rounded sines cannot give v_xy² relatively).
        let near_mirror = want.vxy2 < 1e-6;
        if !near_mirror {
            field_errors(&sensed, &want, &mut directions_max);
        }
        for p in &params {
            for corr in [Correlation::Gaussian, Correlation::Exponential] {
                // The f32 path at the f32 parameters, so the budget is the
                // geometry's share plus the f32 evaluation's own.
                let p32 = Params::new(
                    p.slope() as f32 as f64,
                    p.beta() as f32 as f64,
                    p.n() as f32 as f64,
                    p.a() as f32 as f64,
                )
                .unwrap();
                let exact = total_radiance(&want, corr, &p32);
                // Gaussian tail: condition number x/4 (crate docs, Accuracy).
                let x = want.ratio / (p32.slope() * p32.slope());
                if corr == Correlation::Gaussian && x > 8.0 {
                    continue;
                }
                total_angles = total_angles.max(ulps(total_radiance(&fast, corr, p), exact));
                if !near_mirror {
                    total_directions =
                        total_directions.max(ulps(total_radiance(&sensed, corr, p), exact));
                }
            }
        }
    }
    println!("f32 geometry from angles, max ulps per field:");
    for (name, (a, d)) in FIELDS.iter().zip(angles_max.iter().zip(&directions_max)) {
        println!("  {name:7} from angles {a:6.2}   from directions {d:6.2}");
    }
    println!("  total   from angles {total_angles:6.2}   from directions {total_directions:6.2}");
    // The budgets (docs/conventions.md §2): measured maxima, rounded up.
    let angles_budget = [1.5, 1.5, 2.5, 2.5, 12.0, 5.0, 12.0];
    for ((name, got), budget) in FIELDS.iter().zip(angles_max).zip(angles_budget) {
        assert!(got <= budget, "{name} from angles: {got} ulps > {budget}");
    }
    assert!(
        total_angles <= 16.0,
        "total from angles: {total_angles} ulps"
    );
    // From rounded sines, v_xy² and the ratio carry the inputs' rounding
    // divided by the cancelling difference sin θi − sin θs: no fixed
    // budget; the cosines, sines and lead keep theirs.
    let directions_budget = [0.5, 0.5, 2.0, 2.0, f64::INFINITY, 4.5, f64::INFINITY];
    for ((name, got), budget) in FIELDS.iter().zip(directions_max).zip(directions_budget) {
        assert!(
            got <= budget,
            "{name} from directions: {got} ulps > {budget}"
        );
    }
    assert!(
        total_directions <= 32.0,
        "total from directions: {total_directions} ulps"
    );
}

#[test]
fn f32_constructors_reject_bad_input_by_name() {
    use laminar_brdf_core::InputError;
    let name = |r: Result<Geometry<f32>, InputError>| match r {
        Err(InputError::OutOfRange { input, .. }) => input.name(),
        other => panic!("expected an error, got {other:?}"),
    };
    assert_eq!(name(Geometry::from_angles_f32(-0.1, 0.2, 0.0)), "theta_i");
    assert_eq!(name(Geometry::from_angles_f32(0.1, 1.6, 0.0)), "theta_s");
    assert_eq!(name(Geometry::from_angles_f32(0.1, 0.2, f32::NAN)), "phi_s");
    assert_eq!(name(Geometry::from_angles_f32(0.1, 0.2, 3.2)), "phi_s");
    let ok = Directions {
        cos_i: 1.0,
        sin_i: 0.0,
        cos_s: 0.6,
        sin_s: 0.8,
        cos_phi: -1.0,
        sin_phi: 0.0,
    };
    assert!(Geometry::from_directions(&ok).is_ok());
    let off_circle = Directions { sin_s: 0.7, ..ok };
    assert_eq!(name(Geometry::from_directions(&off_circle)), "theta_s");
    let below = Directions {
        cos_i: -1.0,
        sin_i: 0.0,
        ..ok
    };
    assert_eq!(name(Geometry::from_directions(&below)), "theta_i");
    let nan = Directions {
        sin_phi: f32::NAN,
        ..ok
    };
    assert_eq!(name(Geometry::from_directions(&nan)), "phi_s");
}
