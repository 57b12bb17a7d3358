//! The mechanism at one instant of a run: the frame that `linkdyn animate` shows at that time
//! (same drawing, [`crate::animate::draw`], and same view), as a still PNG or SVG picture.

use super::{PlotError, Table};
use crate::animate::{AnimationOptions, Picture, still};
use crate::model::Model;

/// The mechanism of `model` at time `time` (s) of run `run` (`<body>.x`, `<body>.y`,
/// `<body>.phi` columns, m and rad, interpolated linearly between samples): bodies, ground
/// points, joints, each clearance joint's clearance circle, journal centre and journal path
/// magnified `magnify` times, contact-force arrows; `size` in pixels, `title` instead of the
/// model name. See [`crate::animate`].
pub fn mechanism(
    model: &Model,
    run: &Table,
    time: f64,
    magnify: f64,
    size: (u32, u32),
    title: Option<String>,
) -> Result<Picture, PlotError> {
    let options = AnimationOptions {
        size,
        magnify,
        title,
        ..AnimationOptions::default()
    };
    still(model, run, time, &options)
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
