//! Revolute joints with clearance: contact kinematics, normal-force laws, friction, stiffness,
//! contact events and the grazing guard.
//!
//! A revolute clearance joint is a journal (pin, radius R_J) inside a bearing (hole, radius
//! R_B = R_J + c). It imposes no constraint: the two bodies interact only through contact forces
//! when the journal touches the bearing wall (ref. 5). Everything here is a pure function of
//! scalars and small vectors — no global state vector — so every formulation applies the same
//! forces:
//!
//! 1. **Kinematics** ([`kinematics`], paper eqs. 1–6): e = r_J − r_B, penetration δ = |e| − c
//!    (contact when δ > 0), normal n = e/|e| (bearing centre → journal centre), tangent
//!    t = (−n_y, n_x), contact points P_B = r_B + R_B n and P_J = r_J + R_J n, penetration rate
//!    δ̇ = ė·n and slip velocity v_t = (v_PJ − v_PB)·t.
//! 2. **Normal force** ([`laws`], paper eq. 7): F_N = K δⁿ (1 + χ(c_r) δ̇/δ̇⁽⁻⁾) ≥ 0 with χ
//!    of Lankarani–Nikravesh (ref. 1), Hunt–Crossley (ref. 2), Flores et al. (ref. 3) or Hertz
//!    (χ = 0); or a line-contact elastic part in place of K δⁿ (Johnson's, Liu et al.'s: see
//!    [`laws::johnson`], [`laws::liu`]) with any of these χ.
//! 3. **Stiffness** ([`stiffness`], paper eqs. 8–9):
//!    K = 4/(3(σ_J + σ_B)) sqrt(R_J R_B/(R_B − R_J)), σ = (1 − ν²)/E.
//! 4. **Friction** ([`friction`], paper eqs. 10–11 with eq. 11 corrected): Ambrósio's modified
//!    Coulomb law F_T = −c_f c_d F_N sign(v_t) (ref. 4).
//! 5. **Application**: the journal receives −F_N n + F_T t at P_J, the bearing the opposite at
//!    P_B ([`kinematics::ContactKinematics::forces`]).
//! 6. **Events** ([`events`]): δ is the event function; the impact velocity δ̇⁽⁻⁾ is δ̇ at the
//!    located zero where δ rises, kept for the whole contact in the formulation's state vector.
//! 7. **Friction kinks** ([`kinks`]): v_t ∓ v0, v_t ∓ v1 as event functions while in contact,
//!    so that an implicit step ends at the friction law's kinks.
//! 8. **Grazing guard** ([`grazing`]): while free, the step is limited so that only grazes
//!    shallower than 1e-3 c can begin and end inside one step.
//!
//! 9. **Lubrication** ([`lubrication`]): an oil film (short or long bearing) whose force acts
//!    at any eccentricity and hands over to the dry contact law where the film gets thin.
//!
//! [`ClearanceJoint`] bundles a joint's law, friction and radii behind two calls,
//! [`ClearanceJoint::kinematics`] and [`ClearanceJoint::forces`].
//!
//! Units: SI throughout (m, m/s, N, N·m, Pa). Sign conventions: F_N ≥ 0 pushes the bodies apart;
//! F_T is signed along t and acts on the journal; moments are counter-clockwise positive.
//!
//! Corrections to Farahan et al. (2016) made here: eq. 6 (first term −ṙ n, not −r ṅ; see
//! [`kinematics`]); eq. 11 (c_d cases swapped; see [`friction::ambrosio`]); the clamp F_N ≥ 0 and
//! the fallback when no impact velocity is known, which the paper does not state (see [`laws`]);
//! the friction coefficient "0.1 mm" is dimensionless.
//!
//! # References
//! 1. H. M. Lankarani, P. E. Nikravesh, A contact force model with hysteresis damping for impact
//!    analysis of multibody systems, *Journal of Mechanical Design* 112 (1990) 369–376.
//! 2. K. H. Hunt, F. R. E. Crossley, Coefficient of restitution interpreted as damping in
//!    vibroimpact, *Journal of Applied Mechanics* 42 (1975) 440–445.
//! 3. P. Flores, M. Machado, M. T. Silva, J. M. Martins, On the continuous contact force models for
//!    soft materials in multibody dynamics, *Multibody System Dynamics* 25 (2011) 357–375.
//! 4. J. A. C. Ambrósio, Impact of rigid and flexible multibody systems: deformation description
//!    and contact models, in: *Virtual Nonlinear Multibody Systems*, NATO Science Series II
//!    vol. 103, Kluwer, 2003, pp. 57–81.
//! 5. P. Flores, J. Ambrósio, J. C. P. Claro, H. M. Lankarani, Dynamic behaviour of planar rigid
//!    multi-body systems including revolute joints with clearance, *Proc. IMechE Part K: Journal
//!    of Multi-body Dynamics* 221 (2007) 161–174.
//! 6. S. B. Farahan, M. R. Ghazavi, S. Rahmanian, Nonlinear dynamic analysis of a four-bar
//!    mechanism having revolute joint with clearance, *Journal of Theoretical and Applied Vibration
//!    and Acoustics* (2016), <https://tava.isav.ir/article_19881.html>.

pub mod corner;
pub mod events;
pub mod friction;
pub mod grazing;
pub mod kinematics;
pub mod kinks;
pub mod laws;
pub mod lubrication;
pub mod stiffness;
pub mod wear;

pub use events::{ContactMemory, ContactStats, impact_velocity};
pub use friction::friction_force;
pub use grazing::free_flight_max_step;
pub use kinematics::{CentreMotion, ContactForces, ContactKinematics, clearance_kinematics};
pub use laws::ContactLaw;
pub use lubrication::Lubrication;
pub use stiffness::generalised_stiffness;

use crate::model::{ClearanceSpec, FrictionSpec};

/// A clearance joint's contact model: normal-force law, friction law and radii, from a
/// [`ClearanceSpec`].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ClearanceJoint {
    /// Normal-force law (with K).
    pub law: ContactLaw,
    /// Friction law.
    pub friction: FrictionSpec,
    /// Journal radius R_J (m).
    pub journal_radius: f64,
    /// Radial clearance c = R_B − R_J (m) at which the dry contact begins: the bearing's, or
    /// for a lubricated joint c − h_c, where the film thins to the asperities
    /// ([`lubrication`]).
    pub clearance: f64,
    /// The oil film of a lubricated joint.
    pub lubrication: Option<Lubrication>,
}

impl ClearanceJoint {
    /// The contact model of a clearance joint ([`ContactLaw::from_spec`] for K).
    pub fn from_spec(spec: &ClearanceSpec) -> Self {
        let lubrication = Lubrication::from_spec(spec);
        ClearanceJoint {
            law: ContactLaw::from_spec(spec),
            friction: spec.friction,
            journal_radius: spec.journal_radius,
            clearance: lubrication.map_or(spec.clearance, |l| l.contact_clearance()),
            lubrication,
        }
    }

    /// Deepest penetration any contact law here is used at: a tenth of the journal radius (m).
    /// Hertzian contact assumes δ ≪ R; far beyond it the force is meaningless.
    /// A law with a range of its own (Johnson's relation, see [`laws::johnson`]) lowers it.
    pub fn max_penetration(&self) -> f64 {
        (0.1 * self.journal_radius).min(self.law.elastic.max_penetration())
    }

    /// Bearing radius R_B = R_J + c (m).
    pub fn bearing_radius(&self) -> f64 {
        self.journal_radius + self.clearance
    }

    /// Kinematics of the joint from the motion of the bearing and journal centres
    /// ([`clearance_kinematics`]).
    #[inline]
    pub fn kinematics(&self, bearing: &CentreMotion, journal: &CentreMotion) -> ContactKinematics {
        clearance_kinematics(bearing, journal, self.journal_radius, self.clearance)
    }

    /// The penetration acceleration δ̈ (m/s²) and the rate dF_N/dt (N/s) of the normal force,
    /// for the relative acceleration `e_ddot` = ë of the centres (m/s²) and the stored impact
    /// velocity `stored` (m/s, ≤ 0: none): what locates the largest force and penetration of a
    /// contact between solver steps ([`ContactKinematics::delta_ddot`],
    /// [`ContactLaw::normal_force_rate`]).
    pub fn normal_force_rate(
        &self,
        kinematics: &ContactKinematics,
        e_ddot: [f64; 2],
        stored: f64,
    ) -> (f64, f64) {
        let delta_ddot = kinematics.delta_ddot(e_ddot);
        let rate =
            self.law
                .normal_force_rate(kinematics.delta, kinematics.delta_dot, delta_ddot, stored);
        (delta_ddot, rate)
    }

    /// Normal force, friction force and their action on both bodies, given the joint's kinematics
    /// and the impact velocity δ̇⁽⁻⁾ (m/s) to use (see [`impact_velocity`]).
    /// All zero when δ ≤ 0.
    #[inline]
    pub fn forces(&self, kinematics: &ContactKinematics, impact_velocity: f64) -> ContactForces {
        let (normal, tangential) = self.force_magnitudes(kinematics, impact_velocity);
        kinematics.forces(normal, tangential)
    }

    /// The normal force F_N (N, ≥ 0) and the friction force F_T (N, on the journal along t) of
    /// [`ClearanceJoint::forces`], without their action on the bodies; (0, 0) when δ ≤ 0.
    #[inline(always)] // the right-hand sides call it at every evaluation
    pub fn force_magnitudes(
        &self,
        kinematics: &ContactKinematics,
        impact_velocity: f64,
    ) -> (f64, f64) {
        let normal = self
            .law
            .normal_force(kinematics.delta, kinematics.delta_dot, impact_velocity);
        if normal == 0.0 {
            return (0.0, 0.0);
        }
        let tangential = friction_force(&self.friction, normal, kinematics.tangential_velocity);
        (normal, tangential)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{ContactLawKind, DampingKind, Material};

    fn joint(friction: FrictionSpec) -> ClearanceJoint {
        let steel = Material {
            youngs_modulus: 207e9,
            poisson_ratio: 0.3,
        };
        ClearanceJoint::from_spec(&ClearanceSpec {
            clearance: 0.5e-3,
            journal_radius: 0.01,
            bearing_material: steel,
            journal_material: steel,
            stiffness_override: None,
            law: ContactLawKind::LankaraniNikravesh,
            damping: DampingKind::LankaraniNikravesh,
            length: None,
            restitution: 0.9,
            exponent: 1.5,
            friction,
            initial_eccentricity: [0.0, 0.0],
            lubrication: None,
            wear: None,
        })
    }

    /// End to end: journal pressed 1e-5 m into the wall along +x, moving in at 0.1 m/s and
    /// sliding at +0.5 m/s along t = +y; impact velocity 0.2 m/s.
    /// F_N = 6.9494e10 · (1e-5)^1.5 · (1 + 0.1425 · 0.5) = 2354.1 N; F_T = −0.1 F_N (full Coulomb);
    /// journal force (−F_N, F_T), journal moment R_J F_T, bearing moment −R_B F_T.
    #[test]
    fn end_to_end_forces() {
        let j = joint(FrictionSpec::Ambrosio {
            coefficient: 0.1,
            v0: 1e-4,
            v1: 1e-3,
        });
        let bearing = CentreMotion::default();
        let journal = CentreMotion {
            position: [0.5e-3 + 1e-5, 0.0],
            velocity: [0.1, 0.5],
            omega: 0.0,
        };
        let kin = j.kinematics(&bearing, &journal);
        assert!((kin.delta - 1e-5).abs() < 1e-18);
        assert!((kin.tangential_velocity - 0.5).abs() < 1e-15);
        let f = j.forces(&kin, 0.2);
        let f_n = j.law.elastic_force(1e-5) * (1.0 + 0.1425 * 0.5);
        assert!(
            (f.normal_force - f_n).abs() < 1e-9 * f_n,
            "F_N = {}, expected {f_n}",
            f.normal_force
        );
        assert!((f_n - 2354.1).abs() < 0.1, "hand value: {f_n}");
        assert!(
            (f.friction_force + 0.1 * f_n).abs() < 1e-9 * f_n,
            "F_T = {}",
            f.friction_force
        );
        assert!(
            (f.on_journal[0] + f_n).abs() < 1e-9 * f_n
                && (f.on_journal[1] + 0.1 * f_n).abs() < 1e-9 * f_n
        );
        assert!((f.journal_moment - 0.01 * f.friction_force).abs() < 1e-12 * f_n);
        assert!((f.bearing_moment + 0.0105 * f.friction_force).abs() < 1e-12 * f_n);
        // Dissipative: normal force resists the compression, friction the slip.
        assert!(f.power < 0.0, "power {}", f.power);
    }

    /// Free joint: no force, no friction computed.
    #[test]
    fn free_joint_has_no_force() {
        let j = joint(FrictionSpec::None);
        let kin = j.kinematics(
            &CentreMotion::default(),
            &CentreMotion {
                position: [1e-4, 0.0],
                velocity: [1.0, 1.0],
                omega: 3.0,
            },
        );
        assert!(kin.delta < 0.0);
        assert_eq!(j.forces(&kin, 0.5), ContactForces::default());
    }
}
