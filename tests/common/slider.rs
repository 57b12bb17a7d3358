//! A free rectangular slider in a prismatic-clearance guide on the ground x-axis, and the
//! one-degree-of-freedom impact of a mass on the joint's contact law that its corners are
//! checked against (`tests/prismatic_clearance.rs`, `tests/prismatic_guide_ends.rs`).

use linkdyn::model::Model;
use linkdyn::simulation::{ClearanceSummary, Simulation, SimulationOptions, Trajectory};
use linkdyn::solve::{Method, SolverOptions};

/// The slider and guide (SI): mass, length, width, clearance, corner stiffness and exponent.
pub const MASS: f64 = 1.0;
pub const LENGTH: f64 = 0.1;
pub const WIDTH: f64 = 0.04;
pub const CLEARANCE: f64 = 1e-3;
pub const K: f64 = 1e9;
pub const N: f64 = 1.5;

/// The slider of [`MASS`] (inertia 0.001 kg·m²), released centred in the guide.
pub struct SliderInGuide<'a> {
    /// Gravity along −y (m/s²).
    pub gravity: f64,
    /// Initial speed along the guide (m/s).
    pub vx: f64,
    /// Initial tilt of the slider in the guide (rad).
    pub tilt: f64,
    /// End stops this far (m) ahead of each face of the centred slider; none if `None`.
    pub stop_gap: Option<f64>,
    /// The `[joints.contact]` table's lines.
    pub contact: &'a str,
    /// The `[joints.friction]` table's lines.
    pub friction: &'a str,
}

impl SliderInGuide<'_> {
    /// The model, named `name`.
    pub fn model(&self, name: &str) -> Model {
        let (g, vx, tilt) = (self.gravity, self.vx, self.tilt);
        let stops = match self.stop_gap {
            Some(gap) => format!(
                "guide_start = {}\nguide_end = {}\n",
                -0.5 * LENGTH - gap,
                0.5 * LENGTH + gap
            ),
            None => String::new(),
        };
        let (contact, friction) = (self.contact, self.friction);
        let text = format!(
            r#"
[model]
name = "{name}"
[settings]
gravity = [0.0, -{g}]
[ground]
points = {{ G = [0.0, 0.0] }}
[[bodies]]
name = "slider"
mass = {MASS}
inertia = 0.001
points = {{ C = [0.0, 0.0] }}
initial = {{ x = 0.0, y = 0.0, phi = 0.0, vx = {vx} }}
[[joints]]
name = "guide"
type = "prismatic-clearance"
body_a = "ground"
point_a = "G"
body_b = "slider"
point_b = "C"
clearance = {CLEARANCE}
slider_length = {LENGTH}
slider_width = {WIDTH}
stiffness = {K}
initial_tilt = {tilt}
{stops}[joints.contact]
{contact}
[joints.friction]
{friction}
"#
        );
        linkdyn::model::load_str(&text, &format!("{name}.toml"), &[])
            .unwrap_or_else(|e| panic!("{e}"))
    }
}

/// Runs `model` into memory, panicking with the error text.
pub fn run(model: &Model, options: SimulationOptions) -> Trajectory {
    Simulation::new(model, options)
        .and_then(|s| s.run_to_memory())
        .unwrap_or_else(|e| panic!("{e}"))
}

/// `method` at `rtol`, atol = rtol/100.
pub fn solver(method: Method, rtol: f64) -> SolverOptions {
    SolverOptions::default()
        .method(method)
        .rtol(rtol)
        .atol(rtol * 1e-2)
        .build()
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The summary of contact site `name` (a corner `guide.c0`…, an end stop `guide.e0`…).
pub fn site<'a>(traj: &'a Trajectory, name: &str) -> &'a ClearanceSummary {
    traj.summary
        .clearance_joints
        .iter()
        .find(|j| j.joint == name)
        .unwrap_or_else(|| panic!("no contact site {name}"))
}

/// |a − b|/|b|.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The summary of contact site `name`, whose first impact came at time `t` (s) with impact
/// velocity `v` (m/s), both to 1e-7 relative (at rtol 1e-10 the event time and state are
/// located to about that), and went as deep as `delta_max` (m) to 1e-6 relative.
pub fn assert_first_impact<'a>(
    traj: &'a Trajectory,
    name: &str,
    t: f64,
    v: f64,
    delta_max: f64,
) -> &'a ClearanceSummary {
    let s = site(traj, name);
    let first = s
        .impacts
        .first()
        .unwrap_or_else(|| panic!("{name}: no impact"));
    assert!(
        rel(first.t, t) < 1e-7,
        "{name}: impact at {} s vs {t} s",
        first.t
    );
    assert!(
        rel(first.impact_velocity, v) < 1e-7,
        "{name}: impact velocity {} vs {v}",
        first.impact_velocity
    );
    assert!(
        rel(first.peak_penetration, delta_max) < 1e-6,
        "{name}: peak penetration {} vs closed form {delta_max}",
        first.peak_penetration
    );
    s
}

/// Deepest penetration of a mass `m` hitting a K δⁿ spring at speed `v` with a constant
/// acceleration `g` along the motion: ½ m v² + m g δ = K δⁿ⁺¹/(n + 1) (closed form for g = 0,
/// bisection otherwise).
pub fn deepest_penetration(m: f64, v: f64, g: f64) -> f64 {
    if g == 0.0 {
        return ((N + 1.0) * 0.5 * m * v * v / K).powf(1.0 / (N + 1.0));
    }
    let (mut lo, mut hi) = (0.0, 1e-2);
    for _ in 0..200 {
        let d = 0.5 * (lo + hi);
        if 0.5 * m * v * v + m * g * d > K * d.powf(N + 1.0) / (N + 1.0) {
            lo = d;
        } else {
            hi = d;
        }
    }
    lo
}

/// Rebound speed of a mass `m` hitting the Lankarani–Nikravesh law F = K δⁿ (1 + χ δ̇/v),
/// χ = 3(1 − c_r²)/4, at speed `v` with a constant acceleration `g` along the motion:
/// m δ̈ = m g − F from δ = 0, δ̇ = v until δ returns to 0 (classical RK4, 2e5 steps over about
/// the contact time, the crossing interpolated linearly). The one-degree-of-freedom reference.
pub fn rebound_speed(m: f64, v: f64, c_r: f64, g: f64) -> f64 {
    let chi = 0.75 * (1.0 - c_r * c_r);
    let acc = |d: f64, dd: f64| {
        let f = if d > 0.0 {
            (K * d.powf(N) * (1.0 + chi * dd / v)).max(0.0)
        } else {
            0.0
        };
        g - f / m
    };
    let h = 10.0 * deepest_penetration(m, v, g) / v / 2e5;
    let (mut d, mut dd) = (0.0_f64, v);
    loop {
        let (k1d, k1v) = (dd, acc(d, dd));
        let (k2d, k2v) = (
            dd + 0.5 * h * k1v,
            acc(d + 0.5 * h * k1d, dd + 0.5 * h * k1v),
        );
        let (k3d, k3v) = (
            dd + 0.5 * h * k2v,
            acc(d + 0.5 * h * k2d, dd + 0.5 * h * k2v),
        );
        let (k4d, k4v) = (dd + h * k3v, acc(d + h * k3d, dd + h * k3v));
        let d1 = d + h / 6.0 * (k1d + 2.0 * k2d + 2.0 * k3d + k4d);
        let dd1 = dd + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        if d1 <= 0.0 && dd1 < 0.0 {
            let s = d / (d - d1);
            return -(dd + s * (dd1 - dd));
        }
        d = d1;
        dd = dd1;
    }
}
