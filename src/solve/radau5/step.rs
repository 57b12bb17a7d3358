//! One step of [`Radau5`]: Jacobian and LU bookkeeping, starting values, the simplified Newton
//! iteration, the error estimate and the step-size decision (RADAU5's `RADCOR`, `SLVRAD`,
//! `ESTRAD`).

use super::tableau::{C1, C1M1, C1MC2, C2, C2M1, DD, T, TI};
use super::{Radau5, UROUND, is_recoverable};
use crate::formulation::Formulation;
use crate::solve::SolveError;

/// Outcome of one step attempt.
enum Attempt {
    /// Accepted; (t, y) advanced.
    Accepted,
    /// Rejected; `h_next` holds the step size to retry with.
    Rejected,
    /// Rejected because the RHS failed recoverably (kept to report if h cannot shrink).
    Recoverable(SolveError),
}

impl Radau5 {
    /// Takes one accepted step (retrying rejected attempts with smaller steps). Returns
    /// `Ok(false)` without doing anything if t_end is already reached.
    pub fn step<F: Formulation + ?Sized>(&mut self, f: &F) -> Result<bool, SolveError> {
        let t = self.t;
        if t >= self.t_end {
            return Ok(false);
        }
        let floor = 16.0 * f64::EPSILON * t.abs().max(self.t_end.abs());
        let remaining = self.t_end - t;
        if remaining <= floor {
            // A restart left t a few ulps short of t_end: the state there is the end state.
            self.t_old = t;
            self.h_old = 0.0;
            self.y_old.copy_from_slice(&self.y);
            self.t = self.t_end;
            self.dense_end = self.t_end;
            return Ok(true);
        }
        let cap = {
            let value = f.max_step(t, &self.y);
            if value.is_nan() || value <= 0.0 {
                return Err(SolveError::InvalidMaxStep { t, value });
            }
            value.min(self.opts.h_max)
        };
        let mut recoverable: Option<SolveError> = None;
        loop {
            let attempts = self.stats.steps + self.stats.rejected;
            if attempts >= self.opts.max_steps {
                return Err(SolveError::TooManySteps { t, steps: attempts });
            }
            let mut h = self.h_next.min(cap);
            if remaining <= 1.01 * h && remaining <= cap {
                h = remaining;
            }
            if !(h >= floor && h > 0.0) {
                return Err(recoverable.unwrap_or(SolveError::StepTooSmall { t, h }));
            }
            match self.attempt(f, h)? {
                Attempt::Accepted => return Ok(true),
                Attempt::Rejected => {}
                Attempt::Recoverable(e) => recoverable = Some(e),
            }
        }
    }

    /// Marks an attempt of size h as rejected with retry size `h_retry`.
    fn reject_with(&mut self, h_retry: f64) {
        self.stats.rejected += 1;
        self.reject = true;
        self.h_next = h_retry;
        // Hairer: re-use the Jacobian if it was evaluated at this point, else refresh it.
        self.need_jac = !self.jac_current;
    }

    /// One attempt with step size h.
    fn attempt<F: Formulation + ?Sized>(&mut self, f: &F, h: f64) -> Result<Attempt, SolveError> {
        let (t, n) = (self.t, self.n);
        if self.need_jac && !self.jac_current {
            let calls = f
                .jacobian(t, &self.y, &self.f0, &mut self.jac, &mut self.jac_work)
                .map_err(|source| SolveError::Formulation { t, source })?;
            self.stats.jacobian_evals += 1;
            self.stats.jacobian_rhs_evals += calls as u64;
            self.stats.rhs_evals += calls as u64;
            self.jac_current = true;
            self.lu_h = f64::NAN;
        }
        self.need_jac = false;
        let (fac1, alphn, betan) = (self.eig.gamma / h, self.eig.alpha / h, self.eig.beta / h);
        if self.lu_h != h {
            let ok = self.e1.factor(fac1, &self.jac).is_ok()
                && self.e2.factor(alphn, betan, &self.jac).is_ok();
            self.stats.lu_decompositions += 1;
            if !ok {
                self.lu_h = f64::NAN;
                self.stats.singular_matrices += 1;
                self.reject_with(0.5 * h);
                return Ok(Attempt::Rejected);
            }
            self.lu_h = h;
        }
        self.starting_values(h);

        // Simplified Newton iteration.
        let nit = self.settings.max_newton_iter;
        self.faccon = self.faccon.max(UROUND).powf(0.8);
        self.theta = self.settings.theta_jac.abs();
        let (mut dyno_old, mut thq_old) = (0.0, 0.0);
        let mut newt = 0;
        loop {
            if newt >= nit {
                self.stats.newton_failures += 1;
                self.reject_with(0.5 * h);
                return Ok(Attempt::Rejected);
            }
            for (i, c) in [C1, C2, 1.0].into_iter().enumerate() {
                for k in 0..n {
                    self.y_stage[k] = self.y[k] + self.z[i][k];
                }
                let tc = t + c * h;
                self.stats.rhs_evals += 1;
                if let Err(source) = f.rhs(tc, &self.y_stage, &mut self.fs[i]) {
                    let e = SolveError::Formulation { t: tc, source };
                    if is_recoverable(&e) && self.opts.fixed_step.is_none() {
                        self.stats.recovered_rejections += 1;
                        self.reject_with(0.25 * h);
                        return Ok(Attempt::Recoverable(e));
                    }
                    return Err(e);
                }
            }
            // Right-hand sides of the transformed systems (SLVRAD), then the solves.
            for k in 0..n {
                let (a1, a2, a3) = (self.fs[0][k], self.fs[1][k], self.fs[2][k]);
                let (w1, w2, w3) = (self.w[0][k], self.w[1][k], self.w[2][k]);
                self.fs[0][k] = TI[0][0] * a1 + TI[0][1] * a2 + TI[0][2] * a3 - fac1 * w1;
                self.fs[1][k] =
                    TI[1][0] * a1 + TI[1][1] * a2 + TI[1][2] * a3 - alphn * w2 + betan * w3;
                self.fs[2][k] =
                    TI[2][0] * a1 + TI[2][1] * a2 + TI[2][2] * a3 - alphn * w3 - betan * w2;
            }
            self.e1.solve(&mut self.fs[0]);
            let [_, f2, f3] = &mut self.fs;
            self.e2.solve(f2, f3);
            newt += 1;
            self.stats.newton_iterations += 1;
            let dyno = {
                let sq = |v: &[f64]| self.scaled_rms(v).powi(2);
                ((sq(&self.fs[0]) + sq(&self.fs[1]) + sq(&self.fs[2])) / 3.0).sqrt()
            };
            if !dyno.is_finite() {
                self.stats.newton_failures += 1;
                self.reject_with(0.5 * h);
                return Ok(Attempt::Rejected);
            }
            if newt > 1 && newt < nit {
                let thq = dyno / dyno_old;
                self.theta = if newt == 2 {
                    thq
                } else {
                    (thq * thq_old).sqrt()
                };
                thq_old = thq;
                if self.theta < 0.99 {
                    self.faccon = self.theta / (1.0 - self.theta);
                    let left = (nit - 1 - newt) as i32;
                    let dyth = self.faccon * dyno * self.theta.powi(left) / self.newton_tol;
                    if dyth >= 1.0 {
                        // Convergence predicted too slow: retry with a step that should make it.
                        let qnewt = dyth.clamp(1e-4, 20.0);
                        let hhfac = 0.8 * qnewt.powf(-1.0 / (4.0 + f64::from(left)));
                        self.stats.newton_failures += 1;
                        self.reject_with(hhfac * h);
                        return Ok(Attempt::Rejected);
                    }
                } else {
                    self.stats.newton_failures += 1;
                    self.reject_with(0.5 * h);
                    return Ok(Attempt::Rejected);
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
            if self.faccon * dyno <= self.newton_tol {
                break;
            }
        }

        let err = if self.opts.fixed_step.is_some() {
            0.0
        } else {
            self.error_estimate(f, h)?
        };
        let s = &self.settings;
        let cfac = s.safety * (1.0 + 2.0 * nit as f64);
        let fac = s.safety.min(cfac / (newt + 2 * nit) as f64);
        // quot = h/h_new ∈ [1/hi, 1/lo].
        let (lo, hi) = s.h_ratio_range;
        let mut quot = (err.powf(0.25) / fac).clamp(1.0 / hi, 1.0 / lo);
        if err >= 1.0 {
            self.stats.error_test_failures += 1;
            let retry = if self.first { 0.1 * h } else { h / quot };
            self.reject_with(retry);
            return Ok(Attempt::Rejected);
        }

        // Accepted (pending the RHS at the new point).
        for k in 0..n {
            self.y_stage[k] = self.y[k] + self.z[2][k];
        }
        if let Some(component) = self.y_stage.iter().position(|v| !v.is_finite()) {
            return Err(SolveError::NonFinite {
                t: t + h,
                component,
            });
        }
        self.stats.rhs_evals += 1;
        // fs[0] is free now: it receives f(t + h, y_new).
        if let Err(source) = f.rhs(t + h, &self.y_stage, &mut self.fs[0]) {
            let e = SolveError::Formulation { t: t + h, source };
            if is_recoverable(&e) && self.opts.fixed_step.is_none() {
                self.stats.recovered_rejections += 1;
                self.reject_with(0.25 * h);
                return Ok(Attempt::Recoverable(e));
            }
            return Err(e);
        }
        if s.predictive && self.accepted_since_start > 0 {
            // Gustafsson's predictive controller.
            let facgus = (self.h_acc / h) * (err * err / self.err_acc).powf(0.25) / s.safety;
            quot = quot.max(facgus.clamp(1.0 / hi, 1.0 / lo));
        }
        self.h_acc = h;
        self.err_acc = err.max(1e-2);
        let mut h_new = (h / quot).min(self.opts.h_max);
        if self.reject {
            h_new = h_new.min(h);
        }
        self.commit(h);
        let qt = h_new / h;
        let (q1, q2) = self.settings.keep_h_range;
        let theta_small = self.theta <= self.settings.theta_jac;
        self.h_next = if let Some(h_fixed) = self.opts.fixed_step {
            h_fixed
        } else if theta_small && qt >= q1 && qt <= q2 {
            h
        } else {
            h_new
        };
        self.need_jac = !theta_small;
        Ok(Attempt::Accepted)
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
        let c3q = h / self.h_old;
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

    /// Hairer's error estimate (ESTRAD), with the second filtering on the first step and after a
    /// rejection. Returns max(‖err‖, 10⁻¹⁰).
    fn error_estimate<F: Formulation + ?Sized>(
        &mut self,
        f: &F,
        h: f64,
    ) -> Result<f64, SolveError> {
        let hee = [DD[0] / h, DD[1] / h, DD[2] / h];
        for k in 0..self.n {
            let f2 = hee[0] * self.z[0][k] + hee[1] * self.z[1][k] + hee[2] * self.z[2][k];
            self.err_rhs[k] = f2;
            self.err_vec[k] = f2 + self.f0[k];
        }
        self.e1.solve(&mut self.err_vec);
        let mut err = self.scaled_rms(&self.err_vec).max(1e-10);
        if err >= 1.0 && (self.first || self.reject) {
            for k in 0..self.n {
                self.y_stage[k] = self.y[k] + self.err_vec[k];
            }
            self.stats.rhs_evals += 1;
            match f.rhs(self.t, &self.y_stage, &mut self.fs[1]) {
                Ok(()) => {
                    for k in 0..self.n {
                        self.err_vec[k] = self.fs[1][k] + self.err_rhs[k];
                    }
                    self.e1.solve(&mut self.err_vec);
                    err = self.scaled_rms(&self.err_vec).max(1e-10);
                }
                // The filtered state is only a probe: if it overshoots into a contact, keep the
                // first estimate (≥ 1, so the step is rejected anyway).
                Err(source) if source.is_recoverable() => {}
                Err(source) => return Err(SolveError::Formulation { t: self.t, source }),
            }
        }
        Ok(err)
    }

    /// Moves to the end of an accepted step of size h whose new state is in `y_stage` and
    /// f(t + h, y_new) in `fs[0]`; builds the dense output.
    fn commit(&mut self, h: f64) {
        self.t_old = self.t;
        self.h_old = h;
        self.t += h;
        self.dense_end = self.t;
        std::mem::swap(&mut self.y_old, &mut self.y);
        self.y.copy_from_slice(&self.y_stage);
        self.y_new.copy_from_slice(&self.y_stage);
        std::mem::swap(&mut self.f0, &mut self.fs[0]);
        for k in 0..self.n {
            let (z1, z2, z3) = (self.z[0][k], self.z[1][k], self.z[2][k]);
            let c1 = (z2 - z3) / C2M1;
            let ak = (z1 - z2) / C1MC2;
            let acont3 = (ak - z1 / C1) / C2;
            let c2 = (ak - c1) / C1M1;
            self.cont[0][k] = c1;
            self.cont[1][k] = c2;
            self.cont[2][k] = c2 - acont3;
        }
        self.update_scale();
        self.first = false;
        self.reject = false;
        self.jac_current = false;
        self.accepted_since_start += 1;
        self.stats.record_step(h);
    }
}
