//! `linkdyn run MODEL …`: integrate and write `F.csv` plus the summary `F.json`.

use super::{Failure, fail, fail_model};
use crate::formulation::{Dae, DaeOptions, Formulation, Outputs, ReducedLagrangian};
use crate::model::{JointKind, Model};
use crate::output::{self, ClearanceSummary, Provenance, format_number};
use crate::solve::{self, Method, Recorder, SolverOptions, SolverStats};
use clap::{Args, ValueEnum};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Which equations of motion to integrate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FormulationKind {
    /// Absolute coordinates, ideal joints as Baumgarte-stabilised constraints (any model).
    Dae,
    /// The reduced Lagrangian model of the four-bar with one clearance joint (Farahan et al. 2016).
    Reduced,
}

impl std::fmt::Display for FormulationKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            FormulationKind::Dae => "dae",
            FormulationKind::Reduced => "reduced",
        })
    }
}

/// Time span, sampling and solver settings shared by `run` and `compare`.
#[derive(Debug, Args)]
pub struct SolveArgs {
    /// End time (s).
    #[arg(long, conflicts_with = "revs")]
    pub t_end: Option<f64>,
    /// Number of turns of the (single) driver; default 2 when the model has one driver.
    #[arg(long)]
    pub revs: Option<f64>,
    /// Output sample interval (s); samples come from the dense output, not from solver steps.
    #[arg(long, default_value_t = 1e-4)]
    pub dt: f64,
    /// Relative tolerance.
    #[arg(long, default_value_t = 1e-8)]
    pub rtol: f64,
    /// Absolute tolerance.
    #[arg(long, default_value_t = 1e-10)]
    pub atol: f64,
    /// Integration method: dop853 (8th order) or dopri5 (5th order).
    #[arg(long, default_value = "dop853")]
    pub method: String,
    /// Most step attempts before the solver gives up (with the time it reached).
    #[arg(long, default_value_t = 10_000_000)]
    pub max_steps: u64,
    /// Override a model field: dotted path, array entries by name (repeatable), e.g.
    /// `--set drivers.motor.speed_rpm=3500`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

/// Arguments of `run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Model file (TOML).
    model: PathBuf,
    #[command(flatten)]
    solve: SolveArgs,
    /// Equations of motion.
    #[arg(long, value_enum, default_value_t = FormulationKind::Dae)]
    formulation: FormulationKind,
    /// Integrate the energy bookkeeping (DAE only): adds the `energy.*` columns and the energy
    /// balance to the summary.
    #[arg(long)]
    energy: bool,
    /// Output CSV file; the summary goes beside it with the extension `.json`.
    #[arg(long)]
    out: PathBuf,
}

/// Most output samples one run may keep (each is a row of the CSV).
const MAX_SAMPLES: f64 = 1e8;

/// Settings resolved from [`SolveArgs`] and the model.
#[derive(Debug, Clone)]
pub struct RunSettings {
    /// End time (s).
    pub t_end: f64,
    /// Output interval (s).
    pub dt: f64,
    /// Solver options.
    pub options: SolverOptions,
}

impl RunSettings {
    /// Checks the arguments against the model.
    pub fn resolve(args: &SolveArgs, model: &Model) -> Result<Self, Failure> {
        let t_end = end_time(model, args.t_end, args.revs)?;
        if !(args.dt.is_finite() && args.dt > 0.0) {
            return Err(Failure::bad_input(format!(
                "--dt: expected a positive time step, got {}",
                args.dt
            )));
        }
        // Every sample is kept in memory until the files are written: refuse runs that could
        // not fit rather than exhaust the machine.
        let samples = t_end / args.dt;
        if samples > MAX_SAMPLES {
            return Err(Failure::bad_input(format!(
                "--dt {:e} s over {:e} s asks for {samples:.3e} samples; at most {MAX_SAMPLES:e} are allowed: raise --dt",
                args.dt, t_end
            )));
        }
        let method: Method = args
            .method
            .parse()
            .map_err(|e: solve::SolveError| Failure::bad_input(e.to_string()))?;
        let options = SolverOptions::default()
            .method(method)
            .rtol(args.rtol)
            .atol(args.atol)
            .max_steps(args.max_steps)
            .build()
            .map_err(|e| Failure::bad_input(e.to_string()))?;
        Ok(RunSettings {
            t_end,
            dt: args.dt,
            options,
        })
    }

    /// Every setting as (name, value) for the provenance.
    pub fn provenance(&self, model: &Model, formulation: FormulationKind) -> Provenance {
        let b = model.settings.baumgarte;
        let mut settings = vec![
            ("formulation", formulation.to_string()),
            ("method", self.options.method.to_string()),
            ("rtol", format_number(self.options.rtol)),
            ("atol", format_number(self.options.atol)),
            ("t_end", format_number(self.t_end)),
            ("dt", format_number(self.dt)),
        ];
        if formulation == FormulationKind::Dae {
            settings.push(("baumgarte_alpha", format_number(b.alpha)));
            settings.push(("baumgarte_beta", format_number(b.beta)));
        }
        Provenance {
            linkdyn_version: crate::version(),
            model: model.source.clone(),
            settings: settings
                .into_iter()
                .map(|(k, v)| (k.to_string(), v))
                .collect(),
        }
    }
}

/// A finished run.
#[derive(Debug)]
pub struct Finished {
    /// Sampled outputs and events.
    pub recorder: Recorder,
    /// Solver statistics.
    pub stats: SolverStats,
    /// Wall time of the integration, output evaluation included (s).
    pub wall_time_s: f64,
}

/// Integrates `f` from its initial state with the run settings.
pub fn integrate_recorded<F: Formulation + Outputs>(
    f: &mut F,
    settings: &RunSettings,
) -> Result<Finished, Failure> {
    let started = Instant::now();
    let y0 = f.initial_state();
    let mut recorder = Recorder::new(f);
    let stats = solve::integrate(
        f,
        f.t0(),
        &y0,
        settings.t_end,
        settings.dt,
        &settings.options,
        &mut recorder,
    )
    .map_err(fail)?;
    Ok(Finished {
        recorder,
        stats,
        wall_time_s: started.elapsed().as_secs_f64(),
    })
}

/// Builds the chosen formulation of `model` and runs it; `energy` asks the DAE for its energy
/// bookkeeping.
pub fn run_formulation(
    model: &Model,
    path: &Path,
    kind: FormulationKind,
    settings: &RunSettings,
    energy: bool,
) -> Result<Finished, Failure> {
    match kind {
        FormulationKind::Dae => {
            let options = DaeOptions {
                energy,
                ..DaeOptions::default()
            };
            let mut dae = Dae::new(model, &options).map_err(|e| fail_model(path, e))?;
            integrate_recorded(&mut dae, settings)
        }
        FormulationKind::Reduced if energy => Err(Failure::bad_input(
            "--energy: the energy bookkeeping is available for the DAE formulation only",
        )),
        FormulationKind::Reduced => {
            let mut reduced = ReducedLagrangian::new(model).map_err(|e| fail_model(path, e))?;
            integrate_recorded(&mut reduced, settings)
        }
    }
}

/// The JSON summary of a run.
#[derive(Debug, Serialize)]
pub struct RunSummary<'a> {
    /// What made it.
    pub provenance: &'a Provenance,
    /// Solver options.
    pub solver_options: &'a SolverOptions,
    /// Solver statistics.
    pub solver_stats: &'a SolverStats,
    /// Wall time of the integration, output evaluation included (s).
    pub wall_time_s: f64,
    /// Number of output samples.
    pub samples: usize,
    /// Largest constraint violation |Φ| over the samples (m or rad; 0 for the reduced formulation).
    pub max_constraint_violation: f64,
    /// Per clearance joint: impacts, first impact times, max penetration and peak normal force
    /// (the last two over the output samples).
    pub clearance_joints: Vec<ClearanceSummary>,
    /// With `--energy`: the work–energy balance over the run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy_balance: Option<EnergyBalance>,
}

/// The work–energy balance of a run with `--energy` (J).
#[derive(Debug, Serialize)]
pub struct EnergyBalance {
    /// Driver work at the end.
    pub driver_work: f64,
    /// Work of applied torques and forces at the end.
    pub external_work: f64,
    /// Energy dissipated by contacts and dampers at the end.
    pub dissipated: f64,
    /// max |driver + external work − ΔE − dissipated| over the samples.
    pub max_abs_residual: f64,
    /// That residual relative to the largest |driver work| (or |ΔE| when there is no driver).
    pub relative_residual: f64,
}

impl EnergyBalance {
    /// From the `energy.*` columns, if present.
    pub fn from_recorder(rec: &Recorder) -> Option<Self> {
        let last = |c: &str| rec.column(c).and_then(|v| v.last().copied());
        let balance = rec.column("energy.balance")?;
        let max_abs = |v: &[f64]| v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let max_abs_residual = max_abs(&balance);
        let kinetic = rec.column("energy.kinetic")?;
        let scale = max_abs(&rec.column("energy.driver_work")?)
            .max(max_abs(&rec.column("energy.external_work")?))
            .max(max_abs(&kinetic));
        Some(EnergyBalance {
            driver_work: last("energy.driver_work")?,
            external_work: last("energy.external_work")?,
            dissipated: last("energy.dissipated")?,
            max_abs_residual,
            relative_residual: if scale > 0.0 {
                max_abs_residual / scale
            } else {
                max_abs_residual
            },
        })
    }
}

/// End time from `--t-end` or `--revs` (turns of the single driver).
pub fn end_time(model: &Model, t_end: Option<f64>, revs: Option<f64>) -> Result<f64, Failure> {
    let t = match (t_end, revs) {
        (Some(t), _) => t,
        (None, revs) => {
            let [driver] = model.drivers.as_slice() else {
                return Err(Failure::bad_input(format!(
                    "--revs counts turns of the single driver, but model \"{}\" has {} drivers: give --t-end",
                    model.name,
                    model.drivers.len()
                )));
            };
            if driver.speed == 0.0 {
                return Err(Failure::bad_input(format!(
                    "driver \"{}\" has zero speed: give --t-end instead of --revs",
                    driver.name
                )));
            }
            revs.unwrap_or(2.0) * 2.0 * std::f64::consts::PI / driver.speed.abs()
        }
    };
    if !(t.is_finite() && t > 0.0) {
        return Err(Failure::bad_input(format!(
            "expected a positive, finite end time, got {t} s"
        )));
    }
    Ok(t)
}

/// Names of the model's clearance joints, in model order (the order of their events).
pub fn clearance_joint_names(model: &Model) -> Vec<String> {
    model
        .joints
        .iter()
        .filter(|j| matches!(j.kind, JointKind::Clearance(_)))
        .map(|j| j.name.clone())
        .collect()
}

/// The summary file beside a CSV: `F.csv` → `F.json`.
pub fn summary_path(csv: &Path) -> PathBuf {
    csv.with_extension("json")
}

/// Runs `run`.
pub fn run(args: &RunArgs) -> Result<(), Failure> {
    let model = crate::model::load(&args.model, &args.solve.set).map_err(fail)?;
    let settings = RunSettings::resolve(&args.solve, &model)?;
    let done = run_formulation(
        &model,
        &args.model,
        args.formulation,
        &settings,
        args.energy,
    )?;
    let provenance = settings.provenance(&model, args.formulation);
    let rec = &done.recorder;
    let summary = RunSummary {
        provenance: &provenance,
        solver_options: &settings.options,
        solver_stats: &done.stats,
        wall_time_s: done.wall_time_s,
        samples: rec.len(),
        max_constraint_violation: rec.max_constraint_violation,
        clearance_joints: ClearanceSummary::from_recorder(rec, &clearance_joint_names(&model)),
        energy_balance: EnergyBalance::from_recorder(rec),
    };
    let csv = output::write_csv(&args.out, &provenance, rec).map_err(fail)?;
    let json = output::write_json(&summary_path(&args.out), &summary).map_err(fail)?;
    output::commit_all(vec![csv, json]).map_err(fail)?;
    let impacts: usize = summary.clearance_joints.iter().map(|c| c.impacts).sum();
    eprintln!(
        "{} ({}): {} samples to {} in {:.3} s ({} steps, {} rejected, {} RHS evaluations, {} impacts, max |Phi| = {:.2e})",
        model.name,
        args.formulation,
        rec.len(),
        args.out.display(),
        done.wall_time_s,
        done.stats.steps,
        done.stats.rejected,
        done.stats.rhs_evals,
        impacts,
        rec.max_constraint_violation
    );
    Ok(())
}
