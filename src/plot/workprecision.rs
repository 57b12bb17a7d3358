//! The work–precision figure: error against wall time on log–log axes, one line per
//! formulation × method through its tolerances (loosest first), from a
//! [`WorkPrecisionReport`]. Failed cells and cells without a positive error are left out (a
//! log axis cannot show them; the CSV and the markdown table list them).

use super::{Axis, Dash, Figure, PlotError, Series, Style};
use crate::studies::workprecision::WorkPrecisionReport;

/// Radius of the dot marking each tolerance (pixels).
const DOT: u32 = 4;

/// Largest body-angle error (rad) against median wall time (s), one line per formulation ×
/// method; failed cells are left out.
///
/// Errors: [`PlotError::NoData`] if no cell has both a wall time and a positive error.
pub fn workprecision(report: &WorkPrecisionReport) -> Result<Figure, PlotError> {
    let mut fig = Figure::new(
        format!(
            "Work against precision: {}{} ({:.4} s, median of {} runs)",
            report.model,
            report
                .provenance
                .model
                .overrides
                .iter()
                .map(|o| format!(", {o}"))
                .collect::<String>(),
            report.t_end,
            report.options.repeats
        ),
        Axis {
            label: "wall time (s)".into(),
            log: true,
            range: None,
            min_span: None,
        },
        Axis {
            label: "largest body-angle error (rad)".into(),
            log: true,
            range: None,
            min_span: None,
        },
    );
    let mut colour = 0;
    // One stroke per formulation, one colour per method line: the twelve lines differ in
    // two ways, so that they stay apart where colours are hard to tell.
    for (k, &kind) in report.options.formulations.iter().enumerate() {
        for &method in &report.options.methods {
            let mut points: Vec<(f64, f64, f64)> = report
                .cells
                .iter()
                .filter(|c| c.formulation == kind && c.method == method)
                .filter_map(|c| {
                    let (cost, e) = (c.cost.as_ref()?, c.errors.as_ref()?);
                    (cost.wall_s > 0.0 && e.angle > 0.0).then_some((c.rtol, cost.wall_s, e.angle))
                })
                .collect();
            // Loosest tolerance first: the line runs from cheap and coarse to dear and fine.
            points.sort_by(|a, b| b.0.total_cmp(&a.0));
            let xy: Vec<(f64, f64)> = points.iter().map(|p| (p.1, p.2)).collect();
            if !xy.is_empty() {
                fig.series.push(Series {
                    name: Some(format!("{kind} {method}")),
                    style: Style::Line,
                    colour,
                    dash: Dash::nth(k),
                    points: xy.clone(),
                });
                fig.series.push(Series {
                    name: None,
                    style: Style::Dots { radius: DOT },
                    colour,
                    dash: Dash::Solid,
                    points: xy,
                });
            }
            colour += 1;
        }
    }
    if fig.series.is_empty() {
        return Err(PlotError::NoData {
            path: fig.title.clone(),
            reason: "no cell finished with a measured, positive angle error".into(),
        });
    }
    Ok(fig)
}
