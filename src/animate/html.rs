//! An [`Animation`] as one self-contained HTML page: the frames' marks as inline data, drawn on
//! a canvas by an inline script, with play/pause, a time slider, a speed choice and the current
//! time and crank angle. Nothing is fetched: no external file is named, and the page's
//! Content-Security-Policy (`default-src 'none'`, inline script and style only) forbids it.
//!
//! The fragment `#t=0.05` shows the frame nearest to t = 0.05 s, paused (for links into a run
//! and for screenshots); `#t=0.05&play` plays from there; `&speed=0.25` sets the speed.

use super::Animation;
use super::scene::{Colour, Mark};
use crate::plot::PlotError;
use std::fmt::Write;

/// Speeds offered (× real playback rate); 1 is the default.
const SPEEDS: [f64; 7] = [0.1, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0];

/// A JSON string literal (escaped for a `<script>` element as well: no `</` can close it).
fn js_string(s: &str) -> String {
    serde_json::to_string(s)
        .unwrap_or_else(|_| "\"\"".into())
        .replace("</", "<\\/")
}

fn colour(c: Colour) -> String {
    format!("\"{}\"", c.hex())
}

/// Numbers rounded to 0.1 px, comma-separated, in brackets.
fn flat(points: impl IntoIterator<Item = [f64; 2]>) -> String {
    let mut s = String::from("[");
    for (i, p) in points.into_iter().enumerate() {
        if i > 0 {
            s.push(',');
        }
        let _ = write!(s, "{},{}", round(p[0]), round(p[1]));
    }
    s.push(']');
    s
}

/// x to 0.1 (no trailing `.0`; JSON has no NaN, so a non-finite value becomes 0).
fn round(x: f64) -> String {
    if !x.is_finite() {
        return "0".into();
    }
    let r = (x * 10.0).round() / 10.0;
    if r == r.trunc() {
        format!("{}", r as i64)
    } else {
        format!("{r:.1}")
    }
}

/// `"key":static` if the per-frame values are all equal, else `"KEY":[per frame]`.
fn per_frame(key: &str, values: Vec<String>) -> String {
    if values.windows(2).all(|w| w[0] == w[1]) {
        format!(
            "\"{key}\":{}",
            values.first().map_or("null", String::as_str)
        )
    } else {
        format!("\"{}\":[{}]", key.to_uppercase(), values.join(","))
    }
}

/// The marks of every frame as a JSON array, mark by mark: attributes that do not change are
/// written once; a journal path is written once (the longest) with, per frame, its origin, how
/// many of its points the frame shows and the frame's own remaining points.
fn marks_json(movie: &Animation) -> Result<String, PlotError> {
    let Some(first) = movie.frames.first() else {
        return Err(PlotError::Draw {
            path: "the animation".into(),
            reason: "no frames".into(),
        });
    };
    let n = movie.frames.len();
    let mut out = Vec::new();
    for (i, mark) in first.picture.marks.iter().enumerate() {
        let mut frames = Vec::with_capacity(n);
        for (k, f) in movie.frames.iter().enumerate() {
            match f.picture.marks.get(i) {
                Some(m) if m.kind() == mark.kind() => frames.push(m),
                _ => {
                    return Err(PlotError::Draw {
                        path: "the animation".into(),
                        reason: format!("frame {k} (t = {} s) has other marks than frame 0", f.t),
                    });
                }
            }
        }
        let json = match mark {
            Mark::Path {
                closed,
                stroke,
                width,
                ..
            } => {
                let p = frames
                    .iter()
                    .map(|m| match m {
                        Mark::Path { points, .. } => flat(points.iter().copied()),
                        _ => String::new(),
                    })
                    .collect();
                format!(
                    "{{\"k\":\"path\",\"closed\":{closed},\"c\":{},\"w\":{width},{}}}",
                    colour(*stroke),
                    per_frame("p", p)
                )
            }
            Mark::Polygon { fill, stroke, .. } => {
                let p = frames
                    .iter()
                    .map(|m| match m {
                        Mark::Polygon { points, .. } => flat(points.iter().copied()),
                        _ => String::new(),
                    })
                    .collect();
                let (s, sw) = stroke.map_or(("null".into(), 0.0), |(c, w)| (colour(c), w));
                format!(
                    "{{\"k\":\"poly\",\"f\":{},\"s\":{s},\"sw\":{sw},{}}}",
                    colour(*fill),
                    per_frame("p", p)
                )
            }
            Mark::Circle { fill, stroke, .. } => {
                let v = frames
                    .iter()
                    .map(|m| match m {
                        Mark::Circle { centre, radius, .. } => format!(
                            "[{},{},{}]",
                            round(centre[0]),
                            round(centre[1]),
                            round(*radius)
                        ),
                        _ => String::new(),
                    })
                    .collect();
                let (s, sw) = stroke.map_or(("null".into(), 0.0), |(c, w)| (colour(c), w));
                format!(
                    "{{\"k\":\"circle\",\"f\":{},\"s\":{s},\"sw\":{sw},{}}}",
                    fill.map_or_else(|| "null".into(), colour),
                    per_frame("v", v)
                )
            }
            Mark::Trail { stroke, width, .. } => {
                let trails: Vec<(&[f64; 2], &[[f64; 2]])> = frames
                    .iter()
                    .filter_map(|m| match m {
                        Mark::Trail {
                            origin, offsets, ..
                        } => Some((origin, offsets.as_slice())),
                        _ => None,
                    })
                    .collect();
                let full = trails
                    .iter()
                    .map(|(_, o)| *o)
                    .max_by_key(|o| o.len())
                    .unwrap_or(&[]);
                let mut origins = Vec::with_capacity(n);
                let mut counts = Vec::with_capacity(n);
                let mut tails = Vec::with_capacity(n);
                for (origin, offsets) in &trails {
                    // The longest common prefix with the full path is stored once.
                    let shared = offsets.iter().zip(full).take_while(|(a, b)| a == b).count();
                    origins.push(flat([**origin]));
                    counts.push(shared.to_string());
                    tails.push(flat(offsets.iter().skip(shared).copied()));
                }
                format!(
                    "{{\"k\":\"trail\",\"c\":{},\"w\":{width},\"full\":{},\"o\":[{}],\"n\":[{}],\"tail\":[{}]}}",
                    colour(*stroke),
                    flat(full.iter().copied()),
                    origins.join(","),
                    counts.join(","),
                    tails.join(",")
                )
            }
            Mark::Text {
                size, colour: c, ..
            } => {
                let (mut at, mut text) = (Vec::with_capacity(n), Vec::with_capacity(n));
                for m in &frames {
                    if let Mark::Text { at: a, text: t, .. } = m {
                        at.push(flat([*a]));
                        text.push(js_string(t));
                    }
                }
                format!(
                    "{{\"k\":\"text\",\"c\":{},\"size\":{size},{},{}}}",
                    colour(*c),
                    per_frame("p", at),
                    per_frame("s", text)
                )
            }
        };
        out.push(json);
    }
    Ok(format!("[\n{}\n]", out.join(",\n")))
}

/// The drawing and player script (static; the data come before it).
const SCRIPT: &str = r##"
(function () {
  "use strict";
  const cv = document.getElementById("canvas");
  const g = cv.getContext("2d");
  const slider = document.getElementById("slider");
  const play = document.getElementById("play");
  const speedBox = document.getElementById("speed");
  const now = document.getElementById("now");
  const N = D.t.length;
  let k = 0, playing = true, speed = 1, last = null, acc = 0;
  function line(p, ox, oy, first) {
    for (let j = 0; j + 1 < p.length; j += 2) {
      if (first) { g.moveTo(ox + p[j], oy + p[j + 1]); first = false; }
      else g.lineTo(ox + p[j], oy + p[j + 1]);
    }
    return first;
  }
  function draw(i) {
    g.fillStyle = "#ffffff";
    g.fillRect(0, 0, D.w, D.h);
    g.lineJoin = "round";
    g.lineCap = "round";
    for (const m of D.marks) {
      g.beginPath();
      if (m.k === "path") {
        line(m.p || m.P[i], 0, 0, true);
        if (m.closed) g.closePath();
        g.strokeStyle = m.c; g.lineWidth = m.w; g.stroke();
      } else if (m.k === "poly") {
        line(m.p || m.P[i], 0, 0, true);
        g.closePath();
        g.fillStyle = m.f; g.fill();
        if (m.s) { g.strokeStyle = m.s; g.lineWidth = m.sw; g.stroke(); }
      } else if (m.k === "circle") {
        const v = m.v || m.V[i];
        g.arc(v[0], v[1], v[2], 0, 2 * Math.PI);
        if (m.f) { g.fillStyle = m.f; g.fill(); }
        if (m.s) { g.strokeStyle = m.s; g.lineWidth = m.sw; g.stroke(); }
      } else if (m.k === "trail") {
        const o = m.o[i];
        const first = line(m.full.slice(0, 2 * m.n[i]), o[0], o[1], true);
        line(m.tail[i], o[0], o[1], first);
        g.strokeStyle = m.c; g.lineWidth = m.w; g.stroke();
      } else if (m.k === "text") {
        const p = m.p || m.P[i];
        g.font = m.size + "px 'DejaVu Sans', sans-serif";
        g.fillStyle = m.c;
        g.fillText(m.s !== undefined ? m.s : m.S[i], p[0], p[1]);
      }
    }
    slider.value = String(i);
    let text = "t = " + D.t[i].toFixed(4) + " s";
    if (D.a[i] !== null) text += ", crank " + D.a[i].toFixed(1) + "\u00b0";
    now.textContent = text;
  }
  function show(i) { k = Math.max(0, Math.min(N - 1, i)); draw(k); }
  function setPlaying(p) { playing = p; play.textContent = p ? "Pause" : "Play"; last = null; }
  function nearest(t) {
    let best = 0;
    for (let i = 1; i < N; i++) if (Math.abs(D.t[i] - t) < Math.abs(D.t[best] - t)) best = i;
    return best;
  }
  function fromHash() {
    const h = location.hash.replace(/^#/, "");
    const t = h.match(/(?:^|&)t=([-+0-9.eE]+)/);
    const s = h.match(/(?:^|&)speed=([0-9.eE]+)/);
    if (s && isFinite(parseFloat(s[1])) && parseFloat(s[1]) > 0) {
      speed = parseFloat(s[1]);
      speedBox.value = String(speed);
    }
    if (t && isFinite(parseFloat(t[1]))) {
      setPlaying(/(?:^|&)play(?:&|$)/.test(h));
      show(nearest(parseFloat(t[1])));
    }
  }
  function tick(ts) {
    if (playing) {
      if (last !== null) {
        acc += (ts - last) / 1000 * D.fps * speed;
        const steps = Math.floor(acc);
        if (steps > 0) { acc -= steps; show((k + steps) % N); }
      }
      last = ts;
    }
    requestAnimationFrame(tick);
  }
  slider.max = String(N - 1);
  play.addEventListener("click", function () { setPlaying(!playing); });
  slider.addEventListener("input", function () { acc = 0; show(parseInt(slider.value, 10)); });
  speedBox.addEventListener("change", function () { speed = parseFloat(speedBox.value); });
  window.addEventListener("hashchange", fromHash);
  show(0);
  fromHash();
  requestAnimationFrame(tick);
})();
"##;

/// The page of `movie`.
pub fn page(movie: &Animation) -> Result<String, PlotError> {
    let marks = marks_json(movie)?;
    let (w, h) = movie.view.size;
    let times: Vec<String> = movie.frames.iter().map(|f| format!("{}", f.t)).collect();
    let angles: Vec<String> = movie
        .frames
        .iter()
        .map(|f| {
            f.crank_deg
                .map_or_else(|| "null".into(), |a| format!("{a:.3}"))
        })
        .collect();
    let speeds: String = SPEEDS
        .iter()
        .map(|s| {
            format!(
                "<option value=\"{s}\"{}>{s}×</option>",
                if *s == 1.0 { " selected" } else { "" }
            )
        })
        .collect();
    let title = super::svg::escape(&movie.title);
    Ok(format!(
        r##"<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'">
<meta name="generator" content="linkdyn {version}">
<title>{title}</title>
<style>
body {{ margin: 0; font-family: 'DejaVu Sans', sans-serif; font-size: 14px; background: #fff; color: #282828; }}
canvas {{ display: block; }}
#bar {{ display: flex; gap: 10px; align-items: center; width: {w}px; box-sizing: border-box; padding: 6px 8px; }}
#slider {{ flex: 1; }}
#now {{ min-width: 15em; font-variant-numeric: tabular-nums; }}
</style>
</head>
<body>
<canvas id="canvas" width="{w}" height="{h}"></canvas>
<div id="bar">
<button id="play" type="button">Pause</button>
<input id="slider" type="range" min="0" max="0" step="1" value="0" aria-label="time">
<label>speed <select id="speed">{speeds}</select></label>
<span id="now"></span>
</div>
<script>
const D = {{
"w": {w}, "h": {h}, "fps": {fps},
"t": [{times}],
"a": [{angles}],
"marks": {marks}
}};
{SCRIPT}</script>
</body>
</html>
"##,
        version = crate::version(),
        fps = movie.fps,
        times = times.join(","),
        angles = angles.join(","),
    ))
}
