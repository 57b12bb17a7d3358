//! Generalised stiffness K of a journal inside a bearing (paper eqs. 8–9).
//!
//! Two cylinders of radii R_i, R_j in contact along a line (Hertz, as used by Lankarani and
//! Nikravesh, ref. 1) have the generalised stiffness
//!
//! ```text
//!     K = 4 / (3 (σ_i + σ_j)) · sqrt(R_i R_j / (R_i + R_j)),     σ_k = (1 − ν_k²) / E_k
//! ```
//!
//! with a curvature radius that is positive for a convex and negative for a concave surface
//! (paper, below eq. 9). The journal is convex, R_i = R_J; the bearing is concave, R_j = −R_B, so
//!
//! ```text
//!     R_i R_j / (R_i + R_j) = R_J R_B / (R_B − R_J) = R_J (R_J + c) / c
//! ```
//!
//! | symbol | name here | unit |
//! |---|---|---|
//! | K | return value | N/m^1.5 (N/m^n for the exponent n used with it) |
//! | R_J, R_B | `journal_radius`, `bearing_radius` | m |
//! | c = R_B − R_J | radial clearance | m |
//! | E_k | `Material::youngs_modulus` | Pa |
//! | ν_k | `Material::poisson_ratio` | – |
//! | σ_k | material compliance | 1/Pa |
//!
//! Check value (reference parameters): E = 207 GPa, ν = 0.3, R_J = 10 mm, c = 0.5 mm give
//! K = 6.9494e10 N/m^1.5.
//!
//! Valid for 0 < R_J < R_B. As R_B → R_J (conformal contact) K grows without bound; that limit is
//! returned as +∞ for R_B ≤ R_J, which the model validation (c > 0) never produces.
//!
//! # References
//! 1. H. M. Lankarani, P. E. Nikravesh, A contact force model with hysteresis damping for impact
//!    analysis of multibody systems, *Journal of Mechanical Design* 112 (1990) 369–376.
//! 2. S. B. Farahan, M. R. Ghazavi, S. Rahmanian, Nonlinear dynamic analysis of a four-bar
//!    mechanism having revolute joint with clearance, *Journal of Theoretical and Applied Vibration
//!    and Acoustics* (2016), eqs. 8–9, <https://tava.isav.ir/article_19881.html>.
//! 3. P. Flores, J. Ambrósio, J. C. P. Claro, H. M. Lankarani, Dynamic behaviour of planar rigid
//!    multi-body systems including revolute joints with clearance, *Proc. IMechE Part K: Journal
//!    of Multi-body Dynamics* 221 (2007) 161–174.

use crate::model::Material;

/// Material compliance σ = (1 − ν²)/E (1/Pa) of one side of a contact (paper eq. 9).
pub fn compliance(material: Material) -> f64 {
    (1.0 - material.poisson_ratio * material.poisson_ratio) / material.youngs_modulus
}

/// Generalised stiffness K (N/m^1.5) of a convex journal of radius `journal_radius` (m) inside a
/// concave bearing of radius `bearing_radius` (m): K = 4/(3(σ_J + σ_B)) · sqrt(R_J R_B/(R_B − R_J))
/// (paper eq. 8 with R_j = −R_B). Returns +∞ when `bearing_radius <= journal_radius` (the
/// conformal limit; see the module documentation).
pub fn generalised_stiffness(
    journal_radius: f64,
    bearing_radius: f64,
    journal: Material,
    bearing: Material,
) -> f64 {
    let clearance = bearing_radius - journal_radius;
    if clearance <= 0.0 {
        return f64::INFINITY;
    }
    let radius = journal_radius * bearing_radius / clearance;
    4.0 / (3.0 * (compliance(journal) + compliance(bearing))) * radius.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    const STEEL: Material = Material {
        youngs_modulus: 207e9,
        poisson_ratio: 0.3,
    };

    /// The reference value quoted in parameters.md and STYLE.md, to 5 significant digits.
    #[test]
    fn reference_stiffness() {
        let k = generalised_stiffness(0.010, 0.0105, STEEL, STEEL);
        let rel = (k - 6.9494e10).abs() / 6.9494e10;
        // 5 significant digits: the quoted value is rounded to 6.9494e10, so |Δ|/K < 1e-5.
        assert!(
            rel < 1e-5,
            "K = {k:.6e}, expected 6.9494e10 (rel. error {rel:.2e})"
        );
    }

    /// Hand-computed: σ = 0.91/207e9 = 4.396135e-12 1/Pa per side, sqrt(0.01·0.0105/0.0005)
    /// = sqrt(0.21), K = 4/(3·2σ)·sqrt(0.21).
    #[test]
    fn matches_hand_computation() {
        let sigma = 0.91 / 207e9;
        assert!((compliance(STEEL) - sigma).abs() < 1e-24, "sigma");
        let expected = 4.0 / (3.0 * 2.0 * sigma) * 0.21_f64.sqrt();
        let k = generalised_stiffness(0.010, 0.0105, STEEL, STEEL);
        assert!(
            (k - expected).abs() <= 1e-12 * expected,
            "K = {k:e}, expected {expected:e}"
        );
    }

    /// Softer material on one side lowers K; K is symmetric in the two materials; smaller
    /// clearance (more conformal contact) raises K; no clearance gives the +∞ limit.
    #[test]
    fn limits_and_symmetry() {
        let soft = Material {
            youngs_modulus: 70e9,
            poisson_ratio: 0.33,
        };
        let k_ss = generalised_stiffness(0.01, 0.0105, STEEL, STEEL);
        let k_sa = generalised_stiffness(0.01, 0.0105, STEEL, soft);
        let k_as = generalised_stiffness(0.01, 0.0105, soft, STEEL);
        assert!(k_sa < k_ss, "softer bearing: {k_sa:e} vs {k_ss:e}");
        assert!(
            (k_sa - k_as).abs() <= 1e-15 * k_sa,
            "symmetry: {k_sa:e} vs {k_as:e}"
        );
        assert!(
            generalised_stiffness(0.01, 0.0101, STEEL, STEEL) > k_ss,
            "smaller clearance"
        );
        assert_eq!(
            generalised_stiffness(0.01, 0.01, STEEL, STEEL),
            f64::INFINITY
        );
        assert_eq!(
            generalised_stiffness(0.01, 0.009, STEEL, STEEL),
            f64::INFINITY
        );
    }
}
