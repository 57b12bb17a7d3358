//! Redundant constraints are detected, reported by `check`, and left out of the dynamics without
//! changing the motion: a pendulum hung on two coincident pins moves exactly like the pendulum on
//! one, and a parallelogram linkage with a third, parallel crank (a classic over-constrained
//! mechanism) keeps one degree of freedom. Conflicting rows (a dependent driver, or a dependent
//! row whose velocity or acceleration contradicts its combination) are errors instead: see
//! `tests/bad_models/two_drivers_one_loop.toml` and `driver_on_locked_body.toml`.

mod common;
use common::*;
use linkdyn::formulation::{Dae, DaeOptions};
use linkdyn::solve::Method;

fn doubled_pin_pendulum() -> linkdyn::model::Model {
    let text = std::fs::read_to_string("models/pendulum.toml").unwrap_or_else(|e| panic!("{e}"))
        + "\n[[joints]]\nname = \"O_twin\"\ntype = \"revolute\"\nbody_a = \"ground\"\npoint_a = \"O\"\nbody_b = \"rod\"\npoint_b = \"O\"\n";
    linkdyn::model::load_str(&text, "doubled_pin.toml", &[]).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_doubled_pin_is_redundant_and_does_not_change_the_motion() {
    let model = doubled_pin_pendulum();
    let dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<String> = dae
        .redundant_rows()
        .iter()
        .map(|&k| dae.constraints().row_name(&model, k))
        .collect();
    assert_eq!(names, ["O_twin.x", "O_twin.y"]);
    assert_eq!(dae.assembly().dof, 1);

    let single = load("models/pendulum.toml", &[]);
    let (a, _) = run_dae(&model, 3.0, 1e-2, Method::Dop853, 1e-11, 1e-13);
    let (b, _) = run_dae(&single, 3.0, 1e-2, Method::Dop853, 1e-11, 1e-13);
    let (pa, pb) = (col(&a, "rod.phi"), col(&b, "rod.phi"));
    for i in 0..a.len() {
        // Same equations once the twin rows are left out: identical to round-off.
        assert!(
            (pa[i] - pb[i]).abs() < 1e-12,
            "t = {}: {} vs {}",
            a.t[i],
            pa[i],
            pb[i]
        );
    }
}

#[test]
fn parallelogram_with_a_third_crank_keeps_one_degree_of_freedom() {
    // Ground pivots at x = 0, 1, 2; three equal cranks (0.5 m, released hanging at −1 rad, so
    // they swing below the ground line and never reach the change point where they lie along
    // it and the rank drops) joined by one coupler: 4 bodies,
    // 12 coordinates, 6 pins = 12 rows, yet it moves: one row is redundant.
    let mut text = String::from(
        "[model]\nname = \"parallelogram\"\n[settings]\ngravity = [0.0, -9.81]\n[ground]\npoints = { P0 = [0.0, 0.0], P1 = [1.0, 0.0], P2 = [2.0, 0.0] }\n",
    );
    for k in 0..3 {
        text += &format!(
            "[[bodies]]\nname = \"crank{k}\"\nmass = 1.0\ninertia = 0.02\npoints = {{ G = [-0.25, 0.0], C = [0.25, 0.0] }}\ninitial = {{ x = {x}, y = {y}, phi = -1.0 }}\n",
            x = k as f64 + 0.25 * 1f64.cos(),
            y = -0.25 * 1f64.sin()
        );
    }
    text += "[[bodies]]\nname = \"coupler\"\nmass = 2.0\ninertia = 0.7\npoints = { C0 = [-1.0, 0.0], C1 = [0.0, 0.0], C2 = [1.0, 0.0] }\ninitial = { x = 1.2701511529340699, y = -0.42073549240394825, phi = 0.0 }\n";
    for k in 0..3 {
        text += &format!(
            "[[joints]]\nname = \"G{k}\"\ntype = \"revolute\"\nbody_a = \"ground\"\npoint_a = \"P{k}\"\nbody_b = \"crank{k}\"\npoint_b = \"G\"\n[[joints]]\nname = \"C{k}\"\ntype = \"revolute\"\nbody_a = \"crank{k}\"\npoint_a = \"C\"\nbody_b = \"coupler\"\npoint_b = \"C{k}\"\n"
        );
    }
    let model = linkdyn::model::load_str(&text, "parallelogram.toml", &[])
        .unwrap_or_else(|e| panic!("{e}"));
    let dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(dae.redundant_rows().len(), 1, "one redundant row");
    assert_eq!(dae.assembly().dof, 1, "the parallelogram moves");
    // It swings as a rigid-coupler pendulum: the coupler stays horizontal (φ = 0) throughout.
    let (rec, _) = run_dae(&model, 2.0, 1e-2, Method::Dop853, 1e-10, 1e-12);
    let phi = col(&rec, "coupler.phi");
    let x = col(&rec, "coupler.x");
    assert!(
        phi.iter().all(|p| p.abs() < 1e-8),
        "coupler rotated: max {:e}",
        phi.iter().fold(0.0_f64, |m, p| m.max(p.abs()))
    );
    assert!(
        x.iter().any(|v| (v - x[0]).abs() > 0.1),
        "the linkage did not move"
    );
}
