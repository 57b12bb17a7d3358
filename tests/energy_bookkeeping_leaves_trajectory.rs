//! Claim: energy bookkeeping (`DaeOptions::energy`: driver work, external work and dissipation
//! integrated as three extra states) observes the motion without changing it. The extra states
//! and the stored impact velocities are not error-controlled
//! (`Formulation::error_controlled`), so the integrator takes the same steps with and without
//! them, and every body state is bit-identical at every sample, with the same impacts.
//!
//! Before the bookkeeping states were excluded from the error norm, `--energy` moved the
//! coupler angle by 1.7e-7 rad at the default tolerance (the energy integrals changed the step
//! sizes).

mod common;
use common::energy::{assert_same_motion, run_farahan};
use linkdyn::solve::{Method, SolverOptions};

#[test]
fn energy_bookkeeping_does_not_change_the_motion() {
    for method in Method::ALL {
        // Default tolerances (rtol 1e-8, atol 1e-10): where the difference used to show.
        let opts = SolverOptions::default().method(method);
        let (plain, plain_stats, n) = run_farahan(false, &opts);
        let (booked, booked_stats, _) = run_farahan(true, &opts);
        // Same steps: the error norms see the same controlled components with the same values.
        assert_eq!(
            (plain_stats.steps, plain_stats.rejected),
            (booked_stats.steps, booked_stats.rejected),
            "{method}: steps and rejections without / with energy bookkeeping"
        );
        // Bit-identical, not merely close: the body states never read the bookkeeping states,
        // and with identical steps every floating-point operation on them is the same.
        assert_same_motion(&method.to_string(), &plain, &booked, n);
    }
}
