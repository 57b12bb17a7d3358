//! The HTML animation opened as a person would, in headless Chromium: screenshots at two times
//! (chosen through the page's `#t=` fragment, which moves the slider) show each body of the
//! four-bar at the pixel where the trajectory puts it, the crank gone from where it was, no
//! script error, and no fetch refused by the page's Content-Security-Policy.
//!
//! Needs Chromium (`chromium`, `chromium-browser` or `google-chrome` on the PATH, or the path in
//! `LINKDYN_CHROMIUM`); `.ci/run` installs Debian's package. Without it the test prints why and
//! passes.

mod animate_common;

use animate_common::{BODIES, farahan, near, pixel_of, point_at, rgb_at};
use linkdyn::animate::{Animation, AnimationOptions, body_colour, html};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The canvas is 800 × 600; the controls below it need about 45 px.
const WINDOW: (u32, u32) = (800, 660);
/// Colour tolerance per channel: the pixels tested lie inside 21 px wide bars, where the canvas
/// paints the exact fill colour; a few units allow for the screenshot's colour conversion.
const COLOUR_TOL: u8 = 6;
/// A browser that has not finished a screenshot in this long is stuck.
const BROWSER_LIMIT: Duration = Duration::from_secs(90);

fn chromium() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("LINKDYN_CHROMIUM") {
        return Some(PathBuf::from(p));
    }
    let path = std::env::var_os("PATH")?;
    ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .flat_map(|name| std::env::split_paths(&path).map(move |dir| dir.join(name)))
        .find(|p| p.is_file())
}

/// Screenshot of `page` at `fragment` as RGB, with the browser's log (stderr).
fn screenshot(
    browser: &Path,
    dir: &Path,
    page: &Path,
    fragment: &str,
    name: &str,
) -> (Vec<u8>, String) {
    let shot = dir.join(format!("{name}.png"));
    let url = format!("file://{}#{fragment}", page.display());
    let mut child = match Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--disable-extensions",
            "--no-first-run",
            "--hide-scrollbars",
            "--force-device-scale-factor=1",
            "--enable-logging=stderr",
            "--v=0",
            &format!(
                "--user-data-dir={}",
                dir.join(format!("profile-{name}")).display()
            ),
            &format!("--window-size={},{}", WINDOW.0, WINDOW.1),
            &format!("--screenshot={}", shot.display()),
            &url,
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
    {
        Ok(c) => c,
        Err(e) => panic!("cannot start {}: {e}", browser.display()),
    };
    let start = Instant::now();
    loop {
        match child.try_wait() {
            Ok(Some(_)) => break,
            Ok(None) if start.elapsed() > BROWSER_LIMIT => {
                let _ = child.kill();
                panic!(
                    "{} took over {BROWSER_LIMIT:?} for {url}",
                    browser.display()
                );
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(50)),
            Err(e) => panic!("waiting for {}: {e}", browser.display()),
        }
    }
    let log = match child.wait_with_output() {
        Ok(o) => String::from_utf8_lossy(&o.stderr).into_owned(),
        Err(e) => panic!("{e}"),
    };
    let file = match std::fs::File::open(&shot) {
        Ok(f) => f,
        Err(e) => panic!(
            "no screenshot {} ({e}); browser log:\n{log}",
            shot.display()
        ),
    };
    let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
    decoder.set_transformations(png::Transformations::normalize_to_color8());
    let mut reader = match decoder.read_info() {
        Ok(r) => r,
        Err(e) => panic!("{}: {e}", shot.display()),
    };
    let mut buf = vec![0u8; reader.output_buffer_size()];
    let info = match reader.next_frame(&mut buf) {
        Ok(i) => i,
        Err(e) => panic!("{}: {e}", shot.display()),
    };
    assert_eq!((info.width, info.height), WINDOW, "{name}: screenshot size");
    let channels = info.color_type.samples();
    let rgb = buf[..info.buffer_size()]
        .chunks_exact(channels)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    (rgb, log)
}

#[test]
fn html_in_a_browser_draws_the_trajectory() {
    let Some(browser) = chromium() else {
        eprintln!(
            "skipped: no Chromium (chromium, chromium-browser or google-chrome on the PATH, or LINKDYN_CHROMIUM); \
             install Debian's `chromium` package to run this test"
        );
        return;
    };
    let (model, run) = farahan(0.5);
    let options = AnimationOptions {
        duration: Some(1.0),
        fps: 10.0,
        ..AnimationOptions::default()
    };
    let movie = match Animation::build(&model, &run, &options) {
        Ok(m) => m,
        Err(e) => panic!("{e}"),
    };
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("animate_browser");
    let _ = std::fs::remove_dir_all(&dir);
    if let Err(e) = std::fs::create_dir_all(&dir) {
        panic!("{}: {e}", dir.display());
    }
    let page = dir.join("farahan.html");
    let text = match html::page(&movie) {
        Ok(t) => t,
        Err(e) => panic!("{e}"),
    };
    if let Err(e) = std::fs::write(&page, text) {
        panic!("{}: {e}", page.display());
    }
    // Frames are 12 ms apart: 0.036 s is frame 3 (crank at 54°), 0.096 s frame 8 (144°).
    let shots: Vec<(usize, Vec<u8>)> = [(3usize, "t=0.036"), (8, "t=0.096")]
        .iter()
        .map(|(k, fragment)| {
            let (rgb, log) = screenshot(&browser, &dir, &page, fragment, &format!("frame{k}"));
            for bad in ["Uncaught", "Refused to", "Content Security Policy"] {
                assert!(
                    !log.contains(bad),
                    "#{fragment}: the browser log reports `{bad}`:\n{log}"
                );
            }
            (*k, rgb)
        })
        .collect();
    let width = WINDOW.0 as usize;
    for (k, rgb) in &shots {
        let t = movie.frames[*k].t;
        for (b, body) in BODIES.iter().enumerate() {
            let at = pixel_of(&movie.view, point_at(&run, body, [0.0, 0.0], t));
            let c = rgb_at(rgb, width, at);
            assert!(
                near(c, body_colour(b), COLOUR_TOL),
                "frame {k} (t = {t} s): {body} centre pixel {at:?} is {c:?}, expected {:?}",
                body_colour(b)
            );
        }
    }
    // Between the two times the crank turned 90°: its centre moved 0.125·√2 m ≈ 0.18 m.
    let (k0, _) = &shots[0];
    let (k1, rgb1) = &shots[1];
    let before = pixel_of(
        &movie.view,
        point_at(&run, "crank", [0.0, 0.0], movie.frames[*k0].t),
    );
    let c = rgb_at(rgb1, width, before);
    assert!(
        !near(c, body_colour(0), 30),
        "frame {k1}: the crank still covers its frame-{k0} pixel {before:?} ({c:?})"
    );
}
