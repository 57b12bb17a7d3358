//! The optional `shapes` of a body: read in body-frame coordinates from point names, refused
//! with the file, line, column and field when wrong, and without any effect on the dynamics
//! (the Farahan four-bar with and without bars runs bit-identically).

mod animate_common;

use animate_common::{BARS, farahan_text_with};
use linkdyn::model::Shape;
use linkdyn::simulation::{Simulation, SimulationOptions};

const SLIDER_CRANK: &str = "models/slider_crank_clearance.toml";

#[test]
fn shipped_shapes_resolve_to_body_points() {
    let model = match linkdyn::model::load(SLIDER_CRANK.as_ref(), &[]) {
        Ok(m) => m,
        Err(e) => panic!("{e}"),
    };
    let shapes: Vec<&[Shape]> = model.bodies.iter().map(|b| b.shapes.as_slice()).collect();
    assert_eq!(
        shapes,
        vec![
            // crank: points O and A of the crank.
            &[Shape::Bar {
                from: [-0.05, 0.0],
                to: [0.05, 0.0],
                width: 0.025
            }][..],
            // rod: points A and B of the rod.
            &[Shape::Bar {
                from: [-0.15, 0.0],
                to: [0.15, 0.0],
                width: 0.025
            }][..],
            &[Shape::Polygon {
                vertices: vec![
                    [-0.04, -0.025],
                    [0.04, -0.025],
                    [0.04, 0.025],
                    [-0.04, 0.025]
                ]
            }][..],
        ],
        "shapes of {SLIDER_CRANK}"
    );
}

#[test]
fn bad_shapes_are_refused_with_their_place() {
    let cases = [
        (
            "unknown_point",
            r#"shapes = [{ type = "bar", from = "O2", to = "AA", width = 0.03 }]"#,
            r#":25:45: bodies.crank.shapes[0].to: unknown point "AA" in a bar shape of body "crank": did you mean "A"?"#,
        ),
        (
            "unknown_type",
            r#"shapes = [{ type = "bars", from = "O2", to = "A", width = 0.03 }]"#,
            r#":25:20: bodies.crank.shapes[0].type: unknown shape type "bars" on body "crank" (expected "bar", "polygon" or "disc"): did you mean "bar"?"#,
        ),
        (
            "negative_width",
            r#"shapes = [{ type = "bar", from = "O2", to = "A", width = -0.03 }]"#,
            ":25:58: bodies.crank.shapes[0].width: expected a positive bar width (m), found -0.03",
        ),
        (
            "foreign_field",
            r#"shapes = [{ type = "bar", from = "O2", to = "A", radius = 0.03 }]"#,
            r#":25:11: bodies.crank.shapes[0]: `radius` does not belong to a bar shape of body "crank" (it takes from, to, width)"#,
        ),
        (
            "two_corners",
            r#"shapes = [{ type = "polygon", points = ["O2", "A"] }]"#,
            r#":25:11: bodies.crank.shapes[0]: a polygon shape of body "crank" needs at least 3 corners, found 2"#,
        ),
        (
            "disc_without_centre",
            r#"shapes = [{ type = "disc", radius = 0.03 }]"#,
            r#":25:11: bodies.crank.shapes[0]: a disc shape of body "crank" needs either `at` or `centre`"#,
        ),
    ];
    for (name, line, expected) in cases {
        // The crank's `initial` is on line 24: the shape goes on line 25.
        let text = farahan_text_with([line, "", ""]);
        let message = match linkdyn::model::load_str(&text, "bars.toml", &[]) {
            Ok(_) => panic!("{name}: `{line}` was accepted"),
            Err(e) => e.to_string(),
        };
        let expected = format!("bars.toml{expected}");
        assert_eq!(message, expected, "{name}");
    }
}

#[test]
fn shapes_do_not_change_the_run() {
    let run = |text: &str| {
        let model = match linkdyn::model::load_str(text, "farahan2016.toml", &[]) {
            Ok(m) => m,
            Err(e) => panic!("{e}"),
        };
        let sim = match Simulation::new(&model, SimulationOptions::default().revs(0.1).dt(1e-3)) {
            Ok(s) => s,
            Err(e) => panic!("{e}"),
        };
        match sim.run_to_memory() {
            Ok(r) => (r.names, r.columns),
            Err(e) => panic!("{e}"),
        }
    };
    let (names, with) = run(&farahan_text_with(BARS.map(|(_, l)| l)));
    let (_, without) = run(&farahan_text_with(["", "", ""]));
    assert!(!names.is_empty(), "no columns");
    for (name, (a, b)) in names.iter().zip(with.iter().zip(&without)) {
        let same = a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
        assert!(same, "column {name} differs with and without shapes");
    }
}
