//! [`Radau5Settings`] (the knobs of the Newton iteration and step control that
//! [`SolverOptions`](crate::solve::SolverOptions) does not have).

use serde::Serialize;

use crate::solve::SolveError;

/// Settings specific to [`Radau5Method`](super::Radau5Method), with Hairer's defaults from `radau5.f`
/// (used with error control; fixed-step mode iterates Newton to rounding level instead).
///
/// | setting | default | Hairer's name |
/// |---|---|---|
/// | `max_newton_iter` | 7 | `NIT` |
/// | `theta_jac` | 0.001 | `THET` |
/// | `safety` | 0.9 | `SAFE` |
/// | `keep_h_range` | (1.0, 1.2) | `QUOT1`, `QUOT2` |
/// | `h_ratio_range` | (0.2, 8.0) | `1/FACL`, `1/FACR` |
/// | `predictive` | true (Gustafsson) | `PRED` |
/// | `newton_tol` | `None`: max(10u/rtol', min(0.03, √rtol')) | `FNEWT` |
/// | `hairer_tolerances` | true | (the transform in `RADAU5`) |
/// | `error_mask` | `None`: every component is error-controlled | — |
/// | `cut_at_events` | true | — |
/// | `linear_solver` | [`LinearSolver::Auto`] | (`MLJAC`, `MUJAC`: banded) |
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Radau5Settings {
    /// Largest number of simplified Newton iterations per step attempt.
    pub max_newton_iter: usize,
    /// The Jacobian is re-evaluated after an accepted step unless the Newton contraction rate θ
    /// of that step was ≤ `theta_jac`. Hairer advises 0.1 when Jacobians are expensive
    /// relative to RHS calls (forward differences cost n RHS calls).
    pub theta_jac: f64,
    /// Safety factor of the step-size prediction.
    pub safety: f64,
    /// If the proposed h_new/h lies in this range (and θ ≤ `theta_jac`), h is kept so that the
    /// LU factors can be reused.
    pub keep_h_range: (f64, f64),
    /// Bounds of h_new/h after a step.
    pub h_ratio_range: (f64, f64),
    /// Gustafsson's predictive step-size controller (else the classical one).
    pub predictive: bool,
    /// Stopping tolerance κ·tol of the Newton iteration, relative to the error scale;
    /// `None` for Hairer's default.
    pub newton_tol: Option<f64>,
    /// Hairer's tolerance transform: the code works with rtol' = 0.1·rtol^{2/3} and
    /// atol' = atol·rtol'/rtol, so that the global error is roughly proportional to rtol
    /// (the embedded estimate is of order 3 only).
    pub hairer_tolerances: bool,
    /// `Some(mask)`: only components i with `mask[i] == true` enter the error and Newton
    /// norms (bookkeeping states such as accumulated work or a stored impact velocity are
    /// left out). Length n.
    pub error_mask: Option<Vec<bool>>,
    /// With error control: an accepted attempt across which an event function
    /// ([`Formulation::events`](crate::formulation::Formulation::events)) changes sign is
    /// retried once, ending just past the crossing, so that the law that changes at the event
    /// does not enter the polynomial the event state is read from (see `core.rs`). A crossing
    /// in the first or the last 1 % of the attempt is left uncut: the other law holds on a
    /// sliver only, and a cut near the start would shrink the step to that sliver.
    pub cut_at_events: bool,
    /// How the Newton matrices are factored: dense LU of J, or sparse LU of the formulation's
    /// augmented Jacobian ([`LinearSolver`]).
    pub linear_solver: LinearSolver,
}

/// How Radau5 factors its Newton matrices γ̂/h·I − J and (α̂ + iβ̂)/h·I − J.
///
/// The dense LU (`linalg.rs`) of the n × n Jacobian costs O(n³) per factorisation and the
/// Jacobian itself O(n²) or more to form; the sparse one (`sparse.rs`, faer) factors the
/// formulation's augmented Jacobian
/// ([`Formulation::sparse_jacobian`](crate::formulation::Formulation::sparse_jacobian)), whose
/// cost grows with its non-zeros. Both solve the same linear systems; the results agree to
/// round-off (`tests/radau5_sparse_newton.rs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum LinearSolver {
    /// Sparse when the formulation gives a sparse Jacobian and has at least
    /// [`SPARSE_MIN_STATES`] states, dense otherwise (the default).
    #[default]
    Auto,
    /// Always the dense LU of [`Formulation::jacobian`](crate::formulation::Formulation::jacobian).
    Dense,
    /// The sparse LU whenever the formulation gives a sparse Jacobian (dense otherwise).
    Sparse,
}

/// Fewest states for which [`LinearSolver::Auto`] takes the sparse LU. Measured per accepted
/// Radau5 step on the N-four-bar chain (DAE, `models/nfourbar_chain.toml`, 0.5 s at rtol 1e-8,
/// best of 3 runs, `cargo run --release --example radau5_sparse_scaling`, one sitting on the
/// 2-core machine shared with two other builds, load average ≈ 5; docs/measurements.md, "Radau5
/// with a sparse LU"), dense against sparse: 0.015 / 0.029 ms at 18 states (1 loop), 0.040 /
/// 0.045 ms at 30 (2 loops), 0.081 / 0.066 ms at 42 (3 loops), 0.13 / 0.088 ms at 54, 0.34 /
/// 0.10 ms at 66, 1.9 / 0.21 ms at 126 (10 loops), 98 / 1.1 ms at 486 (40 loops); best of 15
/// in another sitting, 0.039 / 0.046 ms at 30 states and 0.073 / 0.064 ms at 42. The two cross
/// between 30 and 42 states. Every shipped model but the chains has at most 5 bodies (30
/// states, 33 with energy bookkeeping) and keeps the dense LU and its arithmetic.
pub const SPARSE_MIN_STATES: usize = 40;

impl Default for Radau5Settings {
    fn default() -> Self {
        Radau5Settings {
            max_newton_iter: 7,
            theta_jac: 0.001,
            safety: 0.9,
            keep_h_range: (1.0, 1.2),
            h_ratio_range: (0.2, 8.0),
            predictive: true,
            newton_tol: None,
            hairer_tolerances: true,
            error_mask: None,
            cut_at_events: true,
            linear_solver: LinearSolver::Auto,
        }
    }
}

impl Radau5Settings {
    /// Sets `theta_jac`.
    #[must_use]
    pub fn theta_jac(mut self, theta: f64) -> Self {
        self.theta_jac = theta;
        self
    }

    /// Sets `max_newton_iter`.
    #[must_use]
    pub fn max_newton_iter(mut self, nit: usize) -> Self {
        self.max_newton_iter = nit;
        self
    }

    /// Sets the error mask (`true` = error-controlled).
    #[must_use]
    pub fn error_mask(mut self, mask: Vec<bool>) -> Self {
        self.error_mask = Some(mask);
        self
    }

    /// Switches Gustafsson's predictive controller on or off.
    #[must_use]
    pub fn predictive(mut self, on: bool) -> Self {
        self.predictive = on;
        self
    }

    /// Switches the cut of steps at event crossings on or off.
    #[must_use]
    pub fn cut_at_events(mut self, on: bool) -> Self {
        self.cut_at_events = on;
        self
    }

    /// Sets how the Newton matrices are factored.
    #[must_use]
    pub fn linear_solver(mut self, solver: LinearSolver) -> Self {
        self.linear_solver = solver;
        self
    }

    /// Switches Hairer's tolerance transform on or off.
    #[must_use]
    pub fn hairer_tolerances(mut self, on: bool) -> Self {
        self.hairer_tolerances = on;
        self
    }

    /// Checks every setting for a system of `n` states; the error names the first bad one.
    pub fn validate(&self, n: usize) -> Result<(), SolveError> {
        self.validate_knobs()?;
        if let Some(mask) = &self.error_mask
            && mask.len() != n
        {
            return Err(SolveError::StateLength {
                what: "error mask",
                expected: n,
                got: mask.len(),
            });
        }
        Ok(())
    }

    /// Checks every setting but the error mask (whose length depends on the formulation).
    pub fn validate_knobs(&self) -> Result<(), SolveError> {
        if self.max_newton_iter == 0 {
            return Err(SolveError::invalid(
                "max_newton_iter",
                "expected at least 1, got 0",
            ));
        }
        if !(self.theta_jac.is_finite() && self.theta_jac < 1.0) {
            return Err(SolveError::invalid(
                "theta_jac",
                format!("expected a number < 1, got {}", self.theta_jac),
            ));
        }
        if !(self.safety > 0.001 && self.safety < 1.0) {
            return Err(SolveError::invalid(
                "safety",
                format!("expected 0.001 < safety < 1, got {}", self.safety),
            ));
        }
        let (q1, q2) = self.keep_h_range;
        if !(q1 <= 1.0 && q2 >= 1.0) {
            return Err(SolveError::invalid(
                "keep_h_range",
                format!("expected (≤ 1, ≥ 1), got ({q1}, {q2})"),
            ));
        }
        let (lo, hi) = self.h_ratio_range;
        if !(lo > 0.0 && lo <= 1.0 && hi >= 1.0 && hi.is_finite()) {
            return Err(SolveError::invalid(
                "h_ratio_range",
                format!("expected (0 < lo ≤ 1, finite hi ≥ 1), got ({lo}, {hi})"),
            ));
        }
        if let Some(tol) = self.newton_tol
            && !(tol.is_finite() && tol > 0.0)
        {
            return Err(SolveError::invalid(
                "newton_tol",
                format!("expected a finite number > 0, got {tol}"),
            ));
        }
        Ok(())
    }
}
