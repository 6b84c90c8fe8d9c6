//! f32 error budgets against the f64 reference, per component.
//!
//! Domain: θi, θs ∈ [0, π/2], φs ∈ [−π, π], σ/T ∈ [0.12, 4.04], n ∈ [1, 2],
//! a, β ∈ [0, 1]. Budgets are in units of f32 epsilon (2⁻²³), on the error
//! scaled as follows:
//! * Fresnel and absorption terms (values in [0, 1]): absolute error.
//! * Surface radiance: error relative to the leading factor `cos θi / v_z²`
//!   (the value at the mirror direction); the Gaussian/Exponential factor
//!   itself is ill-conditioned far in its tail, where the value is tiny.
//! * Subsurface radiance: relative to `cos θi′ / v_z′² · dω′`.
//! * Total: relative to `β · (subsurface scale) + (1 − β) · (surface scale)`.
//! * Parameters are rounded to f32 before the f64 reference runs, so the
//!   budget measures arithmetic error, not the quantisation of the inputs.

mod common;

use laminar_brdf_core::{components, Correlation, Geometry, Interface, Params};
use proptest::prelude::*;

const EPS: f64 = f32::EPSILON as f64;

/// Budgets (in f32 epsilons) for each component, checked below.
/// Measured maxima over 20 000 deterministic random cases (see
/// `print_measured_error_maxima`): Fresnel 1.75, absorption 1.12, surface
/// 2.29, subsurface 2.41, total 2.70.
const FRESNEL_BUDGET: f64 = 3.0;
const ABSORB_BUDGET: f64 = 2.0;
const SURFACE_BUDGET: f64 = 4.0;
const SUBSURFACE_BUDGET: f64 = 4.0;
const TOTAL_BUDGET: f64 = 4.0;

fn f32_rounded(p: &Params) -> Params {
    let r = |v: f64| v as f32 as f64;
    Params::new(r(p.slope()), r(p.beta()), r(p.n()), r(p.a())).unwrap()
}

/// Scaled errors of every component for one case, in f32 epsilons.
fn scaled_errors(angles: &laminar_brdf_core::Angles, corr: Correlation, p: &Params) -> [f64; 7] {
    // The f64 reference runs at the parameters as the f32 path sees them
    // (rounded to f32), so the budget measures arithmetic error only.
    let p = &f32_rounded(p);
    let g64 = Geometry::<f64>::splat(angles);
    let g32 = Geometry::<f32>::splat(angles);
    let r = components(&g64, corr, p);
    let c = components(&g32, corr, p);
    let iface = Interface::new(&g64, p.n());
    let surf_scale = g64.lead;
    let sub_scale = iface.refracted.lead * iface.solid_angle;
    let total_scale = p.beta() * sub_scale + (1.0 - p.beta()) * surf_scale;
    let rel = |got: f32, want: f64, scale: f64| {
        if scale > 0.0 {
            (got as f64 - want).abs() / (scale * EPS)
        } else {
            (got as f64 - want).abs() / EPS
        }
    };
    [
        rel(c.fresnel_in, r.fresnel_in, 1.0),
        rel(c.fresnel_out, r.fresnel_out, 1.0),
        rel(c.absorb_in, r.absorb_in, 1.0),
        rel(c.absorb_out, r.absorb_out, 1.0),
        rel(c.surface, r.surface, surf_scale),
        rel(c.subsurface, r.subsurface, sub_scale),
        rel(c.total, r.total, total_scale),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]

    #[test]
    fn f32_components_stay_within_budget(
        a in common::angles(),
        corr in common::correlation(),
        p in common::paper_params(),
    ) {
        let e = scaled_errors(&a, corr, &p);
        prop_assert!(e[0] <= FRESNEL_BUDGET && e[1] <= FRESNEL_BUDGET, "fresnel {:?}", e);
        prop_assert!(e[2] <= ABSORB_BUDGET && e[3] <= ABSORB_BUDGET, "absorption {:?}", e);
        prop_assert!(e[4] <= SURFACE_BUDGET, "surface {:?}", e);
        prop_assert!(e[5] <= SUBSURFACE_BUDGET, "subsurface {:?}", e);
        prop_assert!(e[6] <= TOTAL_BUDGET, "total {:?}", e);
    }
}

/// Prints the measured maxima (run with `--ignored --nocapture`).
#[test]
#[ignore]
fn print_measured_error_maxima() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let strat = (
        common::angles(),
        common::correlation(),
        common::paper_params(),
    );
    let mut max = [0.0f64; 7];
    for _ in 0..20_000 {
        let (a, corr, p) = strat.new_tree(&mut runner).unwrap().current();
        for (m, e) in max.iter_mut().zip(scaled_errors(&a, corr, &p)) {
            *m = m.max(e);
        }
    }
    println!("max scaled errors (f32 eps): fresnel_in {:.2} fresnel_out {:.2} absorb_in {:.2} absorb_out {:.2} surface {:.2} subsurface {:.2} total {:.2}",
        max[0], max[1], max[2], max[3], max[4], max[5], max[6]);
}

/// Grazing geometries next to the forward-specular direction, where
/// `sin θi − sin θs cos φs` cancels; both were found by the property test
/// above (surface errors of 9.7 and 10.7 f32 eps when `v_xy²` was formed
/// from rounded sines).
#[test]
fn grazing_forward_specular_stays_within_budget() {
    use core::f64::consts::FRAC_PI_2;
    let cases = [
        (FRAC_PI_2 - 1e-6, 1.4287, 0.0),
        (1.467_241_747_197_936_4, FRAC_PI_2 - 1e-6, 0.0),
        (FRAC_PI_2 - 1e-6, FRAC_PI_2 - 2e-6, 1e-3),
        (1.2, 1.2 + 1e-7, 0.0),
    ];
    for (ti, ts, ps) in cases {
        let a = laminar_brdf_core::Angles::new(ti, ts, ps).unwrap();
        for corr in [Correlation::Exponential, Correlation::Gaussian] {
            for slope in [0.12, 0.5, 4.04] {
                let p = Params::new(slope, 0.5, 1.5, 0.5).unwrap();
                let e = scaled_errors(&a, corr, &p);
                assert!(
                    e[4] <= SURFACE_BUDGET && e[5] <= SUBSURFACE_BUDGET && e[6] <= TOTAL_BUDGET,
                    "θi {ti} θs {ts} φs {ps} {corr:?} slope {slope}: {e:?}"
                );
            }
        }
    }
}
