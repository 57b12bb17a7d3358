//! One scene, several contact laws: the same model run once per law of one clearance joint, with
//! the peak normal force, the impact count and how far the driver torque moves from the first
//! law's (the laws and their sources: docs/contact_laws.md).
//!
//! A law is named as in the model file, optionally with a damping for the line-contact laws:
//! `lankarani-nikravesh`, `johnson`, `johnson:flores`. Each run applies the `--set` overrides
//! of the scene, then `joints.J.contact.law=LAW` (and `joints.J.contact.damping=DAMPING`), so
//! the usual checks apply: a line law needs the joint's `length` among the scene's overrides or
//! in the file.

use crate::error::{Error, Result};
use crate::model::JointKind;
use crate::simulation::{Provenance, Simulation, SimulationOptions};
use serde::Serialize;
use std::path::Path;

/// The result of one law.
#[derive(Debug, Clone, Serialize)]
pub struct LawRun {
    /// The law as given (`johnson:flores`).
    pub law: String,
    /// Impacts of the joint.
    pub impacts: usize,
    /// Largest normal force of the joint (N), the true peak between samples.
    pub peak_normal_force: f64,
    /// Largest penetration of the joint (m).
    pub max_penetration: f64,
    /// RMS over the samples of the driver torque's difference from the first law's (N·m); 0 for
    /// the first law.
    pub torque_rms_difference: f64,
    /// RMS of the driver torque itself (N·m): the scale of the difference.
    pub torque_rms: f64,
    /// Right-hand-side evaluations of the run.
    pub rhs_evals: u64,
    /// Wall time of the run (s).
    pub wall_time_s: f64,
}

/// Every law's run on one scene.
#[derive(Debug, Clone, Serialize)]
pub struct LawComparison {
    /// The clearance joint whose law changes.
    pub joint: String,
    /// The driver whose torque is compared.
    pub driver: String,
    /// Provenance of the first law's run (the scene's overrides and the run settings).
    pub provenance: Provenance,
    /// One row per law, in the order given.
    pub runs: Vec<LawRun>,
}

/// The `--set` overrides that select `law` (`LAW` or `LAW:DAMPING`) on joint `joint`.
pub fn law_overrides(joint: &str, law: &str) -> Vec<String> {
    let (name, damping) = match law.split_once(':') {
        Some((name, damping)) => (name, Some(damping)),
        None => (law, None),
    };
    let mut sets = vec![format!("joints.{joint}.contact.law={}", name.trim())];
    if let Some(d) = damping {
        sets.push(format!("joints.{joint}.contact.damping={}", d.trim()));
    }
    sets
}

/// Runs the model at `path` with the overrides `sets` once per law of `laws` on clearance joint
/// `joint`, each with `options`, and compares them. Every model is loaded and every simulation
/// built (all settings checked) before any runs. The model needs one driver (its torque is
/// compared) and a clearance joint named `joint`.
pub fn compare_contact_laws(
    path: &Path,
    sets: &[String],
    joint: &str,
    laws: &[String],
    options: &SimulationOptions,
) -> Result<LawComparison> {
    if laws.is_empty() {
        return Err(Error::settings("laws", "expected at least one contact law"));
    }
    // The scene itself first: a joint that is not a clearance joint would otherwise be
    // reported as a `contact` table it may not have.
    let scene = crate::model::load(path, sets)?;
    let is_clearance = scene
        .joints
        .iter()
        .any(|j| j.name == joint && matches!(j.kind, JointKind::Clearance(_)));
    if !is_clearance {
        return Err(Error::settings(
            "joint",
            format!("expected the name of a clearance joint of the model, found \"{joint}\""),
        ));
    }
    let [driver] = scene.drivers.as_slice() else {
        return Err(Error::settings(
            "model",
            format!(
                "expected a model with one driver (its torque is compared), found {}",
                scene.drivers.len()
            ),
        ));
    };
    let driver = driver.name.clone();
    let mut sims = Vec::with_capacity(laws.len());
    for law in laws {
        let mut all = sets.to_vec();
        all.extend(law_overrides(joint, law));
        let model = crate::model::load(path, &all)?;
        sims.push(Simulation::new(&model, options.clone())?);
    }
    let torque_column = format!("{driver}.torque");
    let mut runs = Vec::with_capacity(laws.len());
    let mut reference: Option<Vec<f64>> = None;
    let mut provenance = None;
    for (sim, law) in sims.iter().zip(laws) {
        let run = sim.run_to_memory()?;
        let torque = run
            .column(&torque_column)
            .map(<[f64]>::to_vec)
            .ok_or_else(|| {
                Error::settings("model", format!("the run has no column {torque_column}"))
            })?;
        let summary = &run.summary;
        let clearance = summary
            .clearance_joints
            .iter()
            .find(|c| c.joint == joint)
            .ok_or_else(|| Error::settings("joint", format!("no summary of joint {joint}")))?;
        let rms = |v: &mut dyn Iterator<Item = f64>, n: usize| {
            (v.map(|x| x * x).sum::<f64>() / n.max(1) as f64).sqrt()
        };
        let n = torque.len();
        let torque_rms = rms(&mut torque.iter().copied(), n);
        let reference = reference.get_or_insert_with(|| torque.clone());
        // Same settings, same end time and sample interval: the same sample times.
        let difference = rms(
            &mut torque.iter().zip(reference.iter()).map(|(a, b)| a - b),
            n.min(reference.len()),
        );
        provenance.get_or_insert_with(|| summary.provenance.clone());
        runs.push(LawRun {
            law: law.clone(),
            impacts: clearance.impact_count,
            peak_normal_force: clearance.peak_normal_force,
            max_penetration: clearance.max_penetration,
            torque_rms_difference: difference,
            torque_rms,
            rhs_evals: summary.solver_stats.rhs_evals,
            wall_time_s: summary.wall_time_s,
        });
    }
    Ok(LawComparison {
        joint: joint.to_string(),
        driver,
        provenance: provenance.unwrap_or_else(|| sims[0].provenance()),
        runs,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_law_with_a_damping_becomes_two_overrides() {
        assert_eq!(law_overrides("B", "hertz"), ["joints.B.contact.law=hertz"]);
        assert_eq!(
            law_overrides("B", "johnson:flores"),
            [
                "joints.B.contact.law=johnson",
                "joints.B.contact.damping=flores"
            ]
        );
    }
}
