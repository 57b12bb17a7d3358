//! Hunt–Crossley (1975) contact law, with the damping factor written in the
//! Lankarani–Nikravesh form.
//!
//! ```text
//!     F_N = K δⁿ [1 + 3(1 − c_r)/2 · δ̇/δ̇⁽⁻⁾]     for δ > 0,   F_N = 0 otherwise
//! ```
//!
//! F_N (N) ≥ 0 pushes journal and bearing apart; K (N/m^n); δ (m) penetration; n (–); δ̇ (m/s) > 0
//! while compressing; δ̇⁽⁻⁾ (m/s) the rate at the start of the contact; c_r (–). Hunt and
//! Crossley's damping λ δⁿ δ̇ with λ = 3(1 − c_r)K/(2 δ̇⁽⁻⁾) gives the factor χ = 3(1 − c_r)/2
//! (0.15 for c_r = 0.9). Like Lankarani–Nikravesh it is derived for c_r close to 1. Clamp at 0 and
//! the fallback for an unusable δ̇⁽⁻⁾: [`super::hysteresis_force`].
//!
//! # References
//! 1. K. H. Hunt, F. R. E. Crossley, Coefficient of restitution interpreted as damping in
//!    vibroimpact, *Journal of Applied Mechanics* 42 (1975) 440–445.
//! 2. M. Machado, P. Moreira, P. Flores, H. M. Lankarani, Compliant contact force models in
//!    multibody dynamics: evolution of the Hertz contact theory, *Mechanism and Machine Theory* 53
//!    (2012) 99–121.

use super::hysteresis_force;

/// Hysteresis factor χ = 3(1 − c_r)/2 (–) of the Hunt–Crossley law.
#[inline]
pub fn damping_factor(restitution: f64) -> f64 {
    1.5 * (1.0 - restitution)
}

/// The Hunt–Crossley law with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HuntCrossley {
    /// K (N/m^n).
    pub stiffness: f64,
    /// n (–).
    pub exponent: f64,
    /// c_r (–).
    pub restitution: f64,
}

impl HuntCrossley {
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
