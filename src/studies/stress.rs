//! Stress table (docs/numerics.md, "Numerics under stress"): stiff and extreme cases of the reference four-bar
//! (`farahan2016.toml`), the two-joint slider-crank (`slider_crank_clearance.toml`), its
//! lubricated twin (`slider_crank_lubricated.toml`) and the slider-crank with clearance in the
//! slider's guide (`slider_crank_prismatic_clearance.toml`), each run
//! on every formulation the model supports × every method of [`Method::ALL`] × a list of
//! tolerances, with a wall-clock and a step budget per run and a [`Verdict`] per cell.
//!
//! A case is a list of `--set` overrides applied by [`model::load`]; a case
//! the model validation refuses is a correct outcome ([`Verdict::Refused`], with the message).
//! Every run goes through [`Simulation`] with `max_wall` and `max_steps` set, so no cell can
//! hang, and every error comes back as data: nothing here panics on a case.
//!
//! Verdicts (bounds in [`StressBounds`], their sizes argued in `docs/numerics.md`):
//!
//! * **ok**: the run reached t_end, the relative work–energy residual of the DAE run (with the
//!   energy bookkeeping) is below [`StressBounds::energy_residual`], and the body angles agree
//!   with the case's reference — the tightest-tolerance DOP853 DAE run of that case — within
//!   [`StressBounds::angle`]`(rtol)` over the comparison window;
//! * **slow**: over the wall-clock budget ([`SolveError::WallTimeExceeded`]), the step budget
//!   ([`SolveError::TooManySteps`]) or projected to be ([`SolveError::NoProgress`]: stiffness or
//!   step collapse); the cell says how far it got (t reached / t_end) and why;
//! * **failed**: any other error (time, joint and reason from its message), or a run that
//!   finished outside a bound;
//! * **refused**: the model validation refused the case.
//!
//! This module returns plain data; the `linkdyn stress` command prints it and writes the CSV.

use crate::error::Error;
use crate::model::{self, Model};
use crate::simulation::{EndTime, FormulationKind, Simulation, SimulationOptions, Trajectory};
use crate::solve::{Method, SolveError, SolverOptions};
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;

/// The reference four-bar (DAE and reduced formulation).
pub const FOURBAR: &str = "farahan2016.toml";
/// The slider-crank with two clearance joints (DAE only).
pub const SLIDER_CRANK: &str = "slider_crank_clearance.toml";
/// The slider-crank with clearance in the slider's guide (DAE only).
pub const SLIDER_GUIDE: &str = "slider_crank_prismatic_clearance.toml";
/// The slider-crank with its crank pin lubricated (DAE only).
pub const LUBRICATED: &str = "slider_crank_lubricated.toml";

/// What became of one cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Verdict {
    /// Reached t_end within the energy and agreement bounds.
    Ok,
    /// Stopped by the wall-clock or step budget.
    Slow,
    /// Stopped by another error, or finished outside a bound.
    Failed,
    /// The model validation refused the case.
    Refused,
}

impl Verdict {
    /// All verdicts.
    pub const ALL: [Verdict; 4] = [
        Verdict::Ok,
        Verdict::Slow,
        Verdict::Failed,
        Verdict::Refused,
    ];

    /// Lower-case name (`ok`, `slow`, `failed`, `refused`).
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Ok => "ok",
            Verdict::Slow => "slow",
            Verdict::Failed => "failed",
            Verdict::Refused => "refused",
        }
    }
}

impl std::fmt::Display for Verdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// One extreme case: a model file and its `--set` overrides.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StressCase {
    /// Short name (`clearance=1um`, `rpm=3500`, …).
    pub name: String,
    /// The axis it stresses (`reference`, `clearance`, `stiffness`, `speed`, `restitution`,
    /// `friction`, `eccentricity`, `duration`).
    pub axis: &'static str,
    /// Model file name inside the models directory.
    pub model: &'static str,
    /// `--set` overrides.
    pub overrides: Vec<String>,
    /// Length of the run in driver turns.
    pub turns: f64,
}

/// The bounds of the verdicts.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StressBounds {
    /// Largest relative work–energy residual of an ok DAE run
    /// ([`EnergyBalance::relative_residual`](crate::simulation::EnergyBalance::relative_residual)).
    pub energy_residual: f64,
    /// Factor k of the angle bound k·rtol (rad) between a cell and its case's reference.
    pub angle_per_rtol: f64,
    /// Driver turns over which the angles are compared (from t0): beyond a few turns the
    /// rattling journal's motion is chaotic and runs separate at any tolerance.
    pub compare_turns: f64,
}

impl Default for StressBounds {
    /// energy residual 1e-4, angle bound 1e3·rtol rad, compared over the first 2 turns
    /// (reasons in `docs/numerics.md`).
    fn default() -> Self {
        StressBounds {
            energy_residual: 1e-4,
            angle_per_rtol: 1e3,
            compare_turns: 2.0,
        }
    }
}

impl StressBounds {
    /// The angle bound (rad) for a run at `rtol`.
    pub fn angle(&self, rtol: f64) -> f64 {
        self.angle_per_rtol * rtol
    }
}

/// Settings of a stress run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StressOptions {
    /// Directory holding [`FOURBAR`] and [`SLIDER_CRANK`].
    pub models_dir: PathBuf,
    /// The quick subset (one case per axis, ~2-turn runs).
    pub quick: bool,
    /// Relative tolerances of the grid (atol = 1e-3·rtol, m and rad).
    pub rtols: Vec<f64>,
    /// Wall-clock budget of each run (s).
    pub max_wall_per_run: f64,
    /// Step-attempt budget of each run.
    pub max_steps_per_run: u64,
    /// Output samples per driver turn.
    pub samples_per_turn: f64,
    /// Verdict bounds.
    pub bounds: StressBounds,
}

impl StressOptions {
    /// Full mode: every case, rtol 1e-6 and 1e-8, 60 s and 2·10⁷ step attempts per run.
    pub fn full(models_dir: impl Into<PathBuf>) -> Self {
        StressOptions {
            models_dir: models_dir.into(),
            quick: false,
            rtols: vec![1e-6, 1e-8],
            max_wall_per_run: 60.0,
            max_steps_per_run: 20_000_000,
            samples_per_turn: 200.0,
            bounds: StressBounds::default(),
        }
    }

    /// Quick mode (CI): one case per axis, rtol 1e-6, 4 s and 10⁶ step attempts per run.
    pub fn quick(models_dir: impl Into<PathBuf>) -> Self {
        StressOptions {
            quick: true,
            rtols: vec![1e-6],
            max_wall_per_run: 4.0,
            max_steps_per_run: 1_000_000,
            ..StressOptions::full(models_dir)
        }
    }
}

/// One cell: a case on one formulation × method × rtol (or the refusal of the case).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StressCell {
    /// Case name.
    pub case: String,
    /// Axis of the case.
    pub axis: &'static str,
    /// Model file name.
    pub model: &'static str,
    /// Formulation (`None` for a refused case).
    pub formulation: Option<FormulationKind>,
    /// Method (`None` for a refused case).
    pub method: Option<Method>,
    /// Relative tolerance (`None` for a refused case).
    pub rtol: Option<f64>,
    /// The verdict.
    pub verdict: Verdict,
    /// Wall-clock time of the run (s).
    pub wall_s: f64,
    /// Right-hand-side evaluations (`None` when the run stopped early).
    pub rhs_evals: Option<u64>,
    /// Impacts summed over the clearance joints (`None` when the run stopped early).
    pub impacts: Option<usize>,
    /// Relative work–energy residual (DAE runs that finished).
    pub energy_residual: Option<f64>,
    /// max |Δφ| of the body angles against the case's reference over the comparison window
    /// (rad; `None` when either run stopped early).
    pub max_angle_difference: Option<f64>,
    /// t reached / t_end (1 for a finished run; `None` for a refused case).
    pub fraction_reached: Option<f64>,
    /// Why: the error message, the bound exceeded, or notes.
    pub note: String,
}

/// A stress table.
#[derive(Debug, Clone, Serialize)]
pub struct StressReport {
    /// The settings it ran with.
    pub options: StressOptions,
    /// The models as loaded without overrides (their provenance: path, SHA-256).
    pub models: Vec<crate::model::ModelSource>,
    /// One cell per case × formulation × method × rtol, refused cases once.
    pub cells: Vec<StressCell>,
}

fn case(axis: &'static str, name: &str, model: &'static str, sets: &[&str]) -> StressCase {
    StressCase {
        name: name.to_string(),
        axis,
        model,
        overrides: sets.iter().map(|s| s.to_string()).collect(),
        turns: 2.0,
    }
}

/// The cases: on the four-bar every axis, on the slider-crank (two clearance joints) the
/// reference and the extremes of each axis. `quick`: one case per axis (plus the two refused
/// ones and the slider-crank's reference).
pub fn cases(quick: bool) -> Vec<StressCase> {
    let fb = FOURBAR;
    let mut all = vec![
        (true, case("reference", "reference", fb, &[])),
        (true, case("reference", "reference", SLIDER_CRANK, &[])),
        (true, case("reference", "reference", SLIDER_GUIDE, &[])),
        (
            true,
            case("clearance", "c=1um", fb, &["joints.B.clearance=1e-6"]),
        ),
        (
            false,
            case("clearance", "c=0.1mm", fb, &["joints.B.clearance=1e-4"]),
        ),
        (
            false,
            case("clearance", "c=5mm", fb, &["joints.B.clearance=5e-3"]),
        ),
        (
            true,
            case(
                "stiffness",
                "E*1000",
                fb,
                &["joints.B.youngs_modulus=207e12"],
            ),
        ),
        (
            false,
            case(
                "stiffness",
                "E*5",
                fb,
                &["joints.B.youngs_modulus=1.035e12"],
            ),
        ),
        (
            false,
            case("speed", "rpm=10", fb, &["drivers.motor.speed_rpm=10"]),
        ),
        (
            true,
            case("speed", "rpm=3500", fb, &["drivers.motor.speed_rpm=3500"]),
        ),
        (
            false,
            case("speed", "rpm=10000", fb, &["drivers.motor.speed_rpm=10000"]),
        ),
        (
            true,
            case("friction", "cf=0", fb, &["joints.B.friction.law=none"]),
        ),
        (
            false,
            case(
                "friction",
                "cf=0.5",
                fb,
                &["joints.B.friction.coefficient=0.5"],
            ),
        ),
        (
            false,
            case(
                "friction",
                "cf=1.0",
                fb,
                &["joints.B.friction.coefficient=1.0"],
            ),
        ),
        (
            true,
            case(
                "eccentricity",
                "e0=0.999c",
                fb,
                &["joints.B.initial_eccentricity=[4.995e-4, 0.0]"],
            ),
        ),
        (
            true,
            case(
                "eccentricity",
                "e0=c (on the wall)",
                fb,
                &["joints.B.initial_eccentricity=[5e-4, 0.0]"],
            ),
        ),
    ];
    // Restitution × contact law: hertz is purely elastic (c_r = 1 only).
    for law in ["lankarani-nikravesh", "hunt-crossley", "flores"] {
        for c_r in ["0.01", "0.3", "0.9"] {
            if law == "lankarani-nikravesh" && c_r == "0.9" {
                continue; // the reference case
            }
            let quick = law == "flores" && c_r == "0.01";
            all.push((
                quick,
                case(
                    "restitution",
                    &format!("{law} cr={c_r}"),
                    fb,
                    &[
                        &format!("joints.B.contact.law={law}"),
                        &format!("joints.B.contact.restitution={c_r}"),
                    ],
                ),
            ));
        }
    }
    all.push((
        false,
        case(
            "restitution",
            "hertz cr=1",
            fb,
            &["joints.B.contact.law=hertz"],
        ),
    ));
    // The line-contact laws (docs/contact_laws.md), each with its default damping, at the
    // extremes of the clearance where they differ most from the point-contact laws.
    for law in ["johnson", "liu"] {
        for (name, clearance) in [
            ("c=0.5mm", None),
            ("c=1um", Some("joints.B.clearance=1e-6")),
        ] {
            let law_set = format!("joints.B.contact.law={law}");
            let mut sets = vec!["joints.B.length=0.02", law_set.as_str()];
            sets.extend(clearance);
            all.push((
                false,
                case("contact law", &format!("{law} {name}"), fb, &sets),
            ));
        }
    }
    // The slider-crank at the extremes (its joint B: the wrist pin).
    for (axis, name, set) in [
        ("clearance", "c=1um", "joints.B.clearance=1e-6"),
        ("clearance", "c=5mm", "joints.B.clearance=5e-3"),
        ("speed", "rpm=3500", "drivers.motor.speed_rpm=3500"),
        ("friction", "cf=1.0", "joints.B.friction.coefficient=1.0"),
    ] {
        all.push((false, case(axis, name, SLIDER_CRANK, &[set])));
    }
    // The slider in its guide with clearance (joint rail) at the extremes.
    for (axis, name, set) in [
        ("clearance", "c=1um", "joints.rail.clearance=1e-6"),
        ("speed", "rpm=3500", "drivers.motor.speed_rpm=3500"),
        ("friction", "cf=1.0", "joints.rail.friction.coefficient=1.0"),
    ] {
        all.push((false, case(axis, name, SLIDER_GUIDE, &[set])));
    }
    // The lubricated slider-crank (docs/lubrication.md): its reference, the short film in place
    // of the long one, and the high speed, where the film is thinnest.
    for (name, sets) in [
        ("reference", &[][..]),
        ("short film", &["joints.A.lubrication.model=short"][..]),
        ("rpm=3500", &["drivers.motor.speed_rpm=3500"][..]),
    ] {
        all.push((false, case("lubrication", name, LUBRICATED, sets)));
    }
    let mut long = case("duration", "1000 turns", fb, &[]);
    long.turns = 1000.0;
    all.push((false, long));
    all.into_iter()
        .filter(|(q, _)| *q || !quick)
        .map(|(_, c)| c)
        .collect()
}

/// The formulations `model` supports: the reduced one only for the four-bar.
fn formulations(model_file: &str) -> Vec<FormulationKind> {
    if model_file == FOURBAR {
        vec![FormulationKind::Dae, FormulationKind::Reduced]
    } else {
        vec![FormulationKind::Dae]
    }
}

/// Time reached, and why a run that stopped is slow (`Some`) rather than failed (`None`).
fn stop_reason(e: &Error) -> (Option<f64>, Option<&'static str>) {
    match e {
        Error::Solve(s) => match s {
            SolveError::WallTimeExceeded { t, .. } => (Some(*t), Some("wall-clock budget")),
            SolveError::TooManySteps { t, .. } => (Some(*t), Some("step budget")),
            SolveError::NoProgress { t, stiff, .. } => (
                Some(*t),
                Some(if *stiff {
                    "stiffness (step limited by stability)"
                } else {
                    "step collapse"
                }),
            ),
            SolveError::StepTooSmall { t, .. }
            | SolveError::NonFinite { t, .. }
            | SolveError::Sink { t, .. }
            | SolveError::EventNotConverged { t, .. }
            | SolveError::InvalidMaxStep { t, .. }
            | SolveError::OutsideStep { t, .. } => (Some(*t), None),
            SolveError::Formulation { t, .. } => (Some(*t), None),
            _ => (None, None),
        },
        _ => (None, None),
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

/// A finished run of one cell.
struct Finished {
    trajectory: Trajectory,
    wall_s: f64,
}

/// The outcome of one run: finished, or the cell it became.
enum Outcome {
    Finished(Box<Finished>),
    Stopped(StressCell),
}

/// Settings of one run.
struct RunSpec {
    formulation: FormulationKind,
    method: Method,
    rtol: f64,
}

fn run_one(
    model: &Model,
    case: &StressCase,
    spec: &RunSpec,
    options: &StressOptions,
    t_end: f64,
) -> Outcome {
    let solver = SolverOptions::default()
        .method(spec.method)
        .rtol(spec.rtol)
        .atol(1e-3 * spec.rtol)
        .max_steps(options.max_steps_per_run)
        .max_wall(options.max_wall_per_run);
    let dt = t_end / (case.turns * options.samples_per_turn);
    let sim_options = SimulationOptions::default()
        .formulation(spec.formulation)
        .energy(spec.formulation == FormulationKind::Dae)
        .t_end(t_end)
        .dt(dt)
        .solver(solver);
    let started = Instant::now();
    let result = Simulation::new(model, sim_options).and_then(|sim| sim.run_to_memory());
    let wall_s = started.elapsed().as_secs_f64();
    let cell = |verdict, fraction: Option<f64>, note: String| StressCell {
        case: case.name.clone(),
        axis: case.axis,
        model: case.model,
        formulation: Some(spec.formulation),
        method: Some(spec.method),
        rtol: Some(spec.rtol),
        verdict,
        wall_s,
        rhs_evals: None,
        impacts: None,
        energy_residual: None,
        max_angle_difference: None,
        fraction_reached: fraction,
        note,
    };
    match result {
        Ok(trajectory) => Outcome::Finished(Box::new(Finished { trajectory, wall_s })),
        Err(e) => {
            let (t, slow) = stop_reason(&e);
            let fraction = t.map(|t| (t / t_end).clamp(0.0, 1.0));
            let reached = t.map_or(String::new(), |t| {
                format!("t = {t:.6} of {t_end:.6} s ({:.1} %); ", 100.0 * t / t_end)
            });
            match slow {
                Some(why) => Outcome::Stopped(cell(
                    Verdict::Slow,
                    fraction,
                    format!("{why}: {reached}{}", message(&e)),
                )),
                None => Outcome::Stopped(cell(
                    Verdict::Failed,
                    fraction,
                    format!("{reached}{}", message(&e)),
                )),
            }
        }
    }
}

/// max |Δφ| over the body angles of `a` and `b` over their first `samples` common samples.
fn angle_difference(a: &Trajectory, b: &Trajectory, samples: usize) -> f64 {
    let mut worst: f64 = 0.0;
    for (ka, name) in a.names.iter().enumerate() {
        if !name.ends_with(".phi") {
            continue;
        }
        let Some(kb) = b.names.iter().position(|n| n == name) else {
            continue;
        };
        let (Some(ca), Some(cb)) = (a.columns.get(ka), b.columns.get(kb)) else {
            continue;
        };
        for (x, y) in ca.iter().zip(cb).take(samples) {
            let d = (x - y).abs();
            // A NaN difference must show, not vanish in f64::max.
            worst = if d.is_nan() { f64::NAN } else { worst.max(d) };
        }
    }
    worst
}

/// Runs one case on every formulation × method × rtol; refused cases give one cell.
pub fn run_case(case: &StressCase, options: &StressOptions) -> Vec<StressCell> {
    let path = options.models_dir.join(case.model);
    let refused = |note: String| StressCell {
        case: case.name.clone(),
        axis: case.axis,
        model: case.model,
        formulation: None,
        method: None,
        rtol: None,
        verdict: Verdict::Refused,
        wall_s: 0.0,
        rhs_evals: None,
        impacts: None,
        energy_residual: None,
        max_angle_difference: None,
        fraction_reached: None,
        note,
    };
    let model = match model::load(&path, &case.overrides) {
        Ok(m) => m,
        Err(e) => return vec![refused(e.to_string())],
    };
    let notes = model.notes.join("; ");
    let t_end = match crate::simulation::end_time(&model, EndTime::DriverTurns(case.turns)) {
        Ok(t) => t,
        Err(e) => return vec![refused(message(&e))],
    };
    let mut specs = Vec::new();
    for &rtol in &options.rtols {
        for formulation in formulations(case.model) {
            for method in Method::ALL {
                specs.push(RunSpec {
                    formulation,
                    method,
                    rtol,
                });
            }
        }
    }
    // The reference (tightest rtol, DOP853, DAE) first.
    let tightest = options.rtols.iter().copied().fold(f64::INFINITY, f64::min);
    let is_reference = |s: &RunSpec| {
        s.rtol == tightest && s.method == Method::Dop853 && s.formulation == FormulationKind::Dae
    };
    specs.sort_by_key(|s| !is_reference(s));
    let compare_samples = (options.bounds.compare_turns.min(case.turns) * options.samples_per_turn)
        .round() as usize
        + 1;
    let mut reference: Option<Trajectory> = None;
    let mut reference_impacts: Option<usize> = None;
    let mut reference_missing = false;
    let mut cells = Vec::new();
    for spec in &specs {
        let finished = match run_one(&model, case, spec, options, t_end) {
            Outcome::Stopped(mut cell) => {
                if !notes.is_empty() {
                    cell.note = format!("{}; {notes}", cell.note);
                }
                if is_reference(spec) {
                    reference_missing = true;
                }
                cells.push(cell);
                continue;
            }
            Outcome::Finished(f) => f,
        };
        let summary = &finished.trajectory.summary;
        let energy_residual = summary.energy_balance.as_ref().map(|e| e.relative_residual);
        let max_angle_difference = reference
            .as_ref()
            .map_or(Some(0.0), |r| {
                Some(angle_difference(&finished.trajectory, r, compare_samples))
            })
            .filter(|_| !reference_missing);
        let angle_bound = options.bounds.angle(spec.rtol);
        let mut problems = Vec::new();
        if let Some(r) = energy_residual
            && (r.is_nan() || r > options.bounds.energy_residual)
        {
            problems.push(format!(
                "energy residual {r:.2e} above the bound {:.0e}",
                options.bounds.energy_residual
            ));
        }
        if let Some(d) = max_angle_difference
            && (d.is_nan() || d > angle_bound)
        {
            let impacts: usize = summary
                .clearance_joints
                .iter()
                .map(|j| j.impact_count)
                .sum();
            let separated = if reference_impacts != Some(impacts) {
                format!(
                    " (impacts {impacts} vs {} in the reference: the impact sequences separated)",
                    reference_impacts.map_or("?".to_string(), |n| n.to_string())
                )
            } else {
                String::new()
            };
            problems.push(format!(
                "angles differ from the reference by {d:.2e} rad, above the bound {angle_bound:.0e} rad{separated}"
            ));
        }
        let verdict = if problems.is_empty() {
            Verdict::Ok
        } else {
            Verdict::Failed
        };
        if reference_missing {
            problems.push("reference run stopped: angles not compared".to_string());
        } else if is_reference(spec) {
            problems.push("reference".to_string());
        }
        if !notes.is_empty() {
            problems.push(notes.clone());
        }
        let note = problems.join("; ");
        cells.push(StressCell {
            case: case.name.clone(),
            axis: case.axis,
            model: case.model,
            formulation: Some(spec.formulation),
            method: Some(spec.method),
            rtol: Some(spec.rtol),
            verdict,
            wall_s: finished.wall_s,
            rhs_evals: Some(summary.solver_stats.rhs_evals),
            impacts: Some(
                summary
                    .clearance_joints
                    .iter()
                    .map(|j| j.impact_count)
                    .sum(),
            ),
            energy_residual,
            max_angle_difference,
            fraction_reached: Some(1.0),
            note,
        });
        if is_reference(spec) {
            reference_impacts = Some(
                summary
                    .clearance_joints
                    .iter()
                    .map(|j| j.impact_count)
                    .sum(),
            );
            reference = Some(finished.trajectory);
        }
    }
    cells
}

/// Runs every case of `options` (see [`cases`]), one after the other, calling `progress`
/// with each case's cells as they are done.
pub fn run_stress(
    options: &StressOptions,
    mut progress: impl FnMut(&StressCase, &[StressCell]),
) -> StressReport {
    let mut models = Vec::new();
    for file in [FOURBAR, SLIDER_CRANK, SLIDER_GUIDE] {
        if let Ok(m) = model::load(&options.models_dir.join(file), &[]) {
            models.push(m.source);
        }
    }
    let mut cells = Vec::new();
    for case in cases(options.quick) {
        let done = run_case(&case, options);
        progress(&case, &done);
        cells.extend(done);
    }
    StressReport {
        options: options.clone(),
        models,
        cells,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quick_cases_are_a_subset_with_one_per_axis() {
        let quick = cases(true);
        let full = cases(false);
        for c in &quick {
            assert!(
                full.contains(c),
                "quick case {} not in the full table",
                c.name
            );
        }
        for axis in [
            "reference",
            "clearance",
            "stiffness",
            "speed",
            "restitution",
            "friction",
            "eccentricity",
        ] {
            assert!(
                quick.iter().any(|c| c.axis == axis),
                "quick mode misses axis {axis}"
            );
        }
        assert!(full.iter().any(|c| c.turns == 1000.0), "no 1000-turn case");
        assert!(
            quick.iter().all(|c| c.turns == 2.0),
            "quick runs are 2 turns"
        );
    }

    #[test]
    fn budget_errors_are_slow_with_the_time_reached() {
        let e = Error::Solve(SolveError::TooManySteps { t: 0.1, steps: 9 });
        assert_eq!(stop_reason(&e), (Some(0.1), Some("step budget")));
        let e = Error::Solve(SolveError::StepTooSmall { t: 0.2, h: 1e-20 });
        assert_eq!(
            stop_reason(&e),
            (Some(0.2), None),
            "a step collapse to ε fails"
        );
    }
}
