//! A periodic orbit of a model (`linkdyn orbit`): the guess from a few driver turns of
//! integration, the shooting ([`crate::analysis::orbit`]), its state as named output columns,
//! its stability, and one period of it sampled for the CSV.
//!
//! Supported: the reduced formulation (the four-bar with one clearance joint) and the DAE (any
//! linkage). The DAE's state has 2m constraint directions (Φ = 0, Φ̇ = 0, the driven crank's
//! angle among them) that the motion does not have: the shooting steps in the consistent
//! directions only and makes every iterate consistent ([`crate::analysis::orbit::coordinates`]),
//! so those directions are neither unknowns nor multipliers. The generalised formulation
//! corrects its state at step ends, which the variational equations do not follow; it is
//! refused with that reason (docs/periodic_orbits.md, "What is not done").

use std::collections::BTreeMap;
use std::time::Instant;

use serde::Serialize;

use crate::analysis::orbit::{OrbitOptions, periodic_orbit};
use crate::error::{Error, Result};
use crate::formulation::{
    Crossing, Dae, Formulation, FormulationError, Outputs, ReducedLagrangian,
};
use crate::model::Model;
use crate::simulation::{
    EndTime, FormulationKind, Provenance, Simulation, SimulationOptions, analyses,
};
use crate::solve::{self, EventRecord, Sink, SolveError, SolverStats, Stepper, Stop};

/// The period asked for.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum OrbitPeriod {
    /// K turns of the model's single driver.
    Turns(usize),
    /// S seconds.
    Seconds(f64),
}

/// What `linkdyn orbit` asks for.
#[derive(Debug, Clone, PartialEq)]
pub struct OrbitRequest {
    /// Formulation and solver (the end time is the orbit's own and is ignored).
    pub options: SimulationOptions,
    /// The period.
    pub period: OrbitPeriod,
    /// Periods integrated from the initial state before the shooting starts (its guess); the
    /// section is at the end of them.
    pub guess_from_turn: usize,
    /// Output interval of the orbit's samples (s).
    pub dt: f64,
}

/// The result of [`orbit`]: the keys of `F.json` (docs/periodic_orbits.md, "Output").
#[derive(Debug, Clone, Serialize)]
pub struct OrbitResult {
    /// True: an orbit that failed to converge is an error, never a result.
    pub converged: bool,
    /// max_i |P(x)_i − x_i|/ε_i over the unknowns of each Newton iterate (ε_i = atol +
    /// rtol·|x_i|), the last one the orbit's.
    pub residual_history: Vec<f64>,
    /// Newton iterations done.
    pub newton_iterations: usize,
    /// The output columns at the section, by name.
    pub state: BTreeMap<String, f64>,
    /// Time of the section (s): the start of the period.
    pub t_section_s: f64,
    /// Period (s).
    pub period_s: f64,
    /// Period in driver turns, for a model with one driver.
    pub period_turns: Option<f64>,
    /// Nontrivial Floquet multipliers [re, im], by decreasing modulus.
    pub floquet_multipliers: Vec<[f64; 2]>,
    /// Multipliers removed as trivial (inactive bookkeeping states: exactly 0 or 1).
    pub trivial_multipliers: usize,
    /// Every nontrivial |μ| < 1.
    pub stable: bool,
    /// Largest |μ|.
    pub spectral_radius: f64,
    /// Impacts (contact onsets) over one period, all clearance joints.
    pub impacts_per_period: usize,
    /// Smallest gap c − |e| over one period and every clearance joint (m), at the step ends and
    /// samples of the orbit's integration; negative: the deepest penetration. `None` without
    /// clearance joints.
    pub min_gap_m: Option<f64>,
    /// max_i |P(x)_i − x_i|/ε_i of the orbit returned, from one period integrated from it.
    pub closing_error: f64,
    /// Wall time of the guess, the shooting and the orbit's samples (s).
    pub wall_time_s: f64,
    /// Cost of every integration (guess, shooting, samples), summed.
    pub solver_stats: SolverStats,
    /// What made the result.
    pub provenance: Provenance,
    /// Output column names of the samples (the CSV's header after `t`).
    #[serde(skip)]
    pub names: Vec<String>,
    /// One period of the orbit: (t, output columns) on the output grid.
    #[serde(skip)]
    pub samples: Vec<(f64, Vec<f64>)>,
}

/// Finds the periodic orbit of `model` asked for by `request` (module documentation).
///
/// Errors: [`Error::Settings`] for the generalised formulation, a bad period
/// (`period_turns` or `period`), or a bad output interval (`dt`);
/// [`Error::Analysis`] when Newton's method finds no orbit (the message has the residual
/// history) or an integration fails.
pub fn orbit(model: &Model, request: &OrbitRequest) -> Result<OrbitResult> {
    let started = Instant::now();
    let (period, period_turns) = match request.period {
        OrbitPeriod::Turns(k) => {
            let omega = analyses::driver_speed(model, "period_turns")?;
            if k == 0 {
                return Err(Error::settings(
                    "period_turns",
                    "expected a whole number of driver turns ≥ 1, got 0",
                ));
            }
            (k as f64 * std::f64::consts::TAU / omega, Some(k as f64))
        }
        OrbitPeriod::Seconds(s) if s.is_finite() && s > 0.0 => (
            s,
            analyses::driver_speed(model, "period")
                .ok()
                .map(|w| s * w / std::f64::consts::TAU),
        ),
        OrbitPeriod::Seconds(s) => {
            return Err(Error::settings(
                "period",
                format!("expected a finite period > 0 s, got {s}"),
            ));
        }
    };
    require_orbit_formulation(request.options.formulation)?;
    let guess_end = request.guess_from_turn as f64 * period;
    let sim = Simulation::new(
        model,
        SimulationOptions {
            end: EndTime::Seconds(guess_end.max(period)),
            dt: request.dt,
            ..request.options.clone()
        },
    )
    .map_err(or_the_dae)?;
    let setting = Setting {
        period,
        period_turns,
        guess_end,
        started,
    };
    match request.options.formulation {
        FormulationKind::Reduced => orbit_of::<ReducedLagrangian>(&sim, request, &setting),
        _ => orbit_of::<Dae>(&sim, request, &setting),
    }
}

/// A formulation whose periodic orbits the studies compute, as a simulation builds it.
pub(crate) trait StudiedFormulation: Formulation + Outputs + Clone {
    /// The formulation `sim` built, if it is this one.
    fn built(sim: &Simulation) -> Result<&Self>;
    /// How many of its first event functions are contact penetrations δ (m).
    fn contact_events(&self) -> usize;
}

impl StudiedFormulation for ReducedLagrangian {
    fn built(sim: &Simulation) -> Result<&Self> {
        sim.reduced_formulation().ok_or_else(|| {
            Error::settings(
                "formulation",
                "the simulation did not build the reduced formulation",
            )
        })
    }

    /// Event 0, the clearance joint's penetration.
    fn contact_events(&self) -> usize {
        1
    }
}

impl StudiedFormulation for Dae {
    fn built(sim: &Simulation) -> Result<&Self> {
        sim.dae()
            .ok_or_else(|| Error::settings("formulation", "the simulation did not build the DAE"))
    }

    /// The penetrations of the revolute clearance joints, then those of the slider corners of
    /// the prismatic ones.
    fn contact_events(&self) -> usize {
        self.contacts().len()
    }
}

/// The period and the clock of one [`orbit`] request.
struct Setting {
    period: f64,
    period_turns: Option<f64>,
    guess_end: f64,
    started: Instant,
}

/// [`orbit`] with the formulation `F` as built by `sim`.
fn orbit_of<F: StudiedFormulation>(
    sim: &Simulation,
    request: &OrbitRequest,
    setting: &Setting,
) -> Result<OrbitResult> {
    let mut f = F::built(sim)?.clone();
    let contacts = f.contact_events();
    let Setting {
        period,
        period_turns,
        guess_end,
        started,
    } = *setting;
    let solver = sim.solver_options().clone();
    let t0 = f.t0();
    let y_start = f.initial_state();
    let t_section = t0 + guess_end;
    let solve = |source| {
        Error::Analysis(crate::analysis::AnalysisError::Solve {
            analysis: "periodic orbit (guess)",
            source,
        })
    };
    let (guess, guess_stats) =
        integrate_to(&mut f, t0, &y_start, t_section, &solver).map_err(solve)?;
    // Event k < the number of clearance joints is joint k's penetration δ: its gap is located.
    let options = OrbitOptions {
        watched_gaps: contacts,
        ..OrbitOptions::new(period)
    };
    let found = periodic_orbit(&f, t_section, &guess, &options, &solver)?;

    // One period from the orbit, for its samples and impacts.
    let names = f.output_names();
    let mut record = Record {
        names: names.len(),
        row: Vec::new(),
        samples: Vec::new(),
        impacts: 0,
        n_joints: options.watched_gaps,
    };
    let mut copy = f.clone();
    let stats = solve::integrate(
        &mut copy,
        t_section,
        &found.y0,
        t_section + period,
        request.dt,
        &solver,
        &mut record,
    )
    .map_err(solve)?;
    let mut state = BTreeMap::new();
    let mut row = Vec::new();
    f.outputs_into(t_section, &found.y0, &mut row)?;
    for (name, value) in names.iter().zip(&row) {
        state.insert(name.clone(), *value);
    }
    let mut total = guess_stats;
    for s in [&found.stats, &stats] {
        total.add_run(s);
    }
    let stable = found.stable();
    let spectral_radius = found
        .multipliers
        .iter()
        .map(|z| z[0].hypot(z[1]))
        .fold(0.0, f64::max);
    let fmt = crate::numbers::format_number;
    let mut provenance = sim.provenance();
    provenance.settings.remove("t_end");
    provenance.settings.insert("period_s".into(), fmt(period));
    provenance.settings.insert(
        "guess_from_turn".into(),
        request.guess_from_turn.to_string(),
    );
    Ok(OrbitResult {
        converged: true,
        residual_history: found.residual_history,
        newton_iterations: found.iterations,
        state,
        t_section_s: t_section,
        period_s: period,
        period_turns,
        floquet_multipliers: found.multipliers,
        trivial_multipliers: found.trivial_multipliers,
        stable,
        spectral_radius,
        impacts_per_period: record.impacts,
        min_gap_m: found.min_gap,
        closing_error: found.closing_error,
        wall_time_s: started.elapsed().as_secs_f64(),
        solver_stats: total,
        provenance,
        names,
        samples: record.samples,
    })
}

/// A model that the reduced formulation (the default of `linkdyn orbit` and `linkdyn
/// continue`) does not take: its error says that the DAE takes any linkage.
pub(crate) fn or_the_dae(e: Error) -> Error {
    match e {
        Error::Formulation(FormulationError::Unsupported {
            formulation,
            reason,
        }) if formulation == FormulationKind::Reduced.name() => {
            Error::Formulation(FormulationError::Unsupported {
                formulation,
                reason: format!("{reason}; the dae formulation takes any linkage"),
            })
        }
        e => e,
    }
}

/// Refuses the generalised formulation, saying why (module documentation).
pub(crate) fn require_orbit_formulation(formulation: FormulationKind) -> Result<()> {
    if formulation != FormulationKind::Generalized {
        return Ok(());
    }
    Err(Error::settings(
        "formulation",
        "periodic orbits are computed with the reduced formulation or the DAE: the generalized formulation recovers its dependent coordinates by Newton's method at every stage and corrects them at step ends, which the variational equations do not follow; use `formulation` dae (any linkage) or reduced (the four-bar with one clearance joint)",
    ))
}

/// Integrates `f` from (t0, y0) to t1; returns y(t1) and the cost.
fn integrate_to<F: Formulation>(
    f: &mut F,
    t0: f64,
    y0: &[f64],
    t1: f64,
    solver: &solve::SolverOptions,
) -> std::result::Result<(Vec<f64>, SolverStats), SolveError> {
    let mut y = y0.to_vec();
    if t1 <= t0 {
        return Ok((y, SolverStats::default()));
    }
    let mut stepper = Stepper::new(f, t0, y0, t1, solver)?;
    while stepper.step()? != Stop::EndReached {}
    stepper.interpolate(t1, &mut y)?;
    Ok((y, stepper.stats().clone()))
}

/// The orbit's samples and its impacts (event k < `n_joints` is joint k's penetration δ).
struct Record {
    names: usize,
    row: Vec<f64>,
    samples: Vec<(f64, Vec<f64>)>,
    impacts: usize,
    n_joints: usize,
}

impl<F: Formulation + Outputs> Sink<F> for Record {
    fn sample(&mut self, f: &F, t: f64, y: &[f64]) -> std::result::Result<(), SolveError> {
        f.outputs_into(t, y, &mut self.row)
            .map_err(|e| SolveError::Sink {
                t,
                reason: format!("the outputs could not be evaluated: {e}"),
            })?;
        debug_assert_eq!(self.row.len(), self.names, "one value per output column");
        self.samples.push((t, self.row.clone()));
        Ok(())
    }

    fn event(
        &mut self,
        _f: &F,
        event: &EventRecord,
        _y_before: &[f64],
        _y_after: &[f64],
    ) -> std::result::Result<(), SolveError> {
        if event.index < self.n_joints && event.crossing == Crossing::Rising {
            self.impacts += 1;
        }
        Ok(())
    }
}
