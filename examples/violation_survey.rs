//! The measurement behind the DAE's constraint-violation bound (`docs/numerics.md`, "The
//! constraint-violation bound"): every shipped model, DAE formulation, every method, at
//! rtol = atol and at the default ratio atol = rtol/100, from rtol 1e-3 to 1e-12, two driver
//! turns (2 s for models without a driver), sampled every millisecond. For each run it prints
//! the largest |Φ| over the samples and step ends, the tolerance-scaled error
//! `rtol·L + atol` with the linkage's length scale L, their ratio (the bound is
//! 100·(rtol·L + atol): a ratio above 100 is a run the bound stops), and for models with
//! clearance joints max |Φ| relative to the smallest clearance.
//!
//! `cargo run --release --example violation_survey [-- MODEL.toml …]`

use linkdyn::formulation::{Dae, DaeOptions};
use linkdyn::model::JointKind;
use linkdyn::simulation::{Discard, Simulation, SimulationOptions};
use linkdyn::solve::{Method, SolverOptions};

fn main() {
    let mut paths: Vec<String> = std::env::args().skip(1).collect();
    if paths.is_empty() {
        let Ok(dir) = std::fs::read_dir("models") else {
            eprintln!("run from the repository root (models/ not found)");
            std::process::exit(2);
        };
        paths = dir
            .filter_map(|e| e.ok().map(|e| e.path().display().to_string()))
            .filter(|p| p.ends_with(".toml"))
            .collect();
        paths.sort();
    }
    println!("model\tmethod\trtol\tatol\tL (m)\tmax |Φ|\trtol·L + atol\tratio\t|Φ|/c_min\tresult");
    let mut worst = 0.0_f64;
    for path in &paths {
        let model = match linkdyn::model::load(path.as_ref(), &[]) {
            Ok(m) => m,
            Err(e) => {
                eprintln!("{path}: {e}");
                continue;
            }
        };
        let length = match Dae::new(&model, &DaeOptions::default()) {
            Ok(d) => d.length_scale(),
            Err(e) => {
                eprintln!("{path}: {e}");
                continue;
            }
        };
        let c_min = model
            .joints
            .iter()
            .filter_map(|j| match &j.kind {
                JointKind::Clearance(c) => Some(c.clearance),
                _ => None,
            })
            .fold(f64::INFINITY, f64::min);
        for rtol in [1e-3, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12] {
            for atol in [rtol, rtol / 100.0] {
                for method in Method::ALL {
                    let solver = SolverOptions::default()
                        .method(method)
                        .rtol(rtol)
                        .atol(atol)
                        .max_wall(20.0);
                    let options = if model.drivers.is_empty() {
                        SimulationOptions::default().t_end(2.0)
                    } else {
                        SimulationOptions::default().revs(2.0)
                    }
                    .dt(1e-3)
                    .solver(solver);
                    let scale = rtol * length + atol;
                    let sim = match Simulation::new(&model, options) {
                        Ok(s) => s,
                        Err(e) => {
                            eprintln!("{path} {method} {rtol:e}: {e}");
                            continue;
                        }
                    };
                    let (violation, result) = match sim.run(&mut Discard) {
                        Ok(s) => (s.max_constraint_violation, "ok".to_string()),
                        Err(e) => (f64::NAN, format!("{e}").chars().take(160).collect()),
                    };
                    if violation.is_finite() {
                        worst = worst.max(violation / scale);
                    }
                    let relative = if c_min.is_finite() {
                        format!("{:.3e}", violation / c_min)
                    } else {
                        "-".into()
                    };
                    println!(
                        "{path}\t{method}\t{rtol:e}\t{atol:e}\t{length:.3}\t{violation:.3e}\t{scale:.3e}\t{:.3}\t{relative}\t{result}",
                        violation / scale
                    );
                }
            }
        }
    }
    println!("largest ratio max |Φ| / (rtol·L + atol) over the finished runs: {worst:.3}");
}
