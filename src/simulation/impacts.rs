//! True contact peaks between the output samples, and the impact log's records.
//!
//! **Peaks.** For every accepted step during which a clearance joint is in contact, the
//! largest normal force F_N and the largest penetration δ inside the step are located on the
//! step's dense output ([`DenseStep`]), not read off the output samples: the state is
//! interpolated at [`PROBES`] + 1 equally spaced points of the step (ends included), then the
//! largest probe of each quantity is refined by golden-section search ([`maximise`]) on the
//! two probe intervals around it, to [`T_TOL`] of the step length h. Near a smooth maximum
//! F(t) ≈ F* − ½|F''|(t − t*)², so a time error of 1e-4·h costs ½|F''|(1e-4 h)²; for a contact
//! pulse F* sin(π t/T_c) with steps h ≤ T_c that is at most ½π²·1e-8 ≈ 5e-8 of F*: the peak is
//! as accurate as the dense output itself (≈ rtol = 1e-8 by default). The result is never
//! below the largest probe. A step whose probes show that it cannot beat the peak of its
//! contact so far (largest probe + |second difference| below it) is not refined: most steps
//! of a long contact cost the probes only.
//!
//! The contact quantities at an interpolated (t, y) come from [`ContactProbe`], which both
//! formulations implement with their contact kinematics alone (no acceleration solve for the
//! DAE). A model without clearance joints does no work at all (the hook returns at once).

use crate::formulation::{Dae, FormulationError, Generalized, ReducedLagrangian};
use crate::solve::{DenseStep, SolveError};
use serde::Serialize;

/// Interior probe intervals per step in contact (the step is sampled at PROBES + 1 points).
/// A contact pulse spans several steps, so within one step F_N and δ have at most one
/// interior maximum; 8 intervals separate it from a maximum at an end of the step.
pub const PROBES: usize = 8;

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

/// Formulations whose clearance joints can be read at any (t, y) without evaluating the whole
/// right-hand side: what the peak search evaluates at interpolated states.
pub trait ContactProbe {
    /// Clearance joint `k` (model order, the index of its δ event) at (t, y).
    fn contact_probe(&self, k: usize, t: f64, y: &[f64]) -> Result<ContactPoint, FormulationError>;
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
}

impl ContactProbe for Generalized {
    /// The DAE's probe at the state projected onto the constraints.
    fn contact_probe(&self, k: usize, t: f64, y: &[f64]) -> Result<ContactPoint, FormulationError> {
        let projected = self.project(t, y)?;
        self.dae().contact_probe(k, t, &projected)
    }
}

impl ContactProbe for ReducedLagrangian {
    /// From [`ReducedLagrangian::outputs`] (five states: the whole evaluation is a few dozen
    /// flops).
    fn contact_probe(
        &self,
        _k: usize,
        t: f64,
        y: &[f64],
    ) -> Result<ContactPoint, FormulationError> {
        let o = self.outputs(t, y)?;
        Ok(ContactPoint {
            delta: o.delta,
            delta_dot: o.delta_dot,
            normal_force: o.normal_force,
            impact_velocity: o.impact_velocity,
        })
    }
}

/// Finds the maximum of `f` on [lo, hi] by golden-section search, stopping when the bracket is
/// narrower than `t_tol`; returns (t, f(t)) of the best point evaluated (for a unimodal f, t is
/// within `t_tol` of the maximiser). Costs about log(( hi − lo)/t_tol)/log(φ) + 2 evaluations
/// (φ = 1.618…).
///
/// Errors: the first error of `f`.
pub fn maximise<E>(
    mut f: impl FnMut(f64) -> Result<f64, E>,
    lo: f64,
    hi: f64,
    t_tol: f64,
) -> Result<(f64, f64), E> {
    // 1/φ: each iteration keeps this fraction of the bracket and reuses one interior point.
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut a, mut b) = (lo.min(hi), lo.max(hi));
    let mut c = b - g * (b - a);
    let mut d = a + g * (b - a);
    let (mut fc, mut fd) = (f(c)?, f(d)?);
    let mut best = if fc >= fd { (c, fc) } else { (d, fd) };
    // The bracket shrinks geometrically; the cap only guards against a NaN width.
    for _ in 0..200 {
        if (b - a).partial_cmp(&t_tol) != Some(std::cmp::Ordering::Greater) {
            break;
        }
        if fc >= fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c)?;
            if fc > best.1 {
                best = (c, fc);
            }
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d)?;
            if fd > best.1 {
                best = (d, fd);
            }
        }
    }
    Ok(best)
}

/// The peaks of one joint inside one step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepPeak {
    /// Largest normal force (N) and its time (s).
    pub normal_force: (f64, f64),
    /// Largest penetration (m) and its time (s).
    pub delta: (f64, f64),
}

/// Reusable buffers of the peak search and its cost.
#[derive(Debug, Clone, Default)]
pub(crate) struct PeakSearch {
    y: Vec<f64>,
    probes: Vec<(f64, ContactPoint)>,
    /// Dense-output evaluations made by the search.
    pub(crate) interpolations: u64,
    /// Steps searched (per joint in contact).
    pub(crate) steps: u64,
}

impl PeakSearch {
    /// The peaks of joint `k` inside `step` (call only while the joint is in contact). `floor`
    /// holds the peaks (F_N, δ) of the contact so far: a quantity whose probes show that the
    /// step cannot exceed its floor is not refined (its largest probe is returned).
    pub(crate) fn step_peak<F: crate::formulation::Formulation + ContactProbe>(
        &mut self,
        step: &mut DenseStep<'_, F>,
        k: usize,
        floor: (f64, f64),
    ) -> Result<StepPeak, SolveError> {
        self.steps += 1;
        let (a, b) = step.range();
        let f = step.formulation();
        self.y.resize(step.n_states(), 0.0);
        let y = &mut self.y;
        let interpolations = &mut self.interpolations;
        let mut at = |t: f64| -> Result<ContactPoint, SolveError> {
            *interpolations += 1;
            step.interpolate(t, y)?;
            f.contact_probe(k, t, y)
                .map_err(|source| SolveError::Formulation { t, source })
        };
        self.probes.clear();
        for j in 0..=PROBES {
            // The last probe is b exactly (the stored end state where there is one).
            let t = if j == PROBES {
                b
            } else {
                a + (b - a) * j as f64 / PROBES as f64
            };
            self.probes.push((t, at(t)?));
        }
        let tol = T_TOL * (b - a);
        let mut refine =
            |value: fn(&ContactPoint) -> f64, floor: f64| -> Result<(f64, f64), SolveError> {
                let v = |j: usize| self.probes.get(j).map_or(f64::NAN, |p| value(&p.1));
                let mut i = 0;
                for j in 1..self.probes.len() {
                    if v(j) > v(i) {
                        i = j;
                    }
                }
                // PROBES + 1 ≥ 3 probes were pushed above, so index i exists.
                let (t_i, best) = (self.probes[i].0, v(i));
                // Between probes a smooth f rises above its best probe by at most ≈ |Δ²f|/8 (the
                // parabola through three probes); |Δ²f| itself (8× that) is the margin. A step
                // that cannot beat the contact's peak so far is not refined.
                let centre = i.clamp(1, PROBES - 1);
                let second = (v(centre - 1) - 2.0 * v(centre) + v(centre + 1)).abs();
                if best + second < floor {
                    return Ok((best, t_i));
                }
                let lo = self.probes.get(i.wrapping_sub(1)).map_or(a, |p| p.0);
                let hi = self.probes.get(i + 1).map_or(b, |p| p.0);
                let (t, r) = maximise(|t| at(t).map(|p| value(&p)), lo, hi, tol)?;
                Ok(if r > best { (r, t) } else { (best, t_i) })
            };
        let normal_force = refine(|p| p.normal_force, floor.0)?;
        let delta = refine(|p| p.delta, floor.1)?;
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

    #[test]
    fn golden_section_finds_the_maximum_of_a_known_function() {
        // f(t) = 3 − (t − 0.3)² on [0, 1]: maximum 3 at t = 0.3.
        let mut calls = 0;
        let r: Result<_, ()> = maximise(
            |t| {
                calls += 1;
                Ok(3.0 - (t - 0.3) * (t - 0.3))
            },
            0.0,
            1.0,
            1e-8,
        );
        let (t, v) = r.unwrap_or_default();
        // The bracket ends narrower than 1e-8, so |t − 0.3| < 1e-8 and f within 1e-16 of 3
        // (rounding of 3 − tiny: a few ulps).
        assert!((t - 0.3).abs() < 1e-8, "t = {t} vs 0.3");
        assert!((v - 3.0).abs() < 4.0 * f64::EPSILON * 3.0, "f = {v} vs 3");
        // log(1/1e-8)/log φ = 38.3 → 39 iterations + the 2 initial points.
        assert!(calls <= 41, "{calls} evaluations");

        // f(t) = t on [0, 1]: the maximum is at the bracket's end; the search closes in on it
        // and the best point is inside the last bracket, narrower than 1e-9.
        let r: Result<_, ()> = maximise(Ok, 0.0, 1.0, 1e-9);
        let (t, v) = r.unwrap_or_default();
        assert!(
            (t - 1.0).abs() < 1e-9 && t == v,
            "end maximum at t = {t}, f = {v}"
        );
    }

    #[test]
    fn golden_section_passes_the_first_error_on() {
        let r = maximise(|t| if t > 0.5 { Err(t) } else { Ok(t) }, 0.0, 1.0, 1e-6);
        assert!(matches!(r, Err(t) if t > 0.5), "{r:?}");
    }
}
