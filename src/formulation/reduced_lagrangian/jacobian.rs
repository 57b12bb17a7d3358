//! Analytic Jacobian J = ∂f/∂y of the reduced formulation (used by Radau5 through
//! [`Formulation::jacobian`](crate::formulation::Formulation::jacobian)): no RHS call.
//!
//! With y = [θ3, θ4, θ̇3, θ̇4, δ̇⁽⁻⁾] and f = [θ̇3, θ̇4, θ̈3, θ̈4, 0], rows 0, 1 and 4 are constant
//! (e₂, e₃, 0); rows 2 and 3 are ∂q_k/∂y / I_k with the generalised forces of the module
//! documentation of [`super`], q3 = a3 × m3 (g − a_A) + Q3 + M3 + τ3 + Σ (R ρ_P) × F_P and
//! q4 = a4 × m4 g + Q4 + M4 + τ4 + Σ (R ρ_P) × F_P (I_k the pivot inertias):
//!
//! * **rigid-body terms**, exactly: ∂(R(θ) ρ)/∂θ = J R(θ) ρ, so ∂(a × w)/∂θ = (J a) × w for the
//!   weights, the d'Alembert force −m3 a_A of the moving pivot A and every point load;
//! * **contact terms** Q3 = d3 × f3 + r3 F_T, Q4 = d4 × f4 + r4 F_T with f3 = σ (F_N n − F_T t),
//!   f4 = −f3 (σ = +1 with the bearing on the coupler, −1 with it on the rocker) and
//!   r3, r4 = −R_B, R_J (swapped with the bearing): the kinematics analytically,
//!   e = σ (C4 − C3), ∂e/∂θ3 = −σ L3 J u3, ∂e/∂θ4 = σ L4 J u4, ė likewise with the rates
//!   (∂ė/∂θ3 = σ θ̇3 d3, ∂ė/∂θ4 = −σ θ̇4 d4), ∂n = t (t·∂e)/|e|, ∂t = J ∂n, ∂δ = n·∂e,
//!   ∂δ̇ = n·∂ė + ė·∂n, ∂v_t = t·∂ė + ė·∂t + R_J ∂ω_J − R_B ∂ω_B; the scalar laws
//!   F_N(δ, δ̇, δ̇⁽⁻⁾) and F_T(F_N, v_t) by **central differences of the law alone** (a few
//!   flops each, no kinematics, no sin/cos), so that every contact law and friction law of
//!   [`crate::contact`] is covered without a derivative of its own. Increments: 1e-6 of the
//!   argument with floors (1e-10 m, 1e-7 m/s, 1e-3 N) far below the scales of the reference
//!   case (δ ~ 1e-6 m, δ̇ ~ 0.1 m/s, F_N ~ 1e3 N); a kink of a law (δ = 0, the friction ramp's
//!   ends v0, v1) inside an increment gives the mean of the one-sided slopes, which serves a
//!   simplified Newton iteration as well as either.
//!
//! The stored impact velocity enters only through the law: ∂F_N/∂δ̇⁽⁻⁾ where one is stored
//! (> 0), otherwise F_N uses the current δ̇ (see [`impact_velocity`]).

use super::{ReducedLagrangian, state};
use crate::contact::{friction_force, impact_velocity};
use crate::formulation::FormulationError;
use crate::mechanics::planar::{cross, dot, perp, rotate};

/// Relative increment of the central differences of the scalar laws.
const REL: f64 = 1e-6;

/// Central difference of `g` at x with increment REL·max(|x|, floor).
fn central(g: impl Fn(f64) -> f64, x: f64, floor: f64) -> f64 {
    let h = REL * x.abs().max(floor);
    (g(x + h) - g(x - h)) / (2.0 * h)
}

/// A vector of ∂/∂y_k for the five states.
type Grad = [f64; 5];

fn scale(v: [f64; 2], s: f64) -> [f64; 2] {
    [v[0] * s, v[1] * s]
}

impl ReducedLagrangian {
    /// Writes J = ∂f/∂y at (t, y) row-major into `out` (length 25). Fails as
    /// [`Formulation::rhs`](crate::formulation::Formulation::rhs) does (a penetration beyond
    /// 0.1 R_J, a non-finite acceleration).
    pub(super) fn analytic_jacobian(
        &self,
        t: f64,
        y: &[f64],
        out: &mut [f64],
    ) -> Result<(), FormulationError> {
        if out.len() != 25 {
            return Err(FormulationError::Unsupported {
                formulation: super::NAME.into(),
                reason: format!(
                    "Jacobian buffer of length {} for 5 states (25 needed)",
                    out.len()
                ),
            });
        }
        let d = self.dynamics(t, y)?;
        let [_, _, w3, w4, stored] = state(y);
        let (cp, rk) = (&self.coupler, &self.rocker);
        let c = &d.chain;
        let g = self.gravity;
        // Rigid-body terms.
        let w3_force = [cp.mass * (g[0] - c.a_acc[0]), cp.mass * (g[1] - c.a_acc[1])];
        let mut dq3: Grad = [0.0; 5];
        let mut dq4: Grad = [0.0; 5];
        dq3[0] = cross(perp(d.a3), w3_force) + load_derivative(&cp.loads, c.sc[1]);
        dq4[1] = cross(perp(d.a4), scale(g, rk.mass)) + load_derivative(&rk.loads, c.sc[2]);

        // Contact terms (zero while free: F_N = 0 in a neighbourhood of δ < 0).
        let kin = &d.kin;
        let f_n = d.forces.normal_force;
        if kin.delta > 0.0 && kin.distance > 0.0 {
            let sigma = if self.bearing_on_coupler { 1.0 } else { -1.0 };
            let n = kin.normal;
            let tan = perp(n);
            let (d3, d4) = (c.d[1], c.d[2]);
            let (jd3, jd4) = (perp(d3), perp(d4));
            // ∂e and ∂ė per state (columns θ3, θ4, θ̇3, θ̇4, δ̇⁽⁻⁾).
            let de: [[f64; 2]; 5] = [
                scale(jd3, -sigma),
                scale(jd4, sigma),
                [0.0; 2],
                [0.0; 2],
                [0.0; 2],
            ];
            let de_dot: [[f64; 2]; 5] = [
                scale(d3, sigma * w3),
                scale(d4, -sigma * w4),
                scale(jd3, -sigma),
                scale(jd4, sigma),
                [0.0; 2],
            ];
            // Angular velocities of journal and bearing: ∂ω_J − R_B/R_J… per state.
            let (r_j, r_b) = (kin.journal_radius, kin.bearing_radius);
            // ∂(R_J ω_J − R_B ω_B)/∂(θ̇3, θ̇4).
            let (spin3, spin4) = if self.bearing_on_coupler {
                (-r_b, r_j)
            } else {
                (r_j, -r_b)
            };
            let joint = &self.joint;
            let v_imp = impact_velocity(stored, kin.delta_dot);
            let law =
                |delta: f64, delta_dot: f64, v: f64| joint.law.normal_force(delta, delta_dot, v);
            let n_delta = central(|x| law(x, kin.delta_dot, v_imp), kin.delta, 1e-10);
            // δ̇ enters twice without a stored impact velocity (rate and impact velocity).
            let n_rate = if stored > 0.0 {
                central(|x| law(kin.delta, x, stored), kin.delta_dot, 1e-7)
            } else {
                central(|x| law(kin.delta, x, x), kin.delta_dot, 1e-7)
            };
            let n_stored = if stored > 0.0 {
                central(|x| law(kin.delta, kin.delta_dot, x), stored, 1e-7)
            } else {
                0.0
            };
            let v_t = kin.tangential_velocity;
            let friction = |normal: f64, v: f64| friction_force(&joint.friction, normal, v);
            let t_normal = central(|x| friction(x, v_t), f_n, 1e-3);
            let t_slip = central(|x| friction(f_n, x), v_t, 1e-7);
            let f_t = d.forces.friction_force;
            let f3 = d.f3;
            let (r3, r4) = if self.bearing_on_coupler {
                (-r_b, r_j)
            } else {
                (r_j, -r_b)
            };
            for k in 0..5 {
                let dn = scale(tan, dot(tan, de[k]) / kin.distance);
                let dt = perp(dn);
                let d_delta = dot(n, de[k]);
                let d_rate = dot(n, de_dot[k]) + dot(kin.e_dot, dn);
                let d_spin = match k {
                    2 => spin3,
                    3 => spin4,
                    _ => 0.0,
                };
                let d_slip = dot(tan, de_dot[k]) + dot(kin.e_dot, dt) + d_spin;
                let d_fn =
                    n_delta * d_delta + n_rate * d_rate + if k == 4 { n_stored } else { 0.0 };
                let d_ft = t_normal * d_fn + t_slip * d_slip;
                let df3 = [
                    sigma * (d_fn * n[0] + f_n * dn[0] - d_ft * tan[0] - f_t * dt[0]),
                    sigma * (d_fn * n[1] + f_n * dn[1] - d_ft * tan[1] - f_t * dt[1]),
                ];
                // ∂d3/∂θ3 = J d3 and ∂d4/∂θ4 = J d4; f4 = −f3.
                let dd3 = if k == 0 { jd3 } else { [0.0; 2] };
                let dd4 = if k == 1 { jd4 } else { [0.0; 2] };
                dq3[k] += cross(dd3, f3) + cross(d3, df3) + r3 * d_ft;
                dq4[k] += -cross(dd4, f3) - cross(d4, df3) + r4 * d_ft;
            }
        }
        out.fill(0.0);
        out[2] = 1.0; // ∂θ̇3/∂θ̇3 in row 0
        out[5 + 3] = 1.0; // ∂θ̇4/∂θ̇4 in row 1
        let (i3, i4) = (cp.pivot_inertia(), rk.pivot_inertia());
        for k in 0..5 {
            out[10 + k] = dq3[k] / i3;
            out[15 + k] = dq4[k] / i4;
        }
        Ok(())
    }
}

/// ∂/∂θ Σ (R(θ) ρ_P) × F_P = Σ (J R(θ) ρ_P) × F_P at (sin θ, cos θ).
fn load_derivative(loads: &[([f64; 2], [f64; 2])], sin_cos: (f64, f64)) -> f64 {
    loads
        .iter()
        .map(|(point, force)| cross(perp(rotate(sin_cos, *point)), *force))
        .sum()
}
