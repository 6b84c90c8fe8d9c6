//! The allocation-free small fit of the core (`laminar_brdf_core::small_fit`,
//! the on-device fit) against the library's search on the paper grid: the
//! same best grid point and the same objective bits as the `onepass-f32`
//! path; against the default path (envelope, `f32x8`), the same Δ_RMS to
//! `f32` rounding (on near-ties the two may pick different points).

use laminar_brdf_core::measures::DataFault;
use laminar_brdf_core::small_fit::{self, Axes, AxisError, Scratch, SmallFitError};
use laminar_brdf_core::{Correlation, Geometry, Param};
use laminar_brdf_fit::paper::search;
use laminar_brdf_fit::{synthetic, Grid, SearchPath};
use laminar_brdf_fit::{Arith, Method};

#[test]
fn small_fit_is_the_library_search() {
    let grid = Grid::paper();
    let axes = grid.axes();
    let mut scratch = Scratch::new();
    let onepass = SearchPath::new(Method::OnePass, Arith::F32);
    let (mut checked, mut same_as_default) = (0, 0);
    for (k, seed) in [(7, 11), (32, 12), (64, 13)] {
        let angles = synthetic::spread(k);
        let geometry: Vec<Geometry<f32>> = angles.iter().map(Geometry::splat).collect();
        for corr in [Correlation::Exponential, Correlation::Gaussian] {
            for scene in synthetic::sets(corr, &angles, 2, 0.01, seed) {
                let small = small_fit::fit(corr, &geometry, scene.data(), &axes, &mut scratch)
                    .expect("a valid fit");
                let want = search::search(&scene, &grid, corr, onepass, &|| {}).unwrap();
                assert_eq!(small.best, want.best, "K = {k}, {corr:?}");
                assert_eq!(small.rms.to_bits(), want.best_rms.to_bits(), "K = {k}");
                let rh = small
                    .rh_best
                    .map(|(flat, e)| (flat, search::rms_of_sum(e, k)));
                assert_eq!(rh, want.rh_best, "K = {k}");
                // The default path (envelope, f32x8) sums in another order,
                // so on near-ties it may pick another point: its Δ_RMS then
                // equals this one's to f32 rounding.
                let default =
                    search::search(&scene, &grid, corr, SearchPath::DEFAULT, &|| {}).unwrap();
                if default.best == small.best {
                    same_as_default += 1;
                } else {
                    let gap = (default.best_rms - small.rms).abs() / small.rms;
                    println!("K = {k} {corr:?}: default path picks {} (Δ_RMS {:.7}), small fit {} ({:.7}), relative gap {gap:.1e}", default.best, default.best_rms, small.best, small.rms);
                    assert!(gap < 1e-5, "K = {k}: default path Δ_RMS differs by {gap:e}");
                }
                checked += 1;
            }
        }
    }
    println!("small fit = default path's grid point in {same_as_default} of {checked} fits");
    assert_eq!(checked, 12);
}

#[test]
fn small_fit_refuses_bad_input_by_kind() {
    let grid = Grid::paper();
    let axes = grid.axes();
    let mut scratch = Scratch::new();
    let angles = synthetic::spread(65);
    let g: Vec<Geometry<f32>> = angles.iter().map(Geometry::splat).collect();
    let corr = Correlation::Exponential;
    let ones = vec![1.0; 65];
    let e = small_fit::fit(corr, &g, &ones, &axes, &mut scratch).unwrap_err();
    assert_eq!(
        e,
        SmallFitError::Count {
            geometries: 65,
            data: 65
        }
    );
    let mut data = vec![0.5; 8];
    data[3] = f64::NAN;
    let e = small_fit::fit(corr, &g[..8], &data, &axes, &mut scratch).unwrap_err();
    assert_eq!(
        e,
        SmallFitError::Data {
            index: 3,
            fault: DataFault::NotFinite
        }
    );
    let e = small_fit::fit(corr, &g[..8], &[0.0; 8], &axes, &mut scratch).unwrap_err();
    assert_eq!(
        e,
        SmallFitError::Data {
            index: 0,
            fault: DataFault::NoPositiveValue
        }
    );
    // The library's rule, not a weaker one: what a MeasurementSet refuses,
    // the small fit refuses (it returned rms inf or 0 for these).
    for (bad, index, fault) in [
        (-2.0, 5, DataFault::NegativeBeyondMax),
        (1e-101, 5, DataFault::TinyPositive),
    ] {
        let mut data = vec![0.5; 8];
        data[5] = bad;
        let e = small_fit::fit(corr, &g[..8], &data, &axes, &mut scratch).unwrap_err();
        assert_eq!(e, SmallFitError::Data { index, fault });
    }
    let bad = Axes { n: &[0.9], ..axes };
    let e = small_fit::fit(corr, &g[..8], &[0.5; 8], &bad, &mut scratch).unwrap_err();
    assert!(
        matches!(
            e,
            SmallFitError::Axis(AxisError::OutOfDomain { axis: Param::N, .. })
        ),
        "{e:?}"
    );
    let empty = Axes { beta: &[], ..axes };
    let e = small_fit::fit(corr, &g[..8], &[0.5; 8], &empty, &mut scratch).unwrap_err();
    assert_eq!(
        e,
        SmallFitError::Axis(AxisError::Empty { axis: Param::Beta })
    );
}

/// The free-amplitude small fit (`laminar_brdf_core::small_free_fit`, the
/// on-device fit of the library's default objective) against the
/// library's f64 grid stage of that objective on the paper grid's σ/T, n
/// and a axes and β box: the same grid point, or (on near-ties, which
/// f32's rounding may order differently) a point whose f64 objective is
/// within 10⁻⁴ of the library's minimum.
#[test]
fn small_free_fit_finds_the_library_grid_minimum() {
    use laminar_brdf_core::small_free_fit::{fit_free, FreeAxes, FreeScratch};
    use laminar_brdf_fit::{Analysis, Fitter, Model, Objective};
    let grid = Grid::paper();
    let axes = FreeAxes {
        slope: &grid.slope.values,
        n: &grid.n.values,
        a: &grid.a.values,
        beta: grid.beta.range(),
    };
    let mut scratch = FreeScratch::new();
    let mut reference = FreeScratch::<f64>::default();
    let (mut checked, mut same) = (0, 0);
    for (k, seed) in [(7, 21), (32, 22), (64, 23)] {
        let angles = synthetic::spread(k);
        let g32: Vec<Geometry<f32>> = angles.iter().map(Geometry::splat).collect();
        let g64: Vec<Geometry<f64>> = angles.iter().map(Geometry::splat).collect();
        for (corr, model) in [
            (Correlation::Exponential, Model::Exp),
            (Correlation::Gaussian, Model::Gauss),
        ] {
            for scene in synthetic::sets(corr, &angles, 3, 0.01, seed) {
                let small = fit_free(corr, &g32, (scene.data(), None), &axes, &mut scratch)
                    .expect("a valid fit");
                let library = Fitter::new(grid.clone())
                    .expect("a valid grid")
                    .objective(Objective::Free)
                    .analysis(Analysis::NONE)
                    .threads(1)
                    .expect("one thread")
                    .fit(&scene, model);
                let at = |name: Param| {
                    library
                        .parameters
                        .iter()
                        .find(|p| p.name == name)
                        .map(|p| p.grid)
                        .unwrap()
                };
                let (slope, n, a) = axes.point(small.best);
                checked += 1;
                // The library reports σ/T back through its logarithm.
                let near = |x: f64, y: f64| (x - y).abs() <= 1e-12 * y.abs();
                if near(slope, at(Param::Slope)) && n == at(Param::N) && a == at(Param::A) {
                    same += 1;
                    continue;
                }
                // The f64 objective at a point: the grid of that point alone.
                let mut objective = |(slope, n, a): (f64, f64, f64)| {
                    let one = FreeAxes {
                        slope: &[slope],
                        n: &[n],
                        a: &[a],
                        beta: axes.beta,
                    };
                    fit_free(corr, &g64, (scene.data(), None), &one, &mut reference)
                        .unwrap()
                        .objective
                };
                let picked = objective((slope, n, a));
                let best = objective((at(Param::Slope), at(Param::N), at(Param::A)));
                println!(
                    "K = {k} {corr:?}: f32 picks ({slope}, {n}, {a}), the library ({}, {}, {}): f64 objectives {picked:.9e} and {best:.9e}",
                    at(Param::Slope),
                    at(Param::N),
                    at(Param::A)
                );
                assert!(
                    picked <= best * (1.0 + 1e-4),
                    "K = {k} {corr:?}: {picked} against {best}"
                );
            }
        }
    }
    println!("free small fit = the library's grid point in {same} of {checked} fits");
    assert_eq!(checked, 18);
    assert!(same >= 16, "{same} of {checked}");
}
