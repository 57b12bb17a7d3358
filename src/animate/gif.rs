//! An [`Animation`] as an animated GIF (for slides): every frame rasterised, mapped to one
//! fixed palette (the drawing colours, their blends with white for anti-aliased edges, and
//! greys for text), and stored as the rectangle that changed since the previous frame, with
//! unchanged pixels transparent, so a mostly still mechanism costs little.

use super::Animation;
use super::raster::rgb_pixels;
use super::scene::{BACKGROUND, BODY_COLOURS, Colour, FORCE, GROUND, INK, JOURNAL, TRAIL};
use crate::plot::PlotError;
use std::borrow::Cow;
use std::collections::HashMap;

/// The palette index that stands for "unchanged since the previous frame".
const TRANSPARENT: u8 = 255;

fn gif_error(reason: impl ToString) -> PlotError {
    PlotError::Draw {
        path: "the GIF".into(),
        reason: reason.to_string(),
    }
}

/// The fixed palette: drawing colours, their darker outlines, blends with white at 1/4, 1/2
/// and 3/4, and 16 greys; at most 255 entries (index 255 is transparent).
pub fn palette() -> Vec<[u8; 3]> {
    let mut base: Vec<Colour> = vec![BACKGROUND, INK, GROUND, JOURNAL, TRAIL, FORCE];
    for c in BODY_COLOURS {
        base.push(c);
        base.push(Colour(c.0 / 2, c.1 / 2, c.2 / 2));
    }
    let mut out: Vec<[u8; 3]> = Vec::new();
    let mut push = |c: [u8; 3]| {
        if !out.contains(&c) {
            out.push(c);
        }
    };
    for c in &base {
        push([c.0, c.1, c.2]);
        for w in [0.25, 0.5, 0.75] {
            let blend = |v: u8| (f64::from(v) + w * (255.0 - f64::from(v))).round() as u8;
            push([blend(c.0), blend(c.1), blend(c.2)]);
        }
    }
    for g in 0..16u8 {
        push([g * 17, g * 17, g * 17]);
    }
    out.truncate(255);
    out
}

/// Index of the palette colour nearest to `c` (squared RGB distance).
fn nearest(palette: &[[u8; 3]], c: [u8; 3]) -> u8 {
    let d = |p: &[u8; 3]| {
        (0..3)
            .map(|i| {
                let x = i32::from(p[i]) - i32::from(c[i]);
                x * x
            })
            .sum::<i32>()
    };
    palette
        .iter()
        .enumerate()
        .min_by_key(|(_, p)| d(p))
        .map_or(0, |(i, _)| i as u8)
}

/// The GIF's bytes: looping, each frame shown for 100/fps centiseconds rounded (at least 2,
/// the shortest delay browsers honour).
pub fn encode(movie: &Animation) -> Result<Vec<u8>, PlotError> {
    let (w, h) = movie.view.size;
    let (Ok(w16), Ok(h16)) = (u16::try_from(w), u16::try_from(h)) else {
        return Err(gif_error(format!("{w}x{h} px is too large for a GIF")));
    };
    let palette = palette();
    let flat: Vec<u8> = palette.iter().flatten().copied().collect();
    let mut global = flat.clone();
    global.resize(256 * 3, 0);
    let mut bytes = Vec::new();
    {
        let mut encoder = gif::Encoder::new(&mut bytes, w16, h16, &global).map_err(gif_error)?;
        encoder
            .set_repeat(gif::Repeat::Infinite)
            .map_err(gif_error)?;
        let delay = (100.0 / movie.fps).round().clamp(2.0, 65535.0) as u16;
        let mut cache: HashMap<[u8; 3], u8> = HashMap::new();
        let mut previous: Option<Vec<u8>> = None;
        let (wu, hu) = (w as usize, h as usize);
        for frame in &movie.frames {
            let rgb = rgb_pixels(&frame.picture)?;
            let indices: Vec<u8> = rgb
                .chunks_exact(3)
                .map(|p| {
                    let c = [p[0], p[1], p[2]];
                    *cache.entry(c).or_insert_with(|| nearest(&palette, c))
                })
                .collect();
            // The rectangle that changed (the whole picture for the first frame).
            let (mut x0, mut y0, mut x1, mut y1) = (wu, hu, 0usize, 0usize);
            match &previous {
                None => (x0, y0, x1, y1) = (0, 0, wu - 1, hu - 1),
                Some(prev) => {
                    for (i, (a, b)) in indices.iter().zip(prev).enumerate() {
                        if a != b {
                            let (x, y) = (i % wu, i / wu);
                            x0 = x0.min(x);
                            y0 = y0.min(y);
                            x1 = x1.max(x);
                            y1 = y1.max(y);
                        }
                    }
                }
            }
            if x0 > x1 {
                // Nothing changed: one transparent pixel carries the delay.
                (x0, y0, x1, y1) = (0, 0, 0, 0);
            }
            let mut buffer = Vec::with_capacity((x1 - x0 + 1) * (y1 - y0 + 1));
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let i = y * wu + x;
                    let now = indices[i];
                    let same = previous.as_ref().is_some_and(|p| p[i] == now);
                    buffer.push(if same { TRANSPARENT } else { now });
                }
            }
            let gif_frame = gif::Frame {
                left: x0 as u16,
                top: y0 as u16,
                width: (x1 - x0 + 1) as u16,
                height: (y1 - y0 + 1) as u16,
                delay,
                dispose: gif::DisposalMethod::Keep,
                transparent: previous.as_ref().map(|_| TRANSPARENT),
                buffer: Cow::Owned(buffer),
                ..gif::Frame::default()
            };
            encoder.write_frame(&gif_frame).map_err(gif_error)?;
            previous = Some(indices);
        }
    }
    Ok(bytes)
}
