//! Fits as CSV: one row per fit, from its [`FitEntry`].

use super::{pair_key, FitEntry, ParamValue, ParameterEntry};
use laminar_brdf_fit::fitted::format_value;
use laminar_brdf_fit::model::{all_params, Param};
use laminar_brdf_fit::report::NOT_IDENTIFIED;
use laminar_brdf_fit::{Edge, Fit, Model};
use std::collections::BTreeMap;
use std::io::Write;

/// The first columns of the CSV (a contract: scripts read these columns);
/// [`csv_header`] adds the refinement's.
pub const CSV_HEADER: [&str; 15] = [
    "sample",
    "channel",
    "model",
    "rms",
    "chi2_dof",
    "chi2_used",
    "chi2_left_out",
    "params",
    "rh_rms",
    "rh_chi2_dof",
    "rh_params",
    "measurements",
    "nonpositive",
    "search_rms",
    "edges",
];

/// The columns each parameter gets, after its name and `_`.
pub const PARAMETER_COLUMNS: [&str; 12] = [
    "refined",
    "lo68",
    "hi68",
    "lo95",
    "hi95",
    "interval",
    "sd",
    "box_lo",
    "box_hi",
    "released",
    "released_rms",
    "misfit",
];

/// The columns after the parameters' (the objective's, last so that the
/// columns before them keep their places).
pub const FIT_COLUMNS: [&str; 14] = [
    "correlations",
    "trade_offs",
    "objective",
    "amplitude",
    "chi2_weighted",
    "chi2_p",
    "runs_p",
    "lack_of_fit",
    "aicc",
    "bic",
    "rank",
    "cv_rms",
    "cosine_rms",
    "cube_root",
];

/// The full CSV header for fits of `models`: [`CSV_HEADER`], then
/// `rms_grid`, `rms_refined`, then for each parameter of those models
/// `{name}_{column}` for each of [`PARAMETER_COLUMNS`], then [`FIT_COLUMNS`].
pub fn csv_header(models: &[Model]) -> Vec<String> {
    let mut header: Vec<String> = CSV_HEADER.iter().map(|c| c.to_string()).collect();
    header.extend(["rms_grid".to_string(), "rms_refined".to_string()]);
    for name in all_params(models.iter().copied()) {
        header.extend(PARAMETER_COLUMNS.iter().map(|c| format!("{name}_{c}")));
    }
    header.extend(FIT_COLUMNS.iter().map(|c| c.to_string()));
    header
}

pub(super) fn opt(v: Option<f64>) -> String {
    v.map(|x| format!("{x:.6}")).unwrap_or_default()
}

/// A value to 10 significant decimals (parameters and interval ends).
fn value(v: Option<f64>) -> String {
    v.map(format_value).unwrap_or_default()
}

/// `map`'s entries in the order of `model`'s parameters (the maps are
/// sorted by name; the CSV lists parameters in the model's order).
fn in_model_order<V>(map: &BTreeMap<String, V>, model: Model) -> impl Iterator<Item = (Param, &V)> {
    model
        .params()
        .iter()
        .filter_map(move |&p| map.get(p.name()).map(|v| (p, v)))
}

/// `name=value` pairs joined by `;` in the model's order (the `params`
/// columns), each value as `text` writes it.
pub(super) fn params_text<V>(
    map: &BTreeMap<String, V>,
    model: Model,
    text: impl Fn(&V) -> String,
) -> String {
    in_model_order(map, model)
        .map(|(p, v)| format!("{p}={}", text(v)))
        .collect::<Vec<_>>()
        .join(";")
}

/// The pairs `a~b=r` of `map` (correlations, trade-offs) in the model's
/// order of its parameters, r to 3 decimals, joined by `;`.
fn pairs_text(map: &BTreeMap<String, f64>, model: Model) -> String {
    let params = model.params();
    let mut out = Vec::new();
    for (i, a) in params.iter().enumerate() {
        for b in &params[i + 1..] {
            let key = pair_key(*a, *b);
            if let Some(r) = map.get(&key) {
                out.push(format!("{key}={r:.3}"));
            }
        }
    }
    out.join(";")
}

/// The flagged parameters as `name:flag[+flag]` joined by `;`, in the
/// model's order (the `edges` column).
fn edges_text(parameters: &BTreeMap<String, ParameterEntry>, model: Model) -> String {
    in_model_order(parameters, model)
        .filter(|(_, e)| !e.flags.is_empty())
        .map(|(p, e)| {
            let flags: Vec<String> = e.flags.iter().map(Edge::to_string).collect();
            format!("{p}:{}", flags.join("+"))
        })
        .collect::<Vec<_>>()
        .join(";")
}

/// The parameter columns of `p` ([`PARAMETER_COLUMNS`]).
fn parameter_cells(p: Option<&ParameterEntry>) -> Vec<String> {
    let Some(p) = p else {
        return vec![String::new(); PARAMETER_COLUMNS.len()];
    };
    let refined = if p.flags.contains(&Edge::NotIdentified) {
        NOT_IDENTIFIED.to_string()
    } else {
        value(p.refined.and_then(ParamValue::value))
    };
    vec![
        refined,
        value(p.lo68),
        value(p.hi68),
        value(p.lo95),
        value(p.hi95),
        p.interval.map(|s| s.to_string()).unwrap_or_default(),
        p.sd.map(|sd| format!("{sd:.6e}")).unwrap_or_default(),
        value(p.bounds.map(|b| b[0])),
        value(p.bounds.map(|b| b[1])),
        value(p.released.map(|r| r.value)),
        opt(p.released.map(|r| r.rms)),
        opt(p.misfit_ratio),
    ]
}

/// The CSV row of a fit's entry, parameters in the columns of `names`.
fn row(e: &FitEntry, names: &[Param]) -> Vec<String> {
    let mut out = vec![
        e.sample.clone(),
        e.channel.clone(),
        e.model.name().into(),
        format!("{:.6}", e.rms),
        opt(e.chi2_dof),
        e.chi2_used.map(|n| n.to_string()).unwrap_or_default(),
        e.chi2_left_out.map(|n| n.to_string()).unwrap_or_default(),
        params_text(&e.params, e.model, ParamValue::text),
        opt(e.rh_rms),
        opt(e.rh_chi2_dof),
        e.rh_params
            .as_ref()
            .map(|m| params_text(m, e.model, |v| format_value(*v)))
            .unwrap_or_default(),
        e.measurements.to_string(),
        e.nonpositive.to_string(),
        format!("{:.6}", e.search_rms),
        edges_text(&e.parameters, e.model),
        opt(e.rms_grid),
        opt(e.rms_refined),
    ];
    for name in names {
        out.extend(parameter_cells(e.parameters.get(name.name())));
    }
    out.push(pairs_text(&e.correlations, e.model));
    out.push(pairs_text(&e.trade_offs, e.model));
    out.push(e.objective.to_string());
    out.push(e.amplitude.map(|c| format!("{c:.9e}")).unwrap_or_default());
    out.push(opt(e.chi2_weighted));
    let p_value = |p: Option<f64>| p.map(|p| format!("{p:.4e}")).unwrap_or_default();
    out.push(p_value(e.adequacy.and_then(|a| a.chi2_p)));
    out.push(p_value(e.adequacy.and_then(|a| a.runs_p)));
    out.push(
        e.adequacy
            .map(|a| a.lack_of_fit.to_string())
            .unwrap_or_default(),
    );
    out.push(opt(e.information.and_then(|i| i.aicc)));
    out.push(opt(e.information.map(|i| i.bic)));
    out.push(e.rank.map(|r| r.rank.to_string()).unwrap_or_default());
    out.push(opt(e.cross_validation.map(|c| c.rms)));
    let measure = |m: Option<f64>| m.map(|m| format!("{m:.6e}")).unwrap_or_default();
    out.push(measure(e.graphics.map(|g| g.cosine_rms)));
    out.push(measure(e.graphics.map(|g| g.cube_root)));
    out
}

/// Records as CSV with the [`csv_header`] of their models.
pub fn csv(records: &[Fit]) -> String {
    let models: Vec<Model> = records.iter().map(|r| r.model).collect();
    let mut rows = CsvRows::new(Vec::new(), &models).expect("in-memory write");
    for r in records {
        rows.write(r).expect("in-memory write");
    }
    String::from_utf8(rows.into_inner().expect("in-memory flush")).expect("utf-8")
}

/// Records written as CSV rows one at a time (what [`csv()`] gives, without
/// holding every record): the header first, then [`CsvRows::write`] per fit.
pub struct CsvRows<W: Write> {
    writer: csv::Writer<W>,
    names: Vec<Param>,
}

impl<W: Write> CsvRows<W> {
    /// Writes the [`csv_header`] of fits of `models` to `out`.
    ///
    /// # Errors
    /// The writer's error.
    pub fn new(out: W, models: &[Model]) -> std::io::Result<Self> {
        let mut writer = csv::Writer::from_writer(out);
        writer.write_record(csv_header(models))?;
        Ok(Self {
            writer,
            names: all_params(models.iter().copied()),
        })
    }

    /// Writes one record.
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
        self.writer
            .write_record(row(entry, &self.names))
            .map_err(std::io::Error::other)
    }

    /// Flushes and returns the writer.
    ///
    /// # Errors
    /// The writer's error.
    pub fn into_inner(self) -> std::io::Result<W> {
        self.writer.into_inner().map_err(|e| e.into_error())
    }
}
