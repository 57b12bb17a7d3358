//! Radau IIA of order 5 (3 stages), the implicit integrator for stiff contact phases, after
//! Hairer & Wanner's code RADAU5 \[1, Sec. IV.8\].
//!
//! **Method.** The collocation method with nodes c = ((4 − √6)/10, (4 + √6)/10, 1) solves for
//! the stage increments Z_i = Y_i − y_n
//!
//! Z = h (A ⊗ I) F(y_n + Z),  y_{n+1} = y_n + Z₃  (stiffly accurate, L-stable, order 5).
//!
//! **Newton.** Simplified Newton iterations with the Jacobian J at (t_n, y_n) and the
//! transformation W = (T⁻¹ ⊗ I) Z that splits the 3n×3n system into one real n×n system with
//! γ̂/h·I − J and one complex n×n system with (α̂ + iβ̂)/h·I − J (modules `tableau`, `newton`).
//! They are factored by a dense LU of J (`linalg`) or, on large models whose formulation gives
//! its Jacobian in sparse augmented form, by a sparse LU (faer) of the augmented matrices with
//! the column order analysed once per run (`sparse`; [`LinearSolver`], chosen by size:
//! [`SPARSE_MIN_STATES`]).
//! Starting values come from the collocation polynomial of the previous step (zero on the
//! first step and after a restart). The iteration stops when κ·‖ΔW‖ ≤ `newton_tol`, with
//! κ = θ/(1 − θ) and the contraction rate θ = ‖ΔW_k‖/‖ΔW_{k−1}‖ (geometric mean of the last
//! two ratios); it is abandoned (h halved) if θ ≥ 0.99 or `max_newton_iter` is used up, and
//! the step is restarted smaller (h·0.8·q^{−1/(4+k_left)}) if the predicted final error
//! θ^{k_left}/(1 − θ)·‖ΔW‖ exceeds the tolerance \[1, eq. (8.26)–(8.29)\].
//!
//! **Error estimate** \[1, eq. (8.19)–(8.20)\]: err = (I − hγ₀J)⁻¹ [γ₀h f(t_n, y_n) +
//! Σ e_i Z_i], computed as (γ̂/h·I − J)⁻¹ [f(t_n, y_n) + Σ (e_i/h) Z_i] with the LU of the real
//! system. On the first step and after a rejection, if err ≥ 1, the filter is applied once
//! more, to f(t_n, y_n + err) + Σ (e_i/h) Z_i (one extra RHS call), which removes the
//! large-but-harmless estimates of very stiff components.
//!
//! **Step size.** h_new = h / clamp(err^{1/4}/fac, 1/8, 5) with fac = min(safety,
//! safety(1 + 2·nit)/(newt + 2·nit)), and after an accepted step Gustafsson's predictive
//! controller (h_new may only shrink further):
//! h_new ← min(h_new, safety·h·(h_acc/h_prev)·(err_prev/err²)^{1/4}) \[1, eq. (8.25)\].
//! If θ ≤ `theta_jac` and h_new/h ∈ `keep_h_range`, h is kept and the LU factors reused;
//! the Jacobian is re-evaluated after an accepted step only if θ > `theta_jac`, and after a
//! rejected step only if it was not already evaluated at the current point.
//!
//! **Dense output** (order 3, valid on the last step): the collocation polynomial through
//! (t_n, y_n), (t_n + c_i h, y_n + Z_i), written in Newton form around t_{n+1}.
//!
//! **Failures.** A recoverable RHS failure ([`FormulationError::is_recoverable`](crate::formulation::FormulationError::is_recoverable), a trial stage
//! that overshoots into a contact) rejects the attempt and retries with h/4; a singular
//! iteration matrix or a failed Newton iteration retries with h/2. The run stops with
//! [`SolveError::StepTooSmall`](crate::solve::SolveError::StepTooSmall) (or the last recoverable error) when h falls below
//! 16 ulps of t.
//!
//! **Tolerances** (see [`Radau5Settings::hairer_tolerances`]): by default the code
//! works with rtol' = 0.1·rtol^{2/3}, as RADAU5 does; the error scale of component i is
//! atol' + rtol'·|y_i| at the start of the step, and components masked out by
//! [`Radau5Settings::error_mask`] are left out of the error and Newton norms.
//!
//! **Layout.** `Radau5Core` (`core.rs`, private) is the method: one attempt from a state the caller
//! owns. [`Radau5Method`] (`adapter.rs`) puts it behind the
//! [`Integrator`](crate::solve::integrator::Integrator) trait, and the common driver
//! ([`Stepper`](crate::solve::Stepper), [`integrate`](fn@crate::solve::integrate)) does the
//! rest for Radau5 as for every other method (`Method::Radau5`): the clamps of h, the retries
//! of recoverable failures, events, restarts, samples and [`SolverStats`](crate::solve::SolverStats).
//! There is no second driver: tests, examples and benches run Radau5 the way `linkdyn run`
//! does.
//!
//! **Allocation.** All buffers are allocated by [`Radau5Method::new`]; stepping allocates
//! nothing with the dense LU. The sparse
//! LU's factors keep their capacity between factorisations and grow only when a factor needs
//! more room than before; a formulation's Jacobian may allocate its own scratch.
//!
//! ```
//! use linkdyn::formulation::{Formulation, FormulationError, NoStepHooks};
//! use linkdyn::solve::{Method, SolverOptions, Stepper, Stop};
//!
//! /// y' = −1000 (y − cos t): stiff, y follows cos t closely.
//! struct Stiff;
//! impl NoStepHooks for Stiff {}
//!
//! impl Formulation for Stiff {
//!     fn n_states(&self) -> usize { 1 }
//!     fn initial_state(&self) -> Vec<f64> { vec![0.0] }
//!     fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
//!         dy[0] = -1000.0 * (y[0] - t.cos());
//!         Ok(())
//!     }
//! }
//!
//! let opts = SolverOptions::default().method(Method::Radau5).rtol(1e-8).atol(1e-10).build()?;
//! let mut f = Stiff;
//! let mut s = Stepper::new(&mut f, 0.0, &[0.0], 2.0, &opts)?;
//! while s.step()? != Stop::EndReached {}
//! // y → cos t + sin t / 1000 + O(1e-6) after the transient.
//! assert!((s.y()[0] - (2f64.cos() + 2f64.sin() / 1000.0)).abs() < 1e-5);
//! assert!(s.stats().steps < 200, "stiff: {} steps", s.stats().steps);
//! # Ok::<(), linkdyn::solve::SolveError>(())
//! ```
//!
//! # References
//! 1. E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II: Stiff and
//!    Differential-Algebraic Problems*, 2nd ed., Springer, 1996, Sec. IV.8; Fortran code
//!    `radau5.f` (version of 1996/2002).
//! 2. K. Gustafsson, "Control-theoretic techniques for stepsize selection in implicit
//!    Runge–Kutta methods", *ACM Transactions on Mathematical Software* 20(4), 496–517, 1994.

mod adapter;
mod core;
mod newton;
mod settings;
mod sparse;
mod tableau;

pub use adapter::Radau5Method;
pub use settings::{LinearSolver, Radau5Settings, SPARSE_MIN_STATES};
