//! The solve settings shared by `Model.run` and the analyses (the command line's `SolveArgs`
//! and `--formulation`), turned into the library's options in the command line's order.

use linkdyn::Error;
use linkdyn::simulation::{EndTime, FormulationKind, SimulationOptions};
use linkdyn::solve::{Method, SolveError, SolverOptions};
use pyo3::prelude::*;
use pyo3::types::PyString;

/// Sampling, formulation and solver settings, as given from Python.
pub struct Solve {
    /// Output sample interval (s).
    pub dt: f64,
    /// `"dae"` or `"reduced"`.
    pub formulation: String,
    /// Integration method name (`"dop853"`, `"dopri5"`, …).
    pub method: String,
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
    /// Most step attempts.
    pub max_steps: u64,
    /// Wall-clock budget of each integration (s), if any.
    pub max_wall: Option<f64>,
}

impl Solve {
    /// The library's options, checked as the command line checks them (the method first, then
    /// the formulation; the rest in `Simulation::new`). The end time is the default (2 turns).
    pub fn options(&self) -> Result<SimulationOptions, Error> {
        let method: Method = self.method.parse().map_err(|e| match e {
            SolveError::InvalidOption { option, reason } => Error::Settings { option, reason },
            other => Error::Solve(other),
        })?;
        let formulation: FormulationKind = self.formulation.parse()?;
        let solver = SolverOptions::default()
            .method(method)
            .rtol(self.rtol)
            .atol(self.atol)
            .max_steps(self.max_steps);
        let solver = match self.max_wall {
            Some(seconds) => solver.max_wall(seconds),
            None => solver,
        };
        Ok(SimulationOptions::default()
            .dt(self.dt)
            .solver(solver)
            .formulation(formulation))
    }

    /// The options of an analysis integrating `turns` driver turns.
    pub fn for_turns(&self, turns: f64) -> Result<SimulationOptions, Error> {
        Ok(SimulationOptions {
            end: EndTime::DriverTurns(turns),
            ..self.options()?
        })
    }
}

/// Driver turns of an analysis counted in whole turns (`poincare`, `bifurcation`): `revs` as a
/// whole number ≥ 1, `default` if not given (the command line's `whole_turns`).
pub fn whole_turns(revs: Option<f64>, default: usize) -> Result<usize, Error> {
    match revs {
        None => Ok(default),
        Some(r) if r.is_finite() && r >= 1.0 && r.fract() == 0.0 && r < 1e9 => Ok(r as usize),
        Some(r) => Err(Error::settings(
            "revs",
            format!("expected a whole number of turns ≥ 1, got {r}"),
        )),
    }
}

/// A count of transient turns given as a Python int (the command line takes only whole
/// numbers ≥ 0 there).
pub fn whole_transient(transient: i64) -> Result<usize, Error> {
    usize::try_from(transient).map_err(|_| {
        Error::settings(
            "transient",
            format!("expected a whole number of turns ≥ 0, got {transient}"),
        )
    })
}

/// Driver turns of an analysis over a window after `transient` turns (`spectrum`, `phase`,
/// `lyapunov`): `revs`, default transient + 10, more than the transient (the command line's
/// `window_turns`).
pub fn window_turns(revs: Option<f64>, transient: f64) -> Result<f64, Error> {
    if !(transient.is_finite() && transient >= 0.0) {
        return Err(Error::settings(
            "transient",
            format!("expected turns ≥ 0, got {transient}"),
        ));
    }
    let turns = revs.unwrap_or(transient + 10.0);
    if !turns.is_finite() || turns <= transient {
        return Err(Error::settings(
            "revs",
            format!("expected more turns than the {transient} transient turns, got {turns}"),
        ));
    }
    Ok(turns)
}

/// Output column names from `observe`: a string (`"B.ex,B.ey"`, split at commas as
/// `--observe` is) or a sequence of strings (each may hold commas too). `None`: none.
pub fn columns(observe: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<String>> {
    let Some(o) = observe else {
        return Ok(Vec::new());
    };
    let given: Vec<String> = if o.is_instance_of::<PyString>() {
        vec![o.extract()?]
    } else {
        o.try_iter()
            .map_err(|_| observe_type_error(o))?
            .map(|item| item.and_then(|i| i.extract::<String>()))
            .collect::<PyResult<_>>()
            .map_err(|_| observe_type_error(o))?
    };
    Ok(given
        .iter()
        .flat_map(|o| o.split(','))
        .map(|c| c.trim().to_string())
        .filter(|c| !c.is_empty())
        .collect())
}

fn observe_type_error(o: &Bound<'_, PyAny>) -> PyErr {
    let kind = o
        .get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "object".into());
    pyo3::exceptions::PyTypeError::new_err(format!(
        "observe=: expected a column name, a comma-separated string or a list of names, got {kind}"
    ))
}
