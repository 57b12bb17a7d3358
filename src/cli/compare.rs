//! `linkdyn compare MODEL …`: run the DAE and the reduced formulation with the same settings
//! and report their largest differences.

use super::run::{FormulationKind, RunSettings, SolveArgs, clearance_joint_names, run_formulation};
use super::{Failure, fail};
use crate::analysis::{Comparison, compare};
use crate::output::{self, Provenance};
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;

/// Arguments of `compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// Model file (TOML) that both formulations accept (the four-bar with one clearance joint).
    model: PathBuf,
    #[command(flatten)]
    solve: SolveArgs,
    /// Write the comparison as JSON here.
    #[arg(long)]
    out: Option<PathBuf>,
}

#[derive(Debug, Serialize)]
struct CompareReport<'a> {
    provenance: &'a Provenance,
    wall_time_dae_s: f64,
    wall_time_reduced_s: f64,
    rhs_evals_dae: u64,
    rhs_evals_reduced: u64,
    comparison: &'a Comparison,
}

/// Runs `compare`.
pub fn run(args: &CompareArgs) -> Result<(), Failure> {
    let model = crate::model::load(&args.model, &args.solve.set).map_err(fail)?;
    let settings = RunSettings::resolve(&args.solve, &model)?;
    let dae = run_formulation(&model, &args.model, FormulationKind::Dae, &settings, false)?;
    let reduced = run_formulation(
        &model,
        &args.model,
        FormulationKind::Reduced,
        &settings,
        false,
    )?;
    let joints = clearance_joint_names(&model);
    let comparison = compare(&dae.recorder, &reduced.recorder, joints.len());

    println!(
        "{}: DAE vs reduced, {} samples to t = {} s, rtol {:e}",
        model.name, comparison.samples, settings.t_end, settings.options.rtol
    );
    println!(
        "  {:<22} {:>14} {:>14} {:>12}",
        "column", "max |diff|", "max |value|", "at t (s)"
    );
    let key_columns: Vec<String> = model
        .bodies
        .iter()
        .skip(1)
        .map(|b| format!("{}.phi", b.name))
        .chain(
            joints
                .iter()
                .flat_map(|j| ["ex", "ey", "fn"].map(|c| format!("{j}.{c}"))),
        )
        .chain(model.drivers.iter().map(|d| format!("{}.torque", d.name)))
        .collect();
    for name in &key_columns {
        if let Some(c) = comparison.column(name) {
            println!(
                "  {:<22} {:>14.6e} {:>14.6e} {:>12.6}",
                c.column, c.max_abs_difference, c.max_abs_value, c.at_t
            );
        }
    }
    for (k, joint) in joints.iter().enumerate() {
        let dt = comparison.max_impact_time_difference[k]
            .map_or("n/a (different counts)".to_string(), |d| {
                format!("{d:.3e} s")
            });
        println!(
            "  joint {joint}: impacts DAE {}, reduced {}, max |impact time difference| {dt}",
            comparison.impacts_a[k], comparison.impacts_b[k]
        );
    }
    println!(
        "  wall time: DAE {:.3} s ({} RHS), reduced {:.3} s ({} RHS)",
        dae.wall_time_s, dae.stats.rhs_evals, reduced.wall_time_s, reduced.stats.rhs_evals
    );
    if let Some(path) = &args.out {
        let provenance = settings.provenance(&model, FormulationKind::Dae);
        let report = CompareReport {
            provenance: &provenance,
            wall_time_dae_s: dae.wall_time_s,
            wall_time_reduced_s: reduced.wall_time_s,
            rhs_evals_dae: dae.stats.rhs_evals,
            rhs_evals_reduced: reduced.stats.rhs_evals,
            comparison: &comparison,
        };
        output::write_json(path, &report)
            .map_err(fail)?
            .commit()
            .map_err(fail)?;
    }
    Ok(())
}
