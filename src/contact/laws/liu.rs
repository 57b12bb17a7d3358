//! Liu, Zhang & Yang's conformal line contact of a cylinder in a cylindrical hole: the elastic
//! part of the `liu` law, explicit in the penetration.
//!
//! ```text
//!     F = ½ π E* L δ √(δ / (2 (ΔR + δ))),     1/E* = (1 − ν_J²)/E_J + (1 − ν_B²)/E_B
//! ```
//!
//! (ref. 1, the approximate model fitted to their finite-element results for small clearances;
//! ref. 2 compares it with the other internal-contact models).
//!
//! | symbol | name here | unit |
//! |---|---|---|
//! | F | elastic normal force, ≥ 0 | N |
//! | δ | penetration, > 0 in contact | m |
//! | L | axial length of the bearing (`length`) | m |
//! | E* | contact modulus | Pa |
//! | ΔR = R_B − R_J | radial clearance c | m |
//! | ½ π E* L | `coefficient` | N/m |
//!
//! Slope: dF/dδ = F (3/(2δ) − 1/(2(ΔR + δ))) = ½ π E* L √(δ/(2(ΔR + δ))) (3/2 − δ/(2(ΔR + δ))).
//! For δ ≪ ΔR the law is a Hertz-type power law F ≈ ½ π E* L/√(2ΔR) · δ^1.5; for δ ≫ ΔR (a
//! conformal contact, the clearance closed) it tends to the linear ½ π E* L δ/√2. It was
//! derived for small clearances where the contact arc is no longer small against the radius,
//! the regime in which the Hertz point-contact law overestimates the penetration (ref. 1).
//!
//! # References
//! 1. C. S. Liu, K. Zhang, R. Yang, The FEM analysis and approximate model for cylindrical joints
//!    with clearances, *Mechanism and Machine Theory* 42 (2007) 183–197.
//! 2. C. M. Pereira, A. L. Ramalho, J. A. Ambrósio, A critical overview of internal and external
//!    cylinder contact force models, *Nonlinear Dynamics* 63 (2011) 681–697.

use std::f64::consts::PI;

/// Gauss–Legendre nodes on [0, 1] and weights, 8 points (exact for polynomials of degree 15):
/// the elastic energy's integrand after the substitution s = δ t² is smooth on [0, 1].
const GAUSS_8: [(f64, f64); 8] = [
    (0.019_855_071_751_231_856, 0.050_614_268_145_188_13),
    (0.101_666_761_293_186_63, 0.111_190_517_226_687_24),
    (0.237_233_795_041_835_5, 0.156_853_322_938_943_64),
    (0.408_282_678_752_175_1, 0.181_341_891_689_181),
    (0.591_717_321_247_825, 0.181_341_891_689_181),
    (0.762_766_204_958_164_5, 0.156_853_322_938_943_64),
    (0.898_333_238_706_813_4, 0.111_190_517_226_687_24),
    (0.980_144_928_248_768_2, 0.050_614_268_145_188_13),
];

/// The elastic part of Liu et al.'s law for one joint.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct LiuLine {
    /// ½ π E* L (N/m).
    pub coefficient: f64,
    /// ΔR = R_B − R_J (m).
    pub clearance: f64,
}

impl LiuLine {
    /// The law for a bearing of axial length `length` (m), radial clearance `clearance` (m) and
    /// contact modulus `modulus` = E* (Pa).
    pub fn new(length: f64, clearance: f64, modulus: f64) -> Self {
        LiuLine {
            coefficient: 0.5 * PI * modulus * length,
            clearance,
        }
    }

    /// The elastic force F (N, ≥ 0) and its slope dF/dδ (N/m) at penetration `delta` = δ (m);
    /// (0, 0) for δ ≤ 0 or NaN.
    pub fn force_and_slope(&self, delta: f64) -> (f64, f64) {
        if delta.is_nan() || delta <= 0.0 {
            return (0.0, 0.0);
        }
        let gap = self.clearance + delta;
        let root = (delta / (2.0 * gap)).sqrt();
        let force = self.coefficient * delta * root;
        let slope = self.coefficient * root * (1.5 - 0.5 * delta / gap);
        (force, slope)
    }

    /// Elastic energy stored at penetration `delta` (J), W = ∫₀^δ F dδ, by 8-point Gauss–Legendre
    /// quadrature after s = δ t² (integrand 2 c δ^(5/2) t⁴/√(2(ΔR + δt²)), smooth on [0, 1]).
    pub fn energy(&self, delta: f64) -> f64 {
        if delta.is_nan() || delta <= 0.0 {
            return 0.0;
        }
        let sum: f64 = GAUSS_8
            .iter()
            .map(|&(t, w)| {
                let t2 = t * t;
                w * t2 * t2 / (2.0 * (self.clearance + delta * t2)).sqrt()
            })
            .sum();
        2.0 * self.coefficient * delta * delta * delta.sqrt() * sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reference() -> LiuLine {
        LiuLine::new(0.02, 0.5e-3, 207e9 / (2.0 * 0.91))
    }

    /// Hand-computed: at δ = ΔR the root is √(1/4) = 1/2, so F = ½ π E* L ΔR/2 and the slope is
    /// ½ π E* L · ½ · (3/2 − 1/4) = ½ π E* L · 5/8; at δ = ΔR/8, √(1/18).
    #[test]
    fn hand_computed_points() {
        let law = reference();
        let c = 0.5 * PI * (207e9 / 1.82) * 0.02;
        let (f, s) = law.force_and_slope(0.5e-3);
        assert!((f - c * 0.5e-3 / 2.0).abs() <= 1e-14 * f, "F = {f:e}");
        assert!((s - c * 5.0 / 8.0).abs() <= 1e-14 * s, "dF/dδ = {s:e}");
        let (f, _) = law.force_and_slope(0.5e-3 / 8.0);
        let hand = c * 0.5e-3 / 8.0 * (1.0f64 / 18.0).sqrt();
        assert!((f - hand).abs() <= 1e-14 * hand, "F = {f:e}, {hand:e}");
    }

    /// Slope against central differences; energy against the closed form
    /// W = 2c ΔR²/√2 · (3θ/8 − sinh 2θ/4 + sinh 4θ/32), θ = asinh √(δ/ΔR) (s = ΔR sinh²θ),
    /// evaluated where it has no cancellation (δ ≳ ΔR/10) and against the δ ≪ ΔR limit
    /// W ≈ c/√(2ΔR) · δ^(5/2)/(5/2) below.
    #[test]
    fn slope_and_energy() {
        let law = reference();
        let (c, dr) = (law.coefficient, law.clearance);
        for delta in [1e-7, 1e-5, 1e-4, 5e-4] {
            let h = 1e-6 * delta;
            let (_, slope) = law.force_and_slope(delta);
            let numeric =
                (law.force_and_slope(delta + h).0 - law.force_and_slope(delta - h).0) / (2.0 * h);
            assert!(
                (slope - numeric).abs() <= 1e-7 * slope,
                "δ = {delta:e}: {slope:e} vs {numeric:e}"
            );
        }
        for delta in [5e-5, 2e-4, 5e-4] {
            let theta = (delta / dr).sqrt().asinh();
            let closed = 2.0 * c * dr * dr / 2f64.sqrt()
                * (3.0 * theta / 8.0 - (2.0 * theta).sinh() / 4.0 + (4.0 * theta).sinh() / 32.0);
            let w = law.energy(delta);
            assert!(
                (w - closed).abs() <= 1e-9 * closed,
                "δ = {delta:e}: W = {w:e}, closed form {closed:e}"
            );
        }
        let delta: f64 = 1e-9;
        let small = c / (2.0 * dr).sqrt() * delta.powf(2.5) / 2.5;
        let w = law.energy(delta);
        assert!((w - small).abs() <= 1e-5 * small, "W = {w:e}, {small:e}");
    }
}
