//! A periodic orbit of a model continued in one model field (`linkdyn continue`): the field is
//! named by its `--set` path, and each parameter value loads the model with the extra override
//! `PATH=value`, as a point of `linkdyn bifurcation` does; the branch is computed by
//! [`crate::analysis::orbit::continue_orbit`] (docs/periodic_orbits.md, "Continuation").
//!
//! Supported as for [`mod@super::orbit`]: the reduced formulation and the DAE (whose corrector
//! steps in the consistent directions and makes every iterate consistent,
//! [`crate::analysis::orbit::coordinates`]).

use std::marker::PhantomData;
use std::path::Path;
use std::time::Instant;

use serde::Serialize;

use super::orbit::StudiedFormulation;
use crate::analysis::AnalysisError;
use crate::analysis::orbit::{
    Branch, BranchEnd, BranchPoint, ContinuationOptions, OrbitAt, OrbitFamily, SpecialKind,
    continue_orbit_watched, switch_branch_watched,
};
use crate::error::{Error, Result};
use crate::formulation::{Dae, ReducedLagrangian};
use crate::simulation::{
    EndTime, FormulationKind, Provenance, Simulation, SimulationOptions, analyses,
};
use crate::solve::{SolverOptions, SolverStats, Stepper, Stop};

/// What `linkdyn continue` asks for.
#[derive(Debug, Clone, PartialEq)]
pub struct ContinuationRequest<'a> {
    /// The model file (named in messages and the provenance).
    pub model_path: &'a Path,
    /// The model's text (the file's, read once).
    pub model_text: &'a str,
    /// The `--set` overrides of every point, before the parameter's.
    pub overrides: &'a [String],
    /// The continued field, a `--set` path (`joints.B.clearance`).
    pub parameter: &'a str,
    /// First parameter value (the field's unit in the model file).
    pub from: f64,
    /// Last parameter value.
    pub to: f64,
    /// Largest step (parameter units); default |to − from|/20.
    pub step: Option<f64>,
    /// Period in driver turns (K ≥ 1).
    pub period_turns: usize,
    /// Periods integrated from the initial state at `from` before the first shooting (its
    /// guess); the section is at the end of them.
    pub guess_from_turn: usize,
    /// Period doublings followed: 0 continues one branch; N also continues the period-2K
    /// branch from each located period doubling, and theirs, N doublings deep
    /// ([`crate::analysis::orbit::switch_branch`]).
    pub follow_doublings: usize,
    /// Formulation and solver (the end time is ignored).
    pub options: SimulationOptions,
}

/// One point of the branch, as `F.csv` has it.
#[derive(Debug, Clone, Serialize)]
pub struct ContinuationRow {
    /// Parameter value.
    pub parameter: f64,
    /// The output columns at the section (in the order of [`ContinuationResult::names`]).
    pub state: Vec<f64>,
    /// Period (s).
    pub period_s: f64,
    /// Largest |μ|.
    pub max_abs_mu: f64,
    /// Nontrivial Floquet multipliers [re, im], by decreasing modulus.
    pub floquet_multipliers: Vec<[f64; 2]>,
    /// Every nontrivial |μ| < 1.
    pub stable: bool,
    /// Impacts (contact onsets) over one period, all clearance joints.
    pub impacts_per_period: usize,
    /// Smallest gap c − |e| over one period (m; at the step ends and at the gap's minima
    /// located inside the steps); negative: the deepest
    /// penetration.
    pub min_gap_m: Option<f64>,
    /// Closing error max_i |P(x)_i − x_i|/ε_i (units of the integration tolerance).
    pub residual: f64,
    /// A located special point: its kind.
    pub special: Option<SpecialKind>,
    /// The branch ([`ContinuationResult::branches`]: 0 the one from `from`).
    pub branch: usize,
    /// The driver turn of the section within the period: 0 at the section; a period of K
    /// turns has a row for each turn 0..K with the state there (the point's other values
    /// repeated), as a bifurcation diagram shows it.
    pub turn: usize,
}

/// One branch of a continuation.
#[derive(Debug, Clone, Serialize)]
pub struct BranchSummary {
    /// Its index (the rows' `branch`).
    pub branch: usize,
    /// Period of its orbits in driver turns.
    pub period_turns: usize,
    /// The branch it switched from at a period doubling, and that point's parameter; `None`
    /// for the branch from `from`.
    pub switched_from: Option<(usize, f64)>,
    /// Points on it (turn 0 rows).
    pub points: usize,
    /// The located special points.
    pub special_points: usize,
    /// Special points detected between two points but not located: kind, the parameter after
    /// the change, why.
    pub unlocated: Vec<(SpecialKind, f64, String)>,
    /// Why it ended.
    pub end: BranchEnd,
}

/// The result of [`continuation`]: the keys of `F.json` (docs/periodic_orbits.md).
#[derive(Debug, Clone, Serialize)]
pub struct ContinuationResult {
    /// The continued field.
    pub parameter: String,
    /// Output column names at the section (the CSV's columns after the parameter).
    pub names: Vec<String>,
    /// The branches, each in order of arclength, each point with a row per driver turn of its
    /// period ([`ContinuationRow::turn`]).
    #[serde(skip)]
    pub rows: Vec<ContinuationRow>,
    /// Points on the branch from `from`.
    pub points: usize,
    /// The located special points (also rows of the CSV).
    pub special_points: Vec<ContinuationRow>,
    /// Special points detected between two points but not located: kind, the parameter after
    /// the change, why (the branch from `from`).
    pub unlocated: Vec<(SpecialKind, f64, String)>,
    /// Why the branch from `from` ended.
    pub end: BranchEnd,
    /// Period in driver turns (the branch from `from`).
    pub period_turns: usize,
    /// Every branch: the one from `from`, then those switched to at period doublings
    /// (`follow_doublings`), in the order they were computed.
    pub branches: Vec<BranchSummary>,
    /// Period doublings where no period-2K branch was found: the branch, the parameter, why.
    pub switch_failures: Vec<(usize, f64, String)>,
    /// Wall time (s).
    pub wall_time_s: f64,
    /// Cost of every integration, summed.
    pub solver_stats: SolverStats,
    /// What made the result.
    pub provenance: Provenance,
}

/// The model in its field `parameter`, with the formulation `F`.
struct ModelFamily<'a, F> {
    request: &'a ContinuationRequest<'a>,
    contacts: usize,
    formulation: PhantomData<F>,
}

impl<F: StudiedFormulation> ModelFamily<'_, F> {
    fn simulation(&self, p: f64) -> Result<Simulation> {
        let r = self.request;
        let mut overrides = r.overrides.to_vec();
        overrides.push(format!("{}={p}", r.parameter));
        let model = crate::model::load_str(
            r.model_text,
            &r.model_path.display().to_string(),
            &overrides,
        )?;
        Simulation::new(
            &model,
            SimulationOptions {
                end: EndTime::DriverTurns(1.0),
                ..r.options.clone()
            },
        )
    }

    /// The output columns of the orbit at `pt` (`period_turns` driver turns) at each driver
    /// turn of its period: one integration, interpolated at the turns (none for one turn).
    fn sections(
        &self,
        pt: &BranchPoint,
        period_turns: usize,
        solver: &SolverOptions,
        stats: &mut SolverStats,
    ) -> Result<Vec<Vec<f64>>> {
        let at = self.orbit_at(pt.parameter)?;
        let mut f = at.f;
        let mut states = vec![(pt.t0, pt.y0.clone())];
        if period_turns > 1 {
            let solve = |source| {
                Error::Analysis(AnalysisError::Solve {
                    analysis: "continuation (sections)",
                    source,
                })
            };
            let turn = pt.period / period_turns as f64;
            let t_end = pt.t0 + pt.period;
            let mut y = pt.y0.clone();
            let mut stepper = Stepper::new(&mut f, pt.t0, &pt.y0, t_end, solver).map_err(solve)?;
            let mut next = 1;
            loop {
                let stop = stepper.step().map_err(solve)?;
                while next < period_turns && pt.t0 + next as f64 * turn <= stepper.t() {
                    let t = pt.t0 + next as f64 * turn;
                    stepper.interpolate(t, &mut y).map_err(solve)?;
                    states.push((t, y.clone()));
                    next += 1;
                }
                if stop == Stop::EndReached {
                    break;
                }
            }
            stats.add_run(stepper.stats());
        }
        states
            .iter()
            .map(|(t, y)| {
                let mut state = Vec::new();
                f.outputs_into(*t, y, &mut state)?;
                Ok(state)
            })
            .collect()
    }

    /// The formulation at `p`, its section and period.
    fn orbit_at(&self, p: f64) -> Result<OrbitAt<F>> {
        let sim = self.simulation(p)?;
        let omega = analyses::driver_speed(sim.model(), "period_turns")?;
        let f = F::built(&sim)?;
        let period = self.request.period_turns as f64 * std::f64::consts::TAU / omega;
        Ok(OrbitAt {
            t0: f.t0() + self.request.guess_from_turn as f64 * period,
            f: f.clone(),
            period,
        })
    }
}

impl<F: StudiedFormulation> OrbitFamily for ModelFamily<'_, F> {
    type F = F;

    fn at(&self, p: f64) -> std::result::Result<OrbitAt<F>, AnalysisError> {
        self.orbit_at(p).map_err(|e| {
            AnalysisError::invalid(
                "parameter",
                format!("{} = {p}: {e}", self.request.parameter),
            )
        })
    }

    fn contact_events(&self) -> usize {
        self.contacts
    }
}

/// Continues the periodic orbit of the model asked for by `request` (module documentation).
///
/// Errors: [`Error::Settings`] for the generalised formulation or a bad period;
/// the model's own error at `from` or `to`; [`Error::Analysis`] when there is no orbit at
/// `from` (the message has the residual history) or the options are invalid.
pub fn continuation(request: &ContinuationRequest<'_>) -> Result<ContinuationResult> {
    continuation_watched(request, &mut |_, _| true)
}

/// [`continuation`], with `watch` called on every point as it joins a branch (the branch's
/// index, the point): progress. When it returns false that branch ends there
/// ([`BranchEnd::Stopped`]) and no further branch is started; the result holds what was
/// computed.
///
/// Errors: as [`continuation`].
pub fn continuation_watched(
    request: &ContinuationRequest<'_>,
    watch: &mut dyn FnMut(usize, &BranchPoint) -> bool,
) -> Result<ContinuationResult> {
    let started = Instant::now();
    super::orbit::require_orbit_formulation(request.options.formulation)?;
    if request.period_turns == 0 {
        return Err(Error::settings(
            "period_turns",
            "expected a whole number of driver turns ≥ 1, got 0",
        ));
    }
    match request.options.formulation {
        FormulationKind::Reduced => continuation_with::<ReducedLagrangian>(request, watch, started),
        _ => continuation_with::<Dae>(request, watch, started),
    }
}

/// [`continuation_watched`] with the formulation `F`.
fn continuation_with<F: StudiedFormulation>(
    request: &ContinuationRequest<'_>,
    watch: &mut dyn FnMut(usize, &BranchPoint) -> bool,
    started: Instant,
) -> Result<ContinuationResult> {
    let mut family = ModelFamily::<F> {
        request,
        contacts: 0,
        formulation: PhantomData,
    };
    // Both ends load and build: a bad value is bad input, not a failed point.
    let sim = family
        .simulation(request.from)
        .map_err(super::orbit::or_the_dae)?;
    family.simulation(request.to)?;
    family.contacts = F::built(&sim)?.contact_events();
    let start = family.orbit_at(request.from)?;
    let solver = sim.solver_options().clone();
    let mut f = start.f.clone();
    let t_begin = f.t0();
    let y_begin = f.initial_state();
    let mut stats = SolverStats::default();
    let guess = {
        let solve = |source| {
            Error::Analysis(AnalysisError::Solve {
                analysis: "continuation (guess)",
                source,
            })
        };
        let mut y = y_begin.clone();
        if start.t0 > t_begin {
            let mut stepper =
                Stepper::new(&mut f, t_begin, &y_begin, start.t0, &solver).map_err(solve)?;
            while stepper.step().map_err(solve)? != Stop::EndReached {}
            stepper.interpolate(start.t0, &mut y).map_err(solve)?;
            stats.add_run(stepper.stats());
        }
        y
    };
    let step = request
        .step
        .unwrap_or_else(|| (request.to - request.from).abs() / 20.0);
    let options = ContinuationOptions::new(request.from, request.to, step);
    let main = continue_orbit_watched(&family, &guess, &options, &solver, &mut |p| watch(0, p))?;
    let (main_end, main_unlocated) = (main.end.clone(), main.unlocated.clone());
    let (branches, switch_failures) =
        follow_doublings(&family, main, request, &options, &solver, watch);

    let names = start.f.output_names();
    let mut rows = Vec::new();
    let mut summaries = Vec::with_capacity(branches.len());
    for (index, followed) in branches.iter().enumerate() {
        let period_turns = followed.multiple * request.period_turns;
        stats.add_run(&followed.branch.stats);
        for pt in &followed.branch.points {
            let sections = family.sections(pt, period_turns, &solver, &mut stats)?;
            for (turn, state) in sections.into_iter().enumerate() {
                rows.push(ContinuationRow {
                    parameter: pt.parameter,
                    state,
                    period_s: pt.period,
                    max_abs_mu: pt.spectral_radius,
                    floquet_multipliers: pt.multipliers.clone(),
                    stable: pt.stable,
                    impacts_per_period: pt.impacts_per_period,
                    min_gap_m: pt.min_gap,
                    residual: pt.residual,
                    special: pt.special,
                    branch: index,
                    turn,
                });
            }
        }
        summaries.push(BranchSummary {
            branch: index,
            period_turns,
            switched_from: followed.switched_from,
            points: followed.branch.points.len(),
            special_points: followed
                .branch
                .points
                .iter()
                .filter(|p| p.special.is_some())
                .count(),
            unlocated: followed.branch.unlocated.clone(),
            end: followed.branch.end.clone(),
        });
    }
    let fmt = crate::numbers::format_number;
    let mut provenance = sim.provenance();
    provenance.settings.remove("t_end");
    // The first point's simulation has the parameter's override too; the settings say it.
    provenance.model.overrides = request.overrides.to_vec();
    for (key, value) in [
        ("parameter", request.parameter.to_string()),
        ("from", fmt(request.from)),
        ("to", fmt(request.to)),
        ("step", fmt(step)),
        ("period_turns", request.period_turns.to_string()),
        ("guess_from_turn", request.guess_from_turn.to_string()),
        ("follow_doublings", request.follow_doublings.to_string()),
    ] {
        provenance.settings.insert(key.into(), value);
    }
    Ok(ContinuationResult {
        parameter: request.parameter.to_string(),
        names,
        points: summaries.first().map_or(0, |b| b.points),
        special_points: rows
            .iter()
            .filter(|r| r.special.is_some() && r.turn == 0)
            .cloned()
            .collect(),
        rows,
        unlocated: main_unlocated,
        end: main_end,
        period_turns: request.period_turns,
        branches: summaries,
        switch_failures,
        wall_time_s: started.elapsed().as_secs_f64(),
        solver_stats: stats,
        provenance,
    })
}

/// A computed branch: its period as a multiple of the request's, and where it came from.
struct Followed {
    multiple: usize,
    switched_from: Option<(usize, f64)>,
    depth: usize,
    branch: Branch,
}

/// The branch from `from`, then the period-2K branch of each of its located period doublings
/// (and theirs, `request.follow_doublings` deep). A period doubling where a branch switched to
/// from it rejoined (the other end of a bubble) starts none: that branch is already there.
/// Returns the branches and the period doublings where no branch was found, with why.
fn follow_doublings<F: StudiedFormulation>(
    family: &ModelFamily<'_, F>,
    main: Branch,
    request: &ContinuationRequest<'_>,
    options: &ContinuationOptions,
    solver: &SolverOptions,
    watch: &mut dyn FnMut(usize, &BranchPoint) -> bool,
) -> (Vec<Followed>, Vec<(usize, f64, String)>) {
    let mut branches = vec![Followed {
        multiple: 1,
        switched_from: None,
        depth: 0,
        branch: main,
    }];
    let mut failures = Vec::new();
    let mut i = 0;
    let stopped = |b: &[Followed]| b.iter().any(|f| f.branch.end == BranchEnd::Stopped);
    while i < branches.len() && !stopped(&branches) {
        if branches[i].depth < request.follow_doublings {
            let points = &branches[i].branch.points;
            // A switched branch's own ends (where it left and rejoined its parent) are its
            // parent's period doublings, not its own.
            let own = match branches[i].switched_from {
                Some(_) => {
                    1..points.len().saturating_sub(usize::from(matches!(
                        branches[i].branch.end,
                        BranchEnd::Rejoined { .. }
                    )))
                }
                None => 0..points.len(),
            };
            let doublings: Vec<BranchPoint> = points[own]
                .iter()
                .filter(|p| p.special == Some(SpecialKind::PeriodDoubling))
                .cloned()
                .collect();
            let mut rejoined: Vec<f64> = Vec::new();
            for pd in &doublings {
                // The nearest period doubling to where an earlier switched branch rejoined
                // this one, within a step, is that branch's other end.
                if rejoined.iter().any(|r| {
                    let nearest = doublings
                        .iter()
                        .map(|d| d.parameter)
                        .min_by(|a, b| (a - r).abs().total_cmp(&(b - r).abs()));
                    nearest == Some(pd.parameter) && (pd.parameter - r).abs() <= options.max_step
                }) {
                    continue;
                }
                if stopped(&branches) {
                    break;
                }
                let multiple = branches[i].multiple;
                let index = branches.len();
                let switched =
                    switch_branch_watched(family, multiple, pd, options, solver, &mut |p| {
                        watch(index, p)
                    });
                match switched {
                    Ok(branch) => {
                        if let BranchEnd::Rejoined { parameter } = branch.end {
                            rejoined.push(parameter);
                        }
                        let depth = branches[i].depth + 1;
                        branches.push(Followed {
                            multiple: 2 * multiple,
                            switched_from: Some((i, pd.parameter)),
                            depth,
                            branch,
                        });
                    }
                    Err(e) => failures.push((i, pd.parameter, e.to_string())),
                }
            }
        }
        i += 1;
    }
    (branches, failures)
}
