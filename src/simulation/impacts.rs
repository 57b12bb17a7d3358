//! True contact peaks between the output samples, and the impact log's records.
//!
//! **Peaks.** For every accepted step during which a clearance joint is in contact, the
//! largest normal force F_N and the largest penetration δ inside the step are found from the
//! step's ends and, where a maximum lies inside the step, on its dense output ([`DenseStep`]):
//!
//! 1. At both ends of the step the joint's δ, δ̇, δ̈, F_N and dF_N/dt are evaluated from the
//!    state and its time derivative ([`ContactProbe::contact_motion`]): the contact kinematics
//!    and the law alone, with the derivative the method already holds (the explicit pairs' first
//!    and FSAL stages, Radau5's f at its step ends). The end of one step is the start of the
//!    next, so a step in contact costs one such evaluation — no interpolation, no equations of
//!    motion, and DOP853's lazy dense-output stages stay unevaluated.
//! 2. A quantity whose rate falls from positive at the start to negative at the end has a
//!    maximum inside the step. Unless the cubic Hermite polynomial through the two ends' values
//!    and rates shows that this maximum cannot reach the contact's peak so far (with its own
//!    excursion above the ends as the margin), the maximum is located by golden-section search
//!    ([`maximise`]) on the dense output over the step, to [`T_TOL`] of the step length h.
//!    Near a smooth maximum F(t) ≈ F* − ½|F''|(t − t*)², so a time error of 1e-4·h costs
//!    ½|F''|(1e-4 h)²; for a contact pulse F* sin(π t/T_c) with steps h ≤ T_c that is at most
//!    ½π²·1e-8 ≈ 5e-8 of F*: the peak is as accurate as the dense output itself.
//! 3. Otherwise the larger end value is the step's peak.
//!
//! This assumes that a step holds at most one maximum of each quantity: the error control
//! resolves the contact's motion (a contact pulse spans several steps), and the rates at both
//! ends catch any single interior maximum wherever it lies. The unit test
//! `impact_peaks_equal_a_dense_scan_of_every_step` (`src/simulation/tests.rs`) checks the peaks
//! against a dense scan of every step on the reference cases.
//!
//! Cost (instruction counts, farahan2016, 2 turns, `docs/benchmarks.md`): 1.5–6.3 % of a run
//! with DOP853 or Radau5 on either formulation, against 49 % for the search it replaced (9
//! interpolated states per step in contact, each through the whole equations of motion).
//!
//! A model without clearance joints does no work at all (the hook returns at once).

use crate::formulation::{Dae, FormulationError, Generalized, ReducedLagrangian};
use crate::solve::maximise::maximise;
use crate::solve::{DenseStep, SolveError};
use serde::Serialize;

/// Golden-section stopping width, relative to the step length (see the module docs).
pub const T_TOL: f64 = 1e-4;

/// The contact quantities of one clearance joint at a state (t, y).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPoint {
    /// Penetration δ = |e| − c (m; negative while free).
    pub delta: f64,
    /// Penetration rate δ̇ (m/s; positive while the journal moves into the bearing wall).
    pub delta_dot: f64,
    /// Normal force F_N ≥ 0 (N; 0 while free).
    pub normal_force: f64,
    /// The impact velocity δ̇⁽⁻⁾ stored in the state (m/s; 0 when no impact is recorded).
    pub impact_velocity: f64,
}

/// A [`ContactPoint`] with the rates that locate its maxima in time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactMotion {
    /// The contact quantities.
    pub point: ContactPoint,
    /// Penetration acceleration δ̈ (m/s²).
    pub delta_ddot: f64,
    /// dF_N/dt (N/s; 0 while free).
    pub normal_force_rate: f64,
}

/// Formulations whose clearance joints can be read at any (t, y) without evaluating the whole
/// right-hand side: what the peak search evaluates at step ends and interpolated states.
pub trait ContactProbe {
    /// Clearance joint `k` (model order, the index of its δ event) at (t, y).
    fn contact_probe(&self, k: usize, t: f64, y: &[f64]) -> Result<ContactPoint, FormulationError>;

    /// Clearance joint `k` at (t, y) with its rates, for the time derivative `y_dot` = f(t, y)
    /// of the state.
    fn contact_motion(
        &self,
        k: usize,
        t: f64,
        y: &[f64],
        y_dot: &[f64],
    ) -> Result<ContactMotion, FormulationError>;
}

/// The error for a contact site index past the model's sites (a caller's bug, reported rather
/// than a panic).
fn no_site(k: usize) -> FormulationError {
    FormulationError::Unsupported {
        formulation: "DAE".into(),
        reason: format!("no contact site {k}"),
    }
}

/// The [`ContactMotion`] of a joint from its kinematics and forces, the relative acceleration
/// of its centres and its stored impact velocity.
fn motion_of(
    joint: &crate::contact::ClearanceJoint,
    kinematics: &crate::contact::ContactKinematics,
    normal_force: f64,
    e_ddot: [f64; 2],
    stored: f64,
) -> ContactMotion {
    let (delta_ddot, normal_force_rate) = joint.normal_force_rate(kinematics, e_ddot, stored);
    ContactMotion {
        point: ContactPoint {
            delta: kinematics.delta,
            delta_dot: kinematics.delta_dot,
            normal_force,
            impact_velocity: stored,
        },
        delta_ddot,
        normal_force_rate,
    }
}

impl ContactProbe for Dae {
    /// From [`Dae::contact_state`]: the joint's kinematics and contact law only.
    fn contact_probe(
        &self,
        k: usize,
        _t: f64,
        y: &[f64],
    ) -> Result<ContactPoint, FormulationError> {
        let s = self.contact_state(k, y);
        // The stored δ̇⁽⁻⁾ of joint k follows q and q̇ (see `Dae::n_states`).
        let stored = y
            .get(2 * self.n_coordinates() + k)
            .copied()
            .unwrap_or(f64::NAN);
        Ok(ContactPoint {
            delta: s.kinematics.delta,
            delta_dot: s.kinematics.delta_dot,
            normal_force: s.forces.normal_force,
            impact_velocity: stored,
        })
    }

    /// From [`Dae::contact_motion_state`], with q̈ from `y_dot`.
    fn contact_motion(
        &self,
        k: usize,
        _t: f64,
        y: &[f64],
        y_dot: &[f64],
    ) -> Result<ContactMotion, FormulationError> {
        let (s, e_ddot, stored) = self.contact_motion_state(k, y, y_dot);
        let joint = self.contacts().contact_model(k).ok_or_else(|| no_site(k))?;
        Ok(motion_of(
            joint,
            &s.kinematics,
            s.forces.normal_force,
            e_ddot,
            stored,
        ))
    }
}

impl ContactProbe for Generalized {
    /// The DAE's probe at the state projected onto the constraints.
    fn contact_probe(&self, k: usize, t: f64, y: &[f64]) -> Result<ContactPoint, FormulationError> {
        let projected = self.project(t, y)?;
        self.dae().contact_probe(k, t, &projected)
    }

    /// The DAE's motion at the projected state ([`Generalized::contact_motion_state`]).
    fn contact_motion(
        &self,
        k: usize,
        t: f64,
        y: &[f64],
        y_dot: &[f64],
    ) -> Result<ContactMotion, FormulationError> {
        let (s, e_ddot, stored) = self.contact_motion_state(k, t, y, y_dot)?;
        let joint = self
            .dae()
            .contacts()
            .contact_model(k)
            .ok_or_else(|| no_site(k))?;
        Ok(motion_of(
            joint,
            &s.kinematics,
            s.forces.normal_force,
            e_ddot,
            stored,
        ))
    }
}

impl ContactProbe for ReducedLagrangian {
    /// From the link kinematics and the contact law ([`ReducedLagrangian::contact_at`]).
    fn contact_probe(
        &self,
        _k: usize,
        t: f64,
        y: &[f64],
    ) -> Result<ContactPoint, FormulationError> {
        let (kin, forces, stored) = self.contact_at(t, y);
        Ok(ContactPoint {
            delta: kin.delta,
            delta_dot: kin.delta_dot,
            normal_force: forces.normal_force,
            impact_velocity: stored,
        })
    }

    /// From [`ReducedLagrangian::contact_motion_at`], with θ̈3, θ̈4 from `y_dot`.
    fn contact_motion(
        &self,
        _k: usize,
        t: f64,
        y: &[f64],
        y_dot: &[f64],
    ) -> Result<ContactMotion, FormulationError> {
        let (kin, forces, stored, e_ddot) = self.contact_motion_at(t, y, y_dot);
        Ok(motion_of(
            self.clearance_joint(),
            &kin,
            forces.normal_force,
            e_ddot,
            stored,
        ))
    }
}

/// The largest value on θ ∈ [0, 1] of the cubic Hermite polynomial with values `v0`, `v1` and
/// derivatives (with respect to θ) `d0`, `d1` at the ends.
fn hermite_max(v0: f64, v1: f64, d0: f64, d1: f64) -> f64 {
    // p(θ) = v0 + d0 θ + a θ² + b θ³ with p(1) = v1, p'(1) = d1.
    let b = d0 + d1 - 2.0 * (v1 - v0);
    let a = 3.0 * (v1 - v0) - 2.0 * d0 - d1;
    let p = |x: f64| v0 + x * (d0 + x * (a + x * b));
    // Roots of p'(θ) = d0 + 2a θ + 3b θ² inside (0, 1).
    let mut best = v0.max(v1);
    let mut consider = |x: f64| {
        if x > 0.0 && x < 1.0 {
            best = best.max(p(x));
        }
    };
    if b.abs() < 1e-12 * (a.abs() + d0.abs()) {
        if a != 0.0 {
            consider(-d0 / (2.0 * a));
        }
    } else {
        let disc = a * a - 3.0 * b * d0;
        if disc >= 0.0 {
            let r = disc.sqrt();
            consider((-a + r) / (3.0 * b));
            consider((-a - r) / (3.0 * b));
        }
    }
    best
}

/// The peaks of one joint inside one step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepPeak {
    /// Largest normal force (N) and its time (s).
    pub normal_force: (f64, f64),
    /// Largest penetration (m) and its time (s).
    pub delta: (f64, f64),
}

/// A joint's [`ContactMotion`] at a step end, kept for the next step while it starts there.
#[derive(Debug, Clone, Copy)]
struct KnownEnd {
    t: f64,
    motion: ContactMotion,
}

/// The two ends of the step being searched, shared by the joints.
#[derive(Debug, Clone, Default)]
struct StepEnds {
    y_start: Vec<f64>,
    slope_start: Vec<f64>,
    start_ready: bool,
    y_end: Vec<f64>,
    slope_end: Vec<f64>,
    end_ready: bool,
}

/// Reusable buffers of the peak search and its cost.
#[derive(Debug, Clone, Default)]
pub(crate) struct PeakSearch {
    y: Vec<f64>,
    ends: StepEnds,
    /// Per joint: its motion at the end of the last step searched, until an event changes the
    /// state there.
    known: Vec<Option<KnownEnd>>,
    /// Dense-output evaluations made by the search.
    pub(crate) interpolations: u64,
    /// RHS calls made by the search for the slope at a step end the method does not hold (a
    /// step cut at an event; also counted in the run's `rhs_evals`).
    pub(crate) rhs_evals: u64,
    /// Steps searched (per joint in contact).
    pub(crate) steps: u64,
    /// Steps whose interior was searched on the dense output (per joint and quantity).
    pub(crate) refinements: u64,
}

impl PeakSearch {
    /// Forgets the step ends seen so far: an event may have changed the state there (the
    /// stored impact velocity at an impact).
    pub(crate) fn forget_ends(&mut self) {
        self.known.iter_mut().for_each(|k| *k = None);
    }

    /// Starts the search of a new step (its end states are evaluated on first use).
    pub(crate) fn begin_step(&mut self) {
        self.ends.start_ready = false;
        self.ends.end_ready = false;
    }

    /// The peaks of joint `k` inside `step` (call only while the joint is in contact, after
    /// [`PeakSearch::begin_step`] for this step). `floor` holds the peaks (F_N, δ) of the
    /// contact so far: a maximum that cannot exceed its floor is not located.
    pub(crate) fn step_peak<F: crate::formulation::Formulation + ContactProbe>(
        &mut self,
        step: &mut DenseStep<'_, F>,
        k: usize,
        floor: (f64, f64),
    ) -> Result<StepPeak, SolveError> {
        self.steps += 1;
        let (a, b) = step.range();
        let f = step.formulation();
        let n = step.n_states();
        if self.known.len() <= k {
            self.known.resize(k + 1, None);
        }
        let motion_err = |t: f64| move |source| SolveError::Formulation { t, source };
        let start = match self.known[k] {
            Some(known) if known.t == a => known.motion,
            _ => {
                let e = &mut self.ends;
                if !e.start_ready {
                    e.y_start.resize(n, 0.0);
                    e.slope_start.resize(n, 0.0);
                    step.interpolate(a, &mut e.y_start)?;
                    self.rhs_evals += u64::from(step.start_slope(&mut e.slope_start)?);
                    e.start_ready = true;
                }
                f.contact_motion(k, a, &e.y_start, &e.slope_start)
                    .map_err(motion_err(a))?
            }
        };
        let e = &mut self.ends;
        if !e.end_ready {
            e.y_end.resize(n, 0.0);
            e.slope_end.resize(n, 0.0);
            self.rhs_evals += u64::from(step.end_state_and_slope(&mut e.y_end, &mut e.slope_end)?);
            e.end_ready = true;
        }
        let end = f
            .contact_motion(k, b, &e.y_end, &e.slope_end)
            .map_err(motion_err(b))?;
        self.known[k] = Some(KnownEnd { t: b, motion: end });

        self.y.resize(n, 0.0);
        let y = &mut self.y;
        let interpolations = &mut self.interpolations;
        let refinements = &mut self.refinements;
        let h = b - a;
        let mut peak_of = |value: fn(&ContactPoint) -> f64,
                           rate: fn(&ContactMotion) -> f64,
                           floor: f64|
         -> Result<(f64, f64), SolveError> {
            let (va, vb) = (value(&start.point), value(&end.point));
            let ends = if vb >= va { (vb, b) } else { (va, a) };
            let (ra, rb) = (rate(&start), rate(&end));
            if !(ra > 0.0 && rb < 0.0 && h > 0.0) {
                return Ok(ends);
            }
            // The cubic through both ends estimates the interior maximum; twice its excursion
            // above the ends is the margin for the polynomial's own error.
            let estimate = hermite_max(va, vb, ra * h, rb * h);
            if estimate + (estimate - ends.0) < floor {
                return Ok(ends);
            }
            *refinements += 1;
            let mut at = |t: f64| -> Result<f64, SolveError> {
                *interpolations += 1;
                step.interpolate(t, y)?;
                f.contact_probe(k, t, y)
                    .map(|p| value(&p))
                    .map_err(|source| SolveError::Formulation { t, source })
            };
            let (t, v) = maximise(&mut at, a, b, T_TOL * h)?;
            Ok(if v > ends.0 { (v, t) } else { ends })
        };
        let normal_force = peak_of(|p| p.normal_force, |m| m.normal_force_rate, floor.0)?;
        let delta = peak_of(|p| p.delta, |m| m.point.delta_dot, floor.1)?;
        Ok(StepPeak {
            normal_force,
            delta,
        })
    }
}

/// One impact of a clearance joint: the onset of a contact (δ rising through 0, a located
/// event) and what the contact did until the next separation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Impact {
    /// 1 for the joint's first impact, 2 for the next, …
    pub index: usize,
    /// Impact time (s): the located event.
    pub t: f64,
    /// The driver's angle at t, θ0 + ω t (rad, continuous, not wrapped); `null` unless the
    /// model has exactly one driver.
    pub driver_angle: Option<f64>,
    /// Impact velocity δ̇⁽⁻⁾ (m/s, > 0: the journal moving into the bearing wall), as stored in
    /// the state at the event and used by the contact law for the whole contact.
    pub impact_velocity: f64,
    /// Largest normal force between this impact and the next separation (N), located on the
    /// dense output.
    pub peak_normal_force: f64,
    /// Largest penetration δ between this impact and the next separation (m), located on the
    /// dense output.
    pub peak_penetration: f64,
    /// Separation time − impact time (s); `null` while the contact is still open at the end of
    /// the run.
    pub duration: Option<f64>,
    /// The contact is still open at the end of the run.
    pub open: bool,
}

impl Impact {
    /// Whether a step starting at `a` (s) lies in this contact: at or after the impact and
    /// before its separation (a step cut at the separation starts before it).
    pub(crate) fn covers(&self, a: f64) -> bool {
        self.t <= a && self.duration.is_none_or(|d| a < self.t + d)
    }
}

/// A clearance joint in permanent contact: its last contact began at `since` and lasted to the
/// end of the run, at least [`PermanentContact::min_duration`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PermanentContact {
    /// Time of the impact that started it (s).
    pub since: f64,
    /// Its index in the joint's impact log (1-based).
    pub impact_index: usize,
    /// The driver's angle at `since` (rad; `null` unless the model has exactly one driver).
    pub driver_angle: Option<f64>,
    /// How long it has lasted at the end of the run (s).
    pub duration: f64,
    /// The least duration that counts as permanent (s): one driver turn 2π/|ω|, or without a
    /// single turning driver 20 % of the run.
    pub min_duration: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Hermite bound: the parabola θ(1 − θ) (max 1/4 at θ = 1/2), a cubic with its
    /// maximum off-centre, and monotone data whose maximum is an end value.
    #[test]
    fn hermite_maximum_of_known_polynomials() {
        assert!((hermite_max(0.0, 0.0, 1.0, -1.0) - 0.25).abs() < 1e-15);
        // p(θ) = 2θ − θ²: p(1) = 1, p'(0) = 2, p'(1) = 0; its maximum is the end value.
        assert!((hermite_max(0.0, 1.0, 2.0, 0.0) - 1.0).abs() < 1e-15);
        // p(θ) = θ − θ³ on [0, 1]: max 2/(3√3) at θ = 1/√3; p(1) = 0, p'(0) = 1, p'(1) = −2.
        let want = 2.0 / (3.0 * 3f64.sqrt());
        assert!((hermite_max(0.0, 0.0, 1.0, -2.0) - want).abs() < 1e-15);
        assert_eq!(hermite_max(1.0, 2.0, 1.0, 1.0), 2.0);
    }
}
