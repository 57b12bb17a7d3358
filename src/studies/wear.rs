//! Wear of a revolute clearance joint's bearing over many driver turns (`linkdyn wear`):
//! Archard's law accumulated from the contact force and the sliding speed along the run, the
//! bearing profile updated every M turns (equations, approximations and references in
//! [`crate::contact::wear`]).
//!
//! The run is cut into intervals of M driver turns (the last may be shorter). Inside an
//! interval the profile is fixed, so the equations of motion stay smooth; the wear of every
//! accepted step is integrated on the step's dense output by three-point Gauss–Legendre
//! quadrature (exact for a contact force and sliding speed polynomial of degree 5 in time
//! within the step; the contact events end steps at the contact's onset). At the interval's
//! end the accumulated wear is added to the profile, the DAE continues from the final state on
//! the worn bearing, and the profile is recorded.
//!
//! DAE formulation only: the worn profile is part of its contact sites. The reduced formulation
//! (its own four-bar contact) and the generalised one are refused with the reason.

use crate::contact::wear::{ArchardWear, WearProfile};
use crate::error::{Error, Result};
use crate::formulation::{Dae, Formulation};
use crate::model::{JointKind, Model};
use crate::simulation::{FormulationKind, Provenance, Simulation};
use crate::solve::{self, DenseStep, Sink, SolveError, SolverStats};
use serde::Serialize;
use std::f64::consts::TAU;

/// What to run: `turns` driver turns, the profile updated every `update_every` turns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WearRequest {
    /// Driver turns N in all (≥ 1).
    pub turns: usize,
    /// Profile update interval M (driver turns, ≥ 1).
    pub update_every: usize,
}

/// The profile after one update.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WearUpdate {
    /// Update number (0: the unworn bearing at the start).
    pub index: usize,
    /// Time (s).
    pub t: f64,
    /// Driver turns since the start.
    pub turns: f64,
    /// The journal's distance |e| from the bearing centre at `t` (m), the state the next
    /// interval starts from: on a worn bearing the journal sits deeper (|e| > c) where it wore.
    pub eccentricity: f64,
    /// Wear depth per bin (m), bin i centred at (i + ½)·2π/N in the bearing frame.
    pub depth: Vec<f64>,
}

/// Summary of a wear study: the final profile's extremes and the worn volume.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WearSummary {
    /// Largest wear depth (m).
    pub max_depth: f64,
    /// The centre angle of its bin in the bearing frame (rad, counter-clockwise from the
    /// bearing body's x axis).
    pub max_depth_angle: f64,
    /// Worn volume per unit axial length Σ h_i R_B Δθ (m²).
    pub worn_area: f64,
    /// Worn volume (m³): the area times the bearing length.
    pub worn_volume: f64,
    /// Mean wear depth over the circumference (m).
    pub mean_depth: f64,
}

/// Result of [`wear()`]: the profile after every update, the wear data and the run's cost.
#[derive(Debug, Clone, Serialize)]
pub struct WearResult {
    /// The worn joint.
    pub joint: String,
    /// Driver turns and update interval as run.
    pub turns: usize,
    /// Profile update interval (driver turns).
    pub update_every: usize,
    /// Radial clearance c of the unworn bearing (m).
    pub clearance: f64,
    /// The wear law's data (k_w, L, R_B, Hertz factor).
    pub archard: ArchardWear,
    /// Bin centres (rad, bearing frame).
    pub bin_centres: Vec<f64>,
    /// Profiles: the unworn one, then one per update.
    pub updates: Vec<WearUpdate>,
    /// Final profile's summary.
    pub summary: WearSummary,
    /// Solver statistics of all intervals together.
    pub stats: SolverStats,
    /// Model and settings.
    pub provenance: Provenance,
}

impl WearResult {
    /// The study's settings, for the provenance of its files (`wear_joint`, `wear_turns`,
    /// `wear_update_every`, `wear_bins`, `wear_coefficient_m2_per_n`, `wear_length_m`).
    pub fn settings(&self) -> Vec<(&'static str, String)> {
        let fmt = crate::numbers::format_number;
        vec![
            ("wear_joint", self.joint.clone()),
            ("wear_turns", self.turns.to_string()),
            ("wear_update_every", self.update_every.to_string()),
            ("wear_bins", self.bin_centres.len().to_string()),
            ("wear_coefficient_m2_per_n", fmt(self.archard.coefficient)),
            ("wear_length_m", fmt(self.archard.length)),
        ]
    }

    /// The summary file `wear.json` of `linkdyn wear` (docs/wear.md, "Files"): the provenance
    /// with the study's settings, the wear law's data, the summary, the journal's eccentricity
    /// and the deepest wear after each update, and the solver's cost.
    pub fn summary_json(&self) -> serde_json::Value {
        let mut provenance = self.provenance.clone();
        for (k, v) in self.settings() {
            provenance.settings.insert(k.to_string(), v);
        }
        let updates: Vec<_> = self
            .updates
            .iter()
            .map(|u| {
                serde_json::json!({
                    "index": u.index,
                    "t": u.t,
                    "turns": u.turns,
                    "eccentricity_m": u.eccentricity,
                    "max_depth_m": u.depth.iter().copied().fold(0.0, f64::max),
                })
            })
            .collect();
        serde_json::json!({
            "joint": self.joint,
            "turns": self.turns,
            "update_every": self.update_every,
            "bins": self.bin_centres.len(),
            "clearance_m": self.clearance,
            "archard": {
                "coefficient_m2_per_n": self.archard.coefficient,
                "length_m": self.archard.length,
                "bearing_radius_m": self.archard.bearing_radius,
                "hertz_factor_m2_per_n": self.archard.hertz_factor,
            },
            "summary": {
                "max_depth_m": self.summary.max_depth,
                "max_depth_angle_rad": self.summary.max_depth_angle,
                "mean_depth_m": self.summary.mean_depth,
                "worn_area_m2": self.summary.worn_area,
                "worn_volume_m3": self.summary.worn_volume,
            },
            "updates": updates,
            "stats": self.stats,
            "provenance": provenance,
        })
    }
}

/// Runs the wear study on `sim`'s model (see the module documentation).
///
/// Errors: [`Error::Settings`] for a formulation other than the DAE, a model without exactly
/// one driver or without exactly one clearance joint with `[joints.wear]`, or zero turns or
/// interval; [`Error::Solve`] for a failed integration.
pub fn wear(sim: &Simulation, request: WearRequest) -> Result<WearResult> {
    let dae = match (sim.options().formulation, sim.dae()) {
        (FormulationKind::Dae, Some(dae)) => dae,
        (kind, _) => {
            return Err(Error::settings(
                "formulation",
                format!(
                    "the wear study runs on the DAE formulation only (the worn bearing profile is part of its contact sites); got {kind}"
                ),
            ));
        }
    };
    if request.turns == 0 || request.update_every == 0 {
        return Err(Error::settings(
            "turns",
            format!(
                "expected at least one turn and an update interval of at least one turn, got {} turns every {}",
                request.turns, request.update_every
            ),
        ));
    }
    let turns_per_second = sim.driver_turns(1.0).filter(|r| *r > 0.0).ok_or_else(|| {
        Error::settings(
            "turns",
            "the wear study counts driver turns: the model needs exactly one driver with a non-zero speed",
        )
    })?;
    let (k, joint, spec) = worn_joint(sim.model())?;
    let archard = ArchardWear::from_spec(spec).ok_or_else(|| {
        Error::settings(
            "set",
            format!("clearance joint \"{joint}\" has [joints.wear] but no length"),
        )
    })?;
    let bins = spec.wear.map_or(0, |w| w.bins);
    let mut dae = dae.clone();
    let t0 = dae.t0();
    let mut y = dae.initial_state();
    let mut t = t0;
    let mut profile = WearProfile::new(bins);
    let mut updates = vec![WearUpdate {
        index: 0,
        t: t0,
        turns: 0.0,
        eccentricity: dae.contact_state(k, &y).kinematics.distance,
        depth: profile.depths().to_vec(),
    }];
    let mut stats = SolverStats::default();
    let mut done = 0;
    while done < request.turns {
        let next = (done + request.update_every).min(request.turns);
        let t_end = t0 + next as f64 / turns_per_second;
        let mut sink = WearSink {
            joint: k,
            archard,
            accumulated: WearProfile::new(bins),
            last: y.clone(),
            y: vec![0.0; y.len()],
        };
        let interval = solve::integrate(
            &mut dae,
            t,
            &y,
            t_end,
            t_end - t,
            sim.solver_options(),
            &mut sink,
        )?;
        stats.add_run(&interval);
        profile.add(&sink.accumulated);
        dae.set_wear_profile(k, &profile)?;
        y = sink.last;
        t = t_end;
        done = next;
        updates.push(WearUpdate {
            index: updates.len(),
            t,
            turns: done as f64,
            eccentricity: dae.contact_state(k, &y).kinematics.distance,
            depth: profile.depths().to_vec(),
        });
    }
    let (max_depth, max_depth_angle) = profile.max();
    let worn_area = profile.worn_area(archard.bearing_radius);
    Ok(WearResult {
        joint: joint.to_string(),
        turns: request.turns,
        update_every: request.update_every,
        clearance: spec.clearance,
        archard,
        bin_centres: (0..bins).map(|i| profile.bin_centre(i)).collect(),
        updates,
        summary: WearSummary {
            max_depth,
            max_depth_angle,
            worn_area,
            worn_volume: worn_area * archard.length,
            mean_depth: worn_area / (TAU * archard.bearing_radius),
        },
        stats,
        provenance: sim.provenance(),
    })
}

/// The one clearance joint with a `[joints.wear]` table: its index among the revolute
/// clearance joints (the DAE's contact sites), its name and its data.
fn worn_joint(model: &Model) -> Result<(usize, &str, &crate::model::ClearanceSpec)> {
    let worn: Vec<_> = model
        .joints
        .iter()
        .filter_map(|j| match &j.kind {
            JointKind::Clearance(spec) => Some((j.name.as_str(), spec)),
            _ => None,
        })
        .enumerate()
        .filter(|(_, (_, spec))| spec.wear.is_some())
        .map(|(k, (name, spec))| (k, name, spec))
        .collect();
    match worn.as_slice() {
        [one] => Ok(*one),
        [] => Err(Error::settings(
            "set",
            "no clearance joint of the model has a [joints.wear] table; expected one, in the model file or e.g. with --set joints.J.wear.coefficient=1e-14 (m²/N) and --set joints.J.length=0.02 (m)",
        )),
        more => Err(Error::settings(
            "set",
            format!(
                "{} clearance joints have a [joints.wear] table ({}); expected exactly one",
                more.len(),
                more.iter().map(|w| w.1).collect::<Vec<_>>().join(", ")
            ),
        )),
    }
}

/// Gauss–Legendre nodes on [0, 1] and weights (summing to 1), three points.
const GAUSS: [(f64, f64); 3] = [
    (0.5 - 0.387_298_334_620_741_7, 5.0 / 18.0),
    (0.5, 8.0 / 18.0),
    (0.5 + 0.387_298_334_620_741_7, 5.0 / 18.0),
];

/// Accumulates one interval's wear step by step and keeps the last sample (the interval's end
/// state).
struct WearSink {
    joint: usize,
    archard: ArchardWear,
    accumulated: WearProfile,
    last: Vec<f64>,
    y: Vec<f64>,
}

impl Sink<Dae> for WearSink {
    fn sample(&mut self, _f: &Dae, _t: f64, y: &[f64]) -> std::result::Result<(), SolveError> {
        self.last.clear();
        self.last.extend_from_slice(y);
        Ok(())
    }

    fn on_step(&mut self, step: &mut DenseStep<'_, Dae>) -> std::result::Result<(), SolveError> {
        let (a, b) = step.range();
        let h = b - a;
        if h.is_nan() || h <= 0.0 {
            return Ok(());
        }
        let dae = step.formulation();
        let n = dae.n_coordinates();
        for (node, weight) in GAUSS {
            step.interpolate(a + node * h, &mut self.y)?;
            let s = dae.contact_state(self.joint, &self.y);
            if s.forces.normal_force <= 0.0 {
                continue;
            }
            let Some(theta) = dae
                .contacts()
                .contact_angle(self.joint, &self.y[..n], &s.kinematics)
            else {
                continue;
            };
            self.archard.deposit(
                &mut self.accumulated,
                theta,
                s.forces.normal_force,
                s.kinematics.tangential_velocity,
                weight * h,
            );
        }
        Ok(())
    }
}
