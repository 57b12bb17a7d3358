//! The infinitely short journal bearing (Ocvirk; Pinkus & Sternlicht 1961) with the π-film
//! (Gümbel, half-Sommerfeld) condition, for any combination of wedge and squeeze.
//!
//! Reynolds' equation without the circumferential pressure flow (L/D small; ref. 1, §3.6,
//! ref. 2):
//!
//! ```text
//!     ∂/∂z (h³ ∂p/∂z) = 6μ g(θ),   g(θ) = W sin θ − S cos θ,   p(±L/2) = 0,
//!     p(θ, z) = 3μ (L²/4 − z²) (−g(θ))/h³,
//! ```
//!
//! with the wedge speed W = e(ω_J + ω_B − 2φ̇) and the squeeze speed S = 2ė (module
//! documentation of [`super`]). The π-film keeps p where it is positive, g < 0: writing
//! g = −K cos(θ − θ_s), K = √(W² + S²), θ_s = atan2(−W, S), that is the half turn
//! θ_s − π/2 < θ < θ_s + π/2 centred on θ_s. The force of that pressure on the journal,
//! F = −∫∫ p (cos θ, sin θ) R dθ dz with ∫ (L²/4 − z²) dz = L³/6, is
//!
//! ```text
//!     F_n = −(μ R L³/(2c³)) (S I_cc − W I_cs),   F_t = −(μ R L³/(2c³)) (S I_cs − W I_ss)
//! ```
//!
//! over that half turn ([`super::integrals`]). The edges of the half turn move with W and S
//! but p vanishes there, so the force is continuously differentiable in (ε, W, S) for K > 0.
//!
//! Steady rotation (S = 0, W = eω > 0, half turn −π < θ < 0): I_ss = (π/2)(1 − ε²)^(−3/2) and
//! I_cs = −2ε/(1 − ε²)² give the classical load components (ref. 1, eqs. 3-58; ref. 3)
//! F_r = μ ω R L³ ε²/(c²(1 − ε²)²) towards the bearing centre and
//! F_t = π μ ω R L³ ε/(4 c² (1 − ε²)^(3/2)), so that
//! W_load = (μ ω R L³/(4c²)) ε/(1 − ε²)² √(π²(1 − ε²) + 16ε²) and tan ψ = π√(1 − ε²)/(4ε).
//!
//! Pure squeeze (W = 0, S = 2ė > 0, half turn −π/2 < θ < π/2): F_r = μ R L³ ė I(ε)/c³,
//! I(ε) = [(1 + 2ε²)(π/2 + asin ε) + 3ε√(1 − ε²)]/(1 − ε²)^(5/2).
//!
//! # References
//! 1. O. Pinkus, B. Sternlicht, *Theory of Hydrodynamic Lubrication*, McGraw-Hill, New York,
//!    1961, §3.6 (the short bearing).
//! 2. F. W. Ocvirk, Short-bearing approximation for full journal bearings, NACA TN 2808, 1952.
//! 3. P. Flores, J. Ambrósio, J. C. P. Claro, H. M. Lankarani, *Kinematics and Dynamics of
//!    Multibody Systems with Imperfect Joints*, Lecture Notes in Applied and Computational
//!    Mechanics 34, Springer, Berlin, 2008, chapter 6 (lubricated revolute joints).

use super::integrals::film_integrals;
use std::f64::consts::FRAC_PI_2;

/// Pressure force (F_n, F_t) on the journal (N, along n and t; F_n < 0 pushes the journal
/// towards the bearing centre) at the eccentricity ratio `eps`, wedge speed `wedge` = W (m/s)
/// and squeeze speed `squeeze` = S (m/s), with `scale` = μ R L³/(2c³) (N·s/m).
pub fn pressure_force(scale: f64, eps: f64, wedge: f64, squeeze: f64) -> [f64; 2] {
    if wedge == 0.0 && squeeze == 0.0 {
        return [0.0, 0.0];
    }
    let centre = (-wedge).atan2(squeeze);
    let i = film_integrals(eps, centre - FRAC_PI_2, centre + FRAC_PI_2);
    [
        -scale * (squeeze * i.cos_cos - wedge * i.cos_sin),
        -scale * (squeeze * i.cos_sin - wedge * i.sin_sin),
    ]
}

#[cfg(test)]
mod tests {
    use super::super::integrals::tests::quadrature;
    use super::*;
    use std::f64::consts::PI;

    /// The force against quadrature of the π-film pressure (positive part of −g/h̄³ over the
    /// whole turn, an independent route to the same integral), at wedge-dominated,
    /// squeeze-dominated, separating and mixed states.
    #[test]
    fn force_matches_quadrature_of_the_positive_pressure() {
        let scale = 1.0;
        for &eps in &[0.0, 0.4, 0.9] {
            for &(w, s) in &[
                (1.0, 0.0),
                (0.0, 1.0),
                (0.0, -1.0),
                (1.0, 0.7),
                (-0.3, -2.0),
            ] {
                let f = pressure_force(scale, eps, w, s);
                let p = |t: f64| {
                    let g = w * t.sin() - s * t.cos();
                    (-g).max(0.0) / (1.0 - eps * t.cos()).powi(3)
                };
                // F = −(μRL³/2c³) ∫ (−g)⁺/h̄³ (cos, sin) dθ: 3μ ∫ (L²/4 − z²) dz = μL³/2.
                let n = -scale * quadrature(|t| p(t) * t.cos(), -PI, PI, 20000);
                let t = -scale * quadrature(|t| p(t) * t.sin(), -PI, PI, 20000);
                let size = n.hypot(t).max(1e-300);
                // The positive part has kinks where g = 0: the composite rule converges as
                // h², 1e-8 with 20000 panels.
                assert!(
                    (f[0] - n).abs() < 1e-8 * size && (f[1] - t).abs() < 1e-8 * size,
                    "ε = {eps}, W = {w}, S = {s}: closed {f:?}, quadrature ({n}, {t})"
                );
            }
        }
    }

    /// Hand-computed steady-rotation point: ε = 0.5, scale·W = 1 N. Ocvirk's components
    /// (module documentation, divided by scale·W = μωRL³ε/(2c²)): F_r = 2ε/(1 − ε²)² =
    /// 1.7778 N towards the centre, F_t = (π/2)/(1 − ε²)^(3/2) = 2.4184 N;
    /// tan ψ = π√(1 − ε²)/(4ε) = π√0.75/2.
    #[test]
    fn steady_rotation_at_a_hand_computed_point() {
        let f = pressure_force(1.0, 0.5, 1.0, 0.0);
        let radial = 2.0 * 0.5 / (0.75_f64 * 0.75); // 1.77778
        let tangential = PI / (2.0 * 0.75_f64.powf(1.5)); // 2.41840
        assert!((radial - 1.777_777_777_78).abs() < 1e-10);
        assert!((tangential - 2.418_399_152_3).abs() < 1e-9, "{tangential}");
        assert!((f[0] + radial).abs() < 1e-12 * radial, "F_n = {}", f[0]);
        assert!(
            (f[1] - tangential).abs() < 1e-12 * tangential,
            "F_t = {}",
            f[1]
        );
        let psi = (f[1] / -f[0]).atan();
        let expected = (PI * 0.75_f64.sqrt() / 2.0).atan();
        assert!((psi - expected).abs() < 1e-12, "ψ = {psi} vs {expected}");
    }

    /// Pure squeeze against its closed form (module documentation) at ε = 0.7; separating
    /// (S < 0) the π-film's half turn is the thick side and the force pulls towards the wall.
    #[test]
    fn pure_squeeze_closed_form() {
        let eps: f64 = 0.7;
        let closed = ((1.0 + 2.0 * eps * eps) * (FRAC_PI_2 + eps.asin())
            + 3.0 * eps * (1.0 - eps * eps).sqrt())
            / (1.0 - eps * eps).powf(2.5);
        // scale · S = (μRL³/(2c³)) · 2ė: F_r/(μRL³ė/c³) = I(ε).
        let f = pressure_force(0.5, eps, 0.0, 2.0);
        assert!(
            (-f[0] - closed).abs() < 1e-12 * closed,
            "{} vs {closed}",
            -f[0]
        );
        assert!(f[1].abs() < 1e-12 * closed);
        let back = pressure_force(0.5, eps, 0.0, -2.0);
        assert!(back[0] > 0.0 && back[0] < closed, "separating: {back:?}");
    }
}
