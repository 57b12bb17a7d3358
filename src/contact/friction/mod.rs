//! Tangential (friction) force of a clearance joint (paper eqs. 10–11).
//!
//! [`friction_force`] returns the signed tangential force F_T (N) on the **journal** along the
//! contact tangent t = perp(n) = (−n_y, n_x) (see [`crate::contact::kinematics`]); the bearing
//! receives −F_T t. With the tangential slip velocity v_t = (v_PJ − v_PB)·t of the journal's
//! contact point relative to the bearing's, friction opposes the slip: F_T v_t ≤ 0.
//!
//! Laws (from [`FrictionSpec`]): `None` gives 0 without any computation; `Ambrosio` is the modified
//! Coulomb law of [`ambrosio`]; `AmbrosioAsPrinted` is the paper's eq. 11 as printed (cases
//! swapped), a reproduction aid and not physics ([`ambrosio_as_printed`]).
//!
//! # References
//! 1. J. A. C. Ambrósio, Impact of rigid and flexible multibody systems: deformation description
//!    and contact models, in: *Virtual Nonlinear Multibody Systems*, NATO Science Series II
//!    vol. 103, Kluwer, 2003, pp. 57–81.
//! 2. S. B. Farahan, M. R. Ghazavi, S. Rahmanian, Nonlinear dynamic analysis of a four-bar
//!    mechanism having revolute joint with clearance, *Journal of Theoretical and Applied Vibration
//!    and Acoustics* (2016), eqs. 10–11, <https://tava.isav.ir/article_19881.html>.

pub mod ambrosio;
pub mod ambrosio_as_printed;

pub use ambrosio::{AmbrosioFriction, dynamic_correction};
pub use ambrosio_as_printed::{AmbrosioAsPrinted, printed_correction};

use crate::model::FrictionSpec;

/// Signed friction force F_T (N) on the journal along the tangent t, for the normal force
/// `normal_force` = F_N (N, ≥ 0) and the slip velocity `tangential_velocity` = v_t (m/s, journal
/// relative to bearing along t). `FrictionSpec::None` → 0. A non-positive F_N (no contact) gives 0.
#[inline]
pub fn friction_force(spec: &FrictionSpec, normal_force: f64, tangential_velocity: f64) -> f64 {
    match *spec {
        FrictionSpec::None => 0.0,
        FrictionSpec::Ambrosio {
            coefficient,
            v0,
            v1,
        } => AmbrosioFriction {
            coefficient,
            v0,
            v1,
        }
        .force(normal_force, tangential_velocity),
        FrictionSpec::AmbrosioAsPrinted {
            coefficient,
            v0,
            v1,
        } => AmbrosioAsPrinted {
            coefficient,
            v0,
            v1,
        }
        .force(normal_force, tangential_velocity),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn none_gives_zero() {
        assert_eq!(friction_force(&FrictionSpec::None, 1e3, 2.0), 0.0);
        assert_eq!(friction_force(&FrictionSpec::None, f64::NAN, f64::NAN), 0.0);
    }

    /// Dispatch to Ambrósio's law: c_f = 0.1, fully developed at 2 m/s: −0.1 · 500 = −50 N.
    #[test]
    fn ambrosio_dispatch() {
        let spec = FrictionSpec::Ambrosio {
            coefficient: 0.1,
            v0: 1e-4,
            v1: 1e-3,
        };
        assert!((friction_force(&spec, 500.0, 2.0) + 50.0).abs() < 1e-12);
        assert!((friction_force(&spec, 500.0, -2.0) - 50.0).abs() < 1e-12);
    }
}
