//! [`Variational`]: a formulation integrated together with its variational equations, so that
//! one integration gives the flow φ(t; t0, y0) and its sensitivity Φ(t) = ∂φ/∂y0.
//!
//! State: [y, vec Φ] with Φ row-major (n + n² components); Φ(t0) = I. Between events
//! Φ' = J(t, y) Φ with J the formulation's own [`Formulation::jacobian`] (analytic for the
//! reduced formulation). At every located event Φ is multiplied by the event's saltation
//! matrix ([`super::saltation`]) before the integration restarts.
//!
//! Φ is **not** under error control: the steps are those the state alone would take (the error
//! norm covers the formulation's own controlled states and divides by their number), so y here
//! is the plain integration of the formulation, bit for bit, and Φ rides on its steps. The
//! tests check Φ against finite differences of the flow at two tolerances.
//!
//! Every [`StepHooks`] method is forwarded to the wrapped formulation with the y part of the
//! state. A formulation that corrects y at step ends (a projection) would leave Φ without the
//! projection's derivative; the orbit analysis takes formulations that do not (module
//! documentation of [`super`]).

use std::cell::RefCell;

use super::saltation::{SaltationError, saltation_matrix};
use crate::formulation::{
    Crossing, EventResponse, Formulation, FormulationError, StepHooks, Tolerances,
};

/// A formulation and its variational equations as one system (module documentation).
#[derive(Debug, Clone)]
pub struct Variational<F> {
    inner: F,
    n: usize,
    /// Time scale of the motion (s), for the finite-difference steps in time of the
    /// saltation matrices (1/|ω| for a driven linkage).
    time_scale: f64,
    scratch: RefCell<Scratch>,
    /// The first event whose saltation matrix could not be formed (a grazing contact: the
    /// event function crosses zero with zero rate), kept for the caller: `apply_event` cannot
    /// fail.
    failure: Option<SaltationError>,
    /// Events whose saltation was applied, by (index, crossing), for the analysis's report.
    events: Vec<(f64, usize, Crossing)>,
    /// States that some event's saltation matrix cleared (a zero row: the event set them to a
    /// constant, as a separation clears the stored impact velocity).
    cleared: Vec<bool>,
}

#[derive(Debug, Clone)]
struct Scratch {
    jac: Vec<f64>,
    work: Vec<f64>,
}

impl<F: Formulation + Clone> Variational<F> {
    /// Wraps `inner`; `time_scale` (s, > 0) sets the finite-difference step in time of the
    /// saltation matrices.
    pub fn new(inner: F, time_scale: f64) -> Self {
        let n = inner.n_states();
        Variational {
            inner,
            n,
            time_scale,
            scratch: RefCell::new(Scratch {
                jac: vec![0.0; n * n],
                work: vec![0.0; 2 * n],
            }),
            failure: None,
            events: Vec::new(),
            cleared: vec![false; n],
        }
    }

    /// The augmented initial state [y0, vec I].
    pub fn augmented(&self, y0: &[f64]) -> Vec<f64> {
        let n = self.n;
        let mut y = vec![0.0; n + n * n];
        y[..n].copy_from_slice(y0);
        for i in 0..n {
            y[n + i * n + i] = 1.0;
        }
        y
    }

    /// The wrapped formulation.
    pub fn inner(&self) -> &F {
        &self.inner
    }

    /// The first saltation matrix that could not be formed, if any.
    pub fn failure(&self) -> Option<&SaltationError> {
        self.failure.as_ref()
    }

    /// The states that an event has cleared so far (see the field).
    pub fn cleared(&self) -> &[bool] {
        &self.cleared
    }

    /// The events met so far: (time, index, crossing).
    pub fn events(&self) -> &[(f64, usize, Crossing)] {
        &self.events
    }
}

impl<F: Formulation> StepHooks for Variational<F> {
    fn begin_step(&mut self, t: f64, y: &[f64]) {
        self.inner.begin_step(t, &y[..self.n]);
    }

    fn residual_stages(&mut self, min_pivot_ratio: f64) {
        self.inner.residual_stages(min_pivot_ratio);
    }

    fn accept_step(
        &mut self,
        t: f64,
        y: &mut [f64],
        tolerances: Tolerances,
    ) -> Result<EventResponse, FormulationError> {
        let n = self.n;
        self.inner.accept_step(t, &mut y[..n], tolerances)
    }
}

impl<F: Formulation + Clone> Formulation for Variational<F> {
    fn n_states(&self) -> usize {
        self.n + self.n * self.n
    }

    fn initial_state(&self) -> Vec<f64> {
        self.augmented(&self.inner.initial_state())
    }

    fn t0(&self) -> f64 {
        self.inner.t0()
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        let n = self.n;
        let (ys, phi) = y.split_at(n);
        let (dys, dphi) = dy.split_at_mut(n);
        self.inner.rhs(t, ys, dys)?;
        let mut scratch = self.scratch.borrow_mut();
        let Scratch { jac, work } = &mut *scratch;
        self.inner.jacobian(t, ys, dys, jac, work)?;
        // dΦ = J Φ, row-major: row i of dΦ is Σ_k J[i][k] · row k of Φ.
        dphi.fill(0.0);
        for i in 0..n {
            let out = &mut dphi[i * n..(i + 1) * n];
            for k in 0..n {
                let a = jac[i * n + k];
                if a != 0.0 {
                    for (o, p) in out.iter_mut().zip(&phi[k * n..(k + 1) * n]) {
                        *o += a * p;
                    }
                }
            }
        }
        Ok(())
    }

    fn n_events(&self) -> usize {
        self.inner.n_events()
    }

    fn events(&self, t: f64, y: &[f64], g: &mut [f64]) {
        self.inner.events(t, &y[..self.n], g);
    }

    /// Forms the event's saltation matrix S from the state just before, applies the event to
    /// the wrapped formulation, and maps Φ to S Φ.
    fn apply_event(
        &mut self,
        t: f64,
        y: &mut [f64],
        index: usize,
        crossing: Crossing,
    ) -> EventResponse {
        let n = self.n;
        let before = y[..n].to_vec();
        // The reset map is probed on copies taken before the event changes anything.
        let probe = self.inner.clone();
        let response = self.inner.apply_event(t, &mut y[..n], index, crossing);
        // Nothing changed in y and no restart: the vector field is the same on both sides
        // (a friction kink of a continuous law), S = I.
        if response == EventResponse::Continue && before[..] == y[..n] {
            return response;
        }
        self.events.push((t, index, crossing));
        match saltation_matrix(
            &probe,
            t,
            &before,
            &y[..n],
            index,
            crossing,
            self.time_scale,
        ) {
            Ok(s) => {
                for (i, c) in self.cleared.iter_mut().enumerate() {
                    *c |= s[i * n..(i + 1) * n].iter().all(|&v| v == 0.0);
                }
                let phi = &mut y[n..];
                let old = phi.to_vec();
                for i in 0..n {
                    for j in 0..n {
                        phi[i * n + j] = (0..n).map(|k| s[i * n + k] * old[k * n + j]).sum();
                    }
                }
            }
            Err(e) => {
                if self.failure.is_none() {
                    self.failure = Some(e);
                }
            }
        }
        // Φ changed: the integrator restarts from the new state.
        EventResponse::Restart
    }

    fn error_controlled(&self, controlled: &mut [bool]) {
        let (own, phi) = controlled.split_at_mut(self.n);
        self.inner.error_controlled(own);
        phi.fill(false);
    }

    fn max_step(&self, t: f64, y: &[f64]) -> f64 {
        self.inner.max_step(t, &y[..self.n])
    }

    fn diagnose(&self, t: f64, y: &[f64]) -> Option<String> {
        self.inner.diagnose(t, &y[..self.n])
    }
    // Left at their defaults on purpose: `jacobian` (finite differences of the augmented
    // system; the explicit pairs never ask for it), `sparse_jacobian` and `residual_form`
    // (none: implicit methods see the augmented system as a plain ODE), and
    // `second_order_positions` (0: [y, Φ] does not start with all positions).
}
