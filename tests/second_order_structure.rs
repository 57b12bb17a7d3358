//! The q̇ = v structure that the reduced formulation and the DAE declare
//! (`Formulation::second_order_positions`, m): at every state, f_i(t, y) = y_{m+i} for i < m,
//! so row i of the Jacobian is the unit row e_{m+i}. Radau5 solves its Newton systems through
//! the other n − m unknowns on the strength of it; a formulation that declared it wrongly
//! would get wrong Newton corrections (slow or failed convergence, not a wrong answer, which is
//! why it is checked here directly). Checked at the initial state and at 19 states perturbed
//! in every component, at 250 and 3500 rpm, with and without the DAE's energy bookkeeping.

mod common;

use linkdyn::formulation::{Dae, DaeOptions, Formulation, ReducedLagrangian};

fn check<F: Formulation>(name: &str, f: &F) {
    let n = f.n_states();
    let m = f.second_order_positions();
    assert!(m > 0 && 2 * m <= n, "{name}: m = {m}, n = {n}");
    let y0 = f.initial_state();
    let mut state = 0x9E37_79B9_7F4A_7C15_u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    for trial in 0..20 {
        // Positions moved by up to 5e-6 (small beside the clearance: the penetration check
        // stays quiet), velocities by up to 0.5.
        let y: Vec<f64> = y0
            .iter()
            .enumerate()
            .map(|(i, &v)| {
                if trial == 0 {
                    v
                } else if i < m {
                    v + 1e-5 * next()
                } else {
                    v + next()
                }
            })
            .collect();
        let t = 0.0; // the crank angle follows t: positions are perturbed around t = 0
        let mut f_y = vec![0.0; n];
        if let Err(e) = f.rhs(t, &y, &mut f_y) {
            panic!("{name}: {e}");
        }
        for i in 0..m {
            assert_eq!(
                f_y[i].to_bits(),
                y[m + i].to_bits(),
                "{name}: f_{i} at trial {trial}"
            );
        }
        let mut jac = vec![0.0; n * n];
        let mut work = vec![0.0; 2 * n];
        if let Err(e) = f.jacobian(t, &y, &f_y, &mut jac, &mut work) {
            panic!("{name}: {e}");
        }
        for i in 0..m {
            for j in 0..n {
                let unit = f64::from(j == m + i);
                assert_eq!(jac[i * n + j], unit, "{name}: J[{i}][{j}] at trial {trial}");
            }
        }
    }
}

#[test]
fn the_declared_position_rows_are_unit_rows() {
    for rpm in ["250", "3500"] {
        let model = common::load(
            "models/farahan2016.toml",
            &[&format!("drivers.motor.speed_rpm={rpm}")],
        );
        let reduced = ReducedLagrangian::new(&model).unwrap_or_else(|e| panic!("{e}"));
        check("reduced", &reduced);
        let dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        check("dae", &dae);
        let energy = DaeOptions {
            energy: true,
            ..DaeOptions::default()
        };
        let booked = Dae::new(&model, &energy).unwrap_or_else(|e| panic!("{e}"));
        check("dae with energy", &booked);
    }
}
