//! The ideal four-bar (`models/fourbar_ideal.toml`) in closed form: loop-closure angles,
//! rates and accelerations of coupler and rocker at constant crank speed.

use std::f64::consts::PI;

/// Ground, crank, coupler and rocker lengths of `models/fourbar_ideal.toml` (m).
pub const L1: f64 = 0.8;
pub const L2: f64 = 0.25;
pub const L3: f64 = 0.75;
pub const L4: f64 = 0.45;

/// Closed-form (θ3, θ4, θ̇3, θ̇4, θ̈3, θ̈4) at crank angle θ2 and constant speed ω, open branch
/// (B above the line A–O4).
pub fn closed_form(theta2: f64, omega: f64) -> [f64; 6] {
    let a = [L2 * theta2.cos(), L2 * theta2.sin()];
    let o4 = [L1, 0.0];
    let d = [o4[0] - a[0], o4[1] - a[1]];
    let dist = d[0].hypot(d[1]);
    // B is where the circles (A, L3) and (O4, L4) meet; the open branch is to the left of A→O4.
    let along = (L3 * L3 - L4 * L4 + dist * dist) / (2.0 * dist);
    let h = (L3 * L3 - along * along).sqrt();
    let u = [d[0] / dist, d[1] / dist];
    let b = [
        a[0] + along * u[0] - h * u[1],
        a[1] + along * u[1] + h * u[0],
    ];
    let t3 = (b[1] - a[1]).atan2(b[0] - a[0]);
    let t4 = (b[1] - o4[1]).atan2(b[0] - o4[0]);
    // Velocity loop: L3 θ̇3 e3⊥ − L4 θ̇4 e4⊥ = −L2 ω e2⊥, with e⊥ = (−sin, cos).
    let solve = |rx: f64, ry: f64| {
        let (a11, a12, a21, a22) = (-L3 * t3.sin(), L4 * t4.sin(), L3 * t3.cos(), -L4 * t4.cos());
        let det = a11 * a22 - a12 * a21;
        ((rx * a22 - a12 * ry) / det, (a11 * ry - a21 * rx) / det)
    };
    let (w3, w4) = solve(L2 * omega * theta2.sin(), -L2 * omega * theta2.cos());
    // Acceleration loop: the same matrix; right side from the centripetal terms.
    let rx = L2 * omega * omega * theta2.cos() + L3 * w3 * w3 * t3.cos() - L4 * w4 * w4 * t4.cos();
    let ry = L2 * omega * omega * theta2.sin() + L3 * w3 * w3 * t3.sin() - L4 * w4 * w4 * t4.sin();
    let (a3, a4) = solve(rx, ry);
    [t3, t4, w3, w4, a3, a4]
}

/// `angle` shifted by a multiple of 2π to lie within π of `reference`.
pub fn unwrap_near(angle: f64, reference: f64) -> f64 {
    angle + 2.0 * PI * ((reference - angle) / (2.0 * PI)).round()
}

/// Output columns of the coupler and rocker in the order of [`closed_form`].
pub const COLUMNS: [&str; 6] = [
    "coupler.phi",
    "rocker.phi",
    "coupler.omega",
    "rocker.omega",
    "coupler.alpha",
    "rocker.alpha",
];

/// Scales that turn a bound on the angles into one on the rates (~12 rad/s) and accelerations
/// (~10³ rad/s²), whose closed forms amplify the angle error by ω and ω².
pub const SCALES: [f64; 6] = [1.0, 1.0, 12.0, 12.0, 1000.0, 1000.0];

/// Asserts that every sample of `rec` (a run of `models/fourbar_ideal.toml` at crank speed
/// `omega`, crank angle ωt) has the closed form's angles, rates and accelerations within
/// `bound` after [`SCALES`]; returns the largest scaled error.
pub fn assert_closed_form(
    label: &str,
    rec: &linkdyn::solve::Recorder,
    omega: f64,
    bound: f64,
) -> f64 {
    let cols: Vec<Vec<f64>> = COLUMNS.iter().map(|c| super::col(rec, c)).collect();
    let mut worst: f64 = 0.0;
    for (i, t) in rec.t.iter().enumerate() {
        let exact = closed_form(omega * t, omega);
        for k in 0..6 {
            let value = if k < 2 {
                unwrap_near(exact[k], cols[k][i])
            } else {
                exact[k]
            };
            let err = (cols[k][i] - value).abs() / SCALES[k];
            worst = worst.max(err);
            assert!(
                err < bound,
                "{label}: {} at t = {t}: {} vs closed form {value} (scaled error {err:e}, bound {bound:e})",
                COLUMNS[k],
                cols[k][i]
            );
        }
    }
    worst
}
