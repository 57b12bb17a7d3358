//! Special points between two consecutive points of a branch: what changed (the test
//! functions) and where (regula falsi along the step).
//!
//! Each kind of special point is a change of one discrete property of the orbit, and comes
//! with a continuous distance that vanishes at the change:
//!
//! | kind | changes | distance |
//! |---|---|---|
//! | fold | the count of real μ > 1 | min_i \|μ_i − 1\| |
//! | period doubling | the count of real μ < −1 | min_i \|μ_i + 1\| |
//! | Neimark–Sacker | the count of complex pairs with \|μ\| > 1 + tol | min over pairs \|\|μ\| − 1\| |
//! | grazing | the impacts per period, or the sign of the smallest gap | \|smallest gap\| (impacts: none) |
//!
//! Counting, rather than the sign of a product such as det(M − I), keeps a change of the
//! unknowns between two points (a stored impact velocity that becomes active adds a multiplier
//! near 0) from reading as a crossing. The signed distance ψ = ±distance (− while the property
//! is as at the step's start) is what regula falsi zeroes.

use serde::Serialize;

/// A special point of a branch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SpecialKind {
    /// A real Floquet multiplier through +1 (a fold of the branch, or a pitchfork or
    /// transcritical point where the branch does not turn).
    Fold,
    /// A real multiplier through −1: a period-2K orbit branches off.
    PeriodDoubling,
    /// A complex pair of multipliers through the unit circle (a torus branches off).
    NeimarkSacker,
    /// An impact appears or disappears (the impacts per period change), or the smallest gap
    /// passes 0.
    Grazing,
}

impl SpecialKind {
    /// Every kind, in the order in which they are tested.
    pub const ALL: [SpecialKind; 4] = [
        SpecialKind::Fold,
        SpecialKind::PeriodDoubling,
        SpecialKind::NeimarkSacker,
        SpecialKind::Grazing,
    ];

    /// The name in files and messages: `fold`, `PD`, `NS`, `grazing`.
    pub fn name(self) -> &'static str {
        match self {
            SpecialKind::Fold => "fold",
            SpecialKind::PeriodDoubling => "PD",
            SpecialKind::NeimarkSacker => "NS",
            SpecialKind::Grazing => "grazing",
        }
    }
}

impl std::fmt::Display for SpecialKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// What the test functions read from one point.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Observed<'a> {
    pub multipliers: &'a [[f64; 2]],
    pub impacts: usize,
    pub min_gap: Option<f64>,
}

/// A multiplier is real when its imaginary part is below this fraction of its modulus
/// (nalgebra returns exact zeros for real eigenvalues; this only guards rounding).
const REAL: f64 = 1e-12;

/// Whether the multiplier `z` (re, im) is real.
pub(super) fn is_real(z: &[f64; 2]) -> bool {
    z[1].abs() <= REAL * z[0].hypot(z[1])
}

/// The discrete property of `kind` at a point: a count, or for grazing (impacts, gap < 0).
fn property(kind: SpecialKind, o: &Observed<'_>, tol: f64) -> (usize, usize) {
    match kind {
        SpecialKind::Fold => (
            o.multipliers
                .iter()
                .filter(|z| is_real(z) && z[0] > 1.0)
                .count(),
            0,
        ),
        SpecialKind::PeriodDoubling => (
            o.multipliers
                .iter()
                .filter(|z| is_real(z) && z[0] < -1.0)
                .count(),
            0,
        ),
        SpecialKind::NeimarkSacker => (
            o.multipliers
                .iter()
                .filter(|z| !is_real(z) && z[1] > 0.0 && z[0].hypot(z[1]) > 1.0 + tol)
                .count(),
            0,
        ),
        SpecialKind::Grazing => (o.impacts, usize::from(o.min_gap.is_some_and(|g| g < 0.0))),
    }
}

/// The distance of `kind` at a point (≥ 0; 1 where there is none to measure).
fn distance(kind: SpecialKind, o: &Observed<'_>) -> f64 {
    let nearest = |target: f64| {
        o.multipliers
            .iter()
            .map(|z| (z[0] - target).hypot(z[1]))
            .fold(f64::INFINITY, f64::min)
    };
    let d = match kind {
        SpecialKind::Fold => nearest(1.0),
        SpecialKind::PeriodDoubling => nearest(-1.0),
        SpecialKind::NeimarkSacker => o
            .multipliers
            .iter()
            .filter(|z| !is_real(z))
            .map(|z| (z[0].hypot(z[1]) - 1.0).abs())
            .fold(f64::INFINITY, f64::min),
        SpecialKind::Grazing => o.min_gap.map_or(f64::INFINITY, f64::abs),
    };
    if d.is_finite() { d } else { 1.0 }
}

/// The kinds whose property differs between `a` and `b`.
pub(super) fn changes(a: &Observed<'_>, b: &Observed<'_>, tol: f64) -> Vec<SpecialKind> {
    SpecialKind::ALL
        .into_iter()
        .filter(|&k| property(k, a, tol) != property(k, b, tol))
        .collect()
}

/// The signed distance ψ of `kind` at `o`: −distance while its property is as at `start`,
/// +distance once it has changed. For grazing by a change of the impacts alone, ±1 (the
/// smallest gap need not pass near 0 when an impact appears elsewhere in the period).
pub(super) fn signed_distance(
    kind: SpecialKind,
    start: &Observed<'_>,
    end: &Observed<'_>,
    o: &Observed<'_>,
    tol: f64,
) -> f64 {
    let changed = property(kind, o, tol) != property(kind, start, tol);
    let gap_changes =
        kind != SpecialKind::Grazing || property(kind, start, tol).1 != property(kind, end, tol).1;
    let d = if gap_changes { distance(kind, o) } else { 1.0 };
    if changed { d } else { -d }
}

/// Regula falsi with the Illinois modification on ψ over [0, s_end], ψ(0) < 0 < ψ(s_end):
/// `psi(s)` evaluates a point at s (None where no point was found). Stops when the bracket is
/// at most `tol_s` or after `max_evaluations`; returns the s of every point evaluated, with ψ.
pub(super) fn regula_falsi(
    psi_start: f64,
    psi_end: f64,
    s_end: f64,
    tol_s: f64,
    max_evaluations: usize,
    mut psi: impl FnMut(f64) -> Option<f64>,
) -> Vec<(f64, f64)> {
    let (mut a, mut fa) = (0.0, psi_start.min(-f64::MIN_POSITIVE));
    let (mut b, mut fb) = (s_end, psi_end.max(f64::MIN_POSITIVE));
    let mut side = 0i8;
    let mut seen = Vec::new();
    for _ in 0..max_evaluations {
        if (b - a).abs() <= tol_s {
            break;
        }
        // The secant's root, kept off the bracket's ends so that it always shrinks.
        let w = b - a;
        let s = (b - fb * w / (fb - fa)).clamp(a + 0.02 * w, b - 0.02 * w);
        let Some(fs) = psi(s) else { break };
        seen.push((s, fs));
        if fs < 0.0 {
            (a, fa) = (s, fs);
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            (b, fb) = (s, fs);
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    seen
}

#[cfg(test)]
mod tests {
    use super::*;

    fn obs(mu: &[[f64; 2]]) -> Observed<'_> {
        Observed {
            multipliers: mu,
            impacts: 1,
            min_gap: Some(-1e-4),
        }
    }

    #[test]
    fn a_real_multiplier_through_minus_one_is_a_period_doubling_only() {
        let a = [[-0.9, 0.0], [0.2, 0.0]];
        let b = [[-1.1, 0.0], [0.2, 0.0]];
        assert_eq!(
            changes(&obs(&a), &obs(&b), 1e-6),
            vec![SpecialKind::PeriodDoubling]
        );
        // A pair meeting at −1 and splitting along the axis (a conservative system's edge of
        // instability) is one too.
        let (s, c) = 3.1f64.sin_cos();
        let pair = [[c, s], [c, -s]];
        let split = [[-1.05, 0.0], [-1.0 / 1.05, 0.0]];
        assert_eq!(
            changes(&obs(&pair), &obs(&split), 1e-6),
            vec![SpecialKind::PeriodDoubling]
        );
    }

    #[test]
    fn a_pair_on_the_circle_is_no_neimark_sacker_but_one_leaving_it_is() {
        let on = [[0.6, 0.8], [0.6, -0.8]];
        let noisy = [[0.6 * (1.0 + 1e-9), 0.8], [0.6 * (1.0 + 1e-9), -0.8]];
        assert!(changes(&obs(&on), &obs(&noisy), 1e-6).is_empty());
        let out = [[0.63, 0.84], [0.63, -0.84]];
        assert_eq!(
            changes(&obs(&on), &obs(&out), 1e-6),
            vec![SpecialKind::NeimarkSacker]
        );
    }

    #[test]
    fn a_new_impact_or_a_gap_through_zero_is_grazing() {
        let mu = [[0.3, 0.0]];
        let a = obs(&mu);
        let mut b = obs(&mu);
        b.impacts = 2;
        assert_eq!(changes(&a, &b, 1e-6), vec![SpecialKind::Grazing]);
        let mut c = obs(&mu);
        c.min_gap = Some(2e-6);
        assert_eq!(changes(&a, &c, 1e-6), vec![SpecialKind::Grazing]);
        // ψ is the gap's distance, negative on the start's side.
        assert_eq!(
            signed_distance(SpecialKind::Grazing, &a, &c, &c, 1e-6),
            2e-6
        );
        assert_eq!(
            signed_distance(SpecialKind::Grazing, &a, &c, &a, 1e-6),
            -1e-4
        );
    }

    #[test]
    fn regula_falsi_finds_the_root_of_a_square_root_crossing() {
        // ψ(s) = sign(s − r)·√|s − r|: the shape of a pair meeting on the real axis.
        let r = 0.3137;
        let psi = |s: f64| (s - r).signum() * (s - r).abs().sqrt();
        let seen = regula_falsi(psi(0.0), psi(1.0), 1.0, 1e-10, 60, |s| Some(psi(s)));
        let best = seen
            .iter()
            .min_by(|x, y| x.1.abs().total_cmp(&y.1.abs()))
            .map(|x| x.0);
        let best = best.unwrap_or(f64::NAN);
        assert!((best - r).abs() < 1e-8, "root {best}, expected {r}");
    }
}
