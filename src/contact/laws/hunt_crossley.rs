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

#[cfg(test)]
mod tests {
    use super::*;

    const LAW: HuntCrossley = HuntCrossley {
        stiffness: 1e10,
        exponent: 1.5,
        restitution: 0.9,
    };

    #[test]
    fn damping_factor_values() {
        assert!(
            (damping_factor(0.9) - 0.15).abs() < 1e-15,
            "χ = {}",
            damping_factor(0.9)
        );
        assert!(
            (damping_factor(0.5) - 0.75).abs() < 1e-15,
            "χ(0.5) = {}",
            damping_factor(0.5)
        );
        assert_eq!(damping_factor(1.0), 0.0);
    }

    /// Hand values at δ = 1e-4 m (K δ^1.5 = 1e4 N), δ̇⁽⁻⁾ = 2 m/s, χ = 0.15:
    /// δ̇ = +1 → 1e4 (1 + 0.075) = 10750 N; δ̇ = −1 → 9250 N; δ̇ = −20 → 1e4 (1 − 1.5) → 0.
    #[test]
    fn hand_values_and_signs() {
        let cases = [(1.0, 10750.0), (-1.0, 9250.0), (0.0, 1e4), (-20.0, 0.0)];
        for (delta_dot, expected) in cases {
            let f = LAW.normal_force(1e-4, delta_dot, 2.0);
            assert!(
                (f - expected).abs() < 1e-8,
                "δ̇ = {delta_dot}: F = {f}, expected {expected}"
            );
        }
    }

    #[test]
    fn zero_at_contact_start_and_never_pulls() {
        assert_eq!(LAW.normal_force(0.0, 1.0, 1.0), 0.0);
        assert_eq!(LAW.normal_force(-1e-6, 1.0, 1.0), 0.0);
        for k in 0..200 {
            let delta_dot = -20.0 + 0.2 * f64::from(k);
            assert!(
                LAW.normal_force(3e-5, delta_dot, 0.7) >= 0.0,
                "δ̇ = {delta_dot}"
            );
        }
    }
}
