//! Archard's law on a bearing's angular bins: the wear a contact of normal force F_N, sliding at
//! v_t, deposits in a time dt, spread over the Hertz contact width (equations and references in
//! [`crate::contact::wear`]).

use super::WearProfile;
use crate::model::ClearanceSpec;
use std::f64::consts::{FRAC_PI_2, PI};

/// The data Archard's law needs for one worn joint.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ArchardWear {
    /// Dimensional wear coefficient k_w = k/H (m²/N).
    pub coefficient: f64,
    /// Axial length L of the bearing (m).
    pub length: f64,
    /// Bearing radius R_B = R_J + c (m).
    pub bearing_radius: f64,
    /// Hertz factor 4 R*/(π L E*) (m²/N): the half-width is b = sqrt(F_N · this).
    pub hertz_factor: f64,
}

impl ArchardWear {
    /// The wear data of a clearance joint with a `[joints.wear]` table and a `length`; `None`
    /// otherwise (the model builder requires the length wherever there is wear).
    pub fn from_spec(spec: &ClearanceSpec) -> Option<Self> {
        let wear = spec.wear?;
        let length = spec.length?;
        let r_j = spec.journal_radius;
        let r_b = r_j + spec.clearance;
        let compliance =
            |m: crate::model::Material| (1.0 - m.poisson_ratio.powi(2)) / m.youngs_modulus;
        let e_star = 1.0 / (compliance(spec.journal_material) + compliance(spec.bearing_material));
        let r_star = r_j * r_b / spec.clearance;
        Some(ArchardWear {
            coefficient: wear.coefficient,
            length,
            bearing_radius: r_b,
            hertz_factor: 4.0 * r_star / (PI * length * e_star),
        })
    }

    /// Hertz half-width b = sqrt(4 F_N R*/(π L E*)) (m) of the contact under the normal force
    /// F_N (`normal_force`, N), capped at π R_B/2.
    pub fn half_width(&self, normal_force: f64) -> f64 {
        (normal_force.max(0.0) * self.hertz_factor)
            .sqrt()
            .min(FRAC_PI_2 * self.bearing_radius)
    }

    /// Adds to `profile` the wear of a contact at the angle `theta` (rad, bearing frame) with
    /// normal force F_N (`normal_force`, N) and slip velocity v_t (`slip_velocity`, m/s), acting
    /// for `dt` (s): bin i gains k_w |v_t| dt (F_N/L) f_i / (R_B Δθ), f_i the share of the
    /// Hertz pressure over the bin (Σ f_i = 1, so the worn volume is k_w F_N |v_t| dt exactly).
    /// Nothing for F_N ≤ 0, v_t = 0 or dt ≤ 0.
    pub fn deposit(
        &self,
        profile: &mut WearProfile,
        theta: f64,
        normal_force: f64,
        slip_velocity: f64,
        dt: f64,
    ) {
        let n = profile.bins();
        let volume = self.coefficient * normal_force * slip_velocity.abs() * dt;
        if n == 0 || volume.is_nan() || volume <= 0.0 || !theta.is_finite() {
            return;
        }
        let width = profile.bin_width();
        let per_share = volume / (self.length * self.bearing_radius * width);
        let beta = self.half_width(normal_force) / self.bearing_radius;
        let first = ((theta - beta) / width).floor();
        let last = ((theta + beta) / width).floor();
        let depths = profile.depths_mut();
        if beta.is_nan() || beta <= 0.0 || first == last {
            // The whole contact inside one bin.
            let i = (first as i64).rem_euclid(n as i64) as usize;
            if let Some(h) = depths.get_mut(i) {
                *h += per_share;
            }
            return;
        }
        // At most π/Δθ + 2 bins: β ≤ π/2.
        let (first, last) = (first as i64, last as i64);
        for j in first..=last {
            let lo = ((j as f64 * width - theta) / beta).clamp(-1.0, 1.0);
            let hi = (((j + 1) as f64 * width - theta) / beta).clamp(-1.0, 1.0);
            let share = semi_ellipse_cdf(hi) - semi_ellipse_cdf(lo);
            let i = j.rem_euclid(n as i64) as usize;
            if let Some(h) = depths.get_mut(i) {
                *h += per_share * share;
            }
        }
    }
}

/// The share of a semi-elliptical distribution (2/π) sqrt(1 − x²) on [−1, u], less ½:
/// (u sqrt(1 − u²) + asin u)/π for u ∈ [−1, 1].
fn semi_ellipse_cdf(u: f64) -> f64 {
    (u * (1.0 - u * u).max(0.0).sqrt() + u.asin()) / PI
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wear(hertz_factor: f64) -> ArchardWear {
        ArchardWear {
            coefficient: 1e-13,
            length: 0.02,
            bearing_radius: 0.0105,
            hertz_factor,
        }
    }

    /// Archard's closed form on a prescribed contact history: a constant force F at a fixed
    /// angle, sliding at a constant v for a time T, in many small deposits. The worn volume is
    /// k_w F v T (to rounding: 1e-12 relative); with a contact narrower than a bin the depth
    /// of that bin is k_w F v T/(L R_B Δθ), the pressure F/(L R_B Δθ) times k_w v T.
    #[test]
    fn constant_load_and_speed_give_archards_closed_form() {
        let w = wear(1e-20); // b = 1e-8 m: far inside one bin
        let mut p = WearProfile::new(360);
        let (f, v, dt, steps) = (500.0, 0.3, 1e-4, 10_000);
        let theta = p.bin_centre(100);
        for _ in 0..steps {
            w.deposit(&mut p, theta, f, v, dt);
        }
        let t = dt * f64::from(steps);
        let volume = w.coefficient * f * v * t;
        let area = p.worn_area(w.bearing_radius) * w.length;
        assert!(
            (area - volume).abs() < 1e-12 * volume,
            "worn volume {area:e}, Archard {volume:e}"
        );
        let h = volume / (w.length * w.bearing_radius * p.bin_width());
        assert!(
            (p.depths()[100] - h).abs() < 1e-12 * h,
            "depth {:e}, closed form k_w p v t = {h:e}",
            p.depths()[100]
        );
        assert_eq!(p.depths()[99], 0.0);
        assert_eq!(p.depths()[101], 0.0);
    }

    /// A contact much wider than a bin: the bin under its centre wears at the Hertz peak
    /// pressure, h = k_w p0 v T with p0 = 2F/(π L b), to the bin-average error
    /// p0 (Δs/b)²/24 ≈ 3.5e-5 p0 here (Δs = R_B Δθ ≈ 1.8e-5 m, b ≈ 6.3e-4 m); and the volume is
    /// conserved though the contact straddles 0 = 2π.
    #[test]
    fn wide_contact_wears_at_the_hertz_peak_pressure() {
        let w = wear(8e-10);
        let mut p = WearProfile::new(3600);
        let (f, v, t) = (500.0, 0.3, 2.0);
        let theta = p.bin_centre(0);
        w.deposit(&mut p, theta, f, v, t);
        let b = w.half_width(f);
        assert!((b - (f * 8e-10_f64).sqrt()).abs() < 1e-15);
        let p0 = 2.0 * f / (PI * w.length * b);
        let h = w.coefficient * p0 * v * t;
        assert!(
            (p.depths()[0] - h).abs() < 2e-4 * h,
            "centre depth {:e}, k_w p0 v t = {h:e}",
            p.depths()[0]
        );
        let volume = w.coefficient * f * v * t;
        let area = p.worn_area(w.bearing_radius) * w.length;
        assert!(
            (area - volume).abs() < 1e-12 * volume,
            "{area:e} vs {volume:e}"
        );
        // Symmetric about bin 0's centre: bins 0 + k and 0 − k (mod N) equal.
        for k in 1..40 {
            let (a, b) = (p.depths()[k], p.depths()[3600 - k]);
            assert!((a - b).abs() < 1e-12 * h, "bins ±{k}: {a:e} vs {b:e}");
        }
    }

    /// No wear without load, without sliding, or without time.
    #[test]
    fn no_load_no_slip_no_wear() {
        let w = wear(8e-10);
        let mut p = WearProfile::new(36);
        w.deposit(&mut p, 1.0, 0.0, 1.0, 1.0);
        w.deposit(&mut p, 1.0, 10.0, 0.0, 1.0);
        w.deposit(&mut p, 1.0, 10.0, 1.0, 0.0);
        w.deposit(&mut p, f64::NAN, 10.0, 1.0, 1.0);
        assert!(p.is_unworn());
    }
}
