//! The infinitely long journal bearing (Sommerfeld 1904) with Gümbel's condition (the
//! half-Sommerfeld or π-film solution: the full Sommerfeld pressure with its negative part
//! dropped), for any combination of wedge and squeeze.
//!
//! Reynolds' equation without the axial flow (L/D large; ref. 2, §3.2):
//!
//! ```text
//!     ∂/∂θ (h³ ∂p/∂θ) = 6μR² g(θ),   g(θ) = W sin θ − S cos θ,
//!     ∂p/∂θ = (6μR²/c³) (A − W cos θ − S sin θ)/h̄³,   A = 3εW/(2 + ε²),
//! ```
//!
//! with W, S as in [`super::short`]; A makes p periodic (∫ ∂p/∂θ over a turn = 0, with
//! ∫ 1/h̄³ = π(2 + ε²)/(1 − ε²)^(5/2) and ∫ cos θ/h̄³ = 3πε/(1 − ε²)^(5/2)), and the pressure is
//! referred to p = 0 at the thickest film, θ = π (ref. 1). p has at most two extrema per turn
//! (where W cos θ + S sin θ = A), so besides θ = π it changes sign at most once, at θ_z, found
//! by a safeguarded Newton iteration between the extrema; Gümbel's film is the arc from π to
//! θ_z or from θ_z to 3π where p > 0 (the whole turn in pure squeeze towards the wall, none
//! in pure separation). With p = 0 at both ends of that arc, integration by parts gives the
//! force on the journal, F = −∫ p (cos θ, sin θ) R L dθ, from ∂p/∂θ alone:
//!
//! ```text
//!     F_n = (6μR³L/c³) (A I_s − W I_cs − S I_ss),   F_t = −(6μR³L/c³) (A I_c − W I_cc − S I_cs)
//! ```
//!
//! over the arc ([`super::integrals`]). Steady rotation (S = 0, W = eω) gives the
//! half-Sommerfeld load (ref. 2, eqs. 3-31; ref. 3): F_r = 12 μ ω R³ L ε²/(c² (2 + ε²)(1 − ε²))
//! towards the centre, F_t = 6π μ ω R³ L ε/(c² (2 + ε²) √(1 − ε²)).
//!
//! # References
//! 1. A. Sommerfeld, Zur hydrodynamischen Theorie der Schmiermittelreibung, *Zeitschrift für
//!    Mathematik und Physik* 50 (1904) 97–155.
//! 2. O. Pinkus, B. Sternlicht, *Theory of Hydrodynamic Lubrication*, McGraw-Hill, New York,
//!    1961, §3.2 (the infinitely long bearing).
//! 3. P. Flores, J. Ambrósio, J. C. P. Claro, H. M. Lankarani, *Kinematics and Dynamics of
//!    Multibody Systems with Imperfect Joints*, Lecture Notes in Applied and Computational
//!    Mechanics 34, Springer, Berlin, 2008, chapter 6 (lubricated revolute joints).

use super::integrals::film_integrals;
use std::f64::consts::PI;

/// The dimensionless pressure P(θ) = ∫_π^θ (A − W cos − S sin)/h̄³ (p = 6μR²/c³ · P).
fn pressure(eps: f64, a: f64, wedge: f64, squeeze: f64, theta: f64) -> f64 {
    let i = film_integrals(eps, PI, theta);
    a * i.one - wedge * i.cos - squeeze * i.sin
}

/// dP/dθ.
fn pressure_slope(eps: f64, a: f64, wedge: f64, squeeze: f64, theta: f64) -> f64 {
    let (s, c) = theta.sin_cos();
    (a - wedge * c - squeeze * s) / (1.0 - eps * c).powi(3)
}

/// θ mapped into [π, 3π).
fn into_turn(theta: f64) -> f64 {
    PI + (theta - PI).rem_euclid(2.0 * PI)
}

/// The arc [a, b] ⊂ [π, 3π] where Gümbel's film carries pressure, or None.
fn film_arc(eps: f64, a: f64, wedge: f64, squeeze: f64) -> Option<(f64, f64)> {
    let k = wedge.hypot(squeeze);
    let ratio = (a / k).clamp(-1.0, 1.0);
    let axis = squeeze.atan2(wedge);
    let spread = ratio.acos();
    let (mut lo, mut hi) = (into_turn(axis - spread), into_turn(axis + spread));
    if lo > hi {
        std::mem::swap(&mut lo, &mut hi);
    }
    let (p_lo, p_hi) = (
        pressure(eps, a, wedge, squeeze, lo),
        pressure(eps, a, wedge, squeeze, hi),
    );
    if p_lo >= 0.0 && p_hi >= 0.0 {
        return Some((PI, 3.0 * PI));
    }
    if p_lo <= 0.0 && p_hi <= 0.0 {
        return None;
    }
    // P is monotone on [lo, hi] with a sign change: Newton, kept inside the bracket.
    let rising = p_hi > p_lo;
    let (mut left, mut right) = (lo, hi);
    let mut theta = 0.5 * (lo + hi);
    for _ in 0..100 {
        let p = pressure(eps, a, wedge, squeeze, theta);
        if (p > 0.0) == rising {
            right = theta;
        } else {
            left = theta;
        }
        let slope = pressure_slope(eps, a, wedge, squeeze, theta);
        let newton = theta - p / slope;
        let next = if newton > left && newton < right && newton.is_finite() {
            newton
        } else {
            0.5 * (left + right)
        };
        if (next - theta).abs() <= 4.0 * f64::EPSILON * theta.abs() || right - left <= 1e-15 {
            theta = next;
            break;
        }
        theta = next;
    }
    Some(if p_lo > 0.0 {
        (PI, theta)
    } else {
        (theta, 3.0 * PI)
    })
}

/// Pressure force (F_n, F_t) on the journal (N, along n and t; F_n < 0 pushes the journal
/// towards the bearing centre) at the eccentricity ratio `eps`, wedge speed `wedge` = W (m/s)
/// and squeeze speed `squeeze` = S (m/s), with `scale` = 6μR³L/c³ (N·s/m).
pub fn pressure_force(scale: f64, eps: f64, wedge: f64, squeeze: f64) -> [f64; 2] {
    if wedge == 0.0 && squeeze == 0.0 {
        return [0.0, 0.0];
    }
    let a = 3.0 * eps * wedge / (2.0 + eps * eps);
    let Some((from, to)) = film_arc(eps, a, wedge, squeeze) else {
        return [0.0, 0.0];
    };
    let i = film_integrals(eps, from, to);
    [
        scale * (a * i.sin - wedge * i.cos_sin - squeeze * i.sin_sin),
        -scale * (a * i.cos - wedge * i.cos_cos - squeeze * i.cos_sin),
    ]
}

#[cfg(test)]
mod tests {
    use super::super::integrals::tests::quadrature;
    use super::*;

    /// The full Sommerfeld pressure by quadrature of its slope (an independent route), its
    /// positive part integrated against (cos, sin): the closed form must agree, for
    /// wedge-dominated, squeeze-dominated, separating and mixed states.
    #[test]
    fn force_matches_quadrature_of_the_positive_pressure() {
        for &eps in &[0.0, 0.4, 0.85] {
            for &(w, s) in &[
                (1.0, 0.0),
                (0.0, 1.0),
                (0.0, -1.0),
                (1.0, 0.7),
                (-0.3, -2.0),
            ] {
                let f = pressure_force(1.0, eps, w, s);
                let a = 3.0 * eps * w / (2.0 + eps * eps);
                let slope =
                    |t: f64| (a - w * t.cos() - s * t.sin()) / (1.0 - eps * t.cos()).powi(3);
                // p on a grid by the trapezoidal rule of its slope from θ = π, refined: then
                // F = −∫ p⁺ (cos, sin) by the trapezoidal rule on the same grid.
                let m = 200_000;
                let h = 2.0 * PI / m as f64;
                let (mut p, mut n, mut t) = (0.0, 0.0, 0.0);
                let mut prev = slope(PI);
                for i in 1..=m {
                    let th = PI + i as f64 * h;
                    let cur = slope(th);
                    p += 0.5 * h * (prev + cur);
                    prev = cur;
                    let w_i = if i == m { 0.5 } else { 1.0 };
                    n -= w_i * h * p.max(0.0) * th.cos();
                    t -= w_i * h * p.max(0.0) * th.sin();
                }
                // The trapezoidal rules converge as h² (~1e-10 here); rounding leaves ~1e-18 on
                // a zero force.
                let tol = 1e-6 * n.hypot(t) + 1e-15;
                assert!(
                    (f[0] - n).abs() < tol && (f[1] - t).abs() < tol,
                    "ε = {eps}, W = {w}, S = {s}: closed {f:?}, quadrature ({n}, {t})"
                );
            }
        }
    }

    /// Steady rotation against the half-Sommerfeld closed form (module documentation) at
    /// ε = 0.6: with scale · W = 6μR³L/c³ · eω, F_r/(scale·W) = 2ε/((2 + ε²)(1 − ε²)) and
    /// F_t/(scale·W) = π/((2 + ε²)√(1 − ε²)).
    #[test]
    fn steady_rotation_half_sommerfeld() {
        let eps: f64 = 0.6;
        let f = pressure_force(1.0, eps, 1.0, 0.0);
        let radial = 2.0 * eps / ((2.0 + eps * eps) * (1.0 - eps * eps));
        let tangential = PI / ((2.0 + eps * eps) * (1.0 - eps * eps).sqrt());
        assert!(
            (f[0] + radial).abs() < 1e-12 * radial,
            "{} vs {radial}",
            -f[0]
        );
        assert!(
            (f[1] - tangential).abs() < 1e-12 * tangential,
            "{} vs {tangential}",
            f[1]
        );
    }

    /// Pure squeeze towards the wall: the whole turn carries pressure,
    /// p = (6μR²ė/(εc³)) (1/h̄² − 1/(1 + ε)²) (ref. 1 with p(π) = 0), whose force follows by
    /// quadrature; away from the wall the film carries none.
    #[test]
    fn pure_squeeze() {
        let eps: f64 = 0.5;
        let f = pressure_force(1.0, eps, 0.0, 2.0);
        // P(θ) with S = 2ė = 2: p/(6μR²/c³) = (1/ε)(1/h̄² − 1/(1 + ε)²).
        let p = |t: f64| (1.0 / (1.0 - eps * t.cos()).powi(2) - 1.0 / (1.0 + eps).powi(2)) / eps;
        let n = -quadrature(|t| p(t) * t.cos(), -PI, PI, 2000);
        assert!((f[0] - n).abs() < 1e-11 * n.abs(), "{} vs {n}", f[0]);
        assert!(f[0] < 0.0 && f[1].abs() < 1e-12 * n.abs());
        assert_eq!(pressure_force(1.0, eps, 0.0, -2.0), [0.0, 0.0]);
    }
}
