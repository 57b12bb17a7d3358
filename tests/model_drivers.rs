//! The new drivers against closed forms: a prescribed angle θ = t² turns the crank at 2t with
//! angular acceleration 2; a speed ramp's angle is θ0 + ω0 t + Δω (T/2 + t − t_s − T) after the
//! ramp; a motor law τ = T0 (1 − ω/ω0) on a free rotor gives ω(t) = ω0 (1 − e^(−T0 t/(I ω0))).
//! The reduced formulation refuses drivers other than constant speed, naming the driver.

mod common;
use common::*;
use linkdyn::model::{Model, load_str};
use linkdyn::solve::Method;

/// A rod of length 1 m pinned at one end (I_O = m L²/3 = 1/3 kg·m²), no gravity, with the
/// driver given as TOML lines.
fn rotor(driver: &str) -> Model {
    let text = format!(
        r#"
[model]
name = "rotor"
[settings]
gravity = [0, 0]
[parameters]
L = 1
m = 1
[ground]
points = {{ O = [0, 0] }}
[[bodies]]
name = "rod"
mass = "m"
inertia = "m*L^2/12"
points = {{ O = ["-L/2", 0] }}
initial = {{ x = "L/2", y = 0, phi = 0 }}
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
    match load_str(&text, "rotor.toml", &[]) {
        Ok(m) => m,
        Err(e) => panic!("{e}"),
    }
}

/// rtol 1e-10: the driver row is kept by Baumgarte to the integration error, so 1e-8 rad and
/// rad/s leave two orders of margin.
const TOL: f64 = 1e-8;

#[test]
fn prescribed_angle_t_squared_turns_the_crank_at_2t() {
    let model = rotor("type = \"prescribed-angle\"\nangle = \"t^2\"");
    let (rec, _) = run_dae(&model, 1.0, 0.05, Method::Dop853, 1e-10, 1e-12);
    let (phi, omega, alpha) = (
        col(&rec, "rod.phi"),
        col(&rec, "rod.omega"),
        col(&rec, "rod.alpha"),
    );
    for (k, &t) in rec.t.iter().enumerate() {
        let cases = [
            ("phi", phi[k], t * t),
            ("omega", omega[k], 2.0 * t),
            ("alpha", alpha[k], 2.0),
        ];
        for (what, got, want) in cases {
            assert!(
                (got - want).abs() < TOL,
                "θ = t²: {what} at t = {t}: {got} vs {want}"
            );
        }
    }
}

#[test]
fn speed_ramp_angle_is_the_integral_of_the_ramp() {
    for shape in ["linear", "smooth"] {
        let model = rotor(&format!(
            "type = \"speed-ramp\"\nspeed0 = 2\nspeed1 = 10\nstart = 0.2\nduration = 0.5\nshape = \"{shape}\"\ninitial_angle = 0.1"
        ));
        let (rec, _) = run_dae(&model, 1.0, 0.05, Method::Dop853, 1e-10, 1e-12);
        let (phi, omega) = (col(&rec, "rod.phi"), col(&rec, "rod.omega"));
        let (Some(&t), Some(&p), Some(&w)) = (rec.t.last(), phi.last(), omega.last()) else {
            panic!("no samples")
        };
        // After the ramp: θ0 + ω0 t + Δω (T/2 + t − t_s − T) = 0.1 + 2 + 8 (0.25 + 0.3) = 6.5.
        assert!((t - 1.0).abs() < 1e-12, "{shape}: last sample at {t}");
        assert!(
            (p - 6.5).abs() < TOL,
            "{shape} ramp: θ(1) = {p}, expected 6.5"
        );
        assert!(
            (w - 10.0).abs() < TOL,
            "{shape} ramp: ω(1) = {w}, expected 10"
        );
        // Halfway through the ramp both shapes are at the mean speed, 6 rad/s (s(1/2) = 1/2).
        let k = rec.t.iter().position(|&t| (t - 0.45).abs() < 1e-9);
        let Some(k) = k else {
            panic!("no sample at t = 0.45")
        };
        assert!(
            (omega[k] - 6.0).abs() < TOL,
            "{shape} ramp: ω(0.45) = {}, expected 6",
            omega[k]
        );
    }
}

#[test]
fn motor_law_on_a_free_rotor_approaches_its_no_load_speed_exponentially() {
    // τ = T0 (1 − ω/ω0) with T0 = 2 N·m, ω0 = 10 rad/s on I_O = 1/3: rate T0/(I ω0) = 0.6 1/s.
    let model = rotor("type = \"torque\"\ntorque = \"2*(1 - omega/10)\"");
    let (rec, _) = run_dae(&model, 2.0, 0.1, Method::Dop853, 1e-10, 1e-12);
    let omega = col(&rec, "rod.omega");
    let phi = col(&rec, "rod.phi");
    for (k, &t) in rec.t.iter().enumerate() {
        let want = 10.0 * (1.0 - (-0.6 * t).exp());
        let want_phi = 10.0 * t - 10.0 / 0.6 * (1.0 - (-0.6 * t).exp());
        assert!(
            (omega[k] - want).abs() < TOL,
            "motor law: ω({t}) = {} vs {want}",
            omega[k]
        );
        assert!(
            (phi[k] - want_phi).abs() < TOL,
            "motor law: φ({t}) = {} vs {want_phi}",
            phi[k]
        );
    }
}

#[test]
fn reduced_formulation_refuses_a_speed_ramp() {
    let text = std::fs::read_to_string("models/farahan2016.toml").unwrap_or_default();
    let text = text
        .replace(
            "type = \"constant-speed\"",
            "type = \"speed-ramp\"\nspeed0 = 0\nduration = 0.1",
        )
        .replace("speed_rpm", "speed1_rpm");
    let model = match load_str(&text, "farahan2016.toml", &[]) {
        Ok(m) => m,
        Err(e) => panic!("{e}"),
    };
    let err = linkdyn::formulation::ReducedLagrangian::new(&model)
        .err()
        .map(|e| e.to_string());
    let err = err.unwrap_or_default();
    assert!(
        err.contains("driver \"motor\" is not a constant-speed driver; the reduced formulation integrates the four-bar at a constant crank speed (use the DAE formulation)"),
        "{err}"
    );
}
