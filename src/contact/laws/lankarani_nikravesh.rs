//! Lankarani–Nikravesh (1990) contact law with hysteresis damping (paper eq. 7).
//!
//! ```text
//!     F_N = K δⁿ [1 + 3(1 − c_r²)/4 · δ̇/δ̇⁽⁻⁾]     for δ > 0,   F_N = 0 otherwise
//! ```
//!
//! F_N (N) ≥ 0 pushes journal and bearing apart; K (N/m^n) generalised stiffness; δ (m)
//! penetration; n (–) exponent, 1.5 in the paper; δ̇ (m/s) penetration rate, > 0 while
//! compressing; δ̇⁽⁻⁾ (m/s) the rate at the start of the contact; c_r (–) coefficient of
//! restitution. The hysteresis factor χ = 3(1 − c_r²)/4 is 0.1425 for c_r = 0.9. Compression (δ̇ > 0) adds to the elastic force,
//! restitution (δ̇ < 0) takes from it, and the result is clamped at 0 (never pulls). Derived for
//! c_r close to 1 (low dissipation relative to the elastic energy). The shared rules (clamp,
//! fallback when δ̇⁽⁻⁾ is unusable) are in [`super::hysteresis_force`].
//!
//! # References
//! 1. H. M. Lankarani, P. E. Nikravesh, A contact force model with hysteresis damping for impact
//!    analysis of multibody systems, *Journal of Mechanical Design* 112 (1990) 369–376.
//! 2. S. B. Farahan, M. R. Ghazavi, S. Rahmanian, Nonlinear dynamic analysis of a four-bar
//!    mechanism having revolute joint with clearance, *Journal of Theoretical and Applied Vibration
//!    and Acoustics* (2016), eq. 7, <https://tava.isav.ir/article_19881.html>.

use super::hysteresis_force;

/// Hysteresis factor χ = 3(1 − c_r²)/4 (–) of the Lankarani–Nikravesh law.
#[inline]
pub fn damping_factor(restitution: f64) -> f64 {
    0.75 * (1.0 - restitution * restitution)
}

/// The Lankarani–Nikravesh law with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LankaraniNikravesh {
    /// K (N/m^n).
    pub stiffness: f64,
    /// n (–).
    pub exponent: f64,
    /// c_r (–).
    pub restitution: f64,
}

impl LankaraniNikravesh {
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

    const LAW: LankaraniNikravesh = LankaraniNikravesh {
        stiffness: 1e10,
        exponent: 1.5,
        restitution: 0.9,
    };

    /// parameters.md: 3(1 − 0.81)/4 = 0.1425.
    #[test]
    fn damping_factor_reference() {
        assert!(
            (damping_factor(0.9) - 0.1425).abs() < 1e-15,
            "χ = {}",
            damping_factor(0.9)
        );
        assert_eq!(damping_factor(1.0), 0.0);
    }

    /// Hand values at δ = 1e-4 m (K δ^1.5 = 1e4 N), δ̇⁽⁻⁾ = 1 m/s:
    /// δ̇ = +0.5 → 1e4 (1 + 0.07125) = 10712.5 N; δ̇ = −0.5 → 9287.5 N; δ̇ = 0 → 1e4 N;
    /// δ̇ = −10 → 1e4 (1 − 1.425) < 0 → clamped to 0.
    #[test]
    fn hand_values_and_signs() {
        let cases = [(0.5, 10712.5), (-0.5, 9287.5), (0.0, 1e4), (-10.0, 0.0)];
        for (delta_dot, expected) in cases {
            let f = LAW.normal_force(1e-4, delta_dot, 1.0);
            assert!(
                (f - expected).abs() < 1e-8,
                "δ̇ = {delta_dot}: F = {f}, expected {expected}"
            );
        }
        assert!(
            LAW.normal_force(1e-4, 0.5, 1.0) > LAW.normal_force(1e-4, 0.0, 1.0),
            "compression adds"
        );
        assert!(
            LAW.normal_force(1e-4, -0.5, 1.0) < LAW.normal_force(1e-4, 0.0, 1.0),
            "restitution reduces"
        );
    }

    /// Zero at δ = 0 and for δ < 0 whatever the rates; never negative.
    #[test]
    fn zero_at_contact_start_and_never_pulls() {
        assert_eq!(LAW.normal_force(0.0, 2.0, 1.0), 0.0);
        assert_eq!(LAW.normal_force(-1e-6, 2.0, 1.0), 0.0);
        for k in 0..200 {
            let delta_dot = -20.0 + 0.2 * f64::from(k);
            let f = LAW.normal_force(3e-5, delta_dot, 0.7);
            assert!(f >= 0.0, "δ̇ = {delta_dot}: F = {f}");
        }
    }
}
