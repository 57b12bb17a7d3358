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

#[cfg(test)]
mod tests {
    use super::*;

    /// K = 6.9494e10, n = 1.5, δ = 1e-5 m: δ^1.5 = 3.16227766e-8, F = 2197.6 N (hand value);
    /// n = 1: F = K δ = 6.9494e5 N.
    #[test]
    fn hand_values() {
        let law = Hertz {
            stiffness: 6.9494e10,
            exponent: 1.5,
        };
        let f = law.normal_force(1e-5);
        let expected = 6.9494e10 * 1e-5_f64 * 1e-5_f64.sqrt();
        assert!(
            (f - expected).abs() < 1e-9 * expected,
            "F = {f}, expected {expected}"
        );
        assert!((f - 2197.6).abs() < 0.05, "F = {f}, hand value 2197.6");
        let linear = Hertz {
            stiffness: 6.9494e10,
            exponent: 1.0,
        };
        assert!((linear.normal_force(1e-5) - 6.9494e5).abs() < 1e-6, "n = 1");
    }

    #[test]
    fn zero_outside_contact_and_no_damping() {
        let law = Hertz {
            stiffness: 1e10,
            exponent: 1.5,
        };
        assert_eq!(law.normal_force(0.0), 0.0);
        assert_eq!(law.normal_force(-1e-3), 0.0);
        assert_eq!(damping_factor(0.3), 0.0);
    }
}
