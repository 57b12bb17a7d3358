//! Pictures and animations of a mechanism: `linkdyn animate` and `linkdyn plot mechanism`.
//!
//! The path is run → [`Recording`] (the samples of a result table, interpolated at any time) →
//! [`Instant`] → [`draw`] (one function: the mechanism at an instant as a [`Scene`] in world
//! coordinates) → [`View`] (equal scales, fitted once to the whole run) → [`Picture`] (pixel
//! marks) → a writer: [`raster`] (PNG, GIF frames), [`svg`] (still or animated SVG), [`html`]
//! (one self-contained page with play/pause, a time slider and speed control) and [`gif`].
//!
//! Frames are spaced evenly in simulated time: `fps` frames per second of playback, and by
//! default [`SECONDS_PER_TURN`] of playback per turn of the model's first driver, so that a
//! 250 rpm and a 5000 rpm crank both turn visibly.
//!
//! ```no_run
//! use linkdyn::animate::{Animation, AnimationOptions, write};
//! use linkdyn::plot::Table;
//!
//! let model = linkdyn::model::load("models/farahan2016.toml".as_ref(), &[])?;
//! let run = Table::read("r.csv".as_ref())?;
//! let movie = Animation::build(&model, &run, &AnimationOptions::default())?;
//! write(&movie, "r.html".as_ref())?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod gif;
pub mod html;
pub mod raster;
mod recording;
mod scene;
pub mod svg;

pub use recording::Recording;
pub use scene::{
    BACKGROUND, BODY_COLOURS, Bounds, Colour, DrawOptions, FORCE, GROUND, INK, Instant, Item,
    JOURNAL, Mark, Picture, RAIL_PX, SLIDER_BLOCK_FRACTION, Scene, TRAIL, View, body_colour,
    crank_angle, draw, global, slide, slider_block_side, to_global,
};

use crate::model::Model;
use crate::output::{AtomicFile, OutputError};
use crate::plot::{PlotError, Table};
use std::io::Write;
use std::path::Path;

/// Playback seconds per turn of the first driver at 1× speed (default).
pub const SECONDS_PER_TURN: f64 = 4.0;
/// Instants sampled evenly over the run to fit the view (the same for every frame and every
/// still picture of the run, so they line up).
const FIT_SAMPLES: usize = 240;
/// Fraction of the mechanism's size that the 90th-percentile contact force spans as an arrow.
const FORCE_ARROW_FRACTION: f64 = 0.15;

/// Settings of an animation or a still picture, with their defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct AnimationOptions {
    /// Picture size (px). Default 800 × 600.
    pub size: (u32, u32),
    /// Frames per second of playback. Default 30.
    pub fps: f64,
    /// Playback length at 1× (s). Default [`SECONDS_PER_TURN`] per driver turn, or the run's
    /// own duration without a driver, between 2 and 120 s.
    pub duration: Option<f64>,
    /// Most frames; beyond it the frame rate is lowered. Default 600.
    pub max_frames: usize,
    /// Factor on clearance circles, journal offsets and paths. Default 100.
    pub magnify: f64,
    /// Force arrows: metres of arrow per newton. Default: the 90th percentile of the run's
    /// positive contact forces spans 15 % of the mechanism.
    pub force_scale: Option<f64>,
    /// Title instead of the model name.
    pub title: Option<String>,
}

impl Default for AnimationOptions {
    fn default() -> Self {
        AnimationOptions {
            size: (800, 600),
            fps: 30.0,
            duration: None,
            max_frames: 600,
            magnify: 100.0,
            force_scale: None,
            title: None,
        }
    }
}

/// One frame: its time and picture.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Simulated time (s).
    pub t: f64,
    /// Crank angle (degrees in [0, 360)), see [`crank_angle`].
    pub crank_deg: Option<f64>,
    /// What to draw.
    pub picture: Picture,
}

/// An animation: frames evenly spaced in simulated time, all through one view.
#[derive(Debug, Clone, PartialEq)]
pub struct Animation {
    /// World → pixels, shared by every frame.
    pub view: View,
    /// Frames per second of playback at 1×.
    pub fps: f64,
    /// The frames.
    pub frames: Vec<Frame>,
    /// Title of the page.
    pub title: String,
}

/// What fixes the look of every picture of one run: view, drawing options.
struct Staging<'a> {
    rec: Recording<'a>,
    view: View,
    draw: DrawOptions,
}

impl<'a> Staging<'a> {
    fn new(
        model: &'a Model,
        run: &'a Table,
        options: &AnimationOptions,
    ) -> Result<Self, PlotError> {
        check(options)?;
        let rec = Recording::new(model, run)?;
        let (t0, t1) = rec.span();
        let mut draw = DrawOptions {
            title: options.title.clone().unwrap_or_else(|| model.name.clone()),
            magnify: options.magnify,
            force_scale: None,
        };
        let mut bounds = Bounds::default();
        for k in 0..FIT_SAMPLES {
            let t = t0 + (t1 - t0) * k as f64 / (FIT_SAMPLES - 1) as f64;
            bounds.join(&scene::draw(model, &rec.at(t), &draw).bounds());
        }
        let view = View::fit(&bounds, options.size);
        if model.has_clearance_joints() {
            draw.force_scale = Some(match options.force_scale {
                Some(s) => s,
                None => {
                    let size = if bounds.is_empty() {
                        1.0
                    } else {
                        (bounds.max[0] - bounds.min[0]).max(bounds.max[1] - bounds.min[1])
                    };
                    let mut f = rec.contact_forces();
                    f.sort_by(f64::total_cmp);
                    let reference = f.get(f.len() * 9 / 10).copied().unwrap_or(1.0);
                    FORCE_ARROW_FRACTION * size / reference
                }
            });
        }
        Ok(Staging { rec, view, draw })
    }

    fn frame(&self, t: f64) -> Frame {
        let now = self.rec.at(t);
        Frame {
            t: now.t,
            crank_deg: crank_angle(self.rec.model(), &now.poses),
            picture: scene::draw(self.rec.model(), &now, &self.draw).to_picture(&self.view),
        }
    }
}

/// Refuses options no picture can be made with.
fn check(o: &AnimationOptions) -> Result<(), PlotError> {
    let bad = |option: &str, reason: String| {
        Err(PlotError::Option {
            option: option.into(),
            reason,
        })
    };
    let (w, h) = o.size;
    if !(200..=4000).contains(&w) || !(150..=4000).contains(&h) {
        return bad(
            "--size",
            format!("{w}x{h} px: between 200x150 and 4000x4000 pixels"),
        );
    }
    if !(o.magnify.is_finite() && o.magnify >= 1.0) {
        return bad("--magnify", format!("{} is not a factor ≥ 1", o.magnify));
    }
    if !(o.fps.is_finite() && (1.0..=100.0).contains(&o.fps)) {
        return bad("--fps", format!("{} is not between 1 and 100", o.fps));
    }
    if let Some(d) = o.duration
        && !(d.is_finite() && d > 0.0 && d <= 3600.0)
    {
        return bad("--duration", format!("{d} s is not between 0 and 3600 s"));
    }
    if o.max_frames < 2 {
        return bad(
            "--max-frames",
            format!("{} frames cannot move (at least 2)", o.max_frames),
        );
    }
    if let Some(s) = o.force_scale
        && !(s.is_finite() && s > 0.0)
    {
        return bad("--force-scale", format!("{s} m/N is not positive"));
    }
    Ok(())
}

impl Animation {
    /// The animation of run `run` (a result table of `model`): frames at `options.fps` over the
    /// playback length (see [`AnimationOptions`]), at most `options.max_frames`.
    pub fn build(
        model: &Model,
        run: &Table,
        options: &AnimationOptions,
    ) -> Result<Self, PlotError> {
        let stage = Staging::new(model, run, options)?;
        let (t0, t1) = stage.rec.span();
        let duration = options.duration.unwrap_or_else(|| {
            let turns = model
                .drivers
                .first()
                .map(|d| (t1 - t0) * d.speed.abs() / std::f64::consts::TAU);
            match turns {
                Some(turns) if turns > 0.0 => SECONDS_PER_TURN * turns,
                _ => t1 - t0,
            }
            .clamp(2.0, 120.0)
        });
        let wanted = (duration * options.fps).round() as usize + 1;
        let n = wanted.clamp(2, options.max_frames);
        let fps = (n - 1) as f64 / duration;
        let frames = (0..n)
            .map(|i| stage.frame(t0 + (t1 - t0) * i as f64 / (n - 1) as f64))
            .collect();
        Ok(Animation {
            view: stage.view,
            fps,
            frames,
            title: stage.draw.title.clone(),
        })
    }

    /// Playback length at 1× (s).
    pub fn duration(&self) -> f64 {
        self.frames.len().saturating_sub(1) as f64 / self.fps
    }
}

/// The picture of `model` at time `t` (s) of run `run`: the frame an animation of the run with
/// the same options shows at `t`. Refuses a time outside the run.
pub fn still(
    model: &Model,
    run: &Table,
    t: f64,
    options: &AnimationOptions,
) -> Result<Picture, PlotError> {
    let stage = Staging::new(model, run, options)?;
    let (t0, t1) = stage.rec.span();
    if !(t.is_finite() && t >= t0 && t <= t1) {
        return Err(PlotError::Option {
            option: "--time".into(),
            reason: format!(
                "{} s is outside the run {} ({} to {} s)",
                seconds(t),
                run.file_name(),
                seconds(t0),
                seconds(t1)
            ),
        });
    }
    Ok(stage.frame(t).picture)
}

/// A time for messages: at most 9 decimals, trailing zeros dropped (0.12, not
/// 0.12000000000000001).
pub fn seconds(t: f64) -> String {
    let s = format!("{t:.9}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// An animation file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// One self-contained HTML page (canvas and inline script).
    Html,
    /// Animated SVG (SMIL).
    Svg,
    /// Animated GIF.
    Gif,
}

impl Format {
    /// The format named by the file extension (`.html`/`.htm`, `.svg`, `.gif`, any case).
    pub fn from_path(path: &Path) -> Result<Format, PlotError> {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match ext.as_deref() {
            Some("html" | "htm") => Ok(Format::Html),
            Some("svg") => Ok(Format::Svg),
            Some("gif") => Ok(Format::Gif),
            _ => Err(PlotError::Option {
                option: "--out".into(),
                reason: format!(
                    "{}: unknown animation format (use a .html, .svg or .gif file name)",
                    path.display()
                ),
            }),
        }
    }
}

/// Writes `bytes` to `path` atomically (whole or not at all).
pub(crate) fn write_bytes(path: &Path, bytes: &[u8]) -> Result<(), PlotError> {
    let mut file = AtomicFile::create(path)?;
    file.writer()
        .write_all(bytes)
        .map_err(|e| OutputError::Io {
            path: path.display().to_string(),
            reason: e.to_string(),
        })?;
    file.commit()?;
    Ok(())
}

/// Writes `movie` to `path` in the format its extension names, atomically.
pub fn write(movie: &Animation, path: &Path) -> Result<(), PlotError> {
    let bytes = match Format::from_path(path)? {
        Format::Html => html::page(movie)?.into_bytes(),
        Format::Svg => svg::animated(movie)?.into_bytes(),
        Format::Gif => gif::encode(movie)?,
    };
    write_bytes(path, &bytes)
}

/// Writes the still `picture` to `path` as PNG or SVG (from the extension), atomically.
pub fn write_still(picture: &Picture, path: &Path) -> Result<(), PlotError> {
    let bytes = match crate::plot::Format::from_path(path)? {
        crate::plot::Format::Png => raster::png(picture)?,
        crate::plot::Format::Svg => svg::still(picture).into_bytes(),
    };
    write_bytes(path, &bytes)
}
