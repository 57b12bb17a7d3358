//! Shared helpers for the physics tests: run a model to a [`Recorder`].
#![allow(dead_code)]

pub mod branch;
pub mod chain;
pub mod energy;
pub mod fourbar;
pub mod ode;
pub mod slider;

use linkdyn::formulation::{Dae, DaeOptions, Formulation, Outputs};
use linkdyn::model::Model;
use linkdyn::solve::Recorder;
use linkdyn::solve::{Method, SolverOptions, SolverStats, integrate};

/// Loads a shipped model with overrides, panicking with the error text (tests only).
pub fn load(path: &str, overrides: &[&str]) -> Model {
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    match linkdyn::model::load(path.as_ref(), &overrides) {
        Ok(m) => m,
        Err(e) => panic!("{e}"),
    }
}

/// Integrates the DAE of `model` to `t_end`, sampling every `dt`.
pub fn run_dae(
    model: &Model,
    t_end: f64,
    dt: f64,
    method: Method,
    rtol: f64,
    atol: f64,
) -> (Recorder, SolverStats) {
    let mut dae = match Dae::new(model, &DaeOptions::default()) {
        Ok(d) => d,
        Err(e) => panic!("{e}"),
    };
    run_formulation(&mut dae, t_end, dt, method, rtol, atol)
}

/// Integrates any formulation from its initial state to `t_end`, sampling every `dt`.
pub fn run_formulation<F: Formulation + Outputs>(
    f: &mut F,
    t_end: f64,
    dt: f64,
    method: Method,
    rtol: f64,
    atol: f64,
) -> (Recorder, SolverStats) {
    let options = match SolverOptions::default()
        .method(method)
        .rtol(rtol)
        .atol(atol)
        .build()
    {
        Ok(o) => o,
        Err(e) => panic!("{e}"),
    };
    let y0 = f.initial_state();
    let mut rec = Recorder::new(f);
    let stats = match integrate(f, 0.0, &y0, t_end, dt, &options, &mut rec) {
        Ok(s) => s,
        Err(e) => panic!("{e}"),
    };
    (rec, stats)
}

/// Column `name` of a recorder (panics with the name if missing).
pub fn col(rec: &Recorder, name: &str) -> Vec<f64> {
    rec.column(name)
        .unwrap_or_else(|| panic!("no column {name}"))
}

/// Kinetic and gravitational potential energy of every sample (J), from body states.
pub fn mechanical_energy(model: &Model, rec: &Recorder) -> Vec<f64> {
    let g = model.settings.gravity;
    let mut e = vec![0.0; rec.len()];
    for b in &model.bodies {
        let x = col(rec, &format!("{}.x", b.name));
        let y = col(rec, &format!("{}.y", b.name));
        let vx = col(rec, &format!("{}.vx", b.name));
        let vy = col(rec, &format!("{}.vy", b.name));
        let w = col(rec, &format!("{}.omega", b.name));
        for i in 0..rec.len() {
            e[i] += 0.5 * b.mass * (vx[i] * vx[i] + vy[i] * vy[i]) + 0.5 * b.inertia * w[i] * w[i]
                - b.mass * (g[0] * x[i] + g[1] * y[i]);
        }
    }
    e
}
