//! The DAE's friction-kink events (`Dae::friction_kink_events`, `contact/kinks.rs`): off by
//! default; on, four per clearance joint whose friction law has kinks, after the δ events, each
//! v_t ∓ v0, v_t ∓ v1 of its own joint while that joint's contact is open, and answered with
//! `Continue` without touching the state.

mod common;

use common::load;
use linkdyn::formulation::{Crossing, Dae, DaeOptions, EventResponse, Formulation};
use linkdyn::model::Model;

fn dae(model: &Model) -> Dae {
    Dae::new(model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// The kink functions of a joint with slip velocity `v_t`: v0 = 1e-4, v1 = 1e-3 m/s (the
/// shipped models' Ambrósio law).
fn at_kinks(v_t: f64) -> [f64; 4] {
    [v_t - 1e-4, v_t + 1e-4, v_t - 1e-3, v_t + 1e-3]
}

#[test]
fn friction_kinks_are_events_in_contact() {
    // Two clearance joints, A (index 0) and B (index 1), both with Ambrósio friction.
    let model = load("models/slider_crank_clearance.toml", &[]);
    let plain = dae(&model);
    assert_eq!(plain.n_events(), 2, "off by default: δ of each joint only");
    let d = plain.clone().friction_kink_events(true);
    assert_eq!(d.n_events(), 2 + 2 * 4);
    assert_eq!(d.clone().friction_kink_events(false).n_events(), 2);

    let n = d.n_coordinates();
    let mut y = d.initial_state();
    let mut g = vec![0.0; d.n_events()];
    d.events(0.0, &y, &mut g);
    assert_eq!(g[2..], [1.0; 8], "no stored δ̇⁽⁻⁾: kinks inactive");
    let mut deltas = [0.0; 2];
    plain.events(0.0, &y, &mut deltas);
    assert_eq!(g[..2], deltas, "events 0..n_c are the δ, unchanged");

    // A contact open at joint B only: its four functions follow its own slip velocity.
    y[2 * n + 1] = 0.05;
    d.events(0.0, &y, &mut g);
    let v_b = d.contact_state(1, &y).kinematics.tangential_velocity;
    assert_eq!(g[2..6], [1.0; 4], "joint A free: inactive");
    assert_eq!(g[6..], at_kinks(v_b));
    y[2 * n] = 0.02;
    d.events(0.0, &y, &mut g);
    let v_a = d.contact_state(0, &y).kinematics.tangential_velocity;
    assert_eq!(g[2..6], at_kinks(v_a));
    assert_ne!(v_a, v_b, "the two joints slip differently");

    let mut m = d.clone();
    for index in 2..d.n_events() {
        let mut yy = y.clone();
        for crossing in [Crossing::Rising, Crossing::Falling] {
            assert_eq!(
                m.apply_event(0.0, &mut yy, index, crossing),
                EventResponse::Continue
            );
            assert_eq!(yy, y, "event {index} changes nothing");
        }
    }
}

/// A joint without friction has no kinks: with B frictionless only A's four follow the δ.
#[test]
fn a_frictionless_joint_has_no_kink_events() {
    let model = load(
        "models/slider_crank_clearance.toml",
        &["joints.B.friction.law=none"],
    );
    let d = dae(&model).friction_kink_events(true);
    assert_eq!(d.n_events(), 2 + 4);
    let n = d.n_coordinates();
    let mut y = d.initial_state();
    y[2 * n] = 0.02;
    y[2 * n + 1] = 0.05;
    let mut g = vec![0.0; d.n_events()];
    d.events(0.0, &y, &mut g);
    let v_a = d.contact_state(0, &y).kinematics.tangential_velocity;
    assert_eq!(g[2..], at_kinks(v_a));
}
