//! Normal contact-force laws of the form F_N = K δⁿ (1 + χ δ̇/δ̇⁽⁻⁾) (paper eq. 7).
//!
//! All four laws share the Hertzian elastic part K δⁿ and differ only in the hysteresis factor χ,
//! a function of the coefficient of restitution c_r:
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
//! Rules shared by every law (implemented once, in [`hysteresis_force`]):
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
pub mod lankarani_nikravesh;

pub use flores::Flores;
pub use hertz::Hertz;
pub use hunt_crossley::HuntCrossley;
pub use lankarani_nikravesh::LankaraniNikravesh;

use super::stiffness::generalised_stiffness;
use crate::model::{ClearanceSpec, ContactLawKind};

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
    let elastic = stiffness * penetration_power(delta, exponent);
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
    let impact = if stored > 0.0 { stored } else { delta_dot };
    let usable = impact.is_finite() && impact > MIN_IMPACT_VELOCITY;
    if !usable || chi == 0.0 {
        return stiffness * power_rate;
    }
    if stored <= 0.0 {
        return stiffness * power_rate * (1.0 + chi);
    }
    let factor = 1.0 + chi * delta_dot / stored;
    if factor <= 0.0 {
        return 0.0;
    }
    stiffness * (power_rate * factor + power * chi * delta_ddot / stored)
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

/// A normal-force law with its parameters: the four laws behind one interface.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ContactLaw {
    /// Which law.
    pub kind: ContactLawKind,
    /// Generalised stiffness K (N/m^n).
    pub stiffness: f64,
    /// Exponent n (–).
    pub exponent: f64,
    /// Coefficient of restitution c_r ∈ (0, 1] (–).
    pub restitution: f64,
}

impl ContactLaw {
    /// The law of a clearance joint: K from the spec's `stiffness_override` if given, otherwise
    /// from the materials with R_B = R_J + c ([`generalised_stiffness`]).
    pub fn from_spec(spec: &ClearanceSpec) -> ContactLaw {
        let stiffness = spec.stiffness_override.unwrap_or_else(|| {
            generalised_stiffness(
                spec.journal_radius,
                spec.journal_radius + spec.clearance,
                spec.journal_material,
                spec.bearing_material,
            )
        });
        ContactLaw {
            kind: spec.law,
            stiffness,
            exponent: spec.exponent,
            restitution: spec.restitution,
        }
    }

    /// The hysteresis factor χ(c_r) of this law (–): the coefficient of δ̇/δ̇⁽⁻⁾.
    #[inline]
    pub fn damping_factor(&self) -> f64 {
        match self.kind {
            ContactLawKind::LankaraniNikravesh => {
                lankarani_nikravesh::damping_factor(self.restitution)
            }
            ContactLawKind::HuntCrossley => hunt_crossley::damping_factor(self.restitution),
            ContactLawKind::Flores => flores::damping_factor(self.restitution),
            ContactLawKind::Hertz => hertz::damping_factor(self.restitution),
        }
    }

    /// Normal force F_N (N, ≥ 0) at penetration `delta` (m), penetration rate `delta_dot` (m/s)
    /// and impact velocity `impact_velocity` = δ̇⁽⁻⁾ (m/s); 0 for δ ≤ 0. See [`hysteresis_force`]
    /// for the clamp and the fallback when δ̇⁽⁻⁾ is not usable.
    #[inline]
    pub fn normal_force(&self, delta: f64, delta_dot: f64, impact_velocity: f64) -> f64 {
        hysteresis_force(
            self.stiffness,
            self.exponent,
            self.damping_factor(),
            delta,
            delta_dot,
            impact_velocity,
        )
    }

    /// dF_N/dt (N/s) along a motion (δ, δ̇, δ̈) with the stored impact velocity `stored` (≤ 0:
    /// none); see [`hysteresis_force_rate`].
    pub fn normal_force_rate(
        &self,
        delta: f64,
        delta_dot: f64,
        delta_ddot: f64,
        stored: f64,
    ) -> f64 {
        hysteresis_force_rate(
            (self.stiffness, self.exponent, self.damping_factor()),
            delta,
            delta_dot,
            delta_ddot,
            stored,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{FrictionSpec, Material};

    fn spec(law: ContactLawKind, stiffness_override: Option<f64>) -> ClearanceSpec {
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
            restitution: 0.9,
            exponent: 1.5,
            friction: FrictionSpec::None,
            initial_eccentricity: [0.0, 0.0],
        }
    }

    /// K follows from the materials with R_B = R_J + c unless overridden.
    #[test]
    fn from_spec_takes_stiffness_from_materials_or_override() {
        let law = ContactLaw::from_spec(&spec(ContactLawKind::LankaraniNikravesh, None));
        assert!(
            (law.stiffness - 6.9494e10).abs() < 1e-5 * 6.9494e10,
            "K = {:e}",
            law.stiffness
        );
        assert_eq!(law.exponent, 1.5);
        assert_eq!(law.restitution, 0.9);
        let law = ContactLaw::from_spec(&spec(ContactLawKind::Hertz, Some(1e9)));
        assert_eq!(law.stiffness, 1e9);
        assert_eq!(law.kind, ContactLawKind::Hertz);
    }

    /// The dispatch picks each law's χ: 0.1425, 0.15, 8·0.1/(5·0.9) = 0.177…, 0 at c_r = 0.9.
    #[test]
    fn dispatch_uses_each_laws_damping_factor() {
        let cases = [
            (ContactLawKind::LankaraniNikravesh, 0.1425),
            (ContactLawKind::HuntCrossley, 0.15),
            (ContactLawKind::Flores, 0.8 / 4.5),
            (ContactLawKind::Hertz, 0.0),
        ];
        for (kind, chi) in cases {
            let law = ContactLaw::from_spec(&spec(kind, Some(1e10)));
            assert!(
                (law.damping_factor() - chi).abs() < 1e-15,
                "{kind:?}: χ = {}",
                law.damping_factor()
            );
            // δ = 1e-4 m: K δ^1.5 = 1e10 · 1e-6 = 1e4 N; δ̇/δ̇⁽⁻⁾ = 0.5.
            let f = law.normal_force(1e-4, 0.5, 1.0);
            let expected = 1e4 * (1.0 + 0.5 * chi);
            assert!(
                (f - expected).abs() < 1e-9 * expected,
                "{kind:?}: F = {f}, expected {expected}"
            );
        }
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
    }

    /// dF_N/dt against central differences of F_N along δ(t) = δ0 + v t + ½ a t², for every
    /// law, with a stored impact velocity, without one (δ̇ in its place), and where the damping
    /// term is large. Step h = 1e-9 s: the truncation error ~h²·|F‴| is below 1e-8 of |F'| here
    /// and rounding ~1e-16·F/h ≈ 1e-7·F N/s, so 1e-5 relative to max(|F'|, F/s) holds with room.
    #[test]
    fn force_rate_matches_finite_differences_of_the_force() {
        for kind in [
            ContactLawKind::LankaraniNikravesh,
            ContactLawKind::HuntCrossley,
            ContactLawKind::Flores,
            ContactLawKind::Hertz,
        ] {
            let law = ContactLaw::from_spec(&spec(kind, None));
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
}
