//! Chains of parallel four-bars (`models/parallel_fourbar_chain.toml`, N loops: 2N + 1 bodies,
//! 6N + 2 constraint rows): the skyline Schur solve of `src/formulation/schur.rs` gives the
//! accelerations of the dense one, a 101-body chain conserves energy and keeps its links
//! parallel, and the sparse least-norm assembly finds the parallelogram from a disturbed guess.

mod common;
use common::*;
use linkdyn::formulation::schur::SchurSolver;
use linkdyn::formulation::{Dae, DaeOptions, Formulation};
use linkdyn::solve::{Method, Recorder, SolverOptions, integrate};

fn chain(loops: usize) -> linkdyn::model::Model {
    load(
        "models/parallel_fourbar_chain.toml",
        &[&format!("parameters.N={loops}")],
    )
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// q̇, q̈ at y with the given storage of S.
fn rates(dae: &Dae, solver: SchurSolver, y: &[f64]) -> Vec<f64> {
    let dae = dae.clone().with_schur_solver(solver);
    let mut dy = vec![0.0; y.len()];
    dae.rhs(0.1, y, &mut dy).unwrap_or_else(|e| panic!("{e}"));
    dy
}

#[test]
fn skyline_and_dense_schur_give_the_same_accelerations_on_chains() {
    for loops in [3, 5, 50] {
        let dae = Dae::new(&chain(loops), &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        let n = dae.n_coordinates();
        // The assembled state at rest, and a state off the constraints with velocities
        // (Baumgarte terms and centripetal γ non-zero): any y is a valid input to the RHS.
        let y0 = dae.initial_state();
        let mut y1 = y0.clone();
        for (k, x) in y1.iter_mut().enumerate() {
            *x += if k < n { 1e-3 } else { 0.5 } * ((k as f64) * 0.7).sin();
        }
        for (state, y) in [("assembled, at rest", &y0), ("disturbed, moving", &y1)] {
            let dense = rates(&dae, SchurSolver::Dense, y);
            let skyline = rates(&dae, SchurSolver::Skyline, y);
            let scale = max_abs(&dense[n..2 * n]);
            // Both Cholesky factorisations are backward stable: they differ by round-off times
            // the condition number of S, which for these chains (links 0.3 m, couplers 0.2 m,
            // masses 0.4–0.6 kg) stays below 1e4: 1e-10 relative has a margin of 10⁴ over eps·κ.
            for k in n..2 * n {
                assert!(
                    (dense[k] - skyline[k]).abs() <= 1e-10 * scale,
                    "{loops} loops, {state}, q̈[{}]: dense {:e} vs skyline {:e} (scale {scale:e})",
                    k - n,
                    dense[k],
                    skyline[k]
                );
            }
        }
        // The default picks the skyline above 16 rows.
        assert_eq!(
            dae.schur_is_skyline(),
            6 * loops + 2 > 16,
            "{loops} loops: storage"
        );
    }
}

#[test]
fn hundred_body_chain_conserves_energy_and_keeps_its_links_parallel() {
    // 50 loops: 101 bodies, 302 rows (skyline). Half a swing of the 0.6 rad pendulum.
    let model = chain(50);
    let options = DaeOptions {
        energy: true,
        ..DaeOptions::default()
    };
    let mut dae = Dae::new(&model, &options).unwrap_or_else(|e| panic!("{e}"));
    assert!(dae.schur_is_skyline(), "101 bodies use the skyline");
    let rtol = 1e-9;
    let solver = SolverOptions::default()
        .method(Method::Dop853)
        .rtol(rtol)
        .atol(rtol * 1e-3)
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let y0 = dae.initial_state();
    let mut rec = Recorder::new(&dae);
    integrate(&mut dae, 0.0, &y0, 0.5, 0.05, &solver, &mut rec).unwrap_or_else(|e| panic!("{e}"));
    // No driver, no damping, no contact: T + U is constant; the balance column is its change.
    // Kinetic energy reaches about m g L (1 − cos 0.6) ≈ 60 kg × 9.81 m/s² × 0.3 m × 0.17
    // ≈ 30 J; the integration error in energy is of order rtol times that, and Baumgarte's
    // forces do work only on the constraint drift (≈ rtol · L): 1e-6 J is ~ 30 times that.
    let balance = col(&rec, "energy.balance");
    let kinetic = col(&rec, "energy.kinetic");
    assert!(
        max_abs(&kinetic) > 1.0,
        "the chain swings: largest T = {:e} J",
        max_abs(&kinetic)
    );
    assert!(
        max_abs(&balance) < 1e-6,
        "energy not conserved: largest |ΔE| = {:e} J (bound 1e-6 J)",
        max_abs(&balance)
    );
    // Every loop is a parallelogram: all N + 1 links keep the angle of link0.
    let phi0 = col(&rec, "link0.phi");
    for i in 1..=50 {
        let phi = col(&rec, &format!("link{i}.phi"));
        let worst = phi
            .iter()
            .zip(&phi0)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        // Constraint drift of the angles: rtol-sized, kept by Baumgarte; 1e-7 rad is 100×.
        assert!(
            worst < 1e-7,
            "link{i} and link0 differ by {worst:e} rad (bound 1e-7 rad)"
        );
    }
}

#[test]
fn sparse_assembly_finds_the_parallelogram_from_a_disturbed_guess() {
    // 50 loops: 302 rows, so the Newton steps take the sparse least-norm solve.
    let mut model = chain(50);
    let exact = model
        .bodies
        .iter()
        .map(|b| b.initial.phi)
        .collect::<Vec<_>>();
    for (k, body) in model.bodies.iter_mut().enumerate() {
        body.initial.phi += 0.02 * ((k as f64) * 1.3).sin();
        body.initial.x += 0.005 * ((k as f64) * 0.4).cos();
    }
    let dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let assembly = dae.assembly();
    assert!(
        assembly.iterations > 0,
        "the disturbed guess needs Newton steps"
    );
    assert!(
        assembly.residual <= 1e-12,
        "assembled to |Φ| = {:e} (position tolerance 1e-12)",
        assembly.residual
    );
    assert_eq!(assembly.dof, 1, "one degree of freedom");
    // The least-norm steps move the guess as little as possible: the links end parallel at an
    // angle within the 0.02 rad disturbance of the exact one.
    let link0 = assembly.q[2];
    for (k, body) in model.bodies.iter().enumerate() {
        if body.name.starts_with("link") {
            let phi = assembly.q[3 * k + 2];
            assert!(
                (phi - link0).abs() < 1e-10,
                "{} at {phi} rad, link0 at {link0} rad: not parallel",
                body.name
            );
        }
    }
    assert!(
        (link0 - exact[0]).abs() < 0.02,
        "link0 assembled at {link0} rad, guess {} rad",
        exact[0]
    );
}
