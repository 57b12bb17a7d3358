//! [`RunSummary`]: what a run did, computed sample by sample, event by event and step by step
//! by [`SummaryBuilder`] so that it needs none of the samples kept (a run streamed to disk
//! holds memory in proportion to its impacts only, for the impact log).

use super::Provenance;
use super::impacts::{Impact, PermanentContact, StepPeak};
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
    /// Largest constraint violation |Φ| over the output samples and every accepted step end
    /// (m or rad; 0 for the reduced formulation). A DAE run whose |Φ| passes its bound
    /// ([`Dae::violation_limits`](crate::formulation::Dae::violation_limits)) at a step end or a
    /// sample stops with an error instead.
    pub max_constraint_violation: f64,
    /// Times (s) at which a DAE run passed a singular position of the linkage, one per passage
    /// ([`Dae::singular_passages`](crate::formulation::Dae::singular_passages)): the DAE keeps
    /// the assembly branch there only with adequate Baumgarte factors; empty for the other
    /// formulations.
    pub singular_passages: Vec<f64>,
    /// Per clearance joint, in model order: impact count and log, separations, first impact
    /// times, true largest penetration and peak normal force, permanent contact.
    pub clearance_joints: Vec<ClearanceSummary>,
    /// Dense-output evaluations made to locate the contact peaks between the samples (0
    /// without clearance joints); their RHS cost, if any (DOP853: 3 per step interpolated for
    /// the first time), is in `solver_stats.dense_evals`.
    pub peak_search_interpolations: u64,
    /// RHS calls the peak search made itself, for the slope at the ends of steps cut at an
    /// event (the methods hold it at every other step end); included in
    /// `solver_stats.rhs_evals`.
    pub peak_search_rhs_evals: u64,
    /// With the energy bookkeeping: the work–energy balance over the run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy_balance: Option<EnergyBalance>,
}

/// What a clearance joint did over a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ClearanceSummary {
    /// Joint name.
    pub joint: String,
    /// Number of impacts (located onsets of contact, δ rising through 0): the length of
    /// [`ClearanceSummary::impacts`]. (Named `impacts` in summaries before the impact log.)
    pub impact_count: usize,
    /// Number of separations (δ falling through 0).
    pub separations: usize,
    /// Times of the first ten impacts (s).
    pub first_impact_times: Vec<f64>,
    /// True largest penetration δ of the run (m): over the output samples and, in every step
    /// in contact, located on the dense output between them (see
    /// [`impacts`](crate::simulation::impacts)); negative if never in contact (the largest
    /// sampled value); `null` in JSON if there is no sample.
    pub max_penetration: f64,
    /// True largest normal force of the run (N), located as `max_penetration`; 0 if never in
    /// contact.
    pub peak_normal_force: f64,
    /// Permanent contact: the last contact began with an impact, never separated before the
    /// end of the run and lasted at least one driver turn (20 % of the run without a single
    /// turning driver); `null` otherwise.
    pub permanent_contact: Option<PermanentContact>,
    /// Every impact, in time order, with its driver angle, impact velocity, true peaks and
    /// duration.
    pub impacts: Vec<Impact>,
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

/// Running maxima, contact phase and impact log of one clearance joint.
#[derive(Debug, Clone)]
struct JointTally {
    name: String,
    delta: Option<usize>,
    normal_force: Option<usize>,
    separations: usize,
    max_penetration: f64,
    peak_normal_force: f64,
    /// In contact now (after the last event).
    in_contact: bool,
    /// The last event's time and the phase before it: a step cut at an event is handed over
    /// after the event, and lies in the phase before it.
    last_event: Option<(f64, bool)>,
    log: Vec<Impact>,
}

impl JointTally {
    /// Whether the joint is in contact during the step [a, b].
    fn in_contact_during(&self, b: f64) -> bool {
        match self.last_event {
            Some((t, before)) if t >= b => before,
            _ => self.in_contact,
        }
    }
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
    /// The single driver's θ0 (rad) and ω (rad/s), for the impacts' driver angles.
    driver: Option<(f64, f64)>,
    /// First and last time seen (s).
    t_first: Option<f64>,
    t_last: f64,
    pub(super) peak_search_interpolations: u64,
    pub(super) peak_search_rhs_evals: u64,
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
                    separations: 0,
                    max_penetration: f64::NEG_INFINITY,
                    peak_normal_force: f64::NEG_INFINITY,
                    in_contact: false,
                    last_event: None,
                    log: Vec::new(),
                })
                .collect(),
            energy,
            driver: None,
            t_first: None,
            t_last: f64::NEG_INFINITY,
            peak_search_interpolations: 0,
            peak_search_rhs_evals: 0,
        }
    }

    /// The model's single driver, with its angle θ0 at t = 0 (rad) and speed ω (rad/s): the
    /// impacts then carry the driver angle θ0 + ω t, and permanent contact needs one driver
    /// turn 2π/|ω|.
    #[must_use]
    pub fn driver(mut self, initial_angle: f64, speed: f64) -> Self {
        self.driver = Some((initial_angle, speed));
        self
    }

    /// Number of clearance joints.
    pub fn n_clearance_joints(&self) -> usize {
        self.joints.len()
    }

    /// Whether clearance joint `k` is in contact during the step ending at `b` (s), as the
    /// events say (a step cut at an event is handed over after it). A joint in contact at the
    /// first sample counts as in contact from the start.
    pub fn in_contact_during(&self, k: usize, b: f64) -> bool {
        self.joints.get(k).is_some_and(|j| j.in_contact_during(b))
    }

    /// The peaks (F_N in N, δ in m) of the contact of joint `k` under way at time `a` (s):
    /// the last impact's, or the joint's over the run for a contact open since the start.
    pub fn contact_peaks_so_far(&self, k: usize, a: f64) -> (f64, f64) {
        let Some(j) = self.joints.get(k) else {
            return (f64::NEG_INFINITY, f64::NEG_INFINITY);
        };
        match j.log.last() {
            Some(last) if last.covers(a) => (last.peak_normal_force, last.peak_penetration),
            _ => (j.peak_normal_force, j.max_penetration),
        }
    }

    /// Adds the peaks of clearance joint `k` inside the step [a, b] (s), found on the dense
    /// output: they raise the joint's maxima and those of the contact under way (the last
    /// impact at or before a).
    pub fn step_peak(&mut self, k: usize, a: f64, b: f64, peak: &StepPeak) {
        self.t_last = self.t_last.max(b);
        let Some(j) = self.joints.get_mut(k) else {
            return;
        };
        let (force, delta) = (peak.normal_force.0, peak.delta.0);
        j.max_penetration = j.max_penetration.max(delta);
        j.peak_normal_force = j.peak_normal_force.max(force);
        if let Some(last) = j.log.last_mut()
            && last.covers(a)
        {
            last.peak_normal_force = last.peak_normal_force.max(force);
            last.peak_penetration = last.peak_penetration.max(delta);
        }
    }

    /// Adds a sample: the output row (columns as given to [`SummaryBuilder::new`]) and the
    /// constraint violation max |Φ| at it.
    pub fn sample(&mut self, row: &[f64], constraint_violation: f64) {
        self.sample_at(f64::NAN, row, constraint_violation);
    }

    /// [`SummaryBuilder::sample`] at time t (s): the first sample's time starts the run, and a
    /// joint with δ > 0 there is in contact from the start (no impact is logged for it).
    pub fn sample_at(&mut self, t: f64, row: &[f64], constraint_violation: f64) {
        let first = self.samples == 0;
        if first && t.is_finite() {
            self.t_first = Some(t);
        }
        if t.is_finite() {
            self.t_last = self.t_last.max(t);
        }
        self.samples += 1;
        // f64::max ignores NaN: a NaN sample cannot hide the maximum of the others.
        self.max_constraint_violation = self.max_constraint_violation.max(constraint_violation);
        let at = |k: Option<usize>| k.and_then(|k| row.get(k).copied());
        for j in &mut self.joints {
            if let Some(d) = at(j.delta) {
                j.max_penetration = j.max_penetration.max(d);
                if first && j.last_event.is_none() {
                    j.in_contact = d > 0.0;
                }
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

    /// Adds an event (index k is the clearance joint k; other indices are ignored), with the
    /// impact velocity δ̇⁽⁻⁾ stored at it (m/s; read for impacts only, NaN if unknown).
    pub fn event(&mut self, event: &EventRecord, impact_velocity: f64) {
        self.t_last = self.t_last.max(event.t);
        let driver_angle = self.driver.map(|(theta0, omega)| theta0 + omega * event.t);
        let Some(j) = self.joints.get_mut(event.index) else {
            return;
        };
        j.last_event = Some((event.t, j.in_contact));
        match event.crossing {
            Crossing::Rising => {
                j.in_contact = true;
                j.log.push(Impact {
                    index: j.log.len() + 1,
                    t: event.t,
                    driver_angle,
                    impact_velocity,
                    // δ = 0 and F_N = 0 at the onset; the steps in contact raise them.
                    peak_normal_force: 0.0,
                    peak_penetration: 0.0,
                    duration: None,
                    open: true,
                });
            }
            Crossing::Falling => {
                j.in_contact = false;
                j.separations += 1;
                if let Some(last) = j.log.last_mut()
                    && last.open
                {
                    last.duration = Some(event.t - last.t);
                    last.open = false;
                }
            }
        }
    }

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
            singular_passages: Vec::new(),
            clearance_joints: self
                .joints
                .iter()
                .map(|j| ClearanceSummary {
                    joint: j.name.clone(),
                    impact_count: j.log.len(),
                    separations: j.separations,
                    first_impact_times: j.log.iter().take(FIRST_IMPACTS).map(|i| i.t).collect(),
                    max_penetration: j.max_penetration,
                    peak_normal_force: j.peak_normal_force.max(0.0),
                    permanent_contact: self.permanent_contact(j),
                    impacts: j.log.clone(),
                })
                .collect(),
            peak_search_interpolations: self.peak_search_interpolations,
            peak_search_rhs_evals: self.peak_search_rhs_evals,
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

impl SummaryBuilder {
    /// The least duration of a permanent contact (s): one turn of the single driver, 2π/|ω|
    /// — the loads of a driven linkage repeat with the driver turn, so a contact that outlasts
    /// one turn has held through every phase of the load cycle, its reversals included —
    /// or, without a single turning driver, 20 % of the run.
    fn min_permanent_duration(&self) -> f64 {
        match self.driver {
            Some((_, omega)) if omega != 0.0 => 2.0 * std::f64::consts::PI / omega.abs(),
            _ => 0.2 * (self.t_last - self.t_first.unwrap_or(0.0)).max(0.0),
        }
    }

    fn permanent_contact(&self, j: &JointTally) -> Option<PermanentContact> {
        let last = j.log.last()?;
        let duration = self.t_last - last.t;
        let min_duration = self.min_permanent_duration();
        (last.open && duration >= min_duration).then_some(PermanentContact {
            since: last.t,
            impact_index: last.index,
            driver_angle: last.driver_angle,
            duration,
            min_duration,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

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
            b.event(&event(k as f64, 0, Crossing::Rising), 0.1 * k as f64);
            b.event(&event(k as f64 + 0.5, 0, Crossing::Falling), f64::NAN);
        }
        b.event(&event(99.0, 7, Crossing::Rising), 1.0); // not a clearance joint: ignored
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
        assert_eq!((jb.impact_count, jb.separations), (12, 12));
        assert_eq!(jb.impacts.len(), 12);
        for (k, i) in jb.impacts.iter().enumerate() {
            assert_eq!(
                (i.index, i.t, i.impact_velocity),
                (k + 1, k as f64, 0.1 * k as f64)
            );
            assert_eq!((i.duration, i.open), (Some(0.5), false), "impact {k}");
        }
        assert!(jb.permanent_contact.is_none(), "every contact closed");
        assert_eq!(
            jb.first_impact_times,
            (0..10).map(f64::from).collect::<Vec<_>>()
        );
        assert_eq!((jb.max_penetration, jb.peak_normal_force), (2e-6, 300.0));
        assert_eq!(
            (jc.impact_count, jc.max_penetration, jc.peak_normal_force),
            (0, -1e-4, 0.0)
        );
        assert!(s.energy_balance.is_none(), "no energy columns");
    }

    fn finish(b: &SummaryBuilder) -> RunSummary {
        let source = crate::model::ModelSource {
            path: String::new(),
            sha256: String::new(),
            overrides: vec![],
        };
        b.finish(
            super::super::provenance::provenance(&source, vec![]),
            SolverOptions::default(),
            SolverStats::default(),
            0.0,
            0.0,
        )
    }

    fn peak(force: f64, delta: f64) -> StepPeak {
        StepPeak {
            normal_force: (force, 0.0),
            delta: (delta, 0.0),
        }
    }

    #[test]
    fn step_peaks_go_to_the_contact_under_way_and_an_open_last_contact_is_permanent() {
        let cols = names(&["B.delta", "B.fn"]);
        // Driver at 2π rad/s: one turn per second, θ0 = 0.5 rad.
        let mut b = SummaryBuilder::new(&cols, &names(&["B"])).driver(0.5, 2.0 * PI);
        b.sample_at(0.0, &[-1e-4, 0.0], 0.0);
        assert!(!b.in_contact_during(0, 0.1), "free at the start");
        b.event(&event(0.1, 0, Crossing::Rising), 0.3);
        assert!(b.in_contact_during(0, 0.2), "step after the impact");
        b.step_peak(0, 0.1, 0.2, &peak(500.0, 1e-6));
        b.event(&event(0.3, 0, Crossing::Falling), f64::NAN);
        // The step cut at the separation is handed over after it: still in contact.
        assert!(b.in_contact_during(0, 0.3), "step ending at the separation");
        b.step_peak(0, 0.2, 0.3, &peak(800.0, 2e-6));
        assert!(!b.in_contact_during(0, 0.4), "free after the separation");
        b.event(&event(0.4, 0, Crossing::Rising), 0.2);
        b.step_peak(0, 0.4, 0.9, &peak(100.0, 5e-7));
        b.sample_at(1.5, &[1e-7, 50.0], 0.0);
        let s = finish(&b);
        let j = &s.clearance_joints[0];
        assert_eq!((j.peak_normal_force, j.max_penetration), (800.0, 2e-6));
        let [first, second] = j.impacts.as_slice() else {
            panic!("two impacts expected: {:?}", j.impacts);
        };
        assert_eq!(
            (first.peak_normal_force, first.peak_penetration),
            (800.0, 2e-6)
        );
        assert_eq!(first.driver_angle, Some(0.5 + 0.2 * PI));
        assert!((first.duration.unwrap_or(f64::NAN) - 0.2).abs() < 1e-15);
        assert_eq!(
            (second.peak_normal_force, second.duration, second.open),
            (100.0, None, true)
        );
        // Open from 0.4 s to the last sample at 1.5 s: 1.1 s ≥ one turn (1 s).
        let p = j
            .permanent_contact
            .as_ref()
            .unwrap_or_else(|| panic!("permanent contact expected"));
        assert_eq!((p.since, p.impact_index, p.min_duration), (0.4, 2, 1.0));
        assert!((p.duration - 1.1).abs() < 1e-12, "{}", p.duration);
        // Half a turn shorter: not permanent.
        let mut short = SummaryBuilder::new(&cols, &names(&["B"])).driver(0.0, 4.0 * PI);
        short.sample_at(0.0, &[-1e-4, 0.0], 0.0);
        short.event(&event(0.4, 0, Crossing::Rising), 0.2);
        short.sample_at(0.8, &[1e-7, 50.0], 0.0);
        assert!(
            finish(&short).clearance_joints[0]
                .permanent_contact
                .is_none(),
            "0.4 s < one turn of 0.5 s"
        );
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
        let s = finish(&b);
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
        let s = finish(&b);
        let e = s
            .energy_balance
            .unwrap_or_else(|| panic!("energy balance expected"));
        assert_eq!(e.relative_residual, 4.4e-16 / 2.0, "scale |V| = 2 J");
    }
}
