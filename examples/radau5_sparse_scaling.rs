//! Radau5's cost per step against the size of the linkage, with the dense and the sparse LU of
//! its Newton matrices (`Radau5Settings::linear_solver`): the N-four-bar chain
//! (`models/nfourbar_chain.toml`, DAE, rtol 1e-8, atol 1e-10) from t = 0 to 0.5 s, before its
//! first flat position. `cargo run --release --example radau5_sparse_scaling -- --loops
//! 1,2,4,10,40,80 --dense-max 80` prints one markdown row per chain and path (best wall time of
//! `--repeat` runs, default 3): wall time per accepted step and the counts behind it.
//! `--method ida` (with `--features ida`) measures IDA's dense and sparse LU instead
//! (`SolverOptions::ida`).

use linkdyn::formulation::{Dae, DaeOptions, Formulation};
use linkdyn::solve::radau5::{LinearSolver, Radau5Settings};
use linkdyn::solve::{IdaSettings, Method, SolverOptions, SolverStats, Stepper, Stop};
use std::time::Instant;

fn run(dae: &Dae, method: Method, solver: LinearSolver, t_end: f64) -> (f64, SolverStats) {
    let options = SolverOptions::default()
        .method(method)
        .rtol(1e-8)
        .atol(1e-10)
        .radau5(Radau5Settings::default().linear_solver(solver))
        .ida(IdaSettings {
            linear_solver: solver,
        })
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let mut f = dae.clone();
    let y0 = f.initial_state();
    let start = Instant::now();
    let mut s = Stepper::new(&mut f, 0.0, &y0, t_end, &options).unwrap_or_else(|e| panic!("{e}"));
    loop {
        match s.step() {
            Ok(Stop::EndReached) => break,
            Ok(_) => {}
            Err(e) => panic!("{e}"),
        }
    }
    (start.elapsed().as_secs_f64(), s.stats().clone())
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let value = |flag: &str, default: &str| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1))
            .cloned()
            .unwrap_or_else(|| default.to_string())
    };
    let loops: Vec<usize> = value("--loops", "1,2,4,10,40,80")
        .split(',')
        .filter_map(|s| s.trim().parse().ok())
        .collect();
    let dense_max: usize = value("--dense-max", "80").parse().unwrap_or(80);
    let repeat: usize = value("--repeat", "3").parse().unwrap_or(3).max(1);
    let t_end: f64 = value("--t-end", "0.5").parse().unwrap_or(0.5);
    let method = match value("--method", "radau5").as_str() {
        "radau5" => Method::Radau5,
        #[cfg(feature = "ida")]
        "ida" => Method::Ida,
        other => panic!("--method {other}: radau5 (or ida, with --features ida)"),
    };
    println!(
        "| loops | bodies | states | LU | steps (rejected) | Jacobians | Newton iterations | ms per step |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for &n_loops in &loops {
        let model = linkdyn::model::load(
            concat!(env!("CARGO_MANIFEST_DIR"), "/models/nfourbar_chain.toml").as_ref(),
            &[format!("parameters.N={n_loops}")],
        )
        .unwrap_or_else(|e| panic!("{e}"));
        let dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        for (name, solver) in [
            ("dense", LinearSolver::Dense),
            ("sparse", LinearSolver::Sparse),
        ] {
            if solver == LinearSolver::Dense && n_loops > dense_max {
                continue;
            }
            let mut best = f64::INFINITY;
            let mut stats = SolverStats::default();
            for _ in 0..repeat {
                let (wall, s) = run(&dae, method, solver, t_end);
                best = best.min(wall);
                stats = s;
            }
            println!(
                "| {n_loops} | {} | {} | {name} | {} ({}) | {} | {} | {:.3} |",
                model.bodies.len(),
                dae.n_states(),
                stats.steps,
                stats.rejected,
                stats.jacobian_evals,
                stats.newton_iterations,
                1e3 * best / stats.steps.max(1) as f64
            );
        }
    }
}
