//! The reference case of the clearance issue: models/farahan2016.toml, 2 crank turns at 250 rpm
//! (22 impacts), rtol 1e-9, for each formulation × integrator; plus one RHS evaluation of each
//! formulation in contact and a 3500 rpm group. The `simulation` groups run the same cases as
//! `linkdyn run` does (outputs at every 1 ms sample, the impact log with its true peaks): their
//! time over the bare integration's is what the run's bookkeeping costs.

use criterion::{Criterion, criterion_group, criterion_main};
use linkdyn::formulation::{Dae, DaeOptions, Formulation, Outputs, ReducedLagrangian};
use linkdyn::model::Model;
use linkdyn::simulation::{Discard, FormulationKind, Simulation, SimulationOptions};
use linkdyn::solve::{Method, Recorder, SolverOptions, integrate};
use std::hint::black_box;

fn load(overrides: &[String]) -> Model {
    linkdyn::model::load("models/farahan2016.toml".as_ref(), overrides)
        .unwrap_or_else(|e| panic!("{e}"))
}

fn run<F: Formulation + Outputs + Clone>(f: &F, t_end: f64, options: &SolverOptions) -> usize {
    let mut f = f.clone();
    let y0 = f.initial_state();
    let mut rec = Recorder::new(&f);
    // Output every 1 ms: the run's cost, not the CSV's.
    match integrate(&mut f, 0.0, &y0, t_end, 1e-3, options, &mut rec) {
        Ok(_) => rec.events.len(),
        Err(e) => panic!("{e}"),
    }
}

fn options(method: Method) -> SolverOptions {
    SolverOptions::default()
        .method(method)
        .rtol(1e-9)
        .atol(1e-12)
        .build()
        .unwrap_or_else(|e| panic!("{e}"))
}

fn scenario(c: &mut Criterion, speed_rpm: f64) {
    let model = load(&[format!("drivers.motor.speed_rpm={speed_rpm}")]);
    let t_end = 2.0 * 60.0 / speed_rpm;
    let dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let reduced = ReducedLagrangian::new(&model).unwrap_or_else(|e| panic!("{e}"));
    let mut group = c.benchmark_group(format!("farahan2016_{speed_rpm}rpm_2revs_rtol1e-9"));
    group.sample_size(20);
    for method in [Method::Dop853, Method::Dopri5] {
        let opts = options(method);
        group.bench_function(format!("dae_{method}"), |b| {
            b.iter(|| run(&dae, t_end, &opts))
        });
        group.bench_function(format!("reduced_{method}"), |b| {
            b.iter(|| run(&reduced, t_end, &opts))
        });
    }
    group.finish();
}

fn rhs(c: &mut Criterion) {
    let model = load(&[]);
    let dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let reduced = ReducedLagrangian::new(&model).unwrap_or_else(|e| panic!("{e}"));
    // A state in contact: rotate the coupler so that the journal presses into the bearing.
    let mut y = dae.initial_state();
    y[5] += 0.0022;
    let mut dy = vec![0.0; y.len()];
    let mut yr = reduced.initial_state();
    yr[0] += 0.0022;
    let mut dyr = vec![0.0; yr.len()];
    let mut group = c.benchmark_group("farahan2016_rhs_in_contact");
    group.bench_function("dae", |b| {
        b.iter(|| dae.rhs(black_box(0.01), black_box(&y), &mut dy))
    });
    group.bench_function("reduced", |b| {
        b.iter(|| reduced.rhs(black_box(0.01), black_box(&yr), &mut dyr))
    });
    group.finish();
}

/// The full run of `linkdyn run` without the CSV: samples evaluated and summarised, the impact
/// log with its true peaks; both formulations with DOP853 and Radau5.
fn simulation(c: &mut Criterion, speed_rpm: f64) {
    let model = load(&[format!("drivers.motor.speed_rpm={speed_rpm}")]);
    let mut group = c.benchmark_group(format!("farahan2016_{speed_rpm}rpm_2revs_simulation"));
    group.sample_size(20);
    for method in [Method::Dop853, Method::Radau5] {
        for formulation in [FormulationKind::Reduced, FormulationKind::Dae] {
            let options = SimulationOptions::default()
                .revs(2.0)
                .dt(1e-3)
                .formulation(formulation)
                .solver(options(method));
            let sim = Simulation::new(&model, options).unwrap_or_else(|e| panic!("{e}"));
            group.bench_function(format!("{formulation}_{method}"), |b| {
                b.iter(|| {
                    sim.run(&mut Discard)
                        .map(|s| s.clearance_joints.len())
                        .unwrap_or_else(|e| panic!("{e}"))
                })
            });
        }
    }
    group.finish();
}

fn runs(c: &mut Criterion) {
    scenario(c, 250.0);
    scenario(c, 3500.0);
}

fn simulations(c: &mut Criterion) {
    simulation(c, 250.0);
    simulation(c, 3500.0);
}

criterion_group!(benches, rhs, runs, simulations);
criterion_main!(benches);
