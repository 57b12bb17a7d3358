//! [`SimulationOptions`]: which equations, how long, how often to sample, which solver — with
//! written defaults — and their validation against a model.

use crate::error::Error;
use crate::mechanics::drivers::driver_angle;
use crate::model::{Driver, DriverMotion, ForceElement, Model};
use crate::solve::{SolveError, SolverOptions};
use serde::Serialize;
use std::f64::consts::TAU;

/// Which equations of motion to integrate.
///
/// Names (for [`FromStr`](std::str::FromStr), [`Display`](std::fmt::Display) and serde):
/// `"dae"`, `"reduced"`, `"generalized"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FormulationKind {
    /// Absolute coordinates, ideal joints as Baumgarte-stabilised constraints (any model):
    /// [`Dae`](crate::formulation::Dae).
    Dae,
    /// The reduced Lagrangian model of the four-bar with one clearance joint (Farahan et al.
    /// 2016): [`ReducedLagrangian`](crate::formulation::ReducedLagrangian).
    Reduced,
    /// Generalised coordinates by coordinate partitioning (any model): independent coordinates
    /// integrated, dependent ones recovered by Newton at every stage, no constraint drift:
    /// [`Generalized`](crate::formulation::Generalized).
    Generalized,
}

impl FormulationKind {
    /// All kinds, in a fixed order.
    pub const ALL: [FormulationKind; 3] = [
        FormulationKind::Dae,
        FormulationKind::Reduced,
        FormulationKind::Generalized,
    ];

    /// Name as accepted by [`FromStr`](std::str::FromStr).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            FormulationKind::Dae => "dae",
            FormulationKind::Reduced => "reduced",
            FormulationKind::Generalized => "generalized",
        }
    }
}

impl std::fmt::Display for FormulationKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for FormulationKind {
    type Err = Error;

    /// Parses `"dae"`, `"reduced"` or `"generalized"` (ASCII case ignored).
    fn from_str(s: &str) -> Result<Self, Error> {
        FormulationKind::ALL
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| {
                Error::settings(
                    "formulation",
                    format!("expected \"dae\", \"reduced\" or \"generalized\", got \"{s}\""),
                )
            })
    }
}

/// How long to integrate.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EndTime {
    /// Until t_end (s).
    Seconds(f64),
    /// For this many turns of the model's single driver: t_end = 2π·turns/|ω| (ω in rad/s).
    DriverTurns(f64),
}

/// Settings of a [`Simulation`](super::Simulation), with written defaults.
///
/// Build from [`SimulationOptions::default`] with the builder methods; everything is checked
/// against the model by [`Simulation::new`](super::Simulation::new) before any work.
/// `--set` overrides are not options: they are applied by [`model::load`](crate::model::load)
/// and recorded in the model's [`ModelSource`](crate::model::ModelSource), from which the
/// provenance takes them.
///
/// ```
/// use linkdyn::simulation::{EndTime, FormulationKind, SimulationOptions};
/// let o = SimulationOptions::default().t_end(0.5).dt(1e-3);
/// assert_eq!(o.end, EndTime::Seconds(0.5));
/// assert_eq!(o.formulation, FormulationKind::Dae);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SimulationOptions {
    /// Equations of motion.
    pub formulation: FormulationKind,
    /// Integrate the energy bookkeeping too (DAE and generalized only): adds the `energy.*` columns and the
    /// work–energy balance of the summary.
    pub energy: bool,
    /// How long to integrate.
    pub end: EndTime,
    /// Output interval (s): samples at t0 + k·dt from the dense output (see
    /// [`integrate`](fn@crate::solve::integrate)).
    pub dt: f64,
    /// Integrator, tolerances, step limits.
    pub solver: SolverOptions,
}

impl Default for SimulationOptions {
    /// The defaults:
    ///
    /// | option | default |
    /// |---|---|
    /// | `formulation` | [`FormulationKind::Dae`] |
    /// | `energy` | `false` |
    /// | `end` | [`EndTime::DriverTurns`]`(2.0)` (needs a model with one driver) |
    /// | `dt` | 1e-4 s |
    /// | `solver` | [`SolverOptions::default`] (DOP853, rtol 1e-8, atol 1e-10, …) |
    fn default() -> Self {
        SimulationOptions {
            formulation: FormulationKind::Dae,
            energy: false,
            end: EndTime::DriverTurns(2.0),
            dt: 1e-4,
            solver: SolverOptions::default(),
        }
    }
}

impl SimulationOptions {
    /// Sets the equations of motion.
    #[must_use]
    pub fn formulation(mut self, kind: FormulationKind) -> Self {
        self.formulation = kind;
        self
    }

    /// Switches the energy bookkeeping on or off (DAE only).
    #[must_use]
    pub fn energy(mut self, energy: bool) -> Self {
        self.energy = energy;
        self
    }

    /// Integrates until t_end (s).
    #[must_use]
    pub fn t_end(mut self, t_end: f64) -> Self {
        self.end = EndTime::Seconds(t_end);
        self
    }

    /// Integrates for this many turns of the model's single driver.
    #[must_use]
    pub fn revs(mut self, turns: f64) -> Self {
        self.end = EndTime::DriverTurns(turns);
        self
    }

    /// Sets the output interval (s).
    #[must_use]
    pub fn dt(mut self, dt: f64) -> Self {
        self.dt = dt;
        self
    }

    /// Sets the solver options.
    #[must_use]
    pub fn solver(mut self, solver: SolverOptions) -> Self {
        self.solver = solver;
        self
    }
}

/// Most values (samples × (columns + 1), the time included) one run may produce: 1e9, i.e.
/// 8 GB as f64 in a [`Trajectory`](super::Trajectory) and about 20 GB of CSV (about 20 bytes
/// a number). A run asking for more is refused before it starts.
pub const MAX_OUTPUT_VALUES: f64 = 1e9;

/// End time (s) of `end` for `model`.
///
/// Turns count the driven angle θ(t) of the model's single kinematic driver: t_end = 2π·turns/|ω|
/// for a constant speed ω and for a speed ramp (at its final speed ω1, as documented in
/// docs/model_format.md); for a prescribed angle, the first time at which |θ(t) − θ(0)| reaches
/// 2π·turns (`prescribed_turns_time`). A torque driver's angle is an outcome of the run, not
/// known before it: such a model is refused with the advice to give `t_end`.
pub fn end_time(model: &Model, end: EndTime) -> Result<f64, Error> {
    let t = match end {
        EndTime::Seconds(t) => t,
        EndTime::DriverTurns(turns) => driver_turns_time(model, turns)?,
    };
    if !(t.is_finite() && t > 0.0) {
        return Err(Error::settings(
            "t_end",
            format!("expected a positive, finite end time, got {t} s"),
        ));
    }
    Ok(t)
}

/// t_end for `turns` turns of the single kinematic driver (see [`end_time`]).
fn driver_turns_time(model: &Model, turns: f64) -> Result<f64, Error> {
    let motors: Vec<&str> = model
        .forces
        .iter()
        .filter(|f| matches!(f, ForceElement::Motor { .. }))
        .map(ForceElement::name)
        .collect();
    let [driver] = model.drivers.as_slice() else {
        if let ([], [motor]) = (model.drivers.as_slice(), motors.as_slice()) {
            return Err(Error::settings(
                "revs",
                format!(
                    "driver \"{motor}\" is a torque driver: how far its crank turns is an outcome of the run, not known before it; give `t_end` (and read the turns from the joint's angle in the results)"
                ),
            ));
        }
        return Err(Error::settings(
            "revs",
            format!(
                "counts turns of the single driver, but model \"{}\" has {} drivers: give `t_end`",
                model.name,
                model.drivers.len()
            ),
        ));
    };
    if !(turns.is_finite() && turns > 0.0) {
        return Err(Error::settings(
            "revs",
            format!("expected a positive, finite number of turns, got {turns}"),
        ));
    }
    if let DriverMotion::PrescribedAngle(expression) = &driver.motion {
        return prescribed_turns_time(driver, turns).map_err(|reason| {
            Error::settings(
                "revs",
                format!(
                    "driver \"{}\" prescribes θ(t) = {}: {reason}; give `t_end` instead",
                    driver.name, expression.text
                ),
            )
        });
    }
    if driver.speed == 0.0 {
        return Err(Error::settings(
            "revs",
            format!(
                "driver \"{}\" has zero speed: give `t_end` instead",
                driver.name
            ),
        ));
    }
    Ok(turns * TAU / driver.speed.abs())
}

/// Largest time (s) searched for the turns of a prescribed angle: 1e6 s (11.6 days), far
/// beyond any run this tool makes.
pub const PRESCRIBED_TURNS_HORIZON: f64 = 1e6;

/// Largest angle change (rad) per search step, estimated from θ̇: 0.05 rad, so that a
/// crossing of the target and back within one step needs |θ̈| h² ≳ 0.1 rad.
const SEARCH_ANGLE_STEP: f64 = 0.05;

/// Most search steps (a θ(t) that crawls is refused after these).
const MAX_SEARCH_STEPS: usize = 1_000_000;

/// The first time t > 0 at which |θ(t) − θ(0)| = 2π·turns for a prescribed angle θ(t):
/// marched from t = 0 with steps of at most 0.05 rad of angle (estimated from the exact θ̇ of
/// the expression's jet, each step at most doubling the last, from 1e-6 s), up to
/// [`PRESCRIBED_TURNS_HORIZON`] or 1e6 steps, whichever comes first; the crossing is then
/// bisected to the resolution of t.
/// Err: why no such time was found (θ stays below the target, or is not finite).
pub fn prescribed_turns_time(driver: &Driver, turns: f64) -> Result<f64, String> {
    let target = turns * TAU;
    let theta0 = driver_angle(driver, 0.0)[0];
    let travelled = |t: f64| (driver_angle(driver, t)[0] - theta0).abs();
    let (mut t, mut h, mut reached) = (0.0_f64, 1e-6_f64, 0.0_f64);
    for _ in 0..MAX_SEARCH_STEPS {
        let [theta, omega, _] = driver_angle(driver, t);
        if !(theta.is_finite() && omega.is_finite()) {
            return Err(format!("θ or θ̇ is not finite at t = {t} s"));
        }
        let by_angle = if omega == 0.0 {
            f64::INFINITY
        } else {
            SEARCH_ANGLE_STEP / omega.abs()
        };
        h = by_angle.min(2.0 * h).max(1e-9);
        let next = (t + h).min(PRESCRIBED_TURNS_HORIZON);
        let d = travelled(next);
        if d >= target {
            // Bisection on [t, next]: |θ − θ0| < target at t, ≥ target at next.
            let (mut lo, mut hi) = (t, next);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                if travelled(mid) >= target {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            return Ok(hi);
        }
        reached = reached.max(d);
        if next >= PRESCRIBED_TURNS_HORIZON {
            break;
        }
        t = next;
    }
    Err(format!(
        "|θ(t) − θ(0)| does not reach {turns} turn(s) ({target:.6} rad) by t = {t:.6e} s, where the search stopped (at most {reached:.6} rad)"
    ))
}

/// Checks the output interval and the output size of a run of `columns` columns to `t_end`.
pub fn check_sampling(t_end: f64, dt: f64, columns: usize) -> Result<(), Error> {
    if !(dt.is_finite() && dt > 0.0) {
        return Err(Error::settings(
            "dt",
            format!("expected a positive time step, got {dt}"),
        ));
    }
    let samples = (t_end / dt).floor() + 1.0;
    let values = samples * (columns as f64 + 1.0);
    if values > MAX_OUTPUT_VALUES {
        return Err(Error::settings(
            "dt",
            format!(
                "{dt:e} s over {t_end:e} s asks for {samples:.3e} samples × {} columns = {values:.3e} values; at most {MAX_OUTPUT_VALUES:e} are allowed: raise `dt`",
                columns + 1
            ),
        ));
    }
    Ok(())
}

/// Validated solver options; an out-of-range option becomes [`Error::Settings`] naming it.
pub fn check_solver(solver: &SolverOptions) -> Result<SolverOptions, Error> {
    solver.clone().build().map_err(|e| match e {
        SolveError::InvalidOption { option, reason } => Error::Settings { option, reason },
        other => Error::Solve(other),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn message(r: Result<impl std::fmt::Debug, Error>) -> String {
        match r {
            Ok(v) => format!("accepted {v:?}"),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn bad_sampling_is_refused_naming_the_option() {
        assert_eq!(
            message(check_sampling(1.0, -1.0, 3)),
            "dt: expected a positive time step, got -1"
        );
        assert_eq!(
            message(check_sampling(1.0, f64::NAN, 3)),
            "dt: expected a positive time step, got NaN"
        );
        // 1e6 s at 1e-4 s with 9 columns: 1e10 + 1 samples × 10 values > 1e9.
        assert_eq!(
            message(check_sampling(1e6, 1e-4, 9)),
            "dt: 1e-4 s over 1e6 s asks for 1.000e10 samples × 10 columns = 1.000e11 values; at most 1e9 are allowed: raise `dt`"
        );
        assert!(check_sampling(1.0, 1e-4, 40).is_ok());
    }

    #[test]
    fn formulation_names_round_trip() {
        for k in FormulationKind::ALL {
            assert_eq!(k.name().parse::<FormulationKind>().ok(), Some(k));
        }
        assert_eq!(
            message("lagrange".parse::<FormulationKind>()),
            "formulation: expected \"dae\", \"reduced\" or \"generalized\", got \"lagrange\""
        );
    }

    #[test]
    fn bad_solver_option_names_the_option() {
        assert!(message(check_solver(&SolverOptions::default().rtol(-1.0))).starts_with("rtol: "));
        assert!(message(check_solver(&SolverOptions::default().atol(-1.0))).starts_with("atol: "));
    }
}
