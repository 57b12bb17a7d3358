//! Events: sign changes of the formulation's event functions g_i(t, y), located on the dense
//! output and handed to [`Formulation::apply_event`].
//!
//! **Detection.** Each event function has a reference sign s_i ∈ {−1, 0, +1}: the side of zero
//! it is on. After each accepted step g is evaluated at the step end; a component with
//! s_i·g_i(t_new) ≤ 0 has crossed (reaching zero counts as crossing). Only crossings seen at step
//! ends are found: a g_i that leaves its side and comes back within one step is missed, which
//! is why formulations bound the step with [`Formulation::max_step`].
//!
//! **Location.** The root of φ(t) = s_i·g_i(t, y(t)), y(t) the dense output, is bracketed with
//! the Illinois variant of regula falsi \[1\] (with a bisection step whenever three iterations in
//! a row fail to halve the bracket) until the bracket is no wider than
//! `event_tol`·max(1, |t|). The reported time is the bracket's right end, the first point known
//! to be past the crossing (as in CVODE's root finding \[2\]). Among all components the earliest
//! root is taken; components that are past their crossing at that same time are reported next,
//! at the same time, in index order.
//!
//! **Crossing direction.** s_i = +1 → [`Crossing::Falling`], s_i = −1 → [`Crossing::Rising`].
//!
//! **After an event (the zero-at-start rule).** A restarted integration starts on the root,
//! where g_i ≈ 0 with either sign (the bracket is ~`event_tol` wide). To avoid reporting the
//! same root again, the reference sign of every component that fired at the restart time, and
//! of every component that is exactly zero there, is taken from a look-ahead: g at
//! t + δ, y + δ·f(t, y) (an explicit Euler step, no extra RHS call), with
//! δ = 100·`event_tol`·max(1, |t|). In the following step such a component is bracketed from
//! t + δ if its value at t is not yet on its reference side. A component whose look-ahead is
//! still exactly zero is inactive until it is non-zero at a step end, where it takes that sign
//! without an event. With [`EventResponse::Continue`] the fired component's reference sign
//! simply flips (the state is unchanged), so the rest of the step is scanned for its next
//! crossing.
//!
//! # References
//! 1. M. Dowell, P. Jarratt, "A modified regula falsi method for computing the root of an
//!    equation", *BIT* 11, 168–174, 1971.
//! 2. A. C. Hindmarsh et al., "SUNDIALS: Suite of nonlinear and differential/algebraic equation
//!    solvers", *ACM Trans. Math. Softw.* 31(3), 363–396, 2005 (CVODE root finding).
//! 3. L. F. Shampine, I. Gladwell, R. W. Brankin, "Reliable solution of special event location
//!    problems for ODEs", *ACM Trans. Math. Softw.* 17(1), 11–25, 1991.

use serde::Serialize;

use super::error::SolveError;
use super::rk::{eval_rhs, first_non_finite};
use super::stepper::{Stepper, Stop};
use crate::formulation::{Crossing, EventResponse, Formulation};

/// A located event.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EventRecord {
    /// Event time (s), within `event_tol`·max(1, |t|) after the true root.
    pub t: f64,
    /// Index of the event function that changed sign.
    pub index: usize,
    /// Direction of the sign change.
    pub crossing: Crossing,
    /// Whether the formulation answered [`EventResponse::Restart`].
    pub restarted: bool,
}

/// Largest number of root-finding iterations (with the bisection safeguard about
/// 4·log2(h/tol) ≤ 250 are ever needed).
const MAX_ITERATIONS: usize = 500;
/// Look-ahead offset in units of the event tolerance.
const LOOKAHEAD_TOLS: f64 = 100.0;

/// Event bookkeeping of a [`Stepper`] (all vectors allocated once).
pub(super) struct EventState {
    /// Reference sign s_i of each event function.
    refs: Vec<i8>,
    /// Reference sign set by look-ahead or by a flip at an event, not yet confirmed at a step end.
    fresh: Vec<bool>,
    /// Fired at the current event time.
    fired: Vec<bool>,
    /// g at `t_lo`, the start of the part of the step still to scan.
    pub(super) g_lo: Vec<f64>,
    /// g at the end of the last step.
    pub(super) g_hi: Vec<f64>,
    /// g at the current bracket end.
    g_b: Vec<f64>,
    g_tmp: Vec<f64>,
    y_tmp: Vec<f64>,
    /// States before and after `apply_event` at the last event.
    pub(super) y_before: Vec<f64>,
    pub(super) y_after: Vec<f64>,
    t_lo: f64,
    /// `t_lo` is an event time (then `y_after` is the state there).
    lo_is_event: bool,
    /// An event at `t_lo` asked for a restart, done once all events at `t_lo` are reported.
    pub(super) pending_restart: bool,
    pub(super) last: Option<EventRecord>,
}

impl EventState {
    /// Buffers for n states and `ne` event functions, starting at t0.
    pub(super) fn new(n: usize, ne: usize, t0: f64) -> Self {
        Self {
            refs: vec![0; ne],
            fresh: vec![false; ne],
            fired: vec![false; ne],
            g_lo: vec![0.0; ne],
            g_hi: vec![0.0; ne],
            g_b: vec![0.0; ne],
            g_tmp: vec![0.0; ne],
            y_tmp: vec![0.0; n],
            y_before: vec![0.0; n],
            y_after: vec![0.0; n],
            t_lo: t0,
            lo_is_event: false,
            pending_restart: false,
            last: None,
        }
    }
}

/// Which event buffer receives a dense-output state.
#[derive(Debug, Clone, Copy)]
enum DenseBuffer {
    /// `y_tmp`, for event-function values.
    Scratch,
    /// `y_before`, the state at the event.
    BeforeEvent,
}

/// Sign of x as −1, 0 or +1 (NaN counts as 0: the component is inactive).
fn sign(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// A bracket [a, b] with φ(a) > 0 ≥ φ(b).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Bracket {
    /// Left end (s).
    pub a: f64,
    /// φ(a) > 0.
    pub phi_a: f64,
    /// Right end (s).
    pub b: f64,
    /// φ(b) ≤ 0.
    pub phi_b: f64,
}

/// Illinois root finder: shrinks the bracket until b − a ≤ tol and returns b, the first point
/// known to be past the root. `index` only labels the error.
pub(crate) fn illinois(
    bracket: Bracket,
    tol: f64,
    index: usize,
    mut phi: impl FnMut(f64) -> Result<f64, SolveError>,
) -> Result<f64, SolveError> {
    let Bracket {
        mut a,
        mut phi_a,
        mut b,
        mut phi_b,
    } = bracket;
    debug_assert!(a < b && phi_a > 0.0 && phi_b <= 0.0, "not a bracket");
    if phi_b == 0.0 {
        return Ok(b);
    }
    let mut side = 0i8;
    let mut width_ref = b - a;
    let mut stalled = 0;
    let mut iterations = 0;
    while b - a > tol {
        iterations += 1;
        if iterations > MAX_ITERATIONS {
            return Err(SolveError::EventNotConverged {
                t: b,
                index,
                iterations,
            });
        }
        let mut c = if stalled >= 3 {
            0.5 * (a + b)
        } else {
            b - phi_b * (b - a) / (phi_b - phi_a)
        };
        if !c.is_finite() {
            c = 0.5 * (a + b);
        }
        // Keep c at least tol/2 inside, so that each iteration shrinks the bracket by that much.
        let margin = 0.5 * tol;
        c = c.clamp(a + margin, b - margin);
        if c <= a || c >= b {
            break; // no representable point left inside
        }
        let phi_c = phi(c)?;
        if phi_c > 0.0 {
            a = c;
            phi_a = phi_c;
            if side == 1 {
                phi_b *= 0.5;
            }
            side = 1;
        } else {
            b = c;
            phi_b = phi_c;
            if side == -1 {
                phi_a *= 0.5;
            }
            side = -1;
            if phi_c == 0.0 {
                break;
            }
        }
        if b - a <= 0.5 * width_ref {
            width_ref = b - a;
            stalled = 0;
        } else {
            stalled += 1;
        }
    }
    Ok(b)
}

impl<F: Formulation> Stepper<'_, F> {
    /// Look-ahead offset δ at time t.
    fn lookahead_offset(&self, t: f64) -> f64 {
        LOOKAHEAD_TOLS * self.opts.event_tol * t.abs().max(1.0)
    }

    /// g_i on the dense output at time t (the whole vector lands in `g_tmp`).
    fn event_value(&mut self, t: f64, i: usize) -> Result<f64, SolveError> {
        self.event_vector(t)?;
        Ok(self.ev.g_tmp.get(i).copied().unwrap_or(0.0))
    }

    /// The method's dense output at t into `buffer` (`y_tmp` or `y_before`), through the
    /// [`Integrator`](super::integrator::Integrator) trait only.
    fn dense_into(&mut self, t: f64, buffer: DenseBuffer) -> Result<(), SolveError> {
        let slot = match buffer {
            DenseBuffer::Scratch => &mut self.ev.y_tmp,
            DenseBuffer::BeforeEvent => &mut self.ev.y_before,
        };
        // Taking the vector out (no allocation) lets the driver borrow itself mutably.
        let mut out = std::mem::take(slot);
        let result = self.dense_raw(t, &mut out);
        match buffer {
            DenseBuffer::Scratch => self.ev.y_tmp = out,
            DenseBuffer::BeforeEvent => self.ev.y_before = out,
        }
        result
    }

    /// g on the dense output at time t into `g_tmp`.
    fn event_vector(&mut self, t: f64) -> Result<(), SolveError> {
        self.dense_into(t, DenseBuffer::Scratch)?;
        self.f.events(t, &self.ev.y_tmp, &mut self.ev.g_tmp);
        Ok(())
    }

    /// Evaluates g at the initial point and sets the reference signs.
    pub(super) fn init_events(&mut self) {
        if self.ev.refs.is_empty() {
            return;
        }
        self.f.events(self.t, &self.y, &mut self.ev.g_lo);
        self.set_reference_signs();
    }

    /// Reference signs at a (re)start (t, y) with g(t, y) in `g_lo` and f(t, y) in `dy`: the
    /// sign of g, or of the look-ahead for components that just fired or are exactly zero.
    fn set_reference_signs(&mut self) {
        let ev = &mut self.ev;
        let needs_lookahead = ev
            .fired
            .iter()
            .zip(&ev.g_lo)
            .any(|(&fired, &g)| fired || g == 0.0);
        if needs_lookahead {
            let delta = LOOKAHEAD_TOLS * self.opts.event_tol * self.t.abs().max(1.0);
            for ((yt, &y), &dy) in ev.y_tmp.iter_mut().zip(&self.y).zip(&self.dy) {
                *yt = y + delta * dy;
            }
            self.f.events(self.t + delta, &ev.y_tmp, &mut ev.g_tmp);
        }
        for i in 0..ev.refs.len() {
            if ev.fired[i] || ev.g_lo[i] == 0.0 {
                ev.refs[i] = sign(ev.g_tmp[i]);
                ev.fresh[i] = true;
            } else {
                ev.refs[i] = sign(ev.g_lo[i]);
                ev.fresh[i] = false;
            }
        }
        ev.fired.fill(false);
        ev.t_lo = self.t;
        ev.lo_is_event = false;
    }

    /// After a step is accepted: g at its end, scanning starts at its beginning.
    pub(super) fn begin_scan(&mut self) {
        if self.ev.refs.is_empty() {
            return;
        }
        // The method's values at its solution are this step end's unless the formulation
        // corrected the step end (which then asks for a restart).
        match self.integrator.step_end_events() {
            Some(g) if !self.restart_before_next_step && g.len() == self.ev.g_hi.len() => {
                self.ev.g_hi.copy_from_slice(g);
            }
            _ => self.f.events(self.t, &self.y, &mut self.ev.g_hi),
        }
        self.ev.t_lo = self.t_old;
        self.ev.lo_is_event = false;
    }

    /// After a step holds no more events: confirm the reference signs at its end.
    pub(super) fn finish_events(&mut self) {
        let ev = &mut self.ev;
        for i in 0..ev.refs.len() {
            if ev.refs[i] == 0 || ev.fresh[i] {
                ev.refs[i] = sign(ev.g_hi[i]);
            }
            ev.fresh[i] = false;
        }
        ev.g_lo.copy_from_slice(&ev.g_hi);
        ev.fired.fill(false);
        ev.t_lo = self.t;
        ev.lo_is_event = false;
    }

    /// Finds the earliest event in (t_lo, dense_end] of the current step, hands it to the
    /// formulation and returns the stop; `None` if there is none.
    pub(super) fn scan_events(&mut self) -> Result<Option<Stop>, SolveError> {
        let ne = self.ev.refs.len();
        if ne == 0 {
            return Ok(None);
        }
        let t_lo = self.ev.t_lo;
        let t_hi = self.dense_end;
        // Components already past their crossing at t_lo: simultaneous with the last event.
        let mut found = (0..ne).find(|&i| {
            let r = f64::from(self.ev.refs[i]);
            r != 0.0 && !self.ev.fresh[i] && r * self.ev.g_lo[i] <= 0.0
        });
        let mut t_ev = t_lo;
        if found.is_none() && t_hi > t_lo {
            self.ev.g_b.copy_from_slice(&self.ev.g_hi);
            let mut hi = t_hi;
            for i in 0..ne {
                let r = f64::from(self.ev.refs[i]);
                if r == 0.0 || r * self.ev.g_b[i] > 0.0 {
                    continue;
                }
                let phi_lo = r * self.ev.g_lo[i];
                let (a, phi_a) = if phi_lo > 0.0 {
                    (t_lo, phi_lo)
                } else {
                    // A fresh reference sign not yet reached at t_lo: bracket from t_lo + δ.
                    let ta = t_lo + self.lookahead_offset(t_lo);
                    if ta >= hi {
                        continue;
                    }
                    let pa = r * self.event_value(ta, i)?;
                    if pa <= 0.0 {
                        continue;
                    }
                    (ta, pa)
                };
                let tol = self.opts.event_tol * hi.abs().max(1.0);
                let bracket = Bracket {
                    a,
                    phi_a,
                    b: hi,
                    phi_b: r * self.ev.g_b[i],
                };
                let b = illinois(bracket, tol, i, |t| Ok(r * self.event_value(t, i)?))?;
                if b < hi {
                    hi = b;
                    self.event_vector(b)?;
                    self.ev.g_b.copy_from_slice(&self.ev.g_tmp);
                }
                found = Some(i);
            }
            t_ev = hi;
        }
        let Some(index) = found else {
            return Ok(None);
        };
        self.handle_event(index, t_ev)
    }

    /// Hands the event of component `index` at `t_ev` to the formulation.
    fn handle_event(&mut self, index: usize, t_ev: f64) -> Result<Option<Stop>, SolveError> {
        let t_lo = self.ev.t_lo;
        if self.ev.lo_is_event && t_ev == t_lo {
            self.ev.y_before.copy_from_slice(&self.ev.y_after);
        } else {
            self.dense_into(t_ev, DenseBuffer::BeforeEvent)?;
            if t_ev != t_lo {
                // g at t_ev (pre-event) becomes the start of the rest of the scan.
                self.ev.g_lo.copy_from_slice(&self.ev.g_b);
            }
        }
        let r = self.ev.refs.get(index).copied().unwrap_or(0);
        let crossing = if r > 0 {
            Crossing::Falling
        } else {
            Crossing::Rising
        };
        self.ev.y_after.copy_from_slice(&self.ev.y_before);
        let response = self
            .f
            .apply_event(t_ev, &mut self.ev.y_after, index, crossing);
        let restarted = response == EventResponse::Restart;
        if !restarted {
            self.ev.y_after.copy_from_slice(&self.ev.y_before);
        }
        self.stats.events += 1;
        self.ev.last = Some(EventRecord {
            t: t_ev,
            index,
            crossing,
            restarted,
        });
        if let (Some(s), Some(fresh), Some(fired)) = (
            self.ev.refs.get_mut(index),
            self.ev.fresh.get_mut(index),
            self.ev.fired.get_mut(index),
        ) {
            *s = -*s;
            *fresh = true;
            *fired = true;
        }
        self.ev.t_lo = t_ev;
        self.ev.lo_is_event = true;
        if restarted {
            // The rest of the step is void: cut it at the event and move to the new state.
            self.ev.pending_restart = true;
            self.dense_end = t_ev;
            self.step_final = true;
            self.t = t_ev;
            self.y.copy_from_slice(&self.ev.y_after);
            self.y_is_step_end = false;
        }
        self.t_reached = t_ev;
        Ok(Some(Stop::Event { t: t_ev, index }))
    }

    /// Restarts the method at the event time from the state after the event(s): f(t, y) handed
    /// to [`Integrator::restart`](super::integrator::Integrator::restart) (which clears the
    /// method's history), new reference signs; the next step size is the method's last
    /// proposal, bounded by `h_max` (and, at the step, by `max_step`).
    pub(super) fn restart(&mut self) -> Result<(), SolveError> {
        let t = self.t;
        if let Some(component) = first_non_finite(&self.y) {
            return Err(SolveError::NonFinite { t, component });
        }
        eval_rhs(
            &*self.f,
            t,
            &self.y,
            &mut self.dy,
            &mut self.stats.rhs_evals,
        )?;
        self.f.events(t, &self.y, &mut self.ev.g_lo);
        self.set_reference_signs();
        self.ev.pending_restart = false;
        self.restart_before_next_step = false;
        self.integrator.restart(t, &self.y, &self.dy);
        self.stats.restarts += 1;
        self.h_next = self.h_next.min(self.opts.h_max);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn root_of(phi: impl Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> (f64, usize) {
        let mut calls = 0;
        let bracket = Bracket {
            a,
            phi_a: phi(a),
            b,
            phi_b: phi(b),
        };
        let r = illinois(bracket, tol, 0, |t| {
            calls += 1;
            Ok(phi(t))
        });
        (r.unwrap_or(f64::NAN), calls)
    }

    #[test]
    fn illinois_brackets_to_tolerance_from_the_right() {
        // φ = 2 − t², root √2.
        let (r, calls) = root_of(|t| 2.0 - t * t, 0.0, 3.0, 1e-12);
        assert!(r >= 2f64.sqrt() && r - 2f64.sqrt() <= 1e-12, "{r}");
        assert!(calls < 40, "{calls} calls");
    }

    #[test]
    fn illinois_survives_flat_and_steep_functions() {
        // Very asymmetric: regula falsi alone would crawl; Illinois + bisection do not.
        let (r, calls) = root_of(
            |t| (1.0 - t).powi(9).signum() * (1.0 - t).abs().powi(9),
            0.0,
            1.7,
            1e-12,
        );
        assert!((r - 1.0).abs() <= 1e-12, "{r}");
        assert!(calls < 250, "{calls} calls");
        let (r, _) = root_of(|t| if t < 0.3 { 1.0 } else { -1.0 }, 0.0, 1.0, 1e-12);
        assert!((0.3..=0.3 + 1e-12).contains(&r), "{r}");
    }

    #[test]
    fn sign_treats_nan_as_zero() {
        assert_eq!(
            (sign(2.0), sign(-0.5), sign(0.0), sign(f64::NAN)),
            (1, -1, 0, 0)
        );
    }
}
