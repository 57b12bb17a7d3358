//! A slice of the paper's Fig. 6a bifurcation diagram (docs/sweeps.md): four of its 200
//! clearances (0.05, 0.2, 0.35 and 0.5 mm) at 3500 rpm, 150 crank turns each with 100 transient,
//! the reduced formulation at rtol 1e-6: independent starts with DOP853 (the command in
//! docs/usage.md, "Analyses") and with Radau5 and transient detection (the fast command's
//! method and `--settle`). A point of the whole diagram costs what a point here costs, so 50
//! times one iteration is the diagram's CPU time on one core.

use criterion::{Criterion, criterion_group, criterion_main};
use linkdyn::analysis::ParameterGrid;
use linkdyn::simulation::analyses::{SectionSpec, Settle, Sweep};
use linkdyn::simulation::{FormulationKind, SimulationOptions};
use linkdyn::solve::{Method, SolverOptions};
use std::hint::black_box;

const CLEARANCES: [f64; 4] = [0.00005, 0.0002, 0.00035, 0.0005];

fn slice(c: &mut Criterion) {
    let overrides = ["drivers.motor.speed_rpm=3500".to_string()];
    let grid = ParameterGrid::new(0.00005, 0.0005, 199).unwrap_or_else(|e| panic!("{e}"));
    let mut group = c.benchmark_group("fig6a_slice_4_clearances_150_turns");
    group.sample_size(10);
    for (name, method, settle) in [
        ("dop853_independent", Method::Dop853, None),
        (
            "radau5_settle",
            Method::Radau5,
            Some(Settle { min_transient: 5 }),
        ),
    ] {
        let solver = SolverOptions::default()
            .method(method)
            .rtol(1e-6)
            .atol(1e-9)
            .build()
            .unwrap_or_else(|e| panic!("{e}"));
        let sweep = Sweep {
            model_path: "models/farahan2016.toml".as_ref(),
            model_text: None,
            overrides: &overrides,
            parameter: "joints.B.clearance",
            grid,
            options: SimulationOptions::default()
                .formulation(FormulationKind::Reduced)
                .solver(solver),
            section: SectionSpec {
                turns: 150,
                transient: 100,
                phase: 0.0,
                observe: vec!["coupler.phi".into()],
            },
        };
        group.bench_function(name, |b| {
            b.iter(|| {
                for &c in &CLEARANCES {
                    let run = sweep
                        .point_from(c, settle, None)
                        .unwrap_or_else(|e| panic!("{e}"));
                    black_box(run.section.period);
                }
            })
        });
    }
    group.finish();
}

// No plots: criterion's plotters backend finds no system font on the build machines.
criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = slice
}
criterion_main!(benches);
