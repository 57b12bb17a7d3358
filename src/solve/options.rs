//! [`Method`] and [`SolverOptions`]: which integrator, which tolerances, with written defaults.

use std::fmt;
use std::str::FromStr;

use serde::Serialize;

use super::error::SolveError;

/// Explicit embedded Runge–Kutta pair used by the [`Stepper`](crate::solve::Stepper).
///
/// Names (for [`FromStr`], [`Display`](fmt::Display) and serde): `"dopri5"`, `"dop853"`.
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
}

impl Method {
    /// All methods, in a fixed order (for sweeps in tests and benches).
    pub const ALL: [Method; 2] = [Method::Dopri5, Method::Dop853];

    /// Name as accepted by [`FromStr`].
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Method::Dopri5 => "dopri5",
            Method::Dop853 => "dop853",
        }
    }

    /// Classical order p of the propagated solution (5 or 8).
    #[must_use]
    pub fn order(self) -> u32 {
        match self {
            Method::Dopri5 => 5,
            Method::Dop853 => 8,
        }
    }

    /// Order of the continuous extension (dense output): 4 or 7.
    #[must_use]
    pub fn dense_order(self) -> u32 {
        match self {
            Method::Dopri5 => 4,
            Method::Dop853 => 7,
        }
    }

    /// Hairer's default PI-control exponent β: 0.04 for DOPRI5, 0 for DOP853.
    #[must_use]
    pub fn default_beta(self) -> f64 {
        match self {
            Method::Dopri5 => 0.04,
            Method::Dop853 => 0.0,
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

    /// Parses `"dopri5"` or `"dop853"` (ASCII case ignored).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Method::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| {
                SolveError::invalid(
                    "method",
                    format!("expected \"dopri5\" or \"dop853\", got \"{s}\""),
                )
            })
    }
}

/// Options of the explicit Runge–Kutta integrators.
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
    /// Runge–Kutta pair.
    pub method: Method,
    /// Relative tolerance (dimensionless). The local error of component i is kept below
    /// `atol + rtol·max(|y_i|, |y_new_i|)` in the root-mean-square sense.
    pub rtol: f64,
    /// Absolute tolerance (units of the state components).
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
    /// Exponent β of Hairer's PI step-size controller; `None` uses
    /// [`Method::default_beta`] (0.04 for DOPRI5, 0 for DOP853). β = 0 is the classical
    /// (I-only) controller.
    pub beta: Option<f64>,
    /// `Some(h)`: fixed step size h (s), no error control (the error estimate is not even
    /// computed). Steps are still shortened to meet `t_end`, `h_max`,
    /// [`Formulation::max_step`](crate::formulation::Formulation::max_step) and restarts at
    /// events. Meant for convergence studies; `None` (adaptive) otherwise.
    pub fixed_step: Option<f64>,
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
    /// | `beta` | `None` (0.04 for DOPRI5, 0 for DOP853) |
    /// | `fixed_step` | `None` (adaptive) |
    fn default() -> Self {
        Self {
            method: Method::Dop853,
            rtol: 1e-8,
            atol: 1e-10,
            h0: None,
            h_max: f64::INFINITY,
            max_steps: 10_000_000,
            event_tol: 1e-12,
            beta: None,
            fixed_step: None,
        }
    }
}

/// Smallest accepted `rtol`: below ten machine epsilons the error test cannot be met in f64.
const RTOL_MIN: f64 = 10.0 * f64::EPSILON;
/// Smallest accepted `event_tol`: a bracket cannot shrink below a few ulps of t.
const EVENT_TOL_MIN: f64 = 4.0 * f64::EPSILON;

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

    /// Sets the PI-control exponent β (0 ≤ β ≤ 0.2).
    #[must_use]
    pub fn beta(mut self, beta: f64) -> Self {
        self.beta = Some(beta);
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
        self.beta.unwrap_or_else(|| self.method.default_beta())
    }

    /// Checks every option; the error names the first bad one and what was expected.
    pub fn validate(&self) -> Result<(), SolveError> {
        if !(self.rtol.is_finite() && self.rtol >= RTOL_MIN) {
            return Err(SolveError::invalid(
                "rtol",
                format!(
                    "expected a finite number ≥ {RTOL_MIN:.1e} (10 machine epsilons), got {}",
                    self.rtol
                ),
            ));
        }
        if !(self.atol.is_finite() && self.atol >= 0.0) {
            return Err(SolveError::invalid(
                "atol",
                format!("expected a finite number ≥ 0, got {}", self.atol),
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
        if let Some(beta) = self.beta
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
            (d().rtol(-1e-6), "`rtol`", "got -0.000001"),
            (d().rtol(f64::NAN), "`rtol`", "NaN"),
            (d().rtol(1e-20), "`rtol`", "10 machine epsilons"),
            (d().atol(-1.0), "`atol`", "≥ 0"),
            (d().atol(f64::INFINITY), "`atol`", "inf"),
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
    fn infinite_h_max_and_atol_zero_are_allowed() {
        assert!(
            SolverOptions::default()
                .h_max(f64::INFINITY)
                .atol(0.0)
                .build()
                .is_ok()
        );
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
                "invalid solver option `method`: expected \"dopri5\" or \"dop853\", got \"rk4\""
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
