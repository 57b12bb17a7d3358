//! Radau5's sparse LU of its Newton matrices (`Radau5Settings::linear_solver`,
//! `solve/radau5/sparse.rs`) solves the same linear systems as the dense LU: the same steps,
//! the same Newton iterations and the same trajectory to round-off, on a chain of ten
//! four-bar loops (126 states) and on the clearance four-bar through its impacts. And the
//! automatic choice takes the sparse LU only where it was measured to pay.

mod common;

use common::load;
use linkdyn::formulation::{Dae, DaeOptions, Formulation, ReducedLagrangian};
use linkdyn::solve::ErrorWeights;
use linkdyn::solve::radau5::{LinearSolver, Radau5Method, Radau5Settings, SPARSE_MIN_STATES};
use linkdyn::solve::{Method, SolverOptions, SolverStats, Stepper, Stop};

/// Radau5 with `solver` from the initial state to `t_end`: the final state and the statistics.
fn run(dae: &Dae, solver: LinearSolver, t_end: f64, rtol: f64) -> (Vec<f64>, SolverStats) {
    let options = SolverOptions::default()
        .method(Method::Radau5)
        .rtol(rtol)
        .atol(rtol * 1e-2)
        .radau5(Radau5Settings::default().linear_solver(solver))
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let mut f = dae.clone();
    let y0 = f.initial_state();
    let mut s = Stepper::new(&mut f, 0.0, &y0, t_end, &options).unwrap_or_else(|e| panic!("{e}"));
    loop {
        match s.step() {
            Ok(Stop::EndReached) => break,
            Ok(_) => {}
            Err(e) => panic!("{solver:?}: {e}"),
        }
    }
    (s.y().to_vec(), s.stats().clone())
}

/// Largest |a_i − b_i| / max(|a_i|, 1) over the states.
fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / x.abs().max(1.0))
        .fold(0.0, f64::max)
}

fn dae(path: &str, overrides: &[&str], energy: bool) -> Dae {
    let options = DaeOptions {
        energy,
        ..DaeOptions::default()
    };
    Dae::new(&load(path, overrides), &options).unwrap_or_else(|e| panic!("{path}: {e}"))
}

#[test]
fn sparse_and_dense_lu_give_the_same_chain_motion() {
    // Ten loops swinging from the upright position for 0.5 s, before the first flat position.
    let chain = dae("models/nfourbar_chain.toml", &["parameters.N=10"], false);
    assert_eq!(chain.n_states(), 126);
    let (dense, dense_stats) = run(&chain, LinearSolver::Dense, 0.5, 1e-8);
    let (sparse, sparse_stats) = run(&chain, LinearSolver::Sparse, 0.5, 1e-8);
    // The same decisions: steps, rejections, Jacobians and Newton iterations.
    for (what, d, s) in [
        ("steps", dense_stats.steps, sparse_stats.steps),
        ("rejected", dense_stats.rejected, sparse_stats.rejected),
        (
            "Jacobians",
            dense_stats.jacobian_evals,
            sparse_stats.jacobian_evals,
        ),
        (
            "Newton iterations",
            dense_stats.newton_iterations,
            sparse_stats.newton_iterations,
        ),
    ] {
        assert_eq!(d, s, "chain of 10: {what}, dense {d} vs sparse {s}");
    }
    // Round-off of two elimination orders, carried over ~35 steps: measured 5e-15; 1e-12
    // leaves a factor of 200 and is still 1e4 below the local error the tolerance allows.
    let diff = largest_difference(&dense, &sparse);
    assert!(
        diff < 1e-12,
        "chain of 10 at t = 0.5 s: dense and sparse LU states differ by {diff:e} (relative)"
    );
}

#[test]
fn sparse_and_dense_lu_give_the_same_impacts() {
    // The clearance four-bar (DAE with energy bookkeeping: contact terms, stored impact
    // velocities and decoupled energy states in the Newton matrices) through its first three
    // impacts. Not further: through a train of impacts the run itself is sensitive to round-off
    // (the dense LU alone with rtol changed by 1e-13 relative took 175 steps instead of 174 to
    // 5 ms and ended 4e-7 apart, relative), so later states compare the impact train, not the
    // linear algebra.
    let fourbar = dae("models/farahan2016.toml", &[], true);
    let (dense, dense_stats) = run(&fourbar, LinearSolver::Dense, 0.003, 1e-8);
    let (sparse, sparse_stats) = run(&fourbar, LinearSolver::Sparse, 0.003, 1e-8);
    assert!(
        dense_stats.events >= 3,
        "the run must cross impacts: {} events",
        dense_stats.events
    );
    assert_eq!(
        (dense_stats.steps, dense_stats.events),
        (sparse_stats.steps, sparse_stats.events),
        "four-bar: (steps, events) dense vs sparse"
    );
    // Measured 5e-12 relative (the dense LU against itself with rtol changed by 1e-13: 1.5e-12):
    // the stiff contact law amplifies the round-off of the factorisations.
    let diff = largest_difference(&dense, &sparse);
    assert!(
        diff < 1e-9,
        "four-bar at t = 3 ms: dense and sparse LU states differ by {diff:e} (relative)"
    );
}

#[test]
fn the_automatic_choice_follows_the_measured_size() {
    let settings = |solver| Radau5Settings::default().linear_solver(solver);
    let core = |f: &dyn Formulation, solver| {
        let weights = ErrorWeights::new(f, 1e-8, 1e-10);
        Radau5Method::new(f, &weights, f64::INFINITY, &settings(solver))
    };
    let small = dae("models/farahan2016.toml", &[], false);
    let chain = dae("models/nfourbar_chain.toml", &["parameters.N=4"], false);
    assert!(small.n_states() < SPARSE_MIN_STATES && chain.n_states() >= SPARSE_MIN_STATES);
    assert!(!core(&small, LinearSolver::Auto).uses_sparse_lu());
    assert!(core(&small, LinearSolver::Sparse).uses_sparse_lu());
    assert!(core(&chain, LinearSolver::Auto).uses_sparse_lu());
    assert!(!core(&chain, LinearSolver::Dense).uses_sparse_lu());
    // A formulation without a sparse Jacobian keeps the dense LU whatever is asked.
    let reduced = ReducedLagrangian::new(&load("models/farahan2016.toml", &[]))
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(!core(&reduced, LinearSolver::Sparse).uses_sparse_lu());
    // The sparse Newton matrix of the chain of 4 loops (with q̈ and λ: 107 rows) holds a few
    // entries per row, the dense one (n − m)²: the second-order structure leaves the n − m
    // components after the m positions as unknowns.
    let sparse = core(&chain, LinearSolver::Sparse);
    let n = chain.n_states();
    let rows = n + chain.sparse_jacobian().map_or(0, |s| s.n_algebraic());
    assert!(
        sparse.newton_matrix_entries() < 10 * rows,
        "{} entries for {rows} rows",
        sparse.newton_matrix_entries()
    );
    let m = chain.second_order_positions();
    assert!(
        m > 0 && 2 * m <= n,
        "the DAE's positions: m = {m} of n = {n}"
    );
    assert_eq!(
        core(&chain, LinearSolver::Dense).newton_matrix_entries(),
        (n - m) * (n - m)
    );
}
