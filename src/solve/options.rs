//! [`Method`] and [`SolverOptions`]: which integrator, which tolerances, with written defaults.

use std::fmt;
use std::str::FromStr;

use serde::Serialize;

use super::error::SolveError;
use crate::formulation::Tolerances;

/// The integration method used by the [`Stepper`](crate::solve::Stepper): the one selector for
/// every integrator.
///
/// Names (for [`FromStr`], [`Display`](fmt::Display) and serde): `"dopri5"`, `"dop853"`,
/// `"radau5"`.
///
/// Adding a method is local: a variant here, its row ([`MethodInfo`]: name, orders,
/// description, what it needs from a formulation) in [`Method::info`], the variant in
/// [`Method::ALL`], and one arm in `solve::methods::new_integrator` that builds its
/// [`Integrator`](crate::solve::Integrator). Settings of its own go in a struct of their own in
/// [`SolverOptions`] (as [`ExplicitRkSettings`] and
/// [`Radau5Settings`](crate::solve::radau5::Radau5Settings)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Dormand–Prince 5(4), 7 stages with FSAL (6 RHS calls per step), 4th-order dense output
    /// without extra RHS calls. Good for loose tolerances (rtol ≳ 1e-7).
    Dopri5,
    /// Hairer's DOP853, 8(5,3), 12 stages with FSAL (12 RHS calls per step, 11 for a rejected
    /// one), 7th-order dense output with 3 extra RHS calls per interpolated step. Good for
    /// tight tolerances.
    Dop853,
    /// Radau IIA of order 5 (3 stages), implicit and L-stable, after Hairer & Wanner's RADAU5
    /// ([`crate::solve::radau5`]): simplified Newton iterations with a forward-difference (or
    /// the formulation's analytic) Jacobian, cubic dense output. For stiff phases (sustained
    /// contact).
    Radau5,
    /// SUNDIALS IDA (variable-order BDF, orders 1–5) on the residual form with the Lagrange
    /// multipliers as unknowns ([`crate::solve::ida`]); only in a build with the cargo feature
    /// `ida`. Not in [`Method::ALL`] (which lists the methods of every build).
    #[cfg(feature = "ida")]
    Ida,
}

/// One method's row of the table [`Method::info`]: everything the rest of linkdyn asks about a
/// method, in one place.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MethodInfo {
    /// Name as accepted by [`FromStr`].
    pub name: &'static str,
    /// Classical order p of the propagated solution.
    pub order: u32,
    /// Order of the continuous extension (dense output).
    pub dense_order: u32,
    /// One line describing the method (for `linkdyn run --help`).
    pub description: &'static str,
    /// Whether the method solves a nonlinear system per step (suited to stiff problems).
    pub implicit: bool,
    /// Hairer's default PI-control exponent β (explicit pairs only; see
    /// [`ExplicitRkSettings::beta`]).
    pub default_beta: f64,
    /// Whether the formulation should give the friction law's kinks as event functions, so
    /// that the method's steps end at them (see the formulations' `friction_kink_events`).
    pub friction_kink_events: KinkEvents,
}

/// When a method takes the friction law's kinks as event functions ([`MethodInfo`]). An error
/// estimate made for a smooth right-hand side does not see a change of the force law inside a
/// step; a method whose steps end at events keeps its error proportional to the tolerance
/// there (docs/numerics.md, "Error proportional to tolerance").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KinkEvents {
    /// Always (Radau5 ends every step at an event).
    Always,
    /// Where the method cuts its steps at events ([`ExplicitRkSettings::cut_at_events`], which
    /// the simulation switches off at loose tolerances, where runs are chaotic either way).
    WhereStepsAreCut,
    /// Never (IDA's steps do not end at events: the kinks would only add located events).
    Never,
}

const DOPRI5: MethodInfo = MethodInfo {
    name: "dopri5",
    order: 5,
    dense_order: 4,
    description: "Dormand–Prince 5(4), explicit, 6 RHS calls per step, 4th-order dense output; loose tolerances (rtol ≳ 1e-7)",
    implicit: false,
    default_beta: 0.04,
    friction_kink_events: KinkEvents::WhereStepsAreCut,
};

const DOP853: MethodInfo = MethodInfo {
    name: "dop853",
    order: 8,
    dense_order: 7,
    description: "Hairer's DOP853 8(5,3), explicit, 12 RHS calls per step, 7th-order dense output; tight tolerances (default)",
    implicit: false,
    default_beta: 0.0,
    friction_kink_events: KinkEvents::WhereStepsAreCut,
};

const RADAU5: MethodInfo = MethodInfo {
    name: "radau5",
    order: 5,
    dense_order: 3,
    description: "Radau IIA order 5 (RADAU5), implicit, L-stable, Newton with the formulation's Jacobian (analytic for the reduced model), cubic dense output; stiff contact phases",
    implicit: true,
    default_beta: 0.0,
    friction_kink_events: KinkEvents::Always,
};

#[cfg(feature = "ida")]
const IDA: MethodInfo = MethodInfo {
    name: "ida",
    order: 5,
    dense_order: 5,
    description: IDA_DESCRIPTION,
    implicit: true,
    default_beta: 0.0,
    friction_kink_events: KinkEvents::Never,
};

/// Hairer's tolerance transform of RADAU5: rtol' = 0.1·rtol^(2/3), atol' = atol·rtol'/rtol
/// (the embedded error estimate is of order 3 only; the transform makes the global error
/// roughly proportional to rtol).
pub(crate) fn hairer_transform(rtol: f64, atol: f64) -> (f64, f64) {
    let r = 0.1 * rtol.powf(2.0 / 3.0);
    (r, atol * r / rtol)
}

impl Method {
    /// All methods, in a fixed order (for sweeps in tests and benches).
    pub const ALL: [Method; 3] = [Method::Dopri5, Method::Dop853, Method::Radau5];

    /// The method's row of the table: name, orders, description, what it needs.
    #[must_use]
    pub const fn info(self) -> &'static MethodInfo {
        match self {
            Method::Dopri5 => &DOPRI5,
            Method::Dop853 => &DOP853,
            Method::Radau5 => &RADAU5,
            #[cfg(feature = "ida")]
            Method::Ida => &IDA,
        }
    }

    /// Name as accepted by [`FromStr`].
    #[must_use]
    pub fn name(self) -> &'static str {
        self.info().name
    }

    /// Classical order p of the propagated solution (5 or 8).
    #[must_use]
    pub fn order(self) -> u32 {
        self.info().order
    }

    /// Order of the continuous extension (dense output): 4, 7, or 3 (Radau5).
    #[must_use]
    pub fn dense_order(self) -> u32 {
        self.info().dense_order
    }

    /// Hairer's default PI-control exponent β: 0.04 for DOPRI5, 0 for DOP853 (explicit pairs
    /// only; see [`ExplicitRkSettings::beta`]).
    #[must_use]
    pub fn default_beta(self) -> f64 {
        self.info().default_beta
    }

    /// One line describing the method (for `linkdyn run --help`).
    #[must_use]
    pub fn description(self) -> &'static str {
        self.info().description
    }

    /// Whether the method is implicit (solves a nonlinear system per step: suited to stiff
    /// problems).
    #[must_use]
    pub fn is_implicit(self) -> bool {
        self.info().implicit
    }

    /// The names of all methods as `"a", "b" or "c"` (for messages).
    fn names_list(methods: &[Method]) -> String {
        let quoted: Vec<String> = methods.iter().map(|m| format!("\"{m}\"")).collect();
        match quoted.split_last() {
            None => String::new(),
            Some((last, [])) => last.clone(),
            Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Method {
    type Err = SolveError;

    /// Parses a method name (`"dopri5"`, `"dop853"`; ASCII case ignored). `"ida"` needs a
    /// build with the cargo feature `ida`; without it the error says how to rebuild.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s.trim().eq_ignore_ascii_case("ida") {
            #[cfg(feature = "ida")]
            return Ok(Method::Ida);
            #[cfg(not(feature = "ida"))]
            return Err(SolveError::invalid("method", IDA_NOT_BUILT.to_string()));
        }
        Method::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| {
                SolveError::invalid(
                    "method",
                    format!("expected {}, got \"{s}\"", Method::names_list(&Method::ALL)),
                )
            })
    }
}

/// One line on SUNDIALS IDA, for `linkdyn run --help` (with or without the feature).
pub const IDA_DESCRIPTION: &str = "SUNDIALS IDA: variable-order BDF (1–5) on the residual form with the Lagrange multipliers as unknowns, analytic Jacobian; stiff contact phases (needs a build with --features ida)";

/// Why `--method ida` is refused in a build without the cargo feature `ida`.
pub const IDA_NOT_BUILT: &str = "\"ida\" (SUNDIALS IDA) is not in this build: rebuild with \"cargo build --release --features ida\" (needs cmake and libclang; see the README, \"SUNDIALS IDA (optional)\")";

/// The implicit methods available, as `"a" or "b"` (empty if none), for advice in messages.
pub(crate) fn implicit_methods() -> String {
    let implicit: Vec<Method> = Method::ALL
        .into_iter()
        .filter(|m| m.is_implicit())
        .collect();
    Method::names_list(&implicit)
}

/// Settings of the explicit Runge–Kutta pairs only (ignored by other methods).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExplicitRkSettings {
    /// Exponent β of Hairer's PI step-size controller; `None` uses
    /// [`Method::default_beta`] (0.04 for DOPRI5, 0 for DOP853). β = 0 is the classical
    /// (I-only) controller.
    pub beta: Option<f64>,
    /// Whether an otherwise accepted step across a sign change of an event function is retried
    /// ending just past the crossing (default `true`): the error estimate of a step across a
    /// change of the force law (an impact, a kink of the friction law) does not see the
    /// change, and the state at the event is read from that step's dense output
    /// (docs/numerics.md, "Error proportional to tolerance").
    pub cut_at_events: bool,
}

impl Default for ExplicitRkSettings {
    fn default() -> Self {
        Self {
            beta: None,
            cut_at_events: true,
        }
    }
}

/// Options of a run: those shared by every integrator, plus per-method settings
/// ([`SolverOptions::explicit_rk`]).
///
/// Build them from [`SolverOptions::default`] with the builder methods and finish with
/// [`SolverOptions::build`], which rejects out-of-range values with a message naming the option.
/// Serialised (serde) into result files; `h_max = ∞` is written as `null` by JSON writers.
///
/// ```
/// use linkdyn::solve::{Method, SolverOptions};
/// let opts = SolverOptions::default().method(Method::Dopri5).rtol(1e-6).atol(1e-9).build()?;
/// assert_eq!(opts.rtol, 1e-6);
/// assert!(SolverOptions::default().rtol(0.0).build().is_err());
/// # Ok::<(), linkdyn::solve::SolveError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SolverOptions {
    /// Integration method.
    pub method: Method,
    /// Relative tolerance (dimensionless), in \[10 ε, 0.1\]. The local error of component i is
    /// kept below `atol + rtol·max(|y_i|, |y_new_i|)` in the root-mean-square sense over the
    /// error-controlled components
    /// ([`Formulation::error_controlled`](crate::formulation::Formulation::error_controlled)).
    pub rtol: f64,
    /// Absolute tolerance (units of the state components: m, rad, m/s, rad/s), in (0, 1].
    pub atol: f64,
    /// First step size (s); `None` chooses it with Hairer's `hinit` heuristic.
    pub h0: Option<f64>,
    /// Largest step size (s); `f64::INFINITY` for no limit.
    pub h_max: f64,
    /// Largest number of step attempts (accepted plus rejected) in one run.
    pub max_steps: u64,
    /// Relative event-time tolerance: an event root is bracketed to
    /// |Δt| ≤ `event_tol`·max(1, |t|).
    pub event_tol: f64,
    /// Largest wall-clock time of the run (s); `None`: no limit. Exceeding it is
    /// [`SolveError::WallTimeExceeded`].
    pub max_wall: Option<f64>,
    /// `Some(h)`: fixed step size h (s), no error control (the error estimate is not even
    /// computed). Steps are still shortened to meet `t_end`, `h_max`,
    /// [`Formulation::max_step`](crate::formulation::Formulation::max_step) and restarts at
    /// events. Meant for convergence studies; `None` (adaptive) otherwise.
    pub fixed_step: Option<f64>,
    /// Settings of the explicit Runge–Kutta pairs.
    pub explicit_rk: ExplicitRkSettings,
    /// Settings of Radau5 (Newton iteration, Jacobian reuse, controller).
    pub radau5: crate::solve::radau5::Radau5Settings,
    /// Settings of SUNDIALS IDA (`--method ida`, cargo feature `ida`; ignored otherwise).
    pub ida: IdaSettings,
}

/// Settings of SUNDIALS IDA only (ignored by other methods and without the feature `ida`).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct IdaSettings {
    /// How IDA's iteration matrix ∂F/∂Y + c ∂F/∂Ẏ is factored: IDA's dense LU, or the sparse
    /// LU (faer, `crate::linalg::sparse_lu`) over the residual form's pattern where it has one;
    /// `Auto` takes the sparse one from `solve::ida::SPARSE_MIN_UNKNOWNS` unknowns on
    /// (measured: docs/measurements.md, "IDA with a sparse LU").
    pub linear_solver: crate::solve::radau5::LinearSolver,
}

impl Default for SolverOptions {
    /// The defaults:
    ///
    /// | option | default |
    /// |---|---|
    /// | `method` | [`Method::Dop853`] |
    /// | `rtol` | 1e-8 |
    /// | `atol` | 1e-10 |
    /// | `h0` | `None` (automatic, Hairer's `hinit`) |
    /// | `h_max` | `f64::INFINITY` (no limit) |
    /// | `max_steps` | 10 000 000 |
    /// | `event_tol` | 1e-12 (relative: \|Δt\| ≤ 1e-12·max(1, \|t\|)) |
    /// | `max_wall` | `None` (no limit) |
    /// | `fixed_step` | `None` (adaptive) |
    /// | `explicit_rk.beta` | `None` (0.04 for DOPRI5, 0 for DOP853) |
    /// | `explicit_rk.cut_at_events` | `true` |
    fn default() -> Self {
        Self {
            method: Method::Dop853,
            rtol: 1e-8,
            atol: 1e-10,
            h0: None,
            h_max: f64::INFINITY,
            max_steps: 10_000_000,
            event_tol: 1e-12,
            max_wall: None,
            fixed_step: None,
            explicit_rk: ExplicitRkSettings::default(),
            radau5: crate::solve::radau5::Radau5Settings::default(),
            ida: IdaSettings::default(),
        }
    }
}

/// Smallest accepted `rtol`: below ten machine epsilons the error test cannot be met in f64.
const RTOL_MIN: f64 = 10.0 * f64::EPSILON;
/// Largest accepted `rtol`: above 10 % per step the controller's asymptotic error model
/// (error ∝ h^q) no longer holds and no digit of the result is controlled; `rtol = 1` would
/// accept almost any step.
const RTOL_MAX: f64 = 0.1;
/// Largest accepted `atol`: the states are SI positions, angles and velocities of a linkage,
/// for which an absolute error of 1 (m, rad, m/s) already accepts any answer.
const ATOL_MAX: f64 = 1.0;
/// Smallest accepted `event_tol`: a bracket cannot shrink below a few ulps of t.
const EVENT_TOL_MIN: f64 = 4.0 * f64::EPSILON;

/// A number as a person would type it: plain between 1e-4 and 1e6, else in e-notation.
fn show(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-4..1e6).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

impl SolverOptions {
    /// Default options with a fixed step size h (s); see [`SolverOptions::fixed_step`].
    #[must_use]
    pub fn with_fixed_step(h: f64) -> Self {
        Self::default().fixed_step(h)
    }

    /// Sets the Runge–Kutta pair.
    #[must_use]
    pub fn method(mut self, method: Method) -> Self {
        self.method = method;
        self
    }

    /// The tolerances (rtol, atol) the method's error control actually works with: `rtol`,
    /// `atol` for the explicit pairs (and IDA); for Radau5 with
    /// [`Radau5Settings::hairer_tolerances`](crate::solve::radau5::Radau5Settings::hairer_tolerances)
    /// (the default), Hairer's transform rtol' = 0.1·rtol^(2/3), atol' = atol·rtol'/rtol. What
    /// a formulation bounds by the tolerance (the DAE's constraint violation,
    /// [`violation_limit`](crate::formulation::dae::violation_limit)) is bounded by these: at
    /// rtol 1e-12, Radau5 controls 1e-9, and its measured |Φ| reaches 246 (rtol·L + atol)
    /// with the rtol asked for but 0.25 of the controlled one (docs/numerics.md, "The
    /// constraint-violation bound").
    #[must_use]
    pub fn controlled_tolerances(&self) -> Tolerances {
        let (rtol, atol) = match self.method {
            Method::Radau5 if self.radau5.hairer_tolerances => {
                hairer_transform(self.rtol, self.atol)
            }
            _ => (self.rtol, self.atol),
        };
        Tolerances { rtol, atol }
    }

    /// Sets the relative tolerance.
    #[must_use]
    pub fn rtol(mut self, rtol: f64) -> Self {
        self.rtol = rtol;
        self
    }

    /// Sets the absolute tolerance.
    #[must_use]
    pub fn atol(mut self, atol: f64) -> Self {
        self.atol = atol;
        self
    }

    /// Sets the first step size (s).
    #[must_use]
    pub fn h0(mut self, h0: f64) -> Self {
        self.h0 = Some(h0);
        self
    }

    /// Sets the largest step size (s).
    #[must_use]
    pub fn h_max(mut self, h_max: f64) -> Self {
        self.h_max = h_max;
        self
    }

    /// Sets the largest number of step attempts.
    #[must_use]
    pub fn max_steps(mut self, max_steps: u64) -> Self {
        self.max_steps = max_steps;
        self
    }

    /// Sets the relative event-time tolerance.
    #[must_use]
    pub fn event_tol(mut self, event_tol: f64) -> Self {
        self.event_tol = event_tol;
        self
    }

    /// Sets the settings of Radau5.
    #[must_use]
    pub fn radau5(mut self, settings: crate::solve::radau5::Radau5Settings) -> Self {
        self.radau5 = settings;
        self
    }

    /// Sets the settings of IDA.
    #[must_use]
    pub fn ida(mut self, settings: IdaSettings) -> Self {
        self.ida = settings;
        self
    }

    /// Sets the PI-control exponent β of the explicit pairs (0 ≤ β ≤ 0.2).
    #[must_use]
    pub fn beta(mut self, beta: f64) -> Self {
        self.explicit_rk.beta = Some(beta);
        self
    }

    /// Whether the explicit pairs end a step just past an event crossing
    /// ([`ExplicitRkSettings::cut_at_events`]).
    #[must_use]
    pub fn explicit_cut_at_events(mut self, on: bool) -> Self {
        self.explicit_rk.cut_at_events = on;
        self
    }

    /// Sets the largest wall-clock time of the run (s).
    #[must_use]
    pub fn max_wall(mut self, seconds: f64) -> Self {
        self.max_wall = Some(seconds);
        self
    }

    /// Switches adaptivity off: every step has size h (s) unless `t_end`, `h_max`, the
    /// formulation's `max_step` or an event restart make it shorter. No error estimate is
    /// computed and no step is rejected, so `rtol`, `atol`, `h0` and `beta` are ignored.
    #[must_use]
    pub fn fixed_step(mut self, h: f64) -> Self {
        self.fixed_step = Some(h);
        self
    }

    /// Switches adaptivity back on (undoes [`SolverOptions::fixed_step`]).
    #[must_use]
    pub fn adaptive(mut self) -> Self {
        self.fixed_step = None;
        self
    }

    /// The PI exponent in use: `beta`, or the method's default.
    #[must_use]
    pub fn beta_or_default(&self) -> f64 {
        self.explicit_rk
            .beta
            .unwrap_or_else(|| self.method.default_beta())
    }

    /// Checks every option; the error names the first bad one and what was expected.
    pub fn validate(&self) -> Result<(), SolveError> {
        if !(self.rtol >= RTOL_MIN && self.rtol <= RTOL_MAX) {
            return Err(SolveError::invalid(
                "rtol",
                format!(
                    "expected a relative tolerance in [{RTOL_MIN:.1e}, {RTOL_MAX}] (10 machine epsilons to 10 % per step), got {}",
                    show(self.rtol)
                ),
            ));
        }
        if !(self.atol > 0.0 && self.atol <= ATOL_MAX) {
            return Err(SolveError::invalid(
                "atol",
                format!(
                    "expected an absolute tolerance in (0, {ATOL_MAX}] (units of the states: m, rad, m/s, rad/s), got {}",
                    show(self.atol)
                ),
            ));
        }
        if let Some(h0) = self.h0
            && !(h0.is_finite() && h0 > 0.0)
        {
            return Err(SolveError::invalid(
                "h0",
                format!("expected a finite step size > 0 s, got {h0}"),
            ));
        }
        if self.h_max.is_nan() || self.h_max <= 0.0 {
            return Err(SolveError::invalid(
                "h_max",
                format!(
                    "expected a step size > 0 s (or infinity), got {}",
                    self.h_max
                ),
            ));
        }
        if self.max_steps == 0 {
            return Err(SolveError::invalid(
                "max_steps",
                "expected at least 1, got 0",
            ));
        }
        if !(self.event_tol.is_finite() && self.event_tol >= EVENT_TOL_MIN && self.event_tol < 1.0)
        {
            return Err(SolveError::invalid(
                "event_tol",
                format!(
                    "expected a relative time tolerance in [{EVENT_TOL_MIN:.1e}, 1), got {}",
                    self.event_tol
                ),
            ));
        }
        if let Some(seconds) = self.max_wall
            && !(seconds.is_finite() && seconds > 0.0)
        {
            return Err(SolveError::invalid(
                "max_wall",
                format!("expected a finite wall-clock time > 0 s, got {seconds}"),
            ));
        }
        if let Some(beta) = self.explicit_rk.beta
            && !(0.0..=0.2).contains(&beta)
        {
            return Err(SolveError::invalid(
                "beta",
                format!("expected 0 ≤ beta ≤ 0.2 (Hairer's stable range), got {beta}"),
            ));
        }
        if let Some(h) = self.fixed_step
            && !(h.is_finite() && h > 0.0)
        {
            return Err(SolveError::invalid(
                "fixed_step",
                format!("expected a finite step size > 0 s, got {h}"),
            ));
        }
        self.radau5.validate_knobs()?;
        Ok(())
    }

    /// Validates and returns the options.
    pub fn build(self) -> Result<Self, SolveError> {
        self.validate()?;
        Ok(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn message(opts: SolverOptions) -> String {
        match opts.build() {
            Ok(o) => panic!("options {o:?} should have been rejected"),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn defaults_are_as_documented() {
        let o = SolverOptions::default();
        assert_eq!(o.method, Method::Dop853);
        assert_eq!((o.rtol, o.atol), (1e-8, 1e-10));
        assert_eq!(o.h0, None);
        assert_eq!(o.h_max, f64::INFINITY);
        assert_eq!(o.max_steps, 10_000_000);
        assert_eq!(o.event_tol, 1e-12);
        assert_eq!(o.fixed_step, None);
        assert!(o.build().is_ok());
    }

    #[test]
    fn bad_values_are_rejected_with_the_option_name() {
        let d = SolverOptions::default;
        let cases: Vec<(SolverOptions, &str, &str)> = vec![
            (d().rtol(0.0), "`rtol`", "got 0"),
            (d().rtol(-1e-6), "`rtol`", "got -1e-6"),
            (d().rtol(f64::NAN), "`rtol`", "NaN"),
            (d().rtol(1e-20), "`rtol`", "10 machine epsilons"),
            (d().atol(-1.0), "`atol`", "(0, 1]"),
            (d().atol(f64::INFINITY), "`atol`", "inf"),
            (d().max_wall(0.0), "`max_wall`", "> 0 s"),
            (d().h0(0.0), "`h0`", "> 0 s"),
            (d().h_max(0.0), "`h_max`", "> 0 s"),
            (d().h_max(f64::NAN), "`h_max`", "NaN"),
            (d().max_steps(0), "`max_steps`", "at least 1"),
            (d().event_tol(0.0), "`event_tol`", "relative time tolerance"),
            (d().beta(0.5), "`beta`", "0.2"),
            (d().fixed_step(-0.1), "`fixed_step`", "> 0 s"),
        ];
        for (opts, name, expected) in cases {
            let msg = message(opts);
            assert!(msg.contains(name), "message {msg:?} should name {name}");
            assert!(
                msg.contains(expected),
                "message {msg:?} should contain {expected:?}"
            );
        }
    }

    #[test]
    fn infinite_h_max_and_the_range_ends_are_allowed() {
        let d = SolverOptions::default;
        for opts in [
            d().h_max(f64::INFINITY),
            d().rtol(RTOL_MAX).atol(ATOL_MAX),
            d().rtol(RTOL_MIN).atol(f64::MIN_POSITIVE),
        ] {
            assert!(opts.clone().build().is_ok(), "{opts:?}");
        }
    }

    /// The messages for hostile settings (`--rtol 1`, `--rtol -1`, `--atol 0`, `--atol 1e308`), exactly.
    #[test]
    fn out_of_range_tolerances_have_exact_messages() {
        let rtol = |v| {
            format!(
                "invalid solver option `rtol`: expected a relative tolerance in [2.2e-15, 0.1] (10 machine epsilons to 10 % per step), got {v}"
            )
        };
        let atol = |v| {
            format!(
                "invalid solver option `atol`: expected an absolute tolerance in (0, 1] (units of the states: m, rad, m/s, rad/s), got {v}"
            )
        };
        let d = SolverOptions::default;
        assert_eq!(message(d().rtol(1.0)), rtol("1"));
        assert_eq!(message(d().rtol(-1.0)), rtol("-1"));
        assert_eq!(message(d().atol(0.0)), atol("0"));
        assert_eq!(message(d().atol(1e308)), atol("1e308"));
    }

    #[test]
    fn every_method_has_a_description() {
        for m in Method::ALL {
            assert!(
                !m.description().is_empty() && !m.description().contains('\n'),
                "{m}"
            );
        }
    }

    #[test]
    fn method_names_round_trip() {
        for m in Method::ALL {
            assert_eq!(m.name().parse::<Method>().ok(), Some(m));
            assert_eq!(m.to_string(), m.name());
            assert_eq!(
                serde_json::to_string(&m).ok(),
                Some(format!("\"{}\"", m.name()))
            );
        }
        assert_eq!("DOP853".parse::<Method>().ok(), Some(Method::Dop853));
        let err = "rk4"
            .parse::<Method>()
            .map(|_| ())
            .map_err(|e| e.to_string());
        assert_eq!(
            err,
            Err(
                "invalid solver option `method`: expected \"dopri5\", \"dop853\" or \"radau5\", got \"rk4\""
                    .into()
            )
        );
    }

    #[test]
    fn options_serialise() {
        let json = serde_json::to_string(&SolverOptions::default()).unwrap_or_default();
        assert!(json.contains("\"method\":\"dop853\""), "{json}");
        assert!(json.contains("\"h_max\":null"), "{json}");
    }
}
