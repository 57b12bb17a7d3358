//! Projection of the DAE's state onto the constraint manifold near singular positions.
//!
//! Near a singular position (a parallelogram's flat position, where two assembly branches
//! cross) the level sets Φ = ε turn onto the crossed branch: a drift ε in Φ or Φ̇ on arrival
//! leaves the passage as a deflection some 1e3 ε, and Baumgarte's terms at the models' default
//! 10 s⁻¹ damp it only ~15× before the next passage — within two or three passages the motion
//! is on the crossed branch (measured on tests/fixtures/parallelogram.toml at every rtol from
//! 1e-6 to 1e-10 before this projection existed). So on the steps that come near a singular
//! position the step end is projected onto Φ = 0 and Φ̇ = 0, mass-orthogonally (the nearest
//! consistent state in the kinetic-energy metric):
//!
//! ```text
//!     q ← q − M⁻¹ Φ_qᵀ A⁻¹ Φ(q)      (Newton, until |Φ| is at round-off)
//!     q̇ ← q̇ − M⁻¹ Φ_qᵀ A⁻¹ Φ̇(q, q̇)  (once: linear in q̇)
//! ```
//!
//! with A the regularised Schur complement of the multiplier solve, on the step ends spaced
//! by `Spacing` (a projection restarts the integrator; projecting every step end cost
//! accuracy). Arrival drift is then the integration error of the few steps since the last
//! projection. A step end too close to the singular position is not projected (there the
//! branches are within ~s L of each other and A⁻¹ is set by the regularisation, not by the
//! geometry); a later step end, on the far side, is.

use super::{Dae, Work, subtract_constraint_forces};
use crate::formulation::FormulationError;

/// A step whose smallest pivot ratio ([`super::Schur::min_pivot_ratio`]) falls below this
/// ends with a projection: within ~0.1 rad of a flat position, where the ratio falls like s².
/// The shipped regular models stay above it except quick_return (smallest ratio 4.1e-4) and
/// watt_sixbar (7.6e-3), whose steps near their closest approach are projected.
pub const PROJECTION_RATIO: f64 = 1e-2;

/// A step end whose own pivot ratio is below this is left as it is (see the module
/// documentation): within |s| ≲ 1e-2 of the singular position the correction along the
/// near-null direction is divided by a pivot that is mostly round-off and regularisation.
/// Measured on the parallelogram fixtures (2026-11-26, default Baumgarte factors, DOP853 and
/// Radau5 at rtol 1e-6 … 1e-10): with 1e-6 the velocity corrections there reached 1e-7 m/s and
/// DOP853 at rtol 1e-10 stalled on the chain of three (steps of 2e-9 s); with 1e-3 too few
/// step ends were projected and the chain left its branch by 4.6e-5 rad at rtol 1e-6; with
/// 1e-4 every run keeps the branch. (Measured with the pivot regularisation at 1e-10; it is
/// 1e-8 since, and the N-four-bar chains keep their branch with this floor too,
/// `tests/nfourbar_chain.rs`.)
pub const PROJECTION_FLOOR: f64 = 1e-4;

/// Which step ends of one approach to a singular position are projected, by every method.
/// Every projection restarts the integrator, and a step end projected after every step
/// started, in IDA, a cascade (order-1 steps, each projected: 1e6 projections and θ off by
/// 1e4 × rtol at rtol 1e-10), and in Radau5 an error that grew with every projected step (the
/// N-four-bar chain at rtol 1e-10, atol 1e-12: 2.9e-6, 4.4e-6, 4.6e-6 m off the exact motion
/// for 2, 10, 40 loops, against 3.4e-7, 4.8e-7, 4.7e-7 m with the spacing; measured
/// 2026-11-28, docs/formulations.md). So a step end is projected only where the pivot ratio
/// changed by [`SPACING`] since the last projection of the approach (down or up, or through
/// the floor: the smallest ratio seen since, stages included), which spaces the projections
/// geometrically in the distance s from the singular position.
#[derive(Debug, Clone, Copy)]
pub(super) struct Spacing {
    /// Pivot ratio at the last projection of the approach (∞: none yet).
    last: f64,
    /// Smallest ratio seen since (stages and step ends).
    seen: f64,
}

impl Default for Spacing {
    fn default() -> Self {
        Spacing {
            last: f64::INFINITY,
            seen: f64::INFINITY,
        }
    }
}

impl Spacing {
    /// Whether a step end with pivot ratio r is projected.
    pub fn wanted(&self, r: f64) -> bool {
        let low = self.seen.min(r);
        self.last == f64::INFINITY || self.last >= SPACING * low || r >= SPACING * self.last
    }

    /// A stage of the step had the pivot ratio r.
    pub fn saw(&mut self, r: f64) {
        self.seen = self.seen.min(r);
    }

    /// The step ended with the pivot ratio r, projected or not.
    pub fn ended(&mut self, r: f64, projected: bool) {
        if projected {
            self.last = r;
            self.seen = r;
        } else {
            self.saw(r);
        }
    }
}

/// Factor of the pivot ratio between two projections of a run ([`Spacing`]): a factor 2
/// in the distance s. Measured on the parallelogram fixtures (2026-11-26, IDA at rtol 1e-6,
/// 1e-8, 1e-10): with 2, 4 and 10 every run keeps the branch, 36–130 projections per run,
/// θ within 163, 122 and 129 × rtol·max|θ| of the pendulum; 4 the best.
pub(super) const SPACING: f64 = 4.0;

/// Newton iterations of the position projection. The drift it removes is of the order of the
/// local error (≤ 1e-6 L), so two iterations reach round-off; a third is a margin.
const POSITION_ITERATIONS: usize = 3;

impl Dae {
    /// Projects the state y = (q, q̇, …) at time t onto the constraint manifold (module
    /// documentation). Returns the pivot ratio at y and whether it projected: y is left
    /// unchanged where the step end is too close to the singular position (pivot ratio below
    /// [`PROJECTION_FLOOR`]) or where `wanted` (of that ratio) says no, and where the
    /// iteration did not reduce |Φ|.
    pub(super) fn project_state(
        &self,
        t: f64,
        y: &mut [f64],
        work: &mut Work,
        wanted: impl Fn(f64) -> bool,
    ) -> Result<(f64, bool), FormulationError> {
        let n = self.n_coordinates();
        if self.active.is_empty() {
            return Ok((1.0, false));
        }
        let mut ratio = 1.0;
        let original: Vec<f64> = y[..2 * n].to_vec();
        let mut phi_before = 0.0;
        for iteration in 0..=POSITION_ITERATIONS {
            self.factor_at(t, y, work)?;
            if iteration == 0 {
                ratio = work.schur.min_pivot_ratio();
                if ratio < PROJECTION_FLOOR || !wanted(ratio) {
                    return Ok((ratio, false));
                }
                phi_before = self.largest(&work.constraints.phi);
            }
            if iteration == POSITION_ITERATIONS {
                break;
            }
            for (x, &ri) in work.lambda.iter_mut().zip(&self.active) {
                *x = work.constraints.phi[ri];
            }
            self.correct(&mut y[..n], work);
        }
        let phi_after = self.largest(&work.constraints.phi);
        if phi_after.is_nan() || phi_after > phi_before {
            y[..2 * n].copy_from_slice(&original);
            return Ok((ratio, false));
        }
        // Velocities at the projected positions (the factor is the last iteration's).
        for (x, &ri) in work.lambda.iter_mut().zip(&self.active) {
            *x = work.constraints.phi_dot[ri];
        }
        self.correct(&mut y[n..2 * n], work);
        Ok((ratio, true))
    }

    /// Evaluates the constraint rows (Φ, Φ̇, Φ_q, …) at y into `work.constraints`.
    pub(super) fn constraints_at(&self, t: f64, y: &[f64], work: &mut Work) {
        let n = self.n_coordinates();
        for (i, sc) in work.sin_cos.iter_mut().enumerate() {
            *sc = y[3 * i + 2].sin_cos();
        }
        self.constraints.evaluate_into(
            t,
            &y[..n],
            &y[n..2 * n],
            &work.sin_cos,
            &mut work.constraints,
        );
    }

    /// Evaluates the constraint rows at y and factors A there.
    pub(super) fn factor_at(
        &self,
        t: f64,
        y: &[f64],
        work: &mut Work,
    ) -> Result<(), FormulationError> {
        self.constraints_at(t, y, work);
        let rows = &work.constraints.rows;
        work.schur
            .factor_regularised(rows, &self.active, &self.inv_mass, &self.shift)
            .map_err(|k| FormulationError::SingularConstraints {
                t,
                constraint: self.constraints.row_name(&self.model, self.active[k]),
            })
    }

    /// z ← z − M⁻¹ Φ_qᵀ A⁻¹ r, with r in `work.lambda` (overwritten by A⁻¹ r) and the rows and
    /// factor of the last [`Dae::factor_at`].
    pub(super) fn correct(&self, z: &mut [f64], work: &mut Work) {
        work.schur.solve(&mut work.lambda);
        work.forces.fill(0.0);
        subtract_constraint_forces(
            &work.constraints.rows,
            &self.active,
            &work.lambda,
            &mut work.forces,
        );
        for ((zi, f), im) in z.iter_mut().zip(&work.forces).zip(&self.inv_mass) {
            *zi += im * f;
        }
    }

    /// Largest |value| over the active rows.
    pub(super) fn largest(&self, values: &[f64]) -> f64 {
        self.active
            .iter()
            .fold(0.0_f64, |m, &ri| m.max(values[ri].abs()))
    }
}
