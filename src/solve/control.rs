//! Step-size control: Hairer's (PI) controller and the initial-step heuristic `hinit`.
//!
//! **Controller** \[1, Sec. II.4; 2, Sec. IV.2 for the PI form; codes `dopri5.f`,
//! `dop853.f`\]: with the error norm `err` of the step just tried (≤ 1 means accept),
//! fac₁₁ = err^α, α = 1/q − κβ, and the new step is
//! h_new = h / clamp(fac₁₁ / err_old^β / safety, 1/fac_max, 1/fac_min),
//! where err_old is the norm of the last accepted step (at least 1e-4), safety = 0.9, and q,
//! κ, fac_min, fac_max are Hairer's defaults for each method:
//!
//! | method | q | κ | fac_min | fac_max | β (default) |
//! |---|---|---|---|---|---|
//! | DOPRI5 | 5 | 0.75 | 0.2 | 10 | 0.04 |
//! | DOP853 | 8 | 0.2 | 0.333 | 6 | 0 |
//!
//! A rejected step is retried with h / min(1/fac_min, fac₁₁/safety) (no PI term), and the step
//! after a rejection may not grow. A non-finite error norm (NaN or ∞ in a stage) is a rejection
//! with the largest decrease, fac_min.
//!
//! **Initial step** \[1, Sec. II.4, p. 169, `hinit`\], with SciPy's RMS norms
//! (`select_initial_step` in `scipy/integrate/_ivp/common.py`): d₀ = ‖y₀/sk‖, d₁ = ‖f₀/sk‖,
//! h₀ = 0.01 d₀/d₁ (1e-6 s if either is below 1e-5), one explicit Euler step to get
//! d₂ = ‖(f(t₀+h₀, y₀+h₀f₀) − f₀)/sk‖/h₀, h₁ = (0.01/max(d₁, d₂))^(1/q) (or max(1e-6, 1e-3 h₀)
//! if both are below 1e-15), and h = min(100 h₀, h₁, h_cap).
//!
//! # References
//! 1. E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary Differential Equations I*, 2nd ed.,
//!    Springer, 1993.
//! 2. E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II*, 2nd ed., Springer,
//!    1996, Sec. IV.2 (PI control, after Gustafsson).

use super::error::SolveError;
use super::integrator::ErrorWeights;
use super::rk::eval_rhs;
use crate::formulation::Formulation;

/// Safety factor applied to the asymptotically optimal step.
const SAFETY: f64 = 0.9;
/// Smallest error norm remembered for the PI term (Hairer's `facold` floor).
const ERR_OLD_MIN: f64 = 1e-4;

/// Hairer's constants of one method (see the table in the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ControlParams {
    /// Exponent q: the error behaves like h^q (5 for DOPRI5, 8 for DOP853).
    pub q: f64,
    /// κ of the PI exponent α = 1/q − κβ.
    pub kappa: f64,
    /// Smallest factor h_new/h.
    pub fac_min: f64,
    /// Largest factor h_new/h.
    pub fac_max: f64,
}

/// Outcome of the error test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Decision {
    /// Keep the step; try `h_next` next.
    Accept {
        /// Proposed next step size (s).
        h_next: f64,
    },
    /// Discard the step; retry with `h_next`.
    Reject {
        /// Step size for the retry (s).
        h_next: f64,
    },
}

/// Hairer's step-size controller (state: the last accepted error norm and whether the last
/// attempt was rejected).
#[derive(Debug, Clone)]
pub(crate) struct Controller {
    expo1: f64,
    beta: f64,
    fac_min: f64,
    fac_max: f64,
    err_old: f64,
    last_rejected: bool,
}

impl Controller {
    /// Controller with constants `params` and PI exponent `beta`.
    pub(crate) fn new(params: ControlParams, beta: f64) -> Self {
        let ControlParams {
            q,
            kappa,
            fac_min,
            fac_max,
        } = params;
        Self {
            expo1: 1.0 / q - kappa * beta,
            beta,
            fac_min,
            fac_max,
            err_old: ERR_OLD_MIN,
            last_rejected: false,
        }
    }

    /// Forgets the history (after a restart at an event).
    pub(crate) fn reset(&mut self) {
        self.err_old = ERR_OLD_MIN;
        self.last_rejected = false;
    }

    /// Error test for a step of size h with error norm `err`.
    pub(crate) fn decide(&mut self, err: f64, h: f64) -> Decision {
        if !err.is_finite() {
            self.last_rejected = true;
            return Decision::Reject {
                h_next: h * self.fac_min,
            };
        }
        let fac11 = err.powf(self.expo1);
        if err <= 1.0 {
            // β = 0 (DOP853's default): no PI term, and no `powf` call for it on every step.
            let pi_term = if self.beta == 0.0 {
                1.0
            } else {
                self.err_old.powf(self.beta)
            };
            let fac = fac11 / pi_term / SAFETY;
            let fac = fac.clamp(1.0 / self.fac_max, 1.0 / self.fac_min);
            let mut h_next = h / fac;
            if self.last_rejected {
                h_next = h_next.min(h);
            }
            self.err_old = err.max(ERR_OLD_MIN);
            self.last_rejected = false;
            Decision::Accept { h_next }
        } else {
            self.last_rejected = true;
            Decision::Reject {
                h_next: h / (fac11 / SAFETY).min(1.0 / self.fac_min),
            }
        }
    }
}

/// Inputs of [`initial_step`] besides the formulation.
pub(crate) struct InitialStep<'a> {
    /// Initial time (s).
    pub t0: f64,
    /// Initial state.
    pub y0: &'a [f64],
    /// f(t0, y0).
    pub f0: &'a [f64],
    /// Largest step allowed (s): min(h_max, max_step, t_end − t0).
    pub h_cap: f64,
    /// Tolerances and the error-controlled components (the norms below run over those only).
    pub weights: &'a ErrorWeights,
    /// Exponent q (5 for DOPRI5, 8 for DOP853).
    pub q: f64,
}

/// Hairer's `hinit` (see the module documentation); one RHS call, counted in `evals`.
/// `y1` and `f1` are scratch vectors of length n.
pub(crate) fn initial_step<F: Formulation + ?Sized>(
    f: &F,
    p: &InitialStep<'_>,
    y1: &mut [f64],
    f1: &mut [f64],
    evals: &mut u64,
) -> Result<f64, SolveError> {
    let w = p.weights;
    let fallback = 1e-6_f64.min(p.h_cap);
    if w.is_empty() {
        return Ok(p.h_cap.min(1.0));
    }
    let at = |v: &[f64], i: usize| v.get(i).copied().unwrap_or(0.0);
    let d0 = w.rms(p.y0, p.y0, |i| at(p.y0, i));
    let d1 = w.rms(p.y0, p.y0, |i| at(p.f0, i));
    let mut h0 = if d0 < 1e-5 || d1 < 1e-5 {
        1e-6
    } else {
        0.01 * d0 / d1
    };
    if !(h0.is_finite() && h0 > 0.0) {
        h0 = 1e-6;
    }
    h0 = h0.min(p.h_cap);
    for ((y1i, &y), &fy) in y1.iter_mut().zip(p.y0).zip(p.f0) {
        *y1i = y + h0 * fy;
    }
    eval_rhs(f, p.t0 + h0, y1, f1, evals)?;
    let d2 = w.rms(p.y0, p.y0, |i| at(f1, i) - at(p.f0, i)) / h0;
    let h1 = if d1 <= 1e-15 && d2 <= 1e-15 {
        (h0 * 1e-3).max(1e-6)
    } else {
        (0.01 / d1.max(d2)).powf(1.0 / p.q)
    };
    let h = (100.0 * h0).min(h1).min(p.h_cap);
    Ok(if h.is_finite() && h > 0.0 {
        h
    } else {
        fallback
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formulation::FormulationError;
    use crate::formulation::NoStepHooks;

    const DOPRI5: ControlParams = ControlParams {
        q: 5.0,
        kappa: 0.75,
        fac_min: 0.2,
        fac_max: 10.0,
    };
    const DOP853: ControlParams = ControlParams {
        q: 8.0,
        kappa: 0.2,
        fac_min: 0.333,
        fac_max: 6.0,
    };

    #[test]
    fn accepts_and_grows_on_small_error() {
        let mut c = Controller::new(DOPRI5, 0.0);
        match c.decide(0.0, 0.1) {
            Decision::Accept { h_next } => assert!((h_next - 1.0).abs() < 1e-12, "{h_next}"),
            d => panic!("expected acceptance, got {d:?}"),
        }
        // err = 1 with β = 0: h_next = h·0.9.
        match c.decide(1.0, 0.1) {
            Decision::Accept { h_next } => assert!((h_next - 0.09).abs() < 1e-12, "{h_next}"),
            d => panic!("expected acceptance, got {d:?}"),
        }
    }

    #[test]
    fn rejects_and_shrinks_then_does_not_grow() {
        let mut c = Controller::new(DOP853, 0.0);
        match c.decide(1e12, 1.0) {
            Decision::Reject { h_next } => assert!((h_next - 0.333).abs() < 1e-12, "{h_next}"),
            d => panic!("expected rejection, got {d:?}"),
        }
        match c.decide(1e-10, 0.333) {
            Decision::Accept { h_next } => assert_eq!(h_next, 0.333),
            d => panic!("expected acceptance, got {d:?}"),
        }
        match c.decide(f64::NAN, 0.5) {
            Decision::Reject { h_next } => assert!((h_next - 0.5 * 0.333).abs() < 1e-12),
            d => panic!("expected rejection, got {d:?}"),
        }
    }

    #[test]
    fn error_halving_lengthens_the_step_as_err_to_the_minus_one_fifth() {
        // Asymptotic law: h_new/h = 0.9·err^(-1/5) for DOPRI5 with β = 0.
        let mut c = Controller::new(DOPRI5, 0.0);
        match c.decide(0.5, 1.0) {
            Decision::Accept { h_next } => {
                let expected = 0.5f64.powf(-0.2) * 0.9;
                assert!((h_next - expected).abs() < 1e-12, "{h_next} vs {expected}");
            }
            d => panic!("expected acceptance, got {d:?}"),
        }
    }

    struct Decay;
    impl NoStepHooks for Decay {}

    impl Formulation for Decay {
        fn n_states(&self) -> usize {
            1
        }
        fn initial_state(&self) -> Vec<f64> {
            vec![1.0]
        }
        fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
            dy[0] = -y[0];
            Ok(())
        }
    }

    #[test]
    fn hinit_follows_hairer() {
        // y' = -y, y0 = 1, rtol = 1e-6, atol = 0: d0 = d1 = 1e6, h0 = 0.01;
        // d2 = |f1 - f0|/sk/h0 = 0.01/1e-6/0.01 = 1e6; h1 = (0.01/1e6)^(1/5) = 1e-8^(0.2).
        let mut y1 = [0.0];
        let mut f1 = [0.0];
        let mut evals = 0;
        let weights = ErrorWeights::new(&Decay, 1e-6, 0.0);
        let p = InitialStep {
            t0: 0.0,
            y0: &[1.0],
            f0: &[-1.0],
            h_cap: f64::INFINITY,
            weights: &weights,
            q: 5.0,
        };
        let h = initial_step(&Decay, &p, &mut y1, &mut f1, &mut evals).unwrap_or(0.0);
        let expected = (1e-8f64).powf(0.2);
        assert!((h - expected).abs() < 1e-12, "{h} vs {expected}");
        assert_eq!(evals, 1);
        let p = InitialStep { h_cap: 1e-3, ..p };
        let h = initial_step(&Decay, &p, &mut y1, &mut f1, &mut evals).unwrap_or(0.0);
        assert_eq!(h, 1e-3);
    }
}
