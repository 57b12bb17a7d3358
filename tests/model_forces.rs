//! Forces as expressions of time and state against closed forms: a torsional spring written as
//! a torque expression of the body angle makes a harmonic oscillator, a force table of time
//! pushes a slider along x(t) = t³/3 (F = 2t, m = 1), and a gas-force table against the driver
//! angle gives the driver the torque F·(dx/dθ) by virtual work.

mod common;
use common::*;
use linkdyn::model::{Model, load_str};
use linkdyn::solve::Method;

fn model(text: &str) -> Model {
    match load_str(text, "test.toml", &[]) {
        Ok(m) => m,
        Err(e) => panic!("{e}"),
    }
}

/// rtol 1e-10 over a second of motion: 1e-8 leaves two orders of margin for the global error.
const TOL: f64 = 1e-8;

#[test]
fn torque_expression_of_the_angle_is_a_torsional_spring() {
    // I_O = m L²/3 = 1/3, k = 3 N·m/rad: ω_n = 3 rad/s, φ(t) = φ_eq + A cos(ω_n t).
    let m = model(
        r#"
[model]
name = "spring"
[settings]
gravity = [0, 0]
[parameters]
k = 3
phi_eq = 0.2
[ground]
points = { O = [0, 0] }
[[bodies]]
name = "rod"
mass = 1
inertia = "1/12"
points = { O = [-0.5, 0] }
initial = { x = "0.5*cos(0.5)", y = "0.5*sin(0.5)", phi = 0.5 }
[[joints]]
name = "O"
type = "revolute"
body_a = "ground"
point_a = "O"
body_b = "rod"
point_b = "O"
[[forces]]
name = "spring"
type = "torque"
body = "rod"
torque = "-k*(rod.phi - phi_eq)"
"#,
    );
    let (rec, _) = run_dae(&m, 1.0, 0.05, Method::Dop853, 1e-10, 1e-12);
    let phi = col(&rec, "rod.phi");
    for (k, &t) in rec.t.iter().enumerate() {
        let want = 0.2 + 0.3 * (3.0 * t).cos();
        assert!(
            (phi[k] - want).abs() < TOL,
            "torsional spring: φ({t}) = {} vs {want}",
            phi[k]
        );
    }
}

/// A free slider on a frictionless rail, pushed by a table force of time.
const SLIDER: &str = r#"
[model]
name = "pushed"
[settings]
gravity = [0, -9.81]
[ground]
points = { rail = [0, 0] }
[[bodies]]
name = "slider"
mass = 1
inertia = 0.01
points = { C = [0, 0] }
initial = { x = 0, y = 0, phi = 0 }
[[joints]]
name = "rail"
type = "prismatic"
body_a = "ground"
point_a = "rail"
body_b = "slider"
point_b = "C"
[[tables]]
name = "push"
x = [0, 1, 2]
y = [0, 2, 2]
[[forces]]
name = "push"
type = "force"
body = "slider"
point = "C"
force = ["push(t)", 0]
"#;

#[test]
fn table_force_of_time_is_interpolated_linearly() {
    let (rec, _) = run_dae(&model(SLIDER), 1.5, 0.05, Method::Dop853, 1e-10, 1e-12);
    let (x, vx) = (col(&rec, "slider.x"), col(&rec, "slider.vx"));
    for (k, &t) in rec.t.iter().enumerate() {
        // F = 2t until t = 1, then 2: x = t³/3, then 1/3 + (t − 1) + (t − 1)².
        let (want_x, want_v) = if t <= 1.0 {
            (t * t * t / 3.0, t * t)
        } else {
            let s = t - 1.0;
            (1.0 / 3.0 + s + s * s, 1.0 + 2.0 * s)
        };
        assert!(
            (x[k] - want_x).abs() < TOL,
            "table force: x({t}) = {} vs {want_x}",
            x[k]
        );
        assert!(
            (vx[k] - want_v).abs() < TOL,
            "table force: vx({t}) = {} vs {want_v}",
            vx[k]
        );
    }
}

#[test]
fn gas_force_table_against_the_driver_angle_loads_the_driver_by_virtual_work() {
    // Slider-crank at constant speed with F = −gas(θ mod 2π) on the piston: the work of the
    // driver torque and of the gas force equals the change of kinetic + potential energy.
    let text = std::fs::read_to_string("models/slider_crank.toml").unwrap_or_default()
        + r#"
[[tables]]
name = "gas"
x = [0, 1, 3, 6.3]
y = [0, 500, 100, 0]
[[forces]]
name = "gas"
type = "force"
body = "slider"
point = "B"
force = ["-gas(mod(theta, 2*pi))", 0]
"#;
    let m = model(&text);
    let (rec, _) = run_dae(&m, 0.1, 1e-4, Method::Dop853, 1e-10, 1e-12);
    let (torque, omega) = (col(&rec, "motor.torque"), col(&rec, "crank.omega"));
    let (x, vx) = (col(&rec, "slider.x"), col(&rec, "slider.vx"));
    let energy = mechanical_energy(&m, &rec);
    // Trapezoidal ∫ (τ ω + F ẋ) dt with dt = 1e-4 s: error ~ dt² · max|P̈| · t / 12 ≈ 1e-4 J for
    // the ~2 kW peaks here; the tolerance is 1e-3 of the work done.
    let gas = |theta: f64| {
        let th = theta.rem_euclid(2.0 * std::f64::consts::PI);
        let (xs, ys) = ([0.0, 1.0, 3.0, 6.3], [0.0, 500.0, 100.0, 0.0]);
        let k = xs.iter().rposition(|&xi| xi <= th).unwrap_or(0).min(2);
        ys[k] + (ys[k + 1] - ys[k]) * (th - xs[k]) / (xs[k + 1] - xs[k])
    };
    let phi = col(&rec, "crank.phi");
    let power: Vec<f64> = (0..rec.len())
        .map(|k| torque[k] * omega[k] - gas(phi[k]) * vx[k])
        .collect();
    let mut work = 0.0;
    let mut scale = 0.0_f64;
    for k in 1..rec.len() {
        let dt = rec.t[k] - rec.t[k - 1];
        work += 0.5 * dt * (power[k] + power[k - 1]);
        scale = scale.max(work.abs());
        let de = energy[k] - energy[0];
        assert!(
            (work - de).abs() < 1e-3 * scale.max(1.0),
            "gas force: work {work} J vs ΔE {de} J at t = {}",
            rec.t[k]
        );
    }
    assert!(x.iter().all(|v| v.is_finite()), "finite piston positions");
    assert!(scale > 1.0, "the gas force did work: {scale} J");
}
