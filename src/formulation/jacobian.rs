//! Forward-difference Jacobian J = ∂f/∂y of a [`Formulation`]'s right-hand side: the default of
//! [`Formulation::jacobian`], used by the implicit integrator (`solve::radau5`).
//!
//! Column j is (f(t, y + δ_j e_j) − f(t, y)) / δ_j with Hairer's increment \[1, code `radau5.f`,
//! "compute Jacobian matrix numerically"\]
//!
//! δ_j = √(u · max(10⁻⁵, |y_j|)),  u = 10⁻¹⁶ (unit roundoff),
//!
//! i.e. about √u·|y_j|^{1/2}: for |y_j| ≈ 1 the truncation error O(δ |f''|) and the rounding
//! error O(u |f| / δ) are balanced at δ ≈ √u, and the floor 10⁻⁵ keeps δ_j ≥ 3·10⁻¹¹ for
//! components that start at zero (velocities at rest). δ_j is then rounded to the representable
//! difference (y_j + δ_j) − y_j, so the quotient divides by the step actually taken.
//!
//! # References
//! 1. E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II: Stiff and
//!    Differential-Algebraic Problems*, 2nd ed., Springer, 1996, Sec. IV.8; code `radau5.f`.

use super::{Formulation, FormulationError};

/// Unit roundoff used for the increment (Hairer's `UROUND`).
const UROUND: f64 = 1e-16;

/// Increment δ for a component of value `y` (see the module doc), before rounding.
#[must_use]
pub fn increment(y: f64) -> f64 {
    (UROUND * y.abs().max(1e-5)).sqrt()
}

/// Writes the forward-difference Jacobian of `f` at (t, y) into `out`, **row-major**:
/// `out[i * n + j]` = ∂f_i/∂y_j. `f_y` must hold f(t, y); `work` is scratch of length ≥ 2n.
/// Returns the number of RHS calls made (n).
///
/// # Errors
/// A failed RHS evaluation (passed on), or buffers of the wrong length
/// ([`FormulationError::Unsupported`], naming the buffer).
pub fn finite_difference<F: Formulation + ?Sized>(
    f: &F,
    t: f64,
    y: &[f64],
    f_y: &[f64],
    out: &mut [f64],
    work: &mut [f64],
) -> Result<usize, FormulationError> {
    let n = y.len();
    if f_y.len() != n || out.len() != n * n || work.len() < 2 * n {
        return Err(FormulationError::Unsupported {
            formulation: "finite-difference Jacobian".into(),
            reason: format!(
                "buffers for n = {n} states must be f_y: {n}, out: {}, work: ≥ {}; got {}, {}, {}",
                n * n,
                2 * n,
                f_y.len(),
                out.len(),
                work.len()
            ),
        });
    }
    let (y_pert, rest) = work.split_at_mut(n);
    let f_pert = &mut rest[..n];
    y_pert.copy_from_slice(y);
    for j in 0..n {
        let y_j = y[j];
        let delta = (y_j + increment(y_j)) - y_j;
        y_pert[j] = y_j + delta;
        let result = f.rhs(t, y_pert, f_pert);
        y_pert[j] = y_j;
        result?;
        for i in 0..n {
            out[i * n + j] = (f_pert[i] - f_y[i]) / delta;
        }
    }
    Ok(n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formulation::NoStepHooks;

    /// f = (y0² y1, sin y0 + e^{y1}, 3 y2 − y0 y1): a dense, nonlinear Jacobian.
    struct Nonlinear;
    impl NoStepHooks for Nonlinear {}

    impl Formulation for Nonlinear {
        fn n_states(&self) -> usize {
            3
        }
        fn initial_state(&self) -> Vec<f64> {
            vec![0.7, -1.3, 2.0]
        }
        fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
            dy[0] = y[0] * y[0] * y[1];
            dy[1] = y[0].sin() + y[1].exp();
            dy[2] = 3.0 * y[2] - y[0] * y[1];
            Ok(())
        }
    }

    #[test]
    fn matches_the_analytic_jacobian() -> Result<(), FormulationError> {
        let f = Nonlinear;
        let y = f.initial_state();
        let mut f_y = [0.0; 3];
        f.rhs(0.0, &y, &mut f_y)?;
        let mut jac = [0.0; 9];
        let mut work = [0.0; 6];
        let calls = f.jacobian(0.0, &y, &f_y, &mut jac, &mut work)?;
        assert_eq!(calls, 3, "one RHS call per column");
        let exact = [
            2.0 * y[0] * y[1],
            y[0] * y[0],
            0.0,
            y[0].cos(),
            y[1].exp(),
            0.0,
            -y[1],
            -y[0],
            3.0,
        ];
        for (k, (a, b)) in jac.iter().zip(exact).enumerate() {
            // Forward differences: truncation δ·|f''|/2 with δ ≈ 1e-8, plus rounding
            // u·|f|/δ ≈ 1e-8; entries are O(1), so 1e-6 leaves a margin of ~50.
            assert!(
                (a - b).abs() < 1e-6 * (1.0 + b.abs()),
                "entry ({}, {}): finite difference {a} vs analytic {b}",
                k / 3,
                k % 3
            );
        }
        Ok(())
    }

    #[test]
    fn increment_follows_hairers_rule() {
        assert_eq!(increment(1.0), 1e-8);
        assert_eq!(increment(-4.0), 2e-8);
        // Floor for components at zero: √(1e-16 · 1e-5).
        assert!((increment(0.0) - 10f64.powf(-10.5)).abs() < 1e-20);
    }

    #[test]
    fn wrong_buffers_are_an_error_naming_them() {
        let f = Nonlinear;
        let y = f.initial_state();
        let f_y = [0.0; 3];
        let mut jac = [0.0; 8];
        let mut work = [0.0; 6];
        let err = f
            .jacobian(0.0, &y, &f_y, &mut jac, &mut work)
            .map_err(|e| e.to_string());
        assert!(
            matches!(&err, Err(m) if m.contains("out: 9") && m.contains("got 3, 8, 6")),
            "{err:?}"
        );
    }
}
