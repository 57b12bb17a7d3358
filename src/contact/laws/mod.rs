//! Normal contact-force laws of the form F_N = F_e(δ) (1 + χ δ̇/δ̇⁽⁻⁾) (paper eq. 7 with
//! F_e = K δⁿ).
//!
//! Every law is an elastic part F_e(δ) ([`Elastic`]) and a hysteresis factor χ(c_r). The four
//! point-contact laws share the Hertzian elastic part K δⁿ and differ only in χ; the two
//! line-contact laws, [`johnson`] (Johnson's cylinder in a cylindrical hole, implicit in δ) and
//! [`liu`] (Liu et al.'s conformal contact), need the bearing's axial length and take any of the
//! four χ (`damping` in the model file; docs/contact_laws.md compares them all):
//!
//! | law | χ(c_r) | file |
//! |---|---|---|
//! | Lankarani–Nikravesh (1990), paper eq. 7 | 3(1 − c_r²)/4 | `lankarani_nikravesh.rs` |
//! | Hunt–Crossley (1975) | 3(1 − c_r)/2 | `hunt_crossley.rs` |
//! | Flores et al. (2011) | 8(1 − c_r)/(5 c_r) | `flores.rs` |
//! | Hertz | 0 | `hertz.rs` |
//!
//! | symbol | name here | unit |
//! |---|---|---|
//! | F_N | normal force, ≥ 0, pressing journal and bearing apart | N |
//! | K | `stiffness` | N/m^n |
//! | n | `exponent` (1.5 for cylinders in the paper) | – |
//! | δ = \|e\| − c | `delta`, penetration, > 0 in contact | m |
//! | δ̇ | `delta_dot`, > 0 while compressing, < 0 while restituting | m/s |
//! | δ̇⁽⁻⁾ | `impact_velocity`, δ̇ at the instant the contact began, kept for the whole contact | m/s |
//! | c_r | `restitution`, in (0, 1] | – |
//!
//! Sign convention: F_N ≥ 0 is the magnitude of the push; it acts on the journal as −F_N n and on
//! the bearing as +F_N n, n = e/|e| (see [`crate::contact::kinematics`]).
//!
//! Rules shared by every law (implemented once, in [`damped_force`]):
//! - F_N = 0 for δ ≤ 0 (no contact), so the force is continuous at the start of contact.
//! - F_N is clamped at 0 from below. The damping term is negative during restitution (δ̇ < 0) and
//!   for δ̇/δ̇⁽⁻⁾ < −1/χ it would make the bodies pull each other, which a dry contact cannot do.
//!   The paper does not state this clamp; parameters.md requires it.
//! - Fallback when δ̇⁽⁻⁾ is not usable (≤ [`MIN_IMPACT_VELOCITY`], or not finite): the damping term
//!   is switched off and F_N = K δⁿ. This happens when the wall is reached with a vanishing normal
//!   speed, or when a contact has no recorded impact (e.g. present at t = 0) and the penetration
//!   is not growing: the formulation then hands in the current δ̇
//!   ([`crate::contact::events::impact_velocity`]).
//!   Why this fallback: the hysteresis term is calibrated on the impact velocity so that the energy
//!   lost in one impact is ΔE ≈ (1 − c_r²) · ½ m_eff δ̇⁽⁻⁾² (ref. 1), which tends to 0 with δ̇⁽⁻⁾;
//!   the elastic law is that limit. Keeping the ratio δ̇/δ̇⁽⁻⁾ with a tiny denominator would
//!   instead create an arbitrarily large damping coefficient χ K δⁿ/δ̇⁽⁻⁾ (an artificially stiff,
//!   almost plastic contact) out of a number that is only rounding noise.
//!
//! Valid for impact velocities well below the speed of sound in the materials and, for the
//! Lankarani–Nikravesh law, for c_r close to 1 (the paper notes it after eq. 9); Flores et al.
//! (2011) is meant for any c_r.
//!
//! # References
//! 1. H. M. Lankarani, P. E. Nikravesh, A contact force model with hysteresis damping for impact
//!    analysis of multibody systems, *Journal of Mechanical Design* 112 (1990) 369–376.
//! 2. K. H. Hunt, F. R. E. Crossley, Coefficient of restitution interpreted as damping in
//!    vibroimpact, *Journal of Applied Mechanics* 42 (1975) 440–445.
//! 3. P. Flores, M. Machado, M. T. Silva, J. M. Martins, On the continuous contact force models for
//!    soft materials in multibody dynamics, *Multibody System Dynamics* 25 (2011) 357–375.
//! 4. S. B. Farahan, M. R. Ghazavi, S. Rahmanian, Nonlinear dynamic analysis of a four-bar
//!    mechanism having revolute joint with clearance, *Journal of Theoretical and Applied Vibration
//!    and Acoustics* (2016), eq. 7, <https://tava.isav.ir/article_19881.html>.

pub mod flores;
pub mod hertz;
pub mod hunt_crossley;
pub mod johnson;
pub mod lankarani_nikravesh;
pub mod liu;

pub use flores::Flores;
pub use hertz::Hertz;
pub use hunt_crossley::HuntCrossley;
pub use johnson::JohnsonLine;
pub use lankarani_nikravesh::LankaraniNikravesh;
pub use liu::LiuLine;

use super::stiffness::{compliance, generalised_stiffness};
use crate::model::{ClearanceSpec, ContactLawKind, DampingKind};

/// Impact velocities δ̇⁽⁻⁾ at or below this (m/s) are not used: the damping term is switched off
/// (see the module documentation). 1 µm/s: an impact that slow carries a kinetic energy of order
/// 1e-12 J per kg of effective mass, far below anything the damping term is meant to dissipate,
/// while the damping coefficient χ K δⁿ/δ̇⁽⁻⁾ it would create is a million times that of a
/// 1 m/s impact.
pub const MIN_IMPACT_VELOCITY: f64 = 1e-6;

/// F_N = max(0, K δⁿ (1 + χ δ̇/δ̇⁽⁻⁾)) for δ > 0, else 0; with δ̇⁽⁻⁾ ≤ [`MIN_IMPACT_VELOCITY`] (or
/// not finite) the damping term is off: F_N = K δⁿ. Units and signs as in the module
/// documentation; `chi` is the law's hysteresis factor χ (–).
#[inline]
pub fn hysteresis_force(
    stiffness: f64,
    exponent: f64,
    chi: f64,
    delta: f64,
    delta_dot: f64,
    impact_velocity: f64,
) -> f64 {
    // A NaN penetration gives "no force": NaN states are reported by the integrator's
    // finiteness check, not hidden behind a NaN force here.
    if delta.is_nan() || delta <= 0.0 {
        return 0.0;
    }
    damped_force(
        stiffness * penetration_power(delta, exponent),
        chi,
        delta_dot,
        impact_velocity,
    )
}

/// The one place where the hysteresis factor meets the elastic force: F_N = max(0, F_e (1 + χ
/// δ̇/δ̇⁽⁻⁾)) for an elastic force `elastic` = F_e (N) > 0, or F_e itself where δ̇⁽⁻⁾ is not
/// usable or χ = 0 (see the module documentation). Every law goes through it.
#[inline(always)]
pub fn damped_force(elastic: f64, chi: f64, delta_dot: f64, impact_velocity: f64) -> f64 {
    let usable = impact_velocity.is_finite() && impact_velocity > MIN_IMPACT_VELOCITY;
    if !usable || chi == 0.0 {
        return elastic;
    }
    (elastic * (1.0 + chi * delta_dot / impact_velocity)).max(0.0)
}

/// Time derivative dF_N/dt (N/s) of [`hysteresis_force`] along a motion with penetration
/// `delta` = δ (m), rate `delta_dot` = δ̇ (m/s) and acceleration `delta_ddot` = δ̈ (m/s²), with
/// the stored impact velocity `stored` = δ̇⁽⁻⁾ (m/s; ≤ 0 when none is stored, and the law then
/// uses the current δ̇ in its place, as [`crate::contact::impact_velocity`] does):
///
/// ```text
///     stored δ̇⁽⁻⁾ usable:   dF_N/dt = K n δⁿ⁻¹ δ̇ (1 + χ δ̇/δ̇⁽⁻⁾) + K δⁿ χ δ̈/δ̇⁽⁻⁾
///     δ̇ in its place:       F_N = K δⁿ (1 + χ),  dF_N/dt = K n δⁿ⁻¹ δ̇ (1 + χ)
///     damping off:          dF_N/dt = K n δⁿ⁻¹ δ̇
/// ```
///
/// 0 where the force is 0 (δ ≤ 0, or clamped at 0 by a fast separation). Used to find the
/// instants of largest force between solver steps (the impact log's true peaks).
pub fn hysteresis_force_rate(
    law: (f64, f64, f64),
    delta: f64,
    delta_dot: f64,
    delta_ddot: f64,
    stored: f64,
) -> f64 {
    let (stiffness, exponent, chi) = law;
    if delta.is_nan() || delta <= 0.0 {
        return 0.0;
    }
    let power = penetration_power(delta, exponent);
    // d(δⁿ)/dt = n δⁿ⁻¹ δ̇ = n δⁿ δ̇/δ (δ > 0 here).
    let power_rate = exponent * power * delta_dot / delta;
    damped_force_rate(
        (stiffness, power, power_rate),
        chi,
        delta_dot,
        delta_ddot,
        stored,
    )
}

/// dF_N/dt (N/s) of [`damped_force`] for an elastic force F_e = s·e with scale s, shape e and
/// shape rate ė = de/dt (`elastic` = (s, e, ė)); the power laws pass (K, δⁿ, n δⁿ⁻¹ δ̇), the
/// line laws (1, F_e, F_e′ δ̇). Cases and arguments as in [`hysteresis_force_rate`].
#[inline]
pub fn damped_force_rate(
    elastic: (f64, f64, f64),
    chi: f64,
    delta_dot: f64,
    delta_ddot: f64,
    stored: f64,
) -> f64 {
    let (scale, shape, shape_rate) = elastic;
    let impact = if stored > 0.0 { stored } else { delta_dot };
    let usable = impact.is_finite() && impact > MIN_IMPACT_VELOCITY;
    if !usable || chi == 0.0 {
        return scale * shape_rate;
    }
    if stored <= 0.0 {
        return scale * shape_rate * (1.0 + chi);
    }
    let factor = 1.0 + chi * delta_dot / stored;
    if factor <= 0.0 {
        return 0.0;
    }
    scale * (shape_rate * factor + shape * chi * delta_ddot / stored)
}

/// δⁿ, with the Hertzian n = 1.5 as δ √δ (a powf costs several times a sqrt, and this is
/// evaluated at every right-hand side in contact).
#[inline]
pub fn penetration_power(delta: f64, exponent: f64) -> f64 {
    if exponent == 1.5 {
        delta * delta.sqrt()
    } else {
        delta.powf(exponent)
    }
}

/// The hysteresis factor χ(c_r) (–) of a damping kind: the coefficient of δ̇/δ̇⁽⁻⁾.
pub fn damping_factor(damping: DampingKind, restitution: f64) -> f64 {
    match damping {
        DampingKind::LankaraniNikravesh => lankarani_nikravesh::damping_factor(restitution),
        DampingKind::HuntCrossley => hunt_crossley::damping_factor(restitution),
        DampingKind::Flores => flores::damping_factor(restitution),
        DampingKind::None => hertz::damping_factor(restitution),
    }
}

/// The elastic part F_e(δ) of a law, with its parameters.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "kebab-case", tag = "relation")]
pub enum Elastic {
    /// K δⁿ: the point-contact (Hertz-type) laws.
    Power {
        /// Generalised stiffness K (N/m^n).
        stiffness: f64,
        /// Exponent n (–).
        exponent: f64,
    },
    /// Johnson's line contact, implicit in δ ([`johnson`]).
    Johnson(JohnsonLine),
    /// Liu et al.'s conformal line contact ([`liu`]).
    Liu(LiuLine),
}

impl Elastic {
    /// F_e (N) and dF_e/dδ (N/m) at penetration `delta` (m); (0, 0) for δ ≤ 0.
    pub fn force_and_slope(&self, delta: f64) -> (f64, f64) {
        match self {
            Elastic::Power {
                stiffness,
                exponent,
            } => {
                if delta.is_nan() || delta <= 0.0 {
                    return (0.0, 0.0);
                }
                let power = penetration_power(delta, *exponent);
                (stiffness * power, stiffness * exponent * power / delta)
            }
            Elastic::Johnson(law) => law.force_and_slope(delta),
            Elastic::Liu(law) => law.force_and_slope(delta),
        }
    }

    /// F_e (N) at penetration `delta` (m); 0 for δ ≤ 0. For the power laws exactly K δⁿ as
    /// [`hysteresis_force`] computes it.
    pub fn force(&self, delta: f64) -> f64 {
        match self {
            Elastic::Power {
                stiffness,
                exponent,
            } => {
                if delta.is_nan() || delta <= 0.0 {
                    return 0.0;
                }
                stiffness * penetration_power(delta, *exponent)
            }
            _ => self.force_and_slope(delta).0,
        }
    }

    /// Elastic energy ∫₀^δ F_e dδ (J) stored at penetration `delta` (m); 0 for δ ≤ 0.
    pub fn energy(&self, delta: f64) -> f64 {
        if delta.is_nan() || delta <= 0.0 {
            return 0.0;
        }
        match self {
            Elastic::Power {
                stiffness,
                exponent,
            } => stiffness * delta.powf(exponent + 1.0) / (exponent + 1.0),
            Elastic::Johnson(law) => law.energy(delta),
            Elastic::Liu(law) => law.energy(delta),
        }
    }

    /// Deepest penetration (m) the relation itself is valid at (∞ where it sets none).
    pub fn max_penetration(&self) -> f64 {
        match self {
            Elastic::Johnson(law) => law.max_penetration(),
            _ => f64::INFINITY,
        }
    }
}

/// A normal-force law with its parameters: an elastic part and a hysteresis factor behind one
/// interface.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ContactLaw {
    /// Which law (as named in the model file).
    pub kind: ContactLawKind,
    /// The elastic part F_e(δ).
    pub elastic: Elastic,
    /// Which hysteresis factor χ(c_r).
    pub damping: DampingKind,
    /// Coefficient of restitution c_r ∈ (0, 1] (–).
    pub restitution: f64,
    /// χ(c_r), computed once: the right-hand sides use it at every evaluation in contact.
    chi: f64,
}

impl ContactLaw {
    /// The law of a clearance joint. Power laws: K from the spec's `stiffness_override` if
    /// given, otherwise from the materials with R_B = R_J + c ([`generalised_stiffness`]). Line
    /// laws: E* = 1/(σ_J + σ_B) and the bearing length L, which the model validation requires
    /// for them (a missing one gives L = 0, a law without force, never a panic).
    pub fn from_spec(spec: &ClearanceSpec) -> ContactLaw {
        let modulus = 1.0 / (compliance(spec.journal_material) + compliance(spec.bearing_material));
        let length = spec.length.unwrap_or(0.0);
        let elastic = match spec.law {
            ContactLawKind::Johnson => {
                Elastic::Johnson(JohnsonLine::new(length, spec.clearance, modulus))
            }
            ContactLawKind::Liu => Elastic::Liu(LiuLine::new(length, spec.clearance, modulus)),
            ContactLawKind::LankaraniNikravesh
            | ContactLawKind::HuntCrossley
            | ContactLawKind::Flores
            | ContactLawKind::Hertz => Elastic::Power {
                stiffness: spec.stiffness_override.unwrap_or_else(|| {
                    generalised_stiffness(
                        spec.journal_radius,
                        spec.journal_radius + spec.clearance,
                        spec.journal_material,
                        spec.bearing_material,
                    )
                }),
                exponent: spec.exponent,
            },
        };
        ContactLaw {
            kind: spec.law,
            elastic,
            damping: spec.damping,
            restitution: spec.restitution,
            chi: damping_factor(spec.damping, spec.restitution),
        }
    }

    /// A point-contact law K δⁿ (1 + χ(c_r) δ̇/δ̇⁽⁻⁾) with the stiffness K (N/m^n) given: the
    /// corner contacts of a prismatic-clearance joint (`contact::corner`), which have no
    /// bearing geometry to compute K from.
    pub fn power(
        kind: ContactLawKind,
        damping: DampingKind,
        stiffness: f64,
        exponent: f64,
        restitution: f64,
    ) -> ContactLaw {
        ContactLaw {
            kind,
            elastic: Elastic::Power {
                stiffness,
                exponent,
            },
            damping,
            restitution,
            chi: damping_factor(damping, restitution),
        }
    }

    /// The hysteresis factor χ(c_r) of this law (–): the coefficient of δ̇/δ̇⁽⁻⁾.
    #[inline]
    pub fn damping_factor(&self) -> f64 {
        self.chi
    }

    /// Normal force F_N (N, ≥ 0) at penetration `delta` (m), penetration rate `delta_dot` (m/s)
    /// and impact velocity `impact_velocity` = δ̇⁽⁻⁾ (m/s); 0 for δ ≤ 0. See [`damped_force`]
    /// for the clamp and the fallback when δ̇⁽⁻⁾ is not usable.
    #[inline]
    pub fn normal_force(&self, delta: f64, delta_dot: f64, impact_velocity: f64) -> f64 {
        match &self.elastic {
            Elastic::Power {
                stiffness,
                exponent,
            } => hysteresis_force(
                *stiffness,
                *exponent,
                self.chi,
                delta,
                delta_dot,
                impact_velocity,
            ),
            _ => self.line_normal_force(delta, delta_dot, impact_velocity),
        }
    }

    /// [`ContactLaw::normal_force`] of the line-contact laws, kept out of line: inlined, their
    /// solves would grow the right-hand sides of every run, and the point-contact laws' runs
    /// then lost the inlining of the force evaluation (+1.9 % instructions on the reference
    /// run, measured with callgrind).
    #[inline(never)]
    fn line_normal_force(&self, delta: f64, delta_dot: f64, impact_velocity: f64) -> f64 {
        if delta.is_nan() || delta <= 0.0 {
            return 0.0;
        }
        damped_force(
            self.elastic.force(delta),
            self.chi,
            delta_dot,
            impact_velocity,
        )
    }

    /// dF_N/dt (N/s) along a motion (δ, δ̇, δ̈) with the stored impact velocity `stored` (≤ 0:
    /// none); see [`hysteresis_force_rate`] and [`damped_force_rate`].
    pub fn normal_force_rate(
        &self,
        delta: f64,
        delta_dot: f64,
        delta_ddot: f64,
        stored: f64,
    ) -> f64 {
        match &self.elastic {
            Elastic::Power {
                stiffness,
                exponent,
            } => hysteresis_force_rate(
                (*stiffness, *exponent, self.chi),
                delta,
                delta_dot,
                delta_ddot,
                stored,
            ),
            line => {
                if delta.is_nan() || delta <= 0.0 {
                    return 0.0;
                }
                let (force, slope) = line.force_and_slope(delta);
                damped_force_rate(
                    (1.0, force, slope * delta_dot),
                    self.chi,
                    delta_dot,
                    delta_ddot,
                    stored,
                )
            }
        }
    }

    /// The partial derivatives (∂F_N/∂δ, ∂F_N/∂δ̇, ∂F_N/∂δ̇⁽⁻⁾) of [`ContactLaw::normal_force`]
    /// at (δ, δ̇, δ̇⁽⁻⁾), in closed form from dF_e/dδ (the implicit function theorem for
    /// Johnson's law): with the damping term active and F_N > 0,
    /// F_e′ (1 + χ δ̇/δ̇⁽⁻⁾), F_e χ/δ̇⁽⁻⁾, −F_e χ δ̇/δ̇⁽⁻⁾²; with it off, (F_e′, 0, 0); all 0 where
    /// F_N = 0. `None` for the power laws: their Jacobians keep the central differences they
    /// were built with, so that runs with them stay bit-identical.
    pub fn line_slopes(
        &self,
        delta: f64,
        delta_dot: f64,
        impact_velocity: f64,
    ) -> Option<(f64, f64, f64)> {
        if let Elastic::Power { .. } = self.elastic {
            return None;
        }
        if delta.is_nan() || delta <= 0.0 {
            return Some((0.0, 0.0, 0.0));
        }
        let (force, slope) = self.elastic.force_and_slope(delta);
        let usable = impact_velocity.is_finite() && impact_velocity > MIN_IMPACT_VELOCITY;
        if !usable || self.chi == 0.0 {
            return Some((slope, 0.0, 0.0));
        }
        let ratio = delta_dot / impact_velocity;
        let factor = 1.0 + self.chi * ratio;
        if factor <= 0.0 {
            return Some((0.0, 0.0, 0.0));
        }
        Some((
            slope * factor,
            force * self.chi / impact_velocity,
            -force * self.chi * ratio / impact_velocity,
        ))
    }

    /// The elastic force F_e (N) at `delta`: the part of F_N that stores energy.
    pub fn elastic_force(&self, delta: f64) -> f64 {
        self.elastic.force(delta)
    }

    /// Elastic energy (J) stored at `delta` (m).
    pub fn elastic_energy(&self, delta: f64) -> f64 {
        self.elastic.energy(delta)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{FrictionSpec, Material};

    /// Reference joint (docs/reference_parameters.md) with a 20 mm long bearing.
    fn spec(
        law: ContactLawKind,
        damping: DampingKind,
        stiffness_override: Option<f64>,
    ) -> ClearanceSpec {
        let steel = Material {
            youngs_modulus: 207e9,
            poisson_ratio: 0.3,
        };
        ClearanceSpec {
            clearance: 0.5e-3,
            journal_radius: 0.01,
            bearing_material: steel,
            journal_material: steel,
            stiffness_override,
            law,
            damping,
            length: Some(0.02),
            restitution: 0.9,
            exponent: 1.5,
            friction: FrictionSpec::None,
            initial_eccentricity: [0.0, 0.0],
            lubrication: None,
            wear: None,
        }
    }

    const DAMPINGS: [DampingKind; 4] = [
        DampingKind::LankaraniNikravesh,
        DampingKind::HuntCrossley,
        DampingKind::Flores,
        DampingKind::None,
    ];

    /// Every law with its damping: the four point-contact laws with their own, each line
    /// law with each of the four.
    fn every_law() -> Vec<ContactLaw> {
        let mut laws: Vec<ContactLaw> = [
            (
                ContactLawKind::LankaraniNikravesh,
                DampingKind::LankaraniNikravesh,
            ),
            (ContactLawKind::HuntCrossley, DampingKind::HuntCrossley),
            (ContactLawKind::Flores, DampingKind::Flores),
            (ContactLawKind::Hertz, DampingKind::None),
        ]
        .iter()
        .map(|&(k, d)| ContactLaw::from_spec(&spec(k, d, None)))
        .collect();
        for kind in [ContactLawKind::Johnson, ContactLawKind::Liu] {
            for damping in DAMPINGS {
                laws.push(ContactLaw::from_spec(&spec(kind, damping, None)));
            }
        }
        laws
    }

    /// E* = E/(2(1 − ν²)) for steel on steel (Pa).
    const E_STAR: f64 = 207e9 / (2.0 * 0.91);

    /// The elastic force of each law at δ, computed here from its formula: K δ^1.5; Johnson's
    /// implicit relation by bisection on δ(F) over [0, A/e³]; Liu's explicit formula.
    fn elastic_by_formula(kind: ContactLawKind, delta: f64) -> f64 {
        let (l, dr) = (0.02, 0.5e-3);
        match kind {
            ContactLawKind::Johnson => {
                let k = std::f64::consts::PI * l * E_STAR;
                let a = 4.0 * k * dr;
                let penetration = |f: f64| f / k * ((a / f).ln() - 1.0);
                let (mut lo, mut hi) = (0.0, a * (-3.0f64).exp());
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    if penetration(mid) < delta {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                0.5 * (lo + hi)
            }
            ContactLawKind::Liu => {
                0.5 * std::f64::consts::PI
                    * E_STAR
                    * l
                    * delta
                    * (delta / (2.0 * (dr + delta))).sqrt()
            }
            _ => 6.949_4e10 * delta.powf(1.5),
        }
    }

    /// K follows from the materials with R_B = R_J + c unless overridden; the line laws take E*
    /// and L.
    #[test]
    fn from_spec_takes_stiffness_from_materials_or_override() {
        let ln = DampingKind::LankaraniNikravesh;
        let law = ContactLaw::from_spec(&spec(ContactLawKind::LankaraniNikravesh, ln, None));
        let Elastic::Power {
            stiffness,
            exponent,
        } = law.elastic
        else {
            panic!("{:?}", law.elastic);
        };
        assert!(
            (stiffness - 6.9494e10).abs() < 1e-5 * 6.9494e10,
            "K = {stiffness:e}"
        );
        assert_eq!(exponent, 1.5);
        assert_eq!(law.restitution, 0.9);
        let law = ContactLaw::from_spec(&spec(ContactLawKind::Hertz, DampingKind::None, Some(1e9)));
        let f = law.elastic.force(1e-4);
        assert!((f - 1e3).abs() <= 1e-12 * 1e3, "F_e = {f}");
        assert_eq!(law.kind, ContactLawKind::Hertz);
        let law = ContactLaw::from_spec(&spec(ContactLawKind::Johnson, ln, None));
        let Elastic::Johnson(j) = law.elastic else {
            panic!("{:?}", law.elastic);
        };
        let k = std::f64::consts::PI * 0.02 * E_STAR;
        assert!(
            (j.modulus_length - k).abs() <= 1e-14 * k,
            "πLE* = {:e}",
            j.modulus_length
        );
        assert_eq!(j.clearance, 0.5e-3);
    }

    /// Every law and damping at hand-checked points: F_N = F_e(δ) (1 + χ δ̇/δ̇⁽⁻⁾) with F_e
    /// from [`elastic_by_formula`] and χ at c_r = 0.9: 0.1425 (L-N), 0.15 (H-C),
    /// 8·0.1/(5·0.9) = 0.177… (Flores), 0 (none). Relative 1e-9: the reference K is quoted to 5
    /// digits, so the power laws compare with the K the law computed, the others with the
    /// formulas directly (Johnson's solve is good to 1e-13).
    #[test]
    fn every_law_matches_its_formula_with_each_damping() {
        let chi_of = |d: DampingKind| match d {
            DampingKind::LankaraniNikravesh => 0.1425,
            DampingKind::HuntCrossley => 0.15,
            DampingKind::Flores => 0.8 / 4.5,
            DampingKind::None => 0.0,
        };
        for law in every_law() {
            let chi = chi_of(law.damping);
            assert!(
                (law.damping_factor() - chi).abs() < 1e-15,
                "{:?}/{:?}: χ = {}",
                law.kind,
                law.damping,
                law.damping_factor()
            );
            for delta in [1e-7_f64, 1e-6, 1e-5, 5e-5] {
                let elastic = match law.elastic {
                    Elastic::Power { stiffness, .. } => stiffness * delta.powf(1.5),
                    _ => elastic_by_formula(law.kind, delta),
                };
                // δ̇/δ̇⁽⁻⁾ = 0.5.
                let f = law.normal_force(delta, 0.5, 1.0);
                let expected = elastic * (1.0 + 0.5 * chi);
                assert!(
                    (f - expected).abs() < 1e-9 * expected,
                    "{:?}/{:?} δ = {delta:e}: F = {f}, expected {expected}",
                    law.kind,
                    law.damping
                );
            }
        }
    }

    /// The point laws at hand-computed points, one row per law: the hysteresis factor χ at
    /// two restitutions, and F_N at δ = 1e-4 m where K δ^1.5 = 1e4 N (K = 1e10), for a
    /// compressing, resting, restituting and fast-separating δ̇ against the stored δ̇⁽⁻⁾:
    /// F = 1e4 (1 + χ δ̇/δ̇⁽⁻⁾), clamped at 0. Hertz: the reference joint's K = 6.9494e10 at
    /// δ = 1e-5 m gives 2197.6 N, and n = 1 gives K δ.
    #[test]
    fn point_laws_at_hand_computed_points() {
        type Force = fn(f64, f64, f64) -> f64;
        struct Row {
            law: &'static str,
            /// (c_r, χ(c_r)) by hand.
            factors: [(f64, f64); 2],
            factor: fn(f64) -> f64,
            /// δ̇⁽⁻⁾ and (δ̇, F) pairs.
            stored: f64,
            cases: [(f64, f64); 4],
            force: Force,
        }
        let rows = [
            Row {
                law: "lankarani-nikravesh, c_r = 0.9 (χ = 3·0.19/4)",
                factors: [(0.9, 0.1425), (1.0, 0.0)],
                factor: lankarani_nikravesh::damping_factor,
                stored: 1.0,
                cases: [(0.5, 10712.5), (-0.5, 9287.5), (0.0, 1e4), (-10.0, 0.0)],
                force: |d, dd, v| {
                    let law = LankaraniNikravesh {
                        stiffness: 1e10,
                        exponent: 1.5,
                        restitution: 0.9,
                    };
                    law.normal_force(d, dd, v)
                },
            },
            Row {
                law: "hunt-crossley, c_r = 0.9 (χ = 3·0.1/2)",
                factors: [(0.9, 0.15), (0.5, 0.75)],
                factor: hunt_crossley::damping_factor,
                stored: 2.0,
                cases: [(1.0, 10750.0), (-1.0, 9250.0), (0.0, 1e4), (-20.0, 0.0)],
                force: |d, dd, v| {
                    let law = HuntCrossley {
                        stiffness: 1e10,
                        exponent: 1.5,
                        restitution: 0.9,
                    };
                    law.normal_force(d, dd, v)
                },
            },
            Row {
                law: "flores, c_r = 0.8 (χ = 8·0.2/4)",
                factors: [(0.8, 0.4), (0.5, 1.6)],
                factor: flores::damping_factor,
                stored: 1.0,
                cases: [(0.5, 12000.0), (-0.5, 8000.0), (0.0, 1e4), (-3.0, 0.0)],
                force: |d, dd, v| {
                    let law = Flores {
                        stiffness: 1e10,
                        exponent: 1.5,
                        restitution: 0.8,
                    };
                    law.normal_force(d, dd, v)
                },
            },
            Row {
                law: "hertz (no damping)",
                factors: [(0.3, 0.0), (0.9, 0.0)],
                factor: hertz::damping_factor,
                stored: 1.0,
                cases: [(0.5, 1e4), (-0.5, 1e4), (0.0, 1e4), (-10.0, 1e4)],
                force: |d, _, _| {
                    let law = Hertz {
                        stiffness: 1e10,
                        exponent: 1.5,
                    };
                    law.normal_force(d)
                },
            },
        ];
        for row in &rows {
            for (restitution, chi) in row.factors {
                let got = (row.factor)(restitution);
                assert!(
                    (got - chi).abs() < 1e-15,
                    "{}: χ({restitution}) = {got}, by hand {chi}",
                    row.law
                );
            }
            for (delta_dot, expected) in row.cases {
                let f = (row.force)(1e-4, delta_dot, row.stored);
                assert!(
                    (f - expected).abs() < 1e-8,
                    "{}: δ̇ = {delta_dot}: F = {f}, by hand {expected}",
                    row.law
                );
            }
            // Never pulls, whatever the rate.
            for k in 0..200 {
                let delta_dot = -20.0 + 0.2 * f64::from(k);
                let f = (row.force)(3e-5, delta_dot, 0.7);
                assert!(f >= 0.0, "{}: δ̇ = {delta_dot}: F = {f}", row.law);
            }
        }
        let reference = Hertz {
            stiffness: 6.9494e10,
            exponent: 1.5,
        };
        let f = reference.normal_force(1e-5);
        assert!((f - 2197.6).abs() < 0.05, "F = {f}, hand value 2197.6");
        let linear = Hertz {
            stiffness: 6.9494e10,
            exponent: 1.0,
        };
        assert!((linear.normal_force(1e-5) - 6.9494e5).abs() < 1e-6, "n = 1");
    }

    /// The stiffness ordering at the reference joint that docs/contact_laws.md states: at
    /// δ = 1 µm Liu's law (L = 20 mm) is stiffer than the Hertz-type K δ^1.5, and Johnson's
    /// the stiffest (its F grows almost linearly, with a logarithmic correction).
    #[test]
    fn stiffness_ordering_at_the_reference_joint() {
        let delta = 1e-6;
        let power = elastic_by_formula(ContactLawKind::Hertz, delta);
        let liu = elastic_by_formula(ContactLawKind::Liu, delta);
        let johnson = elastic_by_formula(ContactLawKind::Johnson, delta);
        assert!(
            power < liu && liu < johnson,
            "{power:e} {liu:e} {johnson:e}"
        );
    }

    /// Shared rules: zero at and below δ = 0, never negative, fallback when δ̇⁽⁻⁾ is unusable.
    #[test]
    fn shared_rules() {
        assert_eq!(hysteresis_force(1e10, 1.5, 0.1425, 0.0, 1.0, 1.0), 0.0);
        assert_eq!(hysteresis_force(1e10, 1.5, 0.1425, -1e-5, 1.0, 1.0), 0.0);
        assert_eq!(hysteresis_force(1e10, 1.5, 0.1425, f64::NAN, 1.0, 1.0), 0.0);
        // Strong restitution: 1 + 0.1425·(−10) < 0 → clamped to 0.
        assert_eq!(hysteresis_force(1e10, 1.5, 0.1425, 1e-4, -10.0, 1.0), 0.0);
        // Unusable impact velocity: elastic only, whatever δ̇.
        for v in [0.0, MIN_IMPACT_VELOCITY, -0.3, f64::NAN, f64::INFINITY] {
            let f = hysteresis_force(1e10, 1.5, 0.1425, 1e-4, 5.0, v);
            assert!(
                (f - 1e4).abs() < 1e-8,
                "impact velocity {v}: F = {f}, expected 1e4"
            );
        }
        for law in every_law() {
            for delta in [0.0, -1e-5, f64::NAN] {
                assert_eq!(law.normal_force(delta, 1.0, 1.0), 0.0, "{:?}", law.kind);
            }
            if law.damping_factor() > 0.0 {
                assert_eq!(law.normal_force(1e-5, -20.0, 1.0), 0.0, "{:?}", law.kind);
            }
        }
    }

    /// dF_N/dt against central differences of F_N along δ(t) = δ0 + v t + ½ a t², for every
    /// law and damping, with a stored impact velocity, without one (δ̇ in its place), and where
    /// the damping term is large. Step h = 1e-9 s: the truncation error ~h²·|F‴| is below 1e-8
    /// of |F'| here and rounding ~1e-16·F/h ≈ 1e-7·F N/s, so 1e-5 relative to max(|F'|, F/s)
    /// holds with room.
    #[test]
    fn force_rate_matches_finite_differences_of_the_force() {
        for law in every_law() {
            let kind = (law.kind, law.damping);
            for (delta0, v, a, stored) in [
                (1e-5, 0.1, -2e3, 0.3),
                (2e-6, -0.05, 5e2, 0.2),
                (1e-5, 0.2, 1e3, 0.0),
                (3e-6, -0.1, 1e2, 0.3),
                (1e-5, -0.01, -1e3, 0.0),
            ] {
                let force = |t: f64| {
                    let (d, dd) = (delta0 + v * t + 0.5 * a * t * t, v + a * t);
                    law.normal_force(d, dd, crate::contact::impact_velocity(stored, dd))
                };
                let h = 1e-9;
                let numeric = (force(h) - force(-h)) / (2.0 * h);
                let rate = law.normal_force_rate(delta0, v, a, stored);
                let scale = numeric.abs().max(force(0.0));
                assert!(
                    (rate - numeric).abs() <= 1e-5 * scale,
                    "{kind:?} δ = {delta0}, δ̇ = {v}, δ̈ = {a}, stored {stored}: {rate} vs {numeric}"
                );
            }
            // Free: no force, no rate; clamped by a fast separation: no rate either.
            assert_eq!(law.normal_force_rate(-1e-6, 0.1, 0.0, 0.3), 0.0);
            if law.damping_factor() > 0.0 {
                let v_clamp = -10.0 * 0.3 / law.damping_factor();
                assert_eq!(law.normal_force(1e-5, v_clamp, 0.3), 0.0);
                assert_eq!(law.normal_force_rate(1e-5, v_clamp, 1e3, 0.3), 0.0);
            }
        }
    }

    /// The closed-form partials of the line laws against central differences of F_N in each
    /// argument (increments 1e-6 of the argument: truncation ~1e-12, rounding ~1e-10 relative);
    /// the power laws have none (their Jacobians difference the law).
    #[test]
    fn line_slopes_match_central_differences() {
        for law in every_law() {
            let Some(_) = law.line_slopes(1e-5, 0.1, 0.3) else {
                assert!(
                    matches!(law.elastic, Elastic::Power { .. }),
                    "{:?}",
                    law.kind
                );
                continue;
            };
            for (delta, rate, v) in [(1e-5, 0.1, 0.3), (2e-6, -0.05, 0.2), (5e-5, 0.0, 1.0)] {
                let (fd, fr, fv) = law.line_slopes(delta, rate, v).unwrap_or_default();
                let c = |g: &dyn Fn(f64) -> f64, x: f64| {
                    let h = 1e-6 * x.abs().max(1e-3);
                    (g(x + h) - g(x - h)) / (2.0 * h)
                };
                let nd = {
                    let h = 1e-6 * delta;
                    (law.normal_force(delta + h, rate, v) - law.normal_force(delta - h, rate, v))
                        / (2.0 * h)
                };
                let nr = c(&|x| law.normal_force(delta, x, v), rate);
                let nv = c(&|x| law.normal_force(delta, rate, x), v);
                let f = law.normal_force(delta, rate, v);
                for (name, a, n, scale) in [
                    ("∂δ", fd, nd, nd.abs()),
                    ("∂δ̇", fr, nr, f),
                    ("∂δ̇⁽⁻⁾", fv, nv, f),
                ] {
                    assert!(
                        (a - n).abs() <= 1e-6 * scale.max(1e-12),
                        "{:?}/{:?} {name} at δ = {delta:e}: {a:e} vs {n:e}",
                        law.kind,
                        law.damping
                    );
                }
            }
        }
    }
}
