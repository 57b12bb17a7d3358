//! `linkdyn compare MODEL …`: run the DAE and the reduced formulation with the same settings
//! and report their largest differences.

use super::args::SolveArgs;
use super::{Failure, in_model};
use clap::Args;
use linkdyn::output::{self, Provenance};
use linkdyn::simulation::{Simulation, clearance_joint_names};
use linkdyn::studies::compare_formulations;
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
    comparison: &'a linkdyn::analysis::Comparison,
}

/// Runs `compare`.
pub fn run(args: &CompareArgs) -> Result<(), Failure> {
    let model = super::load_model(&args.model, &args.solve.set, &args.solve.ideal)?;
    let options = args.solve.options()?;
    // Every setting is checked before either formulation runs (again inside
    // `compare_formulations`, which costs an assembly).
    let sim = Simulation::new(&model, options.clone()).map_err(|e| in_model(&args.model, e))?;
    if let Some(path) = &args.out {
        output::check_output_file(path, Some(&args.model))?;
    }
    let result = compare_formulations(&model, &options).map_err(|e| in_model(&args.model, e))?;
    let comparison = &result.comparison;
    let joints = clearance_joint_names(&model);
    println!(
        "{}: DAE vs reduced, {} samples to t = {} s, rtol {:e}",
        model.name,
        comparison.samples,
        sim.t_end(),
        sim.solver_options().rtol
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
        let dt = comparison
            .max_impact_time_difference
            .get(k)
            .copied()
            .flatten()
            .map_or("n/a (different counts)".to_string(), |d| {
                format!("{d:.3e} s")
            });
        let count = |v: &[usize]| v.get(k).copied().unwrap_or(0);
        println!(
            "  joint {joint}: impacts DAE {}, reduced {}, max |impact time difference| {dt}",
            count(&comparison.impacts_a),
            count(&comparison.impacts_b)
        );
    }
    let (dae, reduced) = (&result.dae, &result.reduced);
    println!(
        "  wall time: DAE {:.3} s ({} RHS), reduced {:.3} s ({} RHS)",
        dae.wall_time_s,
        dae.solver_stats.rhs_evals,
        reduced.wall_time_s,
        reduced.solver_stats.rhs_evals
    );
    if let Some(path) = &args.out {
        let report = CompareReport {
            provenance: &dae.provenance,
            wall_time_dae_s: dae.wall_time_s,
            wall_time_reduced_s: reduced.wall_time_s,
            rhs_evals_dae: dae.solver_stats.rhs_evals,
            rhs_evals_reduced: reduced.solver_stats.rhs_evals,
            comparison,
        };
        output::write_json(path, &report)?.commit()?;
    }
    Ok(())
}
