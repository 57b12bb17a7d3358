//! `[[repeat]]` templates: the generated chain of parallel four-bars has the expected bodies,
//! joints and ground points for any N set from the command line, and moves as the one-degree-
//! of-freedom compound pendulum it is: (Σ I) φ̈ = −(Σ m g d) cos φ with, per link,
//! I = m L²/3 about its pivot and d = L/2, and per coupler (which translates) I = m_c L², d = L.

mod common;
use common::*;
use linkdyn::solve::Method;

const CHAIN: &str = "models/parallel_fourbar_chain.toml";

#[test]
fn the_chain_template_generates_named_bodies_and_joints() {
    let m = load(CHAIN, &["parameters.N=3"]);
    let bodies: Vec<&str> = m.bodies.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(
        bodies,
        [
            "link0", "link1", "link2", "link3", "coupler1", "coupler2", "coupler3"
        ]
    );
    let joints: Vec<&str> = m.joints.iter().map(|j| j.name.as_str()).collect();
    assert_eq!(
        joints,
        [
            "pivot0", "pivot1", "pivot2", "pivot3", "left1", "right1", "left2", "right2", "left3",
            "right3"
        ]
    );
    let g3 = m
        .ground_points
        .iter()
        .find(|(n, _)| n == "G3")
        .map(|(_, p)| *p);
    assert_eq!(g3, Some([0.6000000000000001, 0.0]), "G3 at 3a");
    let left2 = &m.joints[6];
    assert_eq!(
        (m.frame_name(left2.a.frame), m.frame_name(left2.b.frame)),
        ("link1", "coupler2"),
        "left{{k}} joins link{{k-1}} to coupler{{k}}"
    );
    // Every link has the parameterised mass rho_lin L = 0.6 kg.
    assert!(m.bodies[..4].iter().all(|b| (b.mass - 0.6).abs() < 1e-15));
}

/// RK4 on the 1-DOF equation, 20 000 steps per second: error ~ h⁴ ≈ 6e-18 per unit time.
fn pendulum_angle(n: f64, t_end: f64) -> f64 {
    let (l, a, rho, g) = (0.3, 0.2, 2.0, 9.81);
    let (ml, mc) = (rho * l, rho * a);
    let inertia = (n + 1.0) * ml * l * l / 3.0 + n * mc * l * l;
    let moment = (n + 1.0) * ml * g * l / 2.0 + n * mc * g * l;
    let f = |phi: f64| -moment / inertia * phi.cos();
    let (mut phi, mut w) = (-std::f64::consts::FRAC_PI_2 + 0.6, 0.0);
    let steps = (t_end * 20_000.0).round() as usize;
    let h = t_end / steps as f64;
    for _ in 0..steps {
        let (k1p, k1w) = (w, f(phi));
        let (k2p, k2w) = (w + 0.5 * h * k1w, f(phi + 0.5 * h * k1p));
        let (k3p, k3w) = (w + 0.5 * h * k2w, f(phi + 0.5 * h * k2p));
        let (k4p, k4w) = (w + h * k3w, f(phi + h * k3p));
        phi += h / 6.0 * (k1p + 2.0 * k2p + 2.0 * k3p + k4p);
        w += h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w);
    }
    phi
}

#[test]
fn the_generated_chain_swings_as_one_compound_pendulum() {
    for n in [1, 4] {
        let set = format!("parameters.N={n}");
        let m = load(CHAIN, &[&set]);
        let (rec, _) = run_dae(&m, 1.0, 0.25, Method::Dop853, 1e-11, 1e-13);
        for (k, &t) in rec.t.iter().enumerate() {
            let want = pendulum_angle(n as f64, t);
            for j in 0..=n {
                let got = col(&rec, &format!("link{j}.phi"))[k];
                // rtol 1e-11 over one second: 1e-8 rad leaves margin for the global error and
                // the Baumgarte-held constraint residual.
                assert!(
                    (got - want).abs() < 1e-8,
                    "N = {n}: link{j}.phi({t}) = {got} vs the 1-DOF pendulum {want}"
                );
            }
        }
    }
}

#[test]
fn an_error_in_a_template_names_the_line_and_the_index() {
    let text = std::fs::read_to_string(CHAIN)
        .unwrap_or_default()
        .replace("body_a = \"link{k-1}\"", "body_a = \"link{k-2}\"");
    let err = linkdyn::model::load_str(&text, "chain.toml", &[])
        .err()
        .map(|e| e.to_string());
    assert_eq!(
        err.as_deref(),
        Some(
            "chain.toml:64:10: repeat[1].joints[0].body_a: unknown body \"link-1\" in joint \"left1\": did you mean \"link1\"? (in [[repeat]] with k = 1)"
        )
    );
}
