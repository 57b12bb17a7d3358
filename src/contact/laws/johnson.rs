//! Johnson's line contact of a cylinder in a cylindrical hole: the elastic part of the
//! `johnson` law, implicit in the penetration.
//!
//! ```text
//!     δ = F/(π L E*) · [ln(4 π L E* ΔR / F) − 1],     1/E* = (1 − ν_J²)/E_J + (1 − ν_B²)/E_B
//! ```
//!
//! (ref. 1, §5.6 pp. 99–104 for the line contact of two cylinders; ref. 2 states it for the
//! internal contact of a journal in a bearing and names it the Johnson model).
//!
//! | symbol | name here | unit |
//! |---|---|---|
//! | F | elastic normal force, ≥ 0 | N |
//! | δ | penetration, > 0 in contact | m |
//! | L | axial length of the bearing (`length`) | m |
//! | E* | contact modulus | Pa |
//! | ΔR = R_B − R_J | radial clearance c | m |
//! | k = π L E* | `modulus_length` | N/m |
//! | A = 4 k ΔR | force scale | N |
//!
//! **Solving for F.** With u = ln(A/F) the relation reads e^(−u) (u − 1) = δ/(4ΔR) = d, i.e.
//! h(u) = ln(u − 1) − u − ln d = 0. For u > 2, h is decreasing and concave, so Newton's method
//! started left of the root overshoots once and then decreases monotonically onto it without
//! overshooting again. The start u₀ = L + ln(L − 1 + ln(L − 1)), L = −ln d (two fixed-point steps
//! of u = L + ln(u − 1) from u = L + ln(L − 1)) lies within about 0.02 of the root for the
//! penetrations of a run (d < 1e-2), so three or four steps reach the rounding level; the loop
//! stops when a step is below 4 ulp of u or after [`MAX_NEWTON_STEPS`] steps. F = A e^(−u) then
//! carries a relative error of about |Δu| ≤ 1e-15 u, i.e. better than 1e-13 (checked against a
//! bisection on the explicit relation δ(F) in the tests).
//!
//! **Slope** (implicit function theorem): dδ/dF = (ln(A/F) − 2)/k, so dF/dδ = k/(u − 2).
//!
//! **Validity.** δ(F) rises only while F < A/e² (u > 2); it peaks at δ = 4ΔR/e² ≈ 0.54 ΔR, beyond
//! which the relation has no solution, and near that peak dF/dδ grows without bound. The law is
//! used for u ≥ 3, i.e. δ ≤ [`JohnsonLine::max_penetration`] = 8ΔR/e³ ≈ 0.40 ΔR (0.2 mm for the
//! reference joint, 20 to 200 times the penetrations of a run). Beyond it the force continues
//! along its tangent (slope k) so that it stays finite and monotone; the formulations stop there
//! anyway ([`crate::contact::ClearanceJoint::max_penetration`]). The relation is the
//! two-dimensional (plane-strain) Hertz solution: uniform along the axis, so L must be the length
//! actually in contact, and it assumes a contact half-width small against the radii.
//!
//! # References
//! 1. K. L. Johnson, *Contact Mechanics*, Cambridge University Press, 1985, §5.6, pp. 99–104.
//! 2. C. M. Pereira, A. L. Ramalho, J. A. Ambrósio, A critical overview of internal and external
//!    cylinder contact force models, *Nonlinear Dynamics* 63 (2011) 681–697.

use std::f64::consts::PI;

/// Most Newton steps of the solve for F: the start is within 0.02 of the root, so four steps
/// reach the rounding level; eight leave room for the edge of the range (d near its limit).
pub const MAX_NEWTON_STEPS: usize = 8;

/// u = ln(A/F) at the end of the range where the law is used (see the module documentation).
const U_LIMIT: f64 = 3.0;

/// The elastic part of Johnson's law for one joint.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct JohnsonLine {
    /// k = π L E* (N/m).
    pub modulus_length: f64,
    /// ΔR = R_B − R_J (m).
    pub clearance: f64,
}

impl JohnsonLine {
    /// The law for a bearing of axial length `length` (m), radial clearance `clearance` (m) and
    /// contact modulus `modulus` = E* (Pa).
    pub fn new(length: f64, clearance: f64, modulus: f64) -> Self {
        JohnsonLine {
            modulus_length: PI * length * modulus,
            clearance,
        }
    }

    /// A = 4 k ΔR (N): F = A e^(−u).
    fn force_scale(&self) -> f64 {
        4.0 * self.modulus_length * self.clearance
    }

    /// δ (m) at force `force` = F (N) > 0: the explicit relation of the module documentation.
    pub fn penetration(&self, force: f64) -> f64 {
        force / self.modulus_length * ((self.force_scale() / force).ln() - 1.0)
    }

    /// Deepest penetration the relation is used at (m): 8ΔR/e³, where u = ln(A/F) = 3.
    pub fn max_penetration(&self) -> f64 {
        4.0 * self.clearance * (U_LIMIT - 1.0) * (-U_LIMIT).exp()
    }

    /// u = ln(A/F) solving e^(−u)(u − 1) = d = δ/(4ΔR), for 0 < d < 2e^(−3).
    fn log_ratio(d: f64) -> f64 {
        let big_l = -d.ln();
        let mut u = big_l + (big_l - 1.0 + (big_l - 1.0).ln()).ln();
        for _ in 0..MAX_NEWTON_STEPS {
            // h(u) = ln(u − 1) − u + L, h'(u) = (2 − u)/(u − 1).
            let h = (u - 1.0).ln() - u + big_l;
            let step = h * (u - 1.0) / (u - 2.0);
            u += step;
            if step.abs() <= 4.0 * f64::EPSILON * u {
                break;
            }
        }
        u
    }

    /// The elastic force F (N, ≥ 0) and its slope dF/dδ (N/m) at penetration `delta` = δ (m);
    /// (0, 0) for δ ≤ 0 or NaN.
    pub fn force_and_slope(&self, delta: f64) -> (f64, f64) {
        if delta.is_nan() || delta <= 0.0 {
            return (0.0, 0.0);
        }
        let k = self.modulus_length;
        let scale = self.force_scale();
        let limit = self.max_penetration();
        if delta >= limit {
            // Beyond the range of use: the tangent at the limit, slope k/(3 − 2) = k.
            return (scale * (-U_LIMIT).exp() + k * (delta - limit), k);
        }
        let u = Self::log_ratio(delta / (4.0 * self.clearance));
        (scale * (-u).exp(), k / (u - 2.0))
    }

    /// Elastic energy stored at penetration `delta` (J), W = ∫₀^δ F dδ. With δ(F) explicit,
    /// W = F δ − ∫₀^F δ(f) df = F δ − F²/(2k) · (ln(A/F) − 1/2); beyond the range of use the
    /// tangent's area is added.
    pub fn energy(&self, delta: f64) -> f64 {
        if delta.is_nan() || delta <= 0.0 {
            return 0.0;
        }
        let k = self.modulus_length;
        let limit = self.max_penetration();
        let at = delta.min(limit);
        let (force, _) = self.force_and_slope(at);
        let inside =
            force * at - force * force / (2.0 * k) * ((self.force_scale() / force).ln() - 0.5);
        let beyond = (delta - limit).max(0.0);
        inside + force * beyond + 0.5 * k * beyond * beyond
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference joint: steel on steel (E* = 207e9/(2·0.91) Pa), ΔR = 0.5 mm, L = 20 mm.
    fn reference() -> JohnsonLine {
        JohnsonLine::new(0.02, 0.5e-3, 207e9 / (2.0 * 0.91))
    }

    /// F from δ by bisection on the explicit relation δ(F), independent of the Newton solve:
    /// 200 halvings of [0, A/e³] (δ(F) rises there) leave an interval at the rounding level.
    fn bisect(law: &JohnsonLine, delta: f64) -> f64 {
        let (mut lo, mut hi) = (
            0.0,
            4.0 * law.modulus_length * law.clearance * (-3.0f64).exp(),
        );
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if law.penetration(mid) < delta {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }

    /// The Newton solve against bisection over eight decades of penetration up to the limit:
    /// relative difference below 1e-13 (the stated accuracy), and δ(F) returns δ.
    #[test]
    fn force_matches_bisection_on_the_implicit_relation() {
        let law = reference();
        let limit = law.max_penetration();
        for delta in [
            1e-12,
            1e-10,
            1e-8,
            1e-7,
            1e-6,
            3e-6,
            1e-5,
            1e-4,
            0.999 * limit,
        ] {
            let (f, _) = law.force_and_slope(delta);
            let g = bisect(&law, delta);
            assert!(
                (f - g).abs() <= 1e-13 * g,
                "δ = {delta:e}: Newton {f:e}, bisection {g:e}"
            );
            let back = law.penetration(f);
            assert!(
                (back - delta).abs() <= 1e-13 * delta,
                "δ = {delta:e}: δ(F) = {back:e}"
            );
        }
    }

    /// Hand-computed point: at F = A e^(−5) (u = 5) the relation gives δ = 4ΔR e^(−5) · 4, and
    /// the slope k/(5 − 2) = k/3.
    #[test]
    fn hand_computed_point_and_slope() {
        let law = reference();
        let a = 4.0 * law.modulus_length * law.clearance;
        let delta = 4.0 * law.clearance * (-5.0f64).exp() * 4.0;
        let (f, slope) = law.force_and_slope(delta);
        let f_hand = a * (-5.0f64).exp();
        assert!(
            (f - f_hand).abs() <= 1e-13 * f_hand,
            "F = {f:e}, {f_hand:e}"
        );
        let s_hand = law.modulus_length / 3.0;
        assert!(
            (slope - s_hand).abs() <= 1e-12 * s_hand,
            "dF/dδ = {slope:e}, {s_hand:e}"
        );
    }

    /// dF/dδ against central differences of F, and dW/dδ = F, inside and beyond the limit.
    /// h = 1e-6 δ: truncation ~h² F‴/6 ≲ 1e-12 F′, rounding ~1e-16 F/h = 1e-10 F/δ ≈ 1e-10 F′.
    #[test]
    fn slope_and_energy_match_differences() {
        let law = reference();
        for delta in [1e-7, 2e-6, 1e-5, 1.5 * law.max_penetration()] {
            let h = 1e-6 * delta;
            let (f, slope) = law.force_and_slope(delta);
            let numeric =
                (law.force_and_slope(delta + h).0 - law.force_and_slope(delta - h).0) / (2.0 * h);
            assert!(
                (slope - numeric).abs() <= 1e-7 * slope,
                "δ = {delta:e}: {slope:e} vs {numeric:e}"
            );
            let power = (law.energy(delta + h) - law.energy(delta - h)) / (2.0 * h);
            assert!(
                (power - f).abs() <= 1e-6 * f,
                "δ = {delta:e}: dW/dδ = {power:e}, F = {f:e}"
            );
        }
        assert_eq!(law.force_and_slope(0.0), (0.0, 0.0));
        assert_eq!(law.force_and_slope(-1e-6), (0.0, 0.0));
        assert_eq!(law.energy(-1e-6), 0.0);
    }
}
