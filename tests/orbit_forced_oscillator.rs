//! The periodic orbit of a damped linear oscillator under harmonic forcing, found by shooting,
//! against its closed form.
//!
//! m ẍ + c ẋ + k x = F0 sin(w t), written x'' + 2ζω0 x' + ω0² x = (F0/m) sin(w t). Its
//! steady state (the only periodic orbit of period T = 2π/w) is x(t) = A sin(w t − ϕ) with
//! A = (F0/m)/√((ω0² − w²)² + (2ζω0 w)²) and tan ϕ = 2ζω0 w/(ω0² − w²); its monodromy matrix is
//! exp(J T), whose eigenvalues (the Floquet multipliers) are exp(λ T) with λ = −ζω0 ± iω0√(1−ζ²)
//! the eigenvalues of the free system (L. Meirovitch, *Fundamentals of Vibrations*,
//! McGraw-Hill, 2001, §3.2 (harmonic response) and §1.10 (free damped response); G. Teschl,
//! *Ordinary Differential Equations and Dynamical Systems*, AMS, 2012, §3.6 (Floquet theory)).
//!
//! The oscillator is written here as a formulation of its own, with its analytic Jacobian, and
//! given to the library's shooting (`linkdyn::analysis::orbit`) directly: the shooting on a
//! plain ODE, with no model behind it. `tests/orbit_dae.rs` runs the same oscillator as a
//! model file (a slider on a spring-damper under `force = ["F0*sin(w*t)", 0]`) through the DAE.

mod common;

use common::ode::ForcedOscillator;
use linkdyn::analysis::orbit::{OrbitOptions, periodic_orbit};
use linkdyn::solve::{Method, SolverOptions};

const OMEGA0: f64 = ForcedOscillator::OMEGA0;
const ZETA: f64 = ForcedOscillator::ZETA;
const W: f64 = 2.2; // rad/s

#[test]
fn the_orbit_is_the_steady_state_and_the_multipliers_are_exp_lambda_t() {
    let period = std::f64::consts::TAU / W;
    let solver = SolverOptions::default()
        .method(Method::Dop853)
        .rtol(1e-11)
        .atol(1e-13);
    // Shooting from rest at t0 = 0: a guess far from the orbit (amplitude ~0.45 m).
    let orbit = periodic_orbit(
        &ForcedOscillator { w: W },
        0.0,
        &[0.0, 0.0],
        &OrbitOptions::new(period),
        &solver,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let (x0, v0) = ForcedOscillator { w: W }.steady_state();
    // The orbit to a few hundred integration tolerances (1e-11 relative, states of order 1).
    for (got, want, what) in [(orbit.y0[0], x0, "x"), (orbit.y0[1], v0, "v")] {
        assert!(
            (got - want).abs() < 1e-8,
            "{what}(0) = {got}, steady state {want}"
        );
    }
    // Linear: Newton converges in one step (the residual is then the integration's noise).
    assert!(orbit.iterations <= 2, "{} iterations", orbit.iterations);
    assert_eq!(orbit.trivial_multipliers, 0);
    let decay = (-ZETA * OMEGA0 * period).exp();
    let turn = OMEGA0 * (1.0 - ZETA * ZETA).sqrt() * period;
    let want = [decay * turn.cos(), decay * turn.sin().abs()];
    assert_eq!(orbit.multipliers.len(), 2);
    for mu in &orbit.multipliers {
        // exp(J T) from the variational equations at rtol 1e-11: ~1e-10.
        assert!(
            (mu[0] - want[0]).abs() < 1e-8 && (mu[1].abs() - want[1]).abs() < 1e-8,
            "multiplier {mu:?}, exp(λT) = {want:?} ± i"
        );
    }
    assert!(orbit.stable());
}
