//! The DAE and the reduced formulation of one model, run with the same settings and compared
//! ([`crate::analysis::compare()`]): the check that the two formulations describe one linkage.

use crate::analysis::{Comparison, compare};
use crate::error::Result;
use crate::model::Model;
use crate::simulation::{FormulationKind, RunSummary, Simulation, SimulationOptions};
use serde::Serialize;

/// The DAE and the reduced formulation of one model run with the same settings.
#[derive(Debug, Clone, Serialize)]
pub struct FormulationComparison {
    /// Summary of the DAE run (its provenance is the comparison's).
    pub dae: RunSummary,
    /// Summary of the reduced run.
    pub reduced: RunSummary,
    /// Their differences (run a: DAE, run b: reduced; event k: clearance joint k).
    pub comparison: Comparison,
}

/// Runs `model` with the DAE and with the reduced formulation, both with `options` (its
/// `formulation` is ignored; the energy bookkeeping must be off, as the reduced formulation
/// has none), and compares them. Both simulations are built — every setting checked — before
/// either runs.
pub fn compare_formulations(
    model: &Model,
    options: &SimulationOptions,
) -> Result<FormulationComparison> {
    let with = |kind| Simulation::new(model, options.clone().formulation(kind));
    let dae = with(FormulationKind::Dae)?;
    let reduced = with(FormulationKind::Reduced)?;
    let (a, b) = (dae.run_to_memory()?, reduced.run_to_memory()?);
    let comparison = compare(&a, &b, dae.clearance_joints().len());
    Ok(FormulationComparison {
        dae: a.summary,
        reduced: b.summary,
        comparison,
    })
}
