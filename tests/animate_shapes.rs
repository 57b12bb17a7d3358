//! The optional `shapes` of a body: read in body-frame coordinates from point names, refused
//! with the file, line, column and field when wrong, and without any effect on the dynamics
//! (a run with and without them is bit-identical).

use linkdyn::model::Shape;
use linkdyn::simulation::{Simulation, SimulationOptions};
use std::path::PathBuf;

const FARAHAN: &str = "models/farahan2016.toml";

fn scratch_model(name: &str, text: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("animate_shapes");
    if let Err(e) = std::fs::create_dir_all(&dir) {
        panic!("{}: {e}", dir.display());
    }
    let path = dir.join(format!("{name}.toml"));
    if let Err(e) = std::fs::write(&path, text) {
        panic!("{}: {e}", path.display());
    }
    path
}

fn farahan_text() -> String {
    match std::fs::read_to_string(FARAHAN) {
        Ok(t) => t,
        Err(e) => panic!("{FARAHAN}: {e}"),
    }
}

/// The crank's shape line in models/farahan2016.toml.
const CRANK_BAR: &str = r#"shapes = [{ type = "bar", from = "O2", to = "A", width = 0.03 }]"#;

#[test]
fn shipped_bars_resolve_to_body_points() {
    let model = match linkdyn::model::load(FARAHAN.as_ref(), &[]) {
        Ok(m) => m,
        Err(e) => panic!("{e}"),
    };
    let crank = &model.bodies[0];
    assert_eq!(
        crank.shapes,
        vec![Shape::Bar {
            from: [-0.125, 0.0],
            to: [0.125, 0.0],
            width: 0.03
        }],
        "crank shapes (points O2 and A of the crank)"
    );
    assert!(
        model.bodies.iter().all(|b| b.shapes.len() == 1),
        "one bar per body"
    );
}

#[test]
fn bad_shapes_are_refused_with_their_place() {
    let text = farahan_text();
    assert!(
        text.contains(CRANK_BAR),
        "{FARAHAN} no longer has `{CRANK_BAR}`"
    );
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
        let path = scratch_model(name, &text.replace(CRANK_BAR, line));
        let message = match linkdyn::model::load(&path, &[]) {
            Ok(_) => panic!("{name}: `{line}` was accepted"),
            Err(e) => e.to_string(),
        };
        let expected = format!("{}{expected}", path.display());
        assert_eq!(message, expected, "{name}");
    }
}

#[test]
fn shapes_do_not_change_the_run() {
    let text = farahan_text();
    let bare: String = text
        .lines()
        .filter(|l| !l.starts_with("shapes = "))
        .map(|l| format!("{l}\n"))
        .collect();
    let bare_path = scratch_model("no_shapes", &bare);
    let run = |path: &std::path::Path| {
        let model = match linkdyn::model::load(path, &[]) {
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
    let (names, with) = run(FARAHAN.as_ref());
    let (_, without) = run(&bare_path);
    for (name, (a, b)) in names.iter().zip(with.iter().zip(&without)) {
        let same = a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
        assert!(same, "column {name} differs with and without shapes");
    }
}
