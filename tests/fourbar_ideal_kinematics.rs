//! The ideal four-bar against closed-form loop-closure kinematics, the reference check values,
//! and the driver torque against the power balance M2 ω = d(T + U)/dt.

mod common;
use common::fourbar::{COLUMNS, assert_closed_form, closed_form};
use common::*;
use linkdyn::solve::Method;
use std::f64::consts::PI;

#[test]
fn closed_form_check_values_of_the_reference() {
    let omega = 250.0 * PI / 30.0;
    let [t3, t4, w3, w4, ..] = closed_form(0.0, omega);
    assert!(
        (t3.to_degrees() - 36.5795).abs() < 5e-5,
        "theta3 {}°",
        t3.to_degrees()
    );
    assert!(
        (t4.to_degrees() - 83.3294).abs() < 5e-5,
        "theta4 {}°",
        t4.to_degrees()
    );
    assert!(
        (w3 + 11.899972).abs() < 1e-6 && (w4 + 11.899972).abs() < 1e-6,
        "rates {w3} {w4}"
    );
}

#[test]
fn dae_matches_loop_closure_over_two_turns() {
    let model = load("models/fourbar_ideal.toml", &[]);
    let omega = 250.0 * PI / 30.0;
    let t_end = 2.0 * 2.0 * PI / omega;
    let (rec, _) = run_dae(&model, t_end, 1e-3, Method::Dop853, 1e-12, 1e-14);
    let cols: Vec<Vec<f64>> = COLUMNS.iter().map(|c| col(&rec, c)).collect();
    // Check values at t = 0 (the assembly) to the reference's printed digits.
    assert!(
        (cols[0][0].to_degrees() - 36.5795).abs() < 5e-5,
        "theta3(0) = {}°",
        cols[0][0].to_degrees()
    );
    assert!(
        (cols[1][0].to_degrees() - 83.3294).abs() < 5e-5,
        "theta4(0) = {}°",
        cols[1][0].to_degrees()
    );
    assert!(
        (cols[2][0] + 11.899972).abs() < 1e-6,
        "theta3'(0) = {}",
        cols[2][0]
    );
    assert!(
        (cols[3][0] + 11.899972).abs() < 1e-6,
        "theta4'(0) = {}",
        cols[3][0]
    );
    assert_closed_form("fourbar_ideal, dae", &rec, omega, 1e-9);
}

#[test]
fn driver_torque_balances_the_power() {
    let model = load("models/fourbar_ideal.toml", &[]);
    let omega = 250.0 * PI / 30.0;
    let t_end = 2.0 * 2.0 * PI / omega;
    let (rec, _) = run_dae(&model, t_end, 1e-3, Method::Dop853, 1e-12, 1e-14);
    let g = model.settings.gravity;
    let torque = col(&rec, "motor.torque");
    // d(T + U)/dt = Σ m v·a + I ω α − m g·v, from the sampled states: no numerical derivative.
    let mut power = vec![0.0; rec.len()];
    for b in &model.bodies {
        let c = |q: &str| col(&rec, &format!("{}.{q}", b.name));
        let (vx, vy, w, ax, ay, al) = (c("vx"), c("vy"), c("omega"), c("ax"), c("ay"), c("alpha"));
        for i in 0..rec.len() {
            power[i] += b.mass * (vx[i] * ax[i] + vy[i] * ay[i]) + b.inertia * w[i] * al[i]
                - b.mass * (g[0] * vx[i] + g[1] * vy[i]);
        }
    }
    let scale = torque.iter().map(|m| (m * omega).abs()).fold(0.0, f64::max);
    for i in 0..rec.len() {
        let err = (torque[i] * omega - power[i]).abs() / scale;
        assert!(
            err < 1e-6,
            "t = {}: M2 ω = {} W vs dE/dt = {} W (relative {err:e})",
            rec.t[i],
            torque[i] * omega,
            power[i]
        );
    }
}
