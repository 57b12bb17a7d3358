//! Saltation matrices: how a perturbation of the state is carried across an event.
//!
//! At an event g(t, y) = 0 the formulation may reset its state, y⁺ = h(t, y⁻) (for a contact,
//! the stored impact velocity δ̇⁽⁻⁾ is set at an impact and cleared at a separation), and its
//! vector field may change from f⁻ to f⁺. A perturbation δy⁻ just before the nominal event time
//! t_e moves the event to t_e + dt_e with dt_e = −(∇g · δy⁻)/ġ, ġ = g_t + ∇g · f⁻, and arrives
//! after it as δy⁺ = S δy⁻ with (ref. 1 §7.1, ref. 2 eq. 11, extended by the explicit time
//! dependence h_t of the reset)
//!
//! ```text
//!   S = H + (f⁺ − H f⁻ − h_t) ∇gᵀ / ġ,     H = ∂h/∂y, h_t = ∂h/∂t, at (t_e, y⁻).
//! ```
//!
//! (Derivation: the perturbed trajectory reaches the surface at t_e + dt_e in
//! y⁻ + δy⁻ + f⁻ dt_e, is reset to h(t_e + dt_e, ·) = y⁺ + H(δy⁻ + f⁻ dt_e) + h_t dt_e, and
//! compared with the nominal one at the same time, y⁺ + f⁺ dt_e.)
//!
//! **The contact events of linkdyn** (docs/periodic_orbits.md derives each case):
//! * impact (δ rising through 0): h sets the stored δ̇⁽⁻⁾ to δ̇(t, y); the contact force
//!   vanishes at δ = 0 with or without a stored velocity, so f⁺ = f⁻. S is the identity except
//!   its stored-velocity row, ∇δ̇ − (δ̈/δ̇) ∇δ: the sensitivity of the impact velocity, corrected
//!   for the shift of the impact instant;
//! * separation (δ falling through 0): h clears δ̇⁽⁻⁾, f⁺ = f⁻: S is the identity with the
//!   stored-velocity row zero;
//! * friction kinks of a continuous friction law: h = id and f⁺ = f⁻, S = I (not formed).
//!
//! The formula is applied as written, with H, h_t, ∇g and g_t from central differences of the
//! formulation's own event function and event response (explicit algebraic maps of (t, y),
//! cheap and smooth at the event), so every formulation and every event is covered by one
//! rule; the tests check the result against the closed forms above.
//!
//! # References
//! 1. M. di Bernardo, C. J. Budd, A. R. Champneys, P. Kowalczyk, *Piecewise-smooth Dynamical
//!    Systems: Theory and Applications*, Springer, 2008, §2.5 and §7.1 (saltation matrix).
//! 2. R. I. Leine, D. H. van Campen, B. L. van de Vrande, "Bifurcations in nonlinear
//!    discontinuous systems", *Nonlinear Dynamics* 23, 105–164, 2000, eq. 11.

use crate::formulation::{Crossing, Formulation, FormulationError};

/// Relative finite-difference step for the central differences of the guard and the reset in
/// the state. Small because the contact's δ̇ = ė·e/|e| turns with e on the scale of the
/// clearance, not of the state: a step of 1e-5 rad turns n by ~1e-2 rad on farahan2016
/// (c = 0.44 mm, arms 0.45 m), and the impact row was off by 0.6 %, 1e-7 by 3e-4 (measured
/// against differences of the flow across one impact); rounding ≈ 1e-16/step.
const STEP: f64 = 1e-8;
/// Relative step (of the time scale) for the differences in time: t ± τ must stay many ulps
/// of t apart.
const TIME_STEP: f64 = 1e-6;

/// Why a saltation matrix could not be formed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SaltationError {
    /// The event function crossed zero with (nearly) zero rate: a grazing event, where the
    /// event time is not a differentiable function of the state.
    #[error(
        "event {index} at t = {t:.9} s is grazing (its event function crosses zero at rate {rate:e}): the event time does not depend smoothly on the state there"
    )]
    Grazing {
        /// Time (s).
        t: f64,
        /// Event function index.
        index: usize,
        /// ġ = g_t + ∇g · f⁻.
        rate: f64,
    },
    /// The right-hand side could not be evaluated on either side of the event.
    #[error("the right-hand side could not be evaluated at the event at t = {t:.9} s: {reason}")]
    Rhs {
        /// Time (s).
        t: f64,
        /// The formulation's message.
        reason: String,
    },
}

/// The saltation matrix S (row-major n × n) of event `index` (`crossing`) of `f` at time `t`,
/// from the state `before` the event response to the state `after` it (module
/// documentation). `f` must be the formulation as it was before the event (it is cloned to
/// probe the reset map); `time_scale` (s) sets the step of the differences in time.
pub fn saltation_matrix<F: Formulation + Clone>(
    f: &F,
    t: f64,
    before: &[f64],
    after: &[f64],
    index: usize,
    crossing: Crossing,
    time_scale: f64,
) -> Result<Vec<f64>, SaltationError> {
    let n = before.len();
    let rhs = |y: &[f64]| -> Result<Vec<f64>, SaltationError> {
        let mut dy = vec![0.0; n];
        f.rhs(t, y, &mut dy)
            .map_err(|e: FormulationError| SaltationError::Rhs {
                t,
                reason: e.to_string(),
            })?;
        Ok(dy)
    };
    let f_minus = rhs(before)?;
    let f_plus = rhs(after)?;

    // The guard g_index and the reset h at (t, y), on copies of the formulation.
    let mut g = vec![0.0; f.n_events()];
    let mut guard = |t: f64, y: &[f64]| {
        f.events(t, y, &mut g);
        g.get(index).copied().unwrap_or(f64::NAN)
    };
    let reset = |t: f64, y: &[f64]| {
        let mut copy = f.clone();
        let mut y = y.to_vec();
        copy.apply_event(t, &mut y, index, crossing);
        y
    };

    let mut grad = vec![0.0; n];
    let mut h_y = vec![0.0; n * n];
    let mut probe = before.to_vec();
    for j in 0..n {
        let eps = STEP * before[j].abs().max(1.0);
        probe[j] = before[j] + eps;
        let (g_plus, h_plus) = (guard(t, &probe), reset(t, &probe));
        let up = probe[j];
        probe[j] = before[j] - eps;
        let (g_minus, h_minus) = (guard(t, &probe), reset(t, &probe));
        let down = probe[j];
        probe[j] = before[j];
        grad[j] = (g_plus - g_minus) / (2.0 * eps);
        // A component that the reset leaves alone gets exactly 0 or 1; one it sets gets the
        // difference of what it was set to.
        for i in 0..n {
            let (moved_up, moved_down) = if i == j {
                (up, down)
            } else {
                (before[i], before[i])
            };
            h_y[i * n + j] = if h_plus[i] == moved_up && h_minus[i] == moved_down {
                if i == j { 1.0 } else { 0.0 }
            } else {
                (h_plus[i] - h_minus[i]) / (2.0 * eps)
            };
        }
    }
    let tau = TIME_STEP * time_scale;
    let g_t = (guard(t + tau, before) - guard(t - tau, before)) / (2.0 * tau);
    let (r_plus, r_minus) = (reset(t + tau, before), reset(t - tau, before));
    let h_t: Vec<f64> = (0..n)
        .map(|i| (r_plus[i] - r_minus[i]) / (2.0 * tau))
        .collect();

    let rate = g_t + grad.iter().zip(&f_minus).map(|(a, b)| a * b).sum::<f64>();
    // |ġ| against the sum of its terms' sizes: below 1e-8 of them it is rounding.
    let size = g_t.abs()
        + grad
            .iter()
            .zip(&f_minus)
            .map(|(a, b)| (a * b).abs())
            .sum::<f64>();
    if !(rate.is_finite() && rate.abs() > 1e-8 * size && rate != 0.0) {
        return Err(SaltationError::Grazing { t, index, rate });
    }
    // S = H + (f⁺ − H f⁻ − h_t) ∇gᵀ / ġ.
    let mut s = h_y.clone();
    for i in 0..n {
        let hf: f64 = (0..n).map(|k| h_y[i * n + k] * f_minus[k]).sum();
        let jump = (f_plus[i] - hf - h_t[i]) / rate;
        if jump != 0.0 {
            for j in 0..n {
                s[i * n + j] += jump * grad[j];
            }
        }
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formulation::{EventResponse, NoStepHooks};

    /// y = (x, v, s): x' = v, v' = a(t, x) = −x + sin t, s' = 0, with the events of a contact:
    /// g0 = x (rising: s := v, the impact velocity; falling: s := 0) and g1 = v − 0.5, a kink
    /// that changes nothing.
    #[derive(Clone)]
    struct Store;
    impl NoStepHooks for Store {}
    impl Formulation for Store {
        fn n_states(&self) -> usize {
            3
        }
        fn initial_state(&self) -> Vec<f64> {
            vec![0.0; 3]
        }
        fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
            dy[0] = y[1];
            dy[1] = -y[0] + t.sin();
            dy[2] = 0.0;
            Ok(())
        }
        fn n_events(&self) -> usize {
            2
        }
        fn events(&self, _t: f64, y: &[f64], g: &mut [f64]) {
            g[0] = y[0];
            g[1] = y[1] - 0.5;
        }
        fn apply_event(&mut self, _t: f64, y: &mut [f64], i: usize, c: Crossing) -> EventResponse {
            if i == 0 {
                y[2] = if c == Crossing::Rising { y[1] } else { 0.0 };
                EventResponse::Restart
            } else {
                EventResponse::Continue
            }
        }
    }

    fn close(s: &[f64], want: &[f64], case: &str) {
        for (k, (a, b)) in s.iter().zip(want).enumerate() {
            // Central differences of smooth maps with a 1e-5 step: ~1e-10.
            assert!(
                (a - b).abs() < 1e-8,
                "{case}: S[{k}] = {a}, closed form {b}"
            );
        }
    }

    #[test]
    fn impact_row_is_the_impact_velocity_sensitivity_corrected_for_the_event_time() {
        // At the impact x = 0, v = 0.8, t = 1: S is I except row s = ∇v − (v̇/ẋ) ∇x
        // = (−a/v, 1, 0) with a = v̇ = −0 + sin 1.
        let (t, before) = (1.0, [0.0, 0.8, 0.0]);
        let after = [0.0, 0.8, 0.8];
        let s = saltation_matrix(&Store, t, &before, &after, 0, Crossing::Rising, 1.0);
        let a = 1.0f64.sin();
        let want = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, -a / 0.8, 1.0, 0.0];
        close(&s.unwrap_or_else(|e| panic!("{e}")), &want, "impact");
    }

    #[test]
    fn separation_clears_the_stored_velocity_row_exactly() {
        let (t, before) = (2.0, [0.0, -0.3, 0.8]);
        let after = [0.0, -0.3, 0.0];
        let s = saltation_matrix(&Store, t, &before, &after, 0, Crossing::Falling, 1.0)
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(
            s,
            [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0],
            "separation"
        );
    }

    #[test]
    fn a_kink_of_a_continuous_field_is_the_identity() {
        let (t, before) = (0.5, [0.2, 0.5, 0.8]);
        let s = saltation_matrix(&Store, t, &before, &before, 1, Crossing::Rising, 1.0)
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(s, [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0], "kink");
    }

    #[test]
    fn a_grazing_impact_is_refused() {
        // ẋ = v = 0 at x = 0: the event time is not differentiable.
        let before = [0.0, 0.0, 0.0];
        let e = saltation_matrix(&Store, 0.0, &before, &before, 0, Crossing::Rising, 1.0).err();
        assert!(
            matches!(e, Some(SaltationError::Grazing { index: 0, .. })),
            "{e:?}"
        );
    }
}
