//! Ambrósio's modified Coulomb friction law (paper eqs. 10–11, with eq. 11 corrected).
//!
//! ```text
//!     F_T = −c_f c_d F_N · v_t/|v_t|
//!
//!           ⎧ 0                          |v_t| < v0
//!     c_d = ⎨ (|v_t| − v0)/(v1 − v0)     v0 ≤ |v_t| ≤ v1
//!           ⎩ 1                          |v_t| > v1
//! ```
//!
//! | symbol | name here | unit |
//! |---|---|---|
//! | F_T | friction force on the journal along t (the bearing gets −F_T t) | N |
//! | c_f | `coefficient` | – |
//! | c_d | dynamic correction factor, [`dynamic_correction`] | – |
//! | F_N | normal force, ≥ 0 | N |
//! | v_t | slip velocity of the journal's contact point relative to the bearing's, along t | m/s |
//! | v0, v1 | tolerances, 0 ≤ v0 < v1 | m/s |
//!
//! c_d ramps friction up linearly between v0 and v1, so F_T is continuous in v_t and does not
//! switch sign at every tiny oscillation of v_t about zero, which would force an integrator into
//! very small steps (ref. 1). At v_t = 0 the force is 0 (no stiction: this law cannot hold the
//! contact points together; below v0 the contact slides freely).
//!
//! **Correction to the paper.** Eq. 11 prints c_d = 1 for v_t < v0 and c_d = 0 for v_t > v1,
//! i.e. the first and last cases swapped. That would switch friction off at speed and on at rest,
//! the opposite of the purpose the paper itself states below eq. 11; the form above is
//! Ambrósio's (ref. 1), and is the one implemented. The paper also writes v_t for |v_t| in the
//! case conditions.
//!
//! # References
//! 1. J. A. C. Ambrósio, Impact of rigid and flexible multibody systems: deformation description
//!    and contact models, in: *Virtual Nonlinear Multibody Systems*, NATO Science Series II
//!    vol. 103, Kluwer, 2003, pp. 57–81.
//! 2. S. B. Farahan, M. R. Ghazavi, S. Rahmanian, Nonlinear dynamic analysis of a four-bar
//!    mechanism having revolute joint with clearance, *Journal of Theoretical and Applied Vibration
//!    and Acoustics* (2016), eqs. 10–11, <https://tava.isav.ir/article_19881.html>.

/// Ambrósio's dynamic correction factor c_d ∈ [0, 1] (–) at slip speed `speed` = |v_t| (m/s):
/// 0 below v0, 1 above v1, linear in between. With v1 ≤ v0 (refused by the model validation) it is
/// a step at v1.
#[inline]
pub fn dynamic_correction(speed: f64, v0: f64, v1: f64) -> f64 {
    if speed < v0 {
        0.0
    } else if speed >= v1 {
        1.0
    } else {
        (speed - v0) / (v1 - v0)
    }
}

/// Ambrósio's modified Coulomb law with its parameters.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct AmbrosioFriction {
    /// Friction coefficient c_f (–).
    pub coefficient: f64,
    /// Slip speed below which friction is off (m/s).
    pub v0: f64,
    /// Slip speed above which friction is fully developed (m/s).
    pub v1: f64,
}

impl AmbrosioFriction {
    /// F_T = −c_f c_d F_N sign(v_t) (N): the signed force on the journal along t, for the normal
    /// force `normal_force` (N) and slip velocity `tangential_velocity` (m/s). 0 when F_N ≤ 0.
    #[inline]
    pub fn force(&self, normal_force: f64, tangential_velocity: f64) -> f64 {
        if normal_force.is_nan() || normal_force <= 0.0 {
            return 0.0;
        }
        let speed = tangential_velocity.abs();
        let c_d = dynamic_correction(speed, self.v0, self.v1);
        if c_d == 0.0 {
            return 0.0;
        }
        -self.coefficient * c_d * normal_force * tangential_velocity.signum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LAW: AmbrosioFriction = AmbrosioFriction {
        coefficient: 0.1,
        v0: 1e-4,
        v1: 1e-3,
    };

    /// The three regions of c_d and their boundaries (continuity at v0 and v1).
    #[test]
    fn correction_factor_regions() {
        assert_eq!(dynamic_correction(0.0, 1e-4, 1e-3), 0.0);
        assert_eq!(dynamic_correction(0.5e-4, 1e-4, 1e-3), 0.0);
        assert_eq!(dynamic_correction(1e-4, 1e-4, 1e-3), 0.0);
        // Midway: (5.5e-4 − 1e-4)/(9e-4) = 0.5.
        assert!((dynamic_correction(5.5e-4, 1e-4, 1e-3) - 0.5).abs() < 1e-12);
        assert_eq!(dynamic_correction(1e-3, 1e-4, 1e-3), 1.0);
        assert_eq!(dynamic_correction(2.0, 1e-4, 1e-3), 1.0);
    }

    /// Below v0 friction is off — the paper's printed eq. 11 would give full friction here.
    #[test]
    fn slow_slip_has_no_friction() {
        assert_eq!(LAW.force(1000.0, 5e-5), 0.0);
        assert_eq!(LAW.force(1000.0, -5e-5), 0.0);
        assert_eq!(LAW.force(1000.0, 0.0), 0.0);
    }

    /// Ramp: v_t = ±5.5e-4 m/s → c_d = 0.5 → F_T = ∓0.1·0.5·1000 = ∓50 N.
    #[test]
    fn ramp_region_value_and_sign() {
        assert!(
            (LAW.force(1000.0, 5.5e-4) + 50.0).abs() < 1e-9,
            "{}",
            LAW.force(1000.0, 5.5e-4)
        );
        assert!(
            (LAW.force(1000.0, -5.5e-4) - 50.0).abs() < 1e-9,
            "{}",
            LAW.force(1000.0, -5.5e-4)
        );
    }

    /// Full Coulomb above v1 — the paper's printed eq. 11 would give no friction here — and always
    /// opposing the slip: F_T v_t ≤ 0.
    #[test]
    fn fast_slip_full_coulomb_opposing() {
        assert!((LAW.force(1000.0, 0.3) + 100.0).abs() < 1e-12);
        assert!((LAW.force(1000.0, -0.3) - 100.0).abs() < 1e-12);
        for k in -50..=50 {
            let v = f64::from(k) * 4e-5;
            assert!(
                LAW.force(800.0, v) * v <= 0.0,
                "v_t = {v}: F_T = {}",
                LAW.force(800.0, v)
            );
        }
    }

    #[test]
    fn no_normal_force_no_friction() {
        assert_eq!(LAW.force(0.0, 1.0), 0.0);
        assert_eq!(LAW.force(-5.0, 1.0), 0.0);
    }
}
