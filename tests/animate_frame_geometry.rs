//! A frame of an animation puts every body where the trajectory says: the pixel at each body's
//! centre of mass (computed here from the run's x, y columns) has the body's colour, the pin
//! between crank and coupler is drawn at the crank tip r = (x, y) + R(φ)(0.125, 0), and the
//! bodies leave those pixels when the crank has turned. Frames are evenly spaced in time, and a
//! still picture (`linkdyn plot mechanism`) is the same picture as the frame at its time.

mod animate_common;

use animate_common::{BODIES, farahan, near, pixel_of, point_at, rgb_at};
use linkdyn::animate::{
    Animation, AnimationOptions, BACKGROUND, INK, body_colour, raster::rgb_pixels, still,
};

/// Exact colours: the pixels tested are inside 21 px wide bars and 8 px pins, away from
/// anti-aliased edges, so one unit of rounding is all the tolerance needed.
const COLOUR_TOL: u8 = 1;

#[test]
fn frame_pixels_follow_the_trajectory() {
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
    // 0.5 turns at 250 rpm = 0.12 s in 1 s of playback at 10 fps: 11 frames, 12 ms apart.
    assert_eq!(movie.frames.len(), 11, "frame count");
    for (k, f) in movie.frames.iter().enumerate() {
        let expected = 0.12 * k as f64 / 10.0;
        assert!(
            (f.t - expected).abs() < 1e-12,
            "frame {k} at t = {} s, expected {expected} s",
            f.t
        );
    }
    let width = movie.view.size.0 as usize;
    let (first, last) = (&movie.frames[0], &movie.frames[10]);
    let pixels = |k: usize| match rgb_pixels(&movie.frames[k].picture) {
        Ok(p) => p,
        Err(e) => panic!("{e}"),
    };
    let (rgb0, rgb1) = (pixels(0), pixels(10));
    for (k, body) in BODIES.iter().enumerate() {
        let colour = body_colour(k);
        for (frame, rgb) in [(first, &rgb0), (last, &rgb1)] {
            let at = pixel_of(&movie.view, point_at(&run, body, [0.0, 0.0], frame.t));
            let c = rgb_at(rgb, width, at);
            assert!(
                near(c, colour, COLOUR_TOL),
                "{body} at t = {} s: pixel {at:?} is {c:?}, expected its colour {colour:?}",
                frame.t
            );
        }
    }
    // The crank turns 90° between the frames, so its centre of mass moves by
    // 0.125·√2 m ≈ 0.18 m: far more than the bar's half width (15 mm).
    let at0 = pixel_of(&movie.view, point_at(&run, "crank", [0.0, 0.0], first.t));
    let c = rgb_at(&rgb1, width, at0);
    assert!(
        !near(c, body_colour(0), 30),
        "crank at t = {} s still covers its t = 0 pixel {at0:?} ({c:?})",
        last.t
    );
    // Pin A on the crank tip: white inside a dark outline.
    for (frame, rgb) in [(first, &rgb0), (last, &rgb1)] {
        let a = pixel_of(&movie.view, point_at(&run, "crank", [0.125, 0.0], frame.t));
        let c = rgb_at(rgb, width, a);
        assert!(
            near(c, BACKGROUND, COLOUR_TOL),
            "pin A at t = {} s: pixel {a:?} is {c:?}, expected the white pin",
            frame.t
        );
        let rim = (a.0 + 4, a.1);
        let c = rgb_at(rgb, width, rim);
        assert!(
            near(c, INK, 60),
            "pin A at t = {} s: its outline pixel {rim:?} is {c:?}, expected dark {INK:?}",
            frame.t
        );
    }
}

#[test]
fn a_still_picture_is_the_frame_at_its_time() {
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
    let frame = &movie.frames[4];
    let picture = match still(&model, &run, frame.t, &options) {
        Ok(p) => p,
        Err(e) => panic!("{e}"),
    };
    assert!(
        picture == frame.picture,
        "the still at t = {} s differs from frame 4",
        frame.t
    );
    let late = still(&model, &run, 1.0, &options).map(|_| ());
    let message = late.map_err(|e| e.to_string());
    assert_eq!(
        message,
        Err("--time: 1 s is outside the run farahan2016.toml (0 to 0.12 s)".to_string()),
        "a time after the run"
    );
}
