//! Hundreds of bodies on chains of four-bars (`models/parallel_fourbar_chain.toml` with N = 5, 50,
//! 200 loops: 11, 101 and 401 bodies, 32, 302 and 1202 constraint rows; and
//! `models/nfourbar_chain.toml`):
//!
//! * `parallel_fourbar_chain_rhs`: one DAE right-hand-side evaluation, with the Schur complement
//!   dense and skyline;
//! * `parallel_fourbar_chain_build`: building the model, `Dae::new` (assembly of positions and
//!   velocities, the redundancy check, the length scale, the Schur structure) from the loaded
//!   `Model`;
//! * `nfourbar_chain_generalized_rhs`: one right-hand side of the generalised formulation on
//!   the N-four-bar chain (`models/nfourbar_chain.toml`, N = 4, 10, 40, 80 loops: 9, 21, 81 and
//!   161 bodies, m = 6N + 2 dependent coordinates), with the dependent block's LU dense and
//!   sparse, from a warm start 1 ms ahead along the motion (one Newton iteration, as at a
//!   stage).
//!
//! Run: `cargo bench --bench many_bodies`. The dense factorisation of the 401-body chain takes
//! about a second per call on the 2-core machine, so the groups keep few samples and a 2 s
//! target.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use linkdyn::formulation::generalized::BlockSolver;
use linkdyn::formulation::schur::SchurSolver;
use linkdyn::formulation::{Dae, DaeOptions, Formulation, Generalized};
use std::hint::black_box;
use std::time::Duration;

/// The chain of `loops` parallel four-bars, loaded.
fn chain_model(loops: usize) -> linkdyn::model::Model {
    let set = [format!("parameters.N={loops}")];
    linkdyn::model::load("models/parallel_fourbar_chain.toml".as_ref(), &set)
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The chain of `loops` parallel four-bars, assembled.
fn chain(loops: usize) -> Dae {
    Dae::new(&chain_model(loops), &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn build(c: &mut Criterion) {
    let mut group = c.benchmark_group("parallel_fourbar_chain_build");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for loops in [5, 50, 200] {
        let model = chain_model(loops);
        let bodies = model.bodies.len();
        group.bench_with_input(BenchmarkId::new("dae_new", bodies), &bodies, |b, _| {
            b.iter(|| Dae::new(black_box(&model), &DaeOptions::default()))
        });
    }
    group.finish();
}

fn rhs(c: &mut Criterion) {
    let mut group = c.benchmark_group("parallel_fourbar_chain_rhs");
    group
        .sample_size(20)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for loops in [5, 50, 200] {
        let base = chain(loops);
        let bodies = base.model().bodies.len();
        for (name, solver) in [
            ("dense", SchurSolver::Dense),
            ("skyline", SchurSolver::Skyline),
        ] {
            let dae = base.clone().with_schur_solver(solver);
            let y = dae.initial_state();
            let mut dy = vec![0.0; y.len()];
            group.bench_with_input(BenchmarkId::new(name, bodies), &bodies, |b, _| {
                b.iter(|| dae.rhs(black_box(0.01), black_box(&y), &mut dy))
            });
        }
    }
    group.finish();
}

fn generalized_rhs(c: &mut Criterion) {
    let mut group = c.benchmark_group("nfourbar_chain_generalized_rhs");
    group
        .sample_size(20)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for loops in [4, 10, 40, 80] {
        let set = [format!("parameters.N={loops}")];
        let model = linkdyn::model::load("models/nfourbar_chain.toml".as_ref(), &set)
            .unwrap_or_else(|e| panic!("{e}"));
        let bodies = model.bodies.len();
        for (name, solver) in [
            ("dense", BlockSolver::Dense),
            ("sparse", BlockSolver::Sparse),
        ] {
            let f = Generalized::new(&model, &DaeOptions::default())
                .unwrap_or_else(|e| panic!("{e}"))
                .with_block_solver(solver);
            // 1 ms along the motion: the dependent coordinates' warm start is off by O(1e-6),
            // so Newton iterates once, as at a stage.
            let y0 = f.initial_state();
            let mut dy = vec![0.0; y0.len()];
            f.rhs(0.0, &y0, &mut dy).unwrap_or_else(|e| panic!("{e}"));
            let y: Vec<f64> = y0.iter().zip(&dy).map(|(y, d)| y + 1e-3 * d).collect();
            group.bench_with_input(BenchmarkId::new(name, bodies), &bodies, |b, _| {
                b.iter(|| f.rhs(black_box(1e-3), black_box(&y), &mut dy))
            });
        }
    }
    group.finish();
}

// No plots: criterion's plotters backend finds no system font on the build machines.
criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = build, rhs, generalized_rhs
}
criterion_main!(benches);
