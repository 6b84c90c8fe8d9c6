//! The fitted-model file: fits as pretty JSON (streamed, one fit at a
//! time), and read back.

use super::{FitEntry, FitsFile, MaterialEntry, FORMAT, READ_VERSIONS, VERSION};
use crate::error::ReadError;
use laminar_brdf_fit::Fit;
use std::io::Write;
use std::path::Path;

/// Fits as the fitted-model file (pretty JSON): [`JsonFits`] into memory.
pub fn json(records: &[Fit]) -> String {
    json_entries(&records.iter().map(FitEntry::new).collect::<Vec<_>>())
}

/// Entries as the fitted-model file (pretty JSON).
pub fn json_entries(entries: &[FitEntry]) -> String {
    let mut out = JsonFits::new(Vec::new()).expect("in-memory write");
    for e in entries {
        out.write_entry(e).expect("in-memory write");
    }
    String::from_utf8(out.finish().expect("in-memory write")).expect("utf-8")
}

/// The fitted-model file's fields before its fits.
pub(super) fn empty_file() -> FitsFile {
    FitsFile {
        format: FORMAT.into(),
        version: VERSION,
        quantities: [
            ("objective", "free: weighted least squares Σ w(D − c·M)² with a free amplitude c ≥ 0, M eq. 8's raw mix (beta is eq. 8's β, solved with c in closed form), w = 1/σ² from the input's uncertainties (else 1), every estimate and interval inside the box searched; paper: the paper's objective, data and model each divided by their max over the measurements"),
            ("rms", "Δ_RMS (eq. 15) = 100·sqrt(Σ(D−P)²)/K: D measured radiance (BRDF·cos θi) divided by its max over the K kept measurements, P the fitted prediction; of the refined estimate (free) or of the best grid point (paper, as in the paper's tables)"),
            ("chi2_dof", "χ²/ν (eq. 16) = Σ(P−D)²/D over the chi2_used measurements with D > 0, divided by chi2_used − p"),
            ("chi2_weighted", "free: the weighted χ²/ν = Σ w(D−P)²/(K − p) of the estimate, p counting the amplitude (about 1 when the input's σ are right)"),
            ("amplitude", "free: the fitted amplitude c (P = c·M on the data divided by their max)"),
            ("adequacy", "free: does the model fit? chi2_p = P(χ²_ν ≥ Σ w r²) with the input's σ; runs_z, runs_p: the runs of residual signs ordered by the half vector's zenith θh (then θi), standardised, and the one-sided p-value of too few runs; lack_of_fit when either p-value is below 0.01"),
            ("information", "free: aic, aicc, bic on the weighted objective (with σ: χ² + 2k, …, k = p; without: K ln(Σr²/K) + 2k, k = p + 1); lower is better, differences between models fitted to one set count"),
            ("rank", "the model's place among those fitted to the same set by AICc (1 best), delta = its AICc above the best's, weight = its Akaike weight"),
            ("params", "fitted parameters rounded to 10 decimals; beta is eq. 8's β (free) or the balance of the paper normalisation (paper); not_identified in place of a value the data do not determine (the parameter's flags hold not_identified; fitted keeps a value, which predicts the same)"),
            ("fitted", "the model to predict with: full-precision params; normalisation = {amplitude} (free: P = amplitude·(beta·L_sb + (1−beta)·L_sf)), or the maxima over the fit's geometries of the raw surface term, raw subsurface term and the normalised mix (paper; baselines: of the raw radiance; P = (beta·L_sb/subsurface_max + (1−beta)·L_sf/surface_max)/mix_max)"),
            ("beta_eq8", "the balance of eq. 8 giving the fitted lobe: P = eq8_scale·(beta_eq8·L_sb + (1−beta_eq8)·L_sf)"),
            ("data_scale", "the max of the measured radiance the data were divided by: P·data_scale is radiance in the input's units"),
            ("fitted_note", "fitted is the refined model when the fit was refined (grid_fitted is then the grid's best); laminar predict uses fitted"),
            ("rms_grid", "Δ_RMS of the best grid point (= rms for the paper objective)"),
            ("rms_refined", "Δ_RMS after refinement (free: Levenberg–Marquardt from the grid's basins inside the box, which lowers the weighted objective; paper: Nelder–Mead in f64 within the model's domain, never above rms_grid)"),
            ("parameters", "each searched parameter: grid (the grid value), refined, lo68/hi68 and lo95/hi95 (68.27% and 95% intervals), interval (where the headline comes from: robust = the profile's interval with its distances from the estimate scaled by the sandwich (HC3) to model-based standard deviation ratio, the free objective's default, which holds when the model does not fit exactly; profile = the profile of the objective at Δχ² = 1 and 3.84 (free without uncertainties: F(1, K − p)'s quantiles) with the noise variance from the residuals, Σ(D−P)²/(K−p), or from the input's uncertainties; jacobian = refined ± 1 and 1.96 sd), sd (the Jacobian's standard deviation, only when no parameter is at a domain bound), flags: range_edge (paper: the grid value is first or last of its axis, the optimum may lie outside the range searched; free: the estimate is on a face of the box), domain_bound (grid or refined value at a bound of the model's domain, e.g. a = 0 or 1, n = 1), open_below/open_above (the 95% profile interval does not close within the range searched on that side), not_identified (free: the 95% interval is the whole box), not_determined (free: the 68.27% interval is the whole box), misfit_sensitive (free: misfit_ratio beyond 1.5 or below 1/1.5); alternatives: the other intervals computed ({interval, lo68, hi68, lo95, hi95}); misfit_ratio: the sandwich sd over the model-based sd; box: [lo, hi], the box the free objective searched, refined and bounded the intervals in; released: for an estimate on a face of the box that is not a bound of the model's domain, the value and Δ_RMS of one local fit with that bound released (a diagnostic, not an estimate)"),
            ("correlations", "correlations of the refined parameters from the Jacobian covariance s²(JᵀJ)⁻¹"),
            ("trade_offs", "pairs of parameters whose correlation is at least 0.9 in magnitude: the data constrain their combination, not each one"),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect(),
        fits: Vec::new(),
        materials: Vec::new(),
    }
}

/// Materials (joint fits) as the fitted-model file (pretty JSON), with no
/// single fits; each material's channels are selected by their labels
/// `sample/channel/model` as fits are.
pub fn json_materials(materials: &[MaterialEntry]) -> String {
    let mut file = empty_file();
    file.quantities.insert(
        "materials".into(),
        "joint fits across a sample's channels (laminar fit-joint): shared holds σ/T, σ′/T′ (untied models) and n once, each with the pairs bootstrap's 68.27% and 95% percentile intervals (the same geometries resampled in every channel); each channel its a (likewise), beta (eq. 8's), amplitude, data_scale, sse, lack_of_fit and fitted, the model to predict with (selected as sample/channel/model); chromatic_p and roughness_p the tests of one a and one σ/T for every channel; variants each way of fitting the channels (joint, roughness_per_channel, separate) by its AICc above the best's".into(),
    );
    file.materials = materials.to_vec();
    serde_json::to_string_pretty(&file).expect("a fitted-model file serialises") + "\n"
}

/// The fitted-model file written one fit at a time, byte for byte what
/// [`json`] gives, without holding every record (`fit-batch` of any N in
/// constant memory): the document's head, then [`JsonFits::write`] per fit,
/// then [`JsonFits::finish`].
pub struct JsonFits<W: Write> {
    out: W,
    written: usize,
}

/// Indentation of a fit inside the document (`serde_json`'s pretty
/// printer indents by two spaces; fits are at depth 2).
const FIT_INDENT: &str = "    ";

impl<W: Write> JsonFits<W> {
    /// Writes the document's head (format, version, quantities) to `out`.
    ///
    /// # Errors
    /// The writer's error.
    pub fn new(mut out: W) -> std::io::Result<Self> {
        let head = serde_json::to_string_pretty(&empty_file()).map_err(std::io::Error::other)?;
        // The empty document ends in `"fits": []\n}`: keep up to the `[`.
        let open = head.strip_suffix("[]\n}").ok_or_else(|| {
            std::io::Error::other("the fitted-model file's head has an unexpected form")
        })?;
        out.write_all(open.as_bytes())?;
        out.write_all(b"[")?;
        Ok(Self { out, written: 0 })
    }

    /// Writes one fit.
    ///
    /// # Errors
    /// The writer's error.
    pub fn write(&mut self, record: &Fit) -> std::io::Result<()> {
        self.write_entry(&FitEntry::new(record))
    }

    /// Writes one fit's entry.
    ///
    /// # Errors
    /// The writer's error.
    pub fn write_entry(&mut self, entry: &FitEntry) -> std::io::Result<()> {
        let entry = serde_json::to_string_pretty(entry).map_err(std::io::Error::other)?;
        self.out
            .write_all(if self.written == 0 { b"\n" } else { b",\n" })?;
        for (k, line) in entry.lines().enumerate() {
            if k > 0 {
                self.out.write_all(b"\n")?;
            }
            self.out.write_all(FIT_INDENT.as_bytes())?;
            self.out.write_all(line.as_bytes())?;
        }
        self.written += 1;
        Ok(())
    }

    /// Closes the document and returns the writer, flushed.
    ///
    /// # Errors
    /// The writer's error.
    pub fn finish(mut self) -> std::io::Result<W> {
        let close: &[u8] = if self.written == 0 {
            b"]\n}\n"
        } else {
            b"\n  ]\n}\n"
        };
        self.out.write_all(close)?;
        self.out.flush()?;
        Ok(self.out)
    }
}

/// Reads a fitted-model file written by [`json`].
///
/// # Errors
/// [`ReadError`] when the file cannot be read or is not a fitted-model file of this version.
pub fn read_fits(file: &Path) -> Result<FitsFile, ReadError> {
    let text = std::fs::read_to_string(file).map_err(|e| ReadError::io(file, "read", e))?;
    parse_fits(file, &text)
}

/// [`read_fits`] on contents already in memory (`file` names them in errors).
///
/// # Errors
/// As [`read_fits`].
pub fn parse_fits(file: &Path, text: &str) -> Result<FitsFile, ReadError> {
    let fits: FitsFile = serde_json::from_str(text).map_err(|e| {
        ReadError::format(
            file,
            e.line(),
            format!(
                "column {}: not a laminar fitted-model file ({e}); write one with `laminar fit --format json`",
                e.column()
            ),
        )
    })?;
    if fits.format != FORMAT || !READ_VERSIONS.contains(&fits.version) {
        return Err(ReadError::format(
            file,
            0,
            format!(
                "format `{}` version {}, expected `{FORMAT}` version 1 to {VERSION}",
                fits.format, fits.version
            ),
        ));
    }
    Ok(fits)
}
