//! Radau5 against DOP853 on the reference clearance case (models/farahan2016.toml, 250 rpm,
//! 2 crank turns), near the rtol where each reaches a largest angle error of 1e-8 rad (measured
//! with `cargo run --release --example radau5_farahan`, both formulations with analytic
//! Jacobians): DOP853 rtol 1e-9 (reduced 3.5e-9; DAE 3.1e-8) and 1e-10 (DAE 1.5e-8), Radau5
//! with Hairer's defaults at rtol 1e-9 (DAE 9.8e-9), 5e-10 (reduced 1.2e-8, DAE 7.4e-9) and
//! 1e-10, and with the tuned settings (theta_jac 0.1, newton_tol 0.1) at 1e-10.
//!
//! The DAE's Radau5 target point (docs/numerics.md, "Radau5 at events"): since Radau5 cuts its steps at event crossings
//! (`Radau5Settings::cut_at_events`), the DAE reaches 7.9e-9 rad at rtol 3e-9 with 34 924 RHS
//! (`tests/radau5_target_250rpm.rs`); `radau5_rtol3e-9` times it, and `radau5_nocut_rtol3e-9`
//! the same run without the cut (1.7e-8 rad, 34 580 RHS), against DOP853's best DAE point
//! (rtol 1e-10, 1.6e-8 rad).
//!
//! The reduced formulation's target point (with the reset of Newton's convergence estimate at
//! restarts and the friction kinks as event functions): Radau5 rtol 1e-8, 8.4e-9 rad with
//! 31 824 RHS (`tests/radau5_target_250rpm.rs`), against DOP853 rtol 2e-9 (2.2e-9 rad, its
//! cheapest point ≤ 1e-8 rad; rtol 3e-9 gives 6.3e-8).

//!
//! `nfourbar_chain_40_one_step`: one Radau5 step of h = 10 ms from the initial state of the
//! 40-loop N-four-bar chain (`models/nfourbar_chain.toml`, DAE, 486 states), restarted each
//! time so that every step evaluates the Jacobian, factors both Newton matrices and iterates
//! Newton from zero: with the dense LU and with the sparse one (`Radau5Settings::linear_solver`;
//! docs/measurements.md, "Radau5 with a sparse LU").

use criterion::{Criterion, criterion_group, criterion_main};
use linkdyn::formulation::{Dae, DaeOptions, Formulation, Outputs, ReducedLagrangian};
use linkdyn::solve::radau5::{LinearSolver, Radau5Method, Radau5Settings};
use linkdyn::solve::{
    Attempt, ErrorWeights, Integrator, Method, Recorder, SolverOptions, SolverStats, Trial,
    integrate,
};
use std::time::Duration;

fn run<F: Formulation + Outputs + Clone>(f: &F, options: &SolverOptions) -> usize {
    let mut f = f.clone();
    let y0 = f.initial_state();
    let mut rec = Recorder::new(&f);
    match integrate(&mut f, 0.0, &y0, 0.48, 1e-3, options, &mut rec) {
        Ok(_) => rec.events.len(),
        Err(e) => panic!("{e}"),
    }
}

fn options(method: Method, rtol: f64, settings: Radau5Settings) -> SolverOptions {
    SolverOptions::default()
        .method(method)
        .rtol(rtol)
        .atol(rtol * 1e-3)
        .radau5(settings)
        .build()
        .unwrap_or_else(|e| panic!("{e}"))
}

fn no_cut() -> Radau5Settings {
    Radau5Settings::default().cut_at_events(false)
}

fn tuned() -> Radau5Settings {
    let mut s = Radau5Settings::default().theta_jac(0.1);
    s.newton_tol = Some(0.1);
    s
}

fn farahan(c: &mut Criterion) {
    let model = linkdyn::model::load("models/farahan2016.toml".as_ref(), &[])
        .unwrap_or_else(|e| panic!("{e}"));
    let dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let reduced = ReducedLagrangian::new(&model).unwrap_or_else(|e| panic!("{e}"));
    let mut group = c.benchmark_group("farahan2016_250rpm_2revs_error_1e-8");
    group.sample_size(20);
    let cases = [
        (
            "dop853_rtol1e-9",
            options(Method::Dop853, 1e-9, Radau5Settings::default()),
        ),
        (
            "dop853_rtol1e-10",
            options(Method::Dop853, 1e-10, Radau5Settings::default()),
        ),
        (
            "dop853_rtol2e-9",
            options(Method::Dop853, 2e-9, Radau5Settings::default()),
        ),
        (
            "radau5_rtol1e-8",
            options(Method::Radau5, 1e-8, Radau5Settings::default()),
        ),
        (
            "radau5_rtol3e-9",
            options(Method::Radau5, 3e-9, Radau5Settings::default()),
        ),
        (
            "radau5_nocut_rtol3e-9",
            options(Method::Radau5, 3e-9, no_cut()),
        ),
        (
            "radau5_rtol1e-9",
            options(Method::Radau5, 1e-9, Radau5Settings::default()),
        ),
        (
            "radau5_rtol5e-10",
            options(Method::Radau5, 5e-10, Radau5Settings::default()),
        ),
        (
            "radau5_rtol1e-10",
            options(Method::Radau5, 1e-10, Radau5Settings::default()),
        ),
        (
            "radau5_tuned_rtol1e-10",
            options(Method::Radau5, 1e-10, tuned()),
        ),
    ];
    for (name, opts) in &cases {
        group.bench_function(format!("reduced_{name}"), |b| {
            b.iter(|| run(&reduced, opts))
        });
        group.bench_function(format!("dae_{name}"), |b| b.iter(|| run(&dae, opts)));
    }
    group.finish();
}

fn chain_step(c: &mut Criterion) {
    let model = linkdyn::model::load(
        "models/nfourbar_chain.toml".as_ref(),
        &["parameters.N=40".to_string()],
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let y0 = dae.initial_state();
    let mut f0 = vec![0.0; y0.len()];
    dae.rhs(0.0, &y0, &mut f0).unwrap_or_else(|e| panic!("{e}"));
    let mut group = c.benchmark_group("nfourbar_chain_40_one_step");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for (name, solver) in [
        ("dae_radau5_dense_lu", LinearSolver::Dense),
        ("dae_radau5_sparse_lu", LinearSolver::Sparse),
    ] {
        let settings = Radau5Settings::default().linear_solver(solver);
        let weights = ErrorWeights::new(&dae, 1e-8, 1e-10);
        let mut method = Radau5Method::new(&dae, &weights, f64::INFINITY, &settings);
        let mut stats = SolverStats::default();
        let trial = Trial {
            t: 0.0,
            y: &y0,
            h: 0.01,
            t_new: 0.01,
            error_control: true,
        };
        group.bench_function(name, |b| {
            b.iter(|| {
                Integrator::<Dae>::restart(&mut method, 0.0, &y0, &f0);
                match method.attempt(&dae, &trial, &mut stats) {
                    Ok(Attempt::Accepted { .. }) => {}
                    other => panic!("{name}: {other:?}"),
                }
            })
        });
    }
    group.finish();
}

criterion_group!(benches, farahan, chain_step);
criterion_main!(benches);
