//! The in-line slider-crank against its closed form x_B = r cos θ + √(l² − r² sin² θ).

mod common;
use common::*;
use linkdyn::solve::Method;
use std::f64::consts::PI;

const R: f64 = 0.1;
const L: f64 = 0.3;

/// Slider position, velocity and acceleration at crank angle θ = ωt, constant ω.
fn closed_form(theta: f64, omega: f64) -> [f64; 3] {
    let (s, c) = theta.sin_cos();
    let root = (L * L - R * R * s * s).sqrt();
    let x = R * c + root;
    // dx/dθ and d²x/dθ², then chain rule with θ̇ = ω, θ̈ = 0.
    let dx = -R * s - R * R * s * c / root;
    let ddx = -R * c - R * R * (c * c - s * s) / root - R.powi(4) * s * s * c * c / root.powi(3);
    [x, dx * omega, ddx * omega * omega]
}

#[test]
fn slider_follows_the_closed_form() {
    let model = load("models/slider_crank.toml", &[]);
    let omega = 600.0 * PI / 30.0;
    let t_end = 2.0 * 2.0 * PI / omega;
    let (rec, _) = run_dae(&model, t_end, 1e-4, Method::Dop853, 1e-12, 1e-14);
    let (x, v, a) = (
        col(&rec, "slider.x"),
        col(&rec, "slider.vx"),
        col(&rec, "slider.ax"),
    );
    let y = col(&rec, "slider.y");
    for (i, t) in rec.t.iter().enumerate() {
        let [xe, ve, ae] = closed_form(omega * t, omega);
        // Scales: R = 0.1 m, R ω ≈ 6 m/s, R ω² ≈ 400 m/s².
        assert!((x[i] - xe).abs() < 1e-10, "x at t = {t}: {} vs {xe}", x[i]);
        assert!(
            (v[i] - ve).abs() < 1e-9 * 6.0,
            "v at t = {t}: {} vs {ve}",
            v[i]
        );
        assert!(
            (a[i] - ae).abs() < 1e-9 * 400.0,
            "a at t = {t}: {} vs {ae}",
            a[i]
        );
        assert!(
            y[i].abs() < 1e-10,
            "slider left the rail at t = {t}: y = {}",
            y[i]
        );
    }
}
