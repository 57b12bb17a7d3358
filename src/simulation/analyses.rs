//! Model-level analyses: the tools of [`crate::analysis`] applied to a [`Simulation`] (the
//! formulation it built, its solver options, its single driver).
//!
//! | function | what |
//! |---|---|
//! | [`poincare`] | section once per driver turn at the exact instants, with the period verdict |
//! | [`poincare_from`] | the same with transient detection and a warm start from another point's end |
//! | [`spectrum`] | amplitude spectrum of an output column, peaks as multiples of the driving frequency |
//! | [`phase`] | phase-portrait data of an output column (its rate column or differences) |
//! | [`lyapunov`] | largest Lyapunov exponent (bookkeeping states masked, states scaled) |
//! | [`bifurcation`] | a sweep of any model field (`--set` path), one section per point, in parallel |
//!
//! # Driver turns
//! Every analysis counts time in turns of the model's single driver: T = 2π/|ω| (s), turn k
//! starts at t0 + kT, and the section of turn k is taken at t_k = t0 + φ/|ω| + kT for a phase
//! offset φ ∈ [0, 2π) rad.
//!
//! # Period tolerance
//! The verdict ([`period_verdict`](analysis::period_verdict)) compares section points. Each
//! point carries the integration's error, which the step control keeps near atol + rtol·|y|
//! per step and which a settled (contracting) orbit does not accumulate beyond a modest
//! multiple of it. Each component j is therefore divided by its integration tolerance ε_j
//! before the verdict: for a state, ε_j = atol + rtol·max_i |p_{i,j}|; for an output column,
//! the larger of that and the states' tolerances carried through the column's sensitivities at
//! the initial state (see `propagated_tolerance`). The verdict is then asked for
//! tol_abs = [`PERIOD_TOL_FACTOR`] (= 1000 ε_j in the component's units) and
//! tol_rel = [`PERIOD_TOL_REL`] of the component's spread; [`ModelSection::tolerance`] gives
//! the tolerance in the component's units, which the command line prints.
//!
//! Measured on the reference four-bar at 3500 rpm, c = 0.44 mm (reduced formulation): the
//! turn-to-turn jitter of the settled period-one section is up to 16 ε for `coupler.phi`
//! (rtol 1e-8) and up to about 100 ε for the journal eccentricity (rtol 1e-10, propagated ε),
//! and it scales with rtol: 1000 ε leaves a margin of 4 or more.
//!
//! # Transient detection and warm starts
//! [`poincare_from`] can end the transient early ([`Settle`]): the section is then taken at
//! every turn from the start, and the transient ends after turn τ − 1 for the first τ ≥
//! `min_transient` at which the last [`SETTLE_REPEATS`] points each repeat the one k turns
//! before (for some k ≤ [`SETTLE_K_MAX`]) within [`SETTLE_TOL_FACTOR`]·ε_j (ε_j as above), or
//! after the full `transient` turns if that never happens. The recorded points follow, as many
//! as without detection. The factor is 100 times below the verdict's: a transient that has come
//! within 1000 ε of its attractor is not over (on the reference four-bar at 3500 rpm, rtol
//! 1e-6, 1000 ε of `coupler.phi` is 6.4e-4 rad, about the whole Fig. 6a diagram), while the
//! settled turn-to-turn jitter is about 3 ε (1.7e-6 rad): 10 ε leaves a margin of 3, and a
//! jitter above it only costs the full transient.
//!
//! It can also start from where a neighbouring point's run ended (a [`WarmState`] of the
//! reduced formulation, [`ReducedLagrangian::start_from`](crate::formulation::ReducedLagrangian::start_from)) instead of the model's initial
//! state: the run then starts at the section's phase, t = t0 + φ/|ω|, where the earlier run's
//! last point was taken, so the turns and the section stay aligned.

use std::path::Path;

use serde::Serialize;

use super::{Built, EndTime, FormulationKind, Simulation, SimulationOptions};
use crate::analysis::{
    self, AnalysisError, Chunk, Direction, LyapunovEstimate, LyapunovOptions, ParameterGrid,
    PeriodAnalysis, PeriodOptions, PeriodVerdict, PhasePortrait, PoincareSection, SectionOptions,
    Spectrum, SpectrumOptions, SweepPoint,
};
use crate::error::{Error, Result};
use crate::formulation::reduced_lagrangian::WarmState;
use crate::formulation::{Formulation, Outputs};
use crate::model::Model;

/// Period tolerance in units of a component's integration tolerance ε_j (module docs).
pub const PERIOD_TOL_FACTOR: f64 = 1e3;
/// Period tolerance relative to a component's spread over the judged points (module docs):
/// differences below 0.1 % of the attractor's extent are not told apart.
pub const PERIOD_TOL_REL: f64 = 1e-3;
/// Transient detection: tolerance in units of ε_j (module docs).
pub const SETTLE_TOL_FACTOR: f64 = 10.0;
/// Transient detection: consecutive points that must repeat (module docs).
pub const SETTLE_REPEATS: usize = 4;
/// Transient detection: the longest period looked for, as the verdict's.
pub const SETTLE_K_MAX: usize = 8;

/// Transient detection (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Settle {
    /// Fewest transient turns, whatever the points say.
    pub min_transient: usize,
}

/// Fewest transient turns with transient detection unless the caller says otherwise.
pub const DEFAULT_TRANSIENT_MIN: usize = 5;
/// Chunks of a warm-started sweep unless the caller says otherwise: one per this many points
/// (a cold start costs a few turns more than a warm one, so short chunks waste little)…
pub const POINTS_PER_CHUNK: usize = 25;
/// … and at most this many (the Fig. 6a grid of 200 points: 8).
pub const MAX_DEFAULT_CHUNKS: usize = 8;

/// What a sweep asks for beyond independent points, as given (before [`SweepMode::new`]
/// checks it).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct SweepModeRequest {
    /// Transient detection (`settle`).
    pub settle: bool,
    /// Fewest transient turns with `settle` (`transient_min`).
    pub transient_min: Option<usize>,
    /// Most transient turns (`transient`).
    pub transient: usize,
    /// Warm starts (`warm_start`).
    pub warm_start: bool,
    /// Chunks of a warm-started sweep (`chunks`).
    pub chunks: Option<usize>,
    /// Branches of a warm-started sweep (`direction`: up, down, or both as `[Up, Down]`).
    pub directions: Option<Vec<Direction>>,
    /// Whether the sweep is a shard of a larger one (`shard`).
    pub sharded: bool,
    /// Points in the grid.
    pub n_points: usize,
}

/// A checked sweep mode: transient detection and warm starts.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SweepMode {
    /// Transient detection, if asked for.
    pub settle: Option<Settle>,
    /// Chunks and directions of a warm-started sweep, if asked for.
    pub warm: Option<(usize, Vec<Direction>)>,
}

impl SweepMode {
    /// Checks the options of transient detection and warm starts against each other and the
    /// formulation (`formulation`), before any work; fills in the defaults.
    ///
    /// Errors: [`Error::Settings`] naming the option that cannot apply, and why.
    pub fn new(request: &SweepModeRequest, formulation: FormulationKind) -> Result<SweepMode> {
        let r = request;
        if !r.settle && r.transient_min.is_some() {
            return Err(Error::settings(
                "transient_min",
                "sets the fewest transient turns of `settle`; add `settle` or leave it out",
            ));
        }
        let settle = if r.settle {
            let min = r.transient_min.unwrap_or(DEFAULT_TRANSIENT_MIN);
            if min > r.transient {
                return Err(Error::settings(
                    "transient_min",
                    format!(
                        "expected at most the {} turns of `transient` (the most a transient may take), got {min}",
                        r.transient
                    ),
                ));
            }
            Some(Settle { min_transient: min })
        } else {
            None
        };
        if !r.warm_start {
            for (given, option) in [
                (r.chunks.is_some(), "chunks"),
                (r.directions.is_some(), "direction"),
            ] {
                if given {
                    return Err(Error::settings(
                        option,
                        "applies to a warm-started sweep only; add `warm_start` or leave it out",
                    ));
                }
            }
            return Ok(SweepMode { settle, warm: None });
        }
        if r.sharded {
            return Err(Error::settings(
                "shard",
                "a warm-started sweep (`warm_start`) cannot be sharded: each point starts from the one before it in its chunk, and a shard takes every n-th point; split it with `chunks` and `threads` instead",
            ));
        }
        if formulation != FormulationKind::Reduced {
            return Err(Error::settings(
                "warm_start",
                format!(
                    "needs `formulation` reduced (only the reduced model can start from another point's state), got `formulation` {formulation}"
                ),
            ));
        }
        let chunks = r
            .chunks
            .unwrap_or((r.n_points / POINTS_PER_CHUNK).clamp(1, MAX_DEFAULT_CHUNKS));
        let directions = r.directions.clone().unwrap_or_else(|| vec![Direction::Up]);
        Ok(SweepMode {
            settle,
            warm: Some((chunks, directions)),
        })
    }

    /// Whether the verdicts carry the transient turns and the start (`transient_turns,start`).
    pub fn extended(&self) -> bool {
        self.settle.is_some() || self.warm.is_some()
    }

    /// The chunks of a warm-started sweep over `grid`, every direction's (none without warm
    /// starts).
    ///
    /// Errors: more chunks than points.
    pub fn chunks(&self, grid: &ParameterGrid) -> Result<Option<Vec<Chunk>>> {
        let Some((n, directions)) = &self.warm else {
            return Ok(None);
        };
        let mut all = Vec::new();
        for d in directions {
            all.extend(analysis::continuation_chunks(grid, *n, *d)?);
        }
        Ok(Some(all))
    }
}

/// A section of [`poincare_from`]: the section, how it started, and where it ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PointRun {
    /// The section and its verdict; `section.turns[0]` is the transient turns used.
    pub section: ModelSection,
    /// Whether it started from the given [`WarmState`] (false: from the model's initial state,
    /// also when the warm state could not be carried into this model).
    pub warm: bool,
    /// The state at its last point (reduced formulation only), for the next point to start
    /// from.
    pub end: Option<WarmState>,
}

/// Applies `$body` to the simulation's formulation, cloned into `$f` (a fresh copy per call,
/// as [`Simulation::run`] does, so the simulation can be reused).
macro_rules! with_formulation {
    ($sim:expr, $f:ident => $body:expr) => {
        match &$sim.formulation {
            Built::Dae(b) => {
                let mut $f = (**b).clone();
                $body
            }
            Built::Reduced(b) => {
                let mut $f = (**b).clone();
                $body
            }
            Built::Generalized(b) => {
                let mut $f = (**b).clone();
                $body
            }
        }
    };
}

/// Angular speed |ω| (rad/s) of the model's single driver. Errors: [`Error::Settings`] for
/// `option` when the model has not exactly one driver with a non-zero speed.
pub fn driver_speed(model: &Model, option: &'static str) -> Result<f64> {
    match model.drivers.as_slice() {
        [d] if d.speed.is_finite() && d.speed != 0.0 => Ok(d.speed.abs()),
        [d] => Err(Error::settings(
            option,
            format!(
                "driver turns need a driver that turns, but driver \"{}\" has speed {} rad/s",
                d.name, d.speed
            ),
        )),
        ds => Err(Error::settings(
            option,
            format!(
                "driver turns need exactly one driver, the model has {}",
                ds.len()
            ),
        )),
    }
}

/// Where and how long to cut: `turns` driver turns in all, the first `transient` dropped, one
/// point per turn at phase `phase` (rad) of the turn.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SectionSpec {
    /// Driver turns integrated, R ≥ transient + 1.
    pub turns: usize,
    /// Turns dropped before the first point, M.
    pub transient: usize,
    /// Phase offset φ within the turn (rad), in [0, 2π).
    pub phase: f64,
    /// Output columns to record; empty for [`default_section_columns`] (angles modulo whole
    /// turns).
    pub observe: Vec<String>,
}

/// The columns a section records when none are named: what describes the motion at the
/// section, and nothing that does not — each clearance joint's eccentricity (`J.ex`, `J.ey`)
/// and each moving body's angle and rate (`b.phi`, `b.omega`), in model order. Never the
/// formulation's raw states (bookkeeping such as a stored impact velocity) or a driven angle
/// that grows by a turn every turn: [`poincare`] takes the angles of these columns modulo
/// whole turns (the first point's into (−π, π], the others nearest it), so that a body that turns with the
/// crank repeats as one that swings does.
pub fn default_section_columns(sim: &Simulation) -> Vec<String> {
    let mut columns = Vec::new();
    for joint in &sim.model.joints {
        if matches!(joint.kind, crate::model::JointKind::Clearance(_)) {
            columns.push(format!("{}.ex", joint.name));
            columns.push(format!("{}.ey", joint.name));
        }
    }
    for body in &sim.model.bodies {
        columns.push(format!("{}.phi", body.name));
        columns.push(format!("{}.omega", body.name));
    }
    columns.retain(|c| sim.names.contains(c));
    columns
}

/// Shifts each `angles` component of the points by whole turns: the first point's into
/// (−π, π], every other to the value nearest the first's. The angle of a body that turns once
/// per driver turn then repeats at the section, and one that swings keeps its swing whole.
fn modulo_turns(points: &mut [Vec<f64>], angles: &[bool]) {
    let tau = std::f64::consts::TAU;
    let Some(mut first) = points.first().cloned() else {
        return;
    };
    for (f, _) in first.iter_mut().zip(angles).filter(|(_, a)| **a) {
        *f -= tau * (*f / tau).round();
    }
    for p in points.iter_mut() {
        for ((v, &f), _) in p.iter_mut().zip(&first).zip(angles).filter(|(_, a)| **a) {
            *v -= tau * ((*v - f) / tau).round();
        }
    }
}

/// A section of a model with its period verdict.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelSection {
    /// Turn number k of each point (M, …, R − 1).
    pub turns: Vec<usize>,
    /// The section itself (names, exact times t_k, points, solver statistics).
    pub section: PoincareSection,
    /// Period verdict on the points (tolerances in units of ε_j, see the module docs).
    pub period: PeriodAnalysis,
    /// Period tolerance per component in the component's units: PERIOD_TOL_FACTOR·ε_j.
    pub tolerance: Vec<f64>,
    /// For a period-k verdict, the first turn from which every point repeats the one k turns
    /// before within the tolerance: the turns the motion took to settle. `None` otherwise.
    pub settled_at_turn: Option<usize>,
}

impl SectionSpec {
    /// The checks of [`poincare`] that need no integration, on `sim`: a single turning driver,
    /// the phase, the turns and the observed columns. Returns the driver speed |ω| (rad/s).
    /// A sweep runs them before any point, so that bad input is refused before any work.
    ///
    /// Errors: as [`poincare`]'s [`Error::Settings`].
    pub fn check(&self, sim: &Simulation) -> Result<f64> {
        let spec = self;
        let omega = driver_speed(&sim.model, "revs")?;
        let tau = std::f64::consts::TAU;
        if !(spec.phase.is_finite() && (0.0..tau).contains(&spec.phase)) {
            return Err(Error::settings(
                "phase",
                format!("expected a phase in [0, 2π) rad, got {}", spec.phase),
            ));
        }
        if spec.turns <= spec.transient {
            return Err(Error::settings(
                "revs",
                format!(
                    "expected more turns than the {} transient turns, got {}",
                    spec.transient, spec.turns
                ),
            ));
        }
        if let Some(c) = spec.observe.iter().find(|c| !sim.names.contains(c)) {
            return Err(Error::settings(
                "observe",
                format!(
                    "no output column \"{c}\"; the columns are {}",
                    sim.names.join(", ")
                ),
            ));
        }
        Ok(omega)
    }
}

/// Section of `sim`'s model once per driver turn (module docs) with its period verdict.
///
/// Errors: [`Error::Settings`] for a model without a single turning driver (`revs`), a phase
/// outside [0, 2π) (`phase`), or turns ≤ transient (`revs`); [`Error::Analysis`] for an unknown
/// column or a failed integration.
pub fn poincare(sim: &Simulation, spec: &SectionSpec) -> Result<ModelSection> {
    let omega = spec.check(sim)?;
    let tau = std::f64::consts::TAU;
    let options = SectionOptions {
        period: tau / omega,
        phase_offset: spec.phase / omega,
        n_transient: spec.transient,
        n_points: spec.turns - spec.transient,
    };
    let solver = sim.solver_options();
    let by_default = spec.observe.is_empty();
    let observe = if by_default {
        default_section_columns(sim)
    } else {
        spec.observe.clone()
    };
    let columns: Vec<&str> = observe.iter().map(String::as_str).collect();
    let (mut section, propagated) = with_formulation!(sim, f => {
        let (t0, y0) = (f.t0(), f.initial_state());
        let tol = propagated_tolerance(&f, t0, &y0, &observe, solver)?;
        let s = analysis::section_outputs(&mut f, t0, &y0, &options, &columns, solver)?;
        (s, Some(tol))
    });
    if by_default {
        let angles: Vec<bool> = observe.iter().map(|c| c.ends_with(".phi")).collect();
        modulo_turns(&mut section.points, &angles);
    }
    let turns = (spec.transient..spec.turns).collect();
    let (period, tolerance, settled_at_turn) =
        verdict(&section.points, spec.transient, sim, propagated.as_deref())?;
    Ok(ModelSection {
        turns,
        section,
        period,
        tolerance,
        settled_at_turn,
    })
}

/// [`poincare`] with transient detection (`settle`) and a warm start (`start`, reduced
/// formulation only; module docs "Transient detection and warm starts"), returning the state
/// at the last point too (reduced formulation). With neither, the section is [`poincare`]'s,
/// bit for bit. Transient detection and warm starts need output columns (`spec.observe`).
///
/// Errors: as [`poincare`]; [`Error::Settings`] for `warm-start` with another formulation and
/// for `observe` when no column is named.
pub fn poincare_from(
    sim: &Simulation,
    spec: &SectionSpec,
    settle: Option<Settle>,
    start: Option<&WarmState>,
) -> Result<PointRun> {
    if spec.observe.is_empty() {
        if settle.is_some() || start.is_some() {
            return Err(Error::settings(
                "observe",
                "transient detection and warm starts need at least one output column",
            ));
        }
        return Ok(PointRun {
            section: poincare(sim, spec)?,
            warm: false,
            end: None,
        });
    }
    let omega = spec.check(sim)?;
    let tau = std::f64::consts::TAU;
    let solver = sim.solver_options();
    let columns: Vec<&str> = spec.observe.iter().map(String::as_str).collect();
    let mut options = SectionOptions {
        period: tau / omega,
        phase_offset: spec.phase / omega,
        n_transient: spec.transient,
        n_points: spec.turns - spec.transient,
    };
    let (settled, propagated, warm, end) = match &sim.formulation {
        Built::Reduced(b) => {
            let mut f = (**b).clone();
            // The verdict's tolerance from the model's initial state, warm or cold, so that
            // both are judged alike.
            let propagated =
                propagated_tolerance(&f, f.t0(), &f.initial_state(), &spec.observe, solver)?;
            // The section's phase in the first turn: where a warm start begins, and the time
            // the end state is read at (the same crank angle as the last point's, and the
            // same time whether the state comes from this run or from a result file).
            let t_phase = f.t0() + spec.phase / omega;
            let warm = match start {
                // Already at the section's phase: the turns count from here.
                Some(w) => {
                    let ok = f.start_from(t_phase, w).is_ok();
                    if ok {
                        options.phase_offset = 0.0;
                    }
                    ok
                }
                None => false,
            };
            let s = settled_section(&mut f, &options, &columns, solver, settle, &propagated)?;
            let end = Some(f.warm_state(t_phase, &s.end.1));
            (s, propagated, warm, end)
        }
        _ if start.is_some() => {
            return Err(Error::settings(
                "warm-start",
                "warm starts need the reduced formulation (--formulation reduced)",
            ));
        }
        // Cold, any formulation (the reduced one is taken above).
        _ => with_formulation!(sim, f => {
            let p = propagated_tolerance(&f, f.t0(), &f.initial_state(), &spec.observe, solver)?;
            let s = settled_section(&mut f, &options, &columns, solver, settle, &p)?;
            (s, p, false, None)
        }),
    };
    let first = settled.transient;
    let n = settled.section.points.len();
    let (period, tolerance, settled_at_turn) =
        verdict(&settled.section.points, first, sim, Some(&propagated))?;
    Ok(PointRun {
        section: ModelSection {
            turns: (first..first + n).collect(),
            section: settled.section,
            period,
            tolerance,
            settled_at_turn,
        },
        warm,
        end,
    })
}

/// The section of `f` from its own start, with transient detection if `settle`.
fn settled_section<F: Formulation + Outputs>(
    f: &mut F,
    options: &SectionOptions,
    columns: &[&str],
    solver: &crate::solve::SolverOptions,
    settle: Option<Settle>,
    propagated: &[f64],
) -> Result<analysis::SettledSection> {
    let (t0, y0) = (f.t0(), f.initial_state());
    let mut check = |points: &[Vec<f64>]| has_settled(points, solver, propagated);
    let settling = settle.map(|s| analysis::Settling {
        min_transient: s.min_transient,
        settled: &mut check,
    });
    Ok(analysis::section_outputs_settling(
        f, t0, &y0, options, columns, solver, settling,
    )?)
}

/// Whether the last [`SETTLE_REPEATS`] of `points` each repeat the one k before within
/// [`SETTLE_TOL_FACTOR`]·ε_j, for some k ≤ [`SETTLE_K_MAX`] (module docs).
fn has_settled(
    points: &[Vec<f64>],
    solver: &crate::solve::SolverOptions,
    propagated: &[f64],
) -> bool {
    let eps = integration_tolerance(points, solver, Some(propagated));
    let n = points.len();
    (1..=SETTLE_K_MAX).any(|k| {
        n >= k + SETTLE_REPEATS
            && (n - SETTLE_REPEATS..n).all(|i| {
                points[i]
                    .iter()
                    .zip(&points[i - k])
                    .zip(&eps)
                    .all(|((a, b), e)| (a - b).abs() <= SETTLE_TOL_FACTOR * e)
            })
    })
}

/// ε_j per component of `points` (module docs): atol + rtol·max_i |p_{i,j}|, or the propagated
/// tolerance where larger.
fn integration_tolerance(
    points: &[Vec<f64>],
    solver: &crate::solve::SolverOptions,
    propagated: Option<&[f64]>,
) -> Vec<f64> {
    let d = points.first().map_or(0, Vec::len);
    (0..d)
        .map(|j| {
            let max = points
                .iter()
                .filter_map(|p| p.get(j))
                .fold(0.0_f64, |m, v| m.max(v.abs()));
            let own = solver.atol + solver.rtol * max;
            propagated
                .and_then(|p| p.get(j))
                .map_or(own, |&e| own.max(e))
        })
        .collect()
}

/// The period verdict of `points` (the first at turn `first_turn`) with the tolerance derived
/// from `sim`'s integration tolerances (module docs): the analysis, the tolerance per component
/// in its units, and the turn the motion settled at.
fn verdict(
    points: &[Vec<f64>],
    first_turn: usize,
    sim: &Simulation,
    propagated: Option<&[f64]>,
) -> Result<(PeriodAnalysis, Vec<f64>, Option<usize>)> {
    let eps = integration_tolerance(points, sim.solver_options(), propagated);
    let scaled: Vec<Vec<f64>> = points
        .iter()
        .map(|p| p.iter().zip(&eps).map(|(v, e)| v / e).collect())
        .collect();
    let opts = PeriodOptions {
        tol_rel: PERIOD_TOL_REL,
        tol_abs: PERIOD_TOL_FACTOR,
        // Judge at most the recorded points: a short run asks for less, not for more points.
        k_max: 8.min(points.len() / 2).max(1),
        m: 16.min(points.len() / 2).max(1),
    };
    let mut period = analysis::period_verdict(&scaled, &opts)?;
    // Back to the components' units for the caller.
    for (t, e) in period.tolerance.iter_mut().zip(&eps) {
        *t *= e;
    }
    let tolerance: Vec<f64> = eps.iter().map(|e| PERIOD_TOL_FACTOR * e).collect();
    let settled = match period.verdict {
        PeriodVerdict::Period { k, .. } => {
            let tol: Vec<f64> = period.tolerance.clone();
            let repeats = |i: usize| {
                i >= k
                    && points[i]
                        .iter()
                        .zip(&points[i - k])
                        .zip(&tol)
                        .all(|((a, b), t)| (a - b).abs() <= *t)
            };
            // The last index from which every later point repeats.
            let mut first = points.len();
            while first > 0 && repeats(first - 1) {
                first -= 1;
            }
            Some(first_turn + first)
        }
        _ => None,
    };
    Ok((period, tolerance, settled))
}

/// The integration tolerance carried into output columns `columns` at (t0, y0):
/// ε_j = Σ_i |∂p_j/∂y_i|·(atol + rtol·|y_i|) over the error-controlled states, by forward
/// differences with h_i = 1e-7·max(|y_i|, 1). An output computed from the states inherits
/// their errors through its sensitivities: the journal eccentricity of a four-bar, e.g., is a
/// small difference of positions ~0.3 m long, so its error is rtol·0.3 m, not rtol·|e|.
fn propagated_tolerance<F: Formulation + Outputs>(
    f: &F,
    t0: f64,
    y0: &[f64],
    columns: &[String],
    solver: &crate::solve::SolverOptions,
) -> Result<Vec<f64>> {
    let names = f.output_names();
    let chosen: Vec<usize> = columns
        .iter()
        .filter_map(|c| names.iter().position(|n| n == c))
        .collect();
    let mut controlled = vec![true; y0.len()];
    f.error_controlled(&mut controlled);
    let eval = |y: &[f64], out: &mut Vec<f64>| {
        f.outputs_into(t0, y, out)
            .map_err(|source| AnalysisError::Outputs {
                analysis: "period tolerance",
                t: t0,
                source,
            })
    };
    let mut base = Vec::new();
    eval(y0, &mut base)?;
    let mut eps = vec![0.0; chosen.len()];
    let mut y = y0.to_vec();
    let mut out = Vec::new();
    for i in (0..y0.len()).filter(|&i| controlled[i]) {
        let h = 1e-7 * y0[i].abs().max(1.0);
        y[i] = y0[i] + h;
        eval(&y, &mut out)?;
        y[i] = y0[i];
        let tol_i = solver.atol + solver.rtol * y0[i].abs();
        for (e, &j) in eps.iter_mut().zip(&chosen) {
            let d = (out.get(j).copied().unwrap_or(0.0) - base.get(j).copied().unwrap_or(0.0)) / h;
            if d.is_finite() {
                *e += d.abs() * tol_i;
            }
        }
    }
    Ok(eps)
}

/// A column's samples after the transient: times, values, rates (where a rate column exists),
/// and the driver speed |ω| (rad/s).
struct Window {
    t: Vec<f64>,
    x: Vec<f64>,
    rate: Option<Vec<f64>>,
    omega: f64,
}

/// A run's samples of one column from turn `transient` on, with the driving frequency.
fn column_after(sim: &Simulation, column: &str, transient: f64) -> Result<Window> {
    let omega = driver_speed(&sim.model, "revs")?;
    let names = sim.column_names();
    let find = |c: &str| names.iter().position(|n| n == c);
    let Some(j) = find(column) else {
        return Err(Error::settings(
            "observe",
            format!(
                "no output column \"{column}\"; the columns are {}",
                names.join(", ")
            ),
        ));
    };
    let rate = rate_column(column).and_then(|r| find(&r));
    let run = sim.run_to_memory()?;
    let t_start = sim.t0() + transient * std::f64::consts::TAU / omega;
    // Samples at t ≥ t_start (to rounding of the output grid).
    let first = run
        .t
        .iter()
        .position(|&t| t >= t_start - 1e-9 * sim.dt())
        .unwrap_or(run.t.len());
    let slice = |k: usize| run.columns.get(k).map(|c| c[first..].to_vec());
    let t = run.t[first..].to_vec();
    let x = slice(j).unwrap_or_default();
    let rate = rate.and_then(slice);
    Ok(Window { t, x, rate, omega })
}

/// The rate column of `column` where the formulations have one: `B.phi` → `B.omega`,
/// `B.x` → `B.vx`, `B.y` → `B.vy`, and bare `x`/`y`/`phi` likewise.
pub fn rate_column(column: &str) -> Option<String> {
    let (body, quantity) = match column.rsplit_once('.') {
        Some((b, q)) => (Some(b), q),
        None => (None, column),
    };
    let rate = match quantity {
        "phi" => "omega",
        "x" => "vx",
        "y" => "vy",
        _ => return None,
    };
    Some(match body {
        Some(b) => format!("{b}.{rate}"),
        None => rate.to_string(),
    })
}

/// Amplitude spectrum of output `column` over a run of `sim` (its end time and output
/// interval) after `transient` driver turns; peaks carry their multiple of the driving
/// frequency f_d = |ω|/2π (Hz).
pub fn spectrum(sim: &Simulation, column: &str, transient: f64) -> Result<(Spectrum, f64)> {
    let Window { t, x, omega, .. } = column_after(sim, column, transient)?;
    let f_drive = omega / std::f64::consts::TAU;
    let opts = SpectrumOptions {
        driving_frequency: Some(f_drive),
        ..SpectrumOptions::default()
    };
    Ok((analysis::amplitude_spectrum(&t, &x, &opts)?, f_drive))
}

/// Phase-portrait data of output `column` over a run of `sim` after `transient` driver turns:
/// the times and the portrait (rate from [`rate_column`] if the run has it, else differences).
pub fn phase(sim: &Simulation, column: &str, transient: f64) -> Result<(Vec<f64>, PhasePortrait)> {
    let Window { t, x, rate, .. } = column_after(sim, column, transient)?;
    let p = analysis::phase_portrait(&t, &x, rate.as_deref())?;
    Ok((t, p))
}

/// How long and how finely to estimate the Lyapunov exponent, in driver turns.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LyapunovSpec {
    /// Turns integrated in all.
    pub turns: f64,
    /// Turns integrated before the estimate starts.
    pub transient: f64,
    /// Initial and renormalised separation d0 in the scaled norm (dimensionless).
    pub d0: f64,
    /// Turns between renormalisations (τ = this × T).
    pub renormalise_every: f64,
}

/// Scale of each state in the Lyapunov norm, so that the norm is dimensionless and weighs
/// components by the motion they stand for:
///
/// * angles (rad): 1 — a unit of angle;
/// * positions (m): L, the longest arm of any body (distance of a body point from the body's
///   reference point), so that a position change L weighs as much as the 1 rad rotation of
///   that arm that would produce it;
/// * velocities: |ω|·(scale of the position or angle), so that a velocity error weighs as the
///   displacement it causes in 1/|ω| s (one radian of the driver);
/// * bookkeeping states (masked, never measured): 1.
///
/// States are laid out as the formulations do: DAE q = (x, y, φ) per body then q̇, then
/// bookkeeping; reduced (θ3, θ4, θ̇3, θ̇4, δ̇⁽⁻⁾); generalized (z, ż, bookkeeping).
pub fn lyapunov_scales(sim: &Simulation, omega: f64, n: usize) -> Vec<f64> {
    let length = sim
        .model
        .bodies
        .iter()
        .flat_map(|b| b.points.iter())
        .map(|(_, p)| p[0].hypot(p[1]))
        .fold(0.0_f64, f64::max);
    let length = if length > 0.0 { length } else { 1.0 };
    let mut scales = vec![1.0; n];
    // Generalized: z (f coordinates, mixed lengths and angles: scale 1) then ż (scale ω), then
    // bookkeeping.
    let (coordinates, rates) = match &sim.formulation {
        Built::Dae(f) => (Some(f.n_coordinates()), 2..4),
        Built::Generalized(f) => (None, f.dof()..2 * f.dof()),
        Built::Reduced(_) => (None, 2..4),
    };
    match coordinates {
        Some(nq) => {
            for (i, s) in scales.iter_mut().enumerate().take(2 * nq) {
                let position = if (i % nq) % 3 == 2 { 1.0 } else { length };
                *s = if i < nq { position } else { omega * position };
            }
        }
        None => {
            for s in scales.iter_mut().skip(rates.start).take(rates.len()) {
                *s = omega;
            }
        }
    }
    scales
}

/// Largest Lyapunov exponent of `sim`'s model (1/s): bookkeeping states from
/// [`Formulation::error_controlled`] are neither perturbed nor measured, the norm uses
/// [`lyapunov_scales`].
pub fn lyapunov(sim: &Simulation, spec: &LyapunovSpec) -> Result<LyapunovEstimate> {
    let omega = driver_speed(&sim.model, "revs")?;
    let period = std::f64::consts::TAU / omega;
    if !(spec.renormalise_every.is_finite() && spec.renormalise_every > 0.0) {
        return Err(Error::settings(
            "renormalise_every_revs",
            format!("expected turns > 0, got {}", spec.renormalise_every),
        ));
    }
    if !(spec.transient.is_finite() && spec.transient >= 0.0) {
        return Err(Error::settings(
            "transient",
            format!("expected turns ≥ 0, got {}", spec.transient),
        ));
    }
    let intervals = ((spec.turns - spec.transient) / spec.renormalise_every + 1e-9).floor();
    if !(intervals.is_finite() && intervals >= 2.0) {
        return Err(Error::settings(
            "revs",
            format!(
                "expected at least 2 renormalisation intervals after the transient, got {} turns, {} transient, every {} turns",
                spec.turns, spec.transient, spec.renormalise_every
            ),
        ));
    }
    with_formulation!(sim, f => {
        let n = f.n_states();
        let mut controlled = vec![true; n];
        f.error_controlled(&mut controlled);
        let options = LyapunovOptions {
            d0: spec.d0,
            tau: spec.renormalise_every * period,
            n_intervals: intervals as usize,
            t_transient: spec.transient * period,
            bookkeeping: controlled.iter().map(|c| !c).collect(),
            scales: lyapunov_scales(sim, omega, n),
            ..LyapunovOptions::default()
        };
        let y0 = f.initial_state();
        let t0 = f.t0();
        // `f` is not changed by the estimate; the binding is mutable for the macro's sake.
        let f = &mut f;
        Ok(analysis::largest_lyapunov(&*f, t0, &y0, &options, sim.solver_options())?)
    })
}

/// A bifurcation sweep: model field `parameter` (a `--set` path) over `grid`, each point a
/// [`poincare`] section of one column.
#[derive(Debug, Clone)]
pub struct Sweep<'a> {
    /// The model file.
    pub model_path: &'a Path,
    /// The model's text where it did not come from a file (a model built in Python): each
    /// point then loads this text, naming `model_path` in messages, instead of reading the file.
    pub model_text: Option<&'a str>,
    /// The `--set` overrides of every point (before the parameter's).
    pub overrides: &'a [String],
    /// The swept field, a `--set` path (`joints.B.clearance`).
    pub parameter: &'a str,
    /// The parameter values.
    pub grid: ParameterGrid,
    /// Formulation and solver settings of every point (the end time is the section's).
    pub options: SimulationOptions,
    /// The section of each point: turns, transient, phase and the one observed column.
    pub section: SectionSpec,
}

/// One sweep point's result: its section (one column) and verdict.
pub type SweepResult = Result<ModelSection>;

impl Sweep<'_> {
    /// The `--set` override of point value `value`.
    pub fn override_for(&self, value: f64) -> String {
        format!("{}={value}", self.parameter)
    }

    /// The simulation of one parameter value (model loaded with the extra override).
    pub fn simulation(&self, value: f64) -> Result<Simulation> {
        let mut overrides = self.overrides.to_vec();
        overrides.push(self.override_for(value));
        let model = match self.model_text {
            Some(text) => {
                crate::model::load_str(text, &self.model_path.display().to_string(), &overrides)?
            }
            None => crate::model::load(self.model_path, &overrides)?,
        };
        let options = SimulationOptions {
            end: EndTime::DriverTurns(self.section.turns as f64),
            ..self.options.clone()
        };
        Simulation::new(&model, options)
    }

    /// One point: load, build, section.
    pub fn point(&self, value: f64) -> SweepResult {
        poincare(&self.simulation(value)?, &self.section)
    }

    /// The [`WarmState`] of the model of parameter `value` in state `y` at the section's phase
    /// (the state a point's run ended in, as a result file keeps it), to start the next point
    /// from.
    ///
    /// Errors: the model cannot be loaded or built, or is not of the reduced formulation.
    pub fn warm_state(&self, value: f64, y: &[f64]) -> Result<WarmState> {
        let sim = self.simulation(value)?;
        let omega = driver_speed(&sim.model, "revs")?;
        match &sim.formulation {
            Built::Reduced(f) => Ok(f.warm_state(f.t0() + self.section.phase / omega, y)),
            _ => Err(Error::settings(
                "warm-start",
                "warm starts need the reduced formulation (--formulation reduced)",
            )),
        }
    }

    /// One point with transient detection and a warm start ([`poincare_from`]).
    pub fn point_from(
        &self,
        value: f64,
        settle: Option<Settle>,
        start: Option<&WarmState>,
    ) -> Result<PointRun> {
        poincare_from(&self.simulation(value)?, &self.section, settle, start)
    }
}

/// Runs the points `indices` of `sweep` in parallel (rayon's current pool, see
/// [`analysis::run_points`]), handing each finished point to `on_done` as it completes; returns
/// the points in grid order. A point whose model, simulation or integration fails is handed
/// over with its error (the caller decides whether that ends the sweep).
pub fn bifurcation<E, D>(
    sweep: &Sweep<'_>,
    indices: &[usize],
    on_done: D,
) -> std::result::Result<Vec<SweepPoint<SweepResult>>, E>
where
    E: Send + From<AnalysisError>,
    D: FnMut(&SweepPoint<SweepResult>) -> std::result::Result<(), E> + Send,
{
    analysis::run_points(&sweep.grid, indices, |_, p| sweep.point(p), on_done)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rate_columns_follow_the_output_names() {
        assert_eq!(rate_column("B.phi").as_deref(), Some("B.omega"));
        assert_eq!(rate_column("coupler.x").as_deref(), Some("coupler.vx"));
        assert_eq!(rate_column("y").as_deref(), Some("vy"));
        assert_eq!(rate_column("B.Fn"), None);
    }

    #[test]
    fn turns_not_beyond_the_transient_are_refused_naming_revs() {
        let model = crate::model::load("models/farahan2016.toml".as_ref(), &[]);
        let Ok(model) = model else {
            panic!("{model:?}");
        };
        let sim = Simulation::new(&model, SimulationOptions::default());
        let Ok(sim) = sim else {
            panic!("{sim:?}");
        };
        let e = poincare(
            &sim,
            &SectionSpec {
                turns: 3,
                transient: 3,
                phase: 0.0,
                observe: vec![],
            },
        )
        .err()
        .map(|e| e.to_string());
        assert_eq!(
            e.as_deref(),
            Some("revs: expected more turns than the 3 transient turns, got 3")
        );
    }
}
