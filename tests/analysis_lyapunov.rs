//! Largest Lyapunov exponents of systems with known answers (`linkdyn::analysis::lyapunov`):
//! a damped pendulum (−ζω), an undamped pendulum (0) and the Lorenz system (0.9056).

use linkdyn::analysis::lyapunov::{LyapunovEstimate, LyapunovOptions, largest_lyapunov};
use linkdyn::formulation::{Formulation, FormulationError, NoStepHooks};
use linkdyn::solve::{Method, SolverOptions};

/// θ'' + 2ζω θ' + ω² sin θ = 0 as (θ, θ'), plus an optional extra state z' = growth·z that is
/// decoupled from the pendulum (a stand-in for a bookkeeping state that must not be measured).
#[derive(Clone)]
struct Pendulum {
    omega: f64,
    zeta: f64,
    growth: Option<f64>,
}

impl NoStepHooks for Pendulum {}

impl Formulation for Pendulum {
    fn n_states(&self) -> usize {
        if self.growth.is_some() { 3 } else { 2 }
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![0.1, 0.0, 1.0]
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        dy[0] = y[1];
        dy[1] = -2.0 * self.zeta * self.omega * y[1] - self.omega * self.omega * y[0].sin();
        if let Some(g) = self.growth {
            dy[2] = g * y[2];
        }
        Ok(())
    }
}

/// The Lorenz system with σ = 10, ρ = 28, β = 8/3.
#[derive(Clone)]
struct Lorenz;

impl NoStepHooks for Lorenz {}

impl Formulation for Lorenz {
    fn n_states(&self) -> usize {
        3
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![1.0, 1.0, 1.0]
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        dy[0] = 10.0 * (y[1] - y[0]);
        dy[1] = y[0] * (28.0 - y[2]) - y[1];
        dy[2] = y[0] * y[1] - 8.0 / 3.0 * y[2];
        Ok(())
    }
}

fn tight() -> SolverOptions {
    match SolverOptions::default()
        .method(Method::Dop853)
        .rtol(1e-11)
        .atol(1e-14)
        .build()
    {
        Ok(o) => o,
        Err(e) => panic!("options: {e}"),
    }
}

fn estimate<F: Formulation + Clone>(
    case: &str,
    f: &F,
    y0: &[f64],
    o: &LyapunovOptions,
    s: &SolverOptions,
) -> LyapunovEstimate {
    match largest_lyapunov(f, 0.0, y0, o, s) {
        Ok(e) => {
            eprintln!(
                "{case}: λ = {:.6} ± {:.2e} (drift {:.2e}), {} steps",
                e.exponent, e.uncertainty, e.drift, e.stats.steps
            );
            e
        }
        Err(e) => panic!("{case}: {e}"),
    }
}

#[test]
fn damped_pendulum_exponent_is_minus_zeta_omega() {
    // Near θ = 0 the tangent dynamics are those of x'' + 2ζωx' + ω²x = 0, whose eigenvalues
    // −ζω ± iω√(1−ζ²) share the real part −ζω: both exponents are −ζω (their sum −2ζω is also
    // the trace of the Jacobian, exactly, for any θ). Over a run of length T the separation
    // ln(|Φ(T)v|/|v|) differs from −ζωT by at most ln κ(V), κ the condition number of the
    // eigenvector matrix (κ = √(2.2/1.8) ≈ 1.11 for ω = 1, ζ = 0.1, ln κ ≈ 0.1), so
    // |λ + ζω| ≤ 0.1/T = 1e-3 at T = 100 s. The nonlinearity (|θ| ≤ 0.1: sin θ = θ(1 − 1.7e-3))
    // and the integration add less than that; bound 2e-3.
    let f = Pendulum {
        omega: 1.0,
        zeta: 0.1,
        growth: None,
    };
    let o = LyapunovOptions {
        d0: 1e-9,
        tau: 1.0,
        n_intervals: 100,
        ..LyapunovOptions::default()
    };
    let e = estimate("damped pendulum", &f, &[0.1, 0.0], &o, &tight());
    assert!(
        (e.exponent + 0.1).abs() < 2e-3,
        "damped pendulum: λ = {} vs −ζω = −0.1 (bound 2e-3)",
        e.exponent
    );
    assert_eq!(e.history.len(), 100);
    assert!(
        (e.history[99].0 - 100.0).abs() < 1e-12,
        "history ends at t = {}",
        e.history[99].0
    );
}

#[test]
fn bookkeeping_states_are_neither_perturbed_nor_measured() {
    // An unstable extra state z' = 0.5 z: measured, it dominates (λ → 0.5); marked as
    // bookkeeping, it is excluded and the pendulum's −ζω is found as above. The run is short
    // (T = 25 s, z ≤ e^12.5 ≈ 3e5) and d0 = 1e-6 large enough that the separation in z stays
    // far above the rounding of z (ulp ≈ 6e-11).
    let f = Pendulum {
        omega: 1.0,
        zeta: 0.1,
        growth: Some(0.5),
    };
    let mut o = LyapunovOptions {
        d0: 1e-6,
        tau: 1.0,
        n_intervals: 25,
        ..LyapunovOptions::default()
    };
    let y0 = [0.1, 0.0, 1.0];
    let measured = estimate("with z measured", &f, &y0, &o, &tight());
    // The first interval turns the perturbation (equal parts in θ, θ', z) towards z, costing
    // at most ln √3 ≈ 0.55: |λ − 0.5| ≤ 0.55/T = 0.022.
    assert!(
        (measured.exponent - 0.5).abs() < 0.022,
        "z measured: λ = {} vs 0.5 (bound 0.022)",
        measured.exponent
    );
    o.bookkeeping = vec![false, false, true];
    let masked = estimate("with z bookkeeping", &f, &y0, &o, &tight());
    assert!(
        (masked.exponent + 0.1).abs() < 5e-3,
        "z bookkeeping: λ = {} vs −0.1 (bound 5e-3: ln κ/T = 0.1/25 as above, plus 1e-3)",
        masked.exponent
    );
}

/// |λ| for the undamped pendulum after `n` intervals of 1 s.
fn undamped(n: usize) -> f64 {
    let f = Pendulum {
        omega: 1.0,
        zeta: 0.0,
        growth: None,
    };
    let o = LyapunovOptions {
        d0: 1e-9,
        tau: 1.0,
        n_intervals: n,
        ..LyapunovOptions::default()
    };
    estimate(
        &format!("undamped pendulum, T = {n} s"),
        &f,
        &[1.0, 0.0],
        &o,
        &tight(),
    )
    .exponent
    .abs()
}

#[test]
fn undamped_pendulum_exponent_vanishes_with_run_length() {
    // An integrable one-degree-of-freedom system: the tangent map is periodic plus a shear
    // (the period depends on the amplitude), so separations grow at most linearly,
    // d(T) ≤ d0·C·(1 + T/T_p) with C = O(1), and |λ| ≤ ln(C(1 + T/T_p))/T. With C = 10 and
    // T_p ≈ 6.7 s (amplitude 1 rad) that is 0.05 at T = 100 s and 0.016 at T = 400 s.
    for (t, bound) in [(100, 0.05), (400, 0.016)] {
        let lambda = undamped(t);
        assert!(
            lambda < bound,
            "undamped pendulum, T = {t} s: |λ| = {lambda} (bound {bound})"
        );
    }
}

fn lorenz(n_intervals: usize) -> LyapunovEstimate {
    let o = LyapunovOptions {
        d0: 1e-8,
        tau: 0.5,
        n_intervals,
        t_transient: 20.0,
        ..LyapunovOptions::default()
    };
    let s = match SolverOptions::default().rtol(1e-10).atol(1e-12).build() {
        Ok(s) => s,
        Err(e) => panic!("{e}"),
    };
    estimate(
        &format!("Lorenz, {n_intervals} intervals"),
        &Lorenz,
        &[1.0, 1.0, 1.0],
        &o,
        &s,
    )
}

/// λ₁ of the Lorenz system, σ = 10, ρ = 28, β = 8/3 (Sprott 2003, Appendix A).
const LORENZ_LAMBDA: f64 = 0.9056;

#[test]
fn lorenz_largest_exponent() {
    // A run of T = 2000 s (4000 intervals of 0.5 s, ≈ 0.2 s of CPU): the local exponents
    // fluctuate by O(1) with correlation times ≈ 1 s, so the statistical error of the mean is
    // ≈ 1/√(2000) ≈ 0.02. Bound 0.05, and the batch-means uncertainty must cover the
    // difference within 4 of its own sizes (it is an estimate of the same statistical error).
    let e = lorenz(4000);
    let diff = (e.exponent - LORENZ_LAMBDA).abs();
    assert!(
        diff < 0.05,
        "Lorenz: λ = {} vs {LORENZ_LAMBDA} (bound 0.05)",
        e.exponent
    );
    assert!(
        diff < 4.0 * e.uncertainty + 0.01,
        "Lorenz: |λ − λ_ref| = {diff} not covered by the uncertainty {}",
        e.uncertainty
    );
    assert!(
        e.uncertainty > 0.0 && e.uncertainty < 0.05,
        "uncertainty {}",
        e.uncertainty
    );
}

#[test]
#[ignore = "long: T = 40 000 s of the Lorenz system (a few seconds)"]
fn lorenz_largest_exponent_long() {
    // Statistical error ≈ 1/√(40 000) ≈ 5e-3: bound 0.015.
    let e = lorenz(80_000);
    assert!(
        (e.exponent - LORENZ_LAMBDA).abs() < 0.015,
        "Lorenz (long): λ = {} vs {LORENZ_LAMBDA} (bound 0.015)",
        e.exponent
    );
}
