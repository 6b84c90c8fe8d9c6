//! The paper's result tables (Tables II–V) built from fit records, each
//! rendered as Markdown and CSV by one [`Table`] type.

use crate::selection::material;
use laminar_brdf_fit::fitted::format_value;
use laminar_brdf_fit::{Edge, Estimate, Fit, Model, Parameter};
use laminar_brdf_io::fits::markdown_table;

/// A titled table of text cells.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// File stem, e.g. `table2_rms`.
    pub name: &'static str,
    /// Title line.
    pub title: String,
    /// What the numbers are (printed under the title in Markdown).
    pub note: String,
    /// Column names.
    pub header: Vec<String>,
    /// Rows of cells, as many as `header`.
    pub rows: Vec<Vec<String>>,
}

impl Table {
    /// GitHub-flavoured Markdown, title as a heading.
    pub fn markdown(&self) -> String {
        let header: Vec<&str> = self.header.iter().map(String::as_str).collect();
        format!(
            "## {}\n\n{}\n\n{}",
            self.title,
            self.note,
            markdown_table(&header, &self.rows)
        )
    }

    /// CSV with the header row.
    pub fn csv(&self) -> String {
        let mut w = csv::Writer::from_writer(Vec::new());
        w.write_record(&self.header).expect("in-memory write");
        for r in &self.rows {
            w.write_record(r).expect("in-memory write");
        }
        String::from_utf8(w.into_inner().expect("in-memory flush")).expect("utf-8")
    }
}

/// The records of one (sample, channel), in record order.
fn groups(records: &[Fit]) -> Vec<Vec<&Fit>> {
    let mut out: Vec<Vec<&Fit>> = Vec::new();
    for r in records {
        match out
            .iter_mut()
            .find(|g| g[0].sample == r.sample && g[0].channel == r.channel)
        {
            Some(g) => g.push(r),
            None => out.push(vec![r]),
        }
    }
    out
}

/// The estimate of `model` in a group: its own fit, or for `rh-exp` and
/// `rh-gauss` the a = 0 slice of the absorptive fit when that was run instead.
fn estimate<'a>(group: &[&'a Fit], model: Model) -> Option<&'a Estimate> {
    if let Some(r) = group.iter().find(|r| r.model == model) {
        return Some(&r.best);
    }
    let parent = match model {
        Model::RhExp => Model::Exp,
        Model::RhGauss => Model::Gauss,
        _ => return None,
    };
    group
        .iter()
        .find(|r| r.model == parent)
        .and_then(|r| r.rh.as_ref())
}

fn cell(v: Option<f64>) -> String {
    v.map(|x| format!("{x:.4}")).unwrap_or_else(|| "–".into())
}

fn key(group: &[&Fit]) -> Vec<String> {
    let r = group[0];
    vec![
        r.sample.clone(),
        material(&r.sample).to_string(),
        r.channel.clone(),
    ]
}

fn header(rest: &[&str]) -> Vec<String> {
    ["sample", "material", "channel"]
        .iter()
        .chain(rest)
        .map(|s| s.to_string())
        .collect()
}

/// What Δ_RMS is.
const RMS_NOTE: &str = "Δ_RMS = 100·sqrt(Σ_k (D_k − P_k)²)/K (eq. 15): D the measured radiance (BRDF·cos θi) and P the model's prediction, each divided by its max over the K kept (non-specular) measurements.";

/// Table II: `Δ_RMS` (eq. 15) of every model.
pub fn rms_table(records: &[Fit]) -> Table {
    let rows = groups(records)
        .iter()
        .map(|g| {
            let mut row = key(g);
            row.extend(Model::tied().map(|m| cell(estimate(g, m).map(|e| e.rms))));
            row
        })
        .collect();
    Table {
        name: "table2_rms",
        title: "Table II: Δ_RMS (eq. 15) of every model of the paper's search".into(),
        note: RMS_NOTE.into(),
        header: header(&Model::tied().map(Model::name).collect::<Vec<_>>()),
        rows,
    }
}

/// A parameter as a table cell: the refined value (the grid value when not
/// refined) with its 68% interval in brackets (`<` or `>` before an end
/// where the interval stays open within the range searched) and the marks
/// ‡ (grid value at the end of its axis) and † (at a bound of the domain).
fn parameter_cell(p: &Parameter) -> String {
    let v = |x: f64| format!("{x:.3}");
    let interval = p.interval68.map_or(String::new(), |i| {
        let lo = if i.open_below { "<" } else { "" };
        let hi = if i.open_above { ">" } else { "" };
        format!(" [{lo}{}, {hi}{}]", v(i.lo), v(i.hi))
    });
    let mut marks = String::new();
    if p.flags.contains(&Edge::RangeEdge) {
        marks.push('‡');
    }
    if p.flags.contains(&Edge::DomainBound) {
        marks.push('†');
    }
    format!("{}{marks}{interval}", v(p.value()))
}

/// Tables III and IV: the estimated parameters of an absorptive model.
pub fn parameter_table(records: &[Fit], model: Model) -> Table {
    let names = model.params();
    let rows = groups(records)
        .iter()
        .filter_map(|g| {
            let fit = g.iter().find(|r| r.model == model)?;
            let e = fit.estimate();
            let mut row = key(g);
            row.extend(names.iter().map(|&n| {
                match fit.parameters.iter().find(|p| p.name == n) {
                    Some(p) => parameter_cell(p),
                    None => e
                        .fitted
                        .params
                        .value(n)
                        .map(format_value)
                        .unwrap_or_default(),
                }
            }));
            row.push(
                e.fitted
                    .beta_eq8
                    .map(|b| format!("{b:.4}"))
                    .unwrap_or_default(),
            );
            row.push(cell(Some(fit.best.rms)));
            row.push(cell(fit.refined.as_ref().map(|r| r.rms)));
            Some(row)
        })
        .collect();
    let (name, number, label) = if model == Model::Gauss {
        ("table4_gauss_params", "IV", "Gaussian")
    } else {
        ("table3_exp_params", "III", "Exponential")
    };
    Table {
        name,
        title: format!("Table {number}: estimated parameters of the absorptive {label} model"),
        note: format!(
            "Each parameter: the refined value (local refinement from the best grid point, docs/conventions.md §11) and in brackets its 68% interval from the profile of the error surface (noise variance from the residuals); `<` or `>` before an end: the interval does not close within the range searched on that side, so the data do not bound the parameter there. ‡ marks a grid value at the first or last value of its axis (the optimum may lie outside the range searched: not a measurement of that parameter), † a value at a bound of the model's domain (a = 0 or 1, β = 0 or 1, n = 1). slope = σ/T; beta is the balance of the paper normalisation (each term divided by its own max before mixing), beta_eq8 the balance of eq. 8 with the same lobe shape (docs/conventions.md §4). rms is the grid's Δ_RMS, rms_refined the refined one. {RMS_NOTE}"
        ),
        header: header(
            &names
                .iter()
                .map(|p| p.name())
                .chain(["beta_eq8", "rms", "rms_refined"])
                .collect::<Vec<_>>(),
        ),
        rows,
    }
}

/// Table V: `χ²/ν` (eq. 16) of the absorptive models against Ragheb–Hancock.
pub fn chi_square_table(records: &[Fit]) -> Table {
    let models = [Model::Exp, Model::RhExp, Model::Gauss, Model::RhGauss];
    let rows = groups(records)
        .iter()
        .map(|g| {
            let mut row = key(g);
            let chi = |m| estimate(g, m).and_then(|e| e.chi2);
            row.extend(models.iter().map(|&m| cell(chi(m).map(|c| c.per_dof))));
            let left_out = models.iter().find_map(|&m| chi(m).map(|c| c.left_out));
            row.push(left_out.map(|n| n.to_string()).unwrap_or_default());
            row
        })
        .collect();
    Table {
        name: "table5_chi2",
        title: "Table V: χ²/ν (eq. 16), absorptive against Ragheb–Hancock".into(),
        note: "χ²/ν = Σ (P_k − D_k)²/D_k over the measurements with D_k > 0, divided by ν = d − p (d terms used, p = 4 absorptive, 3 Ragheb–Hancock); left_out counts the measurements with D_k ≤ 0.".into(),
        header: header(&["exp", "rh-exp", "gauss", "rh-gauss", "left_out"]),
        rows,
    }
}

/// Tables II–V in paper order.
pub fn paper_tables(records: &[Fit]) -> Vec<Table> {
    vec![
        rms_table(records),
        parameter_table(records, Model::Exp),
        parameter_table(records, Model::Gauss),
        chi_square_table(records),
    ]
}
