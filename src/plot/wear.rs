//! The polar figure of a worn bearing (`linkdyn wear`): the unworn clearance circle and the
//! worn clearance c + s·h(θ) in the bearing body's frame, the wear magnified by a stated factor
//! s so that micrometres of wear show on a clearance of a fraction of a millimetre.

use super::{Axis, Dash, Figure, Series, Style};
use crate::numbers::{format_for_people, format_number};

/// Millimetres per metre: the figure's unit.
const MM_PER_M: f64 = 1e3;

/// The exaggeration factor s ≥ 1 that draws the deepest wear `max_depth` (m) at about half the
/// clearance `clearance` (m): the largest of 1, 2 and 5 times a power of ten not above
/// c/(2 h_max); 1 for an unworn bearing or wear beyond c/2.
pub fn exaggeration(clearance: f64, max_depth: f64) -> f64 {
    if !(max_depth > 0.0 && clearance > 0.0) {
        return 1.0;
    }
    let ideal = 0.5 * clearance / max_depth;
    if !ideal.is_finite() || ideal <= 1.0 {
        return 1.0;
    }
    let decade = 10f64.powf(ideal.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|s| *s <= ideal)
        .unwrap_or(decade)
        .max(1.0)
}

/// The figure: `joint`'s unworn clearance circle (radius c = `clearance`, m) and each profile
/// of `profiles` (legend name, depth per bin in m, bins centred at `bin_centres`, rad, bearing
/// frame) drawn as the closed curve r(θ) = c + s·h(θ) in mm, s from [`exaggeration`] for the
/// deepest of them, stated in the title.
pub fn worn_profile(
    joint: &str,
    clearance: f64,
    bin_centres: &[f64],
    profiles: &[(String, &[f64])],
) -> Figure {
    let max_depth = profiles
        .iter()
        .flat_map(|(_, d)| d.iter().copied())
        .fold(0.0, f64::max);
    let s = exaggeration(clearance, max_depth);
    let c_mm = clearance * MM_PER_M;
    let mut fig = Figure::new(
        format!(
            "Worn bearing {joint}, wear magnified {}×: c + {}·h(θ), c = {} mm, max h = {} µm",
            format_number(s),
            format_number(s),
            format_number(c_mm),
            format_for_people(max_depth * 1e6)
        ),
        Axis::labelled(format!("{joint} bearing x (mm)")),
        Axis::labelled(format!("{joint} bearing y (mm)")),
    );
    let closed = |r: &dyn Fn(usize) -> f64| -> Vec<(f64, f64)> {
        let mut points: Vec<(f64, f64)> = bin_centres
            .iter()
            .enumerate()
            .map(|(i, th)| (r(i) * th.cos(), r(i) * th.sin()))
            .collect();
        if let Some(first) = points.first().copied() {
            points.push(first);
        }
        points
    };
    fig.series.push(Series {
        name: Some("unworn clearance circle".into()),
        style: Style::Reference,
        colour: 1,
        dash: Dash::Solid,
        points: closed(&|_| c_mm),
    });
    for (k, (name, depth)) in profiles.iter().enumerate() {
        fig.series.push(Series {
            name: Some(name.clone()),
            style: Style::Line,
            colour: if k == 0 { 0 } else { k + 1 },
            dash: Dash::nth(k),
            points: closed(&|i| c_mm + s * depth.get(i).copied().unwrap_or(0.0) * MM_PER_M),
        });
    }
    fig.x.min_span = Some(2.0 * c_mm);
    fig.y.min_span = Some(2.0 * c_mm);
    fig.equal_aspect = true;
    fig
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The factor draws the deepest wear at most at half the clearance, within a factor 2.5
    /// of it (steps 1, 2, 5), and never shrinks the wear.
    #[test]
    fn exaggeration_is_a_round_factor_up_to_half_the_clearance() {
        for (c, h) in [(5e-4, 1e-6), (5e-4, 3e-7), (1e-3, 4.9e-5), (5e-4, 2e-9)] {
            let s = exaggeration(c, h);
            assert!(s * h <= 0.5 * c * (1.0 + 1e-12), "c {c}, h {h}: s = {s}");
            assert!(s * h > 0.5 * c / 2.5, "c {c}, h {h}: s = {s} too small");
        }
        assert_eq!(exaggeration(5e-4, 4e-4), 1.0);
        assert_eq!(exaggeration(5e-4, 0.0), 1.0);
    }
}
