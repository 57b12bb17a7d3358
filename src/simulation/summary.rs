//! [`RunSummary`]: what a run did, computed sample by sample by [`SummaryBuilder`] so that it
//! needs none of the samples kept (a run streamed to disk holds O(1) memory).

use super::Provenance;
use crate::formulation::Crossing;
use crate::solve::{EventRecord, SolverOptions, SolverStats};
use serde::Serialize;

/// Number of impact times kept per clearance joint in [`ClearanceSummary::first_impact_times`].
pub const FIRST_IMPACTS: usize = 10;

/// The summary of a run (written as the JSON result file by the `linkdyn` command).
#[derive(Debug, Clone, Serialize)]
pub struct RunSummary {
    /// What made it.
    pub provenance: Provenance,
    /// Solver options.
    pub solver_options: SolverOptions,
    /// Solver statistics.
    pub solver_stats: SolverStats,
    /// Wall time of the integration, output evaluation included (s); the time the consumer
    /// of the samples took (e.g. writing the CSV) is not included but given apart.
    pub wall_time_s: f64,
    /// Wall time spent by the consumer of the samples (e.g. writing the CSV) (s).
    pub sink_time_s: f64,
    /// Number of output samples.
    pub samples: usize,
    /// Largest constraint violation |Φ| over the samples (m or rad; 0 for the reduced
    /// formulation).
    pub max_constraint_violation: f64,
    /// Per clearance joint, in model order: impacts, separations, first impact times, largest
    /// penetration and peak normal force (the last two over the output samples).
    pub clearance_joints: Vec<ClearanceSummary>,
    /// With the energy bookkeeping: the work–energy balance over the run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy_balance: Option<EnergyBalance>,
}

/// What a clearance joint did over a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ClearanceSummary {
    /// Joint name.
    pub joint: String,
    /// Number of impacts (located onsets of contact, δ rising through 0).
    pub impacts: usize,
    /// Number of separations (δ falling through 0).
    pub separations: usize,
    /// Times of the first ten impacts (s).
    pub first_impact_times: Vec<f64>,
    /// Largest penetration δ over the output samples (m; negative if never in contact;
    /// `null` in JSON if there is no sample).
    pub max_penetration: f64,
    /// Largest normal force over the output samples (N).
    pub peak_normal_force: f64,
}

/// The work–energy balance of a run with the energy bookkeeping (J).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EnergyBalance {
    /// Driver work at the end.
    pub driver_work: f64,
    /// Work of applied torques and forces at the end.
    pub external_work: f64,
    /// Energy dissipated by contacts and dampers at the end.
    pub dissipated: f64,
    /// max |driver + external work − ΔE − dissipated| over the samples.
    pub max_abs_residual: f64,
    /// That residual relative to the largest energy the balance adds up: the largest of
    /// |driver work|, |external work|, kinetic energy and |potential energy| over the samples
    /// (the residual itself if all are 0). The potential energy is in the scale because the
    /// balance is computed from it: a system at rest (no work, no kinetic energy) has a
    /// residual of a few rounding errors of V, which this reads as ~1e-16 rather than as
    /// that rounding error over a kinetic energy of 1e-31 J (5e15 before this floor). |V|
    /// depends on the datum (the ground origin in the shipped models): a datum far from the
    /// linkage makes the ratio smaller than it should be.
    pub relative_residual: f64,
}

/// Running maxima of one clearance joint.
#[derive(Debug, Clone)]
struct JointTally {
    name: String,
    delta: Option<usize>,
    normal_force: Option<usize>,
    impacts: usize,
    separations: usize,
    first_impact_times: Vec<f64>,
    max_penetration: f64,
    peak_normal_force: f64,
}

/// Column indices and running values of the energy balance.
#[derive(Debug, Clone)]
struct EnergyTally {
    balance: usize,
    kinetic: usize,
    potential: Option<usize>,
    driver_work: usize,
    external_work: usize,
    dissipated: usize,
    max_abs_balance: f64,
    scale: f64,
    last: Option<[f64; 3]>,
}

/// Builds a [`RunSummary`] sample by sample and event by event, in O(1) memory in the run
/// length.
#[derive(Debug, Clone)]
pub struct SummaryBuilder {
    samples: usize,
    max_constraint_violation: f64,
    joints: Vec<JointTally>,
    energy: Option<EnergyTally>,
}

impl SummaryBuilder {
    /// A builder for output columns `names` and the clearance joints `joints` (in model order:
    /// the δ event of joint k has index k). The energy balance is kept if the `energy.*`
    /// columns are present.
    pub fn new(names: &[String], joints: &[String]) -> Self {
        let index = |n: &str| names.iter().position(|c| c == n);
        let energy = (|| {
            Some(EnergyTally {
                balance: index("energy.balance")?,
                kinetic: index("energy.kinetic")?,
                potential: index("energy.potential"),
                driver_work: index("energy.driver_work")?,
                external_work: index("energy.external_work")?,
                dissipated: index("energy.dissipated")?,
                max_abs_balance: 0.0,
                scale: 0.0,
                last: None,
            })
        })();
        SummaryBuilder {
            samples: 0,
            max_constraint_violation: 0.0,
            joints: joints
                .iter()
                .map(|name| JointTally {
                    name: name.clone(),
                    delta: index(&format!("{name}.delta")),
                    normal_force: index(&format!("{name}.fn")),
                    impacts: 0,
                    separations: 0,
                    first_impact_times: Vec::new(),
                    max_penetration: f64::NEG_INFINITY,
                    peak_normal_force: f64::NEG_INFINITY,
                })
                .collect(),
            energy,
        }
    }

    /// Adds a sample: the output row (columns as given to [`SummaryBuilder::new`]) and the
    /// constraint violation max |Φ| at it.
    pub fn sample(&mut self, row: &[f64], constraint_violation: f64) {
        self.samples += 1;
        // f64::max ignores NaN: a NaN sample cannot hide the maximum of the others.
        self.max_constraint_violation = self.max_constraint_violation.max(constraint_violation);
        let at = |k: Option<usize>| k.and_then(|k| row.get(k).copied());
        for j in &mut self.joints {
            if let Some(d) = at(j.delta) {
                j.max_penetration = j.max_penetration.max(d);
            }
            if let Some(f) = at(j.normal_force) {
                j.peak_normal_force = j.peak_normal_force.max(f);
            }
        }
        if let Some(e) = &mut self.energy {
            let get = |k: usize| row.get(k).copied().unwrap_or(f64::NAN);
            e.max_abs_balance = e.max_abs_balance.max(get(e.balance).abs());
            e.scale = e
                .scale
                .max(get(e.driver_work).abs())
                .max(get(e.external_work).abs())
                .max(get(e.kinetic).abs())
                .max(e.potential.map_or(0.0, |k| get(k).abs()));
            e.last = Some([get(e.driver_work), get(e.external_work), get(e.dissipated)]);
        }
    }

    /// Adds an event (index k is the clearance joint k; other indices are ignored).
    pub fn event(&mut self, event: &EventRecord) {
        let Some(j) = self.joints.get_mut(event.index) else {
            return;
        };
        match event.crossing {
            Crossing::Rising => {
                j.impacts += 1;
                if j.first_impact_times.len() < FIRST_IMPACTS {
                    j.first_impact_times.push(event.t);
                }
            }
            Crossing::Falling => j.separations += 1,
        }
    }

    // DENSE-OUTPUT HOOK (for the solvers helper): when `solve::Sink` gains a per-step callback
    // with the step's dense output, add `pub fn step(&mut self, ...)` here that raises
    // `max_penetration` and `peak_normal_force` to their true maxima between samples, call it
    // from `Observed` in `sink.rs`, and change the two field docs above ("over the output
    // samples") and the README accordingly.

    /// Number of samples seen.
    pub fn samples(&self) -> usize {
        self.samples
    }

    /// The summary, with what the builder cannot know.
    pub fn finish(
        &self,
        provenance: Provenance,
        solver_options: SolverOptions,
        solver_stats: SolverStats,
        wall_time_s: f64,
        sink_time_s: f64,
    ) -> RunSummary {
        RunSummary {
            provenance,
            solver_options,
            solver_stats,
            wall_time_s,
            sink_time_s,
            samples: self.samples,
            max_constraint_violation: self.max_constraint_violation,
            clearance_joints: self
                .joints
                .iter()
                .map(|j| ClearanceSummary {
                    joint: j.name.clone(),
                    impacts: j.impacts,
                    separations: j.separations,
                    first_impact_times: j.first_impact_times.clone(),
                    max_penetration: j.max_penetration,
                    peak_normal_force: j.peak_normal_force.max(0.0),
                })
                .collect(),
            energy_balance: self.energy.as_ref().and_then(|e| {
                let [driver_work, external_work, dissipated] = e.last?;
                Some(EnergyBalance {
                    driver_work,
                    external_work,
                    dissipated,
                    max_abs_residual: e.max_abs_balance,
                    relative_residual: if e.scale > 0.0 {
                        e.max_abs_balance / e.scale
                    } else {
                        e.max_abs_balance
                    },
                })
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    fn event(t: f64, index: usize, crossing: Crossing) -> EventRecord {
        EventRecord {
            t,
            index,
            crossing,
            restarted: true,
        }
    }

    #[test]
    fn counts_and_maxima_are_kept_incrementally() {
        let cols = names(&["B.delta", "B.fn", "C.delta", "C.fn"]);
        let mut b = SummaryBuilder::new(&cols, &names(&["B", "C"]));
        b.sample(&[-1e-4, 0.0, -2e-4, 0.0], 1e-12);
        b.sample(&[2e-6, 300.0, -1e-4, 0.0], 3e-12);
        b.sample(&[-5e-5, 0.0, -1e-4, 0.0], 2e-12);
        for k in 0..12 {
            b.event(&event(k as f64, 0, Crossing::Rising));
            b.event(&event(k as f64 + 0.5, 0, Crossing::Falling));
        }
        b.event(&event(99.0, 7, Crossing::Rising)); // not a clearance joint: ignored
        let s = b.finish(
            super::super::provenance::provenance(
                &crate::model::ModelSource {
                    path: "m.toml".into(),
                    sha256: "0".into(),
                    overrides: vec![],
                },
                vec![],
            ),
            SolverOptions::default(),
            SolverStats::default(),
            0.0,
            0.0,
        );
        assert_eq!(s.samples, 3);
        assert_eq!(s.max_constraint_violation, 3e-12);
        let (jb, jc) = (&s.clearance_joints[0], &s.clearance_joints[1]);
        assert_eq!((jb.impacts, jb.separations), (12, 12));
        assert_eq!(
            jb.first_impact_times,
            (0..10).map(f64::from).collect::<Vec<_>>()
        );
        assert_eq!((jb.max_penetration, jb.peak_normal_force), (2e-6, 300.0));
        assert_eq!(
            (jc.impacts, jc.max_penetration, jc.peak_normal_force),
            (0, -1e-4, 0.0)
        );
        assert!(s.energy_balance.is_none(), "no energy columns");
    }

    #[test]
    fn energy_balance_uses_the_last_values_and_the_largest_scale() {
        let cols = names(&[
            "energy.kinetic",
            "energy.driver_work",
            "energy.external_work",
            "energy.dissipated",
            "energy.balance",
        ]);
        let mut b = SummaryBuilder::new(&cols, &[]);
        b.sample(&[0.0, 0.0, 0.0, 0.0, 0.0], 0.0);
        b.sample(&[4.0, 2.0, -1.0, 0.5, -1e-6], 0.0);
        b.sample(&[1.0, 3.0, -1.0, 1.0, 2e-7], 0.0);
        let source = crate::model::ModelSource {
            path: String::new(),
            sha256: String::new(),
            overrides: vec![],
        };
        let s = b.finish(
            super::super::provenance::provenance(&source, vec![]),
            SolverOptions::default(),
            SolverStats::default(),
            0.0,
            0.0,
        );
        let e = s
            .energy_balance
            .unwrap_or_else(|| panic!("energy balance expected"));
        assert_eq!(
            (e.driver_work, e.external_work, e.dissipated),
            (3.0, -1.0, 1.0)
        );
        assert_eq!(e.max_abs_residual, 1e-6);
        // Scale: the kinetic energy 4 J is the largest magnitude seen.
        assert_eq!(e.relative_residual, 1e-6 / 4.0);
    }

    #[test]
    fn a_system_at_rest_has_a_rounding_level_relative_residual() {
        // A pendulum hanging at rest: no work, kinetic energy 1e-31 J from rounding, V = −2 J,
        // balance residual 4.4e-16 J (two ulps of V). Against the kinetic energy alone this
        // read 4.4e15; against |V| it is 2.2e-16, the rounding level it is.
        let cols = names(&[
            "energy.kinetic",
            "energy.potential",
            "energy.driver_work",
            "energy.external_work",
            "energy.dissipated",
            "energy.balance",
        ]);
        let mut b = SummaryBuilder::new(&cols, &[]);
        b.sample(&[0.0, -2.0, 0.0, 0.0, 0.0, 0.0], 0.0);
        b.sample(&[1e-31, -2.0, 0.0, 0.0, 0.0, 4.4e-16], 0.0);
        let source = crate::model::ModelSource {
            path: String::new(),
            sha256: String::new(),
            overrides: vec![],
        };
        let s = b.finish(
            super::super::provenance::provenance(&source, vec![]),
            SolverOptions::default(),
            SolverStats::default(),
            0.0,
            0.0,
        );
        let e = s
            .energy_balance
            .unwrap_or_else(|| panic!("energy balance expected"));
        assert_eq!(e.relative_residual, 4.4e-16 / 2.0, "scale |V| = 2 J");
    }
}
