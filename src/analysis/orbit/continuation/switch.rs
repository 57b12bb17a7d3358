//! Branch switching at a period doubling: the branch of period-2K orbits that a located period
//! doubling of a period-K branch starts (docs/periodic_orbits.md, "Branch switching").
//!
//! # Where the branch starts
//! At a period doubling (x*, p*) the monodromy M of the period-K map P has a real multiplier
//! −1, eigenvector v. As fixed points of P², two branches cross at x*: the period-K branch,
//! and the period-2K branch x = x* + a v + O(a²), p = p* + O(a²), whose two halves x and P(x)
//! differ by 2a v + O(a²) (the flip bifurcation's normal form, a pitchfork of P²; Kuznetsov
//! §4.4). The switch:
//! 1. v by inverse iteration with M_AA + I (nearly singular there), restricted to the
//!    shooting's unknowns;
//! 2. the corrector on P²(x) − x = 0 from x* + h v̂ at p*, with the condition
//!    v̂·(w − w*) = h in scaled coordinates w (the amplitude along v̂ fixed, p free; Doedel,
//!    Keller and Kernévez). Near x* the period-2K orbit's multiplier next to +1 is within the
//!    monodromy's accuracy of 1 (it leaves 1 as a²), where Newton's matrix is as good as
//!    singular: the first point is taken only where that multiplier is at least
//!    [`NEAR_ONE`] from 1. h starts where the two halves of the orbit differ by 10
//!    `closing_limit` integration tolerances (closer, it is the period-K orbit within the
//!    tolerance that closes an orbit) and grows — ×4 while the corrected point is not a
//!    period-2K orbit, by the square-root law towards 2 [`NEAR_ONE`] from 1 once it is, back
//!    to the geometric mean where the corrector fails;
//! 3. the march of [`super::continue_orbit`] from there, its tangent oriented away from x*.
//!
//! The branch's first point is the period doubling itself as a period-2K orbit (M², the
//! multipliers squared), marked PD; the line from it to the next point is a chord.
//!
//! # Where it ends
//! Besides the range's ends: where it nears the period-K branch again — its multiplier next
//! to +1 within [`NEAR_ONE`] of 1 with the halves' difference d = x − P(x) shrinking, or d
//! through 0 or within `closing_limit` ε — at a period doubling of the period-K branch (such
//! as the other end of a period-doubling bubble). There the two halves meet as the square-root
//! law says, |d|² linear in p, so the junction's parameter is the zero of the line through
//! the last two points' |d|²; the period-K orbit is corrected there (p fixed, from the middle
//! of the last halves: M − I is regular at a period doubling) and ends the branch as a
//! period-2K orbit marked PD ([`super::BranchEnd::Rejoined`]). Its multiplier next to −1 says
//! how close to the period doubling the junction came.

//! # References
//! 1. Yu. A. Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd ed., Springer, 2004,
//!    §4.4 (the flip bifurcation), §10.3.
//! 2. E. J. Doedel, H. B. Keller and J. P. Kernévez, "Numerical analysis and control of
//!    bifurcation problems (II): bifurcation in infinite dimensions", *Int. J. Bifurcation and
//!    Chaos* 1 (1991) 745–772 (branch switching at period doublings of periodic solutions).

use nalgebra::{DMatrix, DVector};

use super::corrector::{Solved, WHAT, correct, plain};
use super::special::is_real;
use super::{
    Branch, BranchEnd, BranchPoint, ContinuationOptions, Marching, OrbitAt, OrbitFamily, Scales,
    SpecialKind, Watch, finished, newton, parameter_direction, validate,
};
use crate::analysis::AnalysisError;
use crate::analysis::orbit::coordinates::{
    angular_states, in_consistent_directions, less_whole_turns,
};
use crate::analysis::orbit::floquet::{active_states, restricted};
use crate::analysis::orbit::monodromy::shoot_watching;
use crate::formulation::Formulation;
use crate::solve::{SolverOptions, SolverStats};

/// `base` with its period multiplied by `times`.
struct Multiple<'a, Fam> {
    base: &'a Fam,
    times: usize,
}

impl<Fam: OrbitFamily> OrbitFamily for Multiple<'_, Fam> {
    type F = Fam::F;

    fn at(&self, p: f64) -> Result<OrbitAt<Fam::F>, AnalysisError> {
        let mut at = self.base.at(p)?;
        at.period *= self.times as f64;
        Ok(at)
    }

    fn contact_events(&self) -> usize {
        self.base.contact_events()
    }
}

/// The eigenvalue of `m` nearest −1 must be within this of it: a located period doubling is
/// within [`super::LOCATED`] of −1.
const NEAR_MINUS_ONE: f64 = 0.1;

/// Inverse iterations for the eigenvector of the multiplier near −1 (M + I is nearly singular
/// there: each iteration gains the ratio of its two smallest eigenvalues).
const INVERSE_ITERATIONS: usize = 6;

/// Amplitudes tried for the first period-2K point.
const AMPLITUDES: usize = 16;

/// A period-2K orbit whose multiplier next to +1 is within this of 1 is too near the period
/// doubling for Newton's matrix M² − I (module documentation): on the reference four-bar at
/// rtol 1e-10 that multiplier jumped by up to 0.06 between neighbouring points there.
pub(super) const NEAR_ONE: f64 = 0.1;

/// True where a period-2K orbit with these multipliers is too near its period doubling: a
/// real one within [`NEAR_ONE`] of +1.
pub(super) fn near_junction(multipliers: &[[f64; 2]]) -> bool {
    distance_to_one(multipliers) < NEAR_ONE
}

/// The period-K side of a period-2K branch.
pub(super) trait Halving {
    /// x − P_half(x) at a corrected point: the difference between the two halves of its
    /// period (raw units, full state length; zeros at inactive states).
    fn halves(&self, solved: &Solved, stats: &mut SolverStats) -> Result<Vec<f64>, AnalysisError>;
    /// The period-K orbit at the period doubling predicted at p (from `y`, searched within
    /// `reach` of p), as a period-2K orbit marked PD.
    fn junction(
        &self,
        p: f64,
        y: &[f64],
        reach: f64,
        stats: &mut SolverStats,
    ) -> Result<BranchPoint, AnalysisError>;
}

/// [`Halving`] for `family`'s orbits of `single.times` periods.
struct Halves<'a, Fam> {
    single: Multiple<'a, Fam>,
    options: &'a ContinuationOptions,
    solver: &'a SolverOptions,
    scales: &'a Scales,
}

impl<Fam: OrbitFamily> Halving for Halves<'_, Fam> {
    fn halves(&self, solved: &Solved, stats: &mut SolverStats) -> Result<Vec<f64>, AnalysisError> {
        let k_at = self.single.at(solved.p)?;
        let mid = plain(
            &k_at.f,
            solved.t0,
            &solved.y,
            solved.t0 + k_at.period,
            self.solver,
            stats,
        )?;
        let angular = angular_states(&k_at.f);
        let mut d = vec![0.0; solved.y.len()];
        for &i in &solved.active {
            d[i] = less_whole_turns(angular[i], solved.y[i] - mid[i]);
        }
        Ok(d)
    }

    fn junction(
        &self,
        p: f64,
        y: &[f64],
        reach: f64,
        stats: &mut SolverStats,
    ) -> Result<BranchPoint, AnalysisError> {
        let e_p = parameter_direction(y.len());
        // The period-K orbit at q (from `y`), and its real multiplier nearest −1, plus 1.
        let orbit_at = |q: f64, y: &[f64], stats: &mut SolverStats| {
            let solved = correct(
                &self.single,
                y,
                q,
                &e_p,
                self.scales,
                &newton(self.options, self.solver, self.options.first_iterations),
                self.solver,
                stats,
            )?;
            let point = finished(solved, &e_p, self.scales, self.single.contact_events())?;
            let psi = point
                .multipliers
                .iter()
                .filter(|z| is_real(z))
                .map(|z| z[0] + 1.0)
                .min_by(|a, b| a.abs().total_cmp(&b.abs()))
                .unwrap_or(f64::INFINITY);
            Ok::<_, AnalysisError>((q, psi, point))
        };
        // The period doubling itself: the secant method on ψ(q) = μ(q) + 1 from the
        // square-root law's prediction (M − I is regular there, each q a quick correction),
        // no further from it than the last point of the branch was: where the monodromy is
        // coarse (in contact, ~1e-3) and μ stays within its noise of −1 over a stretch, the
        // secant could wander along it.
        let mut b = orbit_at(p, y, stats)?;
        let step = (1e-3 * self.scales.parameter)
            .max(self.options.locate_tolerance)
            .min(0.5 * reach);
        let mut a = match orbit_at(p + step, &b.2.solved.y, stats) {
            Ok(a) => a,
            Err(_) => return Ok(as_doubled(&b.2.row(Some(SpecialKind::PeriodDoubling)))),
        };
        for _ in 0..self.options.locate_evaluations {
            if !(b.1.is_finite() && a.1.is_finite()) || a.1 == b.1 {
                break;
            }
            let q = b.0 - b.1 * (b.0 - a.0) / (b.1 - a.1);
            if (q - p).abs() > reach {
                break;
            }
            let Ok(c) = orbit_at(q, &b.2.solved.y, stats) else {
                break;
            };
            let done = (c.0 - b.0).abs() <= self.options.locate_tolerance;
            a = b;
            b = c;
            if done {
                break;
            }
        }
        let best = if a.1.abs() < b.1.abs() { a } else { b };
        Ok(as_doubled(&best.2.row(Some(SpecialKind::PeriodDoubling))))
    }
}

/// The branch of period-2K orbits that starts at the located period doubling `at` of a branch
/// of `family`'s orbits over `multiple` of its periods (1 for a branch of
/// [`super::continue_orbit`]; the new branch's orbits span 2·`multiple`), continued within
/// the range of `options` (module documentation). Its points' periods are twice `at`'s.
///
/// Errors: `at` is not a located period doubling, or its monodromy has no multiplier within
/// 0.1 of −1; invalid options; [`AnalysisError::NoConvergence`] when no period-2K orbit is
/// found near it (with the last residual history); a failed integration.
pub fn switch_branch<Fam: OrbitFamily>(
    family: &Fam,
    multiple: usize,
    at: &BranchPoint,
    options: &ContinuationOptions,
    solver: &SolverOptions,
) -> Result<Branch, AnalysisError> {
    switch_branch_watched(family, multiple, at, options, solver, &mut |_| true)
}

/// [`switch_branch`], with `watch` called on every point as it joins the branch (progress);
/// when it returns false the branch ends there ([`super::BranchEnd::Stopped`]).
///
/// Errors: as [`switch_branch`].
pub fn switch_branch_watched<Fam: OrbitFamily>(
    family: &Fam,
    multiple: usize,
    at: &BranchPoint,
    options: &ContinuationOptions,
    solver: &SolverOptions,
    watch: Watch<'_>,
) -> Result<Branch, AnalysisError> {
    validate(&at.y0, options)?;
    if at.special != Some(SpecialKind::PeriodDoubling) {
        return Err(AnalysisError::invalid(
            "at",
            format!(
                "expected a located period doubling, got the point at p = {} ({})",
                at.parameter,
                at.special.map_or("no special point", |k| k.name())
            ),
        ));
    }
    if multiple == 0 {
        return Err(AnalysisError::invalid("multiple", "expected ≥ 1, got 0"));
    }
    let n = at.y0.len();
    let mut stats = SolverStats::default();
    let single = Multiple {
        base: family,
        times: multiple,
    };
    let double = Multiple {
        base: family,
        times: 2 * multiple,
    };
    let k_at = single.at(at.parameter)?;
    let mut shot = shoot_watching(
        &k_at.f,
        at.t0,
        &at.y0,
        at.t0 + k_at.period,
        k_at.period / std::f64::consts::TAU,
        solver,
        WHAT,
        family.contact_events(),
    )?;
    stats.add_run(&shot.stats);
    let mut controlled = vec![true; n];
    k_at.f.error_controlled(&mut controlled);
    let active = active_states(&shot.monodromy, &controlled);
    // A constrained state's flip direction lies in its consistent directions.
    in_consistent_directions(&k_at.f, at.t0, &at.y0, &mut shot.monodromy, &active)?;
    let v = flip_eigenvector(&restricted(&shot.monodromy, n, &active)).ok_or_else(|| {
        AnalysisError::invalid(
            "at",
            format!(
                "the monodromy at p = {} has no multiplier within {NEAR_MINUS_ONE} of −1",
                at.parameter
            ),
        )
    })?;

    let scales = Scales {
        state: at.y0.iter().map(|y| y.abs().max(1.0)).collect(),
        parameter: (options.to - options.from).abs(),
    };
    // v̂ in scaled coordinates (states, then p: 0).
    let mut c = vec![0.0; n + 1];
    for (a, &i) in active.iter().enumerate() {
        c[i] = v[a] / scales.state[i];
    }
    let norm = c.iter().map(|x| x * x).sum::<f64>().sqrt();
    c.iter_mut().for_each(|x| *x /= norm);

    let tol = solver.controlled_tolerances();
    let eps = |y: f64| tol.atol + tol.rtol * y.abs();
    // Halves 2h·v̂ apart differ by 10 closing limits in the unknown where v̂ is largest in ε.
    let reach = active
        .iter()
        .map(|&i| c[i].abs() * scales.state[i] / eps(at.y0[i]))
        .fold(0.0, f64::max);
    let h_min = 10.0 * options.closing_limit / (2.0 * reach);

    let halving = Halves {
        single: Multiple {
            base: family,
            times: multiple,
        },
        options,
        solver,
        scales: &scales,
    };
    let march = Marching {
        options,
        solver,
        scales: &scales,
        halves: Some(&halving),
    };
    let (lo, hi) = (options.from.min(options.to), options.from.max(options.to));
    let mut last_error = None;
    let mut h = h_min;
    // The largest amplitude whose point was a period-2K orbit too near the period doubling.
    let mut too_near: Option<f64> = None;
    for _ in 0..AMPLITUDES {
        // Beyond the states' own size (scaled 1) the orbit is no longer near x*.
        if h > 1.0 {
            break;
        }
        let y: Vec<f64> = (0..n)
            .map(|i| at.y0[i] + h * c[i] * scales.state[i])
            .collect();
        let tried = correct(
            &double,
            &y,
            at.parameter,
            &c,
            &scales,
            &newton(options, solver, options.first_iterations),
            solver,
            &mut stats,
        )
        .and_then(|solved| march.point(&double, solved, &c, &mut stats));
        h = match tried {
            Ok(first)
                if march.halves_apart(&first) > options.closing_limit
                    && (lo..=hi).contains(&first.solved.p) =>
            {
                let gap = distance_to_one(&first.multipliers);
                if gap >= NEAR_ONE {
                    let rows = vec![as_doubled(at), first.row(None)];
                    let first_p = first.solved.p;
                    let (mut points, unlocated, end) =
                        march.run(&double, first, rows, h, &mut stats, &mut *watch);
                    let end = refuse_return_to_start(end, at.parameter, first_p, &mut points);
                    return Ok(Branch {
                        points,
                        unlocated,
                        end,
                        stats,
                    });
                }
                // The gap grows as h²: aim at twice the limit.
                too_near = Some(h);
                h * (2.0 * NEAR_ONE / gap.max(1e-12)).sqrt().clamp(1.5, 16.0)
            }
            Ok(_) => h * 4.0,
            Err(e) => {
                last_error = Some(e);
                match too_near {
                    Some(near) => (h * near).sqrt(),
                    None => h * 4.0,
                }
            }
        };
    }
    Err(match last_error {
        Some(AnalysisError::NoConvergence {
            analysis,
            reason,
            history,
        }) => AnalysisError::NoConvergence {
            analysis,
            reason: format!(
                "no period-2K orbit found at the period doubling p = {}: {reason}",
                at.parameter
            ),
            history,
        },
        Some(e) => e,
        None => AnalysisError::NoConvergence {
            analysis: WHAT,
            reason: format!(
                "no period-2K orbit found at the period doubling p = {} with a multiplier at least {NEAR_ONE} from +1: amplitudes {h_min:.3e} to {h:.3e} (scaled) gave the period-K orbit, left the range or stayed nearer",
                at.parameter
            ),
            history: Vec::new(),
        },
    })
}

/// A branch that "rejoined" the period-K branch nearer to the period doubling it started from
/// (at `start`) than its first point (at `first`) did has not found a branch: its first points
/// lay within the multipliers' noise of the period doubling and the junction test took them
/// for its other end (seen with the chord in ∂G/∂p: on the four-bar at rtol 2e-10 a branch of
/// 6 points rejoined 1.5e-8 m from its start, the bubble being 7e-6 m wide). Generically a
/// flip branch does not end where it began, so that end is a failure, with the reason, rather
/// than a branch returned as found; and its last point, the junction marked as a period
/// doubling, is dropped from `points` (it is no period doubling of this branch).
fn refuse_return_to_start(
    end: BranchEnd,
    start: f64,
    first: f64,
    points: &mut Vec<BranchPoint>,
) -> BranchEnd {
    match end {
        BranchEnd::Rejoined { parameter } if (parameter - start).abs() < (first - start).abs() => {
            if points
                .last()
                .is_some_and(|p| p.parameter == parameter && p.special.is_some())
            {
                points.pop();
            }
            BranchEnd::Failed {
                message: format!(
                    "the branch returned to the period doubling it started from (rejoined at p = {parameter}, {:.2e} from it, nearer than its first point at p = {first}): its first points lay within the multipliers' noise of the period doubling; tighten rtol",
                    (parameter - start).abs()
                ),
            }
        }
        other => other,
    }
}

/// |μ − 1| of the real multiplier nearest +1 (1 without one; a complex pair near +1, as a
/// conservative system's on the unit circle, is not the period doubling's).
fn distance_to_one(multipliers: &[[f64; 2]]) -> f64 {
    multipliers
        .iter()
        .filter(|z| is_real(z))
        .map(|z| (z[0] - 1.0).abs())
        .fold(1.0, f64::min)
}

/// The eigenvector (unit length) of the real eigenvalue of `m` nearest −1, by inverse
/// iteration with m + I; None when the iteration's eigenvalue is not within
/// [`NEAR_MINUS_ONE`] of −1.
fn flip_eigenvector(m: &DMatrix<f64>) -> Option<DVector<f64>> {
    let k = m.nrows();
    let shifted = m + DMatrix::identity(k, k);
    // An exactly singular M + I (the crossing hit in floating point) is shifted off it.
    let lu = shifted.clone().lu();
    let lu = if lu.is_invertible() {
        lu
    } else {
        (shifted + DMatrix::identity(k, k) * 1e-12).lu()
    };
    let mut v = DVector::from_element(k, 1.0 / (k as f64).sqrt());
    for _ in 0..INVERSE_ITERATIONS {
        let w = lu.solve(&v)?;
        let norm = w.norm();
        if !(norm.is_finite() && norm > 0.0) {
            return None;
        }
        v = w / norm;
    }
    let mu = v.dot(&(m * &v));
    ((mu + 1.0).abs() <= NEAR_MINUS_ONE).then_some(v)
}

/// The period doubling `at` seen as a period-2K orbit: the period doubled, M² (the multipliers
/// squared), the impacts doubled.
fn as_doubled(at: &BranchPoint) -> BranchPoint {
    let multipliers: Vec<[f64; 2]> = at
        .multipliers
        .iter()
        .map(|z| [z[0] * z[0] - z[1] * z[1], 2.0 * z[0] * z[1]])
        .collect();
    let spectral_radius = at.spectral_radius * at.spectral_radius;
    BranchPoint {
        period: 2.0 * at.period,
        multipliers,
        spectral_radius,
        stable: spectral_radius < 1.0,
        impacts_per_period: 2 * at.impacts_per_period,
        residual_history: Vec::new(),
        tangent_parameter: 0.0,
        special: Some(SpecialKind::PeriodDoubling),
        ..at.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A branch's rows: a point at each parameter, the last one a junction marked PD.
    fn rows(parameters: &[f64]) -> Vec<BranchPoint> {
        let last = parameters.len().saturating_sub(1);
        parameters
            .iter()
            .enumerate()
            .map(|(k, &parameter)| BranchPoint {
                parameter,
                y0: vec![0.0; 5],
                t0: 0.0,
                period: 1.0,
                multipliers: vec![[0.5, 0.0]],
                trivial_multipliers: 1,
                spectral_radius: 0.5,
                stable: true,
                impacts_per_period: 2,
                min_gap: None,
                residual: 1.0,
                residual_history: Vec::new(),
                tangent_parameter: 0.0,
                special: (k == last).then_some(SpecialKind::PeriodDoubling),
            })
            .collect()
    }

    /// The four-bar's spurious junction (rtol 2e-10, chord in ∂G/∂p): started at 0.4151604 mm,
    /// first point 0.6 µm below, "rejoined" at 0.4151754 mm. Refused, its junction row dropped;
    /// a junction at the bubble's other end, and every other end, passes unchanged.
    #[test]
    fn a_branch_that_returns_to_its_start_is_refused_without_its_junction() {
        let (start, first) = (0.4151604e-3, 0.4145604e-3);
        let back = 0.4151754e-3;
        let mut points = rows(&[start, first, 0.4148e-3, back]);
        let spurious = refuse_return_to_start(
            BranchEnd::Rejoined { parameter: back },
            start,
            first,
            &mut points,
        );
        let BranchEnd::Failed { message } = spurious else {
            panic!("{spurious:?}")
        };
        assert!(
            message.starts_with("the branch returned to the period doubling it started from"),
            "{message}"
        );
        // The spurious junction is gone; the points before it stay.
        let kept: Vec<f64> = points.iter().map(|p| p.parameter).collect();
        assert_eq!(kept, vec![start, first, 0.4148e-3]);
        let across = BranchEnd::Rejoined {
            parameter: 0.40795e-3,
        };
        let mut points = rows(&[start, first, 0.40795e-3]);
        assert_eq!(
            refuse_return_to_start(across.clone(), start, first, &mut points),
            across
        );
        assert_eq!(points.len(), 3);
        // The same on a branch that leaves its period doubling upwards.
        let up = BranchEnd::Rejoined {
            parameter: 0.41478e-3,
        };
        let mut points = rows(&[0.40789e-3, 0.4085e-3, 0.41478e-3]);
        assert_eq!(
            refuse_return_to_start(up.clone(), 0.40789e-3, 0.4085e-3, &mut points),
            up
        );
        assert_eq!(points.len(), 3);
        let mut points = rows(&[start, first, 0.40e-3]);
        assert_eq!(
            refuse_return_to_start(BranchEnd::Reached, start, first, &mut points),
            BranchEnd::Reached
        );
        assert_eq!(points.len(), 3);
    }

    #[test]
    fn the_flip_eigenvector_is_found_next_to_other_multipliers() {
        // Eigenvalues −1.0003, 0.5, −0.9 (a neighbour the iteration must not take).
        let p = DMatrix::from_row_slice(3, 3, &[1.0, 0.2, 0.0, 0.3, 1.0, 0.1, 0.0, 0.4, 1.0]);
        let d = DMatrix::from_diagonal(&DVector::from_vec(vec![-1.0003, 0.5, -0.9]));
        let m = &p
            * d
            * p.clone()
                .try_inverse()
                .unwrap_or_else(|| DMatrix::zeros(3, 3));
        let v = flip_eigenvector(&m).unwrap_or_else(|| DVector::zeros(3));
        let expected = p.column(0).normalize();
        let along = v.dot(&expected).abs();
        assert!((along - 1.0).abs() < 1e-9, "{v} against {expected}");
        // Without a multiplier near −1 there is none.
        let far = DMatrix::from_diagonal(&DVector::from_vec(vec![0.3, 0.5, -0.5]));
        assert!(flip_eigenvector(&far).is_none());
    }
}
