//! A slider (a body with one point and no `shapes`) and a prismatic joint's rail are drawn by
//! default, where the trajectory puts them: in models/slider_crank.toml the slider is a square
//! block of side `SLIDER_BLOCK_FRACTION` × the longest body (the 0.3 m rod) about its point B,
//! and the rail a grey line along the x axis through the ground point that reaches a block
//! beyond the slider's farthest place in the run. Before, a body with one point was a polyline
//! of one point (nothing on screen) and no rail was drawn.

mod animate_common;

use animate_common::{near, pixel_of, point_at, rgb_at, run_table};
use linkdyn::animate::{
    Animation, AnimationOptions, BACKGROUND, GROUND, SLIDER_BLOCK_FRACTION, body_colour,
    raster::rgb_pixels,
};
use linkdyn::plot::Table;
use linkdyn::simulation::SimulationOptions;

/// The pixels tested lie a third of a block (about 20 px) inside the block's edges or on the
/// 3 px rail's centre line, away from anti-aliased edges: a unit of rounding is the tolerance.
const COLOUR_TOL: u8 = 1;

/// The slider-crank run for one crank turn, as the table `linkdyn run` would write.
fn slider_crank() -> (linkdyn::model::Model, Table) {
    let model = match linkdyn::model::load("models/slider_crank.toml".as_ref(), &[]) {
        Ok(m) => m,
        Err(e) => panic!("{e}"),
    };
    let table = run_table(
        &model,
        "models/slider_crank.toml",
        SimulationOptions::default().revs(1.0).dt(1e-4),
    );
    (model, table)
}

/// The slider in its guide with clearance (models/slider_crank_prismatic_clearance.toml) with
/// the overrides `set`, run for one crank turn and animated at 4 frames per second.
fn guide_movie(set: &[String]) -> (linkdyn::model::Model, Table, Animation) {
    const MODEL: &str = "models/slider_crank_prismatic_clearance.toml";
    let model = match linkdyn::model::load(MODEL.as_ref(), set) {
        Ok(m) => m,
        Err(e) => panic!("{e}"),
    };
    let run = run_table(
        &model,
        MODEL,
        SimulationOptions::default().revs(1.0).dt(1e-4),
    );
    let options = AnimationOptions {
        duration: Some(1.0),
        fps: 4.0,
        ..AnimationOptions::default()
    };
    let movie = match Animation::build(&model, &run, &options) {
        Ok(m) => m,
        Err(e) => panic!("{e}"),
    };
    (model, run, movie)
}

#[test]
fn slider_block_and_rail_are_drawn_where_the_run_puts_them() {
    let (model, run) = slider_crank();
    let options = AnimationOptions {
        duration: Some(1.0),
        fps: 8.0,
        ..AnimationOptions::default()
    };
    let movie = match Animation::build(&model, &run, &options) {
        Ok(m) => m,
        Err(e) => panic!("{e}"),
    };
    let width = movie.view.size.0 as usize;
    // The rod, crank to slider pin: 0.3 m, the longest body.
    let block = SLIDER_BLOCK_FRACTION * 0.3;
    let slider = model
        .bodies
        .iter()
        .position(|b| b.name == "slider")
        .unwrap_or_else(|| panic!("no body named slider"));
    let Ok(xs) = run.column("slider.x") else {
        panic!("no column slider.x")
    };
    let farthest = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let nearest = xs.iter().copied().fold(f64::INFINITY, f64::min);
    // The rail runs along y = 0 from the ground point (0, 0): the slider stays on it.
    assert!(
        (0.19..0.21).contains(&nearest) && (0.39..0.41).contains(&farthest),
        "an in-line slider-crank with a 0.1 m crank and a 0.3 m rod slides between 0.2 and 0.4 m, got {nearest} to {farthest}"
    );
    for frame in &movie.frames {
        let rgb = match rgb_pixels(&frame.picture) {
            Ok(p) => p,
            Err(e) => panic!("{e}"),
        };
        // Inside the block, a third of a side ahead of B (the rod comes from behind it).
        let inside = pixel_of(
            &movie.view,
            point_at(&run, "slider", [block / 3.0, 0.0], frame.t),
        );
        let c = rgb_at(&rgb, width, inside);
        assert!(
            near(c, body_colour(slider), COLOUR_TOL),
            "t = {} s: pixel {inside:?} in the slider block is {c:?}, expected {:?}",
            frame.t,
            body_colour(slider)
        );
        // The rail, three quarters of a block beyond the farthest slider centre: past the
        // block's edge (half a side) and short of the rail's end (a whole side).
        let rail = pixel_of(&movie.view, [farthest + 0.75 * block, 0.0]);
        let c = rgb_at(&rgb, width, rail);
        assert!(
            near(c, GROUND, COLOUR_TOL),
            "t = {} s: rail pixel {rail:?} is {c:?}, expected the rail's grey {GROUND:?}",
            frame.t
        );
        // And nothing beyond the rail's end (a block and a half past the farthest centre).
        let past = pixel_of(&movie.view, [farthest + 1.5 * block, 0.0]);
        let c = rgb_at(&rgb, width, past);
        assert!(
            near(c, BACKGROUND, COLOUR_TOL),
            "t = {} s: pixel {past:?} past the rail's end is {c:?}, expected background",
            frame.t
        );
    }
}

/// A slider in a guide with clearance (models/slider_crank_prismatic_clearance.toml: an
/// 80 × 50 mm slider, c = 0.5 mm) is drawn between the guide's two surfaces: two grey lines at
/// y = ±(w/2 + c) = ±25.5 mm that reach half a slider and a block beyond its farthest place,
/// background between them there, and the slider's own polygon where the run puts it.
#[test]
fn slider_is_drawn_between_the_two_surfaces_of_its_guide() {
    let (model, run, movie) = guide_movie(&[]);
    let width = movie.view.size.0 as usize;
    let block = SLIDER_BLOCK_FRACTION * 0.3;
    let slider = model
        .bodies
        .iter()
        .position(|b| b.name == "slider")
        .unwrap_or_else(|| panic!("no body named slider"));
    let Ok(xs) = run.column("slider.x") else {
        panic!("no column slider.x")
    };
    let farthest = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let beyond = farthest + 0.04 + 0.5 * block;
    for frame in &movie.frames {
        let rgb = match rgb_pixels(&frame.picture) {
            Ok(p) => p,
            Err(e) => panic!("{e}"),
        };
        for y in [-0.0255, 0.0255] {
            let at = pixel_of(&movie.view, [beyond, y]);
            let c = rgb_at(&rgb, width, at);
            assert!(
                near(c, GROUND, COLOUR_TOL),
                "t = {} s: guide surface pixel {at:?} (y = {y} m) is {c:?}, expected {GROUND:?}",
                frame.t
            );
        }
        let between = pixel_of(&movie.view, [beyond, 0.0]);
        let c = rgb_at(&rgb, width, between);
        assert!(
            near(c, BACKGROUND, COLOUR_TOL),
            "t = {} s: pixel {between:?} between the surfaces is {c:?}, expected background",
            frame.t
        );
        // Inside the slider's polygon, ahead of its pin (the rod comes from behind).
        let inside = pixel_of(&movie.view, point_at(&run, "slider", [0.025, 0.0], frame.t));
        let c = rgb_at(&rgb, width, inside);
        assert!(
            near(c, body_colour(slider), COLOUR_TOL),
            "t = {} s: pixel {inside:?} in the slider is {c:?}, expected {:?}",
            frame.t,
            body_colour(slider)
        );
    }
}

/// The same guide given end stops (`guide_start` = 0.14 m, `guide_end` = 0.46 m, 20 mm beyond
/// the slider's faces at the ends of its travel, 0.16 and 0.44 m): each stop is a grey line
/// across the guide. Checked at the end stop, where nothing else is ever drawn (the rod ends
/// at the slider's pin, x ≤ 0.4 m; the rod lies along the centre line at the dead centres, so
/// the start stop is hidden behind it there): the guide's centre line is grey at the stop and
/// between the surfaces near it in every frame, background just inside it.
#[test]
fn the_end_stops_of_a_guide_are_drawn_across_it() {
    let (_, _, movie) = guide_movie(&[
        "joints.rail.guide_start=0.14".to_string(),
        "joints.rail.guide_end=0.46".to_string(),
    ]);
    let width = movie.view.size.0 as usize;
    for frame in &movie.frames {
        let rgb = match rgb_pixels(&frame.picture) {
            Ok(p) => p,
            Err(e) => panic!("{e}"),
        };
        for (x, y, expected, what) in [
            (0.46, 0.0, GROUND, "the end stop"),
            (0.46, 0.02, GROUND, "the end stop, near the upper surface"),
            (0.46, -0.02, GROUND, "the end stop, near the lower surface"),
            (0.45, 0.0, BACKGROUND, "just inside the end stop"),
        ] {
            let at = pixel_of(&movie.view, [x, y]);
            let c = rgb_at(&rgb, width, at);
            assert!(
                near(c, expected, COLOUR_TOL),
                "t = {} s: pixel {at:?} at {what} ({x}, {y}) m is {c:?}, expected {expected:?}",
                frame.t
            );
        }
    }
}
