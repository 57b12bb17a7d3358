//! `Model.orbit` and `Model.continuation`: the library's studies behind `linkdyn orbit` and
//! `linkdyn continue` ([`linkdyn::studies::orbit`], [`linkdyn::studies::continuation`]) with
//! the command line's options, checks and defaults (`src/cli/{orbit,continuation}.rs`),
//! computed with the GIL released and returned as the records `PeriodicOrbit` and
//! `Continuation` of `linkdyn._analyses`.

use crate::analyses::{floats, ints, record, to_python};
use crate::errors::Failed;
use crate::settings::Solve;
use crate::sweep::Progress;
use linkdyn::Error;
use linkdyn::analysis::orbit::BranchEnd;
use linkdyn::model::Model;
use linkdyn::studies::continuation::{ContinuationRequest, continuation_watched};
use linkdyn::studies::orbit::{OrbitPeriod, OrbitRequest, orbit};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::Path;

/// A count given as a Python int that must be ≥ `least` (the command line's `usize` options).
pub fn count(option: &'static str, value: i64, least: i64, what: &str) -> Result<usize, Error> {
    if value < least {
        return Err(Error::settings(
            option,
            format!("expected {what}, got {value}"),
        ));
    }
    usize::try_from(value).map_err(|_| Error::settings(option, format!("expected {what}")))
}

/// A complex128 NumPy array of multipliers given as `[re, im]`.
fn complex<'py>(py: Python<'py>, mu: &[[f64; 2]]) -> PyResult<Bound<'py, PyAny>> {
    let re: Vec<f64> = mu.iter().map(|z| z[0]).collect();
    let im: Vec<f64> = mu.iter().map(|z| z[1]).collect();
    let j = pyo3::types::PyComplex::from_doubles(py, 0.0, 1.0);
    let re = PyArray1::from_vec(py, re).into_any();
    let im = PyArray1::from_vec(py, im).into_any();
    re.add(im.mul(j)?)?.call_method1("astype", ("complex128",))
}

/// Options of `Model.orbit` beyond the solve settings.
pub struct OrbitArgs {
    pub period_turns: Option<i64>,
    pub period: Option<f64>,
    pub guess_from_turn: i64,
}

/// `Model.orbit` (`linkdyn orbit`).
pub fn periodic_orbit<'py>(
    py: Python<'py>,
    model: &Model,
    path: &str,
    solve: &Solve,
    a: OrbitArgs,
) -> PyResult<Bound<'py, PyAny>> {
    let result = py
        .detach(|| -> Result<_, Failed> {
            let period = match (a.period_turns, a.period) {
                (Some(_), Some(_)) => {
                    return Err(Error::settings(
                        "period",
                        "give `period_turns` or `period`, not both",
                    )
                    .into());
                }
                (None, Some(s)) => OrbitPeriod::Seconds(s),
                (Some(k), None) => OrbitPeriod::Turns(count(
                    "period_turns",
                    k,
                    0,
                    "a whole number of driver turns ≥ 1",
                )?),
                (None, None) => OrbitPeriod::Turns(1),
            };
            let guess_from_turn = count(
                "guess_from_turn",
                a.guess_from_turn,
                0,
                "a whole number of periods ≥ 0",
            )?;
            let request = OrbitRequest {
                options: solve.options()?,
                period,
                guess_from_turn,
                dt: solve.dt,
            };
            Ok(orbit(model, &request)?)
        })
        .map_err(|f| f.into_py(py, path))?;
    let n = result.samples.len();
    let d = result.names.len();
    let t: Vec<f64> = result.samples.iter().map(|(t, _)| *t).collect();
    let flat: Vec<f64> = result
        .samples
        .iter()
        .flat_map(|(_, row)| row.iter().copied())
        .collect();
    // The keys of the command's F.json, then its F.csv as arrays.
    let fields = PyDict::new(py);
    let json = to_python(py, &result)?;
    for key in [
        "converged",
        "newton_iterations",
        "state",
        "t_section_s",
        "period_s",
        "period_turns",
        "trivial_multipliers",
        "stable",
        "spectral_radius",
        "impacts_per_period",
        "min_gap_m",
        "closing_error",
        "wall_time_s",
        "solver_stats",
        "provenance",
    ] {
        fields.set_item(key, json.get_item(key)?)?;
    }
    fields.set_item(
        "residual_history",
        floats(py, result.residual_history.clone()),
    )?;
    fields.set_item(
        "floquet_multipliers",
        complex(py, &result.floquet_multipliers)?,
    )?;
    fields.set_item("names", &result.names)?;
    fields.set_item("t", floats(py, t))?;
    fields.set_item("samples", floats(py, flat).reshape([n, d])?)?;
    record(py, "PeriodicOrbit", &fields)
}

/// Options of `Model.continuation` beyond the solve settings.
pub struct ContinuationArgs {
    pub param: String,
    pub from: f64,
    pub to: f64,
    pub step: Option<f64>,
    pub period_turns: i64,
    pub guess_from_turn: i64,
    pub follow_doublings: i64,
}

/// `Model.continuation` (`linkdyn continue`). `text` is the model's text before the overrides
/// (each point reloads it with `param=value`, as the command reloads the file).
pub fn branch<'py>(
    py: Python<'py>,
    model: &Model,
    path: &str,
    text: &str,
    solve: &Solve,
    a: ContinuationArgs,
    progress: Progress,
) -> PyResult<Bound<'py, PyAny>> {
    let overrides = model.source.overrides.clone();
    let reporter: Py<PyAny> = py
        .import("linkdyn._progress")?
        .call_method1(
            "branch_reporter",
            (
                progress.into_object(py),
                format!("continuation {}", a.param),
            ),
        )?
        .unbind();
    // Ctrl-C and progress: Python's signal handlers run when the GIL is held, so each point
    // takes it briefly to report itself and check; a KeyboardInterrupt (or an exception from
    // the progress callback) ends the branch and is raised once Rust returns.
    let mut signal: Option<PyErr> = None;
    let mut points = 0_usize;
    let result = py
        .detach(|| -> Result<_, Failed> {
            // The command line's checks, in its order.
            if a.from == a.to {
                return Err(Error::settings(
                    "to",
                    format!(
                        "expected a value other than from_ {} (a branch needs a range)",
                        a.from
                    ),
                )
                .into());
            }
            if let Some(h) = a.step
                && !(h.is_finite() && h > 0.0)
            {
                return Err(Error::settings(
                    "step",
                    format!("expected a finite step > 0, got {h}"),
                )
                .into());
            }
            let period_turns = count(
                "period_turns",
                a.period_turns,
                0,
                "a whole number of driver turns ≥ 1",
            )?;
            let guess_from_turn = count(
                "guess_from_turn",
                a.guess_from_turn,
                0,
                "a whole number of periods ≥ 0",
            )?;
            let follow_doublings = count(
                "follow_doublings",
                a.follow_doublings,
                0,
                "a whole number of period doublings ≥ 0",
            )?;
            // Both ends load with the parameter: an unknown path or a bad value is named now.
            for value in [a.from, a.to] {
                let mut with = overrides.clone();
                with.push(format!("{}={value}", a.param));
                linkdyn::model::load_str(text, path, &with)
                    .map_err(|e| Failed::prefixed(Error::from(e), format!("param {}", a.param)))?;
            }
            let request = ContinuationRequest {
                model_path: Path::new(path),
                model_text: text,
                overrides: &overrides,
                parameter: &a.param,
                from: a.from,
                to: a.to,
                step: a.step,
                period_turns,
                guess_from_turn,
                follow_doublings,
                options: solve.options()?,
            };
            Ok(continuation_watched(&request, &mut |branch, point| {
                points += 1;
                let reported = Python::attach(|py| {
                    let p = PyDict::new(py);
                    p.set_item("points", points)?;
                    p.set_item("branch", branch)?;
                    p.set_item("parameter", point.parameter)?;
                    p.set_item("stable", point.stable)?;
                    p.set_item("max_abs_mu", point.spectral_radius)?;
                    p.set_item("special", point.special.map_or("", |k| k.name()))?;
                    reporter.bind(py).call_method1("point", (p,))?;
                    py.check_signals()
                });
                match reported {
                    Ok(()) => true,
                    Err(e) => {
                        signal = Some(e);
                        false
                    }
                }
            })?)
        })
        .map_err(|f| f.into_py(py, path));
    let closed = reporter.bind(py).call_method0("close");
    let result = result?;
    if let Some(e) = signal {
        return Err(e);
    }
    closed?;
    let rows = &result.rows;
    let n = rows.len();
    let d = result.names.len();
    let column = |f: &dyn Fn(&linkdyn::studies::continuation::ContinuationRow) -> f64| {
        floats(py, rows.iter().map(f).collect())
    };
    let flat: Vec<f64> = rows.iter().flat_map(|r| r.state.iter().copied()).collect();
    let fields = PyDict::new(py);
    fields.set_item("parameter_name", &result.parameter)?;
    fields.set_item("names", &result.names)?;
    fields.set_item("parameter", column(&|r| r.parameter))?;
    fields.set_item("state", floats(py, flat).reshape([n, d])?)?;
    fields.set_item("period_s", column(&|r| r.period_s))?;
    fields.set_item("max_abs_mu", column(&|r| r.max_abs_mu))?;
    let stable: Vec<bool> = rows.iter().map(|r| r.stable).collect();
    fields.set_item("stable", PyArray1::from_vec(py, stable))?;
    let impacts: Vec<usize> = rows.iter().map(|r| r.impacts_per_period).collect();
    fields.set_item("impacts_per_period", ints(py, &impacts))?;
    fields.set_item("min_gap_m", column(&|r| r.min_gap_m.unwrap_or(f64::NAN)))?;
    fields.set_item("residual", column(&|r| r.residual))?;
    let special: Vec<&str> = rows
        .iter()
        .map(|r| r.special.map_or("", |k| k.name()))
        .collect();
    fields.set_item("special", special)?;
    let branch: Vec<usize> = rows.iter().map(|r| r.branch).collect();
    fields.set_item("branch", ints(py, &branch))?;
    let turn: Vec<usize> = rows.iter().map(|r| r.turn).collect();
    fields.set_item("turn", ints(py, &turn))?;
    let multipliers = rows
        .iter()
        .map(|r| complex(py, &r.floquet_multipliers))
        .collect::<PyResult<Vec<_>>>()?;
    fields.set_item("floquet_multipliers", multipliers)?;
    let json = to_python(py, &result)?;
    for key in [
        "special_points",
        "unlocated",
        "end",
        "period_turns",
        "branches",
        "switch_failures",
        "wall_time_s",
        "solver_stats",
        "provenance",
    ] {
        fields.set_item(key, json.get_item(key)?)?;
    }
    let record = record(py, "Continuation", &fields)?;
    // A branch that stopped before `to` is a result (the command writes its files and exits
    // 3): returned, with the command's message as a RuntimeWarning.
    let last = rows
        .iter()
        .rfind(|r| r.branch == 0)
        .map_or(f64::NAN, |r| r.parameter);
    let stopped = match &result.end {
        BranchEnd::Reached
        | BranchEnd::TurnedBack
        | BranchEnd::Rejoined { .. }
        | BranchEnd::Stopped => None,
        BranchEnd::MaxPoints => Some(format!(
            "the branch stopped after {} points at {} = {last}, before to",
            result.points, a.param
        )),
        BranchEnd::Failed { message } => Some(format!(
            "the branch stopped at {} = {last}, before to: {message}",
            a.param
        )),
    };
    if let Some(text) = stopped {
        let category = py.get_type::<pyo3::exceptions::PyRuntimeWarning>();
        let text = std::ffi::CString::new(text).unwrap_or_default();
        PyErr::warn(py, &category, &text, 1)?;
    }
    Ok(record)
}
