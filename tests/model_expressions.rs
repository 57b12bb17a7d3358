//! `[parameters]` and expressions in numeric fields: values against hand computation,
//! `--set parameters.X=…` re-evaluating every dependant, and exact located error messages
//! (file:line:column at the offending token) for syntax errors, unknown names with a
//! did-you-mean, cycles, reserved names and run-time names in load-time fields.

use linkdyn::model::{Model, load_str};

const BASE: &str = r#"[model]
name = "p"
[parameters]
rho = 7800
w = "0.01"
L2 = 0.1
m2 = "rho * L2 * w^2"
[ground]
points = { O = [0, 0] }
[[bodies]]
name = "crank"
mass = "m2"
inertia = "m2*L2^2/12"
points = { O = ["-L2/2", 0], A = ["L2/2", 0] }
initial = { x = "L2/2", y = 0, phi = "atan2(0, 1)" }
[[joints]]
name = "O"
type = "revolute"
body_a = "ground"
point_a = "O"
body_b = "crank"
point_b = "O"
"#;

fn load(text: &str, sets: &[&str]) -> Result<Model, String> {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    load_str(text, "p.toml", &sets).map_err(|e| e.to_string())
}

/// Every value is one or two roundings from the hand value: 1e-15 relative.
fn close(what: &str, got: f64, want: f64) {
    assert!(
        (got - want).abs() <= 1e-15 * want.abs(),
        "{what}: {got} vs {want}"
    );
}

#[test]
fn parameters_feed_every_numeric_field() {
    let m = load(BASE, &[]).unwrap_or_else(|e| panic!("{e}"));
    let crank = &m.bodies[0];
    close("mass", crank.mass, 7800.0 * 0.1 * 1e-4);
    close("inertia", crank.inertia, 0.078 * 0.01 / 12.0);
    assert_eq!(crank.points[1], ("O".to_string(), [-0.05, 0.0]));
    close("initial x", crank.initial.x, 0.05);
    assert_eq!(
        m.parameters,
        [
            ("L2".to_string(), 0.1),
            ("m2".into(), 0.078),
            ("rho".into(), 7800.0),
            ("w".into(), 0.01)
        ]
    );
}

#[test]
fn set_re_evaluates_the_dependants() {
    let m = load(BASE, &["parameters.L2=0.2"]).unwrap_or_else(|e| panic!("{e}"));
    close("mass after --set L2", m.bodies[0].mass, 7800.0 * 0.2 * 1e-4);
    close(
        "inertia after --set L2",
        m.bodies[0].inertia,
        0.156 * 0.04 / 12.0,
    );
    let m = load(BASE, &["parameters.L2=2*w"]).unwrap_or_else(|e| panic!("{e}"));
    close("point after --set L2=2*w", m.bodies[0].points[0].1[0], 0.01);
}

fn error(from: &str, to: &str) -> String {
    assert!(BASE.contains(from), "{from}");
    load(&BASE.replace(from, to), &[]).err().unwrap_or_default()
}

#[test]
fn errors_point_at_the_token() {
    assert_eq!(
        error("mass = \"m2\"", "mass = \"m2 * (rho\""),
        "p.toml:12:18: bodies.crank.mass: in expression \"m2 * (rho\": unexpected end of the expression; expected ')' to close the '('"
    );
    assert_eq!(
        error("mass = \"m2\"", "mass = \"m3\""),
        "p.toml:12:9: bodies.crank.mass: in expression \"m3\": unknown name \"m3\": did you mean \"m2\"?; expected a parameter from [parameters]"
    );
    assert_eq!(
        error("x = \"L2/2\"", "x = \"L2/2 + t\""),
        "p.toml:15:25: bodies.crank.initial.x: in expression \"L2/2 + t\": \"t\" is only known during the run, but this field is evaluated once at load time; time and state may appear in force and torque expressions and prescribed angles"
    );
    assert_eq!(
        error("w = \"0.01\"", "w = \"m2/rho\""),
        "p.toml:7:1: parameters.m2: parameters refer to each other in a cycle: m2 -> w -> m2"
    );
    assert_eq!(
        error("rho = 7800", "pi = 3"),
        "p.toml:4:1: parameters.pi: invalid parameter name \"pi\": \"pi\" is a built-in function or constant"
    );
    assert_eq!(
        error("x = \"L2/2\"", "x = \"sqrt(-1)\""),
        "p.toml:15:17: bodies.crank.initial.x: expected a finite initial x (m), found NaN"
    );
}
