//! Output of fit records as CSV, JSON or Markdown, and whole-or-nothing file writes.

use crate::fit::{format_value, Estimate, FitRecord};
use std::io::Write;
use std::path::Path;

/// CSV header (a contract: scripts read these columns).
pub const CSV_HEADER: [&str; 14] = [
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
];

fn opt(v: Option<f64>) -> String {
    v.map(|x| format!("{x:.6}")).unwrap_or_default()
}

fn row(r: &FitRecord) -> Vec<String> {
    let chi = r.best.chi2;
    let rh = r.rh.as_ref();
    vec![
        r.sample.clone(),
        r.channel.name().into(),
        r.model.name().into(),
        format!("{:.6}", r.best.rms),
        opt(chi.map(|c| c.per_dof)),
        chi.map(|c| c.used.to_string()).unwrap_or_default(),
        chi.map(|c| c.left_out.to_string()).unwrap_or_default(),
        r.best.params_text(),
        opt(rh.map(|e| e.rms)),
        opt(rh.and_then(|e| e.chi2).map(|c| c.per_dof)),
        rh.map(Estimate::params_text).unwrap_or_default(),
        r.measurements.to_string(),
        r.nonpositive.to_string(),
        format!("{:.6}", r.search_rms),
    ]
}

/// Records as CSV with [`CSV_HEADER`].
pub fn csv(records: &[FitRecord]) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(CSV_HEADER).expect("in-memory write");
    for r in records {
        w.write_record(row(r)).expect("in-memory write");
    }
    String::from_utf8(w.into_inner().expect("in-memory flush")).expect("utf-8")
}

/// Records as a JSON array of objects keyed by [`CSV_HEADER`] (params as objects).
pub fn json(records: &[FitRecord]) -> String {
    let params = |e: &Estimate| {
        serde_json::Value::Object(
            e.params
                .iter()
                .map(|(k, v)| {
                    (
                        k.to_string(),
                        serde_json::json!(format_value(*v).parse::<f64>().unwrap_or(*v)),
                    )
                })
                .collect(),
        )
    };
    let items: Vec<serde_json::Value> = records
        .iter()
        .map(|r| {
            serde_json::json!({
                "sample": r.sample,
                "channel": r.channel.name(),
                "model": r.model.name(),
                "rms": r.best.rms,
                "chi2_dof": r.best.chi2.map(|c| c.per_dof),
                "chi2_used": r.best.chi2.map(|c| c.used),
                "chi2_left_out": r.best.chi2.map(|c| c.left_out),
                "params": params(&r.best),
                "rh_rms": r.rh.as_ref().map(|e| e.rms),
                "rh_chi2_dof": r.rh.as_ref().and_then(|e| e.chi2).map(|c| c.per_dof),
                "rh_params": r.rh.as_ref().map(params),
                "measurements": r.measurements,
                "nonpositive": r.nonpositive,
                "search_rms": r.search_rms,
            })
        })
        .collect();
    serde_json::to_string_pretty(&items).expect("serialisable") + "\n"
}

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

/// Records as a Markdown table.
pub fn markdown(records: &[FitRecord]) -> String {
    let header = ["sample", "channel", "model", "rms", "chi2_dof", "params"];
    let rows: Vec<Vec<String>> = records
        .iter()
        .map(|r| {
            let full = row(r);
            vec![
                full[0].clone(),
                full[1].clone(),
                full[2].clone(),
                format!("{:.4}", r.best.rms),
                opt(r.best.chi2.map(|c| c.per_dof)),
                full[7].clone(),
            ]
        })
        .collect();
    markdown_table(&header, &rows)
}

/// Writes `contents` to `path` whole or not at all (temporary file, then rename).
pub fn write_atomic(path: &Path, contents: &str) -> std::io::Result<()> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("out");
    let tmp = dir.join(format!(".{name}.tmp-{}", std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(contents.as_bytes())?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}
