//! The reference four-bar: one DAE right-hand-side evaluation, and a 2-turn run at 250 rpm.

use criterion::{Criterion, criterion_group, criterion_main};
use linkdyn::formulation::{Dae, DaeOptions, Formulation};
use linkdyn::solve::Recorder;
use linkdyn::solve::{Method, SolverOptions, integrate};
use std::hint::black_box;

fn load(path: &str) -> linkdyn::model::Model {
    match linkdyn::model::load(path.as_ref(), &[]) {
        Ok(m) => m,
        Err(e) => panic!("{e}"),
    }
}

fn dae_rhs(c: &mut Criterion) {
    let model = load("models/fourbar_ideal.toml");
    let dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let y = dae.initial_state();
    let mut dy = vec![0.0; y.len()];
    let mut group = c.benchmark_group("fourbar_ideal_250rpm");
    group.bench_function("dae_rhs", |b| {
        b.iter(|| dae.rhs(black_box(0.01), black_box(&y), &mut dy))
    });
    for (name, method) in [
        ("dae_dop853_rtol1e-9_2revs", Method::Dop853),
        ("dae_dopri5_rtol1e-9_2revs", Method::Dopri5),
    ] {
        let options = SolverOptions::default()
            .method(method)
            .rtol(1e-9)
            .atol(1e-11)
            .build()
            .unwrap_or_else(|e| panic!("{e}"));
        let t_end = 2.0 * 60.0 / 250.0;
        group.bench_function(name, |b| {
            b.iter(|| {
                let mut dae = dae.clone();
                let y0 = dae.initial_state();
                let mut rec = Recorder::new(&dae);
                integrate(&mut dae, 0.0, &y0, t_end, 1e-3, &options, &mut rec)
            })
        });
    }
    group.finish();
}

criterion_group!(benches, dae_rhs);
criterion_main!(benches);
