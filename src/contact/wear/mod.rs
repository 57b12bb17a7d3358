//! Archard wear of the bearing surface of a revolute clearance joint: the worn profile h(θ)
//! ([`profile`]), how it enlarges the clearance the contact sees ([`WornBearing`]), and how the
//! contact's pressure and sliding wear it ([`archard`]).
//!
//! **Archard's law** (ref. 1) in its local form: the wear depth at a point of the bearing grows
//! at
//!
//! ```text
//!     ḣ = k_w · p · |v_t|           k_w = k / H   (m²/N)
//! ```
//!
//! with p the contact pressure there (Pa), v_t the slip velocity of the journal on the bearing
//! (m/s, [`crate::contact::kinematics`]), k Archard's dimensionless wear coefficient and H the
//! hardness of the worn surface (Pa). Integrated over the contact, the worn volume grows at
//! V̇ = k_w F_N |v_t|. Only the bearing wears (as in refs. 2 and 3); the journal's wear is not
//! modelled.
//!
//! **Pressure.** Hertz's line contact of the journal in its hole (ref. 4, §4.2): semi-elliptical
//! pressure over the half-width b,
//!
//! ```text
//!     p(s) = 2 F_N / (π L b) · sqrt(1 − s²/b²),    b = sqrt(4 F_N R* / (π L E*))
//!     R* = R_J R_B / (R_B − R_J),    1/E* = (1 − ν_J²)/E_J + (1 − ν_B²)/E_B
//! ```
//!
//! with s the arc length along the bearing from the contact point, L the bearing's axial length
//! (the joint's `length`). Each bin of the profile receives the bin average of ḣ, so the worn
//! volume k_w F_N |v_t| dt is conserved exactly whatever the bin width; for b much smaller than
//! a bin the whole wear lands in one bin (depth k_w F_N |v_t| dt / (L R_B Δθ)). Ref. 2 uses the
//! same two ingredients (a continuous contact force, a pressure field over the contact zone from
//! it, Archard's model); the Hertz formula assumes b ≪ R_B, and b is capped at π R_B/2 (a
//! quarter of the circumference on either side).
//!
//! **Profile update** (refs. 2, 3): the wear accumulated over an interval (e.g. M driver turns)
//! is added to the profile at its end, and the next interval runs on the worn bearing, so the
//! equations of motion stay smooth inside an interval. The worn bearing is the circle R_B
//! deepened by h(θ), θ measured in the bearing body's frame; h is linear between bin centres.
//!
//! **Small-wear approximation** (as in ref. 2): the normal stays along the eccentricity
//! n = e/|e| and the penetration is measured along it,
//!
//! ```text
//!     δ = |e| − c − h(θ_e),    θ_e = atan2(e_y, e_x) − φ_B
//!     δ̇ = ė·n − h′(θ_e) · θ̇_e,    θ̇_e = (ė·t)/|e| − ω_B
//! ```
//!
//! exact for a profile whose slope h′/R_B is small (the worn wall's normal then differs from n
//! by about h′/R_B rad). The contact points, the moment arms and the Hertz half-width keep the
//! unworn radii (second order in h/R_B).
//!
//! # References
//! 1. J. F. Archard, Contact and rubbing of flat surfaces, *Journal of Applied Physics* 24 (1953)
//!    981–988.
//! 2. P. Flores, Modeling and simulation of wear in revolute clearance joints in multibody
//!    systems, *Mechanism and Machine Theory* 44 (2009) 1211–1222.
//! 3. S. Mukras, N. H. Kim, N. A. Mauntler, T. L. Schmitz, W. G. Sawyer, Analysis of planar
//!    multibody systems with revolute joint wear, *Wear* 268 (2010) 643–652.
//! 4. K. L. Johnson, *Contact Mechanics*, Cambridge University Press, 1985.

pub mod archard;
pub mod profile;

pub use archard::ArchardWear;
pub use profile::WearProfile;

use crate::contact::ContactKinematics;
use crate::mechanics::planar::dot;

/// A bearing worn to a profile: what the contact of a worn joint sees (module documentation,
/// "Small-wear approximation").
#[derive(Debug, Clone, PartialEq)]
pub struct WornBearing {
    /// The wear depth h(θ) per bin (m), θ in the bearing body's frame.
    pub profile: WearProfile,
}

impl WornBearing {
    /// The contact angle θ_e = atan2(n_y, n_x) − φ_B (rad, in (−3π, π]) of the normal `normal`
    /// in the frame of the bearing body at angle `bearing_angle` = φ_B (rad).
    #[inline]
    pub fn contact_angle(normal: [f64; 2], bearing_angle: f64) -> f64 {
        normal[1].atan2(normal[0]) - bearing_angle
    }

    /// Deepens the penetration of `kinematics` (computed for the unworn bearing) by the wear
    /// depth h(θ_e), and its rate by −h′(θ_e) θ̇_e, for the bearing body's angle φ_B
    /// (`bearing_angle`, rad) and angular velocity ω_B (`bearing_omega`, rad/s).
    #[inline]
    pub fn apply(
        &self,
        kinematics: &mut ContactKinematics,
        bearing_angle: f64,
        bearing_omega: f64,
    ) {
        let theta = Self::contact_angle(kinematics.normal, bearing_angle);
        let (h, slope) = self.profile.depth_at(theta);
        kinematics.delta -= h;
        let c = kinematics.bearing_radius - kinematics.journal_radius;
        // Journal centred to rounding noise: n is arbitrary there and the joint free.
        if kinematics.distance > 1e-12 * c {
            let t = kinematics.tangent();
            let theta_dot = dot(kinematics.e_dot, t) / kinematics.distance - bearing_omega;
            kinematics.delta_dot -= slope * theta_dot;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::{CentreMotion, clearance_kinematics};
    use std::f64::consts::PI;

    const C: f64 = 5e-4;
    const R_J: f64 = 0.01;

    /// A profile h(θ) = h0 (1 + cos θ)/2 sampled at the bin centres.
    fn bumpy(bins: usize, h0: f64) -> WornBearing {
        let mut p = WearProfile::new(bins);
        for i in 0..bins {
            let th = p.bin_centre(i);
            p.depths_mut()[i] = 0.5 * h0 * (1.0 + th.cos());
        }
        WornBearing { profile: p }
    }

    /// The journal in a motion that sweeps θ_e past the bearing (bearing spinning too): the
    /// corrected δ̇ against central differences of the corrected δ(t), h = 1e-6 s. Tolerance
    /// 2e-7 m/s, against a slope term h′θ̇ of up to 2.5e-5 m/s (so a missing or mis-signed term
    /// fails): the difference's O(h²) error (δ''' ≲ 1 m/s³ here: 1e-12) and rounding
    /// (1e-16/1e-6), and a difference that straddles a bin centre, where the interpolated
    /// slope changes by at most (h0/2)·Δθ = 1.7e-8 m/rad, times θ̇ ≤ 2.5 rad/s: 4e-8 m/s.
    #[test]
    fn worn_delta_dot_matches_finite_difference() {
        let worn = bumpy(3600, 2e-5);
        let state = |t: f64| {
            let psi = 0.3 + 4.0 * t;
            let rho = C + 1e-5 * (5.0 * t).sin();
            let (s, c) = psi.sin_cos();
            let bearing = CentreMotion {
                position: [0.0, 0.0],
                velocity: [0.0, 0.0],
                omega: 1.5,
            };
            let journal = CentreMotion {
                position: [rho * c, rho * s],
                velocity: [
                    5e-5 * (5.0 * t).cos() * c - rho * 4.0 * s,
                    5e-5 * (5.0 * t).cos() * s + rho * 4.0 * c,
                ],
                omega: 0.0,
            };
            let mut kin = clearance_kinematics(&bearing, &journal, R_J, C);
            worn.apply(&mut kin, 0.2 + 1.5 * t, 1.5);
            kin
        };
        let h = 1e-6;
        for k in 0..25 {
            let t = 0.0371 * f64::from(k) + 0.001;
            let fd = (state(t + h).delta - state(t - h).delta) / (2.0 * h);
            let d = state(t).delta_dot;
            assert!(
                (fd - d).abs() < 2e-7,
                "t = {t}: δ̇ = {d:e}, finite difference {fd:e}"
            );
        }
    }

    /// A journal resting at the worn angle sits deeper by h: with the bearing turned by φ_B,
    /// the profile's deepest bin (θ = 0 in the bearing frame) faces the global direction φ_B.
    #[test]
    fn worn_penetration_is_deeper_by_the_depth() {
        let h0 = 3e-5;
        let worn = bumpy(360, h0);
        let phi_b = 0.7;
        let (s, c) = (phi_b + 0.5 * 2.0 * PI / 360.0).sin_cos();
        let journal = CentreMotion {
            position: [(C + 1e-6) * c, (C + 1e-6) * s],
            ..CentreMotion::default()
        };
        let mut kin = clearance_kinematics(&CentreMotion::default(), &journal, R_J, C);
        let unworn = kin.delta;
        worn.apply(&mut kin, phi_b, 0.0);
        let expected = worn.profile.depths()[0];
        assert!(
            (unworn - kin.delta - expected).abs() < 1e-18,
            "penetration drop {:e}, bin depth {expected:e}",
            unworn - kin.delta
        );
        assert!(kin.delta < 0.0, "worn by {h0:e}: the journal is free again");
    }
}
