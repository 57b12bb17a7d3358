//! Translational (prismatic) joints with clearance: a rectangular slider in a guide of two
//! parallel surfaces, in contact at its corners.
//!
//! The guide (body a) has a centreline through the point O (`point_a`) along the unit axis u
//! (`axis`, in the guide's frame) and normal N = perp(u); its two surfaces lie at ±h from the
//! centreline, h = w/2 + c (w the slider width, c the clearance per side). The slider (body b)
//! is a rectangle of length L and width w centred on its point `point_b`, its long side along
//! u turned into the slider's frame by −`angle` (so that it lies along the guide when
//! φ_b − φ_a = `angle`, as in the ideal prismatic joint). Its corners, numbered in the slider's
//! frame with u_b, N_b its long and short directions,
//!
//! ```text
//!     c1 = −L/2 u_b − w/2 N_b    c2 = +L/2 u_b − w/2 N_b    (against the surface at −h)
//!     c3 = +L/2 u_b + w/2 N_b    c4 = −L/2 u_b + w/2 N_b    (against the surface at +h)
//! ```
//!
//! are four point-on-plane contacts, each with its own penetration, events and impact velocity
//! (ref. 1, §2). Corner i with side σ_i (−1 for c1, c2; +1 for c3, c4) at the global position C
//! and the guide's material point Q that coincides with C:
//!
//! ```text
//!     m   = σ_i A_a N                    outward unit normal of the surface (into the wall)
//!     t   = perp(m)                      unit tangent
//!     δ   = (C − r_O)·m − h              penetration (m), > 0 in contact
//!     δ̇   = (v_C − v_Q)·m                penetration rate (m/s)
//!     v_t = (v_C − v_Q)·t                slip of the corner on the surface (m/s)
//!     δ̈   = (a_C − a_Q)·m + 2 ω_a v_t    (the last term: Coriolis, from the turning of m)
//! ```
//!
//! (δ̇ follows from δ = (C − r_O)·m − h with ṁ = ω_a perp(m) and v_Q = v_O + ω_a perp(C − r_O).)
//! The normal force F_N = K δⁿ (1 + χ(c_r) δ̇/δ̇⁽⁻⁾) and the friction force F_T are those of the
//! revolute clearance joint ([`crate::contact::laws`], [`crate::contact::friction`]); the slider
//! receives −F_N m + F_T t at C, the guide the opposite at Q. Both act at the same place, so
//! their power is −F_N δ̇ + F_T v_t, and the pair leaves no couple.
//!
//! These are written into a [`ContactKinematics`] so that the events, the impact log, the
//! outputs and the forces of the revolute joint serve the corners unchanged: `e` = C − r_O,
//! `e_dot` = v_C − v_Q, `normal` = m, both radii 0 (the forces act at C and Q themselves, no
//! moment about them), and `distance` = ∞ — a flat surface, whose normal does not turn with the
//! relative motion, so that [`ContactKinematics::delta_ddot`] gives m·ë. The Coriolis term is
//! added to the ë the formulation hands in ([`coriolis_term`]).
//!
//! Valid while the slider stays nearly aligned (tilt ≪ π/2): corners c1, c2 are only checked
//! against the surface at −h and c3, c4 against +h, and the corners are sharp (point contacts;
//! the stiffness K is given in the model, not derived from the materials). The guide's optional
//! end stops are planes across it with the outward normal m = ±A_a u and the same contact
//! (`formulation::corner_contacts`: the face's corners against the stop, δ = (C − r_O)·m − σ s
//! for the stop at s along u, σ = ±1); without them the guide is unbounded along u.
//!
//! # References
//! 1. P. Flores, J. Ambrósio, J. C. P. Claro, H. M. Lankarani, Translational joints with
//!    clearance in rigid multibody systems, *Journal of Computational and Nonlinear Dynamics*
//!    3 (2008) 011007.

use super::ContactKinematics;
use crate::mechanics::planar::{dot, perp};

/// Corner i's position in the slider's frame relative to its centre, for the unit long
/// direction `long` (u_b, slider frame), the slider length and width (m): `i` in 0..4 for
/// c1..c4 (module documentation). Also returns the corner's side σ_i (−1 or +1).
pub fn corner_offset(long: [f64; 2], length: f64, width: f64, i: usize) -> ([f64; 2], f64) {
    let short = perp(long);
    let (x, y) = match i {
        0 => (-0.5 * length, -0.5 * width),
        1 => (0.5 * length, -0.5 * width),
        2 => (0.5 * length, 0.5 * width),
        _ => (-0.5 * length, 0.5 * width),
    };
    let side = if i < 2 { -1.0 } else { 1.0 };
    (
        [x * long[0] + y * short[0], x * long[1] + y * short[1]],
        side,
    )
}

/// The guide-surface point and the corner as [`corner_kinematics`] needs them (global, m, m/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CornerMotion {
    /// Position C of the corner.
    pub corner: [f64; 2],
    /// Velocity v_C of the corner.
    pub corner_velocity: [f64; 2],
    /// Velocity v_Q of the guide's material point at C.
    pub guide_velocity: [f64; 2],
    /// Position r_O of the guide's centreline point.
    pub centreline: [f64; 2],
    /// Outward unit normal m of the surface the corner meets.
    pub normal: [f64; 2],
    /// Distance h = w/2 + c of the surface from the centreline (m).
    pub half_width: f64,
}

/// Kinematics of one corner contact (module documentation), in the form the revolute joint's
/// contact code reads.
#[inline]
pub fn corner_kinematics(m: &CornerMotion) -> ContactKinematics {
    let e = [m.corner[0] - m.centreline[0], m.corner[1] - m.centreline[1]];
    let e_dot = [
        m.corner_velocity[0] - m.guide_velocity[0],
        m.corner_velocity[1] - m.guide_velocity[1],
    ];
    let n = m.normal;
    let delta = dot(e, n) - m.half_width;
    ContactKinematics {
        e,
        e_dot,
        distance: f64::INFINITY,
        delta,
        normal: n,
        delta_dot: dot(e_dot, n),
        tangential_velocity: dot(e_dot, perp(n)),
        bearing_contact_point: [m.corner[0] - delta * n[0], m.corner[1] - delta * n[1]],
        journal_contact_point: m.corner,
        journal_radius: 0.0,
        bearing_radius: 0.0,
    }
}

/// The Coriolis part 2 ω_a v_t m of the penetration's acceleration (m/s²) for the guide's
/// angular velocity `guide_omega` = ω_a (rad/s): added to ë = a_C − a_Q, it makes
/// [`ContactKinematics::delta_ddot`] the exact δ̈ of a corner (module documentation).
pub fn coriolis_term(kinematics: &ContactKinematics, guide_omega: f64) -> [f64; 2] {
    let s = 2.0 * guide_omega * kinematics.tangential_velocity;
    [s * kinematics.normal[0], s * kinematics.normal[1]]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The corners of a 0.1 × 0.04 slider along x: c1 rear-lower, c2 front-lower, c3
    /// front-upper, c4 rear-upper, sides −, −, +, +.
    #[test]
    fn corners_in_order() {
        let expect = [
            ([-0.05, -0.02], -1.0),
            ([0.05, -0.02], -1.0),
            ([0.05, 0.02], 1.0),
            ([-0.05, 0.02], 1.0),
        ];
        for (i, (p, s)) in expect.iter().enumerate() {
            let (q, side) = corner_offset([1.0, 0.0], 0.1, 0.04, i);
            assert!(
                (q[0] - p[0]).abs() < 1e-15 && (q[1] - p[1]).abs() < 1e-15 && side == *s,
                "corner {i}: {q:?} {side} vs {p:?} {s}"
            );
        }
    }

    /// A corner 1e-5 m past the lower surface (h = 0.021 m, normal −y) moving down at 0.2 m/s
    /// and sliding at +0.3 m/s along x: δ = 1e-5, δ̇ = 0.2, v_t = (0.3, −0.2)·perp(0, −1) =
    /// (0.3, −0.2)·(1, 0) = 0.3; the contact point on the surface is 1e-5 above the corner.
    #[test]
    fn penetration_rate_and_slip() {
        let k = corner_kinematics(&CornerMotion {
            corner: [0.4, -0.021 - 1e-5],
            corner_velocity: [0.3, -0.2],
            guide_velocity: [0.0, 0.0],
            centreline: [0.0, 0.0],
            normal: [0.0, -1.0],
            half_width: 0.021,
        });
        assert!((k.delta - 1e-5).abs() < 1e-17, "δ = {}", k.delta);
        assert!((k.delta_dot - 0.2).abs() < 1e-15, "δ̇ = {}", k.delta_dot);
        assert!(
            (k.tangential_velocity - 0.3).abs() < 1e-15,
            "v_t = {}",
            k.tangential_velocity
        );
        assert!((k.bearing_contact_point[1] + 0.021).abs() < 1e-15);
        // Forces: the slider is pushed up (−F_N m = +F_N y), the guide down; no moments.
        let f = k.forces(100.0, -10.0);
        assert_eq!(f.on_journal, [-10.0, 100.0]);
        assert_eq!(f.on_bearing, [10.0, -100.0]);
        assert_eq!((f.journal_moment, f.bearing_moment), (0.0, 0.0));
        assert!((f.power - (-100.0 * 0.2 - 10.0 * 0.3)).abs() < 1e-12);
        // Flat surface: δ̈ = m·ë, no curvature term.
        assert!((k.delta_ddot([1.0, -3.0]) - 3.0).abs() < 1e-15);
    }

    /// δ̈ of a corner on a turning guide against a finite difference of δ̇ along an exact
    /// motion: guide turning at ω = 2 rad/s about the origin (surface at h = 0.01 along its
    /// local −y), corner moving at constant velocity (a_C = 0).
    #[test]
    fn corner_acceleration_includes_coriolis() {
        let omega: f64 = 2.0;
        let v_c = [0.5, -0.1];
        let c0 = [0.3, -0.012];
        let at = |t: f64| {
            let (s, c) = (omega * t).sin_cos();
            let corner = [c0[0] + v_c[0] * t, c0[1] + v_c[1] * t];
            let normal = [s, -c]; // −N turned by ωt
            corner_kinematics(&CornerMotion {
                corner,
                corner_velocity: v_c,
                guide_velocity: [-omega * corner[1], omega * corner[0]],
                centreline: [0.0, 0.0],
                normal,
                half_width: 0.01,
            })
        };
        let h = 1e-6;
        let fd = (at(h).delta_dot - at(-h).delta_dot) / (2.0 * h);
        let k = at(0.0);
        // a_Q = −ω² C (the guide's material point at C on a uniformly turning body).
        let a_q = [-omega * omega * c0[0], -omega * omega * c0[1]];
        let cor = coriolis_term(&k, omega);
        let e_ddot = [-a_q[0] + cor[0], -a_q[1] + cor[1]];
        let dd = k.delta_ddot(e_ddot);
        assert!(
            (dd - fd).abs() < 1e-6 * fd.abs().max(1.0),
            "δ̈ {dd} vs FD {fd}"
        );
        // And δ̇ is the derivative of δ.
        let fd_delta = (at(h).delta - at(-h).delta) / (2.0 * h);
        assert!(
            (k.delta_dot - fd_delta).abs() < 1e-8,
            "δ̇ {} vs {fd_delta}",
            k.delta_dot
        );
    }
}
