//! Library errors → the exceptions of `linkdyn._errors`, with the command line's messages.
//!
//! | library error | exception | CLI exit code |
//! |---|---|---|
//! | `Error::Model` | `ModelError` (attributes `file`, `line`, `column`, `field` where known) | 2 |
//! | `Error::Formulation` (before a run: the linkage cannot be assembled or does not fit the formulation) | `ModelError` | 2 |
//! | `Error::Settings` | `SettingsError` (attribute `option`) | 2 |
//! | `Error::Solve` | `SolverError` (attribute `time`) | 3 |
//! | `Error::Output`, a failing sample sink | `OutputError` | 4 (2 for a refused target) |
//!
//! Messages are the CLI's (`linkdyn/src/cli/mod.rs`, `message`): the error and each cause
//! not already in it, joined by `": "`; a formulation error met while building a simulation
//! is prefixed with the model file as given. The one difference: a settings error names
//! options as the library does (`dt`, `` `t_end` ``) where the CLI spells them as flags
//! (`--dt`, `--t-end`).

use linkdyn::Error;
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
    match build(py, &e, model_path) {
        Ok(err) => err,
        // The exception classes could not be reached (a broken installation): still raise,
        // with the same message.
        Err(other) => {
            let text = format!("{} (and linkdyn._errors failed: {other})", message(&e));
            pyo3::exceptions::PyRuntimeError::new_err(text)
        }
    }
}

fn build(py: Python<'_>, e: &Error, model_path: Option<&str>) -> PyResult<PyErr> {
    let attrs = PyDict::new(py);
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
        // Analyses are not bound yet; should one fail, it is still a linkdyn error.
        Error::Analysis(_) => ("LinkdynError", message(e)),
    };
    let class = py.import("linkdyn._errors")?.getattr(class)?;
    let value = class.call1((text,))?;
    for (k, v) in attrs.iter() {
        value.setattr(k.str()?, v)?;
    }
    Ok(PyErr::from_value(value))
}
