//! Library errors → the exceptions of `linkdyn._errors`, with the command line's messages.
//!
//! | library error | exception | CLI exit code |
//! |---|---|---|
//! | `Error::Model` | `ModelError` (attributes `file`, `line`, `column`, `field` where known) | 2 |
//! | `Error::Formulation` (before a run: the linkage cannot be assembled or does not fit the formulation) | `ModelError` | 2 |
//! | `Error::Settings` | `SettingsError` (attribute `option`) | 2 |
//! | `Error::Solve` | `SolverError` (attribute `time`) | 3 |
//! | `Error::Output`, a failing sample sink | `OutputError` | 4 (2 for a refused target) |
//! | `Error::Analysis`: the integration or the outputs behind an analysis failed | `SolverError` (attribute `time`) | 3 |
//! | `Error::Analysis`: no periodic orbit found (`orbit`, `continuation`) | `SolverError` (`time` None, `residual_history`) | 3 |
//! | `Error::Analysis`, any other (too few samples, a bad grid …) | `AnalysisError` | 2 |
//!
//! Messages are the CLI's (`linkdyn/src/cli/mod.rs`, `message`): the error and each cause
//! not already in it, joined by `": "`; a formulation error met while building a simulation
//! is prefixed with the model file as given. The one difference: a settings error names
//! options as the library does (`dt`, `` `t_end` ``) where the CLI spells them as flags
//! (`--dt`, `--t-end`). A failed sweep point is prefixed as on the command line,
//! `point I (PARAM = VALUE): `, and carries the attributes `point` and `parameter`.

use linkdyn::Error;
use linkdyn::analysis::AnalysisError;
use linkdyn::model::ModelError;
use linkdyn::solve::SolveError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The message of `e`, as the command line prints it after `error: ` (settings aside, see
/// the module doc).
pub fn message(e: &Error) -> String {
    let mut message = e.to_string();
    let mut cause = std::error::Error::source(e);
    while let Some(c) = cause {
        let text = c.to_string();
        if !message.contains(&text) {
            message.push_str(": ");
            message.push_str(&text);
        }
        cause = c.source();
    }
    message
}

/// The time a solver error happened at (s), where it has one.
fn solve_time(e: &SolveError) -> Option<f64> {
    match e {
        SolveError::StepTooSmall { t, .. }
        | SolveError::TooManySteps { t, .. }
        | SolveError::NonFinite { t, .. }
        | SolveError::Formulation { t, .. }
        | SolveError::Sink { t, .. }
        | SolveError::EventNotConverged { t, .. }
        | SolveError::InvalidMaxStep { t, .. }
        | SolveError::OutsideStep { t, .. }
        | SolveError::MethodFailed { t, .. } => Some(*t),
        _ => None,
    }
}

/// The Python exception for `e`; `model_path` (the model file as given) prefixes formulation
/// errors as the command line does.
pub fn to_py(py: Python<'_>, e: Error, model_path: Option<&str>) -> PyErr {
    to_py_with(py, &e, model_path, None, None)
}

/// The Python exception for `e` with `prefix` before its message (the command line's
/// `--param PATH: ` of a sweep's first point, say) and extra attributes `attrs`.
pub fn to_py_with(
    py: Python<'_>,
    e: &Error,
    model_path: Option<&str>,
    prefix: Option<&str>,
    attrs: Option<&Bound<'_, PyDict>>,
) -> PyErr {
    match build(py, e, model_path, prefix, attrs) {
        Ok(err) => err,
        // The exception classes could not be reached (a broken installation): still raise,
        // with the same message.
        Err(other) => {
            let text = format!("{} (and linkdyn._errors failed: {other})", message(e));
            pyo3::exceptions::PyRuntimeError::new_err(text)
        }
    }
}

fn build(
    py: Python<'_>,
    e: &Error,
    model_path: Option<&str>,
    prefix: Option<&str>,
    extra: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyErr> {
    let attrs = PyDict::new(py);
    if let Some(extra) = extra {
        attrs.update(extra.as_mapping())?;
    }
    let (class, text) = match e {
        Error::Model(m) => {
            if let ModelError::Invalid {
                file,
                line,
                column,
                field,
                ..
            } = m
            {
                attrs.set_item("file", file)?;
                attrs.set_item("line", line)?;
                attrs.set_item("column", column)?;
                attrs.set_item("field", field)?;
            } else if let ModelError::Io { file, .. } | ModelError::WholeFile { file, .. } = m {
                attrs.set_item("file", file)?;
            }
            ("ModelError", message(e))
        }
        Error::Formulation(_) => {
            if let Some(p) = model_path {
                attrs.set_item("file", p)?;
            }
            let text = match model_path {
                Some(p) => format!("{p}: {}", message(e)),
                None => message(e),
            };
            ("ModelError", text)
        }
        Error::Settings { option, .. } => {
            attrs.set_item("option", option)?;
            ("SettingsError", message(e))
        }
        Error::Solve(SolveError::Sink { t, .. }) => {
            attrs.set_item("time", t)?;
            ("OutputError", message(e))
        }
        Error::Solve(s) => {
            attrs.set_item("time", solve_time(s))?;
            ("SolverError", message(e))
        }
        Error::Output(_) => ("OutputError", message(e)),
        Error::Analysis(AnalysisError::Solve { source, .. }) => {
            attrs.set_item("time", solve_time(source))?;
            ("SolverError", message(e))
        }
        Error::Analysis(AnalysisError::Outputs { t, .. }) => {
            attrs.set_item("time", t)?;
            ("SolverError", message(e))
        }
        // No periodic orbit found: the method failed on valid input (the CLI's exit 3), with
        // the residual history in the message and as `residual_history`.
        Error::Analysis(AnalysisError::NoConvergence { history, .. }) => {
            attrs.set_item("time", None::<f64>)?;
            attrs.set_item("residual_history", history.clone())?;
            ("SolverError", message(e))
        }
        Error::Analysis(_) => ("AnalysisError", message(e)),
    };
    let text = match prefix {
        Some(p) => format!("{p}: {text}"),
        None => text,
    };
    let class = py.import("linkdyn._errors")?.getattr(class)?;
    let value = class.call1((text,))?;
    for (k, v) in attrs.iter() {
        value.setattr(k.str()?, v)?;
    }
    Ok(PyErr::from_value(value))
}

/// A library error met without the GIL, carried out of `py.detach` (boxed: `linkdyn::Error` is
/// large and the Ok path should not pay for it) with how the command line would print it.
pub struct Failed(Box<FailedInner>);

struct FailedInner {
    error: Error,
    /// Met while building a simulation: a formulation error is prefixed with the model file.
    building: bool,
    /// Text before the message (`param PATH` for a sweep's first point).
    prefix: Option<String>,
}

impl Failed {
    /// An error met while building a simulation of the model (see [`to_py`]).
    pub fn building(error: Error) -> Self {
        Failed(Box::new(FailedInner {
            error,
            building: true,
            prefix: None,
        }))
    }

    /// An error printed with `prefix: ` in front.
    pub fn prefixed(error: Error, prefix: String) -> Self {
        Failed(Box::new(FailedInner {
            error,
            building: false,
            prefix: Some(prefix),
        }))
    }

    /// The Python exception; `model_path` is the model file as given to `load`.
    pub fn into_py(self, py: Python<'_>, model_path: &str) -> PyErr {
        let f = *self.0;
        let path = f.building.then_some(model_path);
        to_py_with(py, &f.error, path, f.prefix.as_deref(), None)
    }
}

impl From<Error> for Failed {
    fn from(error: Error) -> Self {
        Failed(Box::new(FailedInner {
            error,
            building: false,
            prefix: None,
        }))
    }
}

impl From<AnalysisError> for Failed {
    fn from(error: AnalysisError) -> Self {
        Failed::from(Error::from(error))
    }
}
