//! [`Radau5Core`]: one step attempt of Radau IIA from a state the caller owns — Jacobian and LU
//! bookkeeping, starting values, the simplified Newton iteration, the error estimate, the
//! step-size proposal and the dense output (RADAU5's `RADCOR`, `SLVRAD`, `ESTRAD`, `CONTR5`).
//!
//! The caller (the integrator trait's driver, through [`Radau5Method`](super::Radau5Method)) owns
//! (t, y), clamps h, counts accepted steps and retries recoverable RHS failures; the core keeps
//! f(t, y), the Jacobian, the LU factors, the step-size history and the last collocation
//! polynomial. An attempt changes that committed state only when it is accepted.

use super::newton::NewtonMatrices;
use super::settings::Radau5Settings;
use super::tableau::{C1, C1M1, C1MC2, C2, C2M1, DD, Eigen, T, TI};
use crate::formulation::Formulation;
use crate::solve::SolveError;
use crate::solve::integrator::{Attempt, Rejection};
use crate::solve::stats::SolverStats;
use crate::solve::step_cut::{crossed, cut_step, earliest_crossing};

/// Unit roundoff as RADAU5 uses it (`UROUND`).
const UROUND: f64 = 1e-16;

/// Error scale (relative and absolute) of the Newton norm in fixed-step mode.
const FIXED_SCALE: f64 = 1e-13;
/// Newton stopping tolerance in fixed-step mode, relative to [`FIXED_SCALE`]: the estimated
/// remaining error is below 1e-15·(1 + |y_i|).
const FIXED_NEWTON_TOL: f64 = 0.01;

/// Why the core rejected an attempt: the driver's causes, and a cut at an event crossing
/// (reported to the driver as an error-test failure).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Cause {
    /// One of the driver's causes.
    Driver(Rejection),
    /// An event function changed sign inside the step: the step is retried ending just past
    /// the crossing (see [`Radau5Core::event_cut`]).
    EventCut,
}

/// Tolerances and norms of the core.
#[derive(Debug, Clone)]
struct Norms {
    /// Tolerances in use (after Hairer's transform, if on).
    rtol: f64,
    atol: f64,
    /// Newton stopping tolerance κ·tol.
    newton_tol: f64,
    /// Error-controlled components.
    controlled: Vec<bool>,
    n_controlled: usize,
}

/// The state of the Radau IIA method between attempts (all buffers allocated once).
pub(super) struct Radau5Core {
    n: usize,
    settings: Radau5Settings,
    norms: Norms,
    h_max: f64,
    eig: Eigen,
    /// f(t, y) at the start of the next attempt.
    f0: Vec<f64>,
    scal: Vec<f64>,
    /// The Jacobian and the LU factors of the Newton matrices (dense or sparse).
    newton: NewtonMatrices,
    /// Whether the Jacobian was evaluated at the start of the next attempt, and whether that attempt
    /// must evaluate it.
    jac_current: bool,
    need_jac: bool,
    /// Step size of the LU factors (NaN: none valid).
    lu_h: f64,
    z: [Vec<f64>; 3],
    w: [Vec<f64>; 3],
    fs: [Vec<f64>; 3],
    y_stage: Vec<f64>,
    err_vec: Vec<f64>,
    err_rhs: Vec<f64>,
    /// End of the last attempt (the accepted state once accepted) and f there.
    y_new: Vec<f64>,
    f_new: Vec<f64>,
    /// f at the start of the last accepted step (the f0 it started from).
    f_acc_start: Vec<f64>,
    /// Last accepted step [t_acc − h_acc_step, t_acc] and its collocation polynomial.
    t_acc: f64,
    h_acc_step: f64,
    y_acc: Vec<f64>,
    cont: [Vec<f64>; 3],
    /// The collocation polynomial of the current attempt (same form as `cont`), for the
    /// event-crossing check before acceptance.
    cont_try: [Vec<f64>; 3],
    /// Event functions at the start and at the end of the attempt, and at a trial point.
    g_start: Vec<f64>,
    g_end: Vec<f64>,
    g_mid: Vec<f64>,
    /// The time whose state `g_start` holds g of (the start of the attempts since), and
    /// whether `g_end` holds g of the current attempt's end: the end of an accepted attempt
    /// is the start of the next one, so its g is not evaluated twice.
    g_start_at: Option<f64>,
    g_end_fresh: bool,
    /// Whether the current attempt is the retry of a step cut at an event crossing (it is
    /// not cut again).
    cut_retry: bool,
    /// Whether the last accepted step was such a retry and still ended before the crossing:
    /// the next attempt is not cut either (see [`Radau5Core::event_cut`]).
    cut_fell_short: bool,
    first: bool,
    reject: bool,
    faccon: f64,
    theta: f64,
    /// Gustafsson's memory: last accepted h and its error.
    h_acc: f64,
    err_acc: f64,
    accepted_since_start: u64,
}

impl Radau5Core {
    /// A core for the formulation `f` with tolerances `rtol`, `atol` (before Hairer's
    /// transform), largest step `h_max` and `settings` (validated by the caller), with the
    /// dense or the sparse LU as `settings.linear_solver` and `f` ask
    /// ([`LinearSolver`](super::LinearSolver)).
    pub(super) fn for_formulation<F: Formulation + ?Sized>(
        f: &F,
        rtol: f64,
        atol: f64,
        h_max: f64,
        settings: &Radau5Settings,
    ) -> Self {
        let n = f.n_states();
        let newton = NewtonMatrices::new(f, n, settings.linear_solver);
        Self::with_newton(n, rtol, atol, h_max, settings, newton)
    }

    fn with_newton(
        n: usize,
        rtol: f64,
        atol: f64,
        h_max: f64,
        settings: &Radau5Settings,
        newton: NewtonMatrices,
    ) -> Self {
        let (rtol, atol) = if settings.hairer_tolerances {
            crate::solve::options::hairer_transform(rtol, atol)
        } else {
            (rtol, atol)
        };
        let newton_tol = settings
            .newton_tol
            .unwrap_or_else(|| (10.0 * UROUND / rtol).max(0.03f64.min(rtol.sqrt())));
        let controlled = match &settings.error_mask {
            Some(mask) if mask.len() == n => mask.clone(),
            _ => vec![true; n],
        };
        let n_controlled = controlled.iter().filter(|&&c| c).count();
        let vec3 = || [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        Radau5Core {
            n,
            settings: settings.clone(),
            norms: Norms {
                rtol,
                atol,
                newton_tol,
                controlled,
                n_controlled,
            },
            h_max,
            eig: Eigen::new(),
            f0: vec![0.0; n],
            scal: vec![0.0; n],
            newton,
            jac_current: false,
            need_jac: true,
            lu_h: f64::NAN,
            z: vec3(),
            w: vec3(),
            fs: vec3(),
            y_stage: vec![0.0; n],
            err_vec: vec![0.0; n],
            err_rhs: vec![0.0; n],
            y_new: vec![0.0; n],
            f_new: vec![0.0; n],
            f_acc_start: vec![0.0; n],
            t_acc: f64::NAN,
            h_acc_step: 0.0,
            y_acc: vec![0.0; n],
            cont: vec3(),
            cont_try: vec3(),
            g_start: Vec::new(),
            g_end: Vec::new(),
            g_mid: Vec::new(),
            g_start_at: None,
            g_end_fresh: false,
            cut_retry: false,
            cut_fell_short: false,
            first: true,
            reject: false,
            faccon: 1.0,
            theta: settings.theta_jac.abs(),
            h_acc: 0.0,
            err_acc: 0.0,
            accepted_since_start: 0,
        }
    }

    /// (Re)starts with f0 = f(t, y) at the state of the next attempt: the Jacobian is stale,
    /// Newton starts from zero with its convergence estimate κ back at 1, the step-size history
    /// is forgotten. The dense output of the
    /// last accepted step is kept.
    pub(super) fn restart(&mut self, f0: &[f64]) {
        self.f0.copy_from_slice(f0);
        self.jac_current = false;
        self.need_jac = true;
        self.first = true;
        self.reject = false;
        self.cut_retry = false;
        self.cut_fell_short = false;
        self.accepted_since_start = 0;
        self.g_start_at = None;
        // RADAU5 starts with FACCON = 1. Kept from before the restart, a tiny κ (fast
        // contraction in free flight) lets the first Newton iteration from Z = 0 pass as
        // converged: on farahan2016 (reduced, rtol 1e-9) the first step into a contact then
        // had a true error of 3e-5 rad/s in θ̇3 (docs/numerics.md, "The reduced formulation meets
        // the target").
        self.faccon = 1.0;
    }

    /// Whether the Newton matrices are factored by the sparse LU (see
    /// [`LinearSolver`](super::LinearSolver)).
    #[must_use]
    pub(super) fn uses_sparse_lu(&self) -> bool {
        self.newton.is_sparse()
    }

    /// Structural non-zeros of one Newton matrix: k² with the dense LU (k = n − m), those of
    /// the augmented matrix with the sparse one.
    #[must_use]
    pub(super) fn newton_matrix_entries(&self) -> usize {
        self.newton.stored_entries()
    }

    /// The state at the end of the last attempt (meaningless after a rejection).
    #[must_use]
    pub(super) fn solution(&self) -> &[f64] {
        &self.y_new
    }

    /// f at the start and at the end of the last accepted step (exact RHS values: the end one
    /// is evaluated at the accepted state for the next step's error estimate).
    #[must_use]
    pub(super) fn accepted_slopes(&self) -> (&[f64], &[f64]) {
        (&self.f_acc_start, &self.f0)
    }

    /// Marks the attempt rejected with retry size `h_retry`.
    fn reject_with(&mut self, h_retry: f64, cause: Cause, stats: &mut SolverStats) -> Attempt {
        self.reject = true;
        // Hairer: re-use the Jacobian if it was evaluated at this point, else refresh it.
        self.need_jac = !self.jac_current;
        let cause = match cause {
            Cause::Driver(Rejection::NewtonFailure) => {
                stats.newton_failures += 1;
                Rejection::NewtonFailure
            }
            // A NaN estimate is counted as the explicit pairs count it.
            Cause::Driver(c @ (Rejection::ErrorTest | Rejection::NonFinite)) => {
                stats.error_test_failures += 1;
                c
            }
            Cause::EventCut => {
                stats.error_test_failures += 1;
                Rejection::ErrorTest
            }
        };
        Attempt::Rejected {
            h_next: h_retry,
            cause,
        }
    }

    /// Evaluates f, counted; on failure marks the attempt rejected (the caller decides whether
    /// a smaller step may avoid it) and passes the error on with its time.
    fn rhs<F: Formulation + ?Sized>(
        f: &F,
        t: f64,
        y: &[f64],
        out: &mut [f64],
        stats: &mut SolverStats,
    ) -> Result<(), SolveError> {
        stats.rhs_evals += 1;
        f.rhs(t, y, out)
            .map_err(|source| SolveError::Formulation { t, source })
    }

    /// One attempt from (t, y) — which must be the state the core was restarted at or its last
    /// accepted solution — with step size h to `t_new` (t + h, or exactly t_end on the last
    /// step). Without `error_control` (fixed-step mode) no error estimate is made.
    ///
    /// A failed RHS call is returned as `Err` (the attempt counts as rejected internally); the
    /// caller may retry recoverable failures with a smaller step.
    pub(super) fn attempt<F: Formulation + ?Sized>(
        &mut self,
        f: &F,
        (t, y): (f64, &[f64]),
        (h, t_new): (f64, f64),
        error_control: bool,
        stats: &mut SolverStats,
    ) -> Result<Attempt, SolveError> {
        let n = self.n;
        debug_assert_eq!(y.len(), n, "the driver's state has n components");
        // Fixed-step mode ignores rtol and atol (as the explicit pairs do): Newton is iterated
        // to ~1e-15 relative, with more iterations and without the early "too slow" exit,
        // since h must not change.
        let nit = self.settings.max_newton_iter;
        let (rtol, atol, newton_tol, nit, predict) = if error_control {
            let nm = &self.norms;
            (nm.rtol, nm.atol, nm.newton_tol, nit, true)
        } else {
            (FIXED_SCALE, FIXED_SCALE, FIXED_NEWTON_TOL, 3 * nit, false)
        };
        for (s, &v) in self.scal.iter_mut().zip(y) {
            *s = atol + rtol * v.abs();
        }
        self.g_end_fresh = false;
        if self.need_jac && !self.jac_current {
            let calls = self
                .newton
                .evaluate(f, t, y, &self.f0)
                .map_err(|source| SolveError::Formulation { t, source })?;
            stats.jacobian_evals += 1;
            stats.jacobian_rhs_evals += calls as u64;
            stats.rhs_evals += calls as u64;
            self.jac_current = true;
            self.lu_h = f64::NAN;
        }
        self.need_jac = false;
        let (fac1, alphn, betan) = (self.eig.gamma / h, self.eig.alpha / h, self.eig.beta / h);
        if self.lu_h != h {
            stats.lu_decompositions += 1;
            if self.newton.factor(fac1, alphn, betan).is_err() {
                self.lu_h = f64::NAN;
                return Ok(self.reject_with(
                    0.5 * h,
                    Cause::Driver(Rejection::NewtonFailure),
                    stats,
                ));
            }
            self.lu_h = h;
        }
        self.starting_values(h);

        // Simplified Newton iteration.
        self.faccon = self.faccon.max(UROUND).powf(0.8);
        self.theta = self.settings.theta_jac.abs();
        let (mut dyno_old, mut thq_old) = (0.0, 0.0);
        let mut newt = 0;
        loop {
            if newt >= nit {
                return Ok(self.reject_with(
                    0.5 * h,
                    Cause::Driver(Rejection::NewtonFailure),
                    stats,
                ));
            }
            for (i, c) in [C1, C2, 1.0].into_iter().enumerate() {
                for k in 0..n {
                    self.y_stage[k] = y[k] + self.z[i][k];
                }
                let tc = if i == 2 { t_new } else { t + c * h };
                if let Err(e) = Self::rhs(f, tc, &self.y_stage, &mut self.fs[i], stats) {
                    self.reject = true;
                    self.need_jac = !self.jac_current;
                    return Err(e);
                }
            }
            // Right-hand sides of the transformed systems (SLVRAD), then the two solves.
            for k in 0..n {
                let (a1, a2, a3) = (self.fs[0][k], self.fs[1][k], self.fs[2][k]);
                let (w1, w2, w3) = (self.w[0][k], self.w[1][k], self.w[2][k]);
                self.fs[0][k] = TI[0][0] * a1 + TI[0][1] * a2 + TI[0][2] * a3 - fac1 * w1;
                self.fs[1][k] =
                    TI[1][0] * a1 + TI[1][1] * a2 + TI[1][2] * a3 - alphn * w2 + betan * w3;
                self.fs[2][k] =
                    TI[2][0] * a1 + TI[2][1] * a2 + TI[2][2] * a3 - alphn * w3 - betan * w2;
            }
            self.newton.solve_real(&mut self.fs[0]);
            let [_, f2, f3] = &mut self.fs;
            self.newton.solve_complex(f2, f3);
            newt += 1;
            stats.newton_iterations += 1;
            let dyno = {
                let sq = |v: &[f64]| self.scaled_rms(v).powi(2);
                ((sq(&self.fs[0]) + sq(&self.fs[1]) + sq(&self.fs[2])) / 3.0).sqrt()
            };
            if !dyno.is_finite() {
                // Show the driver where: the last stage value with the correction applied.
                for k in 0..n {
                    self.y_new[k] = y[k] + self.z[2][k] + self.fs[2][k];
                }
                return Ok(self.reject_with(0.5 * h, Cause::Driver(Rejection::NonFinite), stats));
            }
            if newt > 1 && newt < nit {
                let thq = dyno / dyno_old;
                self.theta = if newt == 2 {
                    thq
                } else {
                    (thq * thq_old).sqrt()
                };
                thq_old = thq;
                if self.theta >= 0.99 {
                    return Ok(self.reject_with(
                        0.5 * h,
                        Cause::Driver(Rejection::NewtonFailure),
                        stats,
                    ));
                }
                self.faccon = self.theta / (1.0 - self.theta);
                let left = (nit - 1 - newt) as i32;
                let dyth = self.faccon * dyno * self.theta.powi(left) / newton_tol;
                if predict && dyth >= 1.0 {
                    // Convergence predicted too slow: retry with a step that should make it.
                    let qnewt = dyth.clamp(1e-4, 20.0);
                    let hhfac = 0.8 * qnewt.powf(-1.0 / (4.0 + f64::from(left)));
                    return Ok(self.reject_with(
                        hhfac * h,
                        Cause::Driver(Rejection::NewtonFailure),
                        stats,
                    ));
                }
            }
            dyno_old = dyno.max(UROUND);
            for k in 0..n {
                let w1 = self.w[0][k] + self.fs[0][k];
                let w2 = self.w[1][k] + self.fs[1][k];
                let w3 = self.w[2][k] + self.fs[2][k];
                self.w[0][k] = w1;
                self.w[1][k] = w2;
                self.w[2][k] = w3;
                self.z[0][k] = T[0][0] * w1 + T[0][1] * w2 + T[0][2] * w3;
                self.z[1][k] = T[1][0] * w1 + T[1][1] * w2 + T[1][2] * w3;
                self.z[2][k] = T[2][0] * w1 + w2;
            }
            if self.faccon * dyno <= newton_tol {
                break;
            }
        }

        for k in 0..n {
            self.y_new[k] = y[k] + self.z[2][k];
        }
        let err = if error_control {
            self.error_estimate(f, t, y, h, stats)?
        } else {
            0.0
        };
        // An otherwise acceptable step across an event crossing is cut there first.
        if err < 1.0
            && error_control
            && self.settings.cut_at_events
            && !self.cut_retry
            && !self.cut_fell_short
            && let Some(h_cut) = self.event_cut(f, (t, y), (h, t_new))
        {
            self.cut_retry = true;
            return Ok(self.reject_with(h_cut, Cause::EventCut, stats));
        }
        let s = &self.settings;
        let cfac = s.safety * (1.0 + 2.0 * nit as f64);
        let fac = s.safety.min(cfac / (newt + 2 * nit) as f64);
        // quot = h/h_new ∈ [1/hi, 1/lo].
        let (lo, hi) = s.h_ratio_range;
        let mut quot = (err.powf(0.25) / fac).clamp(1.0 / hi, 1.0 / lo);
        if err >= 1.0 {
            let retry = if self.first { 0.1 * h } else { h / quot };
            return Ok(self.reject_with(retry, Cause::Driver(Rejection::ErrorTest), stats));
        }

        // Accepted, once f at the new point is known (the next attempt's f(t, y)).
        if let Err(e) = Self::rhs(f, t_new, &self.y_new, &mut self.f_new, stats) {
            self.reject = true;
            self.need_jac = !self.jac_current;
            return Err(e);
        }
        if s.predictive && self.accepted_since_start > 0 {
            // Gustafsson's predictive controller.
            let facgus = (self.h_acc / h) * (err * err / self.err_acc).powf(0.25) / s.safety;
            quot = quot.max(facgus.clamp(1.0 / hi, 1.0 / lo));
        }
        self.h_acc = h;
        self.err_acc = err.max(1e-2);
        let mut h_new = (h / quot).min(self.h_max);
        if self.reject {
            h_new = h_new.min(h);
        }
        let qt = h_new / h;
        let (q1, q2) = s.keep_h_range;
        let theta_small = self.theta <= s.theta_jac;
        let h_next = if theta_small && qt >= q1 && qt <= q2 {
            h
        } else {
            h_new
        };
        // A cut retry whose end is still before the crossing (the retry's solution moved the
        // crossing by more than the 0.1 % overshoot): the next attempt would be cut again near
        // its start, and so on, h → 0 (seen as v_t slides onto a friction kink). Let the next
        // attempt cross instead.
        let fell_short = self.cut_retry && !self.crosses(f, (t, y), t_new);
        self.commit(t_new, h);
        self.cut_fell_short = fell_short;
        self.need_jac = !theta_small;
        Ok(Attempt::Accepted { h_next })
    }

    /// The step size that ends the attempt just past the earliest sign change of an event
    /// function inside it, or `None` if no event function changes sign between (t, y) and
    /// (t_new, y_new) (or the crossing is already at the step's end).
    ///
    /// Why: the collocation polynomial is one polynomial over the whole step. When the
    /// right-hand side changes its law inside the step (a contact opens or closes), the stages
    /// after the change pull the polynomial before it off by far more than the error estimate
    /// says, and the driver takes the state at the located event from that polynomial. On
    /// farahan2016 (reduced, rtol 1e-10) one such step, across the 8th impact, had a true
    /// local error of 370× the tolerance with an accepted estimate, and every later impact
    /// came 0.2–2 µs late (docs/numerics.md). Ending the step just past the crossing leaves
    /// only a sliver [t_event, t_new] under the other law, and the driver still finds the
    /// event inside the step.
    fn event_cut<F: Formulation + ?Sized>(
        &mut self,
        f: &F,
        (t, y): (f64, &[f64]),
        (h, t_new): (f64, f64),
    ) -> Option<f64> {
        let ne = f.n_events();
        if !self.crosses(f, (t, y), t_new) {
            return None;
        }
        polynomial_of(&self.z, &mut self.cont_try);
        // Earliest crossing: bisection on s ∈ [−1, 0] (s = (τ − t_new)/h) over all the
        // components that change sign, 40 halvings (2⁻⁴⁰·h). The driver's Illinois finder to
        // the same resolution was tried here: its cut points differ from these by less than
        // 2⁻⁴⁰, and that alone moved the reduced four-bar's error at 250 rpm, rtol 1e-8 from
        // 8.2e-9 to 2.4e-8 rad (docs/benchmarks.md, "Radau5").
        let hi = earliest_crossing((-1.0, 0.0), |mid| {
            for k in 0..self.n {
                self.y_stage[k] = y[k] + self.z[2][k] + self.poly_offset(k, mid);
            }
            f.events(t_new + mid * h, &self.y_stage, &mut self.g_mid);
            (0..ne).any(|i| crossed(self.g_start[i], self.g_mid[i]))
        });
        let theta = 1.0 + hi;
        // Past the crossing by 0.1 % of the way to it (the retry's own crossing moves by its
        // error). A crossing in the last 1 % of the step is left as it is, and so is one in
        // the first 1 %: the old law then holds only on a sliver at the start, where the
        // polynomial is pinned to y_n, and the cut would be a step of θ·h — down to a few ulps
        // of t when a step ends just short of a kink (farahan2016 reduced at 3500 rpm,
        // c = 0.4955 mm: θ = 3e-6, a cut to 2.1e-14 s, after which the controller proposed
        // 6.6e-15 s, below the driver's floor; docs/numerics.md, "Radau5 at events").
        cut_step(t, h, theta)
    }

    /// Whether an event function changes sign between (t, y) and the attempt's end
    /// (t_new, y + Z₃); leaves the values in `g_start` and `g_end`.
    fn crosses<F: Formulation + ?Sized>(
        &mut self,
        f: &F,
        (t, y): (f64, &[f64]),
        t_new: f64,
    ) -> bool {
        let ne = f.n_events();
        if ne == 0 {
            return false;
        }
        for g in [&mut self.g_start, &mut self.g_end, &mut self.g_mid] {
            g.resize(ne, 0.0);
        }
        // Event functions depend on (t, y) only, and (t, y) is the last accepted end unless
        // the driver restarted the core (which forgets `g_start_at`).
        if self.g_start_at != Some(t) {
            f.events(t, y, &mut self.g_start);
            self.g_start_at = Some(t);
        }
        for k in 0..self.n {
            self.y_stage[k] = y[k] + self.z[2][k];
        }
        f.events(t_new, &self.y_stage, &mut self.g_end);
        self.g_end_fresh = true;
        (0..ne).any(|i| crossed(self.g_start[i], self.g_end[i]))
    }

    /// The polynomial of the current attempt at s = (τ − t_new)/h, minus its end value.
    fn poly_offset(&self, k: usize, s: f64) -> f64 {
        let [c1, c2, c3] = &self.cont_try;
        s * (c1[k] + (s - C2M1) * (c2[k] + (s - C1M1) * c3[k]))
    }

    /// Starting values of Z and W: the last collocation polynomial extrapolated to the new
    /// nodes, or zero on the first step after the start or a restart.
    fn starting_values(&mut self, h: f64) {
        if self.first {
            for v in self.z.iter_mut().chain(self.w.iter_mut()) {
                v.fill(0.0);
            }
            return;
        }
        let c3q = h / self.h_acc_step;
        let cq = [C1 * c3q, C2 * c3q, c3q];
        for k in 0..self.n {
            let (a1, a2, a3) = (self.cont[0][k], self.cont[1][k], self.cont[2][k]);
            let mut zk = [0.0; 3];
            for (i, &c) in cq.iter().enumerate() {
                zk[i] = c * (a1 + (c - C2M1) * (a2 + (c - C1M1) * a3));
                self.z[i][k] = zk[i];
            }
            for i in 0..3 {
                self.w[i][k] = TI[i][0] * zk[0] + TI[i][1] * zk[1] + TI[i][2] * zk[2];
            }
        }
    }

    /// Hairer's error estimate (ESTRAD), with the second filtering on the first step and after
    /// a rejection. Returns max(‖err‖, 10⁻¹⁰).
    fn error_estimate<F: Formulation + ?Sized>(
        &mut self,
        f: &F,
        t: f64,
        y: &[f64],
        h: f64,
        stats: &mut SolverStats,
    ) -> Result<f64, SolveError> {
        let hee = [DD[0] / h, DD[1] / h, DD[2] / h];
        for k in 0..self.n {
            let f2 = hee[0] * self.z[0][k] + hee[1] * self.z[1][k] + hee[2] * self.z[2][k];
            self.err_rhs[k] = f2;
            self.err_vec[k] = f2 + self.f0[k];
        }
        self.newton.solve_real(&mut self.err_vec);
        let mut err = self.scaled_rms(&self.err_vec).max(1e-10);
        if err >= 1.0 && (self.first || self.reject) {
            for k in 0..self.n {
                self.y_stage[k] = y[k] + self.err_vec[k];
            }
            stats.rhs_evals += 1;
            match f.rhs(t, &self.y_stage, &mut self.fs[1]) {
                Ok(()) => {
                    for k in 0..self.n {
                        self.err_vec[k] = self.fs[1][k] + self.err_rhs[k];
                    }
                    self.newton.solve_real(&mut self.err_vec);
                    err = self.scaled_rms(&self.err_vec).max(1e-10);
                }
                // The filtered state is only a probe: if it overshoots into a contact, keep the
                // first estimate (≥ 1, so the step is rejected anyway).
                Err(source) if source.is_recoverable() => {}
                Err(source) => return Err(SolveError::Formulation { t, source }),
            }
        }
        Ok(err)
    }

    /// Commits an accepted step of size h ending at t_new (state in `y_new`, f in `f_new`):
    /// builds the dense output.
    fn commit(&mut self, t_new: f64, h: f64) {
        self.t_acc = t_new;
        self.h_acc_step = h;
        self.y_acc.copy_from_slice(&self.y_new);
        if self.g_end_fresh {
            std::mem::swap(&mut self.g_start, &mut self.g_end);
            self.g_start_at = Some(t_new);
        } else {
            self.g_start_at = None;
        }
        self.f_acc_start.copy_from_slice(&self.f0);
        self.f0.copy_from_slice(&self.f_new);
        polynomial_of(&self.z, &mut self.cont);
        self.first = false;
        self.cut_retry = false;
        self.reject = false;
        self.jac_current = false;
        self.accepted_since_start += 1;
    }

    /// The dense output of the last accepted step at t (the caller checks that t lies in the
    /// step): the cubic collocation polynomial u with u(t_acc) = y_acc.
    pub(super) fn interpolate(&self, t: f64, out: &mut [f64]) {
        if self.h_acc_step == 0.0 {
            out.copy_from_slice(&self.y_acc);
            return;
        }
        let s = (t - self.t_acc) / self.h_acc_step;
        let [c1, c2, c3] = &self.cont;
        for (k, o) in out.iter_mut().enumerate() {
            *o = self.y_acc[k] + s * (c1[k] + (s - C2M1) * (c2[k] + (s - C1M1) * c3[k]));
        }
    }

    /// Root-mean-square of v_i / scal_i over the error-controlled components; a zero scale
    /// counts a zero entry as 0 and any other as infinitely large.
    fn scaled_rms(&self, v: &[f64]) -> f64 {
        let mut sum = 0.0;
        for ((&x, &s), &c) in v.iter().zip(&self.scal).zip(&self.norms.controlled) {
            if c {
                let q = if s > 0.0 {
                    x / s
                } else if x == 0.0 {
                    0.0
                } else {
                    f64::INFINITY
                };
                sum += q * q;
            }
        }
        (sum / self.norms.n_controlled.max(1) as f64).sqrt()
    }
}

/// Coefficients of the collocation polynomial through the stage increments z (CONTR5's
/// form): u(t_new + s·h) = y_new + s·(c₁ + (s − c₂ + 1)·(c₂' + (s − c₁ + 1)·c₃')).
fn polynomial_of(z: &[Vec<f64>; 3], cont: &mut [Vec<f64>; 3]) {
    let [o1, o2, o3] = cont;
    for (k, ((c1o, c2o), c3o)) in o1
        .iter_mut()
        .zip(o2.iter_mut())
        .zip(o3.iter_mut())
        .enumerate()
    {
        let (z1, z2, z3) = (z[0][k], z[1][k], z[2][k]);
        let c1 = (z2 - z3) / C2M1;
        let ak = (z1 - z2) / C1MC2;
        let acont3 = (ak - z1 / C1) / C2;
        let c2 = (ak - c1) / C1M1;
        *c1o = c1;
        *c2o = c2;
        *c3o = c2 - acont3;
    }
}
