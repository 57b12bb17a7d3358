//! [`Picture`]s as SVG: a still picture, or every frame of an [`Animation`] in one animated
//! SVG (SMIL `<animate>` with discrete steps, one per frame, looping).

use super::Animation;
use super::scene::{BACKGROUND, Mark, Picture};
use crate::plot::PlotError;
use std::fmt::Write;

/// Font family of SVG text (the figures' embedded font where installed, else any sans-serif).
const FONT: &str = "DejaVu Sans, sans-serif";

/// Escapes `&`, `<`, `>` and `"` for XML text and attributes.
pub(crate) fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn points(p: &[[f64; 2]]) -> String {
    let mut s = String::with_capacity(p.len() * 12);
    for (i, q) in p.iter().enumerate() {
        if i > 0 {
            s.push(' ');
        }
        let _ = write!(s, "{:.1},{:.1}", q[0], q[1]);
    }
    s
}

fn trail_points(origin: [f64; 2], offsets: &[[f64; 2]]) -> Vec<[f64; 2]> {
    offsets
        .iter()
        .map(|o| [origin[0] + o[0], origin[1] + o[1]])
        .collect()
}

fn stroke(s: Option<(super::Colour, f64)>) -> String {
    match s {
        Some((c, w)) => format!(r#" stroke="{}" stroke-width="{w}""#, c.hex()),
        None => String::new(),
    }
}

fn open(size: (u32, u32), title: &str) -> String {
    let (w, h) = size;
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">\n\
         <title>{}</title>\n<rect width=\"{w}\" height=\"{h}\" fill=\"{}\"/>\n",
        escape(title),
        BACKGROUND.hex()
    )
}

/// The opening tag of a mark (without its end), and the closing tag.
fn element(mark: &Mark) -> (String, &'static str) {
    match mark {
        Mark::Path {
            points: p,
            closed,
            stroke: c,
            width,
        } => (
            format!(
                r#"<{} points="{}" fill="none" stroke="{}" stroke-width="{width}" stroke-linejoin="round" stroke-linecap="round">"#,
                if *closed { "polygon" } else { "polyline" },
                points(p),
                c.hex()
            ),
            if *closed { "</polygon>" } else { "</polyline>" },
        ),
        Mark::Polygon {
            points: p,
            fill,
            stroke: s,
        } => (
            format!(
                r#"<polygon points="{}" fill="{}"{} stroke-linejoin="round">"#,
                points(p),
                fill.hex(),
                stroke(*s)
            ),
            "</polygon>",
        ),
        Mark::Circle {
            centre,
            radius,
            fill,
            stroke: s,
        } => (
            format!(
                r#"<circle cx="{:.1}" cy="{:.1}" r="{:.1}" fill="{}"{}>"#,
                centre[0],
                centre[1],
                radius,
                fill.map_or_else(|| "none".to_string(), |f| f.hex()),
                stroke(*s)
            ),
            "</circle>",
        ),
        Mark::Trail {
            origin,
            offsets,
            stroke: c,
            width,
        } => (
            format!(
                r#"<polyline points="{}" fill="none" stroke="{}" stroke-width="{width}" stroke-linejoin="round">"#,
                points(&trail_points(*origin, offsets)),
                c.hex()
            ),
            "</polyline>",
        ),
        Mark::Text {
            at,
            text,
            size,
            colour,
        } => (
            format!(
                r#"<text x="{:.1}" y="{:.1}" style="white-space:pre" font-family="{FONT}" font-size="{size}" fill="{}">{}"#,
                at[0],
                at[1],
                colour.hex(),
                escape(text)
            ),
            "</text>",
        ),
    }
}

/// A still picture as an SVG document.
pub fn still(picture: &Picture) -> String {
    let mut s = open(picture.size, "linkdyn mechanism");
    for mark in &picture.marks {
        let (start, end) = element(mark);
        s.push_str(&start);
        s.push_str(end);
        s.push('\n');
    }
    s.push_str("</svg>\n");
    s
}

/// An `<animate>` of `attribute` through `values`, one per frame, looping over `dur` seconds.
fn animate(attribute: &str, values: &[String], dur: f64) -> String {
    format!(
        r#"<animate attributeName="{attribute}" values="{}" dur="{dur:.4}s" calcMode="discrete" repeatCount="indefinite"/>"#,
        values.join(";")
    )
}

/// Adds an `<animate>` of `attribute` if its values change from frame to frame.
fn animate_if_changing(out: &mut String, attribute: &str, values: Vec<String>, dur: f64) {
    if values.windows(2).any(|w| w[0] != w[1]) {
        out.push_str(&animate(attribute, &values, dur));
    }
}

fn polyline_length(p: &[[f64; 2]]) -> f64 {
    p.windows(2)
        .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
        .sum()
}

/// Every frame of `movie` in one animated SVG: each mark of the first frame becomes one element
/// whose changing attributes step through the frames (`calcMode="discrete"`); a journal path is
/// drawn once, moved with its bearing and revealed frame by frame through its dash offset; a
/// caption that changes (the time) is one `<text>` per frame, visible during its frame only.
/// Refuses frames whose marks do not correspond one to one (a drawing error).
pub fn animated(movie: &Animation) -> Result<String, PlotError> {
    let Some(first) = movie.frames.first() else {
        return Err(PlotError::Draw {
            path: "the animation".into(),
            reason: "no frames".into(),
        });
    };
    let n = movie.frames.len();
    for (k, f) in movie.frames.iter().enumerate() {
        let same = f.picture.marks.len() == first.picture.marks.len()
            && f.picture
                .marks
                .iter()
                .zip(&first.picture.marks)
                .all(|(a, b)| a.kind() == b.kind());
        if !same {
            return Err(PlotError::Draw {
                path: "the animation".into(),
                reason: format!("frame {k} (t = {} s) has other marks than frame 0", f.t),
            });
        }
    }
    let dur = n as f64 / movie.fps;
    let mut s = open(first.picture.size, &movie.title);
    for (i, mark) in first.picture.marks.iter().enumerate() {
        let at = |k: usize| &movie.frames[k].picture.marks[i];
        match mark {
            Mark::Path { .. } | Mark::Polygon { .. } => {
                let (start, end) = element(mark);
                s.push_str(&start);
                let values = (0..n)
                    .map(|k| match at(k) {
                        Mark::Path { points: p, .. } | Mark::Polygon { points: p, .. } => points(p),
                        _ => String::new(),
                    })
                    .collect();
                animate_if_changing(&mut s, "points", values, dur);
                s.push_str(end);
            }
            Mark::Circle { .. } => {
                let (start, end) = element(mark);
                s.push_str(&start);
                for (attribute, pick) in [("cx", 0), ("cy", 1), ("r", 2)] {
                    let values = (0..n)
                        .map(|k| match at(k) {
                            Mark::Circle { centre, radius, .. } => {
                                let v = [centre[0], centre[1], *radius];
                                format!("{:.1}", v[pick])
                            }
                            _ => String::new(),
                        })
                        .collect();
                    animate_if_changing(&mut s, attribute, values, dur);
                }
                s.push_str(end);
            }
            Mark::Trail {
                stroke: c, width, ..
            } => {
                // The longest path (the last frame's) is drawn once; frame k shows its first
                // `len_k` pixels, translated to frame k's bearing centre.
                let mut full: &[[f64; 2]] = &[];
                let mut lengths = Vec::with_capacity(n);
                let mut origins = Vec::with_capacity(n);
                for k in 0..n {
                    if let Mark::Trail {
                        origin, offsets, ..
                    } = at(k)
                    {
                        if offsets.len() >= full.len() {
                            full = offsets;
                        }
                        lengths.push(polyline_length(offsets));
                        origins.push(format!("{:.1},{:.1}", origin[0], origin[1]));
                    }
                }
                let total = polyline_length(full);
                let _ = write!(
                    s,
                    r#"<g transform="translate({})">"#,
                    origins.first().map_or("0,0", String::as_str)
                );
                if origins.windows(2).any(|w| w[0] != w[1]) {
                    let _ = write!(
                        s,
                        r#"<animateTransform attributeName="transform" type="translate" values="{}" dur="{dur:.4}s" calcMode="discrete" repeatCount="indefinite"/>"#,
                        origins.join(";")
                    );
                }
                // Dash = whole length + 1 px, so a fully shown path has no gap.
                let dash = total + 1.0;
                let offsets: Vec<String> = lengths
                    .iter()
                    .map(|l| format!("{:.1}", dash - l.min(total)))
                    .collect();
                let _ = write!(
                    s,
                    r#"<polyline points="{}" fill="none" stroke="{}" stroke-width="{width}" stroke-linejoin="round" stroke-dasharray="{dash:.1} {dash:.1}" stroke-dashoffset="{}">"#,
                    points(full),
                    c.hex(),
                    offsets.first().map_or("0", String::as_str)
                );
                animate_if_changing(&mut s, "stroke-dashoffset", offsets, dur);
                s.push_str("</polyline></g>");
            }
            Mark::Text { .. } => {
                let texts: Vec<&Mark> = (0..n).map(at).collect();
                if texts.windows(2).all(|w| w[0] == w[1]) {
                    let (start, end) = element(mark);
                    s.push_str(&start);
                    s.push_str(end);
                } else {
                    for (k, m) in texts.iter().enumerate() {
                        let (start, end) = element(m);
                        let (values, times) = match k {
                            0 => ("visible;hidden".to_string(), format!("0;{}", frac(1, n))),
                            k if k + 1 == n => {
                                ("hidden;visible".to_string(), format!("0;{}", frac(k, n)))
                            }
                            k => (
                                "hidden;visible;hidden".to_string(),
                                format!("0;{};{}", frac(k, n), frac(k + 1, n)),
                            ),
                        };
                        s.push_str(&start.replacen(
                            "<text ",
                            &format!(
                                r#"<text visibility="{}" "#,
                                if k == 0 { "visible" } else { "hidden" }
                            ),
                            1,
                        ));
                        let _ = write!(
                            s,
                            r#"<animate attributeName="visibility" values="{values}" keyTimes="{times}" dur="{dur:.4}s" calcMode="discrete" repeatCount="indefinite"/>"#
                        );
                        s.push_str(end);
                        s.push('\n');
                    }
                }
            }
        }
        s.push('\n');
    }
    s.push_str("</svg>\n");
    Ok(s)
}

/// k/n as a decimal for `keyTimes`.
fn frac(k: usize, n: usize) -> String {
    format!("{:.6}", k as f64 / n as f64)
}
