//! Formulations: turning a [`Model`](crate::model::Model) into first-order equations of motion
//! y' = f(t, y) that the integrators in [`crate::solve`] can step.
//!
//! Each formulation implements [`Formulation`]. Integrators see only this trait, never a concrete
//! mechanism: equations apart from method.

pub mod assembly;
pub mod constrained_state;
pub mod contact_slopes;
pub mod contacts;
pub mod corner_contacts;
pub mod dae;
pub mod generalized;
pub mod jacobian;
pub mod reduced_lagrangian;
pub mod residual;
pub mod schur;
pub mod sparse_jacobian;
#[cfg(test)]
pub(crate) mod test_rng;

pub use constrained_state::ConstrainedState;
pub use dae::{Dae, DaeOptions};
pub use generalized::Generalized;
pub use reduced_lagrangian::ReducedLagrangian;

use thiserror::Error;

/// Direction in which an event function g crossed zero.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Crossing {
    /// g went from negative to positive.
    Rising,
    /// g went from positive to negative.
    Falling,
}

/// What the integrator must do after a formulation handled an event.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventResponse {
    /// The equations changed (e.g. a contact started and its impact velocity was stored):
    /// restart the integrator at the event time from the (possibly modified) state.
    Restart,
    /// Nothing changed; carry on with the current step.
    Continue,
}

/// The tolerances (rtol, atol) that a method's error control works with
/// ([`SolverOptions::controlled_tolerances`](crate::solve::SolverOptions::controlled_tolerances)):
/// what a formulation bounds by the accuracy of the run (the DAE's constraint violation,
/// [`dae::violation_limit`]) is bounded by these.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
}

/// What the stepping driver tells a formulation around each step, for formulations that keep
/// state across steps (the DAE: the constraint-violation bound, projections near singular
/// positions, the count of singular passages; the generalised formulation: the projection of
/// every step end).
///
/// Kept apart from [`Formulation`] (the equations every formulation has) and without default
/// methods, so that a wrapper cannot drop a hook silently: it forwards each one to what it
/// wraps (the Lyapunov analysis's pair of copies does), or says in one line that it has none
/// ([`NoStepHooks`]).
pub trait StepHooks {
    /// Called by the driver before the first attempt of every step from (t, y). A formulation
    /// that keeps statistics over the stages of a step (the DAE: how near they came to a
    /// singular position) resets them here, so that right-hand sides evaluated for the dense
    /// output of the previous step (output samples, which differ from run to run) do not
    /// count.
    fn begin_step(&mut self, t: f64, y: &[f64]);

    /// Called by the driver after every attempt of a method that integrates the residual form
    /// ([`Formulation::residual_form`]; IDA), with the smallest pivot ratio of the constraint
    /// solve over the residuals it evaluated ([`residual::ResidualForm::take_min_pivot_ratio`]):
    /// those evaluations are the stages of the step, and the method never calls
    /// [`Formulation::rhs`] during one.
    fn residual_stages(&mut self, min_pivot_ratio: f64);

    /// Called by the driver at the end of every accepted step, with the new state (t, y) and
    /// the tolerances the method controls, before the step is handed to events and samples. A
    /// formulation checks here what must hold at every step, not only at the output samples
    /// (the DAE: the constraint violation |Φ| within its bound), and keeps running maxima. It
    /// may also correct the step end (the DAE projects it onto the constraints near singular
    /// positions) and then returns [`EventResponse::Restart`]: the integrator restarts from the
    /// corrected y before the next step (the dense output of the step just taken stays as it
    /// was). An error stops the run at t.
    fn accept_step(
        &mut self,
        t: f64,
        y: &mut [f64],
        tolerances: Tolerances,
    ) -> Result<EventResponse, FormulationError>;
}

/// Declares that a formulation has no step hooks: `impl NoStepHooks for MyEquations {}` gives
/// it the [`StepHooks`] that do nothing (and continue at every step end).
pub trait NoStepHooks {}

impl<T: NoStepHooks + ?Sized> StepHooks for T {
    fn begin_step(&mut self, _t: f64, _y: &[f64]) {}

    fn residual_stages(&mut self, _min_pivot_ratio: f64) {}

    fn accept_step(
        &mut self,
        _t: f64,
        _y: &mut [f64],
        _tolerances: Tolerances,
    ) -> Result<EventResponse, FormulationError> {
        Ok(EventResponse::Continue)
    }
}

/// Equations of motion in first-order form, y' = f(t, y), plus optional event functions.
///
/// The state layout is the formulation's own business; the integrator only needs its length.
/// What happens around the steps (checks and corrections at step ends) is the separate
/// [`StepHooks`], which every formulation implements or declines explicitly.
pub trait Formulation: StepHooks {
    /// Number of first-order states (length of y).
    fn n_states(&self) -> usize;

    /// Consistent initial state at `self.t0()`.
    fn initial_state(&self) -> Vec<f64>;

    /// Initial time (s).
    fn t0(&self) -> f64 {
        0.0
    }

    /// Right-hand side: writes y'(t) into `dy`. Fails where the equations cannot be evaluated
    /// (a singular constraint Jacobian, a non-finite force), saying why.
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError>;

    /// Number of event functions g_i(t, y). Default: none.
    fn n_events(&self) -> usize {
        0
    }

    /// Writes the event functions g_i(t, y) into `g` (length [`Formulation::n_events`]).
    /// An event happens where some g_i changes sign.
    fn events(&self, _t: f64, _y: &[f64], _g: &mut [f64]) {}

    /// Called by the integrator at a located event (t is the root to the event tolerance).
    /// The formulation may change its discrete state (e.g. store an impact velocity) and
    /// may modify `y`. Default: ignore the event.
    fn apply_event(
        &mut self,
        _t: f64,
        _y: &mut [f64],
        _index: usize,
        _crossing: Crossing,
    ) -> EventResponse {
        EventResponse::Continue
    }

    /// Jacobian J = ∂f/∂y of [`Formulation::rhs`] at (t, y), written **row-major** into `out`
    /// (length n²): `out[i * n + j]` = ∂f_i/∂y_j. `f_y` holds f(t, y); `work` is scratch of
    /// length ≥ 2n. Returns the number of RHS calls it made, so that integrators can count
    /// them (0 for an analytic Jacobian).
    ///
    /// Default: forward differences with Hairer's increment δ_j = √(10⁻¹⁶·max(10⁻⁵, |y_j|)),
    /// n RHS calls ([`jacobian::finite_difference`]). Formulations may override it with an
    /// analytic Jacobian; the implicit integrator (`solve::radau5`) is its only user.
    fn jacobian(
        &self,
        t: f64,
        y: &[f64],
        f_y: &[f64],
        out: &mut [f64],
        work: &mut [f64],
    ) -> Result<usize, FormulationError> {
        jacobian::finite_difference(self, t, y, f_y, out, work)
    }

    /// The Jacobian in sparse augmented form ([`sparse_jacobian`]), for implicit methods on
    /// large models: the integrator then factors sparse Newton matrices instead of the dense
    /// n × n ones of [`Formulation::jacobian`] (`solve::radau5`, `Radau5Settings::linear_solver`).
    /// Default: `None` (dense only). Wrappers forward it, or implicit methods fall back to the
    /// dense Jacobian.
    fn sparse_jacobian(&self) -> Option<&dyn sparse_jacobian::SparseJacobian> {
        None
    }

    /// Number m of leading states that are positions whose derivatives are the next m states
    /// exactly: f_i(t, y) = y_{m+i} for i < m (q̇ = v, the first-order form of equations of
    /// motion), for every (t, y). Implicit methods then solve their Newton systems through
    /// one of n − m unknowns (`solve::radau5`, Hairer's `M1` option). Must be at most n/2.
    /// Default: 0, no such structure claimed.
    fn second_order_positions(&self) -> usize {
        0
    }

    /// Marks the states whose local error the integrators control. `controlled` (length
    /// [`Formulation::n_states`]) arrives all `true`; a formulation sets `false` for its
    /// bookkeeping states — discrete state kept in y (a stored impact velocity, constant between
    /// events) and integrals that feed back into nothing (energy bookkeeping). Error norms and
    /// the initial-step heuristic skip those components and divide by the number of controlled
    /// ones, so bookkeeping never changes the steps taken. Default: every state is controlled.
    fn error_controlled(&self, _controlled: &mut [bool]) {}

    /// Marks the states that are angles (rad), `angular` arriving all `false`: a periodic
    /// motion returns to them up to whole turns (a driven crank's angle grows by 2π per turn),
    /// so the shooting of periodic orbits compares them modulo 2π. Default: none.
    fn angular_states(&self, _angular: &mut [bool]) {}

    /// Largest step the integrator may take from (t, y) (s). Formulations with events use it
    /// to make sure that no event can start and end inside one step. Default: unlimited.
    fn max_step(&self, _t: f64, _y: &[f64]) -> f64 {
        f64::INFINITY
    }

    /// The same equations in residual form F(t, Y, Ẏ) = 0 with algebraic unknowns (the DAE's
    /// Lagrange multipliers), for DAE solvers (SUNDIALS IDA, `--method ida`); see
    /// [`residual`]. Default: `None`, and such solvers integrate Ẏ − f(t, Y)
    /// ([`residual::OdeResidual`]).
    fn residual_form(&self) -> Option<Box<dyn residual::ResidualForm>> {
        None
    }

    /// What in the mechanism may explain a run that stopped making progress at (t, y): the
    /// constraint rows that are nearly dependent there (a singular position), the clearance
    /// joints at their contact boundary, an ill-conditioned coordinate partition (see
    /// [`dae::diagnosis`]). Called once, by the no-progress rule of the integrators, and appended
    /// to its message ([`SolveError::NoProgress`](crate::solve::SolveError::NoProgress)).
    /// Default: `None` (nothing to add).
    fn diagnose(&self, _t: f64, _y: &[f64]) -> Option<String> {
        None
    }

    /// The conditions every consistent state satisfies ([`constrained_state`]: the DAE's
    /// Φ = 0 and Φ̇ = 0), for analyses that set the state themselves (periodic orbits).
    /// Default: `None`, every state is consistent.
    fn constrained_state(&self) -> Option<&dyn ConstrainedState> {
        None
    }
}

/// Output columns a formulation can report at a sample (t, y): body states, reactions, torques,
/// contact quantities. Names are `object.quantity`, as in the model file.
pub trait Outputs {
    /// Column names, in order.
    fn output_names(&self) -> Vec<String>;

    /// Writes the columns at (t, y) into `out` (cleared first) and returns the largest
    /// constraint violation |Φ| at that sample (0 for formulations without constraints).
    fn outputs_into(&self, t: f64, y: &[f64], out: &mut Vec<f64>) -> Result<f64, FormulationError>;

    /// Checks the constraint violation of a reported state between step ends (an output
    /// sample, from the dense output) against the bound that [`StepHooks::accept_step`]
    /// applies at step ends, with the tolerances the method controls (the DAE:
    /// [`dae::violation_limit`]). Default: nothing to check (no constraints, or, for the
    /// generalised formulation, samples projected onto them).
    fn check_constraints(
        &self,
        _t: f64,
        _y: &[f64],
        _tolerances: Tolerances,
    ) -> Result<(), FormulationError> {
        Ok(())
    }

    /// Largest constraint violation |Φ| over the accepted step ends seen so far by
    /// [`StepHooks::accept_step`] (m or rad; 0 for formulations without constraints).
    /// Default: 0.
    fn step_constraint_violation(&self) -> f64 {
        0.0
    }

    /// Times (s) at which the run passed a singular position of the linkage where the
    /// formulation cannot vouch for the assembly branch ([`Dae::singular_passages`]). Default:
    /// none (the reduced formulation has none; the generalised one keeps its branch by
    /// construction).
    fn singular_passages(&self) -> Vec<f64> {
        Vec::new()
    }
}

/// Errors raised while building or evaluating a formulation.
#[derive(Debug, Error)]
pub enum FormulationError {
    /// Newton's method could not bring the constraints to zero from the initial guesses.
    #[error(
        "the linkage cannot be assembled: the constraint of joint \"{joint}\" is still off by {residual:.3e} (m or rad) after {iterations} Newton iterations; check the link lengths and the bodies' initial guesses"
    )]
    Unassemblable {
        /// Joint or driver whose constraint has the largest residual.
        joint: String,
        /// Largest residual |Φ| (m or rad).
        residual: f64,
        /// Newton iterations done.
        iterations: usize,
    },
    /// The constraint Jacobian lost rank during the motion (a locking or singular position).
    #[error(
        "singular constraint Jacobian at t = {t:.9} s (the linkage passes a singular position; constraint \"{constraint}\")"
    )]
    SingularConstraints {
        /// Time (s).
        t: f64,
        /// Name of the constraint row where the factorisation broke down.
        constraint: String,
    },
    /// A non-finite value appeared in the state or in a force.
    #[error("non-finite {what} of body \"{body}\" at t = {t:.9} s")]
    NonFinite {
        /// Time (s).
        t: f64,
        /// Body name.
        body: String,
        /// Which quantity ("position", "velocity", "acceleration").
        what: String,
    },
    /// A clearance joint penetrated so deep that no contact law holds: the linkage is being
    /// driven through the joint (a model that cannot move as built, or absurd forces).
    #[error(
        "penetration of clearance joint \"{joint}\" reached {penetration:.3e} m at t = {t:.9} s, beyond {limit:.3e} m (the deepest its contact law is used at: a tenth of the journal radius, less for Johnson's law, 1 % of a slider's length for its corners and end stops) where no contact law holds: the linkage is being driven through the joint; check its geometry, driver and loads"
    )]
    PenetrationTooDeep {
        /// Time (s).
        t: f64,
        /// Joint name.
        joint: String,
        /// Penetration δ (m).
        penetration: f64,
        /// The limit (m): 0.1 R_J, less for Johnson's law, 1 % of the slider length for a
        /// corner or end stop.
        limit: f64,
    },
    /// At the assembled position (t = 0) a corner of a prismatic-clearance joint's slider is on
    /// or past one of the guide's end stops: the slider must start strictly between them.
    #[error(
        "prismatic-clearance joint \"{joint}\": at the assembled position (t = 0) the slider's corner {corner} is {past:.6e} m past `{field}` ({stop:e} m along the axis); expected the slider strictly between the guide's end stops, since a contact that is under way at t = 0 has no impact velocity to scale its damping: move `{field}` or the slider"
    )]
    SliderPastGuideEnd {
        /// Joint name.
        joint: String,
        /// The corner (c1 … c4).
        corner: &'static str,
        /// The field of the end stop it is past: `guide_start` or `guide_end`.
        field: &'static str,
        /// The stop's position along the axis (m).
        stop: f64,
        /// How far past the stop the corner is (m, ≥ 0).
        past: f64,
    },
    /// The constraint violation at an accepted step end or an output sample exceeded its bound (see
    /// [`dae::violation_limit`]): the trajectory has left the linkage's configuration space
    /// and no result computed from it can be trusted.
    #[error(
        "constraint \"{constraint}\" is violated by |Φ| = {value:.3e} {unit} at t = {t:.9} s, beyond the bound {limit:.3e} {unit} ({bound}): the motion no longer satisfies the joints; tighten rtol/atol, raise the Baumgarte factors, or check that the linkage can move as driven{diagnosis}"
    )]
    ConstraintViolation {
        /// Time of the step end (s).
        t: f64,
        /// Joint row ("A.x") or driver name.
        constraint: Box<str>,
        /// |Φ| of that row (m or rad).
        value: f64,
        /// The bound (m or rad).
        limit: f64,
        /// Metres for position rows, radians for angle rows.
        unit: ViolationUnit,
        /// How the bound was formed (the length scale and tolerances).
        bound: Box<str>,
        /// The formulation's diagnosis at that state, with a leading space (the rows that are
        /// nearly dependent where the violation comes from a singular position or a lock), or
        /// empty (boxed: the error stays small).
        diagnosis: Box<str>,
    },
    /// A constraint row conflicts with others at t = 0: a driver that is a combination of the
    /// other rows (it cannot be enforced independently), or a dependent row whose prescribed
    /// velocity or acceleration contradicts the rows it depends on.
    #[error(
        "conflicting constraints at t = 0: \"{row}\" depends on {depends_on}, and {reason}; remove one of them or fix the geometry"
    )]
    ConflictingConstraints {
        /// The dependent row (joint row "A.x" or driver name).
        row: String,
        /// The rows it is a combination of, quoted and comma-separated.
        depends_on: String,
        /// Why that is a conflict.
        reason: String,
    },
    /// The generalised-coordinate formulation could not bring the constraints back to zero
    /// from the integrator's predicted dependent coordinates (a step so large that the
    /// prediction left Newton's reach). Recoverable: a smaller step predicts better.
    #[error(
        "the dependent coordinates could not be recovered at t = {t:.9} s: constraint \"{constraint}\" is still off by {residual:.3e} (m or rad) after {iterations} Newton iterations"
    )]
    ProjectionFailed {
        /// Time (s).
        t: f64,
        /// Row with the largest residual (joint row "A.x" or driver name).
        constraint: String,
        /// Its |Φ| (m or rad).
        residual: f64,
        /// Newton iterations done.
        iterations: usize,
    },
    /// The model does not fit this formulation.
    #[error("{formulation} formulation: {reason}")]
    Unsupported {
        /// Formulation name.
        formulation: String,
        /// What it requires and what the model has.
        reason: String,
    },
}

impl FormulationError {
    /// True for errors that a trial state of a too-large step can cause and a smaller step may
    /// avoid (a stage that overshoots into a contact). The integrators then reject the step and
    /// retry with a smaller one, and report the error only when no step size avoids it.
    pub fn is_recoverable(&self) -> bool {
        matches!(
            self,
            FormulationError::PenetrationTooDeep { .. } | FormulationError::ProjectionFailed { .. }
        )
    }
}

/// The unit of a constraint row's violation: metres for a joint's position rows, radians for
/// an angle row (a driver). One byte, so that the error stays small.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ViolationUnit {
    /// Position rows (m).
    Metre,
    /// Angle rows (rad).
    Radian,
}

impl std::fmt::Display for ViolationUnit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ViolationUnit::Metre => "m",
            ViolationUnit::Radian => "rad",
        })
    }
}
