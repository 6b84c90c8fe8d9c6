//! One row of numbers per fit: the fields `laminar fit-batch` writes as CSV,
//! Python's `laminar.fit_batch` returns and the Dask/xarray results hold,
//! named and typed here once for all three.
//!
//! The fields, in order: the estimate's errors and the analysis of the fit
//! ([`FIT_FIELDS`]), the Ragheb–Hancock best (`rh_rms`, then `rh_{p}` for
//! its free parameters), then per parameter `p` of the models its value and
//! [`PARAMETER_FIELDS`] (`{p}`, `{p}_lo68`, …). A value not computed is NaN
//! (an empty cell in CSV). The CSV file adds the row's key in front: `set`
//! (the row of the values, from 0) and `model`; Python holds the key as the
//! array's index and its `model` argument, xarray as the dimensions.

use laminar_brdf_fit::model::{all_params, Param};
use laminar_brdf_fit::{Edge, Fit, Model};
use std::io::Write;

/// What a field's numbers are: the dtype a front end stores them in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FieldKind {
    /// A real number (float64).
    Real,
    /// A count, always present (int32).
    Count,
    /// A sum of [`Edge::bit`]s, 0 for none (uint8); NaN only for a
    /// parameter of another model than the fit's.
    Flags,
}

impl FieldKind {
    /// The numpy dtype string of the kind (`"f8"`, `"i4"`, `"u1"`).
    pub fn dtype(self) -> &'static str {
        match self {
            Self::Real => "f8",
            Self::Count => "i4",
            Self::Flags => "u1",
        }
    }
}

/// The fields about the whole fit, in order: the
/// estimate's Δ_RMS (eq. 15) and χ²/ν (eq. 16), the search's and the grid
/// best's Δ_RMS, the kept measurements, the free objective's amplitude (of
/// the data divided by `data_scale`, the max they were divided by: radiance
/// in the input's units is `amplitude · data_scale · mix`) and weighted
/// χ²/ν, the adequacy (χ² and runs-test p-values, lack of fit),
/// AICc and BIC, the rank and Akaike weight among the models compared, the
/// cross-validated error, and the graphics metrics. `lack_of_fit` is 1 or
/// 0 and `rank` a whole number, both reals: NaN when not computed.
pub const FIT_FIELDS: [&str; 18] = [
    "rms",
    "chi2_dof",
    "search_rms",
    "rms_grid",
    "measurements",
    "amplitude",
    "data_scale",
    "chi2_weighted",
    "chi2_p",
    "runs_p",
    "lack_of_fit",
    "aicc",
    "bic",
    "rank",
    "weight",
    "cv_rms",
    "cosine_rms",
    "cube_root",
];

/// The fields each parameter `p` gets after its value `p`, as `{p}_{field}`:
/// the headline 68% and 95% intervals, the Jacobian's sd, the flags.
pub const PARAMETER_FIELDS: [&str; 6] = ["lo68", "hi68", "lo95", "hi95", "sd", "flags"];

/// The kind of field `name` (a name of [`FIT_FIELDS`] or
/// [`PARAMETER_FIELDS`]): `measurements` is a count, `flags` flags, the
/// rest reals.
fn kind(name: &str) -> FieldKind {
    match name {
        "measurements" => FieldKind::Count,
        "flags" => FieldKind::Flags,
        _ => FieldKind::Real,
    }
}

/// The key columns the CSV file puts before the fields.
pub const CSV_KEY: [&str; 2] = ["set", "model"];

/// The fields of fits of some models: their names and kinds, and each
/// fit's row of numbers.
///
/// ```
/// use laminar_brdf_fit::Model;
/// use laminar_brdf_io::fits::BatchRow;
///
/// let row = BatchRow::new(&[Model::Exp]);
/// let names = row.names();
/// assert_eq!(names[0], "rms");
/// assert!(names.contains(&"n_lo68".to_string()));
/// assert_eq!(names.len(), row.kinds().len());
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct BatchRow {
    params: Vec<Param>,
    rh_params: Vec<Param>,
}

impl BatchRow {
    /// The fields of fits of `models` (the parameters of them all, in the
    /// models' order).
    pub fn new(models: &[Model]) -> Self {
        let params = all_params(models.iter().copied());
        let rh_params = Model::RhExp
            .free_params()
            .iter()
            .copied()
            .filter(|p| params.contains(p) && models.iter().any(|m| m.correlation().is_some()))
            .collect();
        Self { params, rh_params }
    }

    /// The field names, in order.
    pub fn names(&self) -> Vec<String> {
        let mut names: Vec<String> = FIT_FIELDS.iter().map(|n| n.to_string()).collect();
        names.push("rh_rms".into());
        names.extend(self.rh_params.iter().map(|p| format!("rh_{p}")));
        for p in &self.params {
            names.push(p.to_string());
            names.extend(PARAMETER_FIELDS.iter().map(|f| format!("{p}_{f}")));
        }
        names
    }

    /// The fields' kinds, in the order of [`BatchRow::names`].
    pub fn kinds(&self) -> Vec<FieldKind> {
        let mut kinds: Vec<FieldKind> = FIT_FIELDS.into_iter().map(kind).collect();
        kinds.push(FieldKind::Real);
        kinds.extend(self.rh_params.iter().map(|_| FieldKind::Real));
        for _ in &self.params {
            kinds.push(FieldKind::Real);
            kinds.extend(PARAMETER_FIELDS.into_iter().map(kind));
        }
        kinds
    }

    /// Number of fields.
    pub fn width(&self) -> usize {
        FIT_FIELDS.len()
            + 1
            + self.rh_params.len()
            + self.params.len() * (1 + PARAMETER_FIELDS.len())
    }

    /// The row of `fit`, appended to `out` (its [`BatchRow::width`] numbers):
    /// values of [`Fit::estimate`] (refined when refined), NaN where not
    /// computed, not a parameter of the fit's model, or not identified
    /// ([`Fit::not_identified`]; the flags say so).
    pub fn push_row(&self, fit: &Fit, out: &mut Vec<f64>) {
        let nan = f64::NAN;
        let estimate = fit.estimate();
        let adequacy = fit.adequacy;
        let information = fit.information;
        let graphics = estimate.graphics;
        out.extend([
            estimate.rms,
            estimate.chi2.map_or(nan, |c| c.per_dof),
            fit.search_rms,
            fit.best.rms,
            fit.measurements as f64,
            fit.amplitude.unwrap_or(nan),
            estimate.fitted.data_scale,
            fit.chi2_weighted.unwrap_or(nan),
            adequacy.and_then(|a| a.chi2_p).unwrap_or(nan),
            adequacy.and_then(|a| a.runs_p).unwrap_or(nan),
            adequacy.map_or(nan, |a| f64::from(u8::from(a.lack_of_fit))),
            information.and_then(|i| i.aicc).unwrap_or(nan),
            information.map_or(nan, |i| i.bic),
            fit.rank.map_or(nan, |r| r.rank as f64),
            fit.rank.map_or(nan, |r| r.weight),
            fit.cross_validation.map_or(nan, |c| c.rms),
            graphics.map_or(nan, |g| g.cosine_rms),
            graphics.map_or(nan, |g| g.cube_root),
        ]);
        let rh = fit.rh.as_ref();
        out.push(rh.map_or(nan, |e| e.rms));
        let value_in = |pairs: &[(Param, f64)], p: Param| {
            pairs.iter().find(|(q, _)| *q == p).map_or(nan, |&(_, v)| v)
        };
        let rh_pairs = rh.map(|e| e.fitted.params.pairs()).unwrap_or_default();
        out.extend(self.rh_params.iter().map(|&p| value_in(&rh_pairs, p)));
        let pairs = estimate.fitted.params.pairs();
        let ends =
            |i: Option<laminar_brdf_fit::profile::Interval>| i.map_or([nan; 2], |i| [i.lo, i.hi]);
        for &p in &self.params {
            // A value the data do not determine is not stated (its flags
            // say why), as in every other output.
            out.push(if fit.not_identified(p) {
                nan
            } else {
                value_in(&pairs, p)
            });
            let parameter = fit.parameters.iter().find(|q| q.name == p);
            out.extend(ends(parameter.and_then(|q| q.interval68)));
            out.extend(ends(parameter.and_then(|q| q.interval95)));
            out.push(parameter.and_then(|q| q.sd).unwrap_or(nan));
            // A parameter of another model has no flags to state: NaN, as
            // its value; one of the fit's model without flags is 0.
            out.push(match parameter {
                Some(q) => f64::from(Edge::mask(&q.flags)),
                None if fit.model.params().contains(&p) => 0.0,
                None => nan,
            });
        }
    }
}

/// Fits as the batch CSV: the key ([`CSV_KEY`]), then the [`BatchRow`]
/// fields; reals in the shortest text that reads back to the same f64, NaN
/// as an empty cell, counts and flags as integers.
pub struct BatchCsv<W: Write> {
    out: W,
    row: BatchRow,
    kinds: Vec<FieldKind>,
    values: Vec<f64>,
    line: String,
}

impl<W: Write> BatchCsv<W> {
    /// Writes the header of the fields of `models`' fits to `out`.
    ///
    /// # Errors
    /// The writer's error.
    pub fn new(mut out: W, models: &[Model]) -> std::io::Result<Self> {
        let row = BatchRow::new(models);
        let mut header: Vec<String> = CSV_KEY.iter().map(|k| k.to_string()).collect();
        header.extend(row.names());
        writeln!(out, "{}", header.join(","))?;
        Ok(Self {
            out,
            kinds: row.kinds(),
            row,
            values: Vec::new(),
            line: String::new(),
        })
    }

    /// Writes the row of `fit`, the `set`-th row of the values.
    ///
    /// # Errors
    /// The writer's error.
    pub fn write(&mut self, set: usize, fit: &Fit) -> std::io::Result<()> {
        use std::fmt::Write as _;
        self.values.clear();
        self.row.push_row(fit, &mut self.values);
        self.line.clear();
        let _ = write!(self.line, "{set},{}", fit.model);
        for (v, kind) in self.values.iter().zip(&self.kinds) {
            self.line.push(',');
            if v.is_nan() {
                continue;
            }
            let _ = match kind {
                FieldKind::Real => write!(self.line, "{v:?}"),
                _ => write!(self.line, "{}", *v as i64),
            };
        }
        writeln!(self.out, "{}", self.line)
    }

    /// The writer, flushed.
    ///
    /// # Errors
    /// The writer's error on flushing.
    pub fn into_inner(mut self) -> std::io::Result<W> {
        self.out.flush()?;
        Ok(self.out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_kinds_agree_in_number_and_names_are_distinct() {
        for models in [
            &[Model::Exp][..],
            &[Model::Jensen],
            &[Model::Exp, Model::Jensen, Model::OrenNayar],
        ] {
            let row = BatchRow::new(models);
            let names = row.names();
            assert_eq!(names.len(), row.kinds().len());
            assert_eq!(names.len(), row.width());
            let mut sorted = names.clone();
            sorted.sort();
            sorted.dedup();
            assert_eq!(sorted.len(), names.len(), "{names:?}");
        }
    }

    /// Every tied layered model has exp's fields; the untied ones exp's and
    /// σ′/T′'s.
    #[test]
    fn every_layered_model_has_the_same_fields() {
        let exp = BatchRow::new(&[Model::Exp]);
        for model in Model::ALL.into_iter().filter(|m| m.correlation().is_some()) {
            let row = BatchRow::new(&[model]);
            if model.is_untied() {
                let mut names = exp.names();
                names.retain(|n| !row.names().contains(n));
                assert!(names.is_empty(), "{model} lacks {names:?}");
                let extra: Vec<String> = (row.names().into_iter())
                    .filter(|n| !exp.names().contains(n))
                    .collect();
                assert!(!extra.is_empty(), "{model}");
                assert!(
                    extra.iter().all(|n| n.starts_with("sub_slope")),
                    "{model}: {extra:?}"
                );
            } else {
                assert_eq!(row, exp, "{model}");
            }
        }
        assert!(exp.names().contains(&"rh_n".to_string()));
        assert!(!BatchRow::new(&[Model::Jensen])
            .names()
            .iter()
            .any(|n| n.starts_with("rh_") && n != "rh_rms"));
    }
}
