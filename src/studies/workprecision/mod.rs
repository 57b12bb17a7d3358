//! Work against precision (docs/numerics.md, "Work against precision"): every formulation × method × tolerance of a model, its
//! error against a reference run and its cost (wall time, right-hand-side evaluations).
//!
//! **Reference.** Per formulation, the most accurate method ([`WorkPrecisionOptions::reference_method`],
//! DOP853: order 8 with a 7th-order dense output) at a tolerance tighter than the grid
//! ([`WorkPrecisionOptions::reference_rtol`], by default 1/100 of the tightest grid rtol, not
//! below 1e-13). It is confirmed by a second method at the same tolerance
//! ([`WorkPrecisionOptions::confirm_method`], DOPRI5: another tableau, another error estimator,
//! another dense output); their difference, measured with the same error measures as the cells,
//! is reported as the reference's own error ([`Reference::own_error`]). A cell error near or
//! below it says nothing beyond "as good as the reference".
//!
//! Each formulation is judged against its own reference, so the errors are integration errors
//! only (the DAE's Baumgarte drift included, the difference between the two formulations' models
//! not; `linkdyn compare` measures that).
//!
//! **Error measures** ([`CellErrors`]), all on the common output grid (t0 + k·dt, samples from
//! the dense output, so every run is compared at the same instants):
//!
//! * `angle`: max over samples and bodies of |φ − φ_ref| (rad), the body angles `*.phi`;
//! * `orbit`: max over samples and clearance joints of |e − e_ref| (m), the journal-centre
//!   eccentricity vector (`J.ex`, `J.ey`);
//! * impact counts of the run and the reference, summed over the joints, and whether every
//!   joint's count matches;
//! * `impact_time`: max |t_k − t_k,ref| (s) over the impacts paired in order (the first
//!   min(n, n_ref) of each joint: with a count mismatch the pairing past the first difference is
//!   not meaningful, and the cell says so);
//! * `peak_force`: max |F_k − F_k,ref| (N) of the true contact peaks of the impact log
//!   ([`crate::simulation::impacts`]) over the same pairs.
//!
//! **Cost.** Wall time is the median over [`WorkPrecisionOptions::repeats`] runs of the
//! integration with its output evaluation (the summary's `wall_time_s`, which leaves out what
//! the consumer of the samples does); RHS evaluations, Jacobians, steps and rejections come from
//! the first run's [`SolverStats`]. Runs are made one after the other on one thread so that the
//! times are comparable.
//!
//! **Failures.** A cell whose simulation cannot be built (a formulation that does not take the
//! model, a refused option) or whose run fails (a solver error, the wall-clock budget
//! [`WorkPrecisionOptions::max_wall_per_run`]) is [`Cell::failure`] with the message; the table
//! goes on. If a formulation's reference fails, its cells are run and timed but have no errors.

mod report;

pub use report::{CSV_HEADER, csv_text, markdown_text};

use crate::error::Error;
use crate::model::Model;
use crate::numbers::format_number;
use crate::simulation::{
    Discard, EndTime, FormulationKind, Provenance, Simulation, SimulationOptions, Trajectory,
};
use crate::solve::{Method, SolverOptions, SolverStats};
use serde::Serialize;

/// Settings of a work–precision table, with written defaults ([`Default`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WorkPrecisionOptions {
    /// Formulations to run (default: DAE and reduced).
    pub formulations: Vec<FormulationKind>,
    /// Methods to run (default: all of [`Method::ALL`]).
    pub methods: Vec<Method>,
    /// Relative tolerances of the grid (default 1e-4, 1e-5, …, 1e-10).
    pub rtols: Vec<f64>,
    /// atol = this × rtol (m, rad, m/s, rad/s; default 1e-3: the states are O(1e-3 … 1e2)).
    pub atol_per_rtol: f64,
    /// Length of every run (default 2 driver turns).
    pub end: EndTime,
    /// Samples of the common output grid over the run (default 4000: 2000 per turn over two
    /// turns, 0.12 ms at 250 rpm, finer than the shortest contact of the reference case).
    pub samples: usize,
    /// Timed runs per cell; the median is reported (default 3).
    pub repeats: usize,
    /// Wall-clock budget of each run (s, default 60); a run over it is a failed cell.
    pub max_wall_per_run: f64,
    /// The reference method (default DOP853).
    pub reference_method: Method,
    /// The method that confirms the reference (default DOPRI5).
    pub confirm_method: Method,
    /// Reference tolerance; `None`: 1/100 of the tightest grid rtol, not below 1e-13.
    pub reference_rtol: Option<f64>,
}

impl Default for WorkPrecisionOptions {
    /// Every formulation (DAE, reduced, generalized) × every method × rtol 1e-4 … 1e-10 (one per
    /// decade), atol = 1e-3·rtol, 2 driver turns, 4000 samples, 3 timed runs per cell, 60 s per run, reference
    /// DOP853 confirmed by DOPRI5 at 1e-12.
    fn default() -> Self {
        WorkPrecisionOptions {
            formulations: FormulationKind::ALL.to_vec(),
            methods: Method::ALL.to_vec(),
            rtols: vec![1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10],
            atol_per_rtol: 1e-3,
            end: EndTime::DriverTurns(2.0),
            samples: 4000,
            repeats: 3,
            max_wall_per_run: 60.0,
            reference_method: Method::Dop853,
            confirm_method: Method::Dopri5,
            reference_rtol: None,
        }
    }
}

/// Loosest tolerance any reference is run at: below it DOP853's error is near round-off on the
/// reference case, and tighter settings only cost time.
const REFERENCE_RTOL_FLOOR: f64 = 1e-13;

impl WorkPrecisionOptions {
    /// The reference tolerance actually used (see [`WorkPrecisionOptions::reference_rtol`]).
    pub fn reference_rtol(&self) -> f64 {
        self.reference_rtol.unwrap_or_else(|| {
            let tightest = self.rtols.iter().copied().fold(f64::INFINITY, f64::min);
            // Rounded to 7 digits, so that 1e-7/100 reads 1e-9, not 9.999999999999999e-10.
            let r = format!("{:.6e}", tightest / 100.0)
                .parse()
                .unwrap_or(tightest / 100.0);
            f64::max(r, REFERENCE_RTOL_FLOOR)
        })
    }

    /// Checks the lists and numbers; errors name the option.
    pub fn validate(&self) -> Result<(), Error> {
        let empty = |what: &'static str, n: usize| {
            (n == 0).then(|| Error::settings(what, "give at least one"))
        };
        if let Some(e) = empty("formulations", self.formulations.len())
            .or_else(|| empty("methods", self.methods.len()))
            .or_else(|| empty("rtols", self.rtols.len()))
        {
            return Err(e);
        }
        if let Some(r) = self.rtols.iter().find(|r| !(r.is_finite() && **r > 0.0)) {
            return Err(Error::settings(
                "rtols",
                format!("expected positive tolerances, got {r}"),
            ));
        }
        if !(self.atol_per_rtol.is_finite() && self.atol_per_rtol > 0.0) {
            return Err(Error::settings(
                "atol_per_rtol",
                format!("expected a positive factor, got {}", self.atol_per_rtol),
            ));
        }
        if self.samples < 2 {
            return Err(Error::settings(
                "samples",
                format!("expected at least 2 samples, got {}", self.samples),
            ));
        }
        if self.repeats == 0 {
            return Err(Error::settings("repeats", "expected at least 1, got 0"));
        }
        if !(self.max_wall_per_run.is_finite() && self.max_wall_per_run > 0.0) {
            return Err(Error::settings(
                "max_wall_per_run",
                format!(
                    "expected a positive number of seconds, got {}",
                    self.max_wall_per_run
                ),
            ));
        }
        if self.reference_method == self.confirm_method {
            return Err(Error::settings(
                "confirm_method",
                format!(
                    "must differ from the reference method ({}): a second method confirms the reference",
                    self.reference_method
                ),
            ));
        }
        Ok(())
    }

    fn simulation_options(
        &self,
        kind: FormulationKind,
        method: Method,
        rtol: f64,
        dt: f64,
    ) -> SimulationOptions {
        let solver = SolverOptions::default()
            .method(method)
            .rtol(rtol)
            .atol(self.atol_per_rtol * rtol)
            .max_wall(self.max_wall_per_run);
        SimulationOptions {
            end: self.end,
            ..SimulationOptions::default()
                .formulation(kind)
                .dt(dt)
                .solver(solver)
        }
    }
}

/// The errors of one run against the reference of its formulation (module documentation).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CellErrors {
    /// Largest body-angle error over the common grid (rad).
    pub angle: f64,
    /// Largest journal-orbit error |Δe| (m); `None` without clearance joints.
    pub orbit: Option<f64>,
    /// Impacts of the run (all clearance joints).
    pub impacts: usize,
    /// Impacts of the reference.
    pub reference_impacts: usize,
    /// Every joint has as many impacts as in the reference.
    pub impacts_match: bool,
    /// Largest impact-time error over the impacts paired in order (s); `None` if none pairs.
    pub impact_time: Option<f64>,
    /// Largest error of the true peak normal force over the same pairs (N).
    pub peak_force: Option<f64>,
}

/// The cost of one cell.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CellCost {
    /// Median wall time of the timed runs (s).
    pub wall_s: f64,
    /// Every timed run's wall time (s).
    pub wall_runs_s: Vec<f64>,
    /// The first run's solver statistics (RHS evaluations, Jacobians, steps, rejections).
    pub stats: SolverStats,
}

/// One formulation × method × tolerance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Cell {
    /// Formulation.
    pub formulation: FormulationKind,
    /// Method.
    pub method: Method,
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
    /// Cost, if the run finished.
    pub cost: Option<CellCost>,
    /// Errors, if the run and its formulation's reference finished.
    pub errors: Option<CellErrors>,
    /// Why the cell failed (the error message with its causes); `None` if it finished.
    pub failure: Option<String>,
    /// Remarks (no reference, impact counts differ, …).
    pub note: String,
}

/// The reference of one formulation and its confirmation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Reference {
    /// Formulation.
    pub formulation: FormulationKind,
    /// Reference method.
    pub method: Method,
    /// Confirming method.
    pub confirm_method: Method,
    /// Tolerance of both (atol = atol_per_rtol × rtol).
    pub rtol: f64,
    /// Reference run cost (one run, not repeated).
    pub cost: Option<CellCost>,
    /// Impacts of the reference (all clearance joints).
    pub impacts: Option<usize>,
    /// The confirmation's errors against the reference: the reference's own error.
    pub own_error: Option<CellErrors>,
    /// Why the reference or its confirmation failed.
    pub failure: Option<String>,
}

/// A finished work–precision table.
#[derive(Debug, Clone, Serialize)]
pub struct WorkPrecisionReport {
    /// Model name.
    pub model: String,
    /// What made it: version, model file and overrides, the settings.
    pub provenance: Provenance,
    /// The settings.
    pub options: WorkPrecisionOptions,
    /// End time (s) and output interval (s) of every run.
    pub t_end: f64,
    /// Output interval (s).
    pub dt: f64,
    /// One reference per formulation, in the order of the options.
    pub references: Vec<Reference>,
    /// One cell per formulation × method × rtol, in that nesting order.
    pub cells: Vec<Cell>,
}

impl WorkPrecisionReport {
    /// The reference of a formulation.
    pub fn reference(&self, kind: FormulationKind) -> Option<&Reference> {
        self.references.iter().find(|r| r.formulation == kind)
    }
}

/// The message of an error with its causes, once each.
fn message(e: &Error) -> String {
    let mut text = e.to_string();
    let mut cause = std::error::Error::source(e);
    while let Some(c) = cause {
        let part = c.to_string();
        if !text.contains(&part) {
            text.push_str(": ");
            text.push_str(&part);
        }
        cause = c.source();
    }
    text
}

fn median(values: &[f64]) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// Runs `options` once to memory and `repeats − 1` more times to nothing; returns the first
/// run and the cost.
fn timed_run(
    model: &Model,
    options: SimulationOptions,
    repeats: usize,
) -> Result<(Trajectory, CellCost), Error> {
    let sim = Simulation::new(model, options)?;
    let first = sim.run_to_memory()?;
    let mut walls = vec![first.summary.wall_time_s];
    for _ in 1..repeats {
        walls.push(sim.run(&mut Discard)?.wall_time_s);
    }
    let cost = CellCost {
        wall_s: median(&walls),
        wall_runs_s: walls,
        stats: first.summary.solver_stats.clone(),
    };
    Ok((first, cost))
}

/// max |x − y| over the first common samples of two columns; NaN shows.
fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    let mut worst: f64 = 0.0;
    for (x, y) in a.iter().zip(b) {
        let d = (x - y).abs();
        worst = if d.is_nan() { f64::NAN } else { worst.max(d) };
    }
    worst
}

/// The errors of `run` against `reference` (module documentation).
pub fn errors(run: &Trajectory, reference: &Trajectory) -> CellErrors {
    let mut angle: f64 = 0.0;
    for name in run.names.iter().filter(|n| n.ends_with(".phi")) {
        if let (Some(a), Some(b)) = (run.column(name), reference.column(name)) {
            let d = max_difference(a, b);
            angle = if d.is_nan() { f64::NAN } else { angle.max(d) };
        }
    }
    let joints = &run.summary.clearance_joints;
    let ref_joints = &reference.summary.clearance_joints;
    let mut orbit: Option<f64> = None;
    let mut impact_time: Option<f64> = None;
    let mut peak_force: Option<f64> = None;
    let mut impacts_match = joints.len() == ref_joints.len();
    let worse = |acc: Option<f64>, d: f64| {
        Some(acc.map_or(d, |a: f64| if d.is_nan() { d } else { a.max(d) }))
    };
    for (j, r) in joints.iter().zip(ref_joints) {
        let column =
            |t: &Trajectory, c: &str| t.column(&format!("{}.{c}", j.joint)).map(<[f64]>::to_vec);
        if let (Some(ex), Some(ey), Some(rx), Some(ry)) = (
            column(run, "ex"),
            column(run, "ey"),
            column(reference, "ex"),
            column(reference, "ey"),
        ) {
            let mut worst: f64 = 0.0;
            for (((x, y), u), v) in ex.iter().zip(&ey).zip(&rx).zip(&ry) {
                let d = (x - u).hypot(y - v);
                worst = if d.is_nan() { f64::NAN } else { worst.max(d) };
            }
            orbit = worse(orbit, worst);
        }
        impacts_match &= j.impact_count == r.impact_count;
        for (a, b) in j.impacts.iter().zip(&r.impacts) {
            impact_time = worse(impact_time, (a.t - b.t).abs());
            peak_force = worse(
                peak_force,
                (a.peak_normal_force - b.peak_normal_force).abs(),
            );
        }
    }
    let count = |t: &Trajectory| -> usize {
        t.summary
            .clearance_joints
            .iter()
            .map(|j| j.impact_count)
            .sum()
    };
    CellErrors {
        angle,
        orbit,
        impacts: count(run),
        reference_impacts: count(reference),
        impacts_match,
        impact_time,
        peak_force,
    }
}

/// The provenance of a table: version, model source and every setting.
fn provenance(model: &Model, options: &WorkPrecisionOptions, t_end: f64, dt: f64) -> Provenance {
    let list = |v: Vec<String>| v.join(" ");
    let settings = [
        (
            "formulations",
            list(options.formulations.iter().map(|f| f.to_string()).collect()),
        ),
        (
            "methods",
            list(options.methods.iter().map(|m| m.to_string()).collect()),
        ),
        (
            "rtols",
            list(options.rtols.iter().map(|r| format_number(*r)).collect()),
        ),
        (
            "atol",
            format!("{} rtol", format_number(options.atol_per_rtol)),
        ),
        ("t_end", format_number(t_end)),
        ("dt", format_number(dt)),
        ("repeats", options.repeats.to_string()),
        ("max_wall_per_run", format_number(options.max_wall_per_run)),
        ("reference_method", options.reference_method.to_string()),
        ("confirm_method", options.confirm_method.to_string()),
        ("reference_rtol", format_number(options.reference_rtol())),
        (
            "baumgarte",
            format!(
                "alpha {} beta {}",
                format_number(model.settings.baumgarte.alpha),
                format_number(model.settings.baumgarte.beta)
            ),
        ),
    ];
    Provenance {
        linkdyn_version: crate::version(),
        model: model.source.clone(),
        settings: settings
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect(),
    }
}

/// Runs the reference of `kind` and its confirmation.
fn reference(
    model: &Model,
    options: &WorkPrecisionOptions,
    kind: FormulationKind,
    dt: f64,
) -> (Reference, Option<Trajectory>) {
    let rtol = options.reference_rtol();
    let mut r = Reference {
        formulation: kind,
        method: options.reference_method,
        confirm_method: options.confirm_method,
        rtol,
        cost: None,
        impacts: None,
        own_error: None,
        failure: None,
    };
    let run = |method| timed_run(model, options.simulation_options(kind, method, rtol, dt), 1);
    let main = match run(options.reference_method) {
        Ok((t, cost)) => {
            r.cost = Some(cost);
            r.impacts = Some(
                t.summary
                    .clearance_joints
                    .iter()
                    .map(|j| j.impact_count)
                    .sum(),
            );
            t
        }
        Err(e) => {
            r.failure = Some(format!(
                "reference {}: {}",
                options.reference_method,
                message(&e)
            ));
            return (r, None);
        }
    };
    match run(options.confirm_method) {
        Ok((t, _)) => r.own_error = Some(errors(&t, &main)),
        Err(e) => {
            r.failure = Some(format!(
                "confirmation {}: {}",
                options.confirm_method,
                message(&e)
            ))
        }
    }
    (r, Some(main))
}

/// Runs the table for `model`: per formulation its reference, then every method × rtol
/// (module documentation). `progress` receives each reference and each cell as it is done.
///
/// Errors: only bad options ([`Error::Settings`] naming the option) or an end time the model
/// cannot give (driver turns without a single driver); every run's failure is a cell.
pub fn run_workprecision(
    model: &Model,
    options: &WorkPrecisionOptions,
    mut progress: impl FnMut(Progress<'_>),
) -> Result<WorkPrecisionReport, Error> {
    options.validate()?;
    let t_end = crate::simulation::end_time(model, options.end)?;
    let dt = t_end / (options.samples - 1) as f64;
    let mut references = Vec::new();
    let mut cells = Vec::new();
    for &kind in &options.formulations {
        let (r, reference_run) = reference(model, options, kind, dt);
        progress(Progress::Reference(&r));
        for &method in &options.methods {
            for &rtol in &options.rtols {
                let sim_options = options.simulation_options(kind, method, rtol, dt);
                let mut cell = Cell {
                    formulation: kind,
                    method,
                    rtol,
                    atol: options.atol_per_rtol * rtol,
                    cost: None,
                    errors: None,
                    failure: None,
                    note: String::new(),
                };
                match timed_run(model, sim_options, options.repeats) {
                    Ok((run, cost)) => {
                        cell.cost = Some(cost);
                        match &reference_run {
                            Some(reference) => {
                                let e = errors(&run, reference);
                                if !e.impacts_match {
                                    cell.note = format!(
                                        "impact counts differ ({} vs {} in the reference): impacts paired in order",
                                        e.impacts, e.reference_impacts
                                    );
                                }
                                cell.errors = Some(e);
                            }
                            None => cell.note = "no reference: errors not measured".into(),
                        }
                    }
                    Err(e) => cell.failure = Some(message(&e)),
                }
                progress(Progress::Cell(&cell));
                cells.push(cell);
            }
        }
        references.push(r);
    }
    Ok(WorkPrecisionReport {
        model: model.name.clone(),
        provenance: provenance(model, options, t_end, dt),
        options: options.clone(),
        t_end,
        dt,
        references,
        cells,
    })
}

/// What [`run_workprecision`] has just finished.
#[derive(Debug, Clone, Copy)]
pub enum Progress<'a> {
    /// A formulation's reference (and its confirmation).
    Reference(&'a Reference),
    /// A cell.
    Cell(&'a Cell),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        assert!(median(&[]).is_nan());
    }

    #[test]
    fn reference_rtol_is_a_hundredth_of_the_tightest_with_a_floor() {
        let mut o = WorkPrecisionOptions {
            rtols: vec![1e-4, 1e-6],
            ..WorkPrecisionOptions::default()
        };
        assert_eq!(o.reference_rtol(), 1e-8);
        o.rtols = vec![1e-12];
        assert_eq!(o.reference_rtol(), REFERENCE_RTOL_FLOOR);
        o.reference_rtol = Some(1e-9);
        assert_eq!(o.reference_rtol(), 1e-9);
    }

    #[test]
    fn bad_options_name_the_option() {
        let bad = |o: WorkPrecisionOptions| o.validate().map_err(|e| e.to_string()).err();
        let d = WorkPrecisionOptions::default;
        assert_eq!(
            bad(WorkPrecisionOptions {
                rtols: vec![],
                ..d()
            })
            .as_deref(),
            Some("rtols: give at least one")
        );
        assert_eq!(
            bad(WorkPrecisionOptions { repeats: 0, ..d() }).as_deref(),
            Some("repeats: expected at least 1, got 0")
        );
        assert!(
            bad(WorkPrecisionOptions {
                confirm_method: Method::Dop853,
                ..d()
            })
            .is_some_and(|m| m.starts_with("confirm_method: must differ")),
        );
    }
}
