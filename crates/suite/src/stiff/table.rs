//! The suite's table: stiff.csv and stiff.md.

use crate::stiff::{StiffRow, Verdict};
use signorini_report::csv_field;

/// stiff.csv: one line per case.
pub fn write_csv(path: &std::path::Path, rows: &[StiffRow]) -> std::io::Result<()> {
    signorini_report::write_lines(
        path,
        "case,family,parameter,method,exit_code,outcome,converged,certificate,tolerance,max_error,errors,iterations,contact_points,active,dofs,time_s,any_nan,verdict",
        rows.iter().map(|r| {
        let errors = r
            .errors
            .iter()
            .map(|e| format!("{}={:.3e}/{:.1e}", e.name, e.error, e.tolerance))
            .collect::<Vec<_>>()
            .join(";");
        format!(
            "{},{},{},{},{},{},{},{:.3e},{:.1e},{:.3e},{},{},{},{},{},{:.4},{},{}",
            csv_field(&r.case),
            csv_field(&r.family),
            csv_field(&r.parameter),
            csv_field(&r.method),
            r.exit_code,
            csv_field(&r.outcome),
            r.converged,
            r.certificate,
            r.tolerance,
            r.max_error,
            csv_field(&errors),
            r.iterations,
            r.contact_points,
            r.active,
            r.dofs,
            r.time_s,
            r.any_nan,
            csv_field(&verdict_text(&r.verdict)),
        )
        }),
    )
}

/// "passed" or "FAILED: why".
pub fn verdict_text(v: &Verdict) -> String {
    match v {
        Verdict::Passed => "passed".into(),
        Verdict::Failed(m) => format!("FAILED: {m}"),
    }
}

/// A markdown table cell: `|` escaped, newlines flattened, at most `n`
/// characters.
fn cell(s: &str, n: usize) -> String {
    let s = s.replace('\n', " ");
    let s = if s.chars().count() <= n {
        s
    } else {
        format!("{}…", s.chars().take(n).collect::<String>())
    };
    s.replace('|', "\\|")
}

/// stiff.md: the markdown table of the suite.
pub fn markdown(rows: &[StiffRow]) -> String {
    let mut s = String::from(
        "| case | parameter | outcome | max rel. error (quantity; its tolerance) | certificate / tol | contact points (active) | iterations | time s | verdict |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let worst = r
            .errors
            .iter()
            .max_by(|a, b| a.error.total_cmp(&b.error))
            .map(|e| format!("{:.1e} ({}; {:.1e})", e.error, e.name, e.tolerance))
            .unwrap_or_else(|| "–".into());
        let cert = if r.certificate.is_finite() {
            format!("{:.1e} / {:.0e}", r.certificate, r.tolerance)
        } else {
            "–".into()
        };
        let points = if r.exit_code == 1 {
            "–".to_string()
        } else {
            format!("{} ({})", r.contact_points, r.active)
        };
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} | {:.3} | {} |\n",
            cell(&r.case, 60),
            cell(&r.parameter, 60),
            cell(&r.outcome, 90),
            worst,
            cert,
            points,
            r.iterations,
            r.time_s,
            cell(&verdict_text(&r.verdict), 70),
        ));
    }
    s
}
