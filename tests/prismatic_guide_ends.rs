//! Claim: the end stops of a prismatic-clearance joint's guide (`guide_start`, `guide_end`;
//! docs/translational_clearance.md) stop the slider through the joint's contact law:
//!
//! 1. a slider moving freely along the guide reaches the front stop at the free-flight time and
//!    speed, on both front corners at once (sites e2, e3), each with the deepest penetration of
//!    the one-degree-of-freedom impact of half the slider's mass on K δⁿ (a closed form, far
//!    inside the law's range); elastic, it comes back at the same speed to the rear stop;
//! 2. with Lankarani–Nikravesh damping the speed it leaves the stop with is that of the
//!    one-degree-of-freedom impact of half the mass on the damped law, near c_r;
//! 3. the energy balance closes (`--energy`) when the slider slides on the lower guide surface
//!    with friction and hits the stops, for DOP853 and Radau5.

mod common;

use common::slider::{
    LENGTH, MASS, SliderInGuide, assert_first_impact, deepest_penetration, rebound_speed, rel, run,
    site, solver,
};
use linkdyn::model::Model;
use linkdyn::simulation::{FormulationKind, SimulationOptions};
use linkdyn::solve::Method;

/// The free travel from the centred slider's face to each stop (m).
const GAP: f64 = 0.01;

/// A free slider (1 kg) centred in a guide on the ground x-axis with stops GAP ahead of each
/// face, moving along it at `vx` (m/s), under gravity `g` (m/s², along −y).
fn model(g: f64, vx: f64, contact: &str, friction: &str) -> Model {
    SliderInGuide {
        gravity: g,
        vx,
        tilt: 0.0,
        stop_gap: Some(GAP),
        contact,
        friction,
    }
    .model("slider_between_stops")
}

/// Hertz (no damping), no gravity, 0.5 m/s: the front face reaches the stop after GAP/v on both
/// front corners with δ̇⁽⁻⁾ = v; each takes half the mass, so its deepest penetration is the
/// closed form for m/2 (1.2e-4 m, an eighth of the 1 %-of-length limit); the slider comes back
/// at v and meets the rear stop on both rear corners at v; no corner touches a guide surface
/// and the slider does not turn.
#[test]
fn slider_reaches_the_end_stop_and_comes_back_as_the_closed_form_says() {
    let v = 0.5;
    let model = model(0.0, v, "law = \"hertz\"", "law = \"none\"");
    let traj = run(
        &model,
        SimulationOptions::default()
            .t_end(0.08)
            .dt(1e-4)
            .solver(solver(Method::Dop853, 1e-10)),
    );
    let t_hit = GAP / v;
    let delta_max = deepest_penetration(0.5 * MASS, v, 0.0);
    for name in ["guide.e2", "guide.e3"] {
        let s = assert_first_impact(&traj, name, t_hit, v, delta_max);
        // The whole run stays within the law's range: never deeper than the impact's closed
        // form, far below the 1 %-of-length limit at which the run would stop.
        assert!(
            s.max_penetration <= delta_max * (1.0 + 1e-6) && s.max_penetration < 0.01 * LENGTH,
            "{name}: max penetration {} (closed form {delta_max})",
            s.max_penetration
        );
    }
    for name in ["guide.e1", "guide.e4"] {
        let s = site(&traj, name);
        let first = s
            .impacts
            .first()
            .unwrap_or_else(|| panic!("{name}: never hit the rear stop"));
        // Elastic, and free flight in between: the same speed back (1e-6: the rebound is
        // integrated with rtol 1e-10 through a contact of ~1e4 steps).
        assert!(
            rel(first.impact_velocity, v) < 1e-6,
            "{name}: impact velocity {} vs {v}",
            first.impact_velocity
        );
        assert!(
            first.t > t_hit + 2.0 * GAP / v * 0.99,
            "{name} at {} s",
            first.t
        );
    }
    for name in ["guide.c1", "guide.c2", "guide.c3", "guide.c4"] {
        assert_eq!(site(&traj, name).impacts.len(), 0, "{name} touched");
    }
    let phi = traj
        .column("slider.phi")
        .unwrap_or_else(|| panic!("slider.phi"));
    let turned = phi.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    assert!(turned < 1e-12, "the stop turned the slider by {turned} rad");
    // The reaction column is the sites' force on the slider: along −x at the front stop, at
    // most the two front corners' peaks together (sampled, so only ≤).
    let fx = traj
        .column("guide.fx")
        .unwrap_or_else(|| panic!("guide.fx"));
    let most = fx.iter().fold(0.0_f64, |m, x| m.min(*x));
    let peaks = site(&traj, "guide.e2").impacts[0].peak_normal_force
        + site(&traj, "guide.e3").impacts[0].peak_normal_force;
    assert!(
        -most <= peaks * (1.0 + 1e-9) && -most > 0.5 * peaks,
        "sampled reaction {most} N vs peak end-stop forces {peaks} N"
    );
    for column in ["guide.e2.delta", "guide.e2.fn", "guide.e2.ft"] {
        assert!(traj.column(column).is_some(), "no column {column}");
    }
}

/// Lankarani–Nikravesh, c_r = 0.9, no gravity: the slider leaves the front stop at the
/// rebound speed of the one-degree-of-freedom impact of m/2 on the damped law, and, in free
/// flight, meets the rear stop at that speed; the effective restitution is near c_r (the law is
/// calibrated so for c_r → 1).
#[test]
fn slider_rebounds_from_the_end_stop_as_the_law_of_half_the_mass() {
    let v = 0.5;
    let model = model(
        0.0,
        v,
        "law = \"lankarani-nikravesh\"\nrestitution = 0.9",
        "law = \"none\"",
    );
    let traj = run(
        &model,
        SimulationOptions::default()
            .t_end(0.08)
            .dt(1e-4)
            .solver(solver(Method::Dop853, 1e-10)),
    );
    let v_out = rebound_speed(0.5 * MASS, v, 0.9, 0.0);
    for name in ["guide.e1", "guide.e4"] {
        let back = site(&traj, name)
            .impacts
            .first()
            .unwrap_or_else(|| panic!("{name}: never hit the rear stop"))
            .impact_velocity;
        // The 1-DOF reference is integrated to ~1e-9; the run's events to ~1e-8.
        assert!(
            rel(back, v_out) < 1e-5,
            "{name}: rebound {back} m/s vs 1-DOF {v_out} m/s"
        );
        assert!(
            (back / v - 0.9).abs() < 0.03,
            "{name}: effective restitution {} vs c_r = 0.9",
            back / v
        );
    }
}

/// Sliding on the lower guide surface under gravity with Ambrósio friction (c_f = 0.1) at
/// 1 m/s, the slider hits the front stop, comes back and hits the rear one: the energy books
/// (kinetic + potential + contact elastic + dissipated) equal the initial energy, with DOP853
/// and Radau5 on the DAE, and damping and friction dissipate.
#[test]
fn energy_balance_closes_with_the_end_stops() {
    let v = 1.0;
    let model = model(
        9.81,
        v,
        "law = \"lankarani-nikravesh\"\nrestitution = 0.9",
        "law = \"ambrosio\"\ncoefficient = 0.1\nv0 = 1e-4\nv1 = 1e-3",
    );
    let e0 = 0.5 * MASS * v * v;
    for (method, rtol) in [(Method::Dop853, 1e-10), (Method::Radau5, 1e-8)] {
        let traj = run(
            &model,
            SimulationOptions::default()
                .formulation(FormulationKind::Dae)
                .energy(true)
                .t_end(0.06)
                .dt(1e-4)
                .solver(solver(method, rtol)),
        );
        let label = format!("{method:?}");
        for name in ["guide.e2", "guide.e1"] {
            assert!(
                !site(&traj, name).impacts.is_empty(),
                "{label}: {name} never hit"
            );
        }
        let balance = traj
            .summary
            .energy_balance
            .as_ref()
            .unwrap_or_else(|| panic!("{label}: no energy balance"));
        // Tens of impacts of 1e-8-accurate steps: the residual is ~1e-9 of e0.
        assert!(
            balance.max_abs_residual < 1e-6 * e0,
            "{label}: energy balance off by {} J of {e0} J",
            balance.max_abs_residual
        );
        assert!(
            balance.dissipated > 1e-2 * e0,
            "{label}: only {} J dissipated",
            balance.dissipated
        );
    }
}
