//! Claim (docs/formulations.md, "Long chains"): the DAE takes the N-four-bar chain (models/nfourbar_chain.toml: N
//! parallelogram loops of 1 m, 1 kg rods, the IFToMM benchmark) through its flat positions —
//! where every pin lies on the ground line and the constraint Jacobian loses one rank per loop
//! — for 20 s, 20 passages, on the right branch, within 1e-3 m of the exact motion at every
//! 0.05 s sample at the default tolerances (rtol 1e-8) and within 1e-6 m at rtol 1e-10, with
//! the explicit methods for 2, 10, 40 and 80 loops and with Radau5 for 2, 10 and 40; and it
//! reports every passage.
//!
//! Exact solution: the compound pendulum J θ̈ = −G cos θ of `common/chain.rs`, integrated in
//! the test by RK4 at 1e-4 s (error ~1e-12 rad). The tip of link0 is (L cos θ, L sin θ).
//!
//! Before (2026-11-27), with the multiplier solve regularised at μ = 1e-10 D, DOP853 stalled
//! with "no progress" at the first flat position for 20 loops and more, at every tolerance:
//! the regularisation, not the integration, set the step size there (`src/formulation/dae.rs`,
//! `PIVOT_REGULARISATION`).

mod common;
use common::chain::{ROD_LENGTH, flat_passages, theta_exact};
use common::{col, load};
use linkdyn::formulation::{Dae, DaeOptions, Formulation};
use linkdyn::solve::{Method, Recorder, SolverOptions, integrate};

const T_END: f64 = 20.0;
const DT: f64 = 0.05;

/// Runs the DAE of the chain of `loops` loops; returns the samples and the passages reported.
fn run(loops: usize, method: Method, rtol: f64, atol: f64) -> (Recorder, usize) {
    let model = load(
        "models/nfourbar_chain.toml",
        &[&format!("parameters.N={loops}")],
    );
    let mut dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let options = SolverOptions::default()
        .method(method)
        .rtol(rtol)
        .atol(atol)
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let y0 = dae.initial_state();
    let mut rec = Recorder::new(&dae);
    integrate(&mut dae, 0.0, &y0, T_END, DT, &options, &mut rec)
        .unwrap_or_else(|e| panic!("{loops} loops, {method:?}, rtol {rtol:e}: {e}"));
    let passages = dae.singular_passages().len();
    (rec, passages)
}

/// Asserts the tip within `bound` (m) of the exact motion at every sample, every link at the
/// same angle and every coupler level (the parallelogram branch), and the passages reported
/// equal to those of the exact motion.
fn check(loops: usize, method: Method, rtol: f64, bound: f64) {
    check_with_atol(loops, method, rtol, rtol * 1e-2, bound);
}

/// [`check`] with the absolute tolerance given.
fn check_with_atol(loops: usize, method: Method, rtol: f64, atol: f64, bound: f64) {
    let case = format!("{loops} loops, {method:?}, rtol {rtol:e}, atol {atol:e}");
    let (rec, reported) = run(loops, method, rtol, atol);
    let exact = theta_exact(loops, &rec.t, 1e-4);
    let (tx, ty) = (col(&rec, "tip.x"), col(&rec, "tip.y"));
    let (worst, at) = exact
        .iter()
        .zip(tx.iter().zip(&ty))
        .zip(&rec.t)
        .map(|((th, (x, y)), t)| {
            let e = (x - ROD_LENGTH * th.cos()).hypot(y - ROD_LENGTH * th.sin());
            (e, *t)
        })
        .fold((0.0, 0.0), |m, x| if x.0 > m.0 { x } else { m });
    assert!(
        worst < bound,
        "{case}: the tip is {worst:e} m off the exact motion at t = {at} s, bound {bound:e}"
    );
    let link0 = col(&rec, "link0.phi");
    for i in 1..=loops {
        let link = col(&rec, &format!("link{i}.phi"));
        let coupler = col(&rec, &format!("coupler{i}.phi"));
        for k in 0..rec.len() {
            assert!(
                (link[k] - link0[k]).abs() < 1e-3 && coupler[k].abs() < 1e-3,
                "{case}: loop {i} left the parallelogram branch at t = {} s: link {} rad, link0 {} rad, coupler {} rad",
                rec.t[k],
                link[k],
                link0[k],
                coupler[k]
            );
        }
    }
    let passed = flat_passages(&exact);
    assert_eq!(
        passed, 20,
        "{case}: the exact motion passes 20 flat positions"
    );
    assert_eq!(reported, passed, "{case}: passages reported");
}

#[test]
fn dop853_follows_the_chain_through_20_flat_positions() {
    for loops in [2, 10, 40] {
        check(loops, Method::Dop853, 1e-8, 1e-3);
        check(loops, Method::Dop853, 1e-10, 1e-6);
    }
}

#[test]
fn dopri5_follows_the_chain_through_20_flat_positions() {
    for loops in [2, 10, 40] {
        check(loops, Method::Dopri5, 1e-8, 1e-3);
        check(loops, Method::Dopri5, 1e-10, 1e-6);
    }
}

/// Radau5 with its sparse LU (the DAE's Newton matrices in augmented form), at the CLI's
/// default atol 1e-10: measured 2026-11-27, 1.3–1.4e-4 m at rtol 1e-8 and 7.0–7.5e-7 m at rtol
/// 1e-10 for 2, 10 and 40 loops. At atol 1e-12 too: with every step end near a passage
/// projected (a restart each) 2 and 10 loops ended 2.9e-6 and 4.4e-6 m off; with the
/// projections spaced (`projection::Spacing`) 3.4e-7 and 4.8e-7 m (measured 2026-11-28).
#[test]
fn radau5_follows_the_chain_through_20_flat_positions() {
    for loops in [2, 10] {
        check_with_atol(loops, Method::Radau5, 1e-8, 1e-10, 1e-3);
        check_with_atol(loops, Method::Radau5, 1e-10, 1e-10, 1e-6);
        check_with_atol(loops, Method::Radau5, 1e-10, 1e-12, 1e-6);
    }
    check_with_atol(40, Method::Radau5, 1e-8, 1e-10, 1e-3);
}

#[test]
fn the_chain_of_80_loops_passes_too() {
    check(80, Method::Dop853, 1e-8, 1e-3);
}
