//! Fits as a Markdown table.

use super::csv_rows::{opt, params_text};
use super::{FitEntry, ParamValue};
use laminar_brdf_fit::adequacy::Adequacy;
use laminar_brdf_fit::Fit;

/// A Markdown table from a header and rows.
pub fn markdown_table(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut s = format!(
        "| {} |\n|{}\n",
        header.join(" | "),
        " --- |".repeat(header.len())
    );
    for r in rows {
        s += &format!("| {} |\n", r.join(" | "));
    }
    s
}

/// Records as a Markdown table: each fit's reported Δ_RMS and χ²/ν (as
/// the CSV's `rms` and `chi2_dof`), parameters, adequacy (`fit`: `ok` or
/// `lack of fit` with the p-value that says so) and, for the models fitted
/// to one set, their ranking by AICc (`rank`, `ΔAICc`, Akaike `weight`)
/// and cross-validated error (`cv_rms`).
pub fn markdown(records: &[Fit]) -> String {
    let header = [
        "sample", "channel", "model", "rms", "chi2_dof", "params", "fit", "rank", "ΔAICc",
        "weight", "cv_rms",
    ];
    let rows: Vec<Vec<String>> = records
        .iter()
        .map(|r| {
            let e = FitEntry::new(r);
            vec![
                e.sample.clone(),
                e.channel.clone(),
                e.model.name().into(),
                format!("{:.4}", e.rms),
                opt(e.chi2_dof),
                params_text(&e.params, e.model, ParamValue::text),
                e.adequacy.map(adequacy_text).unwrap_or_default(),
                e.rank.map(|k| k.rank.to_string()).unwrap_or_default(),
                e.rank
                    .map(|k| format!("{:.2}", k.delta))
                    .unwrap_or_default(),
                e.rank
                    .map(|k| format!("{:.3}", k.weight))
                    .unwrap_or_default(),
                opt(e.cross_validation.map(|c| c.rms)),
            ]
        })
        .collect();
    markdown_table(&header, &rows)
}

/// `ok`, or `lack of fit` with the smallest p-value below the threshold.
fn adequacy_text(a: Adequacy) -> String {
    if !a.lack_of_fit {
        return "ok".into();
    }
    let p = [a.chi2_p.map(|p| ("χ²", p)), a.runs_p.map(|p| ("runs", p))]
        .into_iter()
        .flatten()
        .min_by(|x, y| x.1.total_cmp(&y.1));
    match p {
        Some((test, p)) => format!("lack of fit ({test} p = {p:.1e})"),
        None => "lack of fit".into(),
    }
}
