//! Drawing a [`Figure`] with plotters and writing it as PNG or SVG, atomically.
//!
//! The PNG is drawn into an RGB buffer and encoded by the `png` crate; the SVG is drawn into a
//! string. Either is then written through [`AtomicFile`] (temporary file + rename), so a
//! figure appears whole or not at all.

use super::font::{FAMILY, ensure_registered};
use super::{Dash, Figure, Marker, PlotError, Style};
use crate::output::AtomicFile;
use plotters::coord::Shift;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use std::io::Write;
use std::path::Path;

/// Relative margin around the data range of a fitted linear axis.
const MARGIN: f64 = 0.03;

/// Series colours: the Okabe–Ito palette (Okabe & Ito 2008, "Color Universal Design"), which
/// readers with any common colour-vision deficiency can tell apart, in an order that keeps the
/// first lines dark enough on white (its yellow last); then four of tab20's colours, so that
/// the twelve lines of a work–precision plot (3 formulations × 4 methods) all differ (those
/// lines also differ in stroke, [`super::Dash`]).
const PALETTE: [RGBColor; 12] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
    RGBColor(240, 228, 66),
    RGBColor(140, 86, 75),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(255, 187, 120),
];

/// Text sizes (px) derived from the figure's font size: ticks and legend at the font size,
/// axis labels 1.2 times, the title 1.5 times (the proportions the figures were made with:
/// 20, 24, 30 px).
#[derive(Clone, Copy)]
struct Fonts {
    tick: u32,
    axis: u32,
    title: u32,
}

impl Fonts {
    fn of(fig: &Figure) -> Fonts {
        let size = if fig.font_size.is_finite() && fig.font_size > 0.0 {
            fig.font_size
        } else {
            super::DEFAULT_FONT_SIZE
        };
        let px = |f: f64| (size * f).round().max(1.0) as u32;
        Fonts {
            tick: px(1.0),
            axis: px(1.2),
            title: px(1.5),
        }
    }
}

/// A figure file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Portable Network Graphics, 8-bit RGB.
    Png,
    /// Scalable Vector Graphics (text as `<text>` elements).
    Svg,
}

impl Format {
    /// The format named by the file extension (`.png` or `.svg`, any case).
    pub fn from_path(path: &Path) -> Result<Format, PlotError> {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match ext.as_deref() {
            Some("png") => Ok(Format::Png),
            Some("svg") => Ok(Format::Svg),
            _ => Err(PlotError::Format {
                path: path.display().to_string(),
            }),
        }
    }
}

/// Draws `fig` and writes it to `path` (format from the extension), atomically.
pub fn render(fig: &Figure, path: &Path) -> Result<(), PlotError> {
    let format = Format::from_path(path)?;
    let bytes = render_to_bytes(fig, format).map_err(|e| match e {
        PlotError::Draw { reason, .. } => PlotError::Draw {
            path: path.display().to_string(),
            reason,
        },
        e => e,
    })?;
    let mut file = AtomicFile::create(path)?;
    file.writer()
        .write_all(&bytes)
        .map_err(|e| crate::output::OutputError::Io {
            path: path.display().to_string(),
            reason: e.to_string(),
        })?;
    file.commit()?;
    Ok(())
}

/// Draws `fig` into the bytes of a PNG or SVG file.
pub fn render_to_bytes(fig: &Figure, format: Format) -> Result<Vec<u8>, PlotError> {
    let draw_error = |reason: String| PlotError::Draw {
        path: fig.title.clone(),
        reason,
    };
    if !ensure_registered() {
        return Err(draw_error("the embedded font does not parse".into()));
    }
    let (w, h) = fig.size;
    if w < 200 || h < 150 {
        return Err(PlotError::Option {
            option: "--size".into(),
            reason: format!("{w}×{h} px is too small for a labelled figure (at least 200×150)"),
        });
    }
    match format {
        Format::Png => {
            let mut rgb = vec![0u8; w as usize * h as usize * 3];
            {
                let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
                draw(&root, fig, Joins::Separate).map_err(draw_error)?;
                root.present().map_err(|e| draw_error(e.to_string()))?;
            }
            let mut bytes = Vec::new();
            let mut encoder = png::Encoder::new(&mut bytes, w, h);
            encoder.set_color(png::ColorType::Rgb);
            encoder.set_depth(png::BitDepth::Eight);
            let mut writer = encoder
                .write_header()
                .map_err(|e| draw_error(e.to_string()))?;
            writer
                .write_image_data(&rgb)
                .map_err(|e| draw_error(e.to_string()))?;
            writer.finish().map_err(|e| draw_error(e.to_string()))?;
            Ok(bytes)
        }
        Format::Svg => {
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
                draw(&root, fig, Joins::Polyline).map_err(draw_error)?;
                root.present().map_err(|e| draw_error(e.to_string()))?;
            }
            Ok(svg.into_bytes())
        }
    }
}

/// The data range of an axis: its fixed range, or the finite (positive on a log axis)
/// coordinates widened by [`MARGIN`] (a factor on a log axis); a single value is widened to
/// a visible interval.
fn axis_range(fig: &Figure, vertical: bool) -> Result<(f64, f64), String> {
    let axis = if vertical { &fig.y } else { &fig.x };
    if let Some((lo, hi)) = axis.range {
        // plotters divides by the span: an empty or reversed range has no picture.
        if !(lo.is_finite() && hi.is_finite() && lo < hi && (!axis.log || lo > 0.0)) {
            return Err(format!(
                "the {} range {lo} to {hi} of {} is not an increasing{} interval",
                if vertical { "y" } else { "x" },
                axis.label,
                if axis.log { ", positive" } else { "" }
            ));
        }
        return Ok((lo, hi));
    }
    let usable = |v: f64| v.is_finite() && (!axis.log || v > 0.0);
    // With the other axis fixed (--xlim), fit only the points shown: the window's own
    // amplitude, not the whole run's.
    let other = if vertical { fig.x.range } else { fig.y.range };
    let fit = |window: Option<(f64, f64)>| {
        let shown = |v: f64| window.is_none_or(|(lo, hi)| lo <= v && v <= hi);
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for s in &fig.series {
            for &(x, y) in &s.points {
                let (v, w) = if vertical { (y, x) } else { (x, y) };
                if usable(x) && usable(y) && shown(w) {
                    lo = lo.min(v);
                    hi = hi.max(v);
                }
            }
        }
        (lo, hi)
    };
    // A window with no data in it still gets the axis the data would have.
    let (mut lo, mut hi) = match fit(other) {
        (lo, hi) if lo > hi => fit(None),
        found => found,
    };
    if lo > hi {
        return Err(format!(
            "no {} values to draw on the {} axis ({})",
            if axis.log { "positive" } else { "finite" },
            if vertical { "y" } else { "x" },
            axis.label
        ));
    }
    if axis.log {
        if hi <= lo {
            return Ok((lo / 2.0, hi * 2.0));
        }
        let f = (hi / lo).powf(MARGIN);
        return Ok((lo / f, hi * f));
    }
    if let Some(span) = axis.min_span.filter(|s| s.is_finite() && *s > hi - lo) {
        let centre = (lo + hi) / 2.0;
        (lo, hi) = (centre - span / 2.0, centre + span / 2.0);
    }
    if hi <= lo {
        let pad = if lo == 0.0 { 1.0 } else { 0.05 * lo.abs() };
        return Ok((lo - pad, hi + pad));
    }
    let pad = MARGIN * (hi - lo);
    Ok((lo - pad, hi + pad))
}

/// Widens the ranges so that one unit has the same length in pixels on both axes of a
/// plotting area of `w`×`h` pixels.
fn equalise((x0, x1): (f64, f64), (y0, y1): (f64, f64), w: u32, h: u32) -> [(f64, f64); 2] {
    let (w, h) = (f64::from(w.max(1)), f64::from(h.max(1)));
    let per_px = ((x1 - x0) / w).max((y1 - y0) / h);
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    let (hw, hh) = (per_px * w / 2.0, per_px * h / 2.0);
    [(cx - hw, cx + hw), (cy - hh, cy + hh)]
}

/// A chart builder with the figure's margins; `y_area` is the width (px) left of the plot
/// for the y tick labels and the y-axis label. The x label area holds a tick label and the
/// axis label with gaps (80 px at the default sizes).
fn builder<'a, 'b, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    fonts: Fonts,
    y_area: u32,
) -> ChartBuilder<'a, 'b, DB> {
    let mut b = ChartBuilder::on(area);
    b.margin(20)
        .margin_right(40)
        .x_label_area_size(fonts.tick + 2 * fonts.axis + 12)
        .y_label_area_size(y_area);
    b
}

/// Width (px) for the y tick labels and axis label: the longest of the labels at eleven
/// points across the range, at DejaVu Sans's digit advance (0.64 em), plus the rotated axis
/// label's line and gaps.
fn y_area_width((lo, hi): (f64, f64), log: bool, fonts: Fonts) -> u32 {
    let chars = (0..=10)
        .map(|k| {
            let v = if log {
                lo * (hi / lo).powf(f64::from(k) / 10.0)
            } else {
                lo + (hi - lo) * f64::from(k) / 10.0
            };
            tick_label(v, hi - lo, log).chars().count()
        })
        .max()
        .unwrap_or(4);
    let ticks = (chars as f64 * 0.64 * f64::from(fonts.tick)).ceil() as u32;
    (ticks + 2 * fonts.axis + 20).max(90)
}

/// How a thick polyline is drawn.
#[derive(Clone, Copy, PartialEq)]
enum Joins {
    /// One polyline (SVG: the viewer joins segments and limits miters itself).
    Polyline,
    /// One path per segment: plotters' bitmap backend joins thick polylines with unlimited
    /// miters, which draws long spikes where a signal reverses sharply (an impact).
    Separate,
}

/// Draws the whole figure on `root`.
fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    fig: &Figure,
    joins: Joins,
) -> Result<(), String> {
    let fonts = Fonts::of(fig);
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let area = root
        .margin(12, 0, 0, 0)
        .titled(&fig.title, (FAMILY, fonts.title))
        .map_err(|e| e.to_string())?;
    let mut xr = axis_range(fig, false)?;
    let mut yr = axis_range(fig, true)?;
    // A range the user fixed is kept as given: equal scales then give way.
    let fixed = fig.x.range.is_some() || fig.y.range.is_some();
    if fig.equal_aspect && !fig.x.log && !fig.y.log && !fixed {
        // The plotting area's size depends only on the label areas, not on the ranges.
        let probe = builder(&area, fonts, y_area_width(yr, fig.y.log, fonts))
            .build_cartesian_2d(0.0..1.0, 0.0..1.0)
            .map_err(|e| e.to_string())?;
        let (w, h) = probe.plotting_area().dim_in_pixel();
        [xr, yr] = equalise(xr, yr, w, h);
    }
    let y_area = y_area_width(yr, fig.y.log, fonts);
    let c = Canvas {
        fig,
        joins,
        fonts,
        y_area,
        ranges: (xr, yr),
    };
    let x = xr.0..xr.1;
    let y = yr.0..yr.1;
    match (fig.x.log, fig.y.log) {
        (false, false) => chart(&area, &c, x, y),
        (false, true) => chart(&area, &c, x, y.log_scale()),
        (true, false) => chart(&area, &c, x.log_scale(), y),
        (true, true) => chart(&area, &c, x.log_scale(), y.log_scale()),
    }
}

/// What [`chart`] needs besides the coordinates.
struct Canvas<'f> {
    fig: &'f Figure,
    joins: Joins,
    fonts: Fonts,
    y_area: u32,
    /// The x and y ranges drawn (data outside is clipped).
    ranges: ((f64, f64), (f64, f64)),
}

/// Dash and gap lengths (px) of a stroke; `None` for a solid line.
fn dash_pattern(dash: Dash) -> Option<(u32, u32)> {
    match dash {
        Dash::Solid => None,
        Dash::Dashed => Some((12, 8)),
        Dash::Dotted => Some((3, 5)),
        Dash::ShortDashed => Some((6, 6)),
    }
}

/// Draws axes, marks, series and legend with the given x and y coordinates.
fn chart<DB, X, Y>(area: &DrawingArea<DB, Shift>, c: &Canvas, x: X, y: Y) -> Result<(), String>
where
    DB: DrawingBackend,
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let (fig, fonts) = (c.fig, c.fonts);
    let mut chart = builder(area, fonts, c.y_area)
        .build_cartesian_2d(x, y)
        .map_err(|e| e.to_string())?;
    let (xr, yr) = (chart.x_range(), chart.y_range());
    let x_ticks = |v: &f64| tick_label(*v, xr.end - xr.start, fig.x.log);
    let y_ticks = |v: &f64| tick_label(*v, yr.end - yr.start, fig.y.log);
    chart
        .configure_mesh()
        .x_label_formatter(&x_ticks)
        .y_label_formatter(&y_ticks)
        .x_desc(fig.x.label.as_str())
        .y_desc(fig.y.label.as_str())
        .axis_desc_style((FAMILY, fonts.axis))
        .label_style((FAMILY, fonts.tick))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(210, 210, 210))
        .x_labels(8)
        .y_labels(8)
        .draw()
        .map_err(|e| e.to_string())?;

    let x_range = chart.x_range();
    let y_range = chart.y_range();
    let grey = RGBColor(120, 120, 120);
    // Labels closer than this (px) to the previous one are left out: the lines still show.
    let min_gap = 2 * i32::try_from(fonts.tick).unwrap_or(20);
    let mut last_label_px = i32::MIN / 2;
    for (xm, label) in &fig.vertical_marks {
        if !(x_range.start..=x_range.end).contains(xm) {
            continue;
        }
        chart
            .draw_series(DashedLineSeries::new(
                [(*xm, y_range.start), (*xm, y_range.end)],
                8,
                6,
                grey.stroke_width(1),
            ))
            .map_err(|e| e.to_string())?;
        let px = chart.backend_coord(&(*xm, y_range.end)).0;
        if !label.is_empty() && px - last_label_px >= min_gap {
            last_label_px = px;
            chart
                .draw_series(std::iter::once(Text::new(
                    label.clone(),
                    (*xm, y_range.end),
                    (FAMILY, fonts.tick.saturating_sub(4).max(6))
                        .into_font()
                        .color(&grey),
                )))
                .map_err(|e| e.to_string())?;
        }
    }

    let log_ok = |v: f64, log: bool| v.is_finite() && (!log || v > 0.0);
    let drawable = |&(px, py): &(f64, f64)| log_ok(px, fig.x.log) && log_ok(py, fig.y.log);
    let (cx, cy) = c.ranges;
    let logs = (fig.x.log, fig.y.log);
    let inside = |&(px, py): &(f64, f64)| cx.0 <= px && px <= cx.1 && cy.0 <= py && py <= cy.1;
    let mut any_name = false;
    for s in &fig.series {
        let (colour, width) = match s.style {
            Style::Reference => (RGBColor(60, 60, 60), 1),
            _ => (PALETTE[s.colour % PALETTE.len()], 2),
        };
        let pattern = dash_pattern(s.dash);
        let mut labelled = false;
        match s.style {
            Style::Line | Style::Reference => {
                // Each run of drawable points, clipped to the ranges, is one polyline.
                let runs = s
                    .points
                    .split(|p| !drawable(p))
                    .flat_map(|run| clip_polyline(run, c.ranges, logs));
                for run in runs {
                    if run.is_empty() {
                        continue;
                    }
                    let style = colour.stroke_width(width);
                    let ann = match pattern {
                        Some((on, off)) => chart.draw_series(DashedLineSeries::new(
                            run.iter().copied(),
                            on,
                            off,
                            style,
                        )),
                        None if c.joins == Joins::Separate && width > 1 => chart.draw_series(
                            run.windows(2).map(|w| PathElement::new(w.to_vec(), style)),
                        ),
                        None => chart.draw_series(LineSeries::new(run.iter().copied(), style)),
                    }
                    .map_err(|e| e.to_string())?;
                    if let (Some(name), false) = (&s.name, labelled) {
                        // The legend's sample has the line's stroke; a solid one is a dash
                        // longer than the sample.
                        let (on, off) = pattern.unwrap_or((40, 1));
                        ann.label(name.as_str()).legend(move |(lx, ly)| {
                            DashedPathElement::new(
                                vec![(lx, ly), (lx + 30, ly)],
                                on,
                                off,
                                colour.stroke_width(3),
                            )
                        });
                        labelled = true;
                    }
                }
            }
            Style::Dots { radius } => {
                let ann = chart
                    .draw_series(
                        s.points
                            .iter()
                            .filter(|p| drawable(p) && inside(p))
                            .map(|&p| Circle::new(p, radius, colour.filled())),
                    )
                    .map_err(|e| e.to_string())?;
                if let Some(name) = &s.name {
                    ann.label(name.as_str())
                        .legend(move |(lx, ly)| Circle::new((lx + 15, ly), 5, colour.filled()));
                    labelled = true;
                }
            }
            Style::Marker { shape, size } => {
                let r = i32::try_from(size).unwrap_or(8);
                let shown = s.points.iter().filter(|p| drawable(p) && inside(p));
                let fill = colour.filled();
                let stroke = colour.stroke_width(3);
                // Two strokes for a cross, one filled polygon for the other shapes.
                let cross = |at| {
                    EmptyElement::at(at)
                        + PathElement::new(vec![(-r, -r), (r, r)], stroke)
                        + PathElement::new(vec![(-r, r), (r, -r)], stroke)
                };
                let corners = marker_outline(shape, r);
                let ann = if shape == Marker::Cross {
                    chart.draw_series(shown.map(|&p| cross(p)))
                } else {
                    chart.draw_series(
                        shown.map(|&p| EmptyElement::at(p) + Polygon::new(corners.clone(), fill)),
                    )
                }
                .map_err(|e| e.to_string())?;
                if let Some(name) = &s.name {
                    let ann = ann.label(name.as_str());
                    if shape == Marker::Cross {
                        ann.legend(move |(lx, ly)| {
                            EmptyElement::at((lx + 15, ly))
                                + PathElement::new(vec![(-r, -r), (r, r)], stroke)
                                + PathElement::new(vec![(-r, r), (r, -r)], stroke)
                        });
                    } else {
                        ann.legend(move |(lx, ly)| {
                            EmptyElement::at((lx + 15, ly)) + Polygon::new(corners.clone(), fill)
                        });
                    }
                    labelled = true;
                }
            }
        }
        any_name |= labelled;
    }
    if any_name {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font((FAMILY, fonts.tick))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// The corners (pixel offsets from the centre, y down) of a filled marker `r` pixels from
/// its centre to its side: one SVG `<polygon>` each. A cross has none (it is two strokes).
fn marker_outline(shape: Marker, r: i32) -> Vec<(i32, i32)> {
    let h = r + r / 3;
    match shape {
        Marker::Square => vec![(-r, -r), (r, -r), (r, r), (-r, r)],
        Marker::Triangle => vec![(0, -h), (r, r), (-r, r)],
        Marker::Diamond => vec![(0, -h), (r, 0), (0, h), (-r, 0)],
        Marker::Cross => Vec::new(),
    }
}

/// The parts of the polyline `points` (all drawable) inside the ranges `(x, y)`, each a run
/// of points: plotters does not clip to the plotting area, so a line beyond a fixed axis
/// range would be drawn across the margins and tick labels. A log axis is clipped in log
/// space, where the figure's segments are straight. Points inside are kept exactly; a segment
/// that leaves or enters gets its crossing with the border (Liang–Barsky).
fn clip_polyline(
    points: &[(f64, f64)],
    (xr, yr): ((f64, f64), (f64, f64)),
    (x_log, y_log): (bool, bool),
) -> Vec<Vec<(f64, f64)>> {
    let fwd = |v: f64, log: bool| if log { v.ln() } else { v };
    let inv = |v: f64, log: bool| if log { v.exp() } else { v };
    let to = |(x, y): (f64, f64)| (fwd(x, x_log), fwd(y, y_log));
    let from = |(x, y): (f64, f64)| (inv(x, x_log), inv(y, y_log));
    let (x0, x1) = (fwd(xr.0, x_log), fwd(xr.1, x_log));
    let (y0, y1) = (fwd(yr.0, y_log), fwd(yr.1, y_log));
    let mut runs = Vec::new();
    let mut run: Vec<(f64, f64)> = Vec::new();
    if let [only] = points {
        if x0 <= to(*only).0 && to(*only).0 <= x1 && y0 <= to(*only).1 && to(*only).1 <= y1 {
            runs.push(vec![*only]);
        }
        return runs;
    }
    for w in points.windows(2) {
        let (p, q) = (w[0], w[1]);
        let (a, b) = (to(p), to(q));
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
        let mut visible = true;
        for (pk, qk) in [
            (-dx, a.0 - x0),
            (dx, x1 - a.0),
            (-dy, a.1 - y0),
            (dy, y1 - a.1),
        ] {
            if pk == 0.0 {
                visible &= qk >= 0.0;
            } else {
                let r = qk / pk;
                if pk < 0.0 {
                    t0 = t0.max(r);
                } else {
                    t1 = t1.min(r);
                }
            }
        }
        if !visible || t0 > t1 {
            if !run.is_empty() {
                runs.push(std::mem::take(&mut run));
            }
            continue;
        }
        let at = |t: f64| from((a.0 + t * dx, a.1 + t * dy));
        if t0 > 0.0 || run.is_empty() {
            if !run.is_empty() {
                runs.push(std::mem::take(&mut run));
            }
            run.push(if t0 > 0.0 { at(t0) } else { p });
        }
        run.push(if t1 < 1.0 { at(t1) } else { q });
        if t1 < 1.0 {
            runs.push(std::mem::take(&mut run));
        }
    }
    if !run.is_empty() {
        runs.push(run);
    }
    runs
}

/// A tick label: a linear axis shows as many decimals as its span needs (three significant
/// digits of the span), without trailing zeros and without `-0`; very large or small values
/// and log-axis values below 1e-3 or from 1e4 are in scientific notation (`2.5e-6`).
fn tick_label(v: f64, span: f64, log: bool) -> String {
    let scientific = |v: f64| {
        let s = format!("{v:.2e}");
        // 2.50e-6 → 2.5e-6, 1.00e3 → 1e3
        match s.split_once('e') {
            Some((m, e)) => {
                let m = m.trim_end_matches('0').trim_end_matches('.');
                format!("{m}e{e}")
            }
            None => s,
        }
    };
    let trimmed = |s: String| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if log {
        let a = v.abs();
        return if (1e-3..1e4).contains(&a) {
            trimmed(format!("{v:.3}"))
        } else {
            scientific(v)
        };
    }
    if !(span.is_finite() && span > 0.0) {
        return format!("{v}");
    }
    if v.abs() < span * 1e-9 {
        return "0".into();
    }
    let magnitude = v.abs().max(span);
    if !(1e-4..1e6).contains(&magnitude) {
        return scientific(v);
    }
    let decimals = (2.0 - span.log10().floor()).max(0.0) as usize;
    trimmed(format!("{v:.decimals$}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels_are_short_and_never_minus_zero() {
        assert_eq!(tick_label(-1e-17, 1.0, false), "0");
        assert_eq!(tick_label(0.4, 1.1, false), "0.4");
        assert_eq!(tick_label(-500.0, 650.0, false), "-500");
        assert_eq!(tick_label(0.00025, 0.001, false), "0.00025");
        assert_eq!(tick_label(2.5e-6, 1e-5, false), "2.5e-6");
        assert_eq!(tick_label(1e-5, 1.0, true), "1e-5");
        assert_eq!(tick_label(0.01, 1.0, true), "0.01");
    }

    #[test]
    fn equal_aspect_gives_equal_units_per_pixel_and_keeps_the_data() {
        let [x, y] = equalise((-1.0, 1.0), (-1.0, 1.0), 900, 600);
        let (ux, uy) = ((x.1 - x.0) / 900.0, (y.1 - y.0) / 600.0);
        // Equal to rounding: both are 2/600 computed two ways.
        assert!((ux - uy).abs() < 1e-15, "x {ux} vs y {uy} per px");
        assert!(x.0 <= -1.0 && x.1 >= 1.0 && y.0 <= -1.0 && y.1 >= 1.0);
    }

    #[test]
    fn clipping_keeps_inside_points_and_cuts_at_the_border() {
        let r = ((0.0, 10.0), (0.0, 10.0));
        // In, out across the right border, back in: two runs ending and starting at x = 10.
        let runs = clip_polyline(&[(5.0, 5.0), (15.0, 5.0), (5.0, 7.0)], r, (false, false));
        assert_eq!(
            runs,
            vec![vec![(5.0, 5.0), (10.0, 5.0)], vec![(10.0, 6.0), (5.0, 7.0)]]
        );
        // Wholly outside: nothing; wholly inside: the points themselves.
        assert!(clip_polyline(&[(11.0, 1.0), (12.0, 2.0)], r, (false, false)).is_empty());
        let inside = vec![(1.0, 1.0), (2.0, 3.0), (4.0, 1.0)];
        assert_eq!(clip_polyline(&inside, r, (false, false)), vec![inside]);
        // On a log x axis the crossing is where the figure's straight segment meets 10.
        let runs = clip_polyline(
            &[(1.0, 0.0), (100.0, 2.0)],
            ((1.0, 10.0), r.1),
            (true, false),
        );
        let end = runs
            .first()
            .and_then(|r| r.last())
            .copied()
            .unwrap_or_default();
        assert!(
            (end.0 - 10.0).abs() < 1e-12 && (end.1 - 1.0).abs() < 1e-12,
            "log-axis crossing at {end:?}, expected (10, 1)"
        );
    }

    #[test]
    fn a_minimum_span_widens_a_point_but_not_a_wider_spread() {
        let mut fig = Figure::new(
            "t",
            super::super::Axis::labelled("x"),
            super::super::Axis::labelled("y"),
        );
        fig.series.push(super::super::Series {
            name: None,
            style: Style::Dots { radius: 1 },
            colour: 0,
            dash: Dash::Solid,
            points: vec![(0.2417, 1.0), (0.24170002, 3.0)],
        });
        fig.x.min_span = Some(0.5);
        fig.y.min_span = Some(0.5);
        let x = axis_range(&fig, false).unwrap_or_default();
        // 0.5 around the centre, plus the 3 % margin on each side.
        assert!(
            (x.1 - x.0 - 0.53).abs() < 1e-12,
            "x range {x:?} spans {} instead of 0.53",
            x.1 - x.0
        );
        let y = axis_range(&fig, true).unwrap_or_default();
        assert!(
            (y.0 - 0.94).abs() < 1e-12 && (y.1 - 3.06).abs() < 1e-12,
            "y {y:?}"
        );
    }

    #[test]
    fn formats_from_extension() {
        assert_eq!(
            Format::from_path("a/b.PNG".as_ref()).ok(),
            Some(Format::Png)
        );
        assert_eq!(Format::from_path("b.svg".as_ref()).ok(), Some(Format::Svg));
        assert_eq!(
            Format::from_path("b.pdf".as_ref()).map_err(|e| e.to_string()),
            Err("--out b.pdf: unknown figure format (use a .png or .svg file name)".to_string())
        );
    }
}
