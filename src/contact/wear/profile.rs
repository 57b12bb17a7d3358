//! The worn profile of a bearing: wear depth h (m) in equal angular bins around the bearing
//! surface, in the bearing body's frame, read back by linear interpolation between the bin
//! centres (periodic), so that the worn wall has no artificial steps.
//!
//! Bin i covers θ ∈ [i Δθ, (i + 1) Δθ) with Δθ = 2π/N, centre (i + ½) Δθ; θ is counter-clockwise
//! from the bearing body's x axis.

use std::f64::consts::TAU;

/// Wear depth per angular bin (m), see the module documentation.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct WearProfile {
    depth: Vec<f64>,
}

impl WearProfile {
    /// An unworn profile of `bins` bins (all depths 0).
    pub fn new(bins: usize) -> Self {
        WearProfile {
            depth: vec![0.0; bins],
        }
    }

    /// Number of bins N.
    pub fn bins(&self) -> usize {
        self.depth.len()
    }

    /// Bin width Δθ = 2π/N (rad).
    pub fn bin_width(&self) -> f64 {
        TAU / self.depth.len().max(1) as f64
    }

    /// Centre (i + ½) Δθ of bin i (rad).
    pub fn bin_centre(&self, i: usize) -> f64 {
        (i as f64 + 0.5) * self.bin_width()
    }

    /// The depths h_i (m), bin by bin.
    pub fn depths(&self) -> &[f64] {
        &self.depth
    }

    /// The depths, to add wear to.
    pub fn depths_mut(&mut self) -> &mut [f64] {
        &mut self.depth
    }

    /// Adds `other`'s depths bin by bin (profiles of different sizes: the common bins only).
    pub fn add(&mut self, other: &WearProfile) {
        for (h, dh) in self.depth.iter_mut().zip(&other.depth) {
            *h += dh;
        }
    }

    /// True if every depth is zero (an unworn bearing).
    pub fn is_unworn(&self) -> bool {
        self.depth.iter().all(|&h| h == 0.0)
    }

    /// The depth h(θ) (m) and its slope dh/dθ (m/rad) at angle θ (rad, any value: taken modulo
    /// 2π), linear between bin centres. (0, 0) for a profile without bins.
    #[inline]
    pub fn depth_at(&self, theta: f64) -> (f64, f64) {
        let n = self.depth.len();
        if n == 0 {
            return (0.0, 0.0);
        }
        let width = self.bin_width();
        let u = theta.rem_euclid(TAU) / width - 0.5;
        let floor = u.floor();
        let frac = u - floor;
        // floor ∈ [−1, N − 1] (N at most for a θ that rounds up to 2π): wrap both neighbours.
        let i0 = (floor as i64).rem_euclid(n as i64) as usize;
        let i1 = (i0 + 1) % n;
        let h0 = self.depth.get(i0).copied().unwrap_or(0.0);
        let h1 = self.depth.get(i1).copied().unwrap_or(0.0);
        (h0 + frac * (h1 - h0), (h1 - h0) / width)
    }

    /// The deepest bin: its depth (m) and its centre angle (rad); (0, π/N) when unworn.
    pub fn max(&self) -> (f64, f64) {
        let (i, h) = self
            .depth
            .iter()
            .copied()
            .enumerate()
            .fold(
                (0, 0.0),
                |best, (i, h)| if h > best.1 { (i, h) } else { best },
            );
        (h, self.bin_centre(i))
    }

    /// Worn cross-section area Σ h_i R_B Δθ (m², the worn volume per unit axial length) on a
    /// bearing of radius R_B (`bearing_radius`, m), in the small-wear approximation.
    pub fn worn_area(&self, bearing_radius: f64) -> f64 {
        self.depth.iter().sum::<f64>() * bearing_radius * self.bin_width()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Interpolation: exact at the bin centres, linear between them, periodic across 0 = 2π,
    /// and the slope is the chord's.
    #[test]
    fn depth_is_linear_between_centres_and_periodic() {
        let mut p = WearProfile::new(8);
        for (i, h) in p.depths_mut().iter_mut().enumerate() {
            *h = i as f64 * 1e-6;
        }
        let w = p.bin_width();
        for i in 0..8 {
            let (h, _) = p.depth_at(p.bin_centre(i));
            assert!((h - i as f64 * 1e-6).abs() < 1e-18, "bin {i}: {h:e}");
        }
        // Midway between the centres of bins 2 and 3.
        let (h, s) = p.depth_at(3.0 * w);
        assert!((h - 2.5e-6).abs() < 1e-18 && (s - 1e-6 / w).abs() < 1e-15);
        // Across 2π: between bin 7 (7e-6) and bin 0 (0), at θ = 0 and at θ = −0 + 2π k.
        for theta in [0.0, TAU, -TAU, 3.0 * TAU] {
            let (h, s) = p.depth_at(theta);
            assert!((h - 3.5e-6).abs() < 1e-17, "θ = {theta}: h = {h:e}");
            assert!((s + 7e-6 / w).abs() < 1e-12, "θ = {theta}: slope = {s:e}");
        }
    }

    /// The worn area is Σ h R Δθ, and the maximum names the deepest bin's centre.
    #[test]
    fn area_and_maximum() {
        let mut p = WearProfile::new(4);
        p.depths_mut().copy_from_slice(&[1e-6, 4e-6, 2e-6, 0.0]);
        let area = p.worn_area(0.01);
        assert!((area - 7e-6 * 0.01 * TAU / 4.0).abs() < 1e-20);
        let (h, at) = p.max();
        assert_eq!(h, 4e-6);
        assert!((at - 1.5 * TAU / 4.0).abs() < 1e-15);
        assert!(!p.is_unworn() && WearProfile::new(3).is_unworn());
    }
}
