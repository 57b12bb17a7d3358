//! Claim (docs/model_format.md, drivers): `--revs N` counts turns of the driven crank angle θ(t) where it is known
//! before the run. A prescribed angle gives the first time at which |θ(t) − θ(0)| = 2πN
//! (closed forms below); a prescribed angle that never gets that far, and a torque driver
//! (whose angle is an outcome of the run), are refused with a message that says why and to
//! give `--t-end` instead. Constant speed keeps its closed form 2πN/|ω|.

use linkdyn::model::{Model, load_str};
use linkdyn::simulation::{EndTime, SimulationOptions, end_time};
use std::f64::consts::PI;

/// A rod of length 1 m pinned at one end, no gravity, with the driver given as TOML lines
/// (as in tests/model_drivers.rs).
fn rotor(driver: &str) -> Model {
    let text = format!(
        r#"
[model]
name = "rotor"
[settings]
gravity = [0, 0]
[ground]
points = {{ O = [0, 0] }}
[[bodies]]
name = "rod"
mass = 1
inertia = 0.083333333333333333
points = {{ O = [-0.5, 0] }}
initial = {{ x = 0.5, y = 0, phi = 0 }}
[[joints]]
name = "O"
type = "revolute"
body_a = "ground"
point_a = "O"
body_b = "rod"
point_b = "O"
[[drivers]]
name = "motor"
joint = "O"
{driver}
"#
    );
    load_str(&text, "rotor.toml", &[]).unwrap_or_else(|e| panic!("{e}"))
}

fn turns(model: &Model, n: f64) -> Result<f64, String> {
    end_time(model, EndTime::DriverTurns(n)).map_err(|e| e.to_string())
}

/// The bisection ends within a few ulps of the root: 1e-14 relative (50 ulps) is the
/// resolution of t, not a numerical tolerance of the method.
fn assert_time(case: &str, got: Result<f64, String>, want: f64) {
    let got = got.unwrap_or_else(|e| panic!("{case}: {e}"));
    assert!(
        (got - want).abs() <= 1e-14 * want,
        "{case}: t_end = {got:.17e} s, exact {want:.17e} s"
    );
}

#[test]
fn a_prescribed_angle_ends_where_the_crank_has_turned_n_times() {
    // θ = t²: 2π·2 = t² at t = √(4π).
    let model = rotor("type = \"prescribed-angle\"\nangle = \"t^2\"");
    assert_time("θ = t², 2 turns", turns(&model, 2.0), (4.0 * PI).sqrt());
    // Turning backwards counts too: θ = 1 − 3t, half a turn at t = π/3.
    let model = rotor("type = \"prescribed-angle\"\nangle = \"1 - 3*t\"");
    assert_time("θ = 1 − 3t, 0.5 turn", turns(&model, 0.5), PI / 3.0);
    // Not monotone: θ = 4 sin t first reaches |θ| = 2π·0.5 = π at sin t = π/4.
    let model = rotor("type = \"prescribed-angle\"\nangle = \"4*sin(t)\"");
    assert_time(
        "θ = 4 sin t, 0.5 turn",
        turns(&model, 0.5),
        (PI / 4.0).asin(),
    );
    // The same through the options a run is built from.
    let model = rotor("type = \"prescribed-angle\"\nangle = \"t^2\"");
    let options = SimulationOptions::default().revs(1.0);
    assert_time(
        "θ = t², 1 turn via SimulationOptions",
        end_time(&model, options.end).map_err(|e| e.to_string()),
        (2.0 * PI).sqrt(),
    );
}

#[test]
fn a_prescribed_angle_that_never_gets_there_is_refused_with_the_reason() {
    // |2 sin t| ≤ 2 < 2π: one turn is never reached. The march stops after its 1e6 steps of
    // 0.05 rad of angle (at most), here at t = 3.94e4 s, well before its horizon of 1e6 s.
    let model = rotor("type = \"prescribed-angle\"\nangle = \"2*sin(t)\"");
    assert_eq!(
        turns(&model, 1.0),
        Err("revs: driver \"motor\" prescribes θ(t) = 2*sin(t): |θ(t) − θ(0)| does not reach 1 turn(s) (6.283185 rad) by t = 3.940294e4 s, where the search stopped (at most 2.000000 rad); give `t_end` instead".to_string())
    );
}

#[test]
fn a_torque_driver_is_refused_because_its_turns_are_an_outcome() {
    let model = rotor("type = \"torque\"\ntorque = \"2*(1 - omega/10)\"");
    assert_eq!(
        turns(&model, 2.0),
        Err("revs: driver \"motor\" is a torque driver: how far its crank turns is an outcome of the run, not known before it; give `t_end` (and read the turns from the joint's angle in the results)".to_string())
    );
}

#[test]
fn constant_speed_keeps_its_closed_form() {
    // 3 rad/s: two turns take 4π/3 s, exactly as computed before the search existed.
    let model = rotor("type = \"constant-speed\"\nspeed = 3");
    assert_eq!(turns(&model, 2.0), Ok(2.0 * 2.0 * PI / 3.0));
}
