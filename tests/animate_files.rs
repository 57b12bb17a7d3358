//! The three animation files as their readers see them: the animated SVG is well-formed XML
//! with one animated element per moving mark and one time caption per frame; the HTML page
//! names nothing outside itself and forbids fetching; the GIF decodes to the frames, and its
//! composed frames show the bodies where the trajectory says. The CLI makes each from a model
//! or a result file and refuses what it cannot make.

mod cli_common;

use cli_common::{linkdyn_stderr, scratch};
mod animate_common;

use animate_common::{BODIES, farahan, pixel_of, point_at};
use linkdyn::animate::{Animation, AnimationOptions, body_colour, gif, html, svg};
use std::path::PathBuf;

fn movie(size: (u32, u32)) -> (Animation, linkdyn::plot::Table) {
    let (model, run) = farahan(0.5);
    let options = AnimationOptions {
        size,
        duration: Some(1.0),
        fps: 10.0,
        ..AnimationOptions::default()
    };
    match Animation::build(&model, &run, &options) {
        Ok(m) => (m, run),
        Err(e) => panic!("{e}"),
    }
}

#[test]
fn animated_svg_parses_with_its_animations() {
    let (movie, _) = movie((800, 600));
    let text = match svg::animated(&movie) {
        Ok(t) => t,
        Err(e) => panic!("{e}"),
    };
    let doc = match roxmltree::Document::parse(&text) {
        Ok(d) => d,
        Err(e) => panic!("the animated SVG is not well-formed XML: {e}"),
    };
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg", "root element");
    assert_eq!(
        root.tag_name().namespace(),
        Some("http://www.w3.org/2000/svg"),
        "SVG namespace"
    );
    let n = movie.frames.len();
    let animates: Vec<_> = doc
        .descendants()
        .filter(|e| e.has_tag_name("animate"))
        .collect();
    // The three bars move; each steps through one outline per frame.
    let outlines: Vec<_> = animates
        .iter()
        .filter(|a| a.attribute("attributeName") == Some("points"))
        .collect();
    assert!(
        outlines.len() >= BODIES.len(),
        "{} animated outlines, expected at least one per body ({})",
        outlines.len(),
        BODIES.len()
    );
    for a in &outlines {
        let values = a.attribute("values").unwrap_or_default().split(';').count();
        assert_eq!(values, n, "values of an animated outline, one per frame");
        assert_eq!(a.attribute("calcMode"), Some("discrete"), "calcMode");
        assert_eq!(
            a.attribute("dur"),
            Some(format!("{:.4}s", n as f64 / movie.fps).as_str()),
            "dur: n frames at fps"
        );
    }
    // The journal centre moves (cx, cy), its path is revealed (stroke-dashoffset).
    for attribute in ["cx", "cy", "stroke-dashoffset"] {
        assert!(
            animates
                .iter()
                .any(|a| a.attribute("attributeName") == Some(attribute)),
            "no animated {attribute}"
        );
    }
    // One time caption per frame, each shown during its own frame only.
    let captions: Vec<_> = doc
        .descendants()
        .filter(|e| e.has_tag_name("text") && e.text().is_some_and(|t| t.contains("t = ")))
        .collect();
    assert_eq!(captions.len(), n, "time captions");
    let last = captions[n - 1].text().unwrap_or_default();
    assert!(
        last.contains("t = 0.1200 s") && last.contains("crank 180.0°"),
        "last caption `{last}`: half a turn from θ2 = 0 at t = 0.12 s"
    );
}

#[test]
fn html_page_is_self_contained() {
    let (movie, _) = movie((800, 600));
    let page = match html::page(&movie) {
        Ok(p) => p,
        Err(e) => panic!("{e}"),
    };
    for url in [
        "http://", "https://", "//cdn", "src=", "href=", "url(", "@import",
    ] {
        assert!(!page.contains(url), "the page contains `{url}`");
    }
    assert!(
        page.contains(
            r#"<meta http-equiv="Content-Security-Policy" content="default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'">"#
        ),
        "no Content-Security-Policy forbidding every fetch"
    );
    for control in [
        r#"<canvas id="canvas" width="800" height="600">"#,
        r#"<button id="play""#,
        r#"<input id="slider" type="range""#,
        r#"<select id="speed">"#,
        r#"<span id="now">"#,
    ] {
        assert!(page.contains(control), "the page lacks `{control}`");
    }
    // The frame times are in the data, first and last exact.
    assert!(
        page.contains("\"t\": [0,0.012,"),
        "frame times do not start 0, 0.012 s"
    );
}

/// The frames of a GIF composed as a viewer shows them (each frame drawn over the previous
/// one, transparent pixels keeping it): RGB per frame.
fn compose(bytes: &[u8]) -> (usize, usize, Vec<Vec<u8>>) {
    let mut options = ::gif::DecodeOptions::new();
    options.set_color_output(::gif::ColorOutput::Indexed);
    let mut decoder = match options.read_info(bytes) {
        Ok(d) => d,
        Err(e) => panic!("the GIF does not decode: {e}"),
    };
    let (w, h) = (decoder.width() as usize, decoder.height() as usize);
    let palette = decoder.global_palette().unwrap_or_default().to_vec();
    let mut canvas = vec![255u8; w * h * 3];
    let mut frames = Vec::new();
    loop {
        let frame = match decoder.read_next_frame() {
            Ok(Some(f)) => f.clone(),
            Ok(None) => break,
            Err(e) => panic!("GIF frame {}: {e}", frames.len()),
        };
        let (fw, left, top) = (
            frame.width as usize,
            frame.left as usize,
            frame.top as usize,
        );
        for (i, &index) in frame.buffer.iter().enumerate() {
            if Some(index) == frame.transparent {
                continue;
            }
            let (x, y) = (left + i % fw, top + i / fw);
            let p = 3 * (y * w + x);
            let c = 3 * index as usize;
            canvas[p..p + 3].copy_from_slice(&palette[c..c + 3]);
        }
        frames.push(canvas.clone());
    }
    (w, h, frames)
}

#[test]
fn gif_frames_show_the_bodies_where_the_trajectory_says() {
    let (movie, run) = movie((640, 480));
    let bytes = match gif::encode(&movie) {
        Ok(b) => b,
        Err(e) => panic!("{e}"),
    };
    let (w, h, frames) = compose(&bytes);
    assert_eq!((w, h), (640, 480), "GIF size");
    assert_eq!(frames.len(), movie.frames.len(), "GIF frames");
    let dir = scratch("gif");
    for k in [0, frames.len() - 1] {
        // Written for a person to look at; the assertions below do not read them.
        let path = dir.join(format!("frame{k}.png"));
        if let Ok(file) = std::fs::File::create(&path) {
            let mut enc = png::Encoder::new(file, w as u32, h as u32);
            enc.set_color(png::ColorType::Rgb);
            let _ = enc
                .write_header()
                .and_then(|mut wr| wr.write_image_data(&frames[k]));
        }
        let t = movie.frames[k].t;
        for (b, body) in BODIES.iter().enumerate() {
            let (x, y) = pixel_of(&movie.view, point_at(&run, body, [0.0, 0.0], t));
            let p = 3 * (y * w + x);
            let c = &frames[k][p..p + 3];
            let want = body_colour(b);
            // Palette colours are exact: the body colours are palette entries.
            assert_eq!(
                c,
                [want.0, want.1, want.2],
                "GIF frame {k} (t = {t} s): {body} centre pixel ({x}, {y})"
            );
        }
    }
}

#[test]
fn cli_animates_a_model_and_a_result_file() {
    let dir = scratch("cli");
    let s = |p: &PathBuf| p.display().to_string();
    let csv = dir.join("r.csv");
    let (code, err) = linkdyn_stderr(&[
        "run",
        "models/farahan2016.toml",
        "--revs",
        "0.25",
        "--dt",
        "1e-3",
        "--out",
        &s(&csv),
    ]);
    assert_eq!(code, 0, "run: {err}");
    for (input, out) in [
        ("models/farahan2016.toml", "m.gif"),
        (s(&csv).as_str(), "r.svg"),
        (s(&csv).as_str(), "r.html"),
    ] {
        let out = dir.join(out);
        let out_s = s(&out);
        let mut args = vec!["animate", input, "--out", &out_s];
        args.extend(["--duration", "0.5", "--fps", "10"]);
        if input.ends_with(".toml") {
            args.extend(["--revs", "0.25", "--dt", "1e-3"]);
        }
        let (code, err) = linkdyn_stderr(&args);
        assert_eq!(code, 0, "animate {input} → {out_s}: {err}");
        // 0.5 s at 10 fps: 6 frames over the 0.06 s of a quarter turn.
        assert!(
            err.contains("6 frames of t = 0 to 0.06 s"),
            "animate {input} → {out_s}: `{err}`"
        );
        let size = std::fs::metadata(&out).map(|m| m.len()).unwrap_or(0);
        assert!(size > 1000, "{out_s}: {size} bytes");
    }
    let (code, err) = linkdyn_stderr(&["animate", &s(&csv), "--out", &s(&dir.join("x.mp4"))]);
    assert_eq!(code, 2, "unknown format: {err}");
    assert!(
        err.contains("unknown animation format (use a .html, .svg or .gif file name)"),
        "unknown format: `{err}`"
    );
    let (code, err) = linkdyn_stderr(&[
        "animate",
        &s(&csv),
        "--revs",
        "1",
        "--out",
        &s(&dir.join("y.html")),
    ]);
    assert_eq!(code, 2, "run options on a result file: {err}");
    assert!(
        err.contains(
            "--t-end, --revs, --set and --ideal apply to a model file (.toml), not to a result file"
        ),
        "run options on a result file: `{err}`"
    );
    assert!(
        !dir.join("y.html").exists(),
        "a refused animation left a file"
    );
}
