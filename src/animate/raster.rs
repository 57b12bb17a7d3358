//! A [`Picture`] drawn into an RGB pixel buffer (plotters' bitmap backend, the embedded font),
//! and encoded as PNG.

use super::scene::{BACKGROUND, Colour, Mark, Picture};
use crate::plot::PlotError;
use crate::plot::font::{FAMILY, ensure_registered};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

fn rgb(c: Colour) -> RGBColor {
    RGBColor(c.0, c.1, c.2)
}

/// Pixel coordinates as the backend takes them (rounded to whole pixels).
fn px(p: &[f64; 2]) -> (i32, i32) {
    (p[0].round() as i32, p[1].round() as i32)
}

fn draw_error(reason: impl ToString) -> PlotError {
    PlotError::Draw {
        path: "the picture".into(),
        reason: reason.to_string(),
    }
}

/// The picture as 8-bit RGB, row by row from the top left (width × height × 3 bytes).
pub fn rgb_pixels(picture: &Picture) -> Result<Vec<u8>, PlotError> {
    if !ensure_registered() {
        return Err(draw_error("the embedded font does not parse"));
    }
    let (w, h) = picture.size;
    let mut buffer = vec![0u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (w, h)).into_drawing_area();
        root.fill(&rgb(BACKGROUND)).map_err(draw_error)?;
        for mark in &picture.marks {
            draw_mark(&root, mark).map_err(draw_error)?;
        }
        root.present().map_err(draw_error)?;
    }
    Ok(buffer)
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

fn stroke_path(
    root: &Area<'_>,
    points: Vec<(i32, i32)>,
    colour: Colour,
    width: f64,
) -> Result<(), String> {
    let style = ShapeStyle {
        color: rgb(colour).to_rgba(),
        filled: false,
        stroke_width: width.round().max(1.0) as u32,
    };
    root.draw(&PathElement::new(points, style))
        .map_err(|e| e.to_string())
}

fn draw_mark(root: &Area<'_>, mark: &Mark) -> Result<(), String> {
    match mark {
        Mark::Path {
            points,
            closed,
            stroke,
            width,
        } => {
            let mut p: Vec<(i32, i32)> = points.iter().map(px).collect();
            if let (true, Some(&first)) = (*closed, p.first()) {
                p.push(first);
            }
            stroke_path(root, p, *stroke, *width)
        }
        Mark::Polygon {
            points,
            fill,
            stroke,
        } => {
            let p: Vec<(i32, i32)> = points.iter().map(px).collect();
            root.draw(&Polygon::new(p.clone(), rgb(*fill).filled()))
                .map_err(|e| e.to_string())?;
            match (stroke, p.first()) {
                (Some((c, w)), Some(&first)) => {
                    let mut closed = p;
                    closed.push(first);
                    stroke_path(root, closed, *c, *w)
                }
                _ => Ok(()),
            }
        }
        Mark::Circle {
            centre,
            radius,
            fill,
            stroke,
        } => {
            let r = radius.round().max(1.0) as i32;
            if let Some(f) = fill {
                root.draw(&Circle::new(px(centre), r, rgb(*f).filled()))
                    .map_err(|e| e.to_string())?;
            }
            if let Some((c, w)) = stroke {
                let style = ShapeStyle {
                    color: rgb(*c).to_rgba(),
                    filled: false,
                    stroke_width: w.round().max(1.0) as u32,
                };
                root.draw(&Circle::new(px(centre), r, style))
                    .map_err(|e| e.to_string())?;
            }
            Ok(())
        }
        Mark::Trail {
            origin,
            offsets,
            stroke,
            width,
        } => {
            let p = offsets
                .iter()
                .map(|o| px(&[origin[0] + o[0], origin[1] + o[1]]))
                .collect();
            stroke_path(root, p, *stroke, *width)
        }
        Mark::Text {
            at,
            text,
            size,
            colour,
        } => {
            let ink = rgb(*colour);
            let style = TextStyle::from((FAMILY, *size).into_font())
                .color(&ink)
                .pos(Pos::new(HPos::Left, VPos::Bottom));
            root.draw(&Text::new(text.clone(), px(at), style))
                .map_err(|e| e.to_string())
        }
    }
}

/// The picture as the bytes of a PNG file (8-bit RGB).
pub fn png(picture: &Picture) -> Result<Vec<u8>, PlotError> {
    let pixels = rgb_pixels(picture)?;
    let (w, h) = picture.size;
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(draw_error)?;
    writer.write_image_data(&pixels).map_err(draw_error)?;
    writer.finish().map_err(draw_error)?;
    Ok(bytes)
}
