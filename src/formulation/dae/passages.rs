//! Which near approaches to a singular position were passages through it.
//!
//! The pivot ratio r ([`crate::formulation::schur::Schur::min_pivot_ratio`]) falls like s² at
//! a distance s from a singular position, so along the motion r ≈ c (t − t*)² + r₀ near its
//! minimum, with r₀ = 0 for a passage through the singular position and r₀ > 0 for an approach
//! that turns away or misses it (the quick-return mechanism comes within r = 4e-4). The steps
//! of one approach (an *episode*: consecutive steps with a stage below
//! [`super::projection::PROJECTION_RATIO`]) give r at their ends; r₀ is the vertex of the
//! parabola through the smallest of them and its two neighbours. That estimate does not depend
//! on a stage landing close to t*, which loose tolerances rarely do (steps of 0.2 rad stride over
//! the region r < 1e-6, |s| < 1e-3). An episode with no interior minimum (one or two step ends,
//! or r still falling at its last step end) keeps the smallest ratio seen, stages included.
//!
//! The stages of the episode's steps (rejected attempts included: their states are
//! approximations of the same motion, and r is smooth) are samples too, at their own times:
//! with them a step that strides over the whole approach still leaves a minimum with
//! neighbours on both sides. Before they were used, DOP853 with its long steps reported 8–18 of
//! the 20 passages of models/nfourbar_chain.toml (2–40 loops, rtol 1e-6 … 1e-10), a lower bound.

use super::SINGULAR_PASSAGE_RATIO;
use super::projection::PROJECTION_RATIO;

/// One approach to a singular position: the pivot ratio at the step ends, and the smallest one
/// of any stage.
#[derive(Debug, Clone, Default)]
pub(super) struct Episode {
    /// (t, r) at the step ends of the episode and at its stages below the projection ratio.
    ends: Vec<(f64, f64)>,
    /// Smallest pivot ratio of any stage of its steps.
    stage_min: f64,
}

impl Episode {
    /// Whether no step has been added since the last [`Episode::finish`].
    pub(super) fn is_empty(&self) -> bool {
        self.ends.is_empty()
    }

    /// Adds a step ending at t with pivot ratio `r_end` whose stages came down to `stage_min`,
    /// with the (t, r) of those of its stages that came near ([`PROJECTION_RATIO`]).
    pub(super) fn add(&mut self, t: f64, r_end: f64, stage_min: f64, stages: &[(f64, f64)]) {
        if self.ends.is_empty() {
            self.stage_min = stage_min;
        }
        self.ends.push((t, r_end));
        self.ends.extend_from_slice(stages);
        self.stage_min = self.stage_min.min(stage_min).min(r_end);
    }

    /// The time of the passage if the episode passed through a singular position (its smallest
    /// ratio, observed or fitted, below [`SINGULAR_PASSAGE_RATIO`]); clears the episode.
    pub(super) fn finish(&mut self) -> Option<f64> {
        let passage = self.passage();
        self.ends.clear();
        passage
    }

    /// See [`Episode::finish`], without clearing.
    pub(super) fn passage(&self) -> Option<f64> {
        let mut points = self.ends.clone();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        points.dedup_by(|a, b| a.0 == b.0);
        let (k, &(t_min, _)) = points
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.1.total_cmp(&b.1.1))?;
        // The parabola holds near the minimum only (r ≲ 1e-2, |s| ≲ 0.1): farther points
        // would bend the fit (r is closer to sin² s, and the smallest pivot may change rows).
        let fitted = (k > 0 && k + 1 < points.len())
            .then(|| [points[k - 1], points[k], points[k + 1]])
            .filter(|p| p.iter().all(|&(_, r)| r < PROJECTION_RATIO))
            .and_then(|[a, b, c]| vertex(a, b, c));
        match fitted {
            Some((t_star, r0)) if r0.min(self.stage_min) < SINGULAR_PASSAGE_RATIO => Some(t_star),
            _ if self.stage_min < SINGULAR_PASSAGE_RATIO => Some(t_min),
            _ => None,
        }
    }
}

/// Vertex (t*, r₀) of the parabola through three points with t₀ < t₁ < t₂ and r₁ the smallest;
/// `None` if it does not open upwards or its vertex lies outside [t₀, t₂].
fn vertex(p0: (f64, f64), p1: (f64, f64), p2: (f64, f64)) -> Option<(f64, f64)> {
    let ((t0, r0), (t1, r1), (t2, r2)) = (p0, p1, p2);
    // Divided differences: r = r1 + b (t − t1) + a (t − t1)(t − t0)... written about t1.
    let d01 = (r1 - r0) / (t1 - t0);
    let d12 = (r2 - r1) / (t2 - t1);
    let a = (d12 - d01) / (t2 - t0);
    if a.is_nan() || a <= 0.0 {
        return None;
    }
    // r'(t) = d01 + a (2t − t0 − t1) = 0.
    let t_star = 0.5 * (t0 + t1) - d01 / (2.0 * a);
    if !(t0..=t2).contains(&t_star) {
        return None;
    }
    let r_star = r0 + d01 * (t_star - t0) + a * (t_star - t0) * (t_star - t1);
    Some((t_star, r_star))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// r = c (t − t*)² sampled coarsely (no sample near t*) is a passage at t*; the same
    /// parabola lifted to r₀ = 1e-4 (an approach that misses) is not.
    #[test]
    fn a_coarsely_sampled_passage_is_found_and_a_near_miss_is_not() {
        let (c, t_star) = (10.0, 0.1234);
        for (r0, expected) in [(0.0, true), (1e-4, false)] {
            let mut e = Episode::default();
            for t in [0.105, 0.115, 0.135, 0.150] {
                let r: f64 = c * (t - t_star) * (t - t_star) + r0;
                e.add(t, r, r, &[]);
            }
            let p = e.finish();
            assert_eq!(p.is_some(), expected, "r0 = {r0}: {p:?}");
            if let Some(t) = p {
                assert!((t - t_star).abs() < 1e-12, "t = {t}");
            }
            assert!(e.is_empty());
        }
    }

    /// One long step over the whole approach: its two ends alone have no interior minimum,
    /// but its stages (at their own times, none near t*) give one, and the fitted vertex
    /// finds the passage; the same samples lifted to r₀ = 4e-4 (quick_return's closest
    /// approach) are not one.
    #[test]
    fn the_stages_of_a_step_that_strides_over_the_approach_find_the_passage() {
        let (c, t_star) = (25.0, 0.7216);
        for (r0, expected) in [(0.0, true), (4e-4, false)] {
            let r = |t: f64| c * (t - t_star) * (t - t_star) + r0;
            let stages: Vec<(f64, f64)> = [0.705, 0.712, 0.7185, 0.7262, 0.733]
                .iter()
                .map(|&t| (t, r(t)))
                .collect();
            let mut e = Episode::default();
            e.add(0.736, r(0.736), r(0.7185), &stages);
            let p = e.finish();
            assert_eq!(p.is_some(), expected, "r0 = {r0}: {p:?}");
            if let Some(t) = p {
                assert!((t - t_star).abs() < 1e-12, "t = {t}");
            }
        }
    }

    /// An episode without an interior minimum relies on what it saw: a stage below the
    /// passage ratio makes it a passage, step ends still falling do not.
    #[test]
    fn an_episode_without_interior_minimum_uses_the_smallest_ratio_seen() {
        let mut e = Episode::default();
        e.add(0.1, 1e-3, 1e-3, &[]);
        e.add(0.2, 1e-4, 1e-7, &[]);
        assert_eq!(e.passage(), Some(0.2));
        let mut e = Episode::default();
        e.add(0.1, 1e-3, 1e-3, &[]);
        e.add(0.2, 3e-4, 2e-4, &[]);
        assert_eq!(e.passage(), None);
    }
}
