//! Lubricated clearance joints: the hydrodynamic force of the oil film of a journal bearing,
//! and its transition to dry contact where the film gets thin.
//!
//! A lubricated clearance joint is a journal of radius R in a bearing of radius R + c, of
//! axial length L, filled with a Newtonian oil of viscosity μ. The film exerts on the journal a
//! pressure force through the journal centre, its reaction through the bearing centre, and
//! shear torques on both (ref. 1, chapter 6; ref. 2, chapter 3).
//!
//! **Motion of the film.** With e = r_J − r_B = e n (as for dry contact,
//! [`crate::contact::kinematics`]), the thickness is h = c(1 − ε cos θ), ε = e/c, θ measured
//! from n (thinnest film at θ = 0). Reynolds' equation for two surfaces spinning at ω_J, ω_B
//! about centres moving with ė (ref. 2, eq. 2-47; ref. 1, eq. 6.5):
//!
//! ```text
//!     (1/R²) ∂/∂θ (h³ ∂p/∂θ) + ∂/∂z (h³ ∂p/∂z) = 6μ [(ω_J + ω_B) ∂h/∂θ + 2 ∂h/∂t]
//!                                            = 6μ (W sin θ − S cos θ)
//!     W = e (ω_J + ω_B − 2φ̇) = e (ω_J + ω_B) − 2 ė·t     wedge speed (m/s)
//!     S = 2 ė·n                                          squeeze speed (m/s)
//! ```
//!
//! (φ the angle of n, e φ̇ = ė·t). Written with W rather than ω_J + ω_B − 2φ̇ it stays finite
//! at e → 0. The two limits of that equation are solved in closed form for any (ε, W, S): the
//! infinitely short bearing ([`short`], Ocvirk; Pinkus & Sternlicht) and the infinitely long
//! one ([`long`], Sommerfeld), both with the π-film (Gümbel) condition, p ≥ 0.
//!
//! **Forces.** The pressure force F = F_n n + F_t t acts on the journal through its centre
//! and −F on the bearing through its centre. The shear of the film adds torques (ref. 2,
//! §3.8; Petroff's term over the whole turn and the pressure-flow term, which integrates by
//! parts to −(e/2) F_t):
//!
//! ```text
//!     T_J = −C (ω_J − ω_B) − (e/2) F_t,   T_B = C (ω_J − ω_B) − (e/2) F_t,
//!     C = 2π μ R³ L/(c √(1 − ε²))
//! ```
//!
//! Flores et al. (ref. 1) apply F alone. With the torques the film is dissipative at every
//! instant: its power F·ė + T_J ω_J + T_B ω_B = −(1/2)∫∫ p (−g) R dθ dz − C (ω_J − ω_B)² ≤ 0
//! (g the right-hand side above, negative wherever p > 0), which is what the energy books
//! (`--energy`) record as the film's dissipation.
//!
//! **Transition to dry contact** (after Flores et al. 2009, ref. 3, who use the hydrodynamic
//! force while the film is thick and the contact force once the surfaces touch; the blend below
//! is this project's choice). The surfaces' asperities meet at the film thickness h_c
//! (`contact_film_thickness`, m, default c/100). The dry contact law of the joint (its
//! `[joints.contact]` and `[joints.friction]`) acts on the penetration into that asperity
//! layer, δ = |e| − (c − h_c): a dry clearance joint of clearance c − h_c. The film force is
//! weighted by w(δ) = 1 − s(2δ/h_c), s(x) = 3x² − 2x³ on [0, 1] (0 below, 1 above):
//!
//! ```text
//!     h ≥ h_c           film only       (w = 1, no contact)
//!     h_c/2 < h < h_c   both            (w falls from 1 to 0 with zero slope at both ends)
//!     h ≤ h_c/2         contact only    (w = 0; the film force is not evaluated)
//! ```
//!
//! The total force is continuously differentiable in e (the dry laws' K δⁿ, n > 1, start with
//! zero slope). An impact event (and the impact log's entry) happens when the film thins to
//! h_c, where the dry law takes its impact velocity δ̇⁽⁻⁾. The weight makes no claim about
//! mixed lubrication: where the film force at h_c exceeds the dry force at h_c/2 the total dips
//! on the way through the layer; h_c should be of the order of the surfaces' combined
//! roughness.
//!
//! Units: SI (m, m/s, rad/s, Pa·s, N, N·m, W). Signs as for dry contact: the film's share of
//! the normal force pushes the journal towards the bearing centre when positive, F_t acts on
//! the journal along t.
//!
//! # References
//! 1. P. Flores, J. Ambrósio, J. C. P. Claro, H. M. Lankarani, *Kinematics and Dynamics of
//!    Multibody Systems with Imperfect Joints*, Lecture Notes in Applied and Computational
//!    Mechanics 34, Springer, Berlin, 2008, chapter 6 (lubricated revolute joints).
//! 2. O. Pinkus, B. Sternlicht, *Theory of Hydrodynamic Lubrication*, McGraw-Hill, New York,
//!    1961, chapters 2–3.
//! 3. P. Flores, J. Ambrósio, J. C. P. Claro, H. M. Lankarani, C. S. Koshy, Lubricated revolute
//!    joints in rigid multibody systems, *Nonlinear Dynamics* 56 (2009) 277–295.

pub mod integrals;
pub mod long;
pub mod short;

use super::kinematics::{ContactForces, ContactKinematics};
use crate::mechanics::planar::{dot, perp};
use crate::model::{ClearanceSpec, FilmModel};
use std::f64::consts::PI;

/// The film of a lubricated clearance joint, from its [`ClearanceSpec`].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Lubrication {
    /// Short or long bearing.
    pub model: FilmModel,
    /// Dynamic viscosity μ (Pa·s).
    pub viscosity: f64,
    /// Axial length L (m).
    pub length: f64,
    /// Journal radius R (m).
    pub journal_radius: f64,
    /// Radial clearance c (m) of the bearing (the dry contact uses c − h_c).
    pub clearance: f64,
    /// Film thickness h_c (m) at which the asperities meet.
    pub contact_film_thickness: f64,
}

/// How journal and bearing move relative to each other, as the film sees it.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FilmMotion {
    /// |e| (m).
    pub eccentricity: f64,
    /// ė·n (m/s), > 0 thinning the film at θ = 0.
    pub radial_rate: f64,
    /// ė·t = e φ̇ (m/s).
    pub tangential_rate: f64,
    /// ω_J (rad/s).
    pub omega_journal: f64,
    /// ω_B (rad/s).
    pub omega_bearing: f64,
}

/// The film's pressure force and shear torques at one instant (unweighted).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FilmForce {
    /// The film's normal force (N): the journal receives −`normal` n; > 0 pushes it towards the
    /// bearing centre.
    pub normal: f64,
    /// Tangential force on the journal along t (N).
    pub tangential: f64,
    /// Shear torque on the journal about its centre (N·m).
    pub journal_torque: f64,
    /// Shear torque on the bearing about its centre (N·m).
    pub bearing_torque: f64,
}

impl FilmForce {
    /// Power of the film on both bodies (W, ≤ 0): F·ė + T_J ω_J + T_B ω_B.
    pub fn power(&self, m: &FilmMotion) -> f64 {
        -self.normal * m.radial_rate
            + self.tangential * m.tangential_rate
            + self.journal_torque * m.omega_journal
            + self.bearing_torque * m.omega_bearing
    }
}

impl Lubrication {
    /// The film of a clearance joint, if the spec has a `[joints.lubrication]` (the model
    /// validation requires `length` then; a missing one gives L = 0, a film without force).
    pub fn from_spec(spec: &ClearanceSpec) -> Option<Lubrication> {
        spec.lubrication.map(|l| Lubrication {
            model: l.model,
            viscosity: l.viscosity,
            length: spec.length.unwrap_or(0.0),
            journal_radius: spec.journal_radius,
            clearance: spec.clearance,
            contact_film_thickness: l.contact_film_thickness,
        })
    }

    /// The clearance c − h_c (m) at which the dry contact begins.
    pub fn contact_clearance(&self) -> f64 {
        self.clearance - self.contact_film_thickness
    }

    /// The film's weight w ∈ [0, 1] at the centre distance |e| = `distance` (m): 1 down to the
    /// film thickness h_c, 0 from h_c/2 (module documentation).
    pub fn film_weight(&self, distance: f64) -> f64 {
        let x = 2.0 * (distance - self.contact_clearance()) / self.contact_film_thickness;
        if x <= 0.0 {
            1.0
        } else if x >= 1.0 {
            0.0
        } else {
            1.0 - x * x * (3.0 - 2.0 * x)
        }
    }

    /// The film's force and torques for the motion `m` (unweighted; `m.eccentricity` must be
    /// below c, which the weight guarantees where it is used).
    pub fn film_force(&self, m: &FilmMotion) -> FilmForce {
        let (mu, r, l, c) = (
            self.viscosity,
            self.journal_radius,
            self.length,
            self.clearance,
        );
        let eps = m.eccentricity / c;
        let wedge = m.eccentricity * (m.omega_journal + m.omega_bearing) - 2.0 * m.tangential_rate;
        let squeeze = 2.0 * m.radial_rate;
        let [f_n, f_t] = match self.model {
            FilmModel::Short => {
                short::pressure_force(mu * r * l * l * l / (2.0 * c * c * c), eps, wedge, squeeze)
            }
            FilmModel::Long => {
                long::pressure_force(6.0 * mu * r * r * r * l / (c * c * c), eps, wedge, squeeze)
            }
        };
        let couette = 2.0 * PI * mu * r * r * r * l / (c * (1.0 - eps * eps).sqrt())
            * (m.omega_journal - m.omega_bearing);
        let pressure_flow = -0.5 * m.eccentricity * f_t;
        FilmForce {
            normal: -f_n,
            tangential: f_t,
            journal_torque: -couette + pressure_flow,
            bearing_torque: couette + pressure_flow,
        }
    }

    /// The film's forces on both bodies, weighted for the transition to contact, for the
    /// joint's kinematics and the two spins (rad/s): the journal's force acts at its centre,
    /// the bearing's at its centre (so the moments are the shear torques alone). Zero where the
    /// weight is.
    pub fn forces(
        &self,
        kinematics: &ContactKinematics,
        omega_journal: f64,
        omega_bearing: f64,
    ) -> ContactForces {
        let weight = self.film_weight(kinematics.distance);
        if weight == 0.0 {
            return ContactForces::default();
        }
        let n = kinematics.normal;
        let t = perp(n);
        let motion = FilmMotion {
            eccentricity: kinematics.distance,
            radial_rate: kinematics.delta_dot,
            tangential_rate: dot(kinematics.e_dot, t),
            omega_journal,
            omega_bearing,
        };
        let f = self.film_force(&motion);
        let (normal, tangential) = (weight * f.normal, weight * f.tangential);
        let on_journal = [
            -normal * n[0] + tangential * t[0],
            -normal * n[1] + tangential * t[1],
        ];
        ContactForces {
            normal_force: normal,
            friction_force: tangential,
            on_journal,
            on_bearing: [-on_journal[0], -on_journal[1]],
            journal_moment: weight * f.journal_torque,
            bearing_moment: weight * f.bearing_torque,
            power: weight * f.power(&motion),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::integrals::tests::quadrature;
    use super::*;

    fn film(model: FilmModel) -> Lubrication {
        Lubrication {
            model,
            viscosity: 0.04,
            length: 0.02,
            journal_radius: 0.01,
            clearance: 5e-4,
            contact_film_thickness: 5e-6,
        }
    }

    /// A spread of motions: every sign of rate, spin and counter-spin, near and far from the
    /// wall.
    fn motions() -> Vec<FilmMotion> {
        let mut out = Vec::new();
        for &e in &[0.0, 1e-4, 3.5e-4, 4.9e-4] {
            for &(vr, vt) in &[(0.0, 0.0), (0.02, 0.0), (-0.03, 0.01), (0.01, -0.05)] {
                for &(wj, wb) in &[(0.0, 0.0), (100.0, 0.0), (60.0, -20.0), (-30.0, 90.0)] {
                    out.push(FilmMotion {
                        eccentricity: e,
                        radial_rate: vr,
                        tangential_rate: vt,
                        omega_journal: wj,
                        omega_bearing: wb,
                    });
                }
            }
        }
        out
    }

    /// The film dissipates at every instant, for both models (module documentation), and
    /// for the short bearing its power equals the closed expression
    /// −(μRL³/(4c³)) ∫ ((S cos θ − W sin θ)⁺)²/h̄³ dθ − C (ω_J − ω_B)² (by quadrature).
    #[test]
    fn film_power_is_the_dissipation() {
        for model in [FilmModel::Short, FilmModel::Long] {
            let l = film(model);
            for m in motions() {
                let p = l.film_force(&m).power(&m);
                assert!(
                    p <= 1e-12 * p.abs().max(1.0),
                    "{model:?} {m:?}: power {p} > 0"
                );
                if model == FilmModel::Short {
                    let eps = m.eccentricity / l.clearance;
                    let w = m.eccentricity * (m.omega_journal + m.omega_bearing)
                        - 2.0 * m.tangential_rate;
                    let s = 2.0 * m.radial_rate;
                    let integral = quadrature(
                        |t| {
                            let g = (s * t.cos() - w * t.sin()).max(0.0);
                            g * g / (1.0 - eps * t.cos()).powi(3)
                        },
                        -PI,
                        PI,
                        20000,
                    );
                    let (mu, r, len, c) = (l.viscosity, l.journal_radius, l.length, l.clearance);
                    let couette = 2.0 * PI * mu * r.powi(3) * len / (c * (1.0 - eps * eps).sqrt());
                    let dw = m.omega_journal - m.omega_bearing;
                    let expected =
                        -mu * r * len.powi(3) / (4.0 * c.powi(3)) * integral - couette * dw * dw;
                    assert!(
                        (p - expected).abs() <= 1e-8 * expected.abs().max(1e-12),
                        "{m:?}: power {p}, expected {expected}"
                    );
                }
            }
        }
    }

    /// The weight: 1 above h_c, 0 below h_c/2, ½ half-way, slopes zero at both ends (one-sided
    /// differences), and the film's forces scale with it.
    #[test]
    fn transition_weight() {
        let l = film(FilmModel::Short);
        let (c, hc) = (l.clearance, l.contact_film_thickness);
        assert_eq!(l.film_weight(c - hc), 1.0);
        assert_eq!(l.film_weight(c - 0.5 * hc), 0.0);
        assert!((l.film_weight(c - 0.75 * hc) - 0.5).abs() < 1e-12);
        // Slopes in units of 1/h_c, over a step of 1e-7 h_c: 3x² at x = 2e-7 gives 1.2e-6.
        let d = 1e-7 * hc;
        let slope_top = (l.film_weight(c - hc + d) - 1.0) / d * hc;
        let slope_bottom = l.film_weight(c - 0.5 * hc - d) / d * hc;
        assert!(
            slope_top.abs() < 1e-5 && slope_bottom.abs() < 1e-5,
            "slopes {slope_top}, {slope_bottom}"
        );
    }

    /// Central differences of the film force in each argument converge (the force is smooth
    /// where the Jacobians sample it): the difference quotients at two step sizes agree.
    #[test]
    fn film_force_is_smooth() {
        for model in [FilmModel::Short, FilmModel::Long] {
            let l = film(model);
            let m0 = FilmMotion {
                eccentricity: 3e-4,
                radial_rate: 0.01,
                tangential_rate: -0.02,
                omega_journal: 80.0,
                omega_bearing: -10.0,
            };
            type Field = fn(&mut FilmMotion) -> &mut f64;
            let fields: [(&str, Field, f64); 5] = [
                ("e", |m| &mut m.eccentricity, 3e-4),
                ("ė·n", |m| &mut m.radial_rate, 0.01),
                ("ė·t", |m| &mut m.tangential_rate, 0.02),
                ("ω_J", |m| &mut m.omega_journal, 80.0),
                ("ω_B", |m| &mut m.omega_bearing, 10.0),
            ];
            for (name, field, size) in fields {
                let slope = |h: f64| {
                    let (mut a, mut b) = (m0, m0);
                    *field(&mut a) += h;
                    *field(&mut b) -= h;
                    let (fa, fb) = (l.film_force(&a), l.film_force(&b));
                    [
                        (fa.normal - fb.normal) / (2.0 * h),
                        (fa.tangential - fb.tangential) / (2.0 * h),
                    ]
                };
                let (coarse, fine) = (slope(1e-3 * size), slope(1e-5 * size));
                for i in 0..2 {
                    assert!(
                        (coarse[i] - fine[i]).abs()
                            <= 1e-4 * coarse[i].abs().max(fine[i].abs()) + 1e-9,
                        "{model:?} ∂F/∂{name}: {coarse:?} vs {fine:?}"
                    );
                }
            }
        }
    }
}
