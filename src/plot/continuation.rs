//! The figure of `linkdyn plot continuation`: a branch of periodic orbits continued in one
//! parameter (the CSV of `linkdyn continue`), stable stretches solid, unstable ones dashed,
//! its special points marked, optionally over a brute-force bifurcation diagram of the same
//! parameter (the CSV of `linkdyn bifurcation`), so that the two views can be checked against
//! each other.
//!
//! The branch file's columns: `<parameter>`, the output columns at the section, then
//! `period_s,max_abs_mu,stable,impacts_per_period,min_gap_m,residual,special,branch,turn`
//! (docs/periodic_orbits.md, "Continuation"). Each branch and turn of its period is one line
//! (files without `branch` and `turn`, one line). A segment between two consecutive points
//! of a line is drawn solid when both points are stable, dashed otherwise: an unstable point
//! never lies on a solid line.

use super::figures::{display_unit, label_with, no_rows, scaled_points};
use super::units::unit_of;
use super::{Axis, Dash, Figure, Marker, PlotError, Series, Style, Table};
use crate::analysis::orbit::SpecialKind;
use std::path::Path;

/// The columns of a branch file after its state columns (the `special` column is read as
/// words, [`Branch::special`]).
pub const SUMMARY_COLUMNS: [&str; 6] = [
    "period_s",
    "max_abs_mu",
    "stable",
    "impacts_per_period",
    "min_gap_m",
    "residual",
];

/// Palette index of the branch's line (both stabilities: the stroke tells them apart).
const BRANCH_COLOUR: usize = 0;
/// Palette index of the brute-force diagram's dots: grey, under the branch.
const DIAGRAM_COLOUR: usize = 9;
/// Half-width (px) of a special point's marker: larger than the diagram's dots and the
/// line's width, so that it shows over both.
const MARKER_SIZE: u32 = 9;

/// How each kind of special point is marked: shape, palette index, legend name.
fn marker_of(kind: SpecialKind) -> (Marker, usize, &'static str) {
    match kind {
        SpecialKind::Fold => (Marker::Square, 2, "fold"),
        SpecialKind::PeriodDoubling => (Marker::Triangle, 1, "period doubling (PD)"),
        SpecialKind::NeimarkSacker => (Marker::Diamond, 3, "Neimark–Sacker (NS)"),
        SpecialKind::Grazing => (Marker::Cross, 4, "grazing"),
    }
}

/// A branch read from the CSV of `linkdyn continue`.
#[derive(Debug, Clone, PartialEq)]
pub struct Branch {
    /// Every numeric column (all but `special`).
    pub table: Table,
    /// Each row's special point, `None` for an ordinary point.
    pub special: Vec<Option<SpecialKind>>,
}

impl Branch {
    /// Reads a branch file; refuses a file without the continuation columns or with an
    /// unknown special-point name.
    pub fn read(path: &Path) -> Result<Branch, PlotError> {
        let (table, words) = Table::read_with_text(path, "special")?;
        for name in SUMMARY_COLUMNS {
            table.column(name)?;
        }
        let mut special = Vec::with_capacity(words.len());
        for (line, word) in words {
            if word.is_empty() {
                special.push(None);
                continue;
            }
            let Some(kind) = SpecialKind::ALL.into_iter().find(|k| k.name() == word) else {
                let names: Vec<&str> = SpecialKind::ALL.iter().map(|k| k.name()).collect();
                return Err(PlotError::Parse {
                    path: path.display().to_string(),
                    line,
                    reason: format!(
                        "column `special`: `{word}` is not a special point (expected {} or nothing)",
                        names.join(", ")
                    ),
                });
            };
            special.push(Some(kind));
        }
        Ok(Branch { table, special })
    }

    /// The continued parameter: the first column's name.
    pub fn parameter(&self) -> &str {
        self.table.names.first().map_or("", String::as_str)
    }

    /// The output columns at the section: those between the parameter and `period_s`.
    pub fn state_names(&self) -> &[String] {
        let end = self
            .table
            .names
            .iter()
            .position(|n| n == SUMMARY_COLUMNS[0])
            .unwrap_or(self.table.names.len());
        self.table.names.get(1..end).unwrap_or_default()
    }
}

/// The continued branch in the coordinate `coordinate`, over the bifurcation diagram `over`
/// when given. The coordinate defaults to the diagram's column; without a diagram it must be
/// given. Refused: a diagram of another parameter (both named), a coordinate that is not a
/// state column of the branch, or one other than the diagram's.
pub fn continuation(
    branch: &Branch,
    over: Option<&Table>,
    coordinate: Option<&str>,
) -> Result<Figure, PlotError> {
    let table = &branch.table;
    let param = branch.parameter();
    let file = table.file_name();
    let states = branch.state_names();
    let option = |option: &str, reason: String| PlotError::Option {
        option: option.into(),
        reason,
    };
    let coordinate = match (over, coordinate) {
        (Some(diagram), given) => {
            diagram.column("index")?;
            diagram.column("turn")?;
            let (swept, _) = diagram.column_at(1, "<parameter> (2nd column)")?;
            let (observed, _) = diagram.column_at(3, "<output> (4th column)")?;
            if swept != param {
                return Err(option(
                    "--over",
                    format!(
                        "{} sweeps `{swept}`, but the branch in {file} is continued in `{param}`: draw the branch over a diagram of the same parameter",
                        diagram.file_name()
                    ),
                ));
            }
            if let Some(c) = given.filter(|c| *c != observed) {
                return Err(option(
                    "--coordinate",
                    format!(
                        "`{c}` differs from the column `{observed}` of the diagram {}: the branch is drawn in the diagram's coordinate (leave --coordinate out)",
                        diagram.file_name()
                    ),
                ));
            }
            observed
        }
        (None, Some(c)) => c,
        (None, None) => {
            return Err(option(
                "--coordinate",
                format!(
                    "which state column of {file} to draw? expected one of {} (or --over a bifurcation diagram, whose column is taken)",
                    states.join(",")
                ),
            ));
        }
    };
    if !states.iter().any(|s| s == coordinate) {
        return Err(option(
            if over.is_some() {
                "--over"
            } else {
                "--coordinate"
            },
            format!(
                "`{coordinate}` is not a state column of {file} (its state columns: {})",
                states.join(",")
            ),
        ));
    }
    let p = table.column(param)?;
    let v = table.column(coordinate)?;
    let stable = table.column("stable")?;
    if table.rows() == 0 {
        return Err(no_rows(table));
    }
    let diagram = match over {
        Some(d) => Some((d.column_at(1, "")?.1, d.column_at(3, "")?.1)),
        None => None,
    };
    let (fp, up) = display_unit(unit_of(param), [p].into_iter().chain(diagram.map(|d| d.0)));
    let (fv, uv) = display_unit(
        unit_of(coordinate),
        [v].into_iter().chain(diagram.map(|d| d.1)),
    );
    let mut fig = Figure::new(
        format!("Continuation in {param}: {}", table.title_name()),
        Axis::labelled(label_with(param, up)),
        Axis::labelled(label_with(coordinate, uv)),
    );
    if let Some((dp, dv)) = diagram {
        fig.series.push(Series {
            name: Some("brute force (linkdyn bifurcation)".into()),
            style: Style::Dots { radius: 2 },
            colour: DIAGRAM_COLOUR,
            dash: Dash::Solid,
            points: scaled_points(dp, fp, dv, fv),
        });
    }
    let points = scaled_points(p, fp, v, fv);
    // One line per branch and turn of its period (a period-2K branch has two section points
    // per parameter value, as the diagram does); a file without those columns is one line.
    let curves: Vec<Vec<usize>> = match (table.column("branch"), table.column("turn")) {
        (Ok(branch), Ok(turn)) => {
            let mut keys: Vec<(f64, f64)> = Vec::new();
            let mut curves: Vec<Vec<usize>> = Vec::new();
            for (i, key) in branch.iter().copied().zip(turn.iter().copied()).enumerate() {
                match keys.iter().position(|k| *k == key) {
                    Some(c) => curves[c].push(i),
                    None => {
                        keys.push(key);
                        curves.push(vec![i]);
                    }
                }
            }
            curves
        }
        _ => vec![(0..points.len()).collect()],
    };
    let mut lines: [Vec<(f64, f64)>; 2] = [Vec::new(), Vec::new()];
    for curve in &curves {
        let stable_of: Vec<f64> = curve.iter().map(|&i| stable[i]).collect();
        for (runs, line) in stability_runs(&stable_of).iter().zip(lines.iter_mut()) {
            // Runs separated by a non-finite point (which breaks the line): one legend entry
            // per stability.
            for &(a, b) in runs {
                if !line.is_empty() {
                    line.push((f64::NAN, f64::NAN));
                }
                line.extend(curve[a..=b].iter().filter_map(|&i| points.get(i).copied()));
            }
        }
    }
    let [solid, dashed] = lines;
    for (line, dash, name) in [
        (solid, Dash::Solid, "stable"),
        (dashed, Dash::Dashed, "unstable"),
    ] {
        if line.is_empty() {
            continue;
        }
        fig.series.push(Series {
            name: Some(name.into()),
            style: Style::Line,
            colour: BRANCH_COLOUR,
            dash,
            points: line,
        });
    }
    for kind in SpecialKind::ALL {
        let marked: Vec<(f64, f64)> = points
            .iter()
            .zip(&branch.special)
            .filter(|(_, s)| **s == Some(kind))
            .map(|(pt, _)| *pt)
            .collect();
        if marked.is_empty() {
            continue;
        }
        let (shape, colour, name) = marker_of(kind);
        fig.series.push(Series {
            name: Some(name.into()),
            style: Style::Marker {
                shape,
                size: MARKER_SIZE,
            },
            colour,
            dash: Dash::Solid,
            points: marked,
        });
    }
    Ok(fig)
}

/// The stretches of a branch drawn solid and dashed, as inclusive row ranges `(first, last)`:
/// a segment between rows i and i + 1 is solid when both rows are stable (`stable` = 1). A
/// branch of one point is a stretch of that point.
fn stability_runs(stable: &[f64]) -> [Vec<(usize, usize)>; 2] {
    let is_stable = |i: usize| stable.get(i).is_some_and(|s| *s == 1.0);
    let mut runs = [Vec::new(), Vec::new()];
    if stable.len() == 1 {
        runs[usize::from(!is_stable(0))].push((0, 0));
        return runs;
    }
    let mut start = 0;
    for i in 0..stable.len().saturating_sub(1) {
        let solid = is_stable(i) && is_stable(i + 1);
        let next = i + 1 < stable.len() - 1 && is_stable(i + 1) && is_stable(i + 2);
        if i + 1 == stable.len() - 1 || next != solid {
            runs[usize::from(!solid)].push((start, i + 1));
            start = i + 1;
        }
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segments_are_solid_only_between_two_stable_points() {
        // stable, stable, unstable, unstable, stable, stable, stable
        let s = [1.0, 1.0, 0.0, 0.0, 1.0, 1.0, 1.0];
        let [solid, dashed] = stability_runs(&s);
        assert_eq!(solid, vec![(0, 1), (4, 6)]);
        assert_eq!(dashed, vec![(1, 4)]);
        // A lone unstable point dashes both its segments; a lone stable one is not solid.
        let [solid, dashed] = stability_runs(&[1.0, 0.0, 1.0]);
        assert!(solid.is_empty(), "{solid:?}");
        assert_eq!(dashed, vec![(0, 2)]);
        let [solid, dashed] = stability_runs(&[0.0]);
        assert!(solid.is_empty() && dashed == vec![(0, 0)]);
    }
}
