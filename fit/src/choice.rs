//! Which model fits a measurement set best, allowing for the parameters
//! each spends (docs/estimation.md, "Choosing a model"): information
//! criteria on the free objective's weighted residuals, and a ranking of
//! the models fitted to one set. Logarithms and exponentials are `libm`'s,
//! not the platform's, so that the criteria and weights have the same bits
//! on every target (the web page's comparison is byte for byte the CLI's).
//!
//! With σ given, `−2 ln L = χ² = Σ w r²` up to a constant, and k = p;
//! without, the noise variance is estimated too: `−2 ln L = K ln(Σ r²/K)`
//! up to a constant, and k = p + 1. Then `AIC = −2 ln L + 2k`,
//! `AICc = AIC + 2k(k + 1)/(K − k − 1)` and `BIC = −2 ln L + k ln K`. The
//! constants are the same for every model fitted to one set, so
//! differences rank the models; the lowest AICc ranks first, and its
//! Akaike weight `exp(−ΔAICc/2)/Σ exp(−ΔAICc/2)` says by how much.
//!
//! Beside the criteria, each model compared is cross-validated
//! ([`CrossValidation`], [`crate::Analysis::folds`] folds): an error
//! that assumes nothing of the likelihood, so it still ranks fairly when
//! no model is right.

use serde::{Deserialize, Serialize};

/// A fit's information criteria.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "typescript", derive(ts_rs::TS))]
pub struct Information {
    /// Akaike's criterion.
    pub aic: f64,
    /// Akaike's with the small-sample correction (NaN-free: absent when
    /// `K ≤ k + 1`).
    pub aicc: Option<f64>,
    /// Schwarz's Bayesian criterion.
    pub bic: f64,
}

impl Information {
    /// The criteria of a fit with weighted objective `sse = Σ w r²` over
    /// `k_measurements`, `p` fitted parameters (the amplitude and β
    /// included); `weighted` when `w = 1/σ²`. `None` for a non-finite or
    /// zero objective without σ (a fit to rounding has no likelihood scale).
    pub fn new(sse: f64, k_measurements: usize, p: usize, weighted: bool) -> Option<Self> {
        let n = k_measurements as f64;
        let (deviance, k) = if weighted {
            (sse, p as f64)
        } else {
            (n * libm::log(sse / n), p as f64 + 1.0)
        };
        if !deviance.is_finite() || k_measurements == 0 {
            return None;
        }
        let aic = deviance + 2.0 * k;
        let aicc = (n > k + 1.0).then(|| aic + 2.0 * k * (k + 1.0) / (n - k - 1.0));
        Some(Self {
            aic,
            aicc,
            bic: deviance + k * libm::log(n),
        })
    }
}

/// A fit's K-fold cross-validated error (`crate::free`'s
/// `cross_validation`): each measurement predicted by the fit to the folds
/// that hold it out.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "typescript", derive(ts_rs::TS))]
pub struct CrossValidation {
    /// Folds the measurements were dealt into.
    pub folds: usize,
    /// `sqrt(Σ w r²/K)` of the held-out residuals (w = 1/σ² with σ
    /// given, else 1: then in units of the data divided by their max).
    pub rms: f64,
    /// The same measure of the full fit's own residuals, for comparison:
    /// `rms` well above it says the model follows its training noise.
    pub in_sample: f64,
}

/// One model's place among the models fitted to a set.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "typescript", derive(ts_rs::TS))]
pub struct Rank {
    /// 1 for the best (lowest AICc).
    pub rank: usize,
    /// Its AICc above the best's (AIC when a fit of the set has no AICc:
    /// every fit of a set is ranked by one criterion).
    pub delta: f64,
    /// Its Akaike weight among the models ranked.
    pub weight: f64,
}

/// The ranks of fits with criteria `criteria` (in their order; `None` for
/// a fit without criteria, which is not ranked), all by one criterion:
/// AICc when every fit ranked has one, else AIC for every fit (a model
/// with too many parameters for its AICc, `K ≤ k + 1`, would otherwise
/// pay AIC's penalty where the others pay AICc's larger one).
pub fn rank(criteria: &[Option<Information>]) -> Vec<Option<Rank>> {
    let by_aicc = criteria.iter().flatten().all(|c| c.aicc.is_some());
    let score = |c: &Information| c.aicc.filter(|_| by_aicc).unwrap_or(c.aic);
    let scores: Vec<Option<f64>> = criteria.iter().map(|c| c.as_ref().map(score)).collect();
    let best = scores
        .iter()
        .flatten()
        .copied()
        .fold(f64::INFINITY, f64::min);
    let total: f64 = scores
        .iter()
        .flatten()
        .map(|s| libm::exp(-(s - best) / 2.0))
        .sum();
    scores
        .iter()
        .map(|s| {
            let s = (*s)?;
            let rank = 1 + scores.iter().flatten().filter(|&&o| o < s).count();
            Some(Rank {
                rank,
                delta: s - best,
                weight: libm::exp(-(s - best) / 2.0) / total,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Equal fits prefer fewer parameters; a much better fit wins despite
    /// more; the weights sum to 1.
    #[test]
    fn ranks_trade_fit_against_parameters() {
        let a = Information::new(1.0, 200, 4, false);
        let b = Information::new(1.0, 200, 2, false);
        let c = Information::new(0.5, 200, 6, false);
        let r = rank(&[a, b, c, None]);
        assert_eq!(r[0].unwrap().rank, 3);
        assert_eq!(r[1].unwrap().rank, 2);
        assert_eq!(r[2].unwrap().rank, 1);
        assert!(r[3].is_none());
        let total: f64 = r.iter().flatten().map(|r| r.weight).sum();
        assert!((total - 1.0).abs() < 1e-12);
        // χ² 210 on 200 with 4 parameters: AIC = 218, BIC = 210 + 4 ln 200.
        let w = Information::new(210.0, 200, 4, true).unwrap();
        assert_eq!(w.aic, 218.0);
        assert!((w.bic - (210.0 + 4.0 * 200f64.ln())).abs() < 1e-12);
        assert!(Information::new(0.0, 200, 4, false).is_none());
    }

    /// On 7 measurements a model with 5 fitted parameters (k = 6 with the
    /// noise variance) has no AICc: the set is then ranked by AIC alone.
    /// Before, its AIC stood against the other's AICc, and the same fit
    /// with a parameter more ranked first (issue 55, item 1).
    #[test]
    fn a_set_is_ranked_by_one_criterion() {
        let bigger = Information::new(1.0, 7, 5, false).unwrap();
        let smaller = Information::new(1.0, 7, 4, false).unwrap();
        assert!(bigger.aicc.is_none() && smaller.aicc.is_some());
        let r = rank(&[Some(bigger), Some(smaller)]);
        let (b, s) = (r[0].unwrap(), r[1].unwrap());
        assert_eq!((s.rank, b.rank), (1, 2));
        // AIC's penalty of one parameter more: exp(−1) of the weight.
        assert_eq!(b.delta, bigger.aic - smaller.aic);
        assert!((b.weight / s.weight - (-1.0f64).exp()).abs() < 1e-12);
        // With AICc for both, AICc ranks them.
        let (x, y) = (
            Information::new(1.0, 9, 5, false),
            Information::new(0.9, 9, 4, false),
        );
        let r = rank(&[x, y]);
        assert_eq!(
            r[0].unwrap().delta,
            x.unwrap().aicc.unwrap() - y.unwrap().aicc.unwrap()
        );
    }
}
