//! Kernels shared by the explicit Runge–Kutta methods: counted right-hand-side calls, stage
//! sums y + h Σ a_j k_j, and the error scale of Hairer's error norm.

use super::error::SolveError;
use crate::formulation::Formulation;

/// Buffers one step works in (all of length n, allocated once by the stepper).
pub(crate) struct StepBuffers<'a> {
    /// Stage derivatives; `k[0]` must hold f(t, y) on entry.
    pub k: &'a mut [Vec<f64>],
    /// Receives y_new.
    pub y_new: &'a mut [f64],
    /// Scratch for stage arguments.
    pub y_stage: &'a mut [f64],
}

/// Evaluates dy = f(t, y), counts the call in `evals` and attaches t to a failure.
pub(crate) fn eval_rhs<F: Formulation + ?Sized>(
    f: &F,
    t: f64,
    y: &[f64],
    dy: &mut [f64],
    evals: &mut u64,
) -> Result<(), SolveError> {
    *evals += 1;
    f.rhs(t, y, dy)
        .map_err(|source| SolveError::Formulation { t, source })
}

/// out = y + h Σ_j coeffs_j k_j. Zero coefficients are skipped (the DOP853 tableau is sparse).
pub(crate) fn combine(y: &[f64], h: f64, coeffs: &[f64], k: &[Vec<f64>], out: &mut [f64]) {
    out.copy_from_slice(y);
    for (&a, kj) in coeffs.iter().zip(k) {
        if a != 0.0 {
            let ha = h * a;
            for (o, &v) in out.iter_mut().zip(kj) {
                *o += ha * v;
            }
        }
    }
}

/// out = Σ_j coeffs_j k_j (zero coefficients skipped).
pub(crate) fn weighted_sum(coeffs: &[f64], k: &[Vec<f64>], out: &mut [f64]) {
    out.fill(0.0);
    for (&a, kj) in coeffs.iter().zip(k) {
        if a != 0.0 {
            for (o, &v) in out.iter_mut().zip(kj) {
                *o += a * v;
            }
        }
    }
}

/// err / sk, where sk = atol + rtol·max(|y_i|, |y_new_i|) is the error scale of component i.
/// With atol = 0 a component that is exactly zero has sk = 0: a zero error then counts as 0,
/// any other error as infinitely large (the step is rejected).
pub(crate) fn scaled(err: f64, y: f64, y_new: f64, rtol: f64, atol: f64) -> f64 {
    let sk = atol + rtol * y.abs().max(y_new.abs());
    if sk > 0.0 {
        err / sk
    } else if err == 0.0 {
        0.0
    } else {
        f64::INFINITY
    }
}

/// Index of the first NaN or infinite entry.
pub(crate) fn first_non_finite(v: &[f64]) -> Option<usize> {
    v.iter().position(|x| !x.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn combine_adds_weighted_stages() {
        let k = vec![vec![1.0, 2.0], vec![10.0, 20.0], vec![100.0, 200.0]];
        let mut out = [0.0; 2];
        combine(&[1.0, 1.0], 0.5, &[1.0, 0.0, 2.0], &k, &mut out);
        assert_eq!(out, [1.0 + 0.5 + 100.0, 1.0 + 1.0 + 200.0]);
        weighted_sum(&[1.0, 0.0, 2.0], &k, &mut out);
        assert_eq!(out, [201.0, 402.0]);
    }

    #[test]
    fn scale_handles_zero_tolerance() {
        assert_eq!(scaled(1e-9, 1.0, -2.0, 1e-6, 1e-9), 1e-9 / (1e-9 + 2e-6));
        assert_eq!(scaled(0.0, 0.0, 0.0, 1e-6, 0.0), 0.0);
        assert_eq!(scaled(1e-30, 0.0, 0.0, 1e-6, 0.0), f64::INFINITY);
        assert_eq!(first_non_finite(&[1.0, f64::NAN]), Some(1));
        assert_eq!(first_non_finite(&[1.0]), None);
    }
}
