//! `Model.wear`: the library's wear study behind `linkdyn wear` ([`linkdyn::studies::wear`])
//! with the command line's checks and defaults (`src/cli/wear.rs`), computed with the GIL
//! released and returned as the record `Wear` of `linkdyn._analyses`: the command's
//! `wear.csv` as arrays and its `wear.json`'s keys.

use crate::analyses::{floats, record, to_python};
use crate::errors::Failed;
use crate::orbit::count;
use crate::settings::Solve;
use linkdyn::model::Model;
use linkdyn::simulation::Simulation;
use linkdyn::studies::{WearRequest, wear};
use numpy::PyArrayMethods;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// `Model.wear` (`linkdyn wear`).
pub fn wear_study<'py>(
    py: Python<'py>,
    model: &Model,
    path: &str,
    solve: &Solve,
    turns: i64,
    update_every: i64,
) -> PyResult<Bound<'py, PyAny>> {
    let result = py
        .detach(|| -> Result<_, Failed> {
            // Negative counts are refused here, 0 by the study with its own message (the
            // command line parses `usize` and leaves 0 to the study too).
            let what = "a whole number of driver turns ≥ 1";
            let request = WearRequest {
                turns: count("turns", turns, 0, what)?,
                update_every: count("update_every", update_every, 0, what)?,
            };
            // As the command: the simulation runs at least one turn; zero turns are the
            // study's to refuse.
            let sim = Simulation::new(model, solve.for_turns(request.turns.max(1) as f64)?)
                .map_err(Failed::building)?;
            Ok(wear(&sim, request)?)
        })
        .map_err(|f| f.into_py(py, path))?;
    let fields = PyDict::new(py);
    let json = to_python(py, &result.summary_json())?;
    for key in [
        "joint",
        "turns",
        "update_every",
        "bins",
        "clearance_m",
        "archard",
        "summary",
        "updates",
        "stats",
        "provenance",
    ] {
        fields.set_item(key, json.get_item(key)?)?;
    }
    // wear.csv as arrays: the profile after each update, by bin.
    let (n, bins) = (result.updates.len(), result.bin_centres.len());
    fields.set_item("theta_rad", floats(py, result.bin_centres.clone()))?;
    fields.set_item(
        "t",
        floats(py, result.updates.iter().map(|u| u.t).collect()),
    )?;
    fields.set_item(
        "update_turns",
        floats(py, result.updates.iter().map(|u| u.turns).collect()),
    )?;
    fields.set_item(
        "eccentricity_m",
        floats(py, result.updates.iter().map(|u| u.eccentricity).collect()),
    )?;
    let depth: Vec<f64> = result
        .updates
        .iter()
        .flat_map(|u| u.depth.iter().copied())
        .collect();
    fields.set_item("depth_m", floats(py, depth).reshape([n, bins])?)?;
    record(py, "Wear", &fields)
}
