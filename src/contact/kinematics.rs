//! Kinematics of a revolute clearance joint: eccentricity, penetration, contact frame, contact
//! points and their relative velocity (paper eqs. 1–6), and how the contact forces act on the two
//! bodies.
//!
//! Conventions (all vectors global, m, m/s):
//!
//! ```text
//!     e   = r_J − r_B                    eccentricity: journal centre minus bearing centre
//!     δ   = |e| − c                      penetration (m), > 0 in contact (paper eq. 2)
//!     n   = e/|e|                        unit normal, bearing centre → journal centre
//!     t   = perp(n) = (−n_y, n_x)        unit tangent, n rotated +90°
//!     P_B = r_B + R_B n                  contact point on the bearing wall (paper eq. 3)
//!     P_J = r_J + R_J n                  contact point on the journal surface (paper eq. 4)
//!     v_P = v_centre + ω × (P − centre)  velocity of the body's material point at P
//!     δ̇   = ė·n = (v_PJ − v_PB)·n        penetration rate, > 0 while moving into the wall
//!     v_t = (v_PJ − v_PB)·t              slip velocity of the journal on the bearing
//!         = ė·t + R_J ω_J − R_B ω_B
//! ```
//!
//! with R_B = R_J + c. The contact points are material points of the two bodies, so v_t includes
//! the spin of journal and bearing. If |e| is below 1e-12 c (journal centred to rounding noise) the
//! normal is undefined and n = (1, 0) is used: δ = −c there, the joint is free and no force uses n.
//!
//! Forces (N) and moments (N·m, counter-clockwise positive):
//!
//! ```text
//!     on the journal, at P_J:  F_J = −F_N n + F_T t    moment about r_J: R_J n × F_J =  R_J F_T
//!     on the bearing, at P_B:  F_B = +F_N n − F_T t    moment about r_B: R_B n × F_B = −R_B F_T
//! ```
//!
//! F_N ≥ 0 from a [`crate::contact::laws::ContactLaw`], F_T from
//! [`crate::contact::friction::friction_force`]. Newton's third law holds for the forces. During
//! penetration P_J − P_B = δ n, so the pair of friction forces leaves a couple δ F_T (second order
//! in the small penetration; the normal forces are collinear and leave none). The power of the
//! pair is −F_N δ̇ + F_T v_t.
//!
//! Relation to the paper: its eq. 6 gives the relative velocity of the bearing's contact point
//! with respect to the journal's as −r ṅ + (ω_b R_b − ω_j R_j − r α̇) t. Differentiating eq. 5
//! gives −ṙ n − r ṅ + (ω_b R_b − ω_j R_j) t with ṅ = α̇ t, that is
//! −ṙ n + (ω_b R_b − ω_j R_j − r α̇) t:
//! the first term of eq. 6 must read **−ṙ n** (as printed the normal part is missing and r α̇
//! appears twice). With r = |e|, ṙ = δ̇ and r α̇ = ė·t this is −δ̇ n − v_t t, the negative of the
//! journal-relative velocity used here.
//!
//! # References
//! 1. P. Flores, J. Ambrósio, J. C. P. Claro, H. M. Lankarani, Dynamic behaviour of planar rigid
//!    multi-body systems including revolute joints with clearance, *Proc. IMechE Part K: Journal
//!    of Multi-body Dynamics* 221 (2007) 161–174.
//! 2. S. B. Farahan, M. R. Ghazavi, S. Rahmanian, Nonlinear dynamic analysis of a four-bar
//!    mechanism having revolute joint with clearance, *Journal of Theoretical and Applied Vibration
//!    and Acoustics* (2016), eqs. 1–6, <https://tava.isav.ir/article_19881.html>.

use crate::mechanics::planar::{cross, dot, perp};

/// Position, velocity and angular velocity of a joint centre (bearing or journal centre), all
/// global: what [`clearance_kinematics`] needs from each body.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct CentreMotion {
    /// Position of the centre (m).
    pub position: [f64; 2],
    /// Velocity of the centre (m/s).
    pub velocity: [f64; 2],
    /// Angular velocity of the body carrying it (rad/s, counter-clockwise positive).
    pub omega: f64,
}

impl From<crate::mechanics::planar::PointState> for CentreMotion {
    fn from(p: crate::mechanics::planar::PointState) -> Self {
        CentreMotion {
            position: p.position,
            velocity: p.velocity,
            omega: p.omega,
        }
    }
}

/// Geometry and relative motion of a clearance joint at one instant (conventions in the module
/// documentation).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ContactKinematics {
    /// Eccentricity e = r_J − r_B (m).
    pub e: [f64; 2],
    /// Its rate ė = v_J − v_B (m/s).
    pub e_dot: [f64; 2],
    /// |e| (m).
    pub distance: f64,
    /// Penetration δ = |e| − c (m); > 0 in contact.
    pub delta: f64,
    /// Unit normal n = e/|e|, from the bearing centre towards the journal centre.
    pub normal: [f64; 2],
    /// Penetration rate δ̇ = ė·n (m/s).
    pub delta_dot: f64,
    /// Slip velocity v_t = (v_PJ − v_PB)·t (m/s), journal relative to bearing.
    pub tangential_velocity: f64,
    /// Contact point on the bearing, P_B = r_B + R_B n (m).
    pub bearing_contact_point: [f64; 2],
    /// Contact point on the journal, P_J = r_J + R_J n (m).
    pub journal_contact_point: [f64; 2],
    /// Journal radius R_J (m).
    pub journal_radius: f64,
    /// Bearing radius R_B = R_J + c (m).
    pub bearing_radius: f64,
}

/// Contact forces of a clearance joint applied to its two bodies (conventions in the module
/// documentation).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct ContactForces {
    /// Normal force F_N (N, ≥ 0).
    pub normal_force: f64,
    /// Friction force F_T on the journal along t (N, signed).
    pub friction_force: f64,
    /// Force on the journal, −F_N n + F_T t (N), applied at P_J.
    pub on_journal: [f64; 2],
    /// Force on the bearing, +F_N n − F_T t = −`on_journal` (N), applied at P_B.
    pub on_bearing: [f64; 2],
    /// Moment of `on_journal` about the journal centre, R_J F_T (N·m).
    pub journal_moment: f64,
    /// Moment of `on_bearing` about the bearing centre, −R_B F_T (N·m).
    pub bearing_moment: f64,
    /// Power of the two forces together, −F_N δ̇ + F_T v_t (W).
    pub power: f64,
}

impl ContactKinematics {
    /// Unit tangent t = perp(n) = (−n_y, n_x).
    #[inline]
    pub fn tangent(&self) -> [f64; 2] {
        perp(self.normal)
    }

    /// Penetration acceleration δ̈ (m/s²) for the relative acceleration ë = r̈_J − r̈_B of the
    /// two centres (m/s²). From δ̇ = ė·n and ṅ = t (t·ė)/|e|:
    ///
    /// ```text
    ///     δ̈ = n·ë + (t·ė)²/|e| = n·ë + (|ė|² − δ̇²)/|e|
    /// ```
    ///
    /// With the journal centred to rounding noise (n undefined, the joint free) the second term
    /// is left out.
    pub fn delta_ddot(&self, e_ddot: [f64; 2]) -> f64 {
        let along = dot(e_ddot, self.normal);
        if self.distance > 1e-12 * (self.bearing_radius - self.journal_radius) {
            let slip = dot(self.e_dot, self.tangent());
            along + slip * slip / self.distance
        } else {
            along
        }
    }

    /// |ė| (m/s): the relative speed of the two centres.
    pub fn relative_speed(&self) -> f64 {
        self.e_dot[0].hypot(self.e_dot[1])
    }

    /// The forces and moments on journal and bearing for a normal force F_N (N) and a friction
    /// force F_T (N, on the journal along t).
    #[inline]
    pub fn forces(&self, normal_force: f64, friction_force: f64) -> ContactForces {
        let n = self.normal;
        let t = self.tangent();
        let on_journal = [
            -normal_force * n[0] + friction_force * t[0],
            -normal_force * n[1] + friction_force * t[1],
        ];
        let on_bearing = [-on_journal[0], -on_journal[1]];
        let journal_arm = [self.journal_radius * n[0], self.journal_radius * n[1]];
        let bearing_arm = [self.bearing_radius * n[0], self.bearing_radius * n[1]];
        ContactForces {
            normal_force,
            friction_force,
            on_journal,
            on_bearing,
            journal_moment: cross(journal_arm, on_journal),
            bearing_moment: cross(bearing_arm, on_bearing),
            power: -normal_force * self.delta_dot + friction_force * self.tangential_velocity,
        }
    }
}

/// Kinematics of the clearance joint with bearing centre `bearing`, journal centre `journal`,
/// journal radius `journal_radius` = R_J (m) and radial clearance `clearance` = c (m); see the
/// module documentation for every convention.
#[inline]
pub fn clearance_kinematics(
    bearing: &CentreMotion,
    journal: &CentreMotion,
    journal_radius: f64,
    clearance: f64,
) -> ContactKinematics {
    let bearing_radius = journal_radius + clearance;
    let e = [
        journal.position[0] - bearing.position[0],
        journal.position[1] - bearing.position[1],
    ];
    let e_dot = [
        journal.velocity[0] - bearing.velocity[0],
        journal.velocity[1] - bearing.velocity[1],
    ];
    // sqrt rather than hypot: |e| is far from overflow and sqrt is several times cheaper in
    // this hot path.
    let distance = (e[0] * e[0] + e[1] * e[1]).sqrt();
    // Below 1e-12 c the direction of e is rounding noise (positions carry errors of ~1e-16 m);
    // any fixed unit vector will do, the joint being free there.
    let normal = if distance > 1e-12 * clearance {
        [e[0] / distance, e[1] / distance]
    } else {
        [1.0, 0.0]
    };
    let t = perp(normal);
    ContactKinematics {
        e,
        e_dot,
        distance,
        delta: distance - clearance,
        normal,
        delta_dot: dot(e_dot, normal),
        tangential_velocity: dot(e_dot, t) + journal_radius * journal.omega
            - bearing_radius * bearing.omega,
        bearing_contact_point: [
            bearing.position[0] + bearing_radius * normal[0],
            bearing.position[1] + bearing_radius * normal[1],
        ],
        journal_contact_point: [
            journal.position[0] + journal_radius * normal[0],
            journal.position[1] + journal_radius * normal[1],
        ],
        journal_radius,
        bearing_radius,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const C: f64 = 5e-4;
    const R_J: f64 = 0.01;

    fn rot(phi: f64, s: [f64; 2]) -> [f64; 2] {
        let (sn, cs) = phi.sin_cos();
        [cs * s[0] - sn * s[1], sn * s[0] + cs * s[1]]
    }

    /// A test motion: bearing centre on a curve, journal centre at a varying eccentricity about
    /// it (crossing in and out of contact), both bodies spinning. Returns the centre states and
    /// the body angles at time t.
    fn motion(t: f64) -> (CentreMotion, CentreMotion, f64, f64) {
        let rb = [0.1 + 0.2 * t + 0.3 * t * t, -0.05 + 0.1 * (3.0 * t).sin()];
        let vb = [0.2 + 0.6 * t, 0.3 * (3.0 * t).cos()];
        let rho = C + 2e-5 * (7.0 * t).sin();
        let rho_dot = 1.4e-4 * (7.0 * t).cos();
        let psi = 0.3 + 1.3 * t;
        let psi_dot = 1.3;
        let (s, c) = psi.sin_cos();
        let e = [rho * c, rho * s];
        let e_dot = [
            rho_dot * c - rho * psi_dot * s,
            rho_dot * s + rho * psi_dot * c,
        ];
        let phi_b = 0.4 + 2.0 * t;
        let phi_j = -0.3 + 5.0 * t - t * t;
        let bearing = CentreMotion {
            position: rb,
            velocity: vb,
            omega: 2.0,
        };
        let journal = CentreMotion {
            position: [rb[0] + e[0], rb[1] + e[1]],
            velocity: [vb[0] + e_dot[0], vb[1] + e_dot[1]],
            omega: 5.0 - 2.0 * t,
        };
        (bearing, journal, phi_b, phi_j)
    }

    /// δ̇ against central differences of δ(t); tolerance 1e-9 m/s: the O(h²) error with h = 1e-5
    /// s is ~1e-10 · |δ'''| (δ''' ~ 1e-2 m/s³), and rounding ~1e-16/1e-5 = 1e-11.
    #[test]
    fn delta_dot_matches_finite_difference() {
        let h = 1e-5;
        for k in 0..20 {
            let t = 0.05 * f64::from(k);
            let kin = |t| {
                let (b, j, _, _) = motion(t);
                clearance_kinematics(&b, &j, R_J, C)
            };
            let fd = (kin(t + h).delta - kin(t - h).delta) / (2.0 * h);
            let k0 = kin(t);
            assert!(
                (fd - k0.delta_dot).abs() < 1e-9,
                "t = {t}: δ̇ = {:e}, finite difference {fd:e}",
                k0.delta_dot
            );
        }
    }

    /// δ̈ against central differences of δ̇(t), with ë from central differences of ė(t).
    /// Tolerance 1e-6 m/s²: both differences carry O(h²) ≈ 1e-10·|δ⁗| errors (δ⁗ ≲ 1e2 m/s⁴
    /// here) and rounding ~1e-16·|ė|/h ≈ 1e-11 m/s².
    #[test]
    fn delta_ddot_matches_finite_difference() {
        let h = 1e-5;
        for k in 0..20 {
            let t = 0.05 * f64::from(k);
            let kin = |t| {
                let (b, j, _, _) = motion(t);
                clearance_kinematics(&b, &j, R_J, C)
            };
            let (k_plus, k_minus) = (kin(t + h), kin(t - h));
            let e_ddot = [
                (k_plus.e_dot[0] - k_minus.e_dot[0]) / (2.0 * h),
                (k_plus.e_dot[1] - k_minus.e_dot[1]) / (2.0 * h),
            ];
            let fd = (k_plus.delta_dot - k_minus.delta_dot) / (2.0 * h);
            let exact = kin(t).delta_ddot(e_ddot);
            assert!(
                (fd - exact).abs() < 1e-6,
                "t = {t}: δ̈ = {exact:e}, finite difference {fd:e}"
            );
        }
    }

    /// v_t and δ̇ against central differences of the positions of the two material points that
    /// are at P_J and P_B at time t0 (each follows its body's centre and rotation).
    /// Tolerance 1e-8 m/s: O(h²) ≈ 1e-10 · |P'''| with |P'''| ≲ 10 m/s³, plus rounding.
    #[test]
    fn slip_velocity_matches_material_points() {
        let h = 1e-5;
        for k in 0..20 {
            let t0 = 0.05 * f64::from(k);
            let (b0, j0, phi_b0, phi_j0) = motion(t0);
            let kin = clearance_kinematics(&b0, &j0, R_J, C);
            // Body-frame coordinates of the material points at P_J, P_B at t0.
            let s_j = rot(
                -phi_j0,
                [
                    kin.journal_radius * kin.normal[0],
                    kin.journal_radius * kin.normal[1],
                ],
            );
            let s_b = rot(
                -phi_b0,
                [
                    kin.bearing_radius * kin.normal[0],
                    kin.bearing_radius * kin.normal[1],
                ],
            );
            let point = |t: f64| {
                let (b, j, phi_b, phi_j) = motion(t);
                let aj = rot(phi_j, s_j);
                let ab = rot(phi_b, s_b);
                (
                    [j.position[0] + aj[0], j.position[1] + aj[1]],
                    [b.position[0] + ab[0], b.position[1] + ab[1]],
                )
            };
            let (pj_p, pb_p) = point(t0 + h);
            let (pj_m, pb_m) = point(t0 - h);
            let rel = [
                ((pj_p[0] - pj_m[0]) - (pb_p[0] - pb_m[0])) / (2.0 * h),
                ((pj_p[1] - pj_m[1]) - (pb_p[1] - pb_m[1])) / (2.0 * h),
            ];
            let vt = dot(rel, kin.tangent());
            let vn = dot(rel, kin.normal);
            assert!(
                (vt - kin.tangential_velocity).abs() < 1e-8,
                "t = {t0}: v_t = {:e}, material points {vt:e}",
                kin.tangential_velocity
            );
            assert!(
                (vn - kin.delta_dot).abs() < 1e-8,
                "t = {t0}: δ̇ = {:e}, material points {vn:e}",
                kin.delta_dot
            );
            // The contact points themselves.
            let pj = kin.journal_contact_point;
            assert!((pj[0] - (j0.position[0] + R_J * kin.normal[0])).abs() < 1e-15);
            let pb = kin.bearing_contact_point;
            assert!((pb[1] - (b0.position[1] + (R_J + C) * kin.normal[1])).abs() < 1e-15);
        }
    }

    /// The journal spinning about its fixed centre slides on a fixed bearing at v_t = R_J ω;
    /// the bearing spinning about its centre gives v_t = −R_B ω; centres at rest give δ̇ = 0.
    #[test]
    fn pure_rotation_gives_surface_speed() {
        let bearing = CentreMotion::default();
        let journal = CentreMotion {
            position: [3e-4, -4e-4],
            velocity: [0.0, 0.0],
            omega: 7.0,
        };
        let kin = clearance_kinematics(&bearing, &journal, R_J, C);
        assert!(
            (kin.tangential_velocity - R_J * 7.0).abs() < 1e-15,
            "v_t = {}",
            kin.tangential_velocity
        );
        assert_eq!(kin.delta_dot, 0.0);
        assert!(kin.delta.abs() < 1e-18, "|e| = c: δ = {}", kin.delta);
        let spinning_bearing = CentreMotion {
            omega: 3.0,
            ..CentreMotion::default()
        };
        let still_journal = CentreMotion {
            omega: 0.0,
            ..journal
        };
        let kin = clearance_kinematics(&spinning_bearing, &still_journal, R_J, C);
        assert!(
            (kin.tangential_velocity + (R_J + C) * 3.0).abs() < 1e-15,
            "v_t = {}",
            kin.tangential_velocity
        );
    }

    /// Newton's third law for the forces; moments R_J F_T and −R_B F_T; the pair's total moment
    /// about any point is the couple δ F_T; the power is −F_N δ̇ + F_T v_t = Σ F·v_P.
    #[test]
    fn third_law_moments_and_power() {
        let (b, j, _, _) = motion(0.37);
        let kin = clearance_kinematics(&b, &j, R_J, C);
        assert!(
            kin.delta > 0.0,
            "test motion in contact at t = 0.37: δ = {}",
            kin.delta
        );
        let (f_n, f_t) = (1234.0, -56.0);
        let f = kin.forces(f_n, f_t);
        assert_eq!(f.on_journal[0] + f.on_bearing[0], 0.0);
        assert_eq!(f.on_journal[1] + f.on_bearing[1], 0.0);
        // Journal force is −F_N along n (pushed back towards the bearing centre) and F_T along t.
        assert!((dot(f.on_journal, kin.normal) + f_n).abs() < 1e-9);
        assert!((dot(f.on_journal, kin.tangent()) - f_t).abs() < 1e-9);
        assert!(
            (f.journal_moment - R_J * f_t).abs() < 1e-12,
            "journal moment {}",
            f.journal_moment
        );
        assert!(
            (f.bearing_moment + (R_J + C) * f_t).abs() < 1e-12,
            "bearing moment {}",
            f.bearing_moment
        );
        let about = [0.3, -0.2];
        let arm = |p: [f64; 2]| [p[0] - about[0], p[1] - about[1]];
        let total = cross(arm(kin.journal_contact_point), f.on_journal)
            + cross(arm(kin.bearing_contact_point), f.on_bearing);
        assert!(
            (total - kin.delta * f_t).abs() < 1e-9,
            "couple {total:e} vs δ F_T = {:e}",
            kin.delta * f_t
        );
        // Power from the material-point velocities.
        let t = kin.tangent();
        let vpj = [
            j.velocity[0] + j.omega * R_J * t[0],
            j.velocity[1] + j.omega * R_J * t[1],
        ];
        let vpb = [
            b.velocity[0] + b.omega * (R_J + C) * t[0],
            b.velocity[1] + b.omega * (R_J + C) * t[1],
        ];
        let power = dot(f.on_journal, vpj) + dot(f.on_bearing, vpb);
        assert!(
            (power - f.power).abs() < 1e-9 * f_n,
            "power {power} vs {}",
            f.power
        );
    }

    /// A centred journal: any fixed normal, δ = −c, finite everything.
    #[test]
    fn centred_journal_is_free_and_finite() {
        let centre = CentreMotion {
            position: [0.2, 0.1],
            velocity: [1.0, -1.0],
            omega: 2.0,
        };
        let kin = clearance_kinematics(&centre, &centre, R_J, C);
        assert_eq!(kin.normal, [1.0, 0.0]);
        assert_eq!(kin.delta, -C);
        assert!(kin.delta_dot.is_finite() && kin.tangential_velocity.is_finite());
    }
}
