//! Work–energy balance of the DAE with clearance joints: driver work = ΔT + ΔU + ΔV_contact +
//! energy dissipated by contact damping and friction; and, with a perfectly elastic contact
//! (Hertz law, no friction) and no driver, conservation of T + U + V_contact.
//!
//! The work and dissipation are integrated as extra states of the DAE (`DaeOptions::energy`),
//! so the balance is checked at the solver's accuracy, not at that of a quadrature of samples.

mod common;
use common::*;
use linkdyn::formulation::{Dae, DaeOptions, Formulation};
use linkdyn::model::Model;
use linkdyn::solve::{Method, Recorder, SolverOptions, integrate};

fn run_with_energy(model: &Model, t_end: f64, rtol: f64) -> Recorder {
    let options = DaeOptions {
        energy: true,
        ..DaeOptions::default()
    };
    let mut dae = Dae::new(model, &options).unwrap_or_else(|e| panic!("{e}"));
    let solver = SolverOptions::default()
        .method(Method::Dop853)
        .rtol(rtol)
        .atol(rtol * 1e-3)
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let y0 = dae.initial_state();
    let mut rec = Recorder::new(&dae);
    integrate(&mut dae, 0.0, &y0, t_end, 1e-4, &solver, &mut rec).unwrap_or_else(|e| panic!("{e}"));
    rec
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

#[test]
fn driver_work_equals_energy_change_plus_dissipation() {
    let model = load("models/farahan2016.toml", &[]);
    let rec = run_with_energy(&model, 2.0 * 60.0 / 250.0, 1e-11);
    let driver = col(&rec, "energy.driver_work");
    let dissipated = col(&rec, "energy.dissipated");
    let balance = col(&rec, "energy.balance");
    // Scale: the largest driver work over the run (J); the energies exchanged are of this size.
    let scale = max_abs(&driver);
    let worst = max_abs(&balance) / scale;
    assert!(
        worst < 1e-6,
        "energy balance off by {worst:e} of the driver work ({scale} J)"
    );
    // The contacts did dissipate (22 impacts with c_r = 0.9 and friction): the check is not
    // passing because nothing happened.
    let lost = dissipated.last().copied().unwrap_or(0.0);
    assert!(lost > 1e-4 * scale, "dissipated only {lost} J");
    // Dissipation never decreases.
    assert!(
        dissipated.windows(2).all(|w| w[1] >= w[0] - 1e-12 * scale),
        "dissipation decreased"
    );
}

/// The reference four-bar with its crank free (no driver, spinning at 250 rpm at t = 0), a
/// perfectly elastic Hertz contact and no friction: a conservative system.
fn free_crank_elastic() -> Model {
    let text = std::fs::read_to_string("models/farahan2016.toml").unwrap_or_else(|e| panic!("{e}"));
    let cut = text.find("[[drivers]]").unwrap_or(text.len());
    let text = text[..cut]
        .replace("initial = { x = 0.125, y = 0.0, phi = 0.0 }", "initial = { x = 0.125, y = 0.0, phi = 0.0, omega = 26.179938779914945 }")
        .replace("law = \"lankarani-nikravesh\"", "law = \"hertz\"")
        .replace("restitution = 0.9", "restitution = 1.0")
        .replace("law = \"ambrosio\"\ncoefficient = 0.1\nv0 = 0.0001                         # m/s\nv1 = 0.001                          # m/s\n", "law = \"none\"\n");
    assert!(
        text.contains("law = \"none\"") && text.contains("omega = 26.17"),
        "model edit failed"
    );
    linkdyn::model::load_str(&text, "free_crank_elastic.toml", &[])
        .unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn elastic_contact_without_driver_conserves_energy() {
    let model = free_crank_elastic();
    let rec = run_with_energy(&model, 0.5, 1e-12);
    let kinetic = col(&rec, "energy.kinetic");
    let potential = col(&rec, "energy.potential");
    let elastic = col(&rec, "energy.contact_elastic");
    let total: Vec<f64> = (0..rec.len())
        .map(|i| kinetic[i] + potential[i] + elastic[i])
        .collect();
    // Scale: the kinetic energy at t = 0 (J).
    let scale = kinetic[0];
    let drift = total
        .iter()
        .map(|e| (e - total[0]).abs())
        .fold(0.0, f64::max)
        / scale;
    assert!(
        drift < 1e-8,
        "T + U + V_contact drifted by {drift:e} of T0 = {scale} J"
    );
    // Contacts happened, so the elastic term was exercised.
    let impacts = rec
        .events
        .iter()
        .filter(|e| e.crossing == linkdyn::formulation::Crossing::Rising)
        .count();
    assert!(
        impacts > 0 && max_abs(&elastic) > 0.0,
        "no contact in the conservative case"
    );
    assert!(
        max_abs(&col(&rec, "energy.dissipated")) < 1e-12 * scale,
        "an elastic contact dissipated energy"
    );
}
