//! Grazing guard: the largest step an integrator may take while a clearance joint is free, so that
//! a contact cannot begin and end inside one step unseen.
//!
//! An integrator detects a contact by a sign change of δ between step ends (or at the points its
//! dense output is checked at). A contact that starts and ends inside one step leaves δ < 0 at
//! both ends and is missed, together with its impact. [`free_flight_max_step`] limits the step
//! while the joint is free (δ < 0, or δ = 0 at a restart after a separation: then the gap is 0
//! and the floor applies).
//!
//! **Rule.** With the gap g = −δ = c − |e| > 0, the relative speed V = |ė| and a bound A on the
//! relative acceleration |ë| of the two centres over the step (m, m/s, m/s²):
//!
//! ```text
//!     h_approach = largest h with  V h + ½ A h²  ≤ κ g         = 2κg / (V + sqrt(V² + 2κ A g))
//!     h_floor    = largest h with (V h + A h²)/2 ≤ ε c         = 4εc / (V + sqrt(V² + 8ε A c))
//!     h_max      = max(h_approach, h_floor)     (∞ when V = A = 0, and when δ > 0)
//! ```
//!
//! with κ = [`APPROACH_FRACTION`] = 0.5 and ε = [`GRAZE_DEPTH_FRACTION`] = 1e-3.
//!
//! **Why it works.** (1) Since |e(t+s)| ≤ |e(t)| + V s + ½ A s² (triangle inequality on the Taylor
//! expansion with |ë| ≤ A), a step h ≤ h_approach cannot bring the journal further than κ g
//! towards the wall: no contact at all can begin inside it. With κ = ½ the gap at most halves per
//! step, so the journal approaches the wall in geometrically shrinking steps.
//! (2) That would stall right at the wall (h_approach → 0 with g), so the step never drops below
//! h_floor. Inside a step of length h that starts and ends free, a missed contact enters at some t₁
//! and leaves at t₂ with t₂ − t₁ ≤ h, reaching its deepest δ_m at t*. As |δ̇| ≤ |ė| ≤ V + A h
//! during the step, δ_m ≤ (V + A h)(t* − t₁) and δ_m ≤ (V + A h)(t₂ − t*), so
//! 2 δ_m ≤ (V + A h) h. With h ≤ h_floor this gives **δ_m ≤ ε c**: only grazes shallower than
//! 1e-3 of the clearance (0.5 µm for c = 0.5 mm) can be missed. With the reference contact
//! (K = 6.9494e10 N/m^1.5) such a graze carries at most K (ε c)^1.5 ≈ 25 N, for at most one
//! floor step.
//!
//! **Limits.** A must bound |ë| over the whole step; formulations pass |ë| at the start of the
//! step, which is exact for constant relative acceleration and correct to first order in the
//! step otherwise (the free-flight motion is smooth: gravity and centripetal terms, no contact
//! force). The safety factor κ = ½ absorbs that variation in the approach bound. Non-finite inputs
//! give no limit (∞): the state is then already non-finite, and the integrator's finiteness check
//! reports where it came from.
//!
//! # References
//! 1. P. Flores, J. Ambrósio, J. C. P. Claro, H. M. Lankarani, Dynamic behaviour of planar rigid
//!    multi-body systems including revolute joints with clearance, *Proc. IMechE Part K: Journal
//!    of Multi-body Dynamics* 221 (2007) 161–174 (contact detection within a step).
//! 2. E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary Differential Equations I*, 2nd ed.,
//!    Springer, 1993, §II.6 (dense output and event location).

/// κ: fraction of the current gap a free step may close at most (–).
pub const APPROACH_FRACTION: f64 = 0.5;

/// ε: depth, as a fraction of the clearance c, of the deepest contact that may begin and end
/// inside one step (–).
pub const GRAZE_DEPTH_FRACTION: f64 = 1e-3;

/// The largest step (s) allowed while the joint is free, from the penetration `delta` = δ (m,
/// < 0 when free), the relative speed `relative_speed` = |ė| (m/s), a bound `relative_acceleration`
/// on |ë| over the step (m/s²) and the radial clearance `clearance` = c (m). ∞ when δ > 0 (in
/// contact the contact stiffness governs the step, and the end of contact is an event) or when
/// the centres neither move nor accelerate relative to each other. Rule and bound: module
/// documentation.
pub fn free_flight_max_step(
    delta: f64,
    relative_speed: f64,
    relative_acceleration: f64,
    clearance: f64,
) -> f64 {
    let finite = delta.is_finite()
        && relative_speed.is_finite()
        && relative_acceleration.is_finite()
        && clearance.is_finite();
    if !finite || delta > 0.0 {
        return f64::INFINITY;
    }
    let v = relative_speed.abs();
    let a = relative_acceleration.abs();
    if v == 0.0 && a == 0.0 {
        return f64::INFINITY;
    }
    let gap = -delta;
    // Roots of ½A h² + V h − κg = 0 and A h² + V h − 2εc = 0 in the cancellation-free form
    // 2C/(V + sqrt(V² + 4·(A/2)·C)) etc., valid also for A = 0.
    let approach =
        2.0 * APPROACH_FRACTION * gap / (v + (v * v + 2.0 * APPROACH_FRACTION * a * gap).sqrt());
    let depth = GRAZE_DEPTH_FRACTION * clearance.abs();
    let floor = 4.0 * depth / (v + (v * v + 8.0 * a * depth).sqrt());
    approach.max(floor)
}

#[cfg(test)]
mod tests {
    use super::*;

    const C: f64 = 5e-4;

    #[test]
    fn unlimited_in_contact_or_at_rest() {
        // δ = 0 (a restart at a separation): no gap left, so the floor step applies:
        // 4εc/(V + √(V² + 8εAc)) with V = A = 1.
        let floor = 4.0 * 1e-3 * C / (1.0 + (1.0 + 8.0 * 1e-3 * C).sqrt());
        assert_eq!(free_flight_max_step(0.0, 1.0, 1.0, C), floor);
        assert_eq!(free_flight_max_step(1e-6, 1.0, 1.0, C), f64::INFINITY);
        assert_eq!(free_flight_max_step(-1e-4, 0.0, 0.0, C), f64::INFINITY);
        assert_eq!(free_flight_max_step(f64::NAN, 1.0, 1.0, C), f64::INFINITY);
    }

    /// Constant speed, far from the wall: h = κ g/V = 0.5 · 1e-4 / 0.2 = 2.5e-4 s.
    #[test]
    fn speed_only_far_from_wall() {
        let h = free_flight_max_step(-1e-4, 0.2, 0.0, C);
        assert!((h - 2.5e-4).abs() < 1e-18, "h = {h:e}");
    }

    /// Acceleration only: ½ A h² = κ g → h = sqrt(2κg/A) = sqrt(1e-4/10) = 3.1623e-3 s.
    #[test]
    fn acceleration_only() {
        let h = free_flight_max_step(-1e-4, 0.0, 10.0, C);
        assert!((h - (1e-5_f64).sqrt()).abs() < 1e-15, "h = {h:e}");
    }

    /// At the wall the floor takes over: speed only, h = 2εc/V = 2·1e-3·5e-4/0.2 = 5e-6 s.
    #[test]
    fn floor_near_the_wall() {
        let h = free_flight_max_step(-1e-12, 0.2, 0.0, C);
        assert!((h - 5e-6).abs() < 1e-18, "h = {h:e}");
    }

    /// The two guarantees, at many combinations of gap, speed and acceleration: a step of h_max
    /// either cannot reach the wall (V h + ½A h² ≤ κ g) or is a floor step whose missed graze
    /// is at most ε c deep ((V + A h) h / 2 ≤ ε c). Tolerance 1e-12 relative: rounding of the
    /// roots.
    #[test]
    fn guarantees_hold() {
        for gap in [1e-12, 1e-9, 1e-7, 1e-6, 1e-5, 1e-4, 4.9e-4] {
            for v in [0.0, 1e-4, 1e-2, 0.3, 5.0] {
                for a in [0.0, 1.0, 1e2, 1e4] {
                    if v == 0.0 && a == 0.0 {
                        continue;
                    }
                    let h = free_flight_max_step(-gap, v, a, C);
                    assert!(h > 0.0 && h.is_finite(), "gap {gap}, V {v}, A {a}: h = {h}");
                    let approach = v * h + 0.5 * a * h * h;
                    let graze = (v + a * h) * h / 2.0;
                    let no_contact = approach <= APPROACH_FRACTION * gap * (1.0 + 1e-12);
                    let shallow = graze <= GRAZE_DEPTH_FRACTION * C * (1.0 + 1e-12);
                    assert!(
                        no_contact || shallow,
                        "gap {gap}, V {v}, A {a}: h = {h:e}, approach {approach:e}, graze {graze:e}"
                    );
                }
            }
        }
    }

    /// Simulated worst case: the journal heads straight for the wall with constant speed and
    /// acceleration; stepping with h_max, the gap at most halves per step until the floor is
    /// reached, and never turns negative before the floor takes over.
    #[test]
    fn straight_approach_never_overshoots_before_floor() {
        let (mut gap, mut v, a) = (2e-4, 0.05, 30.0);
        for _ in 0..200 {
            let h = free_flight_max_step(-gap, v, a, C);
            let floor_only = free_flight_max_step(-1e-300, v, a, C);
            let new_gap = gap - (v * h + 0.5 * a * h * h);
            if h > floor_only {
                assert!(
                    new_gap >= 0.5 * gap * (1.0 - 1e-12),
                    "gap {gap:e} → {new_gap:e} with h = {h:e}"
                );
            } else {
                break;
            }
            gap = new_gap;
            v += a * h;
        }
    }
}
