//! `Model.poincare`, `spectrum`, `phase` and `lyapunov`: the library's model-level analyses
//! ([`linkdyn::simulation::analyses`]) with the command line's options, checks and defaults
//! (`src/cli/{poincare,spectrum,phase,lyapunov}.rs`), computed with the GIL released and
//! returned as the records of `linkdyn._analyses` (NumPy arrays, the verdict, provenance).

use crate::errors::Failed;
use crate::settings::{Solve, whole_transient, whole_turns, window_turns};
use linkdyn::analysis::{PeriodVerdict, RateSource};
use linkdyn::model::Model;
use linkdyn::output::{Provenance, format_number};
use linkdyn::simulation::Simulation;
use linkdyn::simulation::analyses::{self, LyapunovSpec, SectionSpec};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde::Serialize;

/// `value` as plain Python objects (dicts, lists, numbers, None), through JSON.
pub fn to_python<'py>(py: Python<'py>, value: &impl Serialize) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value).map_err(|e| {
        pyo3::exceptions::PyRuntimeError::new_err(format!("cannot convert a result: {e}"))
    })?;
    py.import("json")?.call_method1("loads", (text,))
}

/// `provenance` with the analysis's own settings added (as the command line adds them to its
/// `#` lines), as a dict.
pub fn provenance<'py>(
    py: Python<'py>,
    mut provenance: Provenance,
    extra: &[(&str, String)],
) -> PyResult<Bound<'py, PyAny>> {
    for (k, v) in extra {
        provenance.settings.insert((*k).to_string(), v.clone());
    }
    to_python(py, &provenance)
}

/// The record `class` of `linkdyn._analyses`, built from `fields`.
pub fn record<'py>(
    py: Python<'py>,
    class: &str,
    fields: &Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyAny>> {
    py.import("linkdyn._analyses")?
        .getattr(class)?
        .call((), Some(fields))
}

/// A float64 NumPy array owning `v`.
pub fn floats(py: Python<'_>, v: Vec<f64>) -> Bound<'_, PyArray1<f64>> {
    PyArray1::from_vec(py, v)
}

/// An int64 NumPy array of `v`.
pub fn ints<'py>(py: Python<'py>, v: &[usize]) -> Bound<'py, PyArray1<i64>> {
    // Turn and point counts are far below 2^63.
    PyArray1::from_vec(py, v.iter().map(|&k| k as i64).collect())
}

/// Options of `Model.poincare` beyond the solve settings.
pub struct PoincareArgs {
    pub revs: Option<f64>,
    pub transient: i64,
    pub phase: f64,
    pub observe: Vec<String>,
}

/// `Model.poincare` (`linkdyn poincare`).
pub fn poincare<'py>(
    py: Python<'py>,
    model: &Model,
    path: &str,
    solve: &Solve,
    a: PoincareArgs,
) -> PyResult<Bound<'py, PyAny>> {
    let (provenance, s, omega) = py
        .detach(|| -> Result<_, Failed> {
            let transient = whole_transient(a.transient)?;
            let turns = whole_turns(a.revs, 2)?;
            let sim =
                Simulation::new(model, solve.for_turns(turns as f64)?).map_err(Failed::building)?;
            let spec = SectionSpec {
                turns,
                transient,
                phase: a.phase,
                observe: a.observe,
            };
            let s = analyses::poincare(&sim, &spec)?;
            let omega = analyses::driver_speed(sim.model(), "revs")?;
            Ok((sim.provenance(), s, omega))
        })
        .map_err(|f| f.into_py(py, path))?;
    let period = std::f64::consts::TAU / omega;
    let d = s.section.names.len();
    let n = s.section.points.len();
    let flat: Vec<f64> = s.section.points.iter().flatten().copied().collect();
    let fields = PyDict::new(py);
    fields.set_item("names", &s.section.names)?;
    fields.set_item("turn", ints(py, &s.turns))?;
    fields.set_item("t", floats(py, s.section.times.clone()))?;
    fields.set_item("points", floats(py, flat).reshape([n, d])?)?;
    fields.set_item("verdict", s.period.verdict.to_string())?;
    let k = match s.period.verdict {
        PeriodVerdict::Period { k, .. } => Some(k),
        _ => None,
    };
    fields.set_item("period", k)?;
    fields.set_item("verdict_details", to_python(py, &s.period.verdict)?)?;
    fields.set_item("tolerance", floats(py, s.tolerance.clone()))?;
    fields.set_item("settled_at_turn", s.settled_at_turn)?;
    fields.set_item("driver_period", period)?;
    fields.set_item("stats", to_python(py, &s.section.stats)?)?;
    let extra = [
        ("transient_revs", a.transient.to_string()),
        ("phase_rad", format_number(a.phase)),
        ("driver_period", format_number(period)),
    ];
    fields.set_item("provenance", self::provenance(py, provenance, &extra)?)?;
    record(py, "PoincareSection", &fields)
}

/// Options of `Model.spectrum`, `phase` and `lyapunov` beyond the solve settings.
pub struct WindowArgs {
    pub revs: Option<f64>,
    pub transient: f64,
}

/// The simulation of a windowed analysis: `revs` (default transient + 10) turns.
fn window_simulation(
    model: &Model,
    solve: &Solve,
    w: &WindowArgs,
) -> Result<(Simulation, f64), Failed> {
    let turns = window_turns(w.revs, w.transient)?;
    let sim = Simulation::new(model, solve.for_turns(turns)?).map_err(Failed::building)?;
    Ok((sim, turns))
}

/// `Model.spectrum` (`linkdyn spectrum`).
pub fn spectrum<'py>(
    py: Python<'py>,
    model: &Model,
    path: &str,
    solve: &Solve,
    observe: String,
    w: WindowArgs,
) -> PyResult<Bound<'py, PyAny>> {
    let (provenance, s, f_drive) = py
        .detach(|| -> Result<_, Failed> {
            let (sim, _) = window_simulation(model, solve, &w)?;
            let (s, f_drive) = analyses::spectrum(&sim, &observe, w.transient)?;
            Ok((sim.provenance(), s, f_drive))
        })
        .map_err(|f| f.into_py(py, path))?;
    let window = format!("{:?}", s.window).to_lowercase();
    let fields = PyDict::new(py);
    fields.set_item("observe", &observe)?;
    fields.set_item("peaks", to_python(py, &s.peaks)?)?;
    fields.set_item("frequency", floats(py, s.frequencies))?;
    fields.set_item("amplitude", floats(py, s.amplitudes))?;
    fields.set_item("driving_frequency", f_drive)?;
    fields.set_item("dt", s.dt)?;
    fields.set_item("n_samples", s.n_samples)?;
    fields.set_item("mean", s.mean)?;
    fields.set_item("resampled", s.resampled)?;
    fields.set_item("window", &window)?;
    let extra = [
        ("observe", observe),
        ("transient_revs", format_number(w.transient)),
        ("window", window),
        ("driving_frequency_hz", format_number(f_drive)),
    ];
    fields.set_item("provenance", self::provenance(py, provenance, &extra)?)?;
    record(py, "Spectrum", &fields)
}

/// `Model.phase` (`linkdyn phase`).
pub fn phase<'py>(
    py: Python<'py>,
    model: &Model,
    path: &str,
    solve: &Solve,
    observe: String,
    w: WindowArgs,
) -> PyResult<Bound<'py, PyAny>> {
    let (provenance, t, p) = py
        .detach(|| -> Result<_, Failed> {
            let (sim, _) = window_simulation(model, solve, &w)?;
            let (t, p) = analyses::phase(&sim, &observe, w.transient)?;
            Ok((sim.provenance(), t, p))
        })
        .map_err(|f| f.into_py(py, path))?;
    let source = match p.source {
        RateSource::Column => analyses::rate_column(&observe).unwrap_or_default(),
        RateSource::CentralDifference => "central differences".to_string(),
    };
    let fields = PyDict::new(py);
    fields.set_item("observe", &observe)?;
    fields.set_item("t", floats(py, t))?;
    fields.set_item("value", floats(py, p.value))?;
    fields.set_item("rate", floats(py, p.rate))?;
    fields.set_item("rate_source", &source)?;
    let extra = [
        ("observe", observe),
        ("transient_revs", format_number(w.transient)),
        ("rate", source),
    ];
    fields.set_item("provenance", self::provenance(py, provenance, &extra)?)?;
    record(py, "PhasePortrait", &fields)
}

/// Options of `Model.lyapunov` beyond the window and the solve settings.
pub struct LyapunovArgs {
    pub d0: f64,
    pub renormalise_every_revs: f64,
}

/// `Model.lyapunov` (`linkdyn lyapunov`).
pub fn lyapunov<'py>(
    py: Python<'py>,
    model: &Model,
    path: &str,
    solve: &Solve,
    w: WindowArgs,
    a: LyapunovArgs,
) -> PyResult<Bound<'py, PyAny>> {
    let (provenance, e) = py
        .detach(|| -> Result<_, Failed> {
            let (sim, turns) = window_simulation(model, solve, &w)?;
            let spec = LyapunovSpec {
                turns,
                transient: w.transient,
                d0: a.d0,
                renormalise_every: a.renormalise_every_revs,
            };
            let e = analyses::lyapunov(&sim, &spec)?;
            Ok((sim.provenance(), e))
        })
        .map_err(|f| f.into_py(py, path))?;
    let (t, estimate): (Vec<f64>, Vec<f64>) = e.history.iter().copied().unzip();
    let fields = PyDict::new(py);
    fields.set_item("exponent", e.exponent)?;
    fields.set_item("uncertainty", e.uncertainty)?;
    fields.set_item("drift", e.drift)?;
    fields.set_item("t", floats(py, t))?;
    fields.set_item("estimate", floats(py, estimate))?;
    fields.set_item("stats", to_python(py, &e.stats)?)?;
    let extra = [
        ("transient_revs", format_number(w.transient)),
        ("d0", format_number(a.d0)),
        (
            "renormalise_every_revs",
            format_number(a.renormalise_every_revs),
        ),
    ];
    fields.set_item("provenance", self::provenance(py, provenance, &extra)?)?;
    record(py, "LyapunovExponent", &fields)
}
