//! Drawing a [`Figure`] with plotters and writing it as PNG or SVG, atomically.
//!
//! The PNG is drawn into an RGB buffer and encoded by the `png` crate; the SVG is drawn into a
//! string. Either is then written through [`AtomicFile`] (temporary file + rename), so a
//! figure appears whole or not at all.

use super::font::{FAMILY, ensure_registered};
use super::{Figure, PlotError, Style};
use crate::output::AtomicFile;
use plotters::coord::Shift;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;
use std::io::Write;
use std::path::Path;

/// Font sizes (px): readable on a laptop screen at 1200×800.
const TITLE_PX: u32 = 30;
const AXIS_LABEL_PX: u32 = 24;
const TICK_PX: u32 = 20;
const LEGEND_PX: u32 = 20;
/// Relative margin around the data range of a fitted linear axis.
const MARGIN: f64 = 0.03;

/// Series colours: the "tab10" palette (distinguishable, also in greyscale print), its first
/// six in the order the figures were made with, then black and tab20's light orange, so that
/// the twelve lines of a work–precision plot (3 formulations × 4 methods) all differ.
const PALETTE: [RGBColor; 12] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
    RGBColor(0, 0, 0),
    RGBColor(255, 187, 120),
];

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
        return Ok((lo, hi));
    }
    let usable = |v: f64| v.is_finite() && (!axis.log || v > 0.0);
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for s in &fig.series {
        for &(x, y) in &s.points {
            if usable(x) && usable(y) {
                let v = if vertical { y } else { x };
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
    }
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
/// for the y tick labels and the y-axis label.
fn builder<'a, 'b, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    y_area: u32,
) -> ChartBuilder<'a, 'b, DB> {
    let mut b = ChartBuilder::on(area);
    b.margin(20)
        .margin_right(40)
        .x_label_area_size(80)
        .y_label_area_size(y_area);
    b
}

/// Width (px) for the y tick labels and axis label: the longest of the labels at eleven
/// points across the range, at DejaVu Sans's digit advance (0.64 em), plus the rotated axis
/// label's line and gaps.
fn y_area_width((lo, hi): (f64, f64), log: bool) -> u32 {
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
    let ticks = (chars as f64 * 0.64 * f64::from(TICK_PX)).ceil() as u32;
    (ticks + 2 * AXIS_LABEL_PX + 20).max(90)
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
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let area = root
        .margin(12, 0, 0, 0)
        .titled(&fig.title, (FAMILY, TITLE_PX))
        .map_err(|e| e.to_string())?;
    let mut xr = axis_range(fig, false)?;
    let mut yr = axis_range(fig, true)?;
    if fig.equal_aspect && !fig.x.log && !fig.y.log {
        // The plotting area's size depends only on the label areas, not on the ranges.
        let probe = builder(&area, y_area_width(yr, fig.y.log))
            .build_cartesian_2d(0.0..1.0, 0.0..1.0)
            .map_err(|e| e.to_string())?;
        let (w, h) = probe.plotting_area().dim_in_pixel();
        [xr, yr] = equalise(xr, yr, w, h);
    }
    let y_area = y_area_width(yr, fig.y.log);
    let x = xr.0..xr.1;
    let y = yr.0..yr.1;
    match (fig.x.log, fig.y.log) {
        (false, false) => chart(&area, fig, joins, y_area, x, y),
        (false, true) => chart(&area, fig, joins, y_area, x, y.log_scale()),
        (true, false) => chart(&area, fig, joins, y_area, x.log_scale(), y),
        (true, true) => chart(&area, fig, joins, y_area, x.log_scale(), y.log_scale()),
    }
}

/// Draws axes, marks, series and legend with the given x and y coordinates.
fn chart<DB, X, Y>(
    area: &DrawingArea<DB, Shift>,
    fig: &Figure,
    joins: Joins,
    y_area: u32,
    x: X,
    y: Y,
) -> Result<(), String>
where
    DB: DrawingBackend,
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let mut chart = builder(area, y_area)
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
        .axis_desc_style((FAMILY, AXIS_LABEL_PX))
        .label_style((FAMILY, TICK_PX))
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
    let min_gap = 2 * i32::try_from(TICK_PX).unwrap_or(20);
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
                    (FAMILY, TICK_PX - 4).into_font().color(&grey),
                )))
                .map_err(|e| e.to_string())?;
        }
    }

    let log_ok = |v: f64, log: bool| v.is_finite() && (!log || v > 0.0);
    let drawable = |&(px, py): &(f64, f64)| log_ok(px, fig.x.log) && log_ok(py, fig.y.log);
    let mut any_name = false;
    for s in &fig.series {
        let (colour, width) = match s.style {
            Style::Reference => (RGBColor(60, 60, 60), 1),
            _ => (PALETTE[s.colour % PALETTE.len()], 2),
        };
        let mut labelled = false;
        match s.style {
            Style::Line | Style::Reference => {
                // Each run of drawable points is one polyline.
                for run in s.points.split(|p| !drawable(p)) {
                    if run.is_empty() {
                        continue;
                    }
                    let style = colour.stroke_width(width);
                    let ann = if joins == Joins::Separate && width > 1 {
                        chart.draw_series(
                            run.windows(2).map(|w| PathElement::new(w.to_vec(), style)),
                        )
                    } else {
                        chart.draw_series(LineSeries::new(run.iter().copied(), style))
                    }
                    .map_err(|e| e.to_string())?;
                    if let (Some(name), false) = (&s.name, labelled) {
                        ann.label(name.as_str()).legend(move |(lx, ly)| {
                            PathElement::new([(lx, ly), (lx + 30, ly)], colour.stroke_width(3))
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
                            .filter(|p| drawable(p))
                            .map(|&p| Circle::new(p, radius, colour.filled())),
                    )
                    .map_err(|e| e.to_string())?;
                if let Some(name) = &s.name {
                    ann.label(name.as_str())
                        .legend(move |(lx, ly)| Circle::new((lx + 15, ly), 5, colour.filled()));
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
            .label_font((FAMILY, LEGEND_PX))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
    }
    Ok(())
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
