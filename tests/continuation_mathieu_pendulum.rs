//! A parametrically excited pendulum, θ'' + (a − 2q cos 2t) sin θ = 0 (the pendulum whose
//! pivot oscillates vertically, in the time scale where the forcing has period π): its hanging
//! rest state θ = 0 is a periodic orbit for every a, and its Floquet multipliers are those of
//! the linearisation, Mathieu's equation y'' + (a − 2q cos 2t) y = 0. The rest state loses
//! stability by a period doubling (a multiplier through −1: the pendulum starts swinging at
//! half the forcing frequency) where a crosses the characteristic value a₁(q) or b₁(q)
//! (solutions of period 2π, ce₁ and se₁), and through +1 at a₀(q) (period π, ce₀).
//!
//! Published values, q = 5 (M. Abramowitz and I. A. Stegun, *Handbook of Mathematical
//! Functions*, NBS, 1964, Table 20.1, "Characteristic values, joining factors, some critical
//! values"): a₀ = −5.80004602, b₁ = −5.79008060, a₁ = 1.85818754. (Checked here by the
//! three-term recurrence of the Fourier coefficients, A&S 20.2.5–20.2.11, as a continued
//! fraction: −5.800046021, −5.790080599, 1.858187542.)
//!
//! Continued in a, the located period doublings and the fold must be within 1e-4 relative of
//! these (the bound). Measured (rtol 1e-11, DOP853): a₁ at 1.8581874150 (7e-8
//! relative), b₁ at −5.7900805976 (4e-10), a₀ at −5.8000460290 (1.5e-9).
//! The system is conservative: its multipliers sit on the unit circle between the tongues,
//! which must not read as Neimark–Sacker points.
//!
//! The rest state needs a bounded step (`max_step` below): the monodromy's variational
//! equations ride on the steps the state takes, and a state at rest takes any step.

mod common;

use common::branch::specials;
use linkdyn::analysis::AnalysisError;
use linkdyn::analysis::orbit::{
    Branch, BranchEnd, ContinuationOptions, OrbitAt, OrbitFamily, SpecialKind, continue_orbit,
};
use linkdyn::formulation::{Formulation, FormulationError, NoStepHooks};
use linkdyn::solve::{Method, SolverOptions};

const Q: f64 = 5.0;
const A0: f64 = -5.800_046_02;
const B1: f64 = -5.790_080_60;
const A1: f64 = 1.858_187_54;

#[derive(Clone)]
struct Pendulum {
    a: f64,
}
impl NoStepHooks for Pendulum {}
impl Formulation for Pendulum {
    fn n_states(&self) -> usize {
        2
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![0.0, 0.0]
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        dy[0] = y[1];
        dy[1] = -(self.a - 2.0 * Q * (2.0 * t).cos()) * y[0].sin();
        Ok(())
    }
    fn jacobian(
        &self,
        t: f64,
        y: &[f64],
        _f_y: &[f64],
        out: &mut [f64],
        _work: &mut [f64],
    ) -> Result<usize, FormulationError> {
        let k = -(self.a - 2.0 * Q * (2.0 * t).cos()) * y[0].cos();
        out.copy_from_slice(&[0.0, 1.0, k, 0.0]);
        Ok(0)
    }
    /// The variational equations are not under error control (the steps are the state's),
    /// and at rest the state has no error to control: without a bound, one step would span
    /// the period and the monodromy would be that of one Runge–Kutta step.
    fn max_step(&self, _t: f64, _y: &[f64]) -> f64 {
        MAX_STEP
    }
}

/// π/600: DOP853's local error on Φ' = JΦ, |J| ≤ √15, is then ~(h|J|)⁹ ≈ 1e-14 per step.
const MAX_STEP: f64 = std::f64::consts::PI / 600.0;

struct InA;
impl OrbitFamily for InA {
    type F = Pendulum;
    fn at(&self, a: f64) -> Result<OrbitAt<Pendulum>, AnalysisError> {
        Ok(OrbitAt {
            f: Pendulum { a },
            t0: 0.0,
            period: std::f64::consts::PI,
        })
    }
}

fn branch(from: f64, to: f64, step: f64) -> Branch {
    let solver = SolverOptions::default()
        .method(Method::Dop853)
        .rtol(1e-11)
        .atol(1e-13);
    continue_orbit(
        &InA,
        &[0.0, 0.0],
        &ContinuationOptions::new(from, to, step),
        &solver,
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

fn assert_near(got: f64, published: f64, what: &str) {
    let rel = ((got - published) / published).abs();
    assert!(
        rel < 1e-4,
        "{what}: located at a = {got}, published {published} (relative {rel:.1e})"
    );
}

#[test]
fn the_first_period_doubling_is_at_a1_of_q_5() {
    // From the stable band a₁ < a < b₂ (b₂(5) = 2.09946045) into the first tongue.
    let b = branch(2.05, 1.7, 0.05);
    assert_eq!(b.end, BranchEnd::Reached);
    assert!(b.unlocated.is_empty(), "{:?}", b.unlocated);
    let found = specials(&b);
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].0, SpecialKind::PeriodDoubling, "{found:?}");
    assert_near(found[0].1, A1, "period doubling at a₁(5)");
    // θ = 0 at every point (the rest state is exact), and the multipliers' product is 1
    // (Liouville: the system is conservative).
    for p in &b.points {
        assert!(p.y0.iter().all(|y| *y == 0.0), "{p:?}");
        let det = p.multipliers.iter().fold((1.0, 0.0), |(re, im), z| {
            (re * z[0] - im * z[1], re * z[1] + im * z[0])
        });
        assert!(
            (det.0 - 1.0).abs() < 1e-7 && det.1.abs() < 1e-7,
            "a = {}: det M = {det:?}",
            p.parameter
        );
    }
}

#[test]
fn the_tongue_ends_at_b1_and_the_rest_state_folds_at_a0() {
    // Across the narrow stable band a₀ < a < b₁ (width 0.00996) at q = 5.
    let b = branch(-5.78, -5.81, 0.002);
    assert_eq!(b.end, BranchEnd::Reached);
    let found = specials(&b);
    assert_eq!(found.len(), 2, "{found:?}");
    assert_eq!(found[0].0, SpecialKind::PeriodDoubling, "{found:?}");
    assert_near(found[0].1, B1, "period doubling at b₁(5)");
    assert_eq!(found[1].0, SpecialKind::Fold, "{found:?}");
    assert_near(found[1].1, A0, "multiplier +1 at a₀(5)");
}
