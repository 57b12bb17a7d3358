//! Running a model: the one entry point for the command line, analyses, parameter sweeps and
//! the Python bindings.
//!
//! A [`Simulation`] is built from a [`Model`] and [`SimulationOptions`] (formulation, energy
//! bookkeeping, end time in seconds or driver turns, output interval, solver options).
//! [`Simulation::new`] checks every setting against the model and builds (assembles) the
//! formulation before any integration, so a bad setting costs nothing and comes back as
//! [`Error::Settings`] naming the option. Then:
//!
//! * [`Simulation::run`] streams every sample (state and output columns) and event to a
//!   [`SampleSink`] — e.g. the CSV writer of [`crate::output`] — and returns the
//!   [`RunSummary`], which is computed sample by sample: a run holds O(1) memory in its length
//!   beyond what the sink keeps;
//! * [`Simulation::run_to_memory`] returns a [`Trajectory`]: column names, one `Vec<f64>` per
//!   column, events, and the summary with provenance and solver statistics.
//!
//! The same model and options give the same numbers, bit for bit.
//!
//! ```
//! use linkdyn::simulation::{Simulation, SimulationOptions};
//!
//! let model = linkdyn::model::load("models/fourbar_ideal.toml".as_ref(), &[])?;
//! let sim = Simulation::new(&model, SimulationOptions::default().revs(0.5).dt(1e-3))?;
//! let run = sim.run_to_memory()?;
//! assert_eq!(run.len(), 121); // t = 0, 1 ms, …, 120 ms (a quarter second per turn at 250 rpm)
//! assert!(run.summary.max_constraint_violation < 1e-6);
//! # Ok::<(), linkdyn::Error>(())
//! ```

pub mod analyses;
pub mod impacts;
mod options;
mod provenance;
mod sink;
mod summary;
mod trajectory;

pub use impacts::{ContactPoint, ContactProbe, Impact, PermanentContact};
pub use options::{
    EndTime, FormulationKind, MAX_OUTPUT_VALUES, SimulationOptions, check_sampling, end_time,
};
pub use provenance::{Provenance, escape_line};
pub use sink::{Discard, Sample, SampleSink};
pub use summary::{ClearanceSummary, EnergyBalance, FIRST_IMPACTS, RunSummary, SummaryBuilder};
pub use trajectory::{Columns, Trajectory};

use crate::contact::kinks;
use crate::error::{Error, Result};
use crate::formulation::{Dae, DaeOptions, Formulation, Generalized, Outputs, ReducedLagrangian};
use crate::model::{JointKind, Model};
use crate::solve::{self, SolverOptions};
use sink::Observed;
use std::time::Instant;

/// The formulation a simulation integrates, built (assembled) once.
#[derive(Debug, Clone)]
enum Built {
    Dae(Box<Dae>),
    Reduced(Box<ReducedLagrangian>),
    Generalized(Box<Generalized>),
}

/// Loosest rtol at which the explicit pairs cut their steps at events and have the friction
/// kinks as events. Below it the cuts bring their error to 0.4–21× rtol on farahan2016
/// (from up to 900×; docs/numerics.md, "Error proportional to tolerance"). Above it the run is
/// chaotic anyway (wrong impact counts with or without the cuts), and a different trajectory
/// put a DOP853 sample 1.03 mm deep into the bearing at rtol 1e-3
/// (`tests/loose_tolerance_dense_output.rs`).
pub const EXPLICIT_CUT_MAX_RTOL: f64 = 1e-5;

/// Whether the friction kinks are event functions for `solver` (the method's
/// [`MethodInfo::friction_kink_events`](solve::MethodInfo::friction_kink_events)), and switches
/// the explicit pairs' cut at events off where it does not help: they cut their steps at events
/// (`ExplicitRkSettings::cut_at_events`) only at rtol ≤ [`EXPLICIT_CUT_MAX_RTOL`]; without the
/// cut the kinks would not change their steps, only add located events. Nor do they cut with a
/// friction law that jumps in value at its kinks ([`kinks::continuous`]): where the journal
/// sticks, a sliding mode at a jump crosses the kinks, and the contact boundary, at every step,
/// and the cut steps collapse (measured: no progress at t = 0.0229 s on farahan2016 with the
/// printed law, cutting at the kinks or at the impacts only).
fn kink_events(solver: &mut solve::SolverOptions, model: &Model) -> bool {
    match solver.method.info().friction_kink_events {
        solve::KinkEvents::Always => true,
        solve::KinkEvents::WhereStepsAreCut => {
            let continuous = model.joints.iter().all(|j| match &j.kind {
                JointKind::Clearance(spec) => kinks::continuous(&spec.friction),
                JointKind::PrismaticClearance(spec) => kinks::continuous(&spec.friction),
                _ => true,
            });
            if solver.rtol > EXPLICIT_CUT_MAX_RTOL || !continuous {
                solver.explicit_rk.cut_at_events = false;
            }
            solver.explicit_rk.cut_at_events
        }
        solve::KinkEvents::Never => false,
    }
}

/// A model with validated settings, ready to run any number of times. `Send` but not `Sync`
/// (the DAE keeps scratch space in a `RefCell`): give each thread its own clone.
#[derive(Debug, Clone)]
pub struct Simulation {
    model: Model,
    options: SimulationOptions,
    t_end: f64,
    formulation: Built,
    names: Vec<String>,
    clearance_joints: Vec<String>,
}

impl Simulation {
    /// Checks `options` against `model` and builds the formulation, in this order: end time
    /// (driver turns need exactly one driver with a non-zero speed), output interval, solver
    /// options, formulation choice (energy bookkeeping only with the DAE; the reduced
    /// formulation only for the four-bar with one clearance joint), assembly, and the output
    /// size (at most [`MAX_OUTPUT_VALUES`]).
    ///
    /// Errors: [`Error::Settings`] naming the option, [`Error::Formulation`] for a model the
    /// formulation cannot take or assemble.
    pub fn new(model: &Model, options: SimulationOptions) -> Result<Self> {
        let t_end = end_time(model, options.end)?;
        if !(options.dt.is_finite() && options.dt > 0.0) {
            // Checked again with the output size below; first, so that it is reported first.
            check_sampling(t_end, options.dt, 0)?;
        }
        let mut solver = options::check_solver(&options.solver)?;
        let kinks = kink_events(&mut solver, model);
        let formulation = match options.formulation {
            FormulationKind::Dae => {
                let dae_options = DaeOptions {
                    energy: options.energy,
                    ..DaeOptions::default()
                };
                let dae = Dae::new(model, &dae_options)?.friction_kink_events(kinks);
                Built::Dae(Box::new(dae))
            }
            FormulationKind::Reduced if options.energy => {
                return Err(Error::settings(
                    "energy",
                    "the energy bookkeeping is available for the DAE formulation only",
                ));
            }
            FormulationKind::Reduced => {
                let reduced = ReducedLagrangian::new(model)?.friction_kink_events(kinks);
                Built::Reduced(Box::new(reduced))
            }
            FormulationKind::Generalized => {
                let dae_options = DaeOptions {
                    energy: options.energy,
                    ..DaeOptions::default()
                };
                Built::Generalized(Box::new(
                    Generalized::new(model, &dae_options)?.friction_kink_events(kinks),
                ))
            }
        };
        let names = match &formulation {
            Built::Dae(f) => f.output_names(),
            Built::Reduced(f) => f.output_names(),
            Built::Generalized(f) => f.output_names(),
        };
        check_sampling(t_end, options.dt, names.len())?;
        Ok(Simulation {
            model: model.clone(),
            options: SimulationOptions { solver, ..options },
            t_end,
            formulation,
            names,
            clearance_joints: clearance_joint_names(model),
        })
    }

    /// The model.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The options (validated).
    pub fn options(&self) -> &SimulationOptions {
        &self.options
    }

    /// The solver options (validated).
    pub fn solver_options(&self) -> &SolverOptions {
        &self.options.solver
    }

    /// End time (s).
    pub fn t_end(&self) -> f64 {
        self.t_end
    }

    /// Output interval (s).
    pub fn dt(&self) -> f64 {
        self.options.dt
    }

    /// Start time (s).
    pub fn t0(&self) -> f64 {
        match &self.formulation {
            Built::Dae(f) => f.t0(),
            Built::Reduced(f) => f.t0(),
            Built::Generalized(f) => f.t0(),
        }
    }

    /// Output column names (without `t`), in the order of every [`Sample::outputs`].
    pub fn column_names(&self) -> &[String] {
        &self.names
    }

    /// Names of the clearance joints in model order (event k is joint k's δ = 0).
    pub fn clearance_joints(&self) -> &[String] {
        &self.clearance_joints
    }

    /// Number of samples a run sends: ⌊(t_end − t0)/dt + 1e-9⌋ + 1 (the output grid of
    /// [`integrate`](fn@crate::solve::integrate)).
    pub fn expected_samples(&self) -> usize {
        // Saturating cast; the output size was checked in `new`.
        (((self.t_end - self.t0()) / self.options.dt + 1e-9).floor() + 1.0) as usize
    }

    /// Turns of the model's single driver at time t (s); `None` if the model does not have
    /// exactly one driver.
    pub fn driver_turns(&self, t: f64) -> Option<f64> {
        match self.model.drivers.as_slice() {
            [d] => Some(t * d.speed.abs() / (2.0 * std::f64::consts::PI)),
            _ => None,
        }
    }

    /// What made the results of this simulation: version, model source with overrides, and
    /// every setting (`formulation`, `method`, `rtol`, `atol`, `t_end`, `dt`, and for the DAE
    /// the Baumgarte factors).
    pub fn provenance(&self) -> Provenance {
        let fmt = crate::numbers::format_number;
        let solver = &self.options.solver;
        let mut settings = vec![
            ("formulation", self.options.formulation.to_string()),
            ("method", solver.method.to_string()),
            ("rtol", fmt(solver.rtol)),
            ("atol", fmt(solver.atol)),
            ("t_end", fmt(self.t_end)),
            ("dt", fmt(self.options.dt)),
        ];
        if self.options.formulation == FormulationKind::Dae {
            let b = self.model.settings.baumgarte;
            settings.push(("baumgarte_alpha", fmt(b.alpha)));
            settings.push(("baumgarte_beta", fmt(b.beta)));
        }
        provenance::provenance(&self.model.source, settings)
    }

    /// Integrates from the initial state to t_end, sending every sample and event to `sink`;
    /// returns the summary.
    ///
    /// Errors: [`Error::Solve`] with the time and reason (a sink's own failure comes back as
    /// the sink's [`SolveError::Sink`](crate::solve::SolveError::Sink)).
    pub fn run<S: SampleSink + ?Sized>(&self, sink: &mut S) -> Result<RunSummary> {
        let started = Instant::now();
        let mut summary = SummaryBuilder::new(&self.names, &self.clearance_joints);
        if let [d] = self.model.drivers.as_slice() {
            summary = summary.driver(d.initial_angle, d.speed);
        }
        let mut observed = Observed::new(
            summary,
            sink,
            self.names.len(),
            self.options.solver.controlled_tolerances(),
        );
        let (stats, step_violation, singular_passages) = match &self.formulation {
            Built::Dae(f) => self.integrate(&mut (**f).clone(), &mut observed)?,
            Built::Reduced(f) => self.integrate(&mut (**f).clone(), &mut observed)?,
            Built::Generalized(f) => self.integrate(&mut (**f).clone(), &mut observed)?,
        };
        let sink_time = observed.consumer_time;
        let mut summary = observed.summary.finish(
            self.provenance(),
            self.options.solver.clone(),
            stats,
            started.elapsed().saturating_sub(sink_time).as_secs_f64(),
            sink_time.as_secs_f64(),
        );
        // The samples' |Φ| and every accepted step end's: the maximum over the whole run.
        summary.max_constraint_violation = summary.max_constraint_violation.max(step_violation);
        summary.singular_passages = singular_passages;
        Ok(summary)
    }

    /// The reduced formulation this simulation integrates (as built, at its initial state), or
    /// `None` for the DAE and the generalised formulation: for analyses written for it alone
    /// ([`crate::studies::orbit()`]).
    pub fn reduced_formulation(&self) -> Option<&ReducedLagrangian> {
        match &self.formulation {
            Built::Reduced(f) => Some(f),
            _ => None,
        }
    }

    /// The DAE this simulation integrates (as built, at its initial state), or `None` for the
    /// other formulations: for studies that change it between runs ([`crate::studies::wear()`]).
    pub fn dae(&self) -> Option<&Dae> {
        match &self.formulation {
            Built::Dae(f) => Some(f),
            _ => None,
        }
    }

    /// Runs and keeps every sample in memory.
    pub fn run_to_memory(&self) -> Result<Trajectory> {
        let mut columns = Columns::with_capacity(self.names.len(), self.expected_samples());
        let summary = self.run(&mut columns)?;
        Ok(Trajectory {
            names: self.names.clone(),
            t: columns.t,
            columns: columns.columns,
            constraint_violation: columns.constraint_violation,
            events: columns.events,
            summary,
        })
    }

    fn integrate<F: Formulation + Outputs + impacts::ContactProbe, S: SampleSink + ?Sized>(
        &self,
        f: &mut F,
        observed: &mut Observed<'_, S>,
    ) -> Result<(solve::SolverStats, f64, Vec<f64>)> {
        let y0 = f.initial_state();
        let t0 = f.t0();
        let stats = solve::integrate(
            f,
            t0,
            &y0,
            self.t_end,
            self.options.dt,
            &self.options.solver,
            observed,
        )?;
        Ok((stats, f.step_constraint_violation(), f.singular_passages()))
    }
}

/// Names of the model's contact sites in the order of their events: the revolute clearance
/// joints in model order, then the corners of the prismatic-clearance joints (`J.c1` … `J.c4`,
/// and `J.e1` … `J.e4` against the guide's end stops where it has them,
/// `formulation::contacts`).
pub fn clearance_joint_names(model: &Model) -> Vec<String> {
    let revolute = model
        .joints
        .iter()
        .filter(|j| matches!(j.kind, JointKind::Clearance(_)))
        .map(|j| j.name.clone());
    let corners = model
        .joints
        .iter()
        .filter_map(|j| match &j.kind {
            JointKind::PrismaticClearance(spec) => Some((j, spec)),
            _ => None,
        })
        .flat_map(|(j, spec)| {
            crate::formulation::corner_contacts::site_names(spec)
                .map(move |c| format!("{}.{c}", j.name))
        });
    revolute.chain(corners).collect()
}

#[cfg(test)]
mod tests;
