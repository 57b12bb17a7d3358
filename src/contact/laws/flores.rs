//! Flores et al. (2011) contact law, valid for any coefficient of restitution.
//!
//! ```text
//!     F_N = K δⁿ [1 + 8(1 − c_r)/(5 c_r) · δ̇/δ̇⁽⁻⁾]     for δ > 0,   F_N = 0 otherwise
//! ```
//!
//! F_N (N) ≥ 0 pushes journal and bearing apart; K (N/m^n); δ (m) penetration; n (–); δ̇ (m/s) > 0
//! while compressing; δ̇⁽⁻⁾ (m/s) the rate at the start of the contact; c_r (–) in (0, 1]. The
//! hysteresis factor χ = 8(1 − c_r)/(5 c_r) (0.17778 for c_r = 0.9) follows from an energy balance
//! that does not assume c_r close to 1, so the law stays meaningful for soft, dissipative contacts.
//! Clamp at 0 and the fallback for an unusable δ̇⁽⁻⁾: [`super::hysteresis_force`].
//!
//! # References
//! 1. P. Flores, M. Machado, M. T. Silva, J. M. Martins, On the continuous contact force models for
//!    soft materials in multibody dynamics, *Multibody System Dynamics* 25 (2011) 357–375.

use super::hysteresis_force;

/// Hysteresis factor χ = 8(1 − c_r)/(5 c_r) (–) of the Flores et al. law; c_r > 0 (the model
/// validation refuses c_r ≤ 0).
#[inline]
pub fn damping_factor(restitution: f64) -> f64 {
    8.0 * (1.0 - restitution) / (5.0 * restitution)
}

/// The Flores et al. (2011) law with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Flores {
    /// K (N/m^n).
    pub stiffness: f64,
    /// n (–).
    pub exponent: f64,
    /// c_r (–).
    pub restitution: f64,
}

impl Flores {
    /// F_N (N) at penetration δ (m), rate δ̇ (m/s) and impact velocity δ̇⁽⁻⁾ (m/s).
    pub fn normal_force(&self, delta: f64, delta_dot: f64, impact_velocity: f64) -> f64 {
        hysteresis_force(
            self.stiffness,
            self.exponent,
            damping_factor(self.restitution),
            delta,
            delta_dot,
            impact_velocity,
        )
    }
}
