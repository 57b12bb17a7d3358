//! One builder per kind of figure: tables in, a [`Figure`] out. They pick columns, label the
//! axes with units and scale lengths to mm where a figure says so; they compute nothing else.
//!
//! The file formats they read (every file: `#` provenance lines, a header row, numbers):
//!
//! | figure | columns |
//! |---|---|
//! | [`series`], [`orbit`] | a run: `t` and the outputs (`coupler.omega`, `B.ex`, …) |
//! | [`poincare`] | `turn,t,<outputs>` |
//! | [`bifurcation`] | `index,<parameter>,turn,<output>` |
//! | [`spectrum`] | `frequency_hz,amplitude` |
//! | [`phase`] | `t,value,rate` |
//! | [`lyapunov`] | `t,lambda` |

use super::units::{axis_label, rate_unit, unit_of};
use super::{Axis, Figure, PlotError, Series, Style, Table};
use crate::model::JointKind;
use std::path::PathBuf;

/// Metres to millimetres, for lengths of the order of a clearance.
const MM_PER_M: f64 = 1e3;
/// Points on the drawn clearance circle (a 360-gon is within 0.004 % of the circle's radius).
const CIRCLE_POINTS: usize = 361;
/// Most driving-frequency multiples marked on a spectrum (beyond, the marks are a grey wash).
const MAX_MARKS: usize = 40;

/// Lengths (unit m) whose largest magnitude is below this are drawn in mm: clearance-sized
/// numbers (0.0004 m) read better as 0.4 mm.
const MM_BELOW_M: f64 = 1e-2;

fn points(x: &[f64], y: &[f64]) -> Vec<(f64, f64)> {
    x.iter().copied().zip(y.iter().copied()).collect()
}

fn scaled_points(x: &[f64], fx: f64, y: &[f64], fy: f64) -> Vec<(f64, f64)> {
    x.iter().zip(y).map(|(a, b)| (a * fx, b * fy)).collect()
}

/// The unit an axis shows for a column in SI `unit` and the factor from the file's SI values to it: mm
/// (× 1000) for lengths whose finite values all lie within ±[`MM_BELOW_M`] m, otherwise the
/// column's own unit (× 1).
fn display_unit<'a>(
    unit: Option<&'static str>,
    data: impl IntoIterator<Item = &'a [f64]>,
) -> (f64, Option<&'static str>) {
    if unit != Some("m") {
        return (1.0, unit);
    }
    let max = data
        .into_iter()
        .flatten()
        .filter(|v| v.is_finite())
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    if max < MM_BELOW_M {
        (MM_PER_M, Some("mm"))
    } else {
        (1.0, unit)
    }
}

/// `name (unit)`, or the bare name without a unit.
fn label_with(name: &str, unit: Option<&str>) -> String {
    match unit {
        Some(u) => format!("{name} ({u})"),
        None => name.to_string(),
    }
}

fn no_rows(t: &Table) -> PlotError {
    PlotError::NoData {
        path: t.path.display().to_string(),
        reason: "no data rows".into(),
    }
}

/// Time histories of `columns` of a run against `t`, optionally with the same columns of a
/// second run (`compare`, e.g. the ideal mechanism) on the same axes; a legend names column
/// and file whenever there is more than one line.
pub fn series(
    run: &Table,
    columns: &[String],
    compare: Option<&Table>,
) -> Result<Figure, PlotError> {
    if columns.is_empty() {
        return Err(PlotError::Option {
            option: "--y".into(),
            reason: "name at least one column".into(),
        });
    }
    let mut tables = vec![run];
    tables.extend(compare);
    let several = columns.len() > 1 || compare.is_some();
    // One display unit for all lines, so that they share the axis.
    // Lengths share one display unit (so that mm and m never share an axis unnoticed); every
    // other column keeps its own.
    let mut lengths = Vec::new();
    for name in columns.iter().filter(|c| unit_of(c) == Some("m")) {
        for t in &tables {
            lengths.push(t.column(name)?);
        }
    }
    let length_unit = display_unit(Some("m"), lengths);
    let units: Vec<(f64, Option<&str>)> = columns
        .iter()
        .map(|c| match unit_of(c) {
            Some("m") => length_unit,
            u => (1.0, u),
        })
        .collect();
    let y_label = match units.first() {
        Some(&(_, Some(u))) if units.iter().all(|v| v.1 == Some(u)) => {
            format!("{} ({u})", columns.join(", "))
        }
        _ => columns
            .iter()
            .zip(&units)
            .map(|(c, u)| label_with(c, u.1))
            .collect::<Vec<_>>()
            .join(", "),
    };
    let mut fig = Figure::new(
        match compare {
            Some(c) => format!(
                "{}: {} vs {}",
                columns.join(", "),
                run.file_name(),
                c.file_name()
            ),
            None => format!("{}: {}", columns.join(", "), run.file_name()),
        },
        Axis::labelled(axis_label("t")),
        Axis::labelled(y_label),
    );
    for (k, table) in tables.iter().enumerate() {
        if table.rows() == 0 {
            return Err(no_rows(table));
        }
        let t = table.column("t")?;
        for (j, name) in columns.iter().enumerate() {
            let y = table.column(name)?;
            let factor = units.get(j).map_or(1.0, |u| u.0);
            fig.series.push(Series {
                name: several.then(|| format!("{name} ({})", table.file_name())),
                style: Style::Line,
                colour: k * columns.len() + j,
                points: scaled_points(t, 1.0, y, factor),
            });
        }
    }
    Ok(fig)
}

/// The journal-centre orbit of clearance joint `joint` — (`<joint>.ex`, `<joint>.ey`) in
/// mm — inside its clearance circle of radius `clearance` (m), with equal scales on both axes.
pub fn orbit(run: &Table, joint: &str, clearance: f64) -> Result<Figure, PlotError> {
    if !(clearance.is_finite() && clearance > 0.0) {
        return Err(PlotError::Option {
            option: "--clearance".into(),
            reason: format!("{clearance} m is not a positive length"),
        });
    }
    let ex = run.column(&format!("{joint}.ex"))?;
    let ey = run.column(&format!("{joint}.ey"))?;
    if run.rows() == 0 {
        return Err(no_rows(run));
    }
    let c_mm = clearance * MM_PER_M;
    let mut fig = Figure::new(
        format!(
            "Journal centre orbit, joint {joint} (c = {} mm): {}",
            crate::numbers::format_number(c_mm),
            run.file_name()
        ),
        Axis::labelled(format!("{joint}.ex (mm)")),
        Axis::labelled(format!("{joint}.ey (mm)")),
    );
    let circle = (0..CIRCLE_POINTS)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / (CIRCLE_POINTS - 1) as f64;
            (c_mm * a.cos(), c_mm * a.sin())
        })
        .collect();
    fig.series.push(Series {
        name: Some("clearance circle".into()),
        style: Style::Reference,
        colour: 1,
        points: circle,
    });
    fig.series.push(Series {
        name: Some("journal centre".into()),
        style: Style::Line,
        colour: 0,
        points: ex
            .iter()
            .zip(ey)
            .map(|(x, y)| (x * MM_PER_M, y * MM_PER_M))
            .collect(),
    });
    fig.equal_aspect = true;
    Ok(fig)
}

/// The radial clearance (m) of joint `joint` in the model named by the run's provenance
/// (see [`model_from_provenance`]).
pub fn clearance_from_provenance(run: &Table, joint: &str) -> Result<f64, PlotError> {
    let fail = |reason: String| PlotError::Clearance {
        path: run.path.display().to_string(),
        joint: joint.to_string(),
        reason,
    };
    let (model, path) =
        model_from_provenance(run).map_err(|e| fail(format!("{e}; give --clearance")))?;
    let Some(id) = model.joint_id(joint) else {
        return Err(fail(format!(
            "the model {} has no such joint",
            path.display()
        )));
    };
    match &model.joint(id).kind {
        JointKind::Clearance(spec) => Ok(spec.clearance),
        other => Err(fail(format!(
            "it is a {} joint in {}, not a clearance joint",
            other.type_name(),
            path.display()
        ))),
    }
}

/// The model named by a result file's provenance (`model PATH` and its `set` overrides) and
/// the path it was loaded from, or why not. A relative model path is tried from the current
/// directory, then from the result file's directory.
pub fn model_from_provenance(run: &Table) -> Result<(crate::model::Model, PathBuf), String> {
    let Some((model_path, sets)) = run.model_source() else {
        return Err("the file names no model (no `# model` line)".into());
    };
    let beside: Option<PathBuf> = run
        .path
        .parent()
        .filter(|_| model_path.is_relative())
        .map(|dir| dir.join(&model_path));
    let path = match beside {
        Some(b) if !model_path.exists() && b.exists() => b,
        _ => model_path,
    };
    match crate::model::load(&path, &sets) {
        Ok(m) => Ok((m, path)),
        Err(e) => Err(format!("cannot load the model {}: {e}", path.display())),
    }
}

/// A Poincaré section (`turn,t,<outputs>`): one dot per crossing, `y` against `x`.
pub fn poincare(table: &Table, x: &str, y: &str) -> Result<Figure, PlotError> {
    let xs = table.column(x)?;
    let ys = table.column(y)?;
    if table.rows() == 0 {
        return Err(no_rows(table));
    }
    let (fx, ux) = display_unit(unit_of(x), [xs]);
    let (fy, uy) = display_unit(unit_of(y), [ys]);
    let mut fig = Figure::new(
        format!("Poincaré section: {}", table.file_name()),
        Axis::labelled(label_with(x, ux)),
        Axis::labelled(label_with(y, uy)),
    );
    fig.series.push(Series {
        name: None,
        style: Style::Dots { radius: 3 },
        colour: 0,
        points: scaled_points(xs, fx, ys, fy),
    });
    Ok(fig)
}

/// A bifurcation diagram (`index,<parameter>,turn,<output>`): the observed output at each
/// section crossing against the swept parameter, as small dots.
pub fn bifurcation(table: &Table) -> Result<Figure, PlotError> {
    table.column("index")?;
    table.column("turn")?;
    let (param, p) = table.column_at(1, "<parameter> (2nd column)")?;
    let (value, v) = table.column_at(3, "<output> (4th column)")?;
    if table.rows() == 0 {
        return Err(no_rows(table));
    }
    let (fv, uv) = display_unit(unit_of(value), [v]);
    let mut fig = Figure::new(
        format!("Bifurcation diagram: {}", table.file_name()),
        Axis::labelled(axis_label(param)),
        Axis::labelled(label_with(value, uv)),
    );
    fig.series.push(Series {
        name: None,
        style: Style::Dots { radius: 2 },
        colour: 0,
        points: scaled_points(p, 1.0, v, fv),
    });
    Ok(fig)
}

/// An amplitude spectrum (`frequency_hz,amplitude`), amplitude on a log scale if `log`; with
/// `driving_hz`, dashed lines at its multiples (the first `MAX_MARKS` within the range).
pub fn spectrum(table: &Table, log: bool, driving_hz: Option<f64>) -> Result<Figure, PlotError> {
    let f = table.column("frequency_hz")?;
    let a = table.column("amplitude")?;
    if table.rows() == 0 {
        return Err(no_rows(table));
    }
    let mut fig = Figure::new(
        format!("Amplitude spectrum: {}", table.file_name()),
        Axis::labelled(axis_label("frequency_hz").replace("frequency_hz", "frequency")),
        Axis {
            label: "amplitude".into(),
            log,
            range: None,
        },
    );
    if let Some(fd) = driving_hz {
        if !(fd.is_finite() && fd > 0.0) {
            return Err(PlotError::Option {
                option: "--driving-hz".into(),
                reason: format!("{fd} Hz is not a positive frequency"),
            });
        }
        let f_max = f
            .iter()
            .copied()
            .filter(|v| v.is_finite())
            .fold(0.0, f64::max);
        fig.vertical_marks = (1..=MAX_MARKS)
            .map(|k| k as f64 * fd)
            .take_while(|&fk| fk <= f_max)
            .enumerate()
            .map(|(k, fk)| (fk, format!("{}×", k + 1)))
            .collect();
    }
    fig.series.push(Series {
        name: None,
        style: Style::Line,
        colour: 0,
        points: points(f, a),
    });
    Ok(fig)
}

/// A phase portrait (`t,value,rate`): rate against value. `value_name` (the output the file
/// was made from, e.g. `B.ex`) gives the axes their names and units.
pub fn phase(table: &Table, value_name: Option<&str>) -> Result<Figure, PlotError> {
    let v = table.column("value")?;
    let r = table.column("rate")?;
    if table.rows() == 0 {
        return Err(no_rows(table));
    }
    let (factor, x_label, y_label) = match value_name {
        Some(name) => match display_unit(unit_of(name), [v]) {
            (f, Some(u)) => (
                f,
                format!("{name} ({u})"),
                format!("d({name})/dt ({})", rate_unit(u)),
            ),
            (f, None) => (f, name.to_string(), format!("d({name})/dt")),
        },
        None => (1.0, "value".to_string(), "rate (value/s)".to_string()),
    };
    let mut fig = Figure::new(
        format!("Phase portrait: {}", table.file_name()),
        Axis::labelled(x_label),
        Axis::labelled(y_label),
    );
    fig.series.push(Series {
        name: None,
        style: Style::Line,
        colour: 0,
        points: scaled_points(v, factor, r, factor),
    });
    Ok(fig)
}

/// A Lyapunov history (`t,lambda`): the running estimate λ_k (1/s) against time.
pub fn lyapunov(table: &Table) -> Result<Figure, PlotError> {
    let t = table.column("t")?;
    let l = table.column("lambda")?;
    if table.rows() == 0 {
        return Err(no_rows(table));
    }
    let mut fig = Figure::new(
        format!(
            "Largest Lyapunov exponent, running estimate: {}",
            table.file_name()
        ),
        Axis::labelled(axis_label("t")),
        Axis::labelled("λ (1/s)"),
    );
    fig.series.push(Series {
        name: None,
        style: Style::Line,
        colour: 0,
        points: points(t, l),
    });
    Ok(fig)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn table(text: &str) -> Table {
        Table::parse(Path::new("f.csv"), text).unwrap_or_else(|e| Table {
            path: PathBuf::from(e.to_string()),
            comments: vec![],
            names: vec![],
            columns: vec![],
        })
    }

    #[test]
    fn orbit_is_in_mm_with_the_circle_at_the_clearance() {
        let run = table("t,B.ex,B.ey\n0,0.0004,0\n1,0,-0.0005\n");
        let fig = orbit(&run, "B", 5e-4).map_err(|e| e.to_string());
        let Ok(fig) = fig else {
            panic!("orbit: {fig:?}");
        };
        assert!(fig.equal_aspect);
        assert_eq!(fig.x.label, "B.ex (mm)");
        // The circle's radius is c in mm; the orbit's points are the file's metres × 1000.
        let r_max = fig.series[0]
            .points
            .iter()
            .map(|(x, y)| x.hypot(*y))
            .fold(0.0, f64::max);
        assert!(
            (r_max - 0.5).abs() < 1e-12,
            "circle radius {r_max} mm vs 0.5"
        );
        assert_eq!(fig.series[1].points, vec![(0.4, 0.0), (0.0, -0.5)]);
    }

    #[test]
    fn driving_multiples_stop_at_the_highest_frequency() {
        let s = table("frequency_hz,amplitude\n0,1\n10,2\n25,0.5\n");
        let fig = spectrum(&s, true, Some(4.0)).map_err(|e| e.to_string());
        let marks: Vec<f64> = fig
            .map(|f| f.vertical_marks.iter().map(|m| m.0).collect())
            .unwrap_or_default();
        assert_eq!(marks, vec![4.0, 8.0, 12.0, 16.0, 20.0, 24.0]);
    }

    #[test]
    fn clearance_sized_lengths_are_shown_in_mm() {
        let run = table("t,B.ex,B.ey,motor.torque\n0,0.0004,-0.0005,3\n1,0,0,4\n");
        let fig = series(&run, &["B.ex".into(), "B.ey".into()], None).map_err(|e| e.to_string());
        let fig = fig.map(|f| (f.y.label, f.series[1].points.clone()));
        assert_eq!(
            fig,
            Ok(("B.ex, B.ey (mm)".to_string(), vec![(0.0, -0.5), (1.0, 0.0)]))
        );
        let fig = series(&run, &["B.ex".into(), "motor.torque".into()], None);
        assert_eq!(
            fig.map(|f| f.y.label).map_err(|e| e.to_string()),
            Ok("B.ex (mm), motor.torque (N·m)".to_string())
        );
    }
}
