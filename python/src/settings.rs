//! The solve settings shared by `Model.run` and the analyses (the command line's `SolveArgs`
//! and `--formulation`), turned into the library's options in the command line's order.

use linkdyn::Error;
use linkdyn::simulation::{EndTime, FormulationKind, SimulationOptions};
use linkdyn::solve::{Method, SolveError, SolverOptions};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

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

impl Default for Solve {
    /// The defaults of every method that takes solve settings (the command line's): samples
    /// every 1e-4 s, the DAE, DOP853, rtol 1e-8, atol 1e-10, 1e7 step attempts, no wall-clock
    /// limit.
    fn default() -> Self {
        Solve {
            dt: 1e-4,
            formulation: "dae".to_string(),
            method: "dop853".to_string(),
            rtol: 1e-8,
            atol: 1e-10,
            max_steps: 10_000_000,
            max_wall: None,
        }
    }
}

impl Solve {
    /// The solve settings from the `**solve` keywords of `method` (`run`, `poincare`, …): the
    /// keywords `dt`, `formulation`, `method`, `rtol`, `atol`, `max_steps`, `max_wall`, each optional with the defaults of [`Solve::default`]
    /// (`max_wall` may be `None`). One parser instead of the same seven parameters written
    /// into six signatures (PyO3 has no shared parameter lists). An unknown keyword or a value
    /// of the wrong type raises `TypeError`, as Python does for a declared parameter.
    pub fn from_kwargs(method: &str, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Solve> {
        let mut solve = Solve::default();
        let Some(kwargs) = kwargs else {
            return Ok(solve);
        };
        for (key, value) in kwargs.iter() {
            let key: String = key.extract()?;
            let wrong = |expected: &str| {
                let kind = value
                    .get_type()
                    .name()
                    .map(|n| n.to_string())
                    .unwrap_or_else(|_| "object".into());
                PyTypeError::new_err(format!("{key}=: expected {expected}, got {kind}"))
            };
            match key.as_str() {
                "dt" => solve.dt = value.extract().map_err(|_| wrong("a number (s)"))?,
                "formulation" => {
                    solve.formulation = value.extract().map_err(|_| wrong("a string"))?;
                }
                "method" => solve.method = value.extract().map_err(|_| wrong("a string"))?,
                "rtol" => solve.rtol = value.extract().map_err(|_| wrong("a number"))?,
                "atol" => solve.atol = value.extract().map_err(|_| wrong("a number"))?,
                "max_steps" => {
                    solve.max_steps = value.extract().map_err(|_| wrong("a whole number ≥ 0"))?;
                }
                "max_wall" => {
                    solve.max_wall = value.extract().map_err(|_| wrong("a number (s) or None"))?;
                }
                _ => {
                    return Err(PyTypeError::new_err(format!(
                        "{method}() got an unexpected keyword argument '{key}'"
                    )));
                }
            }
        }
        Ok(solve)
    }

    /// The solve settings of a method whose command defaults to another formulation
    /// (`orbit` and `continue` default to `"reduced"`): [`Solve::from_kwargs`], with
    /// `formulation` set to `default` where the keywords do not give one.
    pub fn from_kwargs_formulation(
        method: &str,
        kwargs: Option<&Bound<'_, PyDict>>,
        default: &str,
    ) -> PyResult<Solve> {
        let mut solve = Solve::from_kwargs(method, kwargs)?;
        let given = match kwargs {
            Some(k) => k.contains("formulation")?,
            None => false,
        };
        if !given {
            solve.formulation = default.to_string();
        }
        Ok(solve)
    }

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
