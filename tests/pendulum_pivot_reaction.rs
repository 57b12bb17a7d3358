//! The pivot reaction of a compound pendulum against its closed form, at every sample.
//!
//! A rigid body of mass m and moment of inertia I about its centre of mass G swings about a
//! fixed pivot O at distance d = |OG|. Let θ be the angle of OG from the downward vertical, so
//! the rod's x-axis (O → G) is at φ = θ − π/2, with unit vectors
//! u = (sin θ, −cos θ) from O to G and t = du/dθ = (cos θ, sin θ). Then
//! - moment balance about the fixed pivot: I_O θ̈ = −m g d sin θ, with I_O = I + m d²;
//! - acceleration of G: a_G = d θ̈ t − d θ̇² u;
//! - Newton for the body, R being the force of the pivot on it: m a_G = R + m (0, −g), so
//!
//!   R·u = −m (g cos θ + d θ̇²)                       (along the rod, towards the pivot),
//!   R·t = m (d θ̈ + g sin θ) = m g sin θ · I / I_O    (across it).
//!
//! For a point mass (I → 0) the first is the familiar m(g cos θ + L θ̇²) and the second
//! vanishes. The test checks both components of `O.fx, O.fy` (the reaction of joint "O" on its
//! second body, the rod) with θ and θ̇ taken from the same sample, for the shipped uniform rod
//! (I = m L²/12, where the cross component is a quarter of m g sin θ) and for a point-mass-like
//! body (I = 1e-9 kg·m²), each released from rest at 60° and at 170° (near the top, where d θ̇²
//! dominates g).

mod common;
use common::*;
use linkdyn::solve::Method;
use std::f64::consts::PI;

const G: f64 = 9.81;
const MASS: f64 = 1.0;
/// Pivot to centre of mass (m): half the shipped 1 m rod.
const D: f64 = 0.5;

/// Overrides that release the rod from rest at `theta0` from the downward vertical, with
/// moment of inertia `inertia` about its centre of mass.
fn overrides(theta0: f64, inertia: f64) -> Vec<String> {
    let phi = -PI / 2.0 + theta0;
    vec![
        format!("bodies.rod.initial.phi={phi:e}"),
        format!("bodies.rod.initial.x={:e}", D * phi.cos()),
        format!("bodies.rod.initial.y={:e}", D * phi.sin()),
        format!("bodies.rod.inertia={inertia:e}"),
    ]
}

fn check(theta0: f64, inertia: f64) {
    let sets = overrides(theta0, inertia);
    let sets: Vec<&str> = sets.iter().map(String::as_str).collect();
    let model = load("models/pendulum.toml", &sets);
    let i_o = inertia + MASS * D * D;
    // Two seconds: every case passes the bottom (a quarter period, √(I_O/(m g d)) K(sin(θ0/2)),
    // is at most 1.0 s, for the rod from 170°), which the last assertion checks.
    let (rec, _) = run_dae(&model, 2.0, 1e-3, Method::Dop853, 1e-11, 1e-13);
    let (t, phi, omega) = (rec.t.clone(), col(&rec, "rod.phi"), col(&rec, "rod.omega"));
    let (fx, fy) = (col(&rec, "O.fx"), col(&rec, "O.fy"));
    assert!(t.len() > 1000, "{} samples", t.len());
    // Tolerance, relative to the force scale m (g + d θ̇²) of the sample: the reaction comes from
    // the multipliers of the same state, so it differs from the closed form by (a) the Baumgarte
    // terms m (2α Φ̇ + β² Φ) of a sample off the constraint manifold by the dense output's error
    // (~rtol): 1e-9 covers them (measured: 2.5e-11 for the rod); and (b) the round-off of the
    // Schur-complement solve, whose condition number grows as m d²/I (the rotation of a nearly
    // point-like body has almost no inertia): 10 ε m d²/I (measured 3.7e-8 for I = 1e-9 kg·m²,
    // where m d²/I = 2.5e8 and 10 ε m d²/I = 5.6e-7).
    let relative = 1e-9 + 10.0 * f64::EPSILON * MASS * D * D / inertia;
    let mut max_along: f64 = 0.0;
    for i in 0..t.len() {
        let theta = phi[i] + PI / 2.0;
        let theta_dot = omega[i];
        let u = [theta.sin(), -theta.cos()];
        let tangent = [theta.cos(), theta.sin()];
        let along = fx[i] * u[0] + fy[i] * u[1];
        let across = fx[i] * tangent[0] + fy[i] * tangent[1];
        let along_exact = -MASS * (G * theta.cos() + D * theta_dot * theta_dot);
        let across_exact = MASS * G * theta.sin() * inertia / i_o;
        max_along = max_along.max(along_exact.abs());
        let tol = relative * MASS * (G + D * theta_dot * theta_dot);
        assert!(
            (along - along_exact).abs() < tol && (across - across_exact).abs() < tol,
            "θ0 = {theta0}, I = {inertia:e}, t = {}: reaction along the rod {along:e} N vs {along_exact:e} N, across {across:e} N vs {across_exact:e} N (tolerance {tol:e} N)",
            t[i]
        );
    }
    // The swing went through the bottom, where the pull is largest: m g (3 − 2 cos θ0) for the
    // point mass, from energy conservation; the rod's is smaller (it rotates too).
    let bottom = MASS * G * (1.0 + 2.0 * MASS * D * D / i_o * (1.0 - theta0.cos()));
    assert!(
        (max_along - bottom).abs() < 1e-3 * bottom,
        "θ0 = {theta0}, I = {inertia:e}: largest pull {max_along} N vs {bottom} N at the bottom"
    );
}

#[test]
fn uniform_rod_released_at_60_degrees() {
    check(PI / 3.0, MASS / 12.0);
}

#[test]
fn uniform_rod_released_near_the_top() {
    check(170.0_f64.to_radians(), MASS / 12.0);
}

#[test]
fn point_mass_released_at_60_degrees() {
    check(PI / 3.0, 1e-9);
}

#[test]
fn point_mass_released_near_the_top() {
    check(170.0_f64.to_radians(), 1e-9);
}
