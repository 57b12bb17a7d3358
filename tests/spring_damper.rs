//! Spring-damper and constant point force against the damped harmonic oscillator: a body on a
//! prismatic rail, pulled by a linear spring-damper to a ground anchor and pushed by a constant
//! force, follows x(t) in closed form; the energy bookkeeping closes the work–energy balance
//! (external work = ΔT + ΔU_spring + damper dissipation).

mod common;
use common::col;
use linkdyn::formulation::{Dae, DaeOptions, Formulation};
use linkdyn::solve::{Method, Recorder, SolverOptions, integrate};

const MASS: f64 = 2.0;
const K: f64 = 200.0; // N/m
const FREE_LENGTH: f64 = 0.8; // m; anchor at x = −1, so the spring is relaxed at x = −0.2

fn model(damping: f64, force: f64) -> linkdyn::model::Model {
    let text = format!(
        r#"
[model]
name = "oscillator"
[settings]
gravity = [0.0, 0.0]
[ground]
points = {{ rail = [0.0, 0.0], anchor = [-1.0, 0.0] }}
[[bodies]]
name = "mass"
mass = {MASS}
inertia = 0.1
points = {{ c = [0.0, 0.0] }}
initial = {{ x = 0.0, y = 0.0, phi = 0.0 }}
[[joints]]
name = "rail"
type = "prismatic"
body_a = "ground"
point_a = "rail"
body_b = "mass"
point_b = "c"
axis = [1.0, 0.0]
[[forces]]
name = "spring"
type = "spring-damper"
body_a = "ground"
point_a = "anchor"
body_b = "mass"
point_b = "c"
stiffness = {K}
damping = {damping}
free_length = {FREE_LENGTH}
[[forces]]
name = "push"
type = "force"
body = "mass"
point = "c"
force = [{force}, 0.0]
"#
    );
    linkdyn::model::load_str(&text, "oscillator.toml", &[]).unwrap_or_else(|e| panic!("{e}"))
}

fn run(damping: f64, force: f64) -> Recorder {
    let options = DaeOptions {
        energy: true,
        ..DaeOptions::default()
    };
    let mut dae = Dae::new(&model(damping, force), &options).unwrap_or_else(|e| panic!("{e}"));
    let solver = SolverOptions::default()
        .method(Method::Dop853)
        .rtol(1e-12)
        .atol(1e-14)
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let y0 = dae.initial_state();
    let mut rec = Recorder::new(&dae);
    integrate(&mut dae, 0.0, &y0, 3.0, 1e-3, &solver, &mut rec).unwrap_or_else(|e| panic!("{e}"));
    rec
}

/// x(t) of m ẍ + c ẋ + k (x + 0.2) = F from rest at x = 0.
fn exact(t: f64, damping: f64, force: f64) -> f64 {
    let omega = (K / MASS).sqrt();
    let zeta = damping / (2.0 * (K * MASS).sqrt());
    let equilibrium = -0.2 + force / K;
    let amplitude = 0.0 - equilibrium;
    let wd = omega * (1.0 - zeta * zeta).sqrt();
    equilibrium
        + amplitude
            * (-zeta * omega * t).exp()
            * ((wd * t).cos() + zeta * omega / wd * (wd * t).sin())
}

#[test]
fn damped_oscillator_matches_closed_form_and_balances_energy() {
    for (damping, force) in [(0.0, 0.0), (4.0, 10.0)] {
        let rec = run(damping, force);
        // A missing column fails (`col` panics with its name) instead of reading as empty, which
        // would make every loop below vacuous.
        assert!(rec.len() > 100, "c = {damping}: only {} samples", rec.len());
        let x = col(&rec, "mass.x");
        let y = col(&rec, "mass.y");
        for (i, t) in rec.t.iter().enumerate() {
            let xe = exact(*t, damping, force);
            // 1e-9 m against a 0.2 m amplitude: rtol 1e-12 over ~5 periods.
            assert!(
                (x[i] - xe).abs() < 1e-9,
                "c = {damping}, F = {force}, t = {t}: x = {} vs {xe}",
                x[i]
            );
            assert!(y[i].abs() < 1e-12, "left the rail: y = {}", y[i]);
        }
        let balance = col(&rec, "energy.balance");
        let worst = balance.iter().fold(0.0_f64, |m, b| m.max(b.abs()));
        // Scale: the spring energy at t = 0, ½ k 0.2² = 4 J.
        assert!(
            worst < 1e-9 * 4.0,
            "c = {damping}: energy balance off by {worst:e} J"
        );
        let dissipated = col(&rec, "energy.dissipated");
        let external = col(&rec, "energy.external_work");
        if damping == 0.0 {
            assert!(
                dissipated.iter().all(|d| d.abs() < 1e-12),
                "undamped spring dissipated energy"
            );
        } else {
            // By t = 3 s the motion has decayed (ζω t = 3): most of the initial 4 J and the
            // force's work went into the damper.
            let last = dissipated.last().copied().unwrap_or(0.0);
            assert!(last > 1.0, "damper dissipated only {last} J");
            assert!(
                external.last().copied().unwrap_or(0.0) < 0.0,
                "the push does negative work as x falls"
            );
        }
    }
}
