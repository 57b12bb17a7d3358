//! The DAE's consistency conditions for analyses that set its state ([`ConstrainedState`]):
//! C(t, y) = (Φ, Φ̇) over the active rows (redundant rows left out, as in the dynamics), so
//! 2m conditions on the 6 per body coordinates and velocities; the stored impact velocities
//! and the energy integrals are free.
//!
//! ∂C/∂y = [[Φ_q, 0], [∂Φ̇/∂q, Φ_q]]: Φ_q from the rows themselves, ∂Φ̇/∂q (the rows'
//! curvature times q̇, and ∂Φ_t/∂q) by central differences of Φ̇, which is smooth in q. A state
//! is made consistent as the DAE's projection near singular positions does it
//! ([`super::projection`]): positions by Newton's method mass-orthogonally onto Φ = 0, then
//! the velocities once onto Φ̇ = 0.

use super::Dae;
use crate::formulation::{ConstrainedState, Formulation, FormulationError};
use crate::mechanics::constraints::ConstraintEval;

/// Newton iterations of the positions at most: the shooting's iterates are off Φ = 0 by the
/// curvature times the square of their step, which three iterations take to round-off from
/// 1e-2 of the length scale; a few more are a margin for longer steps.
const MAX_POSITION_ITERATIONS: usize = 8;

/// Relative step of the central differences of Φ̇ in q (of the length scale for positions,
/// of 1 rad for angles): truncation error ~1e-12 relative, rounding ~1e-10.
const DIFFERENCE_STEP: f64 = 1e-6;

impl ConstrainedState for Dae {
    fn n_conditions(&self) -> usize {
        2 * self.active.len()
    }

    fn condition_jacobian(
        &self,
        t: f64,
        y: &[f64],
        out: &mut [f64],
    ) -> Result<(), FormulationError> {
        let n = self.n_coordinates();
        let ns = self.n_states();
        let m = self.active.len();
        out.fill(0.0);
        let mut work = self.work.borrow_mut();
        self.constraints_at(t, y, &mut work);
        // ∂Φ/∂q and ∂Φ̇/∂q̇: the rows Φ_q.
        for (a, &ri) in self.active.iter().enumerate() {
            for (body, jac) in work.constraints.rows[ri].blocks() {
                let Some(b) = body else { continue };
                for (c, &d) in jac.iter().enumerate() {
                    out[a * ns + 3 * b + c] += d;
                    out[(m + a) * ns + n + 3 * b + c] += d;
                }
            }
        }
        // ∂Φ̇/∂q by central differences.
        let mut eval = ConstraintEval::with_rows(self.constraints.n_rows());
        let mut q = y[..n].to_vec();
        let v = &y[n..2 * n];
        let mut sin_cos = super::sin_cos_of(&q);
        let mut plus = vec![0.0; m];
        for j in 0..n {
            let scale = if j % 3 == 2 { 1.0 } else { self.length_scale };
            let h = DIFFERENCE_STEP * scale.max(q[j].abs());
            let original = q[j];
            for (sign, slot) in [(1.0, true), (-1.0, false)] {
                q[j] = original + sign * h;
                sin_cos[j / 3] = q[3 * (j / 3) + 2].sin_cos();
                self.constraints
                    .evaluate_into(t, &q, v, &sin_cos, &mut eval);
                for (a, &ri) in self.active.iter().enumerate() {
                    if slot {
                        plus[a] = eval.phi_dot[ri];
                    } else {
                        out[(m + a) * ns + j] = (plus[a] - eval.phi_dot[ri]) / (2.0 * h);
                    }
                }
            }
            q[j] = original;
            sin_cos[j / 3] = q[3 * (j / 3) + 2].sin_cos();
        }
        Ok(())
    }

    fn make_consistent(&self, t: f64, y: &mut [f64]) -> Result<(), FormulationError> {
        if self.active.is_empty() {
            return Ok(());
        }
        let n = self.n_coordinates();
        let mut guard = self.work.borrow_mut();
        let work = &mut *guard;
        self.factor_at(t, y, work)?;
        let mut largest = self.largest(&work.constraints.phi);
        for _ in 0..MAX_POSITION_ITERATIONS {
            for (x, &ri) in work.lambda.iter_mut().zip(&self.active) {
                *x = work.constraints.phi[ri];
            }
            let before = y[..n].to_vec();
            self.correct(&mut y[..n], work);
            self.factor_at(t, y, work)?;
            let now = self.largest(&work.constraints.phi);
            // At round-off (or not finite): a further iteration only moves the rounding around.
            let improved = now < largest;
            if !improved {
                if now > largest || now.is_nan() {
                    y[..n].copy_from_slice(&before);
                    self.factor_at(t, y, work)?;
                }
                break;
            }
            largest = now;
        }
        // Velocities at the consistent positions (linear in q̇: once).
        for (x, &ri) in work.lambda.iter_mut().zip(&self.active) {
            *x = work.constraints.phi_dot[ri];
        }
        self.correct(&mut y[n..2 * n], work);
        Ok(())
    }

    fn step_end_corrections(&self) -> usize {
        self.projections
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn farahan() -> Dae {
        let model = crate::model::load("models/farahan2016.toml".as_ref(), &[])
            .unwrap_or_else(|e| panic!("{e}"));
        Dae::new(&model, &Default::default()).unwrap_or_else(|e| panic!("{e}"))
    }

    /// |Φ| and |Φ̇| over the active rows at (t, y).
    fn violation(f: &Dae, t: f64, y: &[f64]) -> (f64, f64) {
        let mut work = f.work.borrow_mut();
        f.constraints_at(t, y, &mut work);
        (
            f.largest(&work.constraints.phi),
            f.largest(&work.constraints.phi_dot),
        )
    }

    #[test]
    fn a_disturbed_state_is_made_consistent_to_round_off() {
        let f = farahan();
        let t = 0.013;
        let mut y = f.initial_state();
        for (i, yi) in y.iter_mut().enumerate() {
            *yi += 1e-3 * ((i as f64) * 0.7).sin();
        }
        let (phi, phi_dot) = violation(&f, t, &y);
        assert!(
            phi > 1e-5 && phi_dot > 1e-4,
            "disturbed: {phi:e} {phi_dot:e}"
        );
        f.make_consistent(t, &mut y)
            .unwrap_or_else(|e| panic!("{e}"));
        let (phi, phi_dot) = violation(&f, t, &y);
        assert!(
            phi < 1e-15 && phi_dot < 1e-12,
            "consistent: {phi:e} {phi_dot:e}"
        );
    }

    #[test]
    fn the_condition_jacobian_matches_differences_of_the_conditions() {
        let f = farahan();
        let t = 0.004;
        let mut y = f.initial_state();
        y[9] += 0.3; // a velocity off its constraint, so that Φ̇ depends on q visibly
        let (ns, m) = (f.n_states(), f.active.len());
        let mut jac = vec![0.0; 2 * m * ns];
        f.condition_jacobian(t, &y, &mut jac)
            .unwrap_or_else(|e| panic!("{e}"));
        let conditions = |y: &[f64]| {
            let mut work = f.work.borrow_mut();
            f.constraints_at(t, y, &mut work);
            let c = &work.constraints;
            let mut out: Vec<f64> = f.active.iter().map(|&r| c.phi[r]).collect();
            out.extend(f.active.iter().map(|&r| c.phi_dot[r]));
            out
        };
        for j in 0..ns {
            let h = 1e-7;
            let (mut up, mut down) = (y.clone(), y.clone());
            up[j] += h;
            down[j] -= h;
            let (cu, cd) = (conditions(&up), conditions(&down));
            for r in 0..2 * m {
                let fd = (cu[r] - cd[r]) / (2.0 * h);
                let got = jac[r * ns + j];
                assert!(
                    (fd - got).abs() <= 1e-6 * (1.0 + fd.abs()),
                    "∂C_{r}/∂y_{j}: {got} against differences {fd}"
                );
            }
        }
    }
}
