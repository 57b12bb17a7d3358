//! Hertz's elastic contact law: no damping, no energy loss.
//!
//! ```text
//!     F_N = K δⁿ     for δ > 0,   F_N = 0 otherwise
//! ```
//!
//! F_N (N) ≥ 0 pushes journal and bearing apart; K (N/m^n); δ (m) penetration; n (–), 1.5 for the
//! paper's cylinders. The coefficient of restitution and the rates are ignored (χ = 0): every
//! impact is perfectly elastic, which makes this law the reference for energy-conservation tests.
//!
//! # References
//! 1. H. Hertz, Über die Berührung fester elastischer Körper, *Journal für die reine und angewandte
//!    Mathematik* 92 (1882) 156–171.
//! 2. H. M. Lankarani, P. E. Nikravesh, A contact force model with hysteresis damping for impact
//!    analysis of multibody systems, *Journal of Mechanical Design* 112 (1990) 369–376.

use super::hysteresis_force;

/// Hysteresis factor of the Hertz law: χ = 0 whatever c_r.
#[inline]
pub fn damping_factor(_restitution: f64) -> f64 {
    0.0
}

/// The Hertz law with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hertz {
    /// K (N/m^n).
    pub stiffness: f64,
    /// n (–).
    pub exponent: f64,
}

impl Hertz {
    /// F_N (N) at penetration δ (m); the rate and impact velocity do not enter.
    pub fn normal_force(&self, delta: f64) -> f64 {
        hysteresis_force(self.stiffness, self.exponent, 0.0, delta, 0.0, 0.0)
    }
}
