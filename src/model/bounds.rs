//! The range of every physical value a model file may give, and why.
//!
//! A value outside its range is refused with the bound and the reason: such values are either
//! typing slips (a journal radius of 1e6 m, a clearance of 1e308 m) or outside what the laws in
//! `contact/` and rigid-body mechanics describe, and letting them through gives overflow, a run
//! that never ends, or numbers that look fine and mean nothing. Every bound is wide enough for
//! every real linkage from MEMS to heavy machinery.
//!
//! Ranges that follow from the laws themselves are checked in `build.rs` where the value is read:
//! every number finite; Poisson ratio ν ∈ (−1, 0.5) (a stable isotropic solid; ν = −1 makes the
//! compliance σ = (1 − ν²)/E vanish and K infinite); coefficient of restitution c_r ∈ (0, 1], none
//! for the purely elastic Hertz law (or exactly 1), at least [`MIN_FLORES_RESTITUTION`] for the
//! Flores law; contact exponent n ∈ [1, 3]; friction coefficient c_f ≥ 0 and 0 ≤ v0 < v1; initial
//! eccentricity |e0| < c (strictly: a contact under way at t = 0 has no impact velocity δ̇⁽⁻⁾ to
//! scale its damping; such a run on the reference four-bar made no impact and did not finish in
//! 1e7 steps, `docs/measurements.md`); clearance c < journal radius R_J.

/// Smallest body mass (kg): a 1 µm steel cube weighs 7.9e-15 kg. Below this nothing is a rigid
/// link, and the inverse mass 1/m that the formulations use grows without bound (1e300 at the
/// 1e-300 kg of a typing slip).
pub const MIN_MASS: f64 = 1e-15;

/// Smallest moment of inertia about the centre of mass (kg·m²): that 1 µm steel cube has
/// m a²/6 = 1.3e-27 kg·m². The same reasoning as for [`MIN_MASS`].
pub const MIN_INERTIA: f64 = 1e-30;

/// Largest body mass (kg): the booms of the largest excavators and mining shovels weigh tens of
/// tonnes; 1000 t leaves a margin of ten over any linkage. Beyond it the mass is a typing slip
/// (`mass = 1e300` made the reference four-bar crawl for 106 s and 88 MB before failing).
pub const MAX_MASS: f64 = 1e6;

/// Largest radius of gyration k = √(I/m) of a body, as a multiple of the linkage's extent D
/// (the largest distance between two of its points at the initial position: ground points,
/// body centres of mass and body points). The points are the joints, which may span much less
/// than the bodies: a rotating arm with k = 0.1 m whose joints lie within 0.25 mm
/// (`tests/grazing_contact.rs`, k = 400 D), a flywheel on a short crank. A thousand times D
/// still refuses what no body has: a 1e-12 kg link given I = 4.6e-3 kg·m² has k = 6.8e4 m on a
/// 1 m four-bar (70 000 D).
pub const MAX_GYRATION_PER_EXTENT: f64 = 1000.0;

/// Largest |coordinate| of a point or an initial position (m): 1 km, ten times the largest
/// machines (cranes, bridges' lifting spans are about 100 m).
pub const MAX_COORDINATE: f64 = 1e3;

/// Smallest extent D of a linkage (m): the largest distance between two of its points at the
/// initial position. Micro-mechanisms (MEMS) are tens of µm across, their pins a few µm
/// ([`MIN_JOURNAL_RADIUS`]); a linkage of 0.3 nm links took 235 s and 120 MB before failing.
pub const MIN_EXTENT: f64 = 1e-6;

/// Largest |angle| of an initial body angle or driver angle (rad): 1e4 rad is 1600 turns. The
/// spacing of f64 values there is 1.8e-12 rad, so positions computed through sin and cos keep
/// twelve digits; at 1e12 rad the spacing is 1.2e-4 rad and every position is off by about
/// 1e-4 of the link (a run from φ = 1e12 ended with |Φ| ≈ 2e-4 m and exit 0).
pub const MAX_ANGLE: f64 = 1e4;

/// Largest driver speed and initial angular velocity (rad/s): 1e4 rad/s is 95 500 rpm, beyond
/// the fastest crank trains (racing engines turn at about 20 000 rpm). A speed in rpm is
/// checked after conversion: 1e308 rpm overflows to an infinite speed in rad/s.
pub const MAX_SPEED: f64 = 1e4;

/// Largest initial linear velocity (m/s) of a body's centre of mass: a point 1 m from its pivot
/// turning at [`MAX_SPEED`].
pub const MAX_VELOCITY: f64 = 1e4;

/// Smallest journal radius R_J (m): pins of micro-mechanisms are a few µm.
pub const MIN_JOURNAL_RADIUS: f64 = 1e-6;

/// Largest journal radius R_J (m): the largest journal bearings (ship shafts, turbines) are
/// about 1 m in radius.
pub const MAX_JOURNAL_RADIUS: f64 = 10.0;

/// Smallest axial bearing length L (m): as [`MIN_JOURNAL_RADIUS`], the pins of
/// micro-mechanisms are a few µm long.
pub const MIN_BEARING_LENGTH: f64 = 1e-6;

/// Largest axial bearing length L (m): as [`MAX_JOURNAL_RADIUS`], ship-shaft and turbine
/// bearings are about a metre long.
pub const MAX_BEARING_LENGTH: f64 = 10.0;

/// Smallest radial clearance c (m): 1 nm, the roughness of the best polished surfaces; below it
/// a rigid-surface contact between journal and bearing means nothing. (The largest clearance is
/// the journal radius itself, checked where both are known: a bearing of more than twice the
/// journal's radius is not a joint with clearance.)
pub const MIN_CLEARANCE: f64 = 1e-9;

/// Smallest dimensional wear coefficient k_w = k/H (m²/N) of `[joints.wear]`: 1e-24 m²/N,
/// below the mildest measured wear (k ≈ 1e-8 on a 1e9 Pa hardness gives 1e-17 m²/N; Archard
/// and Hirst 1956 list k from 1e-2 to 1e-7).
pub const MIN_WEAR_COEFFICIENT: f64 = 1e-24;

/// Largest dimensional wear coefficient k_w (m²/N): 1e-6 m²/N, far above severe wear
/// (k = 1e-2 on a 1e8 Pa polymer gives 1e-10 m²/N), leaving room for the acceleration factors
/// wear studies multiply k_w by to reach a worn profile in few simulated cycles.
pub const MAX_WEAR_COEFFICIENT: f64 = 1e-6;

/// Smallest number of angular bins of a wear profile: 8 (45° each).
pub const MIN_WEAR_BINS: f64 = 8.0;

/// Largest number of angular bins of a wear profile: 1e5 (13 arc seconds each), beyond which
/// a bin is narrower than any contact width the laws here represent.
pub const MAX_WEAR_BINS: f64 = 1e5;

/// Smallest oil viscosity μ (Pa·s) of `[joints.lubrication]`: 1e-6 Pa·s, below any liquid
/// (water 1e-3, light oils 1e-2) and near gases (air 1.8e-5), whose film is no lubricant.
pub const MIN_VISCOSITY: f64 = 1e-6;

/// Largest oil viscosity μ (Pa·s): 1e4 Pa·s, beyond the heaviest greases and bitumens
/// (about 1e3); heavier is a solid for a bearing.
pub const MAX_VISCOSITY: f64 = 1e4;

/// Smallest Young's modulus E (Pa): soft rubber and silicone, about 1 MPa.
pub const MIN_YOUNGS_MODULUS: f64 = 1e6;

/// Largest Young's modulus E (Pa): diamond, 1.2 TPa, the stiffest bulk material.
pub const MAX_YOUNGS_MODULUS: f64 = 1.2e12;

/// Smallest generalised contact stiffness K given directly (N/m^n). K = 4/(3(σ_J + σ_B)) ·
/// √(R_J R_B/c) with σ = (1 − ν²)/E: materials and geometry within the bounds above (ν from 0
/// to 0.5) give K from 9.4e2 (E = 1 MPa, c → R_J = 1 µm) to 3.4e17 (E = 1.2 TPa, ν → 0.5, R_J = 10 m,
/// c = 1 nm); the bounds are that range rounded outward to a decade.
pub const MIN_STIFFNESS: f64 = 1e2;

/// Largest generalised contact stiffness K given directly (N/m^n): see [`MIN_STIFFNESS`].
pub const MAX_STIFFNESS: f64 = 1e18;

/// Smallest coefficient of restitution for the Flores et al. (2011) law. Its damping factor
/// χ = 8(1 − c_r)/(5 c_r) grows as 1/c_r, so the contact gets stiff in its damping and an explicit
/// integrator's steps shrink with it. On the reference four-bar (`models/farahan2016.toml`, DAE,
/// DOP853, rtol 1e-8, 2 turns; see `docs/measurements.md`) c_r = 0.9 needs 8.8e4 right-hand-side
/// evaluations, 0.01 1.5e5, 1e-3 5.7e5, 1e-4 5.0e6, 1e-5 4.2e7 (475×), and 1e-6 does not finish
/// in 1e7 steps. Physically, c_r < 0.01 is a plastic impact (the journal keeps less than 1 % of
/// its approach speed), which a continuous law with a finite stiffness does not describe.
pub const MIN_FLORES_RESTITUTION: f64 = 0.01;

#[cfg(test)]
mod tests {
    use super::*;

    /// K = 4/(3(σ_J + σ_B)) · √(R_J R_B/c), both sides of one material (docs/reference_parameters.md).
    fn stiffness(e: f64, nu: f64, r_j: f64, c: f64) -> f64 {
        let sigma = (1.0 - nu * nu) / e;
        4.0 / (3.0 * 2.0 * sigma) * (r_j * (r_j + c) / c).sqrt()
    }

    #[test]
    fn the_stiffness_bounds_enclose_what_the_material_and_size_bounds_give() {
        // Reference check value first, so the formula here is the right one.
        let k_ref = stiffness(207e9, 0.3, 0.01, 5e-4);
        assert!(
            (k_ref - 6.9494e10).abs() < 1e-4 * 6.9494e10,
            "K_ref = {k_ref:e}"
        );
        // Softest: E = 1 MPa, ν = 0, c → R_J = 1 µm. Stiffest: E = 1.2 TPa, ν → 0.5, R_J = 10 m,
        // c = 1 nm. The documented extremes, to two digits.
        let soft = stiffness(
            MIN_YOUNGS_MODULUS,
            0.0,
            MIN_JOURNAL_RADIUS,
            MIN_JOURNAL_RADIUS,
        );
        let stiff = stiffness(MAX_YOUNGS_MODULUS, 0.5, MAX_JOURNAL_RADIUS, MIN_CLEARANCE);
        assert!((soft - 9.4e2).abs() < 0.01 * 9.4e2, "softest K = {soft:e}");
        assert!(
            (stiff - 3.4e17).abs() < 0.01 * 3.4e17,
            "stiffest K = {stiff:e}"
        );
        assert!(MIN_STIFFNESS <= soft && MIN_STIFFNESS > soft / 10.0);
        assert!(MAX_STIFFNESS >= stiff && MAX_STIFFNESS < stiff * 10.0);
    }
}
