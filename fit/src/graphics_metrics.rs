//! The error measures of the graphics literature, beside the paper's
//! Δ_RMS (eq. 15), so a fit compares with published BRDF fits
//! (docs/estimation.md, "Choosing a model"). Both are taken on the
//! radiance the fit sees, `f · cos θi` for a BRDF (docs/conventions.md §4),
//! in the input's own units (the data and prediction times the data's
//! max):
//!
//! * **cos θi-weighted RMS** (Ngan, Durand and Matusik, "Experimental
//!   analysis of BRDF models", EGSR 2005):
//!   `sqrt(Σ (f_d cos θi − f_m cos θi)² / K)`;
//! * **cube-root distance** (Forés, Ferwerda and Gu, "Toward a perceptually
//!   based metric for BRDF modeling", IS&T CIC 2012):
//!   `sqrt(Σ (∛(f_d cos θi) − ∛(f_m cos θi))² / K)`, which weighs a dim
//!   tail's misfit nearer to what an observer sees than the RMS does.
//!
//! The cube roots are within 1 ulp of the correctly rounded ones
//! (`cube_root`, four at a time). Every measurement counts once (the
//! published metrics' solid-angle weights belong to a dense tabulation,
//! which a measurement set is not).

use crate::cube_root::cbrt4;
use serde::{Deserialize, Serialize};

/// A fit's graphics error measures (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "typescript", derive(ts_rs::TS))]
pub struct GraphicsMetrics {
    /// Ngan et al.'s cos θi-weighted RMS, in the input's units.
    pub cosine_rms: f64,
    /// Forés et al.'s cube-root distance, in the cube root of the input's units.
    pub cube_root: f64,
}

impl GraphicsMetrics {
    /// The measures of `prediction` against `data` (both divided by the
    /// data's max `scale`), of equal nonzero length.
    pub fn new(data: &[f64], prediction: &[f64], scale: f64) -> Option<Self> {
        if data.is_empty() || data.len() != prediction.len() {
            return None;
        }
        let k = data.len() as f64;
        let (mut squares, mut roots) = (0.0, 0.0);
        // Four at a time for the cube roots (`cbrt4`, within 1 ulp); the
        // sums still run one measurement after another.
        for (d, p) in data.chunks(4).zip(prediction.chunks(4)) {
            let len = d.len();
            let four = |v: &[f64]| std::array::from_fn(|i| v.get(i).map_or(1.0, |x| x * scale));
            let (d, p): ([f64; 4], [f64; 4]) = (four(d), four(p));
            let (cd, cp) = (cbrt4(d), cbrt4(p));
            for i in 0..len {
                squares += (d[i] - p[i]) * (d[i] - p[i]);
                let r = cd[i] - cp[i];
                roots += r * r;
            }
        }
        let metrics = Self {
            cosine_rms: (squares / k).sqrt(),
            cube_root: (roots / k).sqrt(),
        };
        (metrics.cosine_rms.is_finite() && metrics.cube_root.is_finite()).then_some(metrics)
    }
}

#[cfg(test)]
mod tests {
    use super::GraphicsMetrics;

    /// The two measures by hand on three measurements, in the input's
    /// units; zero for a perfect prediction; none for unequal lengths.
    #[test]
    fn measures_by_hand() {
        let m = GraphicsMetrics::new(&[1.0, 0.125, 0.0], &[0.5, 0.125, 0.001], 8.0).unwrap();
        // Raw: data (8, 1, 0), prediction (4, 1, 0.008).
        let rms = ((16.0 + 0.0 + 0.008f64 * 0.008) / 3.0).sqrt();
        assert!((m.cosine_rms - rms).abs() < 1e-15);
        let roots = ((2.0 - 4f64.cbrt()).powi(2) + 0.0 + 0.2f64.powi(2)) / 3.0;
        assert!((m.cube_root - roots.sqrt()).abs() < 1e-15);
        let zero = GraphicsMetrics::new(&[0.3, 0.7], &[0.3, 0.7], 2.0).unwrap();
        assert_eq!((zero.cosine_rms, zero.cube_root), (0.0, 0.0));
        assert!(GraphicsMetrics::new(&[1.0], &[1.0, 2.0], 1.0).is_none());
    }
}
