//! Eq. 11 of Farahan et al. (2016) **exactly as printed**, cases swapped: a reproduction aid,
//! not physics.
//!
//! ```text
//!     F_T = −c_f c_d F_N · v_t/|v_t|                       (eq. 10, as in the intended law)
//!
//!           ⎧ 1                          |v_t| < v0
//!     c_d = ⎨ (|v_t| − v0)/(v1 − v0)     v0 ≤ |v_t| ≤ v1     (eq. 11 as printed)
//!           ⎩ 0                          |v_t| > v1
//! ```
//!
//! Symbols and units as in [`super::ambrosio`]: F_T (N) on the journal along t, c_f
//! `coefficient` (–), F_N ≥ 0 (N), v_t the slip velocity (m/s), 0 ≤ v0 < v1 (m/s).
//!
//! **Why it exists.** The paper prints c_d = 1 below v0 and 0 above v1, the first and last cases
//! of Ambrósio's factor swapped (see [`super::ambrosio`] for the intended law). Read literally,
//! friction acts only at near-zero slip speed and vanishes once the contact slides faster than
//! v1 = 1 mm/s, so the joint is nearly frictionless. If the paper's code followed the printed
//! equation, its chaotic response at 250 rpm would follow; this law lets a user test that
//! hypothesis (`linkdyn reproduce` runs all three variants). **Do not use it to model a joint**:
//! it has full Coulomb friction at rest and none when sliding, the opposite of every friction
//! model, and it is what the paper's own sentence below eq. 11 says c_d is there to prevent.
//!
//! **Reading of the printed cases.** The paper writes v_t for |v_t| in the case conditions (the
//! law must be odd in v_t, as eq. 10 is), and leaves |v_t| = v0 to no case; here it belongs to
//! the ramp (c_d = 0 there), which is also the intended law's value at v0.
//!
//! **Discontinuities.** F_T jumps at |v_t| = v0 (c_d: 1 → 0), at |v_t| = v1 (c_d: 1 → 0) and at
//! v_t = 0 (F_T: +c_f F_N → −c_f F_N, a Coulomb sign switch). No event is placed at them: at
//! v_t = 0 the law is a Filippov system whose sliding (stick) motion would trigger events
//! without end (Zeno), and the intended law needs none, so the formulations carry no friction
//! events at all. The adaptive integrators instead shrink the step at each jump until the local
//! error is within tolerance (the error estimate of an embedded pair sees the jump as a large
//! local error); the solution stays within tolerance of the discontinuous ODE away from the
//! jumps, and the price is rejected steps and more right-hand-side evaluations, reported in
//! every run's `SolverStats` (docs/reproduce.md gives the measured cost on `farahan2016`).
//!
//! # References
//! 1. S. B. Farahan, M. R. Ghazavi, S. Rahmanian, Nonlinear dynamic analysis of a four-bar
//!    mechanism having revolute joint with clearance, *Journal of Theoretical and Applied Vibration
//!    and Acoustics* (2016), eqs. 10–11, <https://tava.isav.ir/article_19881.html>.
//! 2. J. A. C. Ambrósio, Impact of rigid and flexible multibody systems: deformation description
//!    and contact models, in: *Virtual Nonlinear Multibody Systems*, NATO Science Series II
//!    vol. 103, Kluwer, 2003, pp. 57–81 (the intended law).

/// The dynamic correction factor c_d ∈ [0, 1] (–) of eq. 11 as printed, at slip speed `speed` =
/// |v_t| (m/s): 1 below v0, the ramp (|v_t| − v0)/(v1 − v0) from v0 to v1, 0 above v1.
#[inline]
pub fn printed_correction(speed: f64, v0: f64, v1: f64) -> f64 {
    if speed < v0 {
        1.0
    } else if speed > v1 || v1 <= v0 {
        0.0
    } else {
        (speed - v0) / (v1 - v0)
    }
}

/// Eq. 11 as printed (module documentation) with its parameters.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct AmbrosioAsPrinted {
    /// Friction coefficient c_f (–).
    pub coefficient: f64,
    /// Slip speed below which c_d = 1 (m/s).
    pub v0: f64,
    /// Slip speed above which c_d = 0 (m/s).
    pub v1: f64,
}

impl AmbrosioAsPrinted {
    /// F_T = −c_f c_d F_N sign(v_t) (N) with the printed c_d: the signed force on the journal along
    /// t for the normal force `normal_force` (N) and slip velocity `tangential_velocity` (m/s).
    /// 0 when F_N ≤ 0 and at v_t = 0 exactly (sign(0) = 0).
    #[inline]
    pub fn force(&self, normal_force: f64, tangential_velocity: f64) -> f64 {
        if normal_force.is_nan() || normal_force <= 0.0 || tangential_velocity == 0.0 {
            return 0.0;
        }
        let c_d = printed_correction(tangential_velocity.abs(), self.v0, self.v1);
        -self.coefficient * c_d * normal_force * tangential_velocity.signum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::friction::dynamic_correction;

    const LAW: AmbrosioAsPrinted = AmbrosioAsPrinted {
        coefficient: 0.1,
        v0: 1e-4,
        v1: 1e-3,
    };

    /// The printed cases: full friction below v0, none above v1, the same ramp in between.
    #[test]
    fn printed_factor_regions() {
        assert_eq!(printed_correction(0.0, 1e-4, 1e-3), 1.0);
        assert_eq!(printed_correction(0.5e-4, 1e-4, 1e-3), 1.0);
        assert_eq!(printed_correction(1e-4, 1e-4, 1e-3), 0.0);
        assert!((printed_correction(5.5e-4, 1e-4, 1e-3) - 0.5).abs() < 1e-12);
        assert_eq!(printed_correction(1e-3, 1e-4, 1e-3), 1.0);
        assert_eq!(printed_correction(1.0000001e-3, 1e-4, 1e-3), 0.0);
        assert_eq!(printed_correction(2.0, 1e-4, 1e-3), 0.0);
    }

    /// Outside the ramp the printed factor is the intended one swapped: c_d + c_d' = 1 below v0
    /// and above v1; inside the ramp both are the same.
    #[test]
    fn swapped_against_intended() {
        for k in 0..200 {
            let v = f64::from(k) * 1e-5;
            let printed = printed_correction(v, 1e-4, 1e-3);
            let intended = dynamic_correction(v, 1e-4, 1e-3);
            if !(1e-4..=1e-3).contains(&v) {
                assert_eq!(
                    printed + intended,
                    1.0,
                    "|v_t| = {v}: {printed} + {intended}"
                );
            } else {
                assert!(
                    (printed - intended).abs() < 1e-12,
                    "|v_t| = {v}: {printed} vs {intended}"
                );
            }
        }
    }

    /// Values and signs: slow slip has full Coulomb (∓0.1 · 1000 = ∓100 N), fast slip none, and
    /// the force always opposes the slip.
    #[test]
    fn values_and_opposition() {
        assert!((LAW.force(1000.0, 5e-5) + 100.0).abs() < 1e-12);
        assert!((LAW.force(1000.0, -5e-5) - 100.0).abs() < 1e-12);
        assert_eq!(LAW.force(1000.0, 0.3), 0.0);
        assert_eq!(LAW.force(1000.0, -0.3), 0.0);
        assert_eq!(LAW.force(1000.0, 0.0), 0.0);
        assert_eq!(LAW.force(0.0, 5e-5), 0.0);
        for k in -50..=50 {
            let v = f64::from(k) * 4e-5;
            assert!(
                LAW.force(800.0, v) * v <= 0.0,
                "v_t = {v}: F_T = {}",
                LAW.force(800.0, v)
            );
        }
    }
}
