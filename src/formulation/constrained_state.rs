//! [`ConstrainedState`]: the conditions every consistent state of a formulation satisfies (the
//! DAE's position and velocity constraints Φ = 0 and Φ̇ = 0), for analyses that move the state
//! themselves. The shooting of periodic orbits (`analysis::orbit`) takes its Newton steps in
//! the directions a consistent state can move in (the null space of ∂C/∂y) and projects every
//! iterate back onto C = 0, so that the constraint directions of the state, which the motion
//! does not have, are neither unknowns nor Floquet multipliers.

use super::FormulationError;

/// Consistency conditions C(t, y) = 0 of a formulation's state (module documentation).
pub trait ConstrainedState {
    /// Number of independent conditions (rows of C).
    fn n_conditions(&self) -> usize;

    /// ∂C/∂y at (t, y), written row-major into `out` (length `n_conditions` × n_states).
    /// Columns of states that no condition reads (bookkeeping) are zero.
    fn condition_jacobian(
        &self,
        t: f64,
        y: &[f64],
        out: &mut [f64],
    ) -> Result<(), FormulationError>;

    /// Moves y to a consistent state nearby (C(t, y) = 0 to round-off), leaving the states that
    /// no condition reads as they are.
    fn make_consistent(&self, t: f64, y: &mut [f64]) -> Result<(), FormulationError>;

    /// Corrections of the state made at step ends so far (projections near singular
    /// positions). Variational equations do not follow them, so a change of this count over
    /// an integration makes its sensitivities unreliable.
    fn step_end_corrections(&self) -> usize;
}
