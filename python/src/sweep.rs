//! `Model.bifurcation`: the command line's `linkdyn bifurcation` (`src/cli/bifurcation.rs`)
//! without its files: the same checks in the same order, the same points (the library's
//! [`Sweep`] on rayon threads through [`analysis::run_points`]), returned as arrays.
//!
//! # Threads and the GIL
//! The points run on a rayon pool started from a scoped thread; none of them touches Python.
//! The calling thread waits for them without the GIL (other Python threads run meanwhile) and
//! takes it briefly at most every [`POLL`] and after each finished point: to update the
//! progress display and to let Python handle signals. Ctrl-C (or an exception from a progress
//! callback) stops the sweep: points not yet started are skipped, the points in flight finish
//! (a point cannot be cut short), then the exception is raised.
//!
//! # Failed points
//! As on the command line, a point whose model, simulation or integration fails does not end
//! the sweep: its rows are NaN, its verdict `"failed"` with the message in `message`, and a
//! `RuntimeWarning` names the failed points once the sweep is done.

use crate::analyses::{floats, ints, provenance, record};
use crate::errors::{self, Failed};
use crate::settings::{Solve, whole_transient, whole_turns};
use linkdyn::Error;
use linkdyn::analysis::{
    self, AnalysisError, Chunk, Direction, ParameterGrid, PeriodVerdict, Shard, SweepPoint,
};
use linkdyn::model::Model;
use linkdyn::output::format_number;
use linkdyn::simulation::Simulation;
use linkdyn::simulation::analyses::{SectionSpec, Sweep, SweepMode, SweepModeRequest, SweepResult};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Condvar, Mutex, PoisonError};
use std::time::Duration;

/// Longest wait without looking at signals and progress.
const POLL: Duration = Duration::from_millis(100);

/// `progress=`: `True`/`False`, or anything else (None, a callable), judged by
/// `linkdyn._progress.reporter`.
#[derive(FromPyObject)]
pub enum Progress {
    Flag(bool),
    Other(Py<PyAny>),
}

impl Progress {
    /// The Python object given, for `linkdyn._progress` to judge.
    pub fn into_object(self, py: Python<'_>) -> Py<PyAny> {
        match self {
            Progress::Flag(b) => PyBool::new(py, b).to_owned().into_any().unbind(),
            Progress::Other(o) => o,
        }
    }
}

/// Options of `Model.bifurcation` beyond the solve settings.
pub struct SweepArgs {
    pub param: String,
    pub observe: String,
    pub from: Option<f64>,
    pub to: Option<f64>,
    pub steps: Option<i64>,
    pub values: Option<Vec<f64>>,
    pub revs: Option<f64>,
    pub transient: i64,
    pub phase: f64,
    pub threads: Option<i64>,
    pub shard: Option<String>,
    pub settle: bool,
    /// The text of a model built in Python (`loads`, `from_dict`), loaded by each point instead
    /// of the file.
    pub model_text: Option<String>,
    pub transient_min: Option<i64>,
    pub warm_start: bool,
    pub chunks: Option<i64>,
    pub direction: Option<String>,
}

/// Settings by name, as on the command line's `#` provenance lines.
type Settings = Vec<(&'static str, String)>;

/// A checked sweep, ready to run.
struct Plan {
    turns: usize,
    transient: usize,
    /// The grid the points are indexed by (for `values=`, 0..n − 1: indices only).
    grid: ParameterGrid,
    /// The parameter value of each grid index.
    values: Vec<f64>,
    /// The grid indices to run (the shard's, ascending).
    indices: Vec<usize>,
    options: linkdyn::simulation::SimulationOptions,
    /// The sweep's settings for the provenance (as the command line's `#` lines).
    settings: Settings,
    provenance: linkdyn::output::Provenance,
    pool: rayon::ThreadPool,
    /// Transient detection and warm starts.
    mode: SweepMode,
    /// The chunks of a warm-started sweep (every direction's), or none.
    chunks: Option<Vec<Chunk>>,
}

/// One finished point: its section (or why it failed) and whether it started from the point
/// before it.
struct Outcome {
    section: SweepResult,
    warm: bool,
}

/// A whole number ≥ 0 given as `option`.
fn whole(option: &'static str, value: i64) -> Result<usize, Failed> {
    usize::try_from(value).map_err(|_| {
        Error::settings(option, format!("expected a whole number ≥ 0, got {value}")).into()
    })
}

impl SweepArgs {
    /// The grid and the parameter value of each index: `from`/`to`/`steps` as the command line
    /// takes them, or explicit `values`.
    fn grid(&self) -> Result<(ParameterGrid, Vec<f64>, Settings), Failed> {
        let grid_given = self.from.is_some() || self.to.is_some() || self.steps.is_some();
        match (&self.values, self.from, self.to, self.steps) {
            (Some(_), ..) if grid_given => Err(Error::settings(
                "values",
                "give `values` or `from_`, `to` and `steps`, not both",
            )
            .into()),
            (Some(values), ..) => {
                if values.is_empty() {
                    return Err(Error::settings("values", "expected at least one value").into());
                }
                if let Some((i, v)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
                    return Err(Error::settings(
                        "values",
                        format!("expected finite values, got {v} at position {i}"),
                    )
                    .into());
                }
                let last = values.len() - 1;
                let grid = ParameterGrid::new(0.0, last as f64, last)?;
                let text: Vec<String> = values.iter().map(|&v| format_number(v)).collect();
                Ok((grid, values.clone(), vec![("values", text.join(","))]))
            }
            (None, Some(from), Some(to), Some(steps)) => {
                let steps = usize::try_from(steps).map_err(|_| {
                    Error::settings("steps", format!("expected a whole number ≥ 0, got {steps}"))
                })?;
                let grid = ParameterGrid::new(from, to, steps)?;
                let settings = vec![
                    ("from", format_number(from)),
                    ("to", format_number(to)),
                    ("steps", steps.to_string()),
                ];
                Ok((grid, grid.values(), settings))
            }
            (None, ..) => Err(Error::settings(
                "steps",
                "give the grid as `from_`, `to` and `steps` (or the points as `values`)",
            )
            .into()),
        }
    }

    /// The sweep with `options` (the command line's [`Sweep`]).
    fn sweep<'a>(&'a self, path: &'a str, model: &'a Model, plan: &'a Plan) -> Sweep<'a> {
        Sweep {
            model_path: Path::new(path),
            model_text: self.model_text.as_deref(),
            overrides: &model.source.overrides,
            parameter: &self.param,
            grid: plan.grid,
            options: plan.options.clone(),
            section: SectionSpec {
                turns: plan.turns,
                transient: plan.transient,
                phase: self.phase,
                observe: vec![self.observe.clone()],
            },
        }
    }

    /// Every check of the command line, in its order, before any point runs.
    fn plan(&self, model: &Model, path: &str, solve: &Solve) -> Result<Plan, Failed> {
        let transient = whole_transient(self.transient)?;
        let turns = whole_turns(self.revs, 150)?;
        if turns <= transient {
            return Err(Error::settings(
                "revs",
                format!("expected more turns than the {transient} transient turns, got {turns}"),
            )
            .into());
        }
        let (grid, values, grid_settings) = self.grid()?;
        let options = solve.for_turns(turns as f64)?;
        let directions = match self.direction.as_deref() {
            None => None,
            Some("up") => Some(vec![Direction::Up]),
            Some("down") => Some(vec![Direction::Down]),
            Some("both") => Some(vec![Direction::Up, Direction::Down]),
            Some(other) => {
                return Err(Error::settings(
                    "direction",
                    format!("expected \"up\", \"down\" or \"both\", got \"{other}\""),
                )
                .into());
            }
        };
        let mode = SweepMode::new(
            &SweepModeRequest {
                settle: self.settle,
                transient_min: self
                    .transient_min
                    .map(|m| whole("transient_min", m))
                    .transpose()?,
                transient,
                warm_start: self.warm_start,
                chunks: self.chunks.map(|c| whole("chunks", c)).transpose()?,
                directions,
                sharded: self.shard.is_some(),
                n_points: grid.len(),
            },
            options.formulation,
        )?;
        let chunks = mode.chunks(&grid)?;
        let base = Simulation::new(model, options.clone()).map_err(Failed::building)?;
        let pool = {
            let builder = rayon::ThreadPoolBuilder::new();
            let builder = match self.threads {
                Some(k) if k < 1 => {
                    return Err(Error::settings(
                        "threads",
                        format!("expected at least 1 thread, got {k}"),
                    )
                    .into());
                }
                // Any count that fits in usize; rayon refuses what it cannot start.
                Some(k) => builder.num_threads(usize::try_from(k).unwrap_or(usize::MAX)),
                None => builder,
            };
            builder
                .build()
                .map_err(|e| Error::settings("threads", format!("cannot start the threads: {e}")))?
        };
        let indices = match &self.shard {
            Some(s) => {
                let shard: Shard = s.parse()?;
                analysis::remaining(&grid, Some(&shard), &[])?
            }
            None => (0..grid.len()).collect(),
        };
        let mut settings = vec![("parameter", self.param.clone())];
        settings.extend(grid_settings);
        settings.extend([
            ("revs", turns.to_string()),
            ("transient_revs", transient.to_string()),
            ("phase_rad", format_number(self.phase)),
            ("observe", self.observe.clone()),
        ]);
        // As the command line's files: only the new modes add lines.
        if let Some(s) = mode.settle {
            settings.push(("settle_min_revs", s.min_transient.to_string()));
        }
        if let Some((n, directions)) = &mode.warm {
            settings.push(("warm_start_chunks", n.to_string()));
            let names: Vec<String> = directions.iter().map(ToString::to_string).collect();
            settings.push(("direction", names.join(",")));
        }
        let plan = Plan {
            turns,
            transient,
            grid,
            values,
            indices,
            options,
            settings,
            provenance: base.provenance(),
            pool,
            mode,
            chunks,
        };
        // The first point's model and simulation, checked now (as the command line does): a
        // bad `param` or value is reported before any work, naming the option.
        let first_value = plan.values.first().copied().unwrap_or(0.0);
        let first = self
            .sweep(path, model, &plan)
            .simulation(first_value)
            .map_err(|e| Failed::prefixed(e, format!("param {}", self.param)))?;
        if first.model().source.sha256 != model.source.sha256 {
            return Err(Error::settings(
                "param",
                format!(
                    "the model file {path} changed since it was loaded (SHA-256 {} then, {} now): each point reads it again, so load it again",
                    model.source.sha256,
                    first.model().source.sha256
                ),
            )
            .into());
        }
        // The other end of the grid too (a bad `to` is bad input, not a failed point), and the
        // section's settings on both ends, as the command line checks them.
        let sweep = self.sweep(path, model, &plan);
        sweep.section.check(&first)?;
        if let Some(&last) = plan.values.last().filter(|_| plan.values.len() > 1) {
            let sim = sweep
                .simulation(last)
                .map_err(|e| Failed::prefixed(e, format!("param {}", self.param)))?;
            sweep.section.check(&sim)?;
        }
        Ok(plan)
    }
}

/// What the points have done so far, shared between the workers and the waiting thread.
#[derive(Default)]
struct Progressed {
    /// Points finished (failed ones included).
    done: usize,
    /// `run_points` has returned.
    finished: bool,
}

/// `Model.bifurcation` (`linkdyn bifurcation`).
pub fn bifurcation<'py>(
    py: Python<'py>,
    model: &Model,
    path: &str,
    solve: &Solve,
    a: SweepArgs,
    progress: Progress,
) -> PyResult<Bound<'py, PyAny>> {
    let plan = py
        .detach(|| a.plan(model, path, solve))
        .map_err(|f| f.into_py(py, path))?;
    let sweep = a.sweep(path, model, &plan);
    let reporter = py.import("linkdyn._progress")?.call_method1(
        "reporter",
        (
            progress.into_object(py),
            plan.indices.len(),
            format!("bifurcation {}", a.param),
        ),
    )?;

    let state = Mutex::new(Progressed::default());
    let changed = Condvar::new();
    let stop = AtomicBool::new(false);
    let lock = || state.lock().unwrap_or_else(PoisonError::into_inner);
    let (joined, python_error) = std::thread::scope(|scope| {
        let worker = scope.spawn(|| {
            let settle = plan.mode.settle;
            let value_of = |i: usize| plan.values.get(i).copied().unwrap_or(f64::NAN);
            let finished = || -> Result<(), AnalysisError> {
                lock().done += 1;
                changed.notify_all();
                Ok(())
            };
            // After an interrupt, points not yet started are skipped.
            let stopped = || stop.load(Ordering::Relaxed);
            let points = plan.pool.install(|| match &plan.chunks {
                None => analysis::run_points_until(
                    &plan.grid,
                    &plan.indices,
                    |i, _| Outcome {
                        section: sweep
                            .point_from(value_of(i), settle, None)
                            .map(|r| r.section),
                        warm: false,
                    },
                    |_| finished(),
                    stopped,
                )
                .map(|points| points.into_iter().map(|p| (None, p)).collect::<Vec<_>>()),
                Some(chunks) => analysis::run_chunks_until(
                    &plan.grid,
                    chunks,
                    Vec::new(),
                    |_, i, _, previous| match sweep.point_from(value_of(i), settle, previous) {
                        Ok(r) => (
                            Outcome {
                                section: Ok(r.section),
                                warm: r.warm,
                            },
                            r.end,
                        ),
                        Err(e) => (
                            Outcome {
                                section: Err(e),
                                warm: false,
                            },
                            None,
                        ),
                    },
                    |_, _| finished(),
                    stopped,
                )
                .map(|points| {
                    points
                        .into_iter()
                        .map(|(d, p)| (Some(d), p))
                        .collect::<Vec<_>>()
                }),
            });
            lock().finished = true;
            changed.notify_all();
            points
        });
        let mut shown = 0;
        let mut python_error: Option<PyErr> = None;
        loop {
            let (done, finished) = py.detach(|| {
                let s = lock();
                let (s, _) = changed
                    .wait_timeout_while(s, POLL, |s| s.done == shown && !s.finished)
                    .unwrap_or_else(PoisonError::into_inner);
                (s.done, s.finished)
            });
            let advanced = done != shown;
            // Kept current after an error too, so that the wait above keeps waiting.
            shown = done;
            if python_error.is_none() {
                let reported = if advanced {
                    reporter.call_method1("update", (done,)).map(drop)
                } else {
                    Ok(())
                };
                if let Err(e) = reported.and_then(|()| py.check_signals()) {
                    python_error = Some(e);
                    stop.store(true, Ordering::Relaxed);
                }
            }
            if finished {
                break;
            }
        }
        (worker.join(), python_error)
    });
    let closed = reporter.call_method0("close");
    if let Some(e) = python_error {
        return Err(e);
    }
    closed?;
    let points = match joined {
        Ok(points) => points.map_err(|e| errors::to_py(py, e.into(), None))?,
        Err(_) => {
            return Err(pyo3::exceptions::PyRuntimeError::new_err(
                "a bifurcation worker thread panicked",
            ));
        }
    };
    let record = build(py, &a, &plan, &points)?;
    let failed: Vec<String> = points
        .iter()
        .filter_map(|(_, p)| match &p.result.section {
            Err(e) => Some(format!(
                "point {} ({} = {}) failed: {}",
                p.index,
                a.param,
                format_number(plan.values.get(p.index).copied().unwrap_or(p.parameter)),
                errors::message(e)
            )),
            _ => None,
        })
        .collect();
    if !failed.is_empty() {
        let text = format!(
            "{} of {} points; {} (their rows are NaN, their verdict \"failed\", the messages in `message`)",
            points.len() - failed.len(),
            points.len(),
            failed.join("; ")
        );
        let warning = py.get_type::<pyo3::exceptions::PyRuntimeWarning>();
        PyErr::warn(
            py,
            &warning,
            &std::ffi::CString::new(text).unwrap_or_default(),
            1,
        )?;
    }
    Ok(record)
}

/// The record of a finished sweep: its rows and its verdicts, in index order (with both
/// directions of a warm-started sweep: the up branch, then the down branch).
fn build<'py>(
    py: Python<'py>,
    a: &SweepArgs,
    plan: &Plan,
    points: &[(Option<Direction>, SweepPoint<Outcome>)],
) -> PyResult<Bound<'py, PyAny>> {
    let (mut index, mut parameter, mut turn, mut value, mut direction) =
        (vec![], vec![], vec![], vec![], vec![]);
    let (mut point_index, mut point_parameter, mut verdict, mut k, mut message) =
        (vec![], vec![], vec![], vec![], vec![]);
    let (mut point_direction, mut transient_turns, mut start) = (vec![], vec![], vec![]);
    for (d, p) in points {
        let v = plan.values.get(p.index).copied().unwrap_or(p.parameter);
        let d = d.map_or(String::new(), |d| d.to_string());
        let (name, period, text, transient) = match &p.result.section {
            Ok(s) => {
                for (t, point) in s.turns.iter().zip(&s.section.points) {
                    for x in point {
                        index.push(p.index);
                        parameter.push(v);
                        turn.push(*t);
                        value.push(*x);
                        direction.push(d.clone());
                    }
                }
                let (name, period) = match &s.period.verdict {
                    PeriodVerdict::Period { k, .. } => ("period", *k),
                    PeriodVerdict::NoPeriod { .. } => ("no_period", 0),
                    PeriodVerdict::NotSettled { .. } => ("not_settled", 0),
                };
                let used = s.turns.first().copied().unwrap_or(plan.transient);
                (name, period, String::new(), used)
            }
            // The command line's NaN rows: one per recorded turn.
            Err(e) => {
                for t in plan.transient..plan.turns {
                    index.push(p.index);
                    parameter.push(v);
                    turn.push(t);
                    value.push(f64::NAN);
                    direction.push(d.clone());
                }
                ("failed", 0, errors::message(e), plan.transient)
            }
        };
        point_index.push(p.index);
        point_parameter.push(v);
        verdict.push(name);
        k.push(period);
        message.push(text);
        point_direction.push(d);
        transient_turns.push(transient);
        start.push(if p.result.warm { "warm" } else { "cold" });
    }
    let fields = PyDict::new(py);
    fields.set_item("parameter_name", &a.param)?;
    fields.set_item("observe", &a.observe)?;
    fields.set_item("index", ints(py, &index))?;
    fields.set_item("parameter", floats(py, parameter))?;
    fields.set_item("turn", ints(py, &turn))?;
    fields.set_item("value", floats(py, value))?;
    fields.set_item("direction", direction)?;
    fields.set_item("point_index", ints(py, &point_index))?;
    fields.set_item("point_parameter", floats(py, point_parameter))?;
    fields.set_item("verdict", verdict)?;
    fields.set_item("k", ints(py, &k))?;
    fields.set_item("message", message)?;
    fields.set_item("point_direction", point_direction)?;
    fields.set_item("transient_turns", ints(py, &transient_turns))?;
    fields.set_item("start", start)?;
    fields.set_item(
        "provenance",
        provenance(py, plan.provenance.clone(), &plan.settings)?,
    )?;
    record(py, "Bifurcation", &fields)
}
