//! Periodic orbits of a driven formulation by shooting, with their Floquet multipliers.
//!
//! # Method (docs/periodic_orbits.md)
//! * **Shooting.** For a period T (K driver turns) and a section at t0, the period map is
//!   P(x) = φ(t0 + T; t0, x). Newton's method solves P(x) − x = 0 from a guess (the state after
//!   a few turns of integration): (M − I) Δx = −(P(x) − x), M = ∂P/∂x the monodromy matrix,
//!   with the step halved while it does not lower the residual. The driver angle is time-like
//!   (a constant-speed driver in the formulation's time), so T is fixed and no phase condition
//!   is needed.
//! * **Unknowns.** Every error-controlled state, and a bookkeeping state (a stored impact
//!   velocity) only where the motion depends on it over the period — a joint in contact at
//!   the section ([`floquet`]). The others are taken from the end of the period.
//! * **Monodromy.** From the variational equations Φ' = J(t, y) Φ integrated with the state on
//!   the same steps ([`variational`]), with a saltation matrix at every event
//!   ([`saltation`]): a finite-difference monodromy is only the tests' cross-check.
//! * **Convergence.** The residual and the steps are measured in units of the integration
//!   tolerance ε_i = atol + rtol·|x_i| (max over the unknowns). Far from the orbit each
//!   Newton step is halved until the residual drops; once the residual is within
//!   `closing_limit` ε (1000, the tolerance within which `linkdyn poincare` calls two section
//!   points equal), one more full step is taken and the better iterate returned, since the
//!   residual then stands at the integration's own noise (the period map computed from a
//!   fresh start differs from the exact one by the global error of one period, tens to
//!   hundreds of ε). Also converged: a residual within 1 ε, or a step within
//!   `step_tolerance` ε. The orbit returned comes with the residual of its own period, its
//!   closing error ([`PeriodicOrbit::closing_error`]).
//! * **Floquet multipliers.** The eigenvalues of M restricted to the unknowns; the inactive
//!   bookkeeping states' multipliers (0 or 1, exactly) are trivial and only counted.
//!
//! * **Constrained states** (the DAE's Φ = 0 and Φ̇ = 0): every iterate is made consistent and
//!   the Newton step is taken in the consistent directions W only; the multipliers are those
//!   of Wᵀ M W ([`coordinates`]).
//!
//! Formulations that correct their state at step ends (projections) are not supported: Φ
//! would miss the correction's derivative (a DAE period with a projection near a singular
//! position is refused).

pub mod continuation;
pub mod coordinates;
pub mod floquet;
pub mod monodromy;
pub mod saltation;
pub mod shooting;
pub mod variational;

pub use continuation::{
    Branch, BranchEnd, BranchPoint, ContinuationOptions, OrbitAt, OrbitFamily, SpecialKind, Watch,
    continue_orbit, continue_orbit_watched, switch_branch, switch_branch_watched,
};
pub use monodromy::{Shot, shoot, shoot_watching};
pub use saltation::{SaltationError, saltation_matrix};
pub use shooting::{OrbitOptions, PeriodicOrbit, periodic_orbit};
pub use variational::Variational;
