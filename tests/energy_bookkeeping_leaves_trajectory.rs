//! Claim: energy bookkeeping (`DaeOptions::energy`: driver work, external work and dissipation
//! integrated as three extra states) observes the motion without changing it. The extra states
//! and the stored impact velocities are not error-controlled
//! (`Formulation::error_controlled`), so the integrator takes the same steps with and without
//! them, and every body state is bit-identical at every sample, with the same impacts.
//!
//! Before the bookkeeping states were excluded from the error norm, `--energy` moved the
//! coupler angle by 1.7e-7 rad at the default tolerance (the energy integrals changed the step
//! sizes).

use linkdyn::formulation::{Dae, DaeOptions, Formulation};
use linkdyn::solve::{
    EventRecord, Method, Sink, SolveError, SolverOptions, SolverStats, integrate,
};

/// Raw states at every sample and the events.
#[derive(Default)]
struct States {
    t: Vec<f64>,
    y: Vec<Vec<f64>>,
    events: Vec<EventRecord>,
}

impl<F> Sink<F> for States {
    fn sample(&mut self, _f: &F, t: f64, y: &[f64]) -> Result<(), SolveError> {
        self.t.push(t);
        self.y.push(y.to_vec());
        Ok(())
    }
    fn event(
        &mut self,
        _f: &F,
        event: &EventRecord,
        _before: &[f64],
        _after: &[f64],
    ) -> Result<(), SolveError> {
        self.events.push(*event);
        Ok(())
    }
}

fn run(energy: bool, method: Method) -> (States, SolverStats, usize) {
    let model = linkdyn::model::load("models/farahan2016.toml".as_ref(), &[])
        .unwrap_or_else(|e| panic!("{e}"));
    let options = DaeOptions {
        energy,
        ..DaeOptions::default()
    };
    let mut dae = Dae::new(&model, &options).unwrap_or_else(|e| panic!("{e}"));
    let body_states = 2 * dae.n_coordinates();
    let y0 = dae.initial_state();
    // Default tolerances (rtol 1e-8, atol 1e-10): where the difference used to show.
    let opts = SolverOptions::default().method(method);
    let mut states = States::default();
    // Two crank turns at 250 rpm.
    let stats = integrate(&mut dae, 0.0, &y0, 0.48, 1e-3, &opts, &mut states)
        .unwrap_or_else(|e| panic!("energy {energy}, {method}: {e}"));
    (states, stats, body_states)
}

#[test]
fn energy_bookkeeping_does_not_change_the_motion() {
    for method in Method::ALL {
        let (plain, plain_stats, n) = run(false, method);
        let (booked, booked_stats, _) = run(true, method);
        // Same steps: the error norms see the same controlled components with the same values.
        assert_eq!(
            (plain_stats.steps, plain_stats.rejected),
            (booked_stats.steps, booked_stats.rejected),
            "{method}: steps and rejections without / with energy bookkeeping"
        );
        assert_eq!(plain.t, booked.t, "{method}: sample times");
        // Bit-identical, not merely close: the body states never read the bookkeeping states,
        // and with identical steps every floating-point operation on them is the same.
        for (k, (a, b)) in plain.y.iter().zip(&booked.y).enumerate() {
            for i in 0..n {
                assert!(
                    a[i].to_bits() == b[i].to_bits(),
                    "{method}: state {i} at t = {} s: {} without, {} with energy bookkeeping",
                    plain.t[k],
                    a[i],
                    b[i]
                );
            }
        }
        assert!(plain.events.len() > 10, "{method}: expected impacts");
        assert_eq!(
            plain.events, booked.events,
            "{method}: impact and separation times"
        );
    }
}
