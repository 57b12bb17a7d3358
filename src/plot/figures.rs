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
use super::{Axis, Dash, Figure, PlotError, Series, Style, Table};
use crate::model::JointKind;
use std::path::PathBuf;

/// Metres to millimetres, for lengths of the order of a clearance.
const MM_PER_M: f64 = 1e3;
/// Points on the drawn clearance circle (a 360-gon is within 0.004 % of the circle's radius).
const CIRCLE_POINTS: usize = 361;
/// Most driving-frequency multiples marked (and labelled) on a spectrum: beyond about twenty
/// the labels overlap and the lines become a grey wash, so wider ranges mark every k-th.
pub const MAX_MARKS: usize = 20;
/// Default upper frequency of a spectrum, in driving multiples: the harmonics that carry the
/// motion of a linkage with clearance; above, the spectrum is the numerical floor.
pub const DEFAULT_HARMONICS: f64 = 25.0;
/// Smallest span of a Poincaré axis without a known clearance, relative to the largest
/// magnitude on it: a converged point shows as a point, not as its round-off spread.
const MIN_RELATIVE_SPAN: f64 = 1e-3;

/// Lengths (unit m) whose largest magnitude is below this are drawn in mm: clearance-sized
/// numbers (0.0004 m) read better as 0.4 mm.
const MM_BELOW_M: f64 = 1e-2;

fn points(x: &[f64], y: &[f64]) -> Vec<(f64, f64)> {
    x.iter().copied().zip(y.iter().copied()).collect()
}

pub(super) fn scaled_points(x: &[f64], fx: f64, y: &[f64], fy: f64) -> Vec<(f64, f64)> {
    x.iter().zip(y).map(|(a, b)| (a * fx, b * fy)).collect()
}

/// The unit an axis shows for a column in SI `unit` and the factor from the file's SI values to it: mm
/// (× 1000) for lengths whose finite values all lie within ±[`MM_BELOW_M`] m, otherwise the
/// column's own unit (× 1).
pub(super) fn display_unit<'a>(
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
pub(super) fn label_with(name: &str, unit: Option<&str>) -> String {
    match unit {
        Some(u) => format!("{name} ({u})"),
        None => name.to_string(),
    }
}

pub(super) fn no_rows(t: &Table) -> PlotError {
    PlotError::NoData {
        path: t.path.display().to_string(),
        reason: "no data rows".into(),
    }
}

/// Refuses a `--label` list that does not give one label per file.
pub fn check_labels(labels: &[String], tables: &[&Table]) -> Result<(), PlotError> {
    if labels.is_empty() || labels.len() == tables.len() {
        return Ok(());
    }
    let files: Vec<String> = tables.iter().map(|t| t.file_name()).collect();
    Err(PlotError::Option {
        option: "--label".into(),
        reason: format!(
            "expected one label per file, {} ({}), got {}",
            tables.len(),
            files.join(", "),
            labels.len()
        ),
    })
}

/// Names for runs drawn together: what they share (for the title) and what tells each apart
/// (for its legend entry), from the provenance's model and `--set` overrides; the file names
/// where a file has no provenance or two runs read the same.
fn run_names(tables: &[&Table]) -> (Option<String>, Vec<String>) {
    let files = || tables.iter().map(|t| t.file_name()).collect::<Vec<_>>();
    let Some(runs) = tables
        .iter()
        .map(|t| t.run_description())
        .collect::<Option<Vec<_>>>()
    else {
        return (None, files());
    };
    let Some((first_model, first_sets)) = runs.first() else {
        return (None, Vec::new());
    };
    let same_model = runs.iter().all(|(m, _)| m == first_model);
    let common: Vec<String> = first_sets
        .iter()
        .filter(|s| runs.iter().all(|(_, sets)| sets.contains(s)))
        .cloned()
        .collect();
    let names: Vec<String> = runs
        .iter()
        .map(|(model, sets)| {
            let own: Vec<&str> = sets
                .iter()
                .filter(|s| !common.contains(s))
                .map(String::as_str)
                .collect();
            if own.is_empty() || !same_model {
                std::iter::once(model.as_str())
                    .chain(own)
                    .collect::<Vec<_>>()
            } else {
                own
            }
            .join(", ")
        })
        .collect();
    let distinct = names
        .iter()
        .enumerate()
        .all(|(k, n)| !names[..k].contains(n));
    if !distinct && tables.len() > 1 {
        return (None, files());
    }
    let shared = match (same_model, common.is_empty()) {
        (true, true) => Some(first_model.clone()),
        (true, false) => Some(format!("{first_model} with {}", common.join(", "))),
        (false, true) => None,
        (false, false) => Some(format!("with {}", common.join(", "))),
    };
    (shared, names)
}

/// Time histories of `columns` of one or more runs (e.g. a run and the ideal mechanism)
/// against `t`, on the same axes. Each line has its own colour (Okabe–Ito) and each run its own
/// stroke (the first solid, the next dashed, …), drawn in order, so a later run's dashes let an
/// earlier run show where they coincide. Legends and title name the runs by `labels` (one per
/// run, or none), otherwise by the model and `--set` overrides in their provenance.
pub fn series(
    tables: &[&Table],
    columns: &[String],
    labels: &[String],
) -> Result<Figure, PlotError> {
    if columns.is_empty() {
        return Err(PlotError::Option {
            option: "--y".into(),
            reason: "name at least one column".into(),
        });
    }
    check_labels(labels, tables)?;
    // Lengths share one display unit (so that mm and m never share an axis unnoticed); every
    // other column keeps its own.
    let mut lengths = Vec::new();
    for name in columns.iter().filter(|c| unit_of(c) == Some("m")) {
        for t in tables {
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
    let (shared, names) = run_names(tables);
    let names: Vec<String> = if labels.is_empty() {
        names
    } else {
        labels.to_vec()
    };
    // What the runs share names the figure; without anything shared, the runs themselves.
    let what = shared.unwrap_or_else(|| names.join(" vs "));
    let mut fig = Figure::new(
        format!("{}: {what}", columns.join(", ")),
        Axis::labelled(axis_label("t")),
        Axis::labelled(y_label),
    );
    let several_runs = tables.len() > 1;
    for (k, table) in tables.iter().enumerate() {
        if table.rows() == 0 {
            return Err(no_rows(table));
        }
        let t = table.column("t")?;
        let run_name = names.get(k).cloned().unwrap_or_else(|| table.file_name());
        let named_run = several_runs || !labels.is_empty();
        for (j, name) in columns.iter().enumerate() {
            let y = table.column(name)?;
            let factor = units.get(j).map_or(1.0, |u| u.0);
            let legend = match (columns.len() > 1, named_run) {
                (true, true) => Some(format!("{name} ({run_name})")),
                (true, false) => Some(name.clone()),
                (false, true) => Some(run_name.clone()),
                (false, false) => None,
            };
            fig.series.push(Series {
                name: legend,
                style: Style::Line,
                colour: k * columns.len() + j,
                dash: Dash::nth(k),
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
            run.title_name()
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
        dash: Dash::Solid,
        points: circle,
    });
    fig.series.push(Series {
        name: Some("journal centre".into()),
        style: Style::Line,
        colour: 0,
        dash: Dash::Solid,
        points: ex
            .iter()
            .zip(ey)
            .map(|(x, y)| (x * MM_PER_M, y * MM_PER_M))
            .collect(),
    });
    // The circle is a series, so fitted axes always include it; the span is stated for
    // renderers that fit only the data.
    fig.x.min_span = Some(2.0 * c_mm);
    fig.y.min_span = Some(2.0 * c_mm);
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

/// The smallest span (display units) of a Poincaré axis showing `values` (file units) scaled
/// by `factor`, and how it was chosen: the clearance for lengths when it is known, otherwise
/// [`MIN_RELATIVE_SPAN`] of the largest magnitude (`None` when every value is zero).
fn section_span(
    unit: Option<&str>,
    values: &[f64],
    factor: f64,
    display: Option<&str>,
    clearance: Option<f64>,
) -> Option<(f64, String)> {
    if let (Some("m"), Some(c)) = (unit, clearance) {
        let span = c * factor;
        let shown = crate::numbers::format_number(span);
        return Some((
            span,
            format!("{shown} {}, the clearance", display.unwrap_or("m")),
        ));
    }
    let max = values
        .iter()
        .filter(|v| v.is_finite())
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    (max > 0.0).then(|| {
        (
            MIN_RELATIVE_SPAN * max * factor,
            format!("{} % of the largest value", MIN_RELATIVE_SPAN * 100.0),
        )
    })
}

/// A Poincaré section (`turn,t,<outputs>`): one dot per crossing, `y` against `x`. Each fitted
/// axis spans at least the clearance (`clearance`, m, for length columns) or a thousandth of
/// its largest value, and the title says which: a converged section is one point, and
/// autoscaling would magnify its round-off spread (nanometres) to fill the plot.
pub fn poincare(
    table: &Table,
    x: &str,
    y: &str,
    clearance: Option<f64>,
) -> Result<Figure, PlotError> {
    let xs = table.column(x)?;
    let ys = table.column(y)?;
    if table.rows() == 0 {
        return Err(no_rows(table));
    }
    if let Some(c) = clearance.filter(|c| !(c.is_finite() && *c > 0.0)) {
        return Err(PlotError::Option {
            option: "--clearance".into(),
            reason: format!("{c} m is not a positive length"),
        });
    }
    let (fx, ux) = display_unit(unit_of(x), [xs]);
    let (fy, uy) = display_unit(unit_of(y), [ys]);
    let span_x = section_span(unit_of(x), xs, fx, ux, clearance);
    let span_y = section_span(unit_of(y), ys, fy, uy, clearance);
    let note = match (&span_x, &span_y) {
        (Some((_, a)), Some((_, b))) if a == b => format!(" (axes span ≥ {a})"),
        (Some((_, a)), Some((_, b))) => format!(" (x span ≥ {a}; y span ≥ {b})"),
        (Some((_, a)), None) => format!(" (x span ≥ {a})"),
        (None, Some((_, b))) => format!(" (y span ≥ {b})"),
        (None, None) => String::new(),
    };
    let mut fig = Figure::new(
        format!("Poincaré section: {}{note}", table.title_name()),
        Axis::labelled(label_with(x, ux)),
        Axis::labelled(label_with(y, uy)),
    );
    fig.x.min_span = span_x.map(|s| s.0);
    fig.y.min_span = span_y.map(|s| s.0);
    fig.series.push(Series {
        name: None,
        style: Style::Dots { radius: 3 },
        colour: 0,
        dash: Dash::Solid,
        points: scaled_points(xs, fx, ys, fy),
    });
    Ok(fig)
}

/// A bifurcation diagram (`index,<parameter>,turn,<output>`): the observed output at each
/// section crossing against the swept parameter, as small dots. Both axes carry units read
/// from the names (a swept `joints.B.clearance` in mm when clearance-sized).
pub fn bifurcation(table: &Table) -> Result<Figure, PlotError> {
    table.column("index")?;
    table.column("turn")?;
    let (param, p) = table.column_at(1, "<parameter> (2nd column)")?;
    let (value, v) = table.column_at(3, "<output> (4th column)")?;
    if table.rows() == 0 {
        return Err(no_rows(table));
    }
    let (fp, up) = display_unit(unit_of(param), [p]);
    let (fv, uv) = display_unit(unit_of(value), [v]);
    let mut fig = Figure::new(
        format!("Bifurcation diagram: {}", table.title_name()),
        Axis::labelled(label_with(param, up)),
        Axis::labelled(label_with(value, uv)),
    );
    fig.series.push(Series {
        name: None,
        style: Style::Dots { radius: 2 },
        colour: 0,
        dash: Dash::Solid,
        points: scaled_points(p, fp, v, fv),
    });
    Ok(fig)
}

/// How a spectrum is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SpectrumOptions {
    /// Logarithmic amplitude axis.
    pub log: bool,
    /// Driving frequency (Hz): its multiples are marked. Default: the file's
    /// `driving_frequency_hz` provenance setting, if any.
    pub driving_hz: Option<f64>,
    /// Highest frequency drawn (Hz); bins above are left out. Default:
    /// [`DEFAULT_HARMONICS`] × the driving frequency when it is known, otherwise every bin.
    pub f_max: Option<f64>,
}

/// An amplitude spectrum (`frequency_hz,amplitude`) up to `options.f_max`, the amplitude
/// labelled with the observed column and its unit (the `observe` provenance setting); with a
/// driving frequency, dashed lines at its multiples within the range, every k-th where more
/// than [`MAX_MARKS`] would crowd it.
pub fn spectrum(table: &Table, options: &SpectrumOptions) -> Result<Figure, PlotError> {
    let f = table.column("frequency_hz")?;
    let a = table.column("amplitude")?;
    if table.rows() == 0 {
        return Err(no_rows(table));
    }
    let driving_hz = options.driving_hz.or_else(|| {
        table
            .setting("driving_frequency_hz")
            .and_then(|v| v.trim().parse().ok())
            .filter(|v: &f64| v.is_finite() && *v > 0.0)
    });
    if let Some(fd) = options
        .driving_hz
        .filter(|fd| !(fd.is_finite() && *fd > 0.0))
    {
        return Err(PlotError::Option {
            option: "--driving-hz".into(),
            reason: format!("{fd} Hz is not a positive frequency"),
        });
    }
    if let Some(fm) = options.f_max.filter(|fm| !(fm.is_finite() && *fm > 0.0)) {
        return Err(PlotError::Option {
            option: "--fmax".into(),
            reason: format!("expected a positive frequency in Hz, got {fm}"),
        });
    }
    let f_top = f
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    let f_max = options
        .f_max
        .or(driving_hz.map(|fd| DEFAULT_HARMONICS * fd))
        .filter(|&fm| fm < f_top);
    let shown: Vec<(f64, f64)> = points(f, a)
        .into_iter()
        .filter(|(fk, _)| f_max.is_none_or(|fm| *fk <= fm))
        .collect();
    if shown.is_empty() {
        return Err(PlotError::NoData {
            path: table.path.display().to_string(),
            reason: format!(
                "no frequency bin at or below --fmax {} Hz",
                f_max.unwrap_or(f64::NAN)
            ),
        });
    }
    let amplitude = match table.setting("observe") {
        Some(col) => match unit_of(&col) {
            Some(u) => format!("amplitude of {col} ({u})"),
            None => format!("amplitude of {col}"),
        },
        None => "amplitude".to_string(),
    };
    let mut fig = Figure::new(
        format!("Amplitude spectrum: {}", table.title_name()),
        Axis::labelled(axis_label("frequency_hz").replace("frequency_hz", "frequency")),
        Axis {
            label: amplitude,
            log: options.log,
            range: None,
            min_span: None,
        },
    );
    let f_end = f_max.unwrap_or(f_top);
    if let Some(fm) = f_max {
        // The axis ends at the requested frequency, not at the last bin below it.
        let f_start = shown.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
        if f_start < fm {
            fig.x.range = Some((f_start, fm));
        }
    }
    if let Some(fd) = driving_hz {
        // Multiples within the range; every `step`-th so that at most MAX_MARKS are drawn,
        // and the driving frequency itself always.
        let n = (f_end / fd).floor().clamp(0.0, 1e9) as usize;
        let step = n.div_ceil(MAX_MARKS).max(1);
        fig.vertical_marks = (1..=n)
            .filter(|k| *k == 1 || k % step == 0)
            .map(|k| (k as f64 * fd, format!("{k}×")))
            .collect();
    }
    fig.series.push(Series {
        name: None,
        style: Style::Line,
        colour: 0,
        dash: Dash::Solid,
        points: shown,
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
        format!("Phase portrait: {}", table.title_name()),
        Axis::labelled(x_label),
        Axis::labelled(y_label),
    );
    fig.series.push(Series {
        name: None,
        style: Style::Line,
        colour: 0,
        dash: Dash::Solid,
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
            table.title_name()
        ),
        Axis::labelled(axis_label("t")),
        Axis::labelled("λ (1/s)"),
    );
    fig.series.push(Series {
        name: None,
        style: Style::Line,
        colour: 0,
        dash: Dash::Solid,
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
        let options = SpectrumOptions {
            log: true,
            driving_hz: Some(4.0),
            f_max: None,
        };
        let fig = spectrum(&s, &options).map_err(|e| e.to_string());
        let marks: Vec<f64> = fig
            .map(|f| f.vertical_marks.iter().map(|m| m.0).collect())
            .unwrap_or_default();
        assert_eq!(marks, vec![4.0, 8.0, 12.0, 16.0, 20.0, 24.0]);
    }

    #[test]
    fn clearance_sized_lengths_are_shown_in_mm() {
        let run = table("t,B.ex,B.ey,motor.torque\n0,0.0004,-0.0005,3\n1,0,0,4\n");
        let fig = series(&[&run], &["B.ex".into(), "B.ey".into()], &[]).map_err(|e| e.to_string());
        let fig = fig.map(|f| (f.y.label, f.series[1].points.clone()));
        assert_eq!(
            fig,
            Ok(("B.ex, B.ey (mm)".to_string(), vec![(0.0, -0.5), (1.0, 0.0)]))
        );
        let fig = series(&[&run], &["B.ex".into(), "motor.torque".into()], &[]);
        assert_eq!(
            fig.map(|f| f.y.label).map_err(|e| e.to_string()),
            Ok("B.ex (mm), motor.torque (N·m)".to_string())
        );
    }

    #[test]
    fn fmax_drops_the_bins_above_and_marks_stay_few_and_in_range() {
        // 5001 bins to 5 kHz, driving at 1 Hz: --fmax 300 keeps the 301 bins up to 300 Hz and
        // marks every 15th multiple (300 / 20), plus the driving frequency.
        let mut text =
            "# driving_frequency_hz = 1\n# observe = B.fn\nfrequency_hz,amplitude\n".to_string();
        for k in 0..=5000 {
            text += &format!("{k},1\n");
        }
        let s = table(&text);
        let options = SpectrumOptions {
            f_max: Some(300.0),
            ..SpectrumOptions::default()
        };
        let fig = spectrum(&s, &options).map_err(|e| e.to_string());
        let Ok(fig) = fig else {
            panic!("spectrum: {fig:?}");
        };
        assert_eq!(fig.series[0].points.len(), 301, "bins drawn up to 300 Hz");
        assert_eq!(fig.x.range, Some((0.0, 300.0)));
        assert_eq!(fig.y.label, "amplitude of B.fn (N)");
        let marks: Vec<f64> = fig.vertical_marks.iter().map(|m| m.0).collect();
        assert!(
            marks.len() <= MAX_MARKS + 1 && marks.iter().all(|&m| m <= 300.0),
            "{} marks: {marks:?}",
            marks.len()
        );
        assert_eq!(marks.first(), Some(&1.0));
        // Without --fmax the driving frequency from the provenance limits it to 25 × 1 Hz.
        let fig = spectrum(&s, &SpectrumOptions::default()).map(|f| f.series[0].points.len());
        assert_eq!(fig.map_err(|e| e.to_string()), Ok(26));
    }

    #[test]
    fn a_converged_section_keeps_a_stated_minimum_span() {
        // Four crossings 20 nm apart around 0.24 mm: without a clearance the axis spans at
        // least 0.1 % of 0.24 mm; with the 0.5 mm clearance at least 0.5 mm.
        let s = table(
            "turn,t,B.ex,B.ey\n0,0,2.4e-4,1e-4\n1,1,2.40002e-4,1e-4\n2,2,2.4e-4,1.00002e-4\n",
        );
        let fig = poincare(&s, "B.ex", "B.ey", None).map_err(|e| e.to_string());
        let span = fig.as_ref().ok().and_then(|f| f.x.min_span).unwrap_or(0.0);
        assert!((span - 2.40002e-4).abs() < 1e-12, "relative span {span} mm");
        assert!(
            fig.is_ok_and(|f| f.title.contains("(axes span ≥ 0.1 % of the largest value)")),
            "title states the span"
        );
        let fig = poincare(&s, "B.ex", "B.ey", Some(5e-4)).map_err(|e| e.to_string());
        assert_eq!(
            fig.as_ref().map(|f| (f.x.min_span, f.y.min_span)),
            Ok((Some(0.5), Some(0.5)))
        );
        assert!(fig.is_ok_and(|f| f.title.ends_with("(axes span ≥ 0.5 mm, the clearance)")));
    }

    #[test]
    fn legends_name_the_runs_by_model_and_overrides() {
        let a = table(
            "# model models/fourbar.toml sha256 00\n# set drivers.motor.speed_rpm=3500\nt,x\n0,1\n",
        );
        let b = table(
            "# model models/fourbar.toml sha256 00\n# set drivers.motor.speed_rpm=3500\n# set joints.B.ideal=true\nt,x\n0,1\n",
        );
        let fig = series(&[&a, &b], &["x".into()], &[]).map_err(|e| e.to_string());
        let Ok(fig) = fig else {
            panic!("series: {fig:?}");
        };
        assert_eq!(fig.title, "x: fourbar with drivers.motor.speed_rpm=3500");
        let names: Vec<_> = fig.series.iter().map(|s| s.name.clone()).collect();
        assert_eq!(
            names,
            vec![Some("fourbar".into()), Some("joints.B.ideal=true".into())]
        );
        assert_ne!(
            fig.series[0].dash, fig.series[1].dash,
            "runs differ in stroke"
        );
        assert_ne!(fig.series[0].colour, fig.series[1].colour, "and in colour");
        let e = series(&[&a, &b], &["x".into()], &["one".into()]).map_err(|e| e.to_string());
        assert_eq!(
            e.map(|_| ()),
            Err("--label: expected one label per file, 2 (f.csv, f.csv), got 1".to_string())
        );
    }

    #[test]
    fn a_swept_clearance_is_labelled_in_mm() {
        let b = table("index,joints.B.clearance,turn,coupler.phi\n0,0.0001,0,1\n1,0.0002,0,1.1\n");
        let fig = bifurcation(&b).map_err(|e| e.to_string());
        assert_eq!(
            fig.map(|f| (f.x.label, f.series[0].points[1])),
            Ok(("joints.B.clearance (mm)".to_string(), (0.2, 1.1)))
        );
    }
}
