//! Radau IIA (order 5) on three stiff problems with known answers: a linear system with
//! eigenvalues −1 and −10⁶ (closed form), Van der Pol with ε = 10⁻⁶ (Hairer's published
//! reference at t = 2) and Robertson's chemical kinetics (published values at t = 40, and the
//! conservation law y₁ + y₂ + y₃ = 1). Radau5 runs through the common driver (`Stepper`,
//! `Method::Radau5`).

use linkdyn::formulation::{Formulation, FormulationError, NoStepHooks};
use linkdyn::solve::{Method, SolveError, SolverOptions, SolverStats, Stepper, Stop};

/// Radau5 options at (rtol, atol), Hairer's default settings.
fn radau5(rtol: f64, atol: f64) -> Result<SolverOptions, SolveError> {
    SolverOptions::default()
        .method(Method::Radau5)
        .rtol(rtol)
        .atol(atol)
        .build()
}

fn run<F: Formulation>(f: &mut F, t_end: f64, rtol: f64, atol: f64) -> (Vec<f64>, SolverStats) {
    let result = radau5(rtol, atol).and_then(|opts| {
        let y0 = f.initial_state();
        let mut r = Stepper::new(f, 0.0, &y0, t_end, &opts)?;
        while r.step()? != Stop::EndReached {}
        assert_eq!(r.t(), t_end, "the run ends exactly on t_end");
        Ok((r.y().to_vec(), r.stats().clone()))
    });
    result.unwrap_or_else(|e| panic!("{e}"))
}

/// y' = A y with A = [[a, b], [b, a]], a = −(1 + 10⁶)/2, b = (10⁶ − 1)/2: eigenvalues −1
/// (eigenvector (1, 1)) and −10⁶ (eigenvector (1, −1)). From y(0) = (2, 0):
/// y(t) = e^{−t}(1, 1) + e^{−10⁶ t}(1, −1).
struct LinearStiff {
    analytic_jacobian: bool,
}
const LAMBDA_FAST: f64 = 1e6;
impl LinearStiff {
    fn coefficients() -> (f64, f64) {
        (-(1.0 + LAMBDA_FAST) / 2.0, (LAMBDA_FAST - 1.0) / 2.0)
    }
    fn exact(t: f64) -> [f64; 2] {
        let (slow, fast) = ((-t).exp(), (-LAMBDA_FAST * t).exp());
        [slow + fast, slow - fast]
    }
}
impl NoStepHooks for LinearStiff {}

impl Formulation for LinearStiff {
    fn n_states(&self) -> usize {
        2
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![2.0, 0.0]
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        let (a, b) = Self::coefficients();
        dy[0] = a * y[0] + b * y[1];
        dy[1] = b * y[0] + a * y[1];
        Ok(())
    }
    fn jacobian(
        &self,
        t: f64,
        y: &[f64],
        f_y: &[f64],
        out: &mut [f64],
        work: &mut [f64],
    ) -> Result<usize, FormulationError> {
        if !self.analytic_jacobian {
            return linkdyn::formulation::jacobian::finite_difference(self, t, y, f_y, out, work);
        }
        let (a, b) = Self::coefficients();
        out.copy_from_slice(&[a, b, b, a]);
        Ok(0)
    }
}

#[test]
fn linear_stiff_system_matches_the_closed_form() {
    let t_end = 10.0;
    let exact = LinearStiff::exact(t_end);
    for analytic_jacobian in [false, true] {
        let mut f = LinearStiff { analytic_jacobian };
        let (y, stats) = run(&mut f, t_end, 1e-10, 1e-12);
        for i in 0..2 {
            // Local errors ≲ rtol·|y| are damped like the slow mode afterwards, so at t = 10
            // the global error is ≲ steps·rtol·|y(10)| ≈ 300·1e-10·4.5e-5 ≈ 1.4e-12 (measured
            // 3e-13); 1e-11 leaves a margin for a different step sequence.
            assert!(
                (y[i] - exact[i]).abs() < 1e-11,
                "analytic J = {analytic_jacobian}: y{i}(10) = {} vs exact {}",
                y[i],
                exact[i]
            );
        }
        // An explicit method would need h < 3/10⁶ (≥ 3·10⁶ steps); L-stability lets Radau
        // step on the slow time scale once the fast transient (τ = 1 µs) has decayed.
        assert!(
            stats.steps < 500,
            "analytic J = {analytic_jacobian}: {} steps",
            stats.steps
        );
        // Every rejection has exactly one recorded cause.
        assert_eq!(
            stats.rejected,
            stats.error_test_failures + stats.newton_failures + stats.recovered_rejections,
            "{stats:?}"
        );
        // Forward differences cost n = 2 RHS calls per Jacobian; the analytic one none.
        let per_jac = if analytic_jacobian { 0 } else { 2 };
        assert_eq!(
            stats.jacobian_rhs_evals,
            per_jac * stats.jacobian_evals,
            "{stats:?}"
        );
        // f(t0), 3 per Newton iteration, 1 per accepted step, ≤ 1 per error estimate, and the
        // Jacobian's: the remainder are the second filterings of the error estimate.
        let accounted = 1 + 3 * stats.newton_iterations + stats.steps + stats.jacobian_rhs_evals;
        assert!(
            stats.rhs_evals >= accounted && stats.rhs_evals <= accounted + stats.rejected + 1,
            "rhs_evals = {} vs accounted {accounted}: {stats:?}",
            stats.rhs_evals
        );
    }
}

/// Van der Pol in Hairer's scaling: y₁' = y₂, y₂' = ((1 − y₁²) y₂ − y₁)/ε, ε = 10⁻⁶,
/// y(0) = (2, 0), t ∈ [0, 2] (the `vdpol` problem of Hairer's stiff test set).
struct VanDerPol;
const EPS: f64 = 1e-6;
impl NoStepHooks for VanDerPol {}

impl Formulation for VanDerPol {
    fn n_states(&self) -> usize {
        2
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![2.0, 0.0]
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        dy[0] = y[1];
        dy[1] = ((1.0 - y[0] * y[0]) * y[1] - y[0]) / EPS;
        Ok(())
    }
}

/// Published y(2) of `vdpol` (E. Hairer, test set for stiff problems, file `res_exact_pic`,
/// http://www.unige.ch/~hairer/testset/stiff/vdpol/; computed with RADAU5 in quadruple
/// precision).
const VDP_AT_2: [f64; 2] = [1.706_167_732_170_456, -0.892_809_701_024_825_7];

#[test]
fn van_der_pol_matches_the_tight_reference_and_the_published_value() {
    let (reference, _) = run(&mut VanDerPol, 2.0, 1e-13, 1e-13);
    for i in 0..2 {
        // At rtol = 1e-13 our own reference agrees with the published one to ~2e-13
        // (measured); 1e-11 allows 100 times the tolerance for the 7 000 steps' rounding.
        assert!(
            (reference[i] - VDP_AT_2[i]).abs() < 1e-11,
            "rtol 1e-13: y{i}(2) = {} vs published {}",
            reference[i],
            VDP_AT_2[i]
        );
    }
    let mut previous_error = f64::INFINITY;
    for rtol in [1e-5, 1e-7, 1e-9] {
        let (y, stats) = run(&mut VanDerPol, 2.0, rtol, rtol);
        let error = (0..2)
            .map(|i| (y[i] - reference[i]).abs())
            .fold(0.0, f64::max);
        // Hairer's tolerance transform (rtol' = 0.1·rtol^{2/3}) is designed so that the
        // global error is about rtol; measured 0.05–0.35·rtol for rtol = 1e-5 … 1e-9.
        assert!(
            error < rtol,
            "rtol {rtol:e}: max error {error:e} vs bound {rtol:e} ({stats:?})"
        );
        assert!(
            error < previous_error,
            "rtol {rtol:e}: error {error:e} did not drop below {previous_error:e}"
        );
        previous_error = error;
        // An explicit method needs h ≲ 2ε near the slow manifold (≥ 10⁶ steps over [0, 2]).
        assert!(stats.steps < 5_000, "rtol {rtol:e}: {} steps", stats.steps);
    }
}

/// Robertson's chemical kinetics: y₁' = −0.04 y₁ + 10⁴ y₂ y₃, y₂' = 0.04 y₁ − 10⁴ y₂ y₃ −
/// 3·10⁷ y₂², y₃' = 3·10⁷ y₂², y(0) = (1, 0, 0).
struct Robertson;
impl NoStepHooks for Robertson {}

impl Formulation for Robertson {
    fn n_states(&self) -> usize {
        3
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![1.0, 0.0, 0.0]
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        let r1 = 0.04 * y[0];
        let r2 = 1e4 * y[1] * y[2];
        let r3 = 3e7 * y[1] * y[1];
        dy[0] = -r1 + r2;
        dy[1] = r1 - r2 - r3;
        dy[2] = r3;
        Ok(())
    }
}

/// y(40) of Robertson's problem (Hairer & Wanner, *Solving ODEs II*, Sec. IV.1 and IV.10;
/// the same digits in the SUNDIALS `cvRoberts_dns` example).
const ROBERTSON_AT_40: [f64; 3] = [
    0.715_827_068_719_4,
    9.185_534_764_56e-6,
    0.284_163_745_745_8,
];

#[test]
fn robertson_conserves_mass_and_matches_the_published_values() -> Result<(), SolveError> {
    let mut f = Robertson;
    let opts = radau5(1e-9, 1e-14)?;
    let mut r = Stepper::new(&mut f, 0.0, &[1.0, 0.0, 0.0], 40.0, &opts)?;
    let mut worst_defect: f64 = 0.0;
    loop {
        let stop = r.step()?;
        let y = r.y();
        worst_defect = worst_defect.max((y[0] + y[1] + y[2] - 1.0).abs());
        if stop == Stop::EndReached {
            break;
        }
    }
    // e^T f = 0 and, with forward differences, e^T J = 0 up to rounding: each simplified
    // Newton correction keeps Σ Z_i = 0, so the sum moves only by rounding, a few ulps per
    // step (≈ 150 steps here; measured 3e-16). 1e-14 is ~50 ulps of 1.
    assert!(
        worst_defect < 1e-14,
        "|y1 + y2 + y3 − 1| reached {worst_defect:e}"
    );
    let y = r.y();
    for i in 0..3 {
        // rtol = 1e-9 aims at a global error ~1e-9 relative (measured 3e-11); y2 ~ 1e-5 is
        // resolved by atol = 1e-14 (1e-9 relative). The published values carry 13 digits.
        let rel = (y[i] - ROBERTSON_AT_40[i]).abs() / ROBERTSON_AT_40[i];
        assert!(
            rel < 1e-9,
            "y{i}(40) = {:e} vs published {:e} (relative {rel:e})",
            y[i],
            ROBERTSON_AT_40[i]
        );
    }
    Ok(())
}
