//! A grazing contact that fits inside one large step is still found, at the exact time, once per
//! revolution — and the grazing guard that makes this possible only shortens the steps near the
//! wall.
//!
//! Construction (no gravity, so nothing but the driver moves anything): a body "arm" turns at a
//! constant speed ω about the ground pivot P = (0, 0), its centre of mass on P, so its motion is
//! prescribed by the revolute joint and the driver whatever the contact force does (the force
//! only changes the reactions). The journal of a clearance joint is the arm's point J at distance
//! r from P; the bearing is the ground point B = (−d, 0). With the arm angle φ(t) = π + ωt,
//!
//! ```text
//!     e(t) = J − B = (r cos φ + d, r sin φ),   |e|² = r² + d² + 2 r d cos φ,
//! ```
//!
//! so the journal centre circles inside the clearance circle and, with r + d = c + ε, bulges
//! past it by at most ε once per revolution, around φ = 0 (mod 2π). Contact (δ = |e| − c > 0)
//! lasts while cos φ > cos θ_c, cos θ_c = (c² − r² − d²)/(2 r d): impacts at φ = 2πk − θ_c,
//! separations at φ = 2πk + θ_c, in closed form.
//!
//! The motion is linear in t (φ̇ constant, the centre of mass at rest), so the Runge–Kutta error
//! estimate is zero to rounding and the controller would take steps of any size: only the
//! grazing guard (`src/contact/grazing.rs`) stands between the integrator and a step over the
//! whole contact. The graze depth ε = 2 µm = 4e-3·c is 4× the depth
//! `GRAZE_DEPTH_FRACTION`·c = 0.5 µm below which the guard allows a graze to be missed, so the
//! guard guarantees every one of these contacts is seen.

use linkdyn::formulation::{Crossing, Dae, DaeOptions, Formulation};
use linkdyn::model::Model;
use linkdyn::solve::{Method, Recorder, SolverOptions, Stepper, Stop, integrate};
use std::f64::consts::PI;

/// Radial clearance c (m).
const C: f64 = 5e-4;
/// How far the journal's path bulges past the clearance circle (m).
const EPSILON: f64 = 2e-6;
/// Journal offset r from P and bearing offset d from P (m): r + d = c + ε, r = d maximises r·d
/// and so makes the contact as short as this ε allows.
const R: f64 = (C + EPSILON) / 2.0;
/// Arm speed (rpm) and revolutions run.
const SPEED_RPM: f64 = 60.0;
const REVS: usize = 5;

fn omega() -> f64 {
    SPEED_RPM * PI / 30.0
}

fn model() -> Model {
    let text = format!(
        r#"
[model]
name = "grazing"
description = "prescribed circular journal path bulging {EPSILON} m past the clearance once per turn"

[settings]
gravity = [0.0, 0.0]

[ground]
points = {{ P = [0.0, 0.0], B = [{minus_d:e}, 0.0] }}

[[bodies]]
name = "arm"
mass = 1.0
inertia = 0.01
points = {{ P = [0.0, 0.0], J = [{r:e}, 0.0] }}
initial = {{ x = 0.0, y = 0.0, phi = {phi0:e} }}

[[joints]]
name = "P"
type = "revolute"
body_a = "ground"
point_a = "P"
body_b = "arm"
point_b = "P"

[[joints]]
name = "G"
type = "clearance"
bearing = "ground"
bearing_point = "B"
journal = "arm"
journal_point = "J"
clearance = {C:e}
journal_radius = 0.01
initial_eccentricity = [0.0, 0.0]

[joints.contact]
law = "hertz"

[joints.friction]
law = "none"

[[drivers]]
name = "motor"
type = "constant-speed"
joint = "P"
speed_rpm = {SPEED_RPM:e}
initial_angle = {phi0:e}
"#,
        minus_d = -R,
        r = R,
        phi0 = PI,
    );
    match linkdyn::model::load_str(&text, "grazing.toml", &[]) {
        Ok(m) => m,
        Err(e) => panic!("{e}"),
    }
}

/// Half-angle θ_c of the contact arc: 1 − cos θ_c = ((r + d)² − c²)/(2 r d) = ε(2c + ε)/(2 r d),
/// taken through the half-angle form to avoid cancellation.
fn contact_half_angle() -> f64 {
    let one_minus_cos = EPSILON * (2.0 * C + EPSILON) / (2.0 * R * R);
    2.0 * (one_minus_cos / 2.0).sqrt().asin()
}

/// The DAE of the model, its initial state and the solver options, for `method`.
fn setup(method: Method) -> (Dae, Vec<f64>, SolverOptions) {
    let dae = match Dae::new(&model(), &DaeOptions::default()) {
        Ok(d) => d,
        Err(e) => panic!("{e}"),
    };
    let y0 = dae.initial_state();
    // The assembly holds the clearance joint as a revolute joint at its initial eccentricity for
    // the positions; for the velocities that contradicts the driver (the journal moves at ω r
    // relative to the fixed bearing), so the assembly falls back to the rows of the dynamics and
    // must start exactly on the prescribed motion.
    let n = dae.n_coordinates();
    assert!(
        y0[0].abs() < 1e-15 && y0[1].abs() < 1e-15 && (y0[2] - PI).abs() < 1e-15,
        "assembled arm pose {:?}, expected (0, 0, π)",
        &y0[..n]
    );
    let v0 = &y0[n..2 * n];
    assert!(
        v0[0].abs() < 1e-12 && v0[1].abs() < 1e-12 && (v0[2] - omega()).abs() < 1e-12,
        "assembled arm velocity {v0:?}, expected (0, 0, {})",
        omega()
    );
    // Loose tolerances: the integrator would like large steps.
    let options = match SolverOptions::default()
        .method(method)
        .rtol(1e-6)
        .atol(1e-9)
        .build()
    {
        Ok(o) => o,
        Err(e) => panic!("{e}"),
    };
    (dae, y0, options)
}

fn t_end() -> f64 {
    REVS as f64 * 2.0 * PI / omega()
}

#[test]
fn one_impact_per_revolution_at_the_exact_times() {
    let w = omega();
    let theta_c = contact_half_angle();
    for method in Method::ALL {
        let (mut dae, y0, options) = setup(method);
        let mut rec = Recorder::new(&dae);
        if let Err(e) = integrate(&mut dae, 0.0, &y0, t_end(), 1e-2, &options, &mut rec) {
            panic!("{method}: {e}");
        }
        let impacts: Vec<f64> = rec
            .events
            .iter()
            .filter(|e| e.index == 0 && e.crossing == Crossing::Rising)
            .map(|e| e.t)
            .collect();
        let separations: Vec<f64> = rec
            .events
            .iter()
            .filter(|e| e.index == 0 && e.crossing == Crossing::Falling)
            .map(|e| e.t)
            .collect();
        assert_eq!(
            impacts.len(),
            REVS,
            "{method}: {} impacts in {REVS} revolutions, expected {REVS}: {:?}",
            impacts.len(),
            rec.events
        );
        assert_eq!(
            separations.len(),
            REVS,
            "{method}: {} separations in {REVS} revolutions, expected {REVS}: {:?}",
            separations.len(),
            rec.events
        );
        assert_eq!(
            rec.events.len(),
            2 * REVS,
            "{method}: {} events, expected {} (one impact and one separation per revolution)",
            rec.events.len(),
            2 * REVS
        );
        // φ = π + ωt reaches 2πk ∓ θ_c at t = ((2k − 1)π ∓ θ_c)/ω. Tolerance 1e-9 s: the events
        // are bracketed to 1e-12·max(1, t) ≤ 1e-11 s, the prescribed motion is integrated
        // exactly up to rounding, and δ̇ ≈ r d ω sin θ_c / c ≈ 1.4e-4 m/s turns a rounding
        // error of ~1e-19 m in δ into ~1e-15 s.
        for k in 0..REVS {
            let turn = (2 * k + 1) as f64 * PI;
            let expected_in = (turn - theta_c) / w;
            let expected_out = (turn + theta_c) / w;
            let err_in = (impacts[k] - expected_in).abs();
            let err_out = (separations[k] - expected_out).abs();
            assert!(
                err_in <= 1e-9,
                "{method}: impact {k} at t = {} s, closed form {expected_in} s (error {err_in:e} s)",
                impacts[k]
            );
            assert!(
                err_out <= 1e-9,
                "{method}: separation {k} at t = {} s, closed form {expected_out} s (error {err_out:e} s)",
                separations[k]
            );
        }
    }
}

/// The guard shortens the steps only near the wall. Far from it (gap ≥ c/2) the steps are
/// large, the whole run costs far fewer steps than steps at the guard's floor everywhere
/// would, and the largest step is longer than a whole contact — so without the guard a
/// contact could begin and end inside one step unseen.
#[test]
fn guard_bites_only_near_the_wall() {
    let w = omega();
    let contact_duration = 2.0 * contact_half_angle() / w;
    // The guard's floor step at the wall (src/contact/grazing.rs): relative speed V = ω r,
    // relative acceleration A = ω² r, depth ε_g c with ε_g = 1e-3:
    // h_floor = 4 ε_g c / (V + sqrt(V² + 8 ε_g A c)) ≈ 6.3e-4 s, 4e-3 rad of arm angle.
    let (v, a, depth) = (w * R, w * w * R, 1e-3 * C);
    let h_floor = 4.0 * depth / (v + (v * v + 8.0 * a * depth).sqrt());
    let floor_steps_per_rev = 2.0 * PI / w / h_floor;
    for method in Method::ALL {
        let (mut dae, y0, options) = setup(method);
        let mut stepper = match Stepper::new(&mut dae, 0.0, &y0, t_end(), &options) {
            Ok(s) => s,
            Err(e) => panic!("{method}: {e}"),
        };
        // Gap c − |e| at the start of the current step; the run starts centred (gap c).
        let mut gap = C;
        let mut smallest_far_step = f64::INFINITY;
        loop {
            let stop = match stepper.step() {
                Ok(s) => s,
                Err(e) => panic!("{method}: {e}"),
            };
            let (from, to) = stepper.dense_range();
            // Full steps only: a step cut short at an event says nothing about the guard. Radau5
            // starts at 10⁻⁶ s (as RADAU5) and grows h at most 8× per step, so its start-up
            // ramp (≥ 4 steps to reach 0.1 rad at ω ≈ 26 rad/s; 8 allowed) is no guard's doing.
            let start_up = method == Method::Radau5 && stepper.stats().steps <= 8;
            if stop == Stop::Step && gap >= C / 2.0 && !start_up {
                smallest_far_step = smallest_far_step.min(to - from);
            }
            gap = -stepper
                .formulation()
                .contact_state(0, stepper.y())
                .kinematics
                .delta;
            if stop == Stop::EndReached {
                break;
            }
        }
        let stats = stepper.stats().clone();
        // At gap ≥ c/2 the guard allows Δφ = ω h ≥ (g/r)/(1 + sqrt(1 + g/r)) ≥ 0.41 rad
        // (κ = ½, V = ω r, A = ω² r, g/r ≥ 1); the bound 0.1 rad leaves room for the first
        // step, which Hairer's `hinit` chooses (0.17 rad with DOPRI5; all later far steps are
        // ≥ 0.3 rad), and is still 25 floor steps.
        assert!(
            w * smallest_far_step >= 0.1,
            "{method}: smallest full step at gap ≥ c/2 is {} rad of arm angle, bound 0.1 rad",
            w * smallest_far_step
        );
        // Floor steps everywhere would cost ≈ 1580 steps per revolution. The guard only crawls
        // in the last eighth of the gap, where the journal approaches the wall almost
        // tangentially: the guard bounds the step by the whole relative speed V, not by the
        // much smaller approach rate, so Δφ ≈ g/(2r) there and the approach costs ~100 steps.
        // Bound: a tenth of the floor-everywhere count.
        let steps_per_rev = stats.steps as f64 / REVS as f64;
        assert!(
            steps_per_rev < floor_steps_per_rev / 10.0,
            "{method}: {steps_per_rev} steps per revolution, bound {} (floor steps everywhere: {floor_steps_per_rev})",
            floor_steps_per_rev / 10.0
        );
        assert!(
            stats.h_max_used > contact_duration,
            "{method}: largest step {} s should exceed the contact duration {contact_duration} s",
            stats.h_max_used
        );
    }
}
