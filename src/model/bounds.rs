//! The range of every physical value a model file may give, and why.
//!
//! A value outside its range is refused with the bound and the reason: such values are either
//! typing slips (a journal radius of 1e6 m, a clearance of 1e308 m) or outside what the laws in
//! `contact/` and rigid-body mechanics describe, and letting them through gives overflow, a run
//! that never ends, or numbers that look fine and mean nothing. Every bound is wide enough for
//! every real linkage from MEMS to heavy machinery.

/// Smallest body mass (kg): a 1 µm steel cube weighs 7.9e-15 kg. Below this nothing is a rigid
/// link, and the inverse mass 1/m that the formulations use grows without bound (1e300 at the
/// 1e-300 kg of a typing slip).
pub const MIN_MASS: f64 = 1e-15;

/// Smallest moment of inertia about the centre of mass (kg·m²): that 1 µm steel cube has
/// m a²/6 = 1.3e-27 kg·m². The same reasoning as for [`MIN_MASS`].
pub const MIN_INERTIA: f64 = 1e-30;

/// Smallest journal radius R_J (m): pins of micro-mechanisms are a few µm.
pub const MIN_JOURNAL_RADIUS: f64 = 1e-6;

/// Largest journal radius R_J (m): the largest journal bearings (ship shafts, turbines) are
/// about 1 m in radius.
pub const MAX_JOURNAL_RADIUS: f64 = 10.0;

/// Smallest radial clearance c (m): 1 nm, the roughness of the best polished surfaces; below it
/// a rigid-surface contact between journal and bearing means nothing. (The largest clearance is
/// the journal radius itself: see `build.rs`, a bearing of more than twice the journal's radius
/// is not a joint.)
pub const MIN_CLEARANCE: f64 = 1e-9;

/// Smallest Young's modulus E (Pa): soft rubber and silicone, about 1 MPa.
pub const MIN_YOUNGS_MODULUS: f64 = 1e6;

/// Largest Young's modulus E (Pa): diamond, 1.2 TPa, the stiffest bulk material.
pub const MAX_YOUNGS_MODULUS: f64 = 1.2e12;

/// Smallest generalised contact stiffness K given directly (N/m^n). K = 4/(3(σ_J + σ_B)) ·
/// √(R_J R_B/c) with σ = (1 − ν²)/E: materials and geometry within the bounds above (ν from 0
/// to 0.5) give K from 9.4e2 (E = 1 MPa, c → R_J = 1 µm) to 3.4e17 (E = 1.2 TPa, ν → 0.5, R_J = 10 m,
/// c = 1 nm); the bounds are that range rounded outward to a decade.
pub const MIN_STIFFNESS: f64 = 1e3;

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
