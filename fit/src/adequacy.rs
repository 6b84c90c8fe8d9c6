//! Does the model fit? (docs/estimation.md, "When the model does not
//! fit"). Two tests of a free-amplitude fit's residuals, reported with
//! every fit:
//!
//! * **χ² lack of fit**, when the input gives each measurement's σ: the
//!   weighted objective `Σ w r²` against χ² with `ν = K − p` degrees of
//!   freedom; the p-value is `P(χ²_ν ≥ Σ w r²)`.
//! * **Runs of residual signs** along the measurement geometry, which needs
//!   no σ: measurements ordered by the half vector's zenith θh (the
//!   coordinate of the surface lobe, eqs. 1–2: `tan²θh = v_xy²/v_z²`),
//!   ties by θi; a model that misses a lobe or a diffuse term leaves long
//!   runs of one sign. The count of runs against its null distribution
//!   under independent residuals (Wald and Wolfowitz 1940, normal
//!   approximation with a continuity correction); the p-value is
//!   one-sided, for too few runs.
//!
//! A fit is flagged `lack_of_fit` when either p-value is below
//! [`LACK_OF_FIT`].

use laminar_brdf_core::{Angles, Geometry};
use serde::{Deserialize, Serialize};
use statrs::function::gamma::checked_gamma_ur;

/// The p-value below which a fit is flagged as not fitting.
pub const LACK_OF_FIT: f64 = 0.01;

/// What the residuals say of a fit's adequacy.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "typescript", derive(ts_rs::TS))]
pub struct Adequacy {
    /// With σ given: `P(χ²_ν ≥ Σ w r²)` (absent without σ).
    pub chi2_p: Option<f64>,
    /// The runs test's standardised count of runs `(R + ½ − E R)/sd R`
    /// (negative: fewer runs than independent residuals give).
    pub runs_z: Option<f64>,
    /// Its one-sided p-value `Φ(runs_z)`.
    pub runs_p: Option<f64>,
    /// True when either p-value is below [`LACK_OF_FIT`].
    pub lack_of_fit: bool,
}

/// `P(χ²_ν ≥ x)`.
pub fn chi2_survival(x: f64, nu: usize) -> Option<f64> {
    if nu == 0 || !x.is_finite() || x < 0.0 {
        return None;
    }
    checked_gamma_ur(nu as f64 / 2.0, x / 2.0).ok()
}

/// The standard normal distribution function.
pub fn normal_cdf(z: f64) -> f64 {
    0.5 * libm::erfc(-z / core::f64::consts::SQRT_2)
}

/// The measurements in the runs test's order (see the module docs): by
/// `tan²θh`, ties by θi, ties of both by index. It depends on the geometry
/// only, so the sets of a batch on one geometry share it (each order costs
/// a geometry's sines and cosines and a sort of all K measurements).
#[derive(Debug, Clone, PartialEq)]
pub struct RunsOrder(Vec<usize>);

impl RunsOrder {
    /// The order of the measurements `angles`.
    pub fn new(angles: &[Angles]) -> Self {
        let mut keyed: Vec<(f64, f64, usize)> = angles
            .iter()
            .enumerate()
            .map(|(k, a)| (Geometry::<f64>::splat(a).ratio, a.theta_i(), k))
            .collect();
        // Stable: equal keys keep the measurements' order.
        keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        Self(keyed.into_iter().map(|(_, _, k)| k).collect())
    }
}

/// The runs test of the residuals `r` at `angles` (see the module docs):
/// `(z, p)`, `None` with fewer than two residuals of each sign.
pub fn runs_test(angles: &[Angles], r: &[f64]) -> Option<(f64, f64)> {
    runs_test_in(&RunsOrder::new(angles), r)
}

/// [`runs_test`] with the measurements' order already formed; residuals
/// of exactly 0 are left out.
pub fn runs_test_in(order: &RunsOrder, r: &[f64]) -> Option<(f64, f64)> {
    let signs: Vec<bool> = order
        .0
        .iter()
        .filter(|&&k| r[k] != 0.0)
        .map(|&k| r[k] > 0.0)
        .collect();
    let pos = signs.iter().filter(|&&s| s).count() as f64;
    let n = signs.len() as f64;
    let neg = n - pos;
    if pos < 2.0 || neg < 2.0 {
        return None;
    }
    let runs = 1.0 + signs.windows(2).filter(|w| w[0] != w[1]).count() as f64;
    let mean = 1.0 + 2.0 * pos * neg / n;
    let variance = 2.0 * pos * neg * (2.0 * pos * neg - n) / (n * n * (n - 1.0));
    // `P(R ≤ runs)` with the continuity correction of a discrete count.
    let z = (runs + 0.5 - mean) / variance.sqrt();
    Some((z, normal_cdf(z)))
}

impl Adequacy {
    /// The tests of a fit with weighted residuals `e = √w r` at `angles`,
    /// `p` fitted parameters; `weighted` when the weights are `1/σ²`.
    pub fn new(angles: &[Angles], e: &[f64], p: usize, weighted: bool) -> Self {
        Self::in_order(&RunsOrder::new(angles), e, p, weighted)
    }

    /// [`Adequacy::new`] with the measurements' order for the runs test
    /// already formed.
    pub fn in_order(order: &RunsOrder, e: &[f64], p: usize, weighted: bool) -> Self {
        let chi2_p = weighted
            .then(|| chi2_survival(e.iter().map(|v| v * v).sum(), e.len().saturating_sub(p)))
            .flatten();
        let runs = runs_test_in(order, e);
        let lack_of_fit =
            chi2_p.is_some_and(|p| p < LACK_OF_FIT) || runs.is_some_and(|(_, p)| p < LACK_OF_FIT);
        Self {
            chi2_p,
            runs_z: runs.map(|r| r.0),
            runs_p: runs.map(|r| r.1),
            lack_of_fit,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synthetic::{geometries, Noise};

    #[test]
    fn chi2_survival_matches_known_values() {
        // χ²₁: P(≥ 3.841) = 0.05; χ²₁₀: P(≥ 18.307) = 0.05; P(≥ ν) near ½.
        assert!((chi2_survival(3.841_458_820_694_124, 1).unwrap() - 0.05).abs() < 1e-9);
        assert!((chi2_survival(18.307_038_053_275_146, 10).unwrap() - 0.05).abs() < 1e-9);
        assert!(chi2_survival(1.0, 0).is_none());
        assert!(chi2_survival(f64::NAN, 3).is_none());
    }

    /// Under independent noise the runs test's p-value is uniform: its
    /// rejection rates at 5% and 1% over 2,000 simulated residual sets lie
    /// in 3σ binomial bands; a smooth misfit is rejected every time.
    #[test]
    fn the_runs_tests_null_holds_and_it_sees_a_missed_lobe() {
        let angles = geometries();
        let mut rng = Noise::new(7);
        let trials = 2000;
        let mut rejected = [0usize; 2];
        for _ in 0..trials {
            let r: Vec<f64> = angles.iter().map(|_| rng.normal()).collect();
            let (_, p) = runs_test(&angles, &r).unwrap();
            rejected[0] += usize::from(p < 0.05);
            rejected[1] += usize::from(p < 0.01);
        }
        for (count, level) in rejected.into_iter().zip([0.05, 0.01]) {
            let rate = count as f64 / trials as f64;
            let half = 3.0 * (level * (1.0 - level) / trials as f64).sqrt();
            assert!((rate - level).abs() <= half, "{rate} at {level}");
        }
        // A residual that follows the geometry (a missed lobe) plus noise.
        let r: Vec<f64> = angles
            .iter()
            .map(|a| libm::cos(2.0 * a.theta_s() + a.theta_i()) + 0.3 * rng.normal())
            .collect();
        let a = Adequacy::new(&angles, &r, 4, false);
        assert!(a.lack_of_fit && a.runs_p.unwrap() < 1e-6, "{a:?}");
        assert!(a.chi2_p.is_none());
    }
}
