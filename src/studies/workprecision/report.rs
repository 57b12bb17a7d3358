//! The text of a work–precision table: CSV (header row first, then `#` provenance lines, then
//! one row per cell, numbers exact, as the run CSV of [`crate::output`]) and markdown. Plain
//! strings: the caller writes them (atomically).

use super::{Cell, CellErrors, Reference, WorkPrecisionReport};
use crate::numbers::format_number;

/// Columns of the CSV, in order.
pub const CSV_HEADER: [&str; 18] = [
    "formulation",
    "method",
    "rtol",
    "atol",
    "status",
    "wall_s",
    "rhs_evals",
    "jacobian_evals",
    "steps",
    "rejected",
    "angle_error_rad",
    "orbit_error_m",
    "impacts",
    "reference_impacts",
    "impacts_match",
    "impact_time_error_s",
    "peak_force_error_n",
    "note",
];

/// One CSV field, quoted as RFC 4180 says where needed.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) || s.starts_with('#') {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

fn opt<T>(v: Option<T>, f: impl Fn(T) -> String) -> String {
    v.map_or(String::new(), f)
}

/// The exact number, or `-`.
fn dash(v: Option<f64>) -> String {
    v.map_or("-".to_string(), format_number)
}

/// `ok` or `failed`.
fn status(c: &Cell) -> &'static str {
    if c.failure.is_some() { "failed" } else { "ok" }
}

/// The note of a cell: the failure's message, else its remarks.
fn note(c: &Cell) -> String {
    c.failure.clone().unwrap_or_else(|| c.note.clone())
}

/// One line per reference: method, tolerance, cost and its own error.
fn reference_line(r: &Reference) -> String {
    let own = r
        .own_error
        .as_ref()
        .map_or("not measured".to_string(), |e| {
            format!(
                "angle {} rad, orbit {} m, impact time {} s, peak force {} N, impacts {} vs {}",
                format_number(e.angle),
                dash(e.orbit),
                dash(e.impact_time),
                dash(e.peak_force),
                e.impacts,
                e.reference_impacts
            )
        });
    let mut line = format!(
        "reference {}: {} rtol {} ({} impacts, {} RHS evaluations, {} s); own error (vs {}): {own}",
        r.formulation,
        r.method,
        format_number(r.rtol),
        r.impacts.map_or("-".into(), |n| n.to_string()),
        r.cost
            .as_ref()
            .map_or("-".into(), |c| c.stats.rhs_evals.to_string()),
        dash(r.cost.as_ref().map(|c| c.wall_s)),
        r.confirm_method,
    );
    if let Some(f) = &r.failure {
        line.push_str(&format!("; failed: {f}"));
    }
    line
}

/// The CSV text of `report` (module documentation).
pub fn csv_text(report: &WorkPrecisionReport) -> String {
    let mut text = CSV_HEADER.join(",");
    text.push('\n');
    let mut lines = report.provenance.lines();
    lines.extend(report.references.iter().map(reference_line));
    for line in lines {
        text.push_str("# ");
        text.push_str(&crate::simulation::escape_line(&line));
        text.push('\n');
    }
    for c in &report.cells {
        let e = c.errors.as_ref();
        let cost = c.cost.as_ref();
        let fields = [
            c.formulation.to_string(),
            c.method.to_string(),
            format_number(c.rtol),
            format_number(c.atol),
            status(c).to_string(),
            opt(cost, |k| format_number(k.wall_s)),
            opt(cost, |k| k.stats.rhs_evals.to_string()),
            opt(cost, |k| k.stats.jacobian_evals.to_string()),
            opt(cost, |k| k.stats.steps.to_string()),
            opt(cost, |k| k.stats.rejected.to_string()),
            opt(e, |e| format_number(e.angle)),
            opt(e.and_then(|e| e.orbit), format_number),
            opt(e, |e| e.impacts.to_string()),
            opt(e, |e| e.reference_impacts.to_string()),
            opt(e, |e| e.impacts_match.to_string()),
            opt(e.and_then(|e| e.impact_time), format_number),
            opt(e.and_then(|e| e.peak_force), format_number),
            note(c),
        ];
        let row: Vec<String> = fields.iter().map(|f| csv_field(f)).collect();
        text.push_str(&row.join(","));
        text.push('\n');
    }
    text
}

/// Three significant digits, or `–`.
fn sci(v: Option<f64>) -> String {
    v.map_or("–".to_string(), |x| format!("{x:.2e}"))
}

/// A markdown table cell: no `|` or line break may end it early.
fn md_cell(s: &str) -> String {
    s.replace('|', "\\|").replace(['\n', '\r'], " ")
}

fn errors_columns(e: Option<&CellErrors>) -> [String; 5] {
    [
        sci(e.map(|e| e.angle)),
        sci(e.and_then(|e| e.orbit)),
        e.map_or("–".to_string(), |e| {
            format!(
                "{}{}",
                e.impacts,
                if e.impacts_match {
                    String::new()
                } else {
                    format!(" (ref {})", e.reference_impacts)
                }
            )
        }),
        sci(e.and_then(|e| e.impact_time)),
        sci(e.and_then(|e| e.peak_force)),
    ]
}

/// The markdown text of `report`: provenance, references with their own error, and one table
/// row per cell (failed cells with their reason).
pub fn markdown_text(report: &WorkPrecisionReport) -> String {
    let mut text = format!(
        "# Work against precision: {}\n\n{} samples every {} s to t_end = {} s; wall time = median of {} runs.\n\n",
        report.model,
        report.options.samples,
        format_number(report.dt),
        format_number(report.t_end),
        report.options.repeats
    );
    text.push_str("```text\n");
    for line in report.provenance.lines() {
        text.push_str(&line);
        text.push('\n');
    }
    text.push_str("```\n\n## References\n\n");
    text.push_str("| formulation | method | rtol | impacts | RHS | wall s | own error: angle (rad) | orbit (m) | impacts (confirm) | impact t (s) | peak F (N) | note |\n");
    text.push_str("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
    for r in &report.references {
        let [angle, orbit, impacts, time, force] = errors_columns(r.own_error.as_ref());
        text.push_str(&format!(
            "| {} | {} vs {} | {:.0e} | {} | {} | {} | {angle} | {orbit} | {impacts} | {time} | {force} | {} |\n",
            r.formulation,
            r.method,
            r.confirm_method,
            r.rtol,
            opt(r.impacts, |n| n.to_string()),
            opt(r.cost.as_ref(), |c| c.stats.rhs_evals.to_string()),
            opt(r.cost.as_ref(), |c| format!("{:.3}", c.wall_s)),
            md_cell(r.failure.as_deref().unwrap_or(""))
        ));
    }
    text.push_str("\n## Cells\n\n");
    text.push_str("| formulation | method | rtol | status | wall ms | RHS | Jac | angle err (rad) | orbit err (m) | impacts | impact t err (s) | peak F err (N) | note |\n");
    text.push_str("|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
    for c in &report.cells {
        let [angle, orbit, impacts, time, force] = errors_columns(c.errors.as_ref());
        let cost = c.cost.as_ref();
        text.push_str(&format!(
            "| {} | {} | {:.0e} | {} | {} | {} | {} | {angle} | {orbit} | {impacts} | {time} | {force} | {} |\n",
            c.formulation,
            c.method,
            c.rtol,
            status(c),
            opt(cost, |k| format!("{:.2}", 1e3 * k.wall_s)),
            opt(cost, |k| k.stats.rhs_evals.to_string()),
            opt(cost, |k| k.stats.jacobian_evals.to_string()),
            md_cell(&note(c))
        ));
    }
    text
}
