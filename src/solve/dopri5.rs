//! DOPRI5: the Dormand–Prince 5(4) pair \[1\] with FSAL and Hairer's 4th-order continuous
//! extension \[2, Sec. II.6, code `dopri5.f`\].
//!
//! One step from (t, y) with size h, stages k_1 = f(t, y) (the FSAL stage of the previous step)
//! and k_i = f(t + c_i h, y + h Σ_{j<i} a_ij k_j), i = 2..7:
//!
//! * y_new = y + h Σ b_i k_i (5th order; b = row 7 of a, so k_7 = f(t + h, y_new) is the next
//!   step's k_1);
//! * error estimate err = h Σ e_i k_i with e = b − b̂, b̂ the 4th-order weights;
//! * dense output on θ = (t* − t)/h ∈ [0, 1] (Hairer's `contd5`):
//!   y(θ) = y + θ (r₁ + (1 − θ)(r₂ + θ (r₃ + (1 − θ) r₄))) with r₁ = y_new − y,
//!   r₂ = h k_1 − r₁, r₃ = r₁ − h k_7 − r₂, r₄ = h Σ d_i k_i — no extra RHS call.
//!
//! Indices below are 0-based (stage i of the papers is `k[i - 1]`).
//!
//! # References
//! 1. J. R. Dormand, P. J. Prince, "A family of embedded Runge–Kutta formulae", *J. Comput.
//!    Appl. Math.* 6(1), 19–26, 1980 (Table 2).
//! 2. E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary Differential Equations I*, 2nd ed.,
//!    Springer, 1993, Sec. II.5 (Table 5.2) and II.6 (dense output).
//! 3. L. F. Shampine, "Some practical Runge–Kutta formulas", *Math. Comp.* 46(173), 135–150,
//!    1986 (the same continuous extension; SciPy's `RK45.P` is its power form).

use super::control::ControlParams;
use super::error::SolveError;
use super::explicit::{DenseInput, Pair};
use super::integrator::{ErrorWeights, Trial};
use super::options::Method;
use super::rk::{StepBuffers, combine, eval_rhs, weighted_sum};
use super::stats::SolverStats;
use crate::formulation::Formulation;

/// The DOPRI5 pair (a marker for [`ExplicitRk`](super::explicit::ExplicitRk)).
pub(crate) struct Dopri5;

impl Pair for Dopri5 {
    const METHOD: Method = Method::Dopri5;
    const STAGES: usize = STAGES;
    const FSAL: usize = FSAL;
    const LAST_STAGE: usize = FSAL - 1;
    const DENSE_VECTORS: usize = DENSE_VECTORS;
    const CONTROL: ControlParams = ControlParams {
        q: 5.0,
        kappa: 0.75,
        fac_min: 0.2,
        fac_max: 10.0,
    };
    /// Hairer's `dopri5.f` (hλ > 3.25).
    const STABILITY_BOUNDARY: f64 = 3.25;

    fn stages<F: Formulation + ?Sized>(
        f: &F,
        trial: &Trial<'_>,
        buf: StepBuffers<'_>,
        evals: &mut u64,
    ) -> Result<(), SolveError> {
        step(f, trial.t, trial.h, trial.t_new, trial.y, buf, evals)
    }

    fn error_norm(
        h: f64,
        y: &[f64],
        y_new: &[f64],
        k: &[Vec<f64>],
        weights: &ErrorWeights,
        scratch: (&mut [f64], &mut [f64]),
    ) -> f64 {
        error_norm(h, y, y_new, k, weights, scratch.0)
    }

    fn prepare_dense<F: Formulation + ?Sized>(
        _f: &F,
        step: &DenseInput<'_>,
        k: &mut [Vec<f64>],
        dense: &mut [Vec<f64>],
        _y_stage: &mut [f64],
        _stats: &mut SolverStats,
    ) -> Result<(), SolveError> {
        prepare_dense(step.h, step.y_old, step.y_new, k, dense);
        Ok(())
    }

    fn eval_dense(theta: f64, y_old: &[f64], dense: &[Vec<f64>], out: &mut [f64]) {
        eval_dense(theta, y_old, dense, out);
    }
}

/// Stage vectors kept per step: 7 (k_7 is the FSAL stage).
pub(crate) const STAGES: usize = 7;
/// Index of the FSAL stage k_7 = f(t + h, y_new).
pub(crate) const FSAL: usize = 6;
/// Vectors r₁..r₄ of the dense output.
pub(crate) const DENSE_VECTORS: usize = 4;

/// Nodes c_i.
pub(crate) const C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];

/// Coupling coefficients a_ij, row i holding a_i0 .. a_i(i−1). Row 6 is b.
pub(crate) const A: [&[f64]; 7] = [
    &[],
    &[1.0 / 5.0],
    &[3.0 / 40.0, 9.0 / 40.0],
    &[44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0],
    &[
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
    ],
    &[
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
    ],
    &[
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];

/// Weights b_i of the 5th-order solution (row 6 of [`A`]).
pub(crate) const B: &[f64] = A[6];

/// Error coefficients e_i = b_i − b̂_i (b̂ the 4th-order weights, with b̂_7 = 1/40 on the FSAL
/// stage), as in Hairer's `dopri5.f` (`e1`..`e7`).
pub(crate) const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// Dense-output coefficients d_i of r₄ (Hairer's `d1`..`d7`; `d2` = 0).
pub(crate) const D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// Computes stages 2..7 and y_new of one step of size h from (t, y); t_new = t + h is passed
/// separately so that the last step of a run lands exactly on t_end.
pub(crate) fn step<F: Formulation + ?Sized>(
    f: &F,
    t: f64,
    h: f64,
    t_new: f64,
    y: &[f64],
    buf: StepBuffers<'_>,
    evals: &mut u64,
) -> Result<(), SolveError> {
    let StepBuffers { k, y_new, y_stage } = buf;
    for s in 1..FSAL {
        let (done, rest) = k.split_at_mut(s);
        combine(y, h, A[s], done, y_stage);
        if let Some(ks) = rest.first_mut() {
            eval_rhs(f, t + C[s] * h, y_stage, ks, evals)?;
        }
    }
    let (done, rest) = k.split_at_mut(FSAL);
    combine(y, h, B, done, y_new);
    if let Some(k7) = rest.first_mut() {
        eval_rhs(f, t_new, y_new, k7, evals)?;
    }
    Ok(())
}

/// Hairer's error norm: sqrt(1/m Σ_i (err_i / sk_i)²) over the m error-controlled components,
/// with err = h Σ e_j k_j and sk_i = atol + rtol·max(|y_i|, |y_new_i|). `scratch` has length n.
pub(crate) fn error_norm(
    h: f64,
    y: &[f64],
    y_new: &[f64],
    k: &[Vec<f64>],
    weights: &ErrorWeights,
    scratch: &mut [f64],
) -> f64 {
    if weights.is_empty() {
        return 0.0;
    }
    weighted_sum(&E, k, scratch);
    (weights.sum_of_squares_of(h, scratch, y, y_new) / weights.len() as f64).sqrt()
}

/// Fills the dense-output vectors r₁..r₄ of a step of size h from y_old to y_new.
pub(crate) fn prepare_dense(
    h: f64,
    y_old: &[f64],
    y_new: &[f64],
    k: &[Vec<f64>],
    dense: &mut [Vec<f64>],
) {
    let [r1, r2, r3, r4, ..] = dense else {
        debug_assert!(false, "dense output needs {DENSE_VECTORS} vectors");
        return;
    };
    let (Some(k1), Some(k7)) = (k.first(), k.get(FSAL)) else {
        debug_assert!(false, "dense output needs {STAGES} stages");
        return;
    };
    weighted_sum(&D, k, r4);
    for i in 0..y_old.len() {
        let dy = y_new[i] - y_old[i];
        let bspl = h * k1[i] - dy;
        r1[i] = dy;
        r2[i] = bspl;
        r3[i] = dy - h * k7[i] - bspl;
        r4[i] *= h;
    }
}

/// Evaluates the dense output at θ = (t* − t_old)/h into `out`.
pub(crate) fn eval_dense(theta: f64, y_old: &[f64], dense: &[Vec<f64>], out: &mut [f64]) {
    let [r1, r2, r3, r4, ..] = dense else {
        debug_assert!(false, "dense output needs {DENSE_VECTORS} vectors");
        return;
    };
    let theta1 = 1.0 - theta;
    for (i, o) in out.iter_mut().enumerate() {
        *o = y_old[i] + theta * (r1[i] + theta1 * (r2[i] + theta * (r3[i] + theta1 * r4[i])));
    }
}

#[cfg(test)]
mod tests {
    use super::super::order_conditions::{Tableau, continuous_weights, max_defect};
    use super::*;

    fn tableau() -> Tableau {
        Tableau::new(&A, STAGES)
    }

    #[test]
    fn rows_sum_to_nodes() {
        for (i, row) in A.iter().enumerate() {
            let sum: f64 = row.iter().sum();
            assert!(
                (sum - C[i]).abs() < 1e-15,
                "row {i}: Σa = {sum}, c = {}",
                C[i]
            );
        }
    }

    #[test]
    fn weights_have_order_5_and_embedded_order_4() {
        let t = tableau();
        let b: Vec<f64> = B.iter().copied().chain([0.0]).collect();
        // Rounding of the rational coefficients to f64 leaves defects of a few ulps.
        assert!(
            max_defect(&t, &b, 5) < 1e-15,
            "order 5: {}",
            max_defect(&t, &b, 5)
        );
        assert!(max_defect(&t, &b, 6) > 1e-6, "DOPRI5 is not of order 6");
        let b_hat: Vec<f64> = b.iter().zip(E).map(|(b, e)| b - e).collect();
        assert!(max_defect(&t, &b_hat, 4) < 1e-15, "embedded order 4");
        assert!(
            max_defect(&t, &b_hat, 5) > 1e-6,
            "embedded method is not of order 5"
        );
    }

    #[test]
    fn dense_output_has_order_4() {
        let t = tableau();
        for theta in [0.1, 0.37, 0.5, 0.83, 1.0] {
            let w = continuous_weights(STAGES, |k, out| {
                let n = STAGES;
                let y_old = vec![0.0; n];
                let mut y_new = vec![0.0; n];
                combine(&y_old, 1.0, B, k, &mut y_new);
                let mut dense = vec![vec![0.0; n]; DENSE_VECTORS];
                prepare_dense(1.0, &y_old, &y_new, k, &mut dense);
                eval_dense(theta, &y_old, &dense, out);
            });
            let d = t.max_continuous_defect(&w, theta, 4);
            assert!(d < 1e-14, "θ = {theta}: order-4 defect {d}");
        }
    }

    #[test]
    fn dense_output_matches_the_step_ends() {
        let n = 3;
        let k: Vec<Vec<f64>> = (0..STAGES)
            .map(|j| (0..n).map(|i| ((i + 2 * j) as f64).sin()).collect())
            .collect();
        let y_old = [1.0, -2.0, 0.5];
        let h = 0.3;
        let mut y_new = [0.0; 3];
        combine(&y_old, h, B, &k, &mut y_new);
        let mut dense = vec![vec![0.0; n]; DENSE_VECTORS];
        prepare_dense(h, &y_old, &y_new, &k, &mut dense);
        let mut out = [0.0; 3];
        eval_dense(0.0, &y_old, &dense, &mut out);
        assert_eq!(out, y_old);
        eval_dense(1.0, &y_old, &dense, &mut out);
        for i in 0..n {
            assert!((out[i] - y_new[i]).abs() < 1e-15, "θ = 1, component {i}");
        }
    }

    /// Hairer's form equals SciPy's power form y_old + h Σ_j k_j Σ_m P_jm θ^{m+1}
    /// (`RK45.P` in `scipy/integrate/_ivp/rk.py`).
    #[test]
    fn dense_output_equals_scipy_power_form() {
        const P: [[f64; 4]; 7] = [
            [
                1.0,
                -8048581381.0 / 2820520608.0,
                8663915743.0 / 2820520608.0,
                -12715105075.0 / 11282082432.0,
            ],
            [0.0, 0.0, 0.0, 0.0],
            [
                0.0,
                131558114200.0 / 32700410799.0,
                -68118460800.0 / 10900136933.0,
                87487479700.0 / 32700410799.0,
            ],
            [
                0.0,
                -1754552775.0 / 470086768.0,
                14199869525.0 / 1410260304.0,
                -10690763975.0 / 1880347072.0,
            ],
            [
                0.0,
                127303824393.0 / 49829197408.0,
                -318862633887.0 / 49829197408.0,
                701980252875.0 / 199316789632.0,
            ],
            [
                0.0,
                -282668133.0 / 205662961.0,
                2019193451.0 / 616988883.0,
                -1453857185.0 / 822651844.0,
            ],
            [
                0.0,
                40617522.0 / 29380423.0,
                -110615467.0 / 29380423.0,
                69997945.0 / 29380423.0,
            ],
        ];
        let n = 2;
        let k: Vec<Vec<f64>> = (0..STAGES)
            .map(|j| (0..n).map(|i| ((3 * i + j) as f64).cos()).collect())
            .collect();
        let (h, y_old) = (0.7, [0.3, -1.1]);
        let mut y_new = [0.0; 2];
        combine(&y_old, h, B, &k, &mut y_new);
        let mut dense = vec![vec![0.0; n]; DENSE_VECTORS];
        prepare_dense(h, &y_old, &y_new, &k, &mut dense);
        for theta in [0.2f64, 0.6, 0.95] {
            let mut out = [0.0; 2];
            eval_dense(theta, &y_old, &dense, &mut out);
            for i in 0..n {
                let mut s = 0.0;
                for (j, row) in P.iter().enumerate() {
                    for (m, p) in row.iter().enumerate() {
                        s += k[j][i] * p * theta.powi(m as i32 + 1);
                    }
                }
                let scipy = y_old[i] + h * s;
                assert!(
                    (out[i] - scipy).abs() < 1e-14,
                    "θ = {theta}: {} vs {scipy}",
                    out[i]
                );
            }
        }
    }
}
