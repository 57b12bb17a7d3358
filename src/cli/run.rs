//! `linkdyn run MODEL …`: integrate and write `F.csv` plus the summary `F.json`.

use super::{Failure, fail, fail_model};
use crate::formulation::{Dae, DaeOptions, Formulation};
use crate::model::Model;
use crate::output::{self, Provenance, Recorder, format_number};
use crate::solve::{self, Method, SolverOptions, SolverStats};
use clap::Args;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Model file (TOML).
    model: PathBuf,
    /// End time (s).
    #[arg(long, conflicts_with = "revs")]
    t_end: Option<f64>,
    /// Number of turns of the (single) driver; default 2 when the model has one driver.
    #[arg(long)]
    revs: Option<f64>,
    /// Output sample interval (s); samples come from the dense output, not from solver steps.
    #[arg(long, default_value_t = 1e-4)]
    dt: f64,
    /// Relative tolerance.
    #[arg(long, default_value_t = 1e-8)]
    rtol: f64,
    /// Absolute tolerance.
    #[arg(long, default_value_t = 1e-10)]
    atol: f64,
    /// Integration method: dop853 (8th order) or dopri5 (5th order).
    #[arg(long, default_value = "dop853")]
    method: String,
    /// Override a model field: dotted path, array entries by name (repeatable), e.g.
    /// `--set drivers.motor.speed_rpm=3500`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Output CSV file; the summary goes beside it with the extension `.json`.
    #[arg(long)]
    out: PathBuf,
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
    /// Largest constraint violation |Φ| over the samples (m or rad).
    pub max_constraint_violation: f64,
    /// Degrees of freedom of the dynamic model.
    pub degrees_of_freedom: usize,
    /// Constraint rows left out as redundant.
    pub redundant_constraints: Vec<String>,
    /// Per clearance joint: impacts, first impact times, max penetration and peak normal force
    /// (the last two over the output samples).
    pub clearance_joints: Vec<output::ClearanceSummary>,
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

/// The summary file beside a CSV: `F.csv` → `F.json`.
pub fn summary_path(csv: &Path) -> PathBuf {
    csv.with_extension("json")
}

/// Runs `run`.
pub fn run(args: &RunArgs) -> Result<(), Failure> {
    let model = crate::model::load(&args.model, &args.set).map_err(fail)?;
    let t_end = end_time(&model, args.t_end, args.revs)?;
    if !(args.dt.is_finite() && args.dt > 0.0) {
        return Err(Failure::bad_input(format!(
            "--dt: expected a positive time step, got {}",
            args.dt
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
        .build()
        .map_err(|e| Failure::bad_input(e.to_string()))?;

    let mut dae =
        Dae::new(&model, &DaeOptions::default()).map_err(|e| fail_model(&args.model, e))?;
    let started = Instant::now();
    let y0 = dae.initial_state();
    let mut recorder = Recorder::new(&dae);
    let stats = solve::integrate(&mut dae, 0.0, &y0, t_end, args.dt, &options, &mut recorder)
        .map_err(fail)?;
    let wall_time_s = started.elapsed().as_secs_f64();

    let baumgarte = dae.baumgarte();
    let provenance = Provenance {
        linkdyn_version: crate::version(),
        model: model.source.clone(),
        settings: [
            ("formulation", "dae".to_string()),
            ("method", method.to_string()),
            ("rtol", format_number(args.rtol)),
            ("atol", format_number(args.atol)),
            ("t_end", format_number(t_end)),
            ("dt", format_number(args.dt)),
            ("baumgarte_alpha", format_number(baumgarte.alpha)),
            ("baumgarte_beta", format_number(baumgarte.beta)),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_string(), v))
        .collect(),
    };
    let summary = RunSummary {
        provenance: &provenance,
        solver_options: &options,
        solver_stats: &stats,
        wall_time_s,
        samples: recorder.len(),
        max_constraint_violation: recorder.max_constraint_violation,
        degrees_of_freedom: dae.n_coordinates()
            - (dae.constraints().n_rows() - dae.redundant_rows().len()),
        redundant_constraints: dae
            .redundant_rows()
            .iter()
            .map(|&k| dae.constraints().row_name(&model, k))
            .collect(),
        clearance_joints: output::ClearanceSummary::from_recorder(
            &recorder,
            &dae.contacts()
                .sites()
                .iter()
                .map(|s| model.joint(s.joint).name.clone())
                .collect::<Vec<_>>(),
        ),
    };
    let csv = output::write_csv(&args.out, &provenance, &recorder).map_err(fail)?;
    let json = output::write_json(&summary_path(&args.out), &summary).map_err(fail)?;
    output::commit_all(vec![csv, json]).map_err(fail)?;
    eprintln!(
        "{}: {} samples to {} in {:.3} s ({} steps, {} rejected, {} RHS evaluations, max |Phi| = {:.2e})",
        model.name,
        recorder.len(),
        args.out.display(),
        wall_time_s,
        stats.steps,
        stats.rejected,
        stats.rhs_evals,
        recorder.max_constraint_violation
    );
    Ok(())
}
