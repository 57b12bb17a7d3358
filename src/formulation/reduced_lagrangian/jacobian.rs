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
//!   ∂δ̇, ∂v_t, ∂F_N, ∂F_T and ∂F_J from ∂e, ∂ė and the spin rates by
//!   [`LawSlopes`] (`formulation/contact_slopes.rs`, shared with the DAE's Jacobian): exact
//!   kinematics, the scalar laws F_N(δ, δ̇, δ̇⁽⁻⁾) and F_T(F_N, v_t) by central differences
//!   of the law alone, so that every contact law and friction law is covered.

use super::{ReducedLagrangian, state};
use crate::formulation::FormulationError;
use crate::formulation::contact_slopes::{Direction, LawSlopes};
use crate::mechanics::planar::{cross, perp, rotate};

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
            // r3, r4 = ∂(R_J ω_J − R_B ω_B)/∂(θ̇3, θ̇4), also the arms of F_T in the moments.
            let (r_j, r_b) = (kin.journal_radius, kin.bearing_radius);
            let (r3, r4) = if self.bearing_on_coupler {
                (-r_b, r_j)
            } else {
                (r_j, -r_b)
            };
            let slopes = LawSlopes::at(&self.joint, kin, stored, f_n);
            let f_t = d.forces.friction_force;
            let f3 = d.f3;
            for k in 0..5 {
                let spin = match k {
                    2 => r3,
                    3 => r4,
                    _ => 0.0,
                };
                let direction = Direction {
                    e: de[k],
                    e_dot: de_dot[k],
                    spin,
                    stored: if k == 4 { 1.0 } else { 0.0 },
                };
                let df = slopes.derivative(kin, f_n, f_t, &direction);
                let d_ft = df.friction;
                // f3 = σ F_B = −σ F_J.
                let df3 = scale(df.on_journal, -sigma);
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
        let (inv3, inv4) = (cp.inverse_pivot_inertia(), rk.inverse_pivot_inertia());
        for k in 0..5 {
            out[10 + k] = dq3[k] * inv3;
            out[15 + k] = dq4[k] * inv4;
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
