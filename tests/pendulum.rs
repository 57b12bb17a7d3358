//! Compound pendulum: small-amplitude period against 2π√(I_O/(m g d)), the exact period of a
//! large swing against the elliptic-integral formula, and energy conservation.

mod common;
use common::*;
use linkdyn::solve::Method;
use std::f64::consts::PI;

const G: f64 = 9.81;
const MASS: f64 = 1.0;
const D: f64 = 0.5; // pivot to centre of mass (m)
const I_CM: f64 = 1.0 / 12.0;

/// Overrides that release the rod from rest at angle `theta0` from the downward vertical.
fn released_at(theta0: f64) -> Vec<String> {
    let phi = -PI / 2.0 + theta0;
    vec![
        format!("bodies.rod.initial.phi={phi:e}"),
        format!("bodies.rod.initial.x={:e}", D * phi.cos()),
        format!("bodies.rod.initial.y={:e}", D * phi.sin()),
    ]
}

/// Times where θ = φ + π/2 crosses zero upwards, by cubic Hermite interpolation of the samples
/// (φ and φ̇ = ω are both sampled, so the interpolant is O(dt⁴) accurate).
fn upward_crossings(t: &[f64], phi: &[f64], omega: &[f64]) -> Vec<f64> {
    let theta: Vec<f64> = phi.iter().map(|p| p + PI / 2.0).collect();
    let mut out = Vec::new();
    for i in 1..t.len() {
        if theta[i - 1] < 0.0 && theta[i] >= 0.0 {
            let h = t[i] - t[i - 1];
            let hermite = |s: f64| {
                let (s2, s3) = (s * s, s * s * s);
                (2.0 * s3 - 3.0 * s2 + 1.0) * theta[i - 1]
                    + (s3 - 2.0 * s2 + s) * h * omega[i - 1]
                    + (-2.0 * s3 + 3.0 * s2) * theta[i]
                    + (s3 - s2) * h * omega[i]
            };
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if hermite(mid) < 0.0 {
                    lo = mid
                } else {
                    hi = mid
                }
            }
            out.push(t[i - 1] + 0.5 * (lo + hi) * h);
        }
    }
    out
}

fn measured_period(theta0: f64, t_end: f64) -> f64 {
    let overrides = released_at(theta0);
    let refs: Vec<&str> = overrides.iter().map(String::as_str).collect();
    let model = load("models/pendulum.toml", &refs);
    let (rec, _) = run_dae(&model, t_end, 1e-3, Method::Dop853, 1e-12, 1e-14);
    let crossings = upward_crossings(&rec.t, &col(&rec, "rod.phi"), &col(&rec, "rod.omega"));
    assert!(
        crossings.len() >= 3,
        "need at least 3 crossings, got {}",
        crossings.len()
    );
    (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64
}

fn agm(mut a: f64, mut b: f64) -> f64 {
    for _ in 0..40 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    a
}

#[test]
fn small_amplitude_period_matches_linear_theory() {
    let t_lin = 2.0 * PI * ((I_CM + MASS * D * D) / (MASS * G * D)).sqrt();
    // θ0 = 1e-3 rad: the amplitude correction θ0²/16 ≈ 6e-8 is far below the 1e-6 tolerance.
    let period = measured_period(1e-3, 6.0 * t_lin);
    let rel = (period - t_lin).abs() / t_lin;
    assert!(
        rel < 1e-6,
        "period {period} s vs linear {t_lin} s: relative {rel:e}"
    );
}

#[test]
fn large_amplitude_period_matches_elliptic_integral() {
    let theta0: f64 = 2.0; // rad, about 115°
    let omega0 = ((MASS * G * D) / (I_CM + MASS * D * D)).sqrt();
    let k = (theta0 / 2.0).sin();
    // T = 4 K(k)/ω0, K(k) = π / (2 AGM(1, √(1 − k²))).
    let exact = 4.0 * (PI / (2.0 * agm(1.0, (1.0 - k * k).sqrt()))) / omega0;
    let period = measured_period(theta0, 5.0 * exact);
    let rel = (period - exact).abs() / exact;
    // 1e-8: crossing times from rtol-1e-12 runs and O(dt⁴) Hermite interpolation.
    assert!(
        rel < 1e-8,
        "period {period} s vs elliptic {exact} s: relative {rel:e}"
    );
}

#[test]
fn large_amplitude_energy_is_conserved() {
    let overrides = released_at(2.5);
    let refs: Vec<&str> = overrides.iter().map(String::as_str).collect();
    let model = load("models/pendulum.toml", &refs);
    let (rec, _) = run_dae(&model, 10.0, 1e-2, Method::Dop853, 1e-12, 1e-14);
    let e = mechanical_energy(&model, &rec);
    let scale = MASS * G * D; // energy scale (J): the swing spans ±m g d
    let drift = e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max) / scale;
    assert!(
        drift < 1e-9,
        "energy drift {drift:e} relative to m g d over 10 s"
    );
}

#[test]
fn constant_torque_without_gravity_gives_uniform_angular_acceleration() {
    let text = std::fs::read_to_string("models/pendulum.toml").unwrap_or_else(|e| panic!("{e}"))
        + "\n[[forces]]\nname = \"motor\"\ntype = \"torque\"\nbody = \"rod\"\ntorque = 0.5\n";
    let model = linkdyn::model::load_str(
        &text,
        "pendulum_torque.toml",
        &["settings.gravity=[0.0, 0.0]".to_string()],
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let (rec, _) = run_dae(&model, 2.0, 1e-2, Method::Dop853, 1e-12, 1e-14);
    let alpha = 0.5 / (I_CM + MASS * D * D); // τ / I_O
    let phi = col(&rec, "rod.phi");
    for (i, t) in rec.t.iter().enumerate() {
        let exact = phi[0] + 0.5 * alpha * t * t;
        // 1e-9 rad: rtol 1e-12 on an angle that grows to ~3 rad.
        assert!(
            (phi[i] - exact).abs() < 1e-9,
            "t = {t}: phi = {} vs {exact}",
            phi[i]
        );
    }
}
