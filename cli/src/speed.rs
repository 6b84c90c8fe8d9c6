//! `laminar report speed-vs-error`: every search path on the selected fits,
//! timed, and compared grid value by grid value with the `f64` reference.
//!
//! The reference over the whole grid is `onepass-f64` (the direct `f64`
//! path is too slow to run on every fit's 5.5 million parameter sets); each
//! report also runs `direct-f64` on a slice of the grid (the first
//! `direct_slopes` σ/T values) and states how far the two `f64` paths are
//! apart there. The direct paths are timed and compared on that slice only.

use laminar_brdf_fit::paper::search::{error_surface, search};
use laminar_brdf_fit::{Arith, Method, SearchPath};
use laminar_brdf_fit::{Axis, Grid, GridError, Model, Scene};
use laminar_brdf_io::fits::markdown_table;
use std::time::Instant;

/// One path's totals over the fits.
#[derive(Debug, Clone, PartialEq)]
pub struct PathRow {
    /// The path.
    pub path: SearchPath,
    /// (parameter set, measurement) pairs per second of its searches.
    pub pairs_per_second: f64,
    /// Largest |ΔRMS| against the reference over every compared grid value.
    pub max_rms_error: f64,
    /// Fits whose chosen parameters equal the reference's choice.
    pub same_choice: usize,
    /// Fits compared.
    pub fits: usize,
    /// Largest reference-RMS gap between its choice and the reference's.
    pub max_gap: f64,
    /// True when only the `direct_slopes` slice was run.
    pub slice_only: bool,
}

/// The report.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedReport {
    /// One row per path, in [`SearchPath::all`] order.
    pub rows: Vec<PathRow>,
    /// Largest |ΔRMS| between `direct-f64` and `onepass-f64` on the slice.
    pub reference_agreement: f64,
    /// Number of σ/T values of the direct slice.
    pub direct_slopes: usize,
    /// Mean Pareto-front size of the envelope searches (exp, gauss).
    pub mean_front: [Option<f64>; 2],
    /// Fraction of the β sweeps the envelope searches skipped by their lower
    /// bound (exp, gauss).
    pub pruned: [Option<f64>; 2],
    /// The lanes the free objective's kernels ran with
    /// ([`laminar_brdf_fit::simd`]).
    pub simd: laminar_brdf_fit::simd::Path,
}

/// Index of the smallest value (first on ties).
fn argmin(v: &[f64]) -> usize {
    v.iter()
        .enumerate()
        .fold(
            (0, f64::INFINITY),
            |b, (i, &x)| if x < b.1 { (i, x) } else { b },
        )
        .0
}

/// Runs every path on `scenes` × {exp, gauss}; `progress(path)` is called as each run starts.
///
/// # Errors
/// [`GridError`] when the grid is invalid or a surface cannot be allocated.
pub fn speed_vs_error(
    scenes: &[Scene],
    grid: &Grid,
    direct_slopes: usize,
    progress: &dyn Fn(&str),
) -> Result<SpeedReport, GridError> {
    let slice = Grid {
        slope: Axis {
            values: grid.slope.values[..direct_slopes.clamp(1, grid.slope.len())].to_vec(),
        },
        ..grid.clone()
    };
    let paths = SearchPath::all();
    let mut rows: Vec<PathRow> = paths
        .iter()
        .map(|&path| PathRow {
            path,
            pairs_per_second: 0.0,
            max_rms_error: 0.0,
            same_choice: 0,
            fits: 0,
            max_gap: 0.0,
            slice_only: path.method == Method::Direct,
        })
        .collect();
    let mut seconds = vec![0.0; paths.len()];
    let mut pairs = vec![0.0; paths.len()];
    let mut reference_agreement: f64 = 0.0;
    let whole_reference = SearchPath::new(Method::OnePass, Arith::F64);
    let mut mean_front = [None; 2];
    let mut pruned = [None; 2];
    for scene in scenes {
        for (i_model, model) in [Model::Exp, Model::Gauss].into_iter().enumerate() {
            let corr = model.correlation().expect("layered");
            progress(&format!("sample {} {model}: reference", scene.sample()));
            let reference = error_surface(scene, grid, corr, whole_reference)?;
            let slice_reference = &reference[..slice.size()];
            let direct = error_surface(scene, &slice, corr, SearchPath::REFERENCE)?;
            reference_agreement = direct
                .iter()
                .zip(slice_reference)
                .fold(reference_agreement, |m, (a, b)| m.max((a - b).abs()));
            for (i, &path) in paths.iter().enumerate() {
                progress(&format!("sample {} {model}: {path}", scene.sample()));
                let (g, refs) = if path.method == Method::Direct {
                    (&slice, slice_reference)
                } else {
                    (grid, &reference[..])
                };
                let start = Instant::now();
                let r = search(scene, g, corr, path, &|| {})?;
                seconds[i] += start.elapsed().as_secs_f64();
                if path == SearchPath::DEFAULT {
                    mean_front[i_model] = r.mean_front;
                    pruned[i_model] = r.pruned;
                }
                pairs[i] += g.size() as f64 * scene.len() as f64;
                let values = if path == whole_reference {
                    reference.clone()
                } else if path == SearchPath::REFERENCE {
                    direct.clone()
                } else {
                    error_surface(scene, g, corr, path)?
                };
                let row = &mut rows[i];
                row.max_rms_error = values
                    .iter()
                    .zip(refs)
                    .fold(row.max_rms_error, |m, (a, b)| m.max((a - b).abs()));
                let want = argmin(refs);
                row.fits += 1;
                if r.best == want {
                    row.same_choice += 1;
                } else {
                    row.max_gap = row.max_gap.max(refs[r.best] - refs[want]);
                }
            }
        }
    }
    for (i, row) in rows.iter_mut().enumerate() {
        row.pairs_per_second = pairs[i] / seconds[i].max(1e-12);
    }
    Ok(SpeedReport {
        rows,
        reference_agreement,
        direct_slopes: slice.slope.len(),
        mean_front,
        pruned,
        simd: laminar_brdf_fit::simd::path(),
    })
}

impl SpeedReport {
    /// The report as a Markdown table.
    pub fn markdown(&self) -> String {
        let reference = self
            .rows
            .iter()
            .find(|r| r.path == SearchPath::REFERENCE)
            .map(|r| r.pairs_per_second)
            .unwrap_or(f64::NAN);
        let header = [
            "path",
            "precision",
            "pairs/s",
            "speed-up over direct-f64",
            "max abs ΔRMS vs f64 reference",
            "same choice as reference",
            "max reference-RMS gap",
        ];
        let rows: Vec<Vec<String>> = self
            .rows
            .iter()
            .map(|r| {
                let precision = match r.path.arith {
                    Arith::F32x8 => "f32 (SIMD ×8)",
                    Arith::F32 => "f32 (scalar twin)",
                    Arith::F64 => "f64",
                };
                let scope = if r.slice_only { " (slice)" } else { "" };
                vec![
                    format!("{}{scope}", r.path),
                    precision.into(),
                    format!("{:.3e}", r.pairs_per_second),
                    format!("{:.1}×", r.pairs_per_second / reference),
                    format!("{:.2e}", r.max_rms_error),
                    format!("{} of {}", r.same_choice, r.fits),
                    format!("{:.2e}", r.max_gap),
                ]
            })
            .collect();
        let mut out = markdown_table(&header, &rows);
        out += &format!(
            "\nReference: `onepass-f64` over the whole grid; `direct-f64` agrees with it to {:.2e} (max |ΔRMS|) on the slice of the first {} σ/T value(s), where the direct paths were run.\n",
            self.reference_agreement, self.direct_slopes
        );
        out += &format!(
            "\nLanes: the free objective's kernels ran with `{}` (`LAMINAR_SIMD` forces `portable` or `avx2`; every path gives the same bits); the search paths above run `wide`'s lanes as built.\n",
            self.simd.name()
        );
        if let [Some(exp), Some(gauss)] = self.mean_front {
            out += &format!(
                "\nEnvelope: the Pareto front of (S, U) holds {exp:.1} measurements on average for exp, {gauss:.1} for gauss (last fit).\n"
            );
        }
        if let [Some(exp), Some(gauss)] = self.pruned {
            out += &format!(
                "Envelope searches skipped the β loop of {:.1}% (exp) and {:.1}% (gauss) of the (σ/T, n, a) triples by the lower bound (last fit); error surfaces never skip.\n",
                100.0 * exp,
                100.0 * gauss
            );
        }
        out
    }
}
