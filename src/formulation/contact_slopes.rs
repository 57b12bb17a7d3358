//! Derivatives of a clearance joint's contact forces with respect to its kinematics, shared by
//! the analytic Jacobians of the reduced formulation (`reduced_lagrangian/jacobian.rs`) and the
//! DAE (`dae/jacobian.rs`).
//!
//! The forces on the journal are F_J = −F_N n + F_T t (the bearing gets −F_J), with moments
//! R_J F_T about the journal centre and −R_B F_T about the bearing centre
//! ([`crate::contact::kinematics`]). For one direction of differentiation ∂ (a state component)
//! the caller supplies ∂e, ∂ė and ∂s = R_J ∂ω_J − R_B ∂ω_B (the spin part of the slip velocity),
//! and whether ∂ moves the stored impact velocity δ̇⁽⁻⁾; then, exactly for the kinematics,
//!
//! ```text
//!     ∂n = t (t·∂e)/|e|,   ∂t = perp(∂n),   ∂δ = n·∂e,   ∂δ̇ = n·∂ė + ė·∂n,
//!     ∂v_t = t·∂ė + ė·∂t + ∂s,
//!     ∂F_N = F_N,δ ∂δ + F_N,δ̇ ∂δ̇ + F_N,δ̇⁽⁻⁾ ∂δ̇⁽⁻⁾,   ∂F_T = F_T,N ∂F_N + F_T,v ∂v_t,
//!     ∂F_J = −∂F_N n − F_N ∂n + ∂F_T t + F_T ∂t.
//! ```
//!
//! The scalar laws F_N(δ, δ̇, δ̇⁽⁻⁾) and F_T(F_N, v_t) are differentiated by **central
//! differences of the law alone** (a few flops each, no kinematics, no sin/cos), so that every
//! contact law and friction law of [`crate::contact`] is covered without a derivative of its
//! own ([`LawSlopes`]). Increments: 1e-6 of the argument with floors (1e-10 m, 1e-7 m/s,
//! 1e-3 N) far below the scales of the reference case (δ ~ 1e-6 m, δ̇ ~ 0.1 m/s, F_N ~ 1e3 N);
//! a kink of a law (δ = 0, the friction ramp's ends v0, v1) inside an increment gives the mean of
//! the one-sided slopes, which serves a simplified Newton iteration as well as either.
//!
//! The line-contact laws (Johnson's, implicit in δ, and Liu's) give their slopes in closed form
//! instead ([`crate::contact::ContactLaw::line_slopes`]); the power laws keep the central
//! differences, so that their runs stay bit-identical.
//!
//! The stored impact velocity enters only through the law: ∂F_N/∂δ̇⁽⁻⁾ where one is stored
//! (> 0); otherwise F_N uses the current δ̇ as impact velocity
//! ([`impact_velocity`]), so δ̇ enters the law twice.

use crate::contact::{ClearanceJoint, ContactKinematics, friction_force, impact_velocity};
use crate::mechanics::planar::{dot, perp};

/// Relative increment of the central differences of the scalar laws.
const REL: f64 = 1e-6;

/// Central difference of `g` at x with increment REL·max(|x|, floor).
fn central(g: impl Fn(f64) -> f64, x: f64, floor: f64) -> f64 {
    let h = REL * x.abs().max(floor);
    (g(x + h) - g(x - h)) / (2.0 * h)
}

/// Slopes of the scalar laws of one joint at one contact state (δ > 0).
#[derive(Debug, Clone, Copy)]
pub struct LawSlopes {
    /// ∂F_N/∂δ (N/m).
    pub normal_delta: f64,
    /// ∂F_N/∂δ̇ (N·s/m), including the impact-velocity argument when none is stored.
    pub normal_rate: f64,
    /// ∂F_N/∂δ̇⁽⁻⁾ (N·s/m), 0 when no impact velocity is stored.
    pub normal_stored: f64,
    /// ∂F_T/∂F_N (dimensionless).
    pub friction_normal: f64,
    /// ∂F_T/∂v_t (N·s/m).
    pub friction_slip: f64,
}

/// The derivative of one joint's forces along one direction ∂.
#[derive(Debug, Clone, Copy)]
pub struct ForceDerivative {
    /// ∂F_N (N per unit of the direction).
    pub normal: f64,
    /// ∂F_T.
    pub friction: f64,
    /// ∂F_J, the force on the journal (the bearing's is −∂F_J).
    pub on_journal: [f64; 2],
}

/// One direction of differentiation: ∂e, ∂ė, ∂s = R_J ∂ω_J − R_B ∂ω_B and ∂δ̇⁽⁻⁾.
#[derive(Debug, Clone, Copy, Default)]
pub struct Direction {
    /// ∂e (m per unit).
    pub e: [f64; 2],
    /// ∂ė.
    pub e_dot: [f64; 2],
    /// ∂(R_J ω_J − R_B ω_B).
    pub spin: f64,
    /// ∂δ̇⁽⁻⁾ (1 for the stored impact velocity's own column, else 0).
    pub stored: f64,
}

impl LawSlopes {
    /// The slopes at kinematics `kin` (in contact: δ > 0, |e| > 0) with the stored impact
    /// velocity `stored` (0 = none) and the normal force `normal` = F_N there.
    pub fn at(joint: &ClearanceJoint, kin: &ContactKinematics, stored: f64, normal: f64) -> Self {
        let v_imp = impact_velocity(stored, kin.delta_dot);
        let law = |delta: f64, delta_dot: f64, v: f64| joint.law.normal_force(delta, delta_dot, v);
        let analytic = joint.law.line_slopes(kin.delta, kin.delta_dot, v_imp);
        // δ̇ enters twice without a stored impact velocity (rate and impact velocity).
        let (normal_delta, normal_rate, normal_stored) = if let Some((d, r, s)) = analytic {
            if stored > 0.0 {
                (d, r, s)
            } else {
                (d, r + s, 0.0)
            }
        } else if stored > 0.0 {
            let normal_delta = central(|x| law(x, kin.delta_dot, v_imp), kin.delta, 1e-10);
            (
                normal_delta,
                central(|x| law(kin.delta, x, stored), kin.delta_dot, 1e-7),
                central(|x| law(kin.delta, kin.delta_dot, x), stored, 1e-7),
            )
        } else {
            let normal_delta = central(|x| law(x, kin.delta_dot, v_imp), kin.delta, 1e-10);
            (
                normal_delta,
                central(|x| law(kin.delta, x, x), kin.delta_dot, 1e-7),
                0.0,
            )
        };
        let v_t = kin.tangential_velocity;
        let friction = |f_n: f64, v: f64| friction_force(&joint.friction, f_n, v);
        LawSlopes {
            normal_delta,
            normal_rate,
            normal_stored,
            friction_normal: central(|x| friction(x, v_t), normal, 1e-3),
            friction_slip: central(|x| friction(normal, x), v_t, 1e-7),
        }
    }

    /// ∂F_N, ∂F_T and ∂F_J along `d`, at `kin` with forces F_N = `normal`, F_T = `friction`.
    pub fn derivative(
        &self,
        kin: &ContactKinematics,
        normal: f64,
        friction: f64,
        d: &Direction,
    ) -> ForceDerivative {
        let n = kin.normal;
        let tan = perp(n);
        let dn = scale(tan, dot(tan, d.e) / kin.distance);
        let dt = perp(dn);
        let d_delta = dot(n, d.e);
        let d_rate = dot(n, d.e_dot) + dot(kin.e_dot, dn);
        let d_slip = dot(tan, d.e_dot) + dot(kin.e_dot, dt) + d.spin;
        let d_fn =
            self.normal_delta * d_delta + self.normal_rate * d_rate + self.normal_stored * d.stored;
        let d_ft = self.friction_normal * d_fn + self.friction_slip * d_slip;
        ForceDerivative {
            normal: d_fn,
            friction: d_ft,
            on_journal: [
                -d_fn * n[0] - normal * dn[0] + d_ft * tan[0] + friction * dt[0],
                -d_fn * n[1] - normal * dn[1] + d_ft * tan[1] + friction * dt[1],
            ],
        }
    }
}

fn scale(v: [f64; 2], s: f64) -> [f64; 2] {
    [v[0] * s, v[1] * s]
}
