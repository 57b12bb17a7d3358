//! The mechanism at one instant: bodies as lines through their points, ground points, joints,
//! and each clearance joint's circle and journal centre magnified (an animation draws one such
//! figure per frame).

use super::{Axis, Figure, PlotError, Series, Style, Table};
use crate::model::{Anchor, Frame, JointKind, Model};

/// Points on a drawn circle.
const CIRCLE_POINTS: usize = 121;

/// Global position of an anchor given the poses (x, y, φ) of the bodies:
/// r = (x, y) + R(φ)·s for a body point s, the point itself on the ground.
fn global(anchor: &Anchor, poses: &[[f64; 3]]) -> Option<[f64; 2]> {
    match anchor.frame {
        Frame::Ground => Some(anchor.local),
        Frame::Body(id) => {
            let [x, y, phi] = *poses.get(id.0)?;
            let (s, c) = phi.sin_cos();
            let [u, v] = anchor.local;
            Some([x + c * u - s * v, y + s * u + c * v])
        }
    }
}

/// The mechanism of `model` at row `row` of a run (`<body>.x`, `<body>.y`, `<body>.phi`
/// columns, m and rad): each body a line through its points (closed when it has three or
/// more), ground points as grey dots, joints as dots, and each clearance joint's clearance
/// circle (radius c) and journal-centre offset e drawn `magnify` times larger around the
/// bearing centre, so that a 0.5 mm clearance is visible on a 0.5 m linkage. Equal scales.
pub fn mechanism(
    model: &Model,
    run: &Table,
    row: usize,
    magnify: f64,
) -> Result<Figure, PlotError> {
    if !(magnify.is_finite() && magnify >= 1.0) {
        return Err(PlotError::Option {
            option: "--magnify".into(),
            reason: format!("{magnify} is not a factor ≥ 1"),
        });
    }
    if row >= run.rows() {
        return Err(PlotError::Option {
            option: "--time".into(),
            reason: format!(
                "row {row} is beyond the {} rows of {}",
                run.rows(),
                run.file_name()
            ),
        });
    }
    let value = |name: String| -> Result<f64, PlotError> {
        run.column(&name)?
            .get(row)
            .copied()
            .ok_or_else(|| PlotError::NoData {
                path: run.path.display().to_string(),
                reason: format!("no row {row} in column `{name}`"),
            })
    };
    let mut poses = Vec::with_capacity(model.bodies.len());
    for b in &model.bodies {
        poses.push([
            value(format!("{}.x", b.name))?,
            value(format!("{}.y", b.name))?,
            value(format!("{}.phi", b.name))?,
        ]);
    }
    let t = run.column("t").ok().and_then(|t| t.get(row).copied());
    let mut fig = Figure::new(
        format!(
            "{} at t = {} s (clearances × {})",
            model.name,
            t.map_or_else(|| "?".to_string(), |t| format!("{t:.4}")),
            crate::simulation::format_number(magnify)
        ),
        Axis::labelled("x (m)"),
        Axis::labelled("y (m)"),
    );
    fig.equal_aspect = true;
    for (k, (b, pose)) in model.bodies.iter().zip(&poses).enumerate() {
        let (s, c) = pose[2].sin_cos();
        let mut pts: Vec<(f64, f64)> = b
            .points
            .iter()
            .map(|(_, [u, v])| (pose[0] + c * u - s * v, pose[1] + s * u + c * v))
            .collect();
        if let (true, Some(&first)) = (pts.len() >= 3, pts.first()) {
            pts.push(first);
        }
        fig.series.push(Series {
            name: Some(b.name.clone()),
            style: Style::Line,
            colour: k,
            points: pts,
        });
    }
    fig.series.push(Series {
        name: Some("ground".into()),
        style: Style::Dots { radius: 6 },
        colour: 5,
        points: model
            .ground_points
            .iter()
            .map(|(_, [x, y])| (*x, *y))
            .collect(),
    });
    let mut joints = Vec::new();
    for j in &model.joints {
        let (Some(a), Some(b)) = (global(&j.a, &poses), global(&j.b, &poses)) else {
            continue;
        };
        match &j.kind {
            JointKind::Clearance(spec) => {
                let r = spec.clearance * magnify;
                fig.series.push(Series {
                    name: None,
                    style: Style::Reference,
                    colour: 0,
                    points: (0..CIRCLE_POINTS)
                        .map(|i| {
                            let q = std::f64::consts::TAU * i as f64 / (CIRCLE_POINTS - 1) as f64;
                            (a[0] + r * q.cos(), a[1] + r * q.sin())
                        })
                        .collect(),
                });
                joints.push((
                    a[0] + magnify * (b[0] - a[0]),
                    a[1] + magnify * (b[1] - a[1]),
                ));
            }
            _ => joints.push((b[0], b[1])),
        }
    }
    fig.series.push(Series {
        name: Some("joints".into()),
        style: Style::Dots { radius: 4 },
        colour: 4,
        points: joints,
    });
    Ok(fig)
}

/// The row of `run` whose `t` is nearest to `time` (s).
pub fn row_at(run: &Table, time: f64) -> Result<usize, PlotError> {
    let t = run.column("t")?;
    t.iter()
        .enumerate()
        .filter(|(_, v)| v.is_finite())
        .min_by(|(_, a), (_, b)| (*a - time).abs().total_cmp(&(*b - time).abs()))
        .map(|(i, _)| i)
        .ok_or_else(|| PlotError::NoData {
            path: run.path.display().to_string(),
            reason: "no data rows".into(),
        })
}
