//! Figures (PNG or SVG) from plain data: time histories, the journal-centre orbit in its
//! clearance circle, Poincaré sections, bifurcation diagrams, spectra, phase portraits,
//! Lyapunov histories and continued branches of periodic orbits.
//!
//! The path is data → [`Figure`] → file:
//!
//! * [`Table`] reads a linkdyn CSV result file (`#` provenance lines, a header, numbers);
//! * [`workprecision::workprecision`] draws a work–precision table (error against time);
//! * the builders in [`figures`] turn tables into a [`Figure`]: titles, axis labels with units
//!   ([`axis_label`]), series and marks. They select and scale columns (m → mm for the orbit)
//!   and compute nothing else;
//! * [`render`] draws a figure with `plotters` and writes it atomically (temporary file +
//!   rename, [`crate::output::AtomicFile`]); the format follows the extension (`.png`, `.svg`).
//!
//! Text is drawn with DejaVu Sans embedded in the binary ([`font`]): no system font
//! library is needed.
//!
//! ```no_run
//! use linkdyn::plot::{figures, render, Table};
//!
//! let run = Table::read("r.csv".as_ref())?;
//! let fig = figures::series(&[&run], &["motor.torque".to_string()], &[])?;
//! render(&fig, "torque.png".as_ref())?;
//! # Ok::<(), linkdyn::plot::PlotError>(())
//! ```

pub mod continuation;
mod error;
pub mod figures;
pub mod font;
mod render;
mod table;
mod units;
pub mod wear;
pub mod workprecision;

pub use error::PlotError;
pub use figures::SpectrumOptions;
pub use render::{Format, render, render_to_bytes};
pub use table::Table;
pub use units::{axis_label, unit_of};

/// Default figure size in pixels (PNG; the SVG uses the same user units): readable on a
/// laptop screen at 100 %.
pub const DEFAULT_SIZE: (u32, u32) = (1200, 800);

/// Default size (px, one pixel per point) of tick and legend text; axis labels are 1.2 times
/// and the title 1.5 times as large. 20 px is readable on a 1200×800 figure at 100 %.
pub const DEFAULT_FONT_SIZE: f64 = 20.0;

/// How a line is stroked, so that series stay apart in greyscale print and for readers who
/// cannot tell the colours apart.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Dash {
    /// A continuous line.
    #[default]
    Solid,
    /// Long dashes (12 px on, 8 px off).
    Dashed,
    /// Dots (3 px on, 5 px off).
    Dotted,
    /// Short dashes (6 px on, 6 px off).
    ShortDashed,
}

impl Dash {
    /// The stroke for the `k`-th series of a figure (solid, dashed, dotted, short dashes, again).
    pub fn nth(k: usize) -> Dash {
        [Dash::Solid, Dash::Dashed, Dash::Dotted, Dash::ShortDashed][k % 4]
    }
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Style {
    /// A polyline through the points in order (non-finite points break it).
    Line,
    /// A thin dark-grey line: reference geometry (a clearance circle), drawn under the data.
    Reference,
    /// A filled dot of this radius (pixels) at each point.
    Dots {
        /// Radius in pixels.
        radius: u32,
    },
    /// A marker of this shape at each point: points that stand out from the data (special
    /// points of a branch), each kind with its own shape so that they differ in greyscale.
    Marker {
        /// The shape.
        shape: Marker,
        /// Half the marker's width in pixels.
        size: u32,
    },
}

/// The shape of a [`Style::Marker`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Marker {
    /// A filled square.
    Square,
    /// A filled triangle, point up.
    Triangle,
    /// A filled diamond (a square on its corner, taller than wide).
    Diamond,
    /// An upright cross (×) of two strokes.
    Cross,
}

/// One data series of a figure.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend entry; `None` keeps it out of the legend.
    pub name: Option<String>,
    /// Line or dots.
    pub style: Style,
    /// Colour index into the figure palette; equal indices give equal colours.
    pub colour: usize,
    /// Stroke of a line (dots ignore it).
    pub dash: Dash,
    /// Points (x, y) in axis units; non-finite points are skipped.
    pub points: Vec<(f64, f64)>,
}

/// A horizontal or vertical axis.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Axis {
    /// Label with unit, e.g. `coupler.omega (rad/s)`.
    pub label: String,
    /// Logarithmic scale (only points with a positive coordinate are drawn).
    pub log: bool,
    /// Fixed range; `None` fits the data with a 3 % margin.
    pub range: Option<(f64, f64)>,
    /// Smallest span of a fitted linear axis (axis units): data spread over less is shown
    /// centred in this span, so that a converged point is not magnified to round-off.
    pub min_span: Option<f64>,
}

/// A figure: what to draw, in axis units, with no reference to any file.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// Title above the plot.
    pub title: String,
    /// Horizontal axis.
    pub x: Axis,
    /// Vertical axis.
    pub y: Axis,
    /// Data series, drawn in order.
    pub series: Vec<Series>,
    /// Vertical reference lines (x, label), drawn dashed behind the data.
    pub vertical_marks: Vec<(f64, String)>,
    /// One unit on the x axis is as long as one unit on the y axis (the ranges are widened
    /// to fit the plotting area's shape).
    pub equal_aspect: bool,
    /// Size in pixels (width, height).
    pub size: (u32, u32),
    /// Size (px) of tick and legend text; axis labels and title scale with it.
    pub font_size: f64,
}

impl Figure {
    /// An empty figure with a title and axes, default size.
    pub fn new(title: impl Into<String>, x: Axis, y: Axis) -> Self {
        Figure {
            title: title.into(),
            x,
            y,
            series: Vec::new(),
            vertical_marks: Vec::new(),
            equal_aspect: false,
            size: DEFAULT_SIZE,
            font_size: DEFAULT_FONT_SIZE,
        }
    }

    /// Names the data (every series but reference geometry) after `label`: the one data
    /// series is called `label`, several are called `<their name> (label)`.
    pub fn label_data(&mut self, label: &str) {
        let n = self
            .series
            .iter()
            .filter(|s| s.style != Style::Reference)
            .count();
        for s in self
            .series
            .iter_mut()
            .filter(|s| s.style != Style::Reference)
        {
            s.name = Some(match (&s.name, n) {
                (Some(name), 2..) => format!("{name} ({label})"),
                _ => label.to_string(),
            });
        }
    }
}

impl Axis {
    /// A linear axis fitted to the data.
    pub fn labelled(label: impl Into<String>) -> Self {
        Axis {
            label: label.into(),
            log: false,
            range: None,
            min_span: None,
        }
    }
}
