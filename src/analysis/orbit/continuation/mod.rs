//! Pseudo-arclength continuation of a periodic orbit in one parameter, with the detection and
//! location of folds, period doublings, Neimark–Sacker points and grazing
//! (docs/periodic_orbits.md, "Continuation").
//!
//! # Formulation
//! The unknowns are the orbit's state x at the section (the shooting's unknowns,
//! [`super::floquet`]) and the parameter p, in scaled coordinates w = (x_i/σ_i, p/σ_p) with
//! σ_i = max(|x_i|, 1) at the first point (SI units) and σ_p = |to − from|. A point of the
//! branch solves
//!
//! ```text
//! G(x, p) = P_p(x) − x = 0,        c·(w − w_pred) = 0,
//! ```
//!
//! P_p the period map at parameter p. Between points, c is the unit tangent v of the branch at
//! the last point and w_pred = w_last + Δs·v (pseudo-arclength, Keller 1977); the first point
//! has c = e_p (p fixed at `from`), and so has the last (p = `to`). The Jacobian is
//! \[\[M − I, ∂G/∂p\], \[c\]\]: M the monodromy matrix of the shot (variational equations with
//! saltation matrices), ∂G/∂p a forward difference of the period map in p (relative step
//! √rtol, [`ContinuationOptions::fd_step`]), formed again at every iterate of the correction
//! (kept from the predicted point, as a chord in that column, it stalled at period
//! doublings: `corrector.rs`). The tangent at a point solves
//! \[\[M − I, ∂G/∂p\], \[v_last\]\] t = (0, 1), with ∂G/∂p from the last iterate.
//!
//! # Corrector
//! Newton's method as in [`super::periodic_orbit`]: steps halved while the residual does not
//! drop, converged on the residual max_i |P(x)_i − x_i|/ε_i (ε_i = atol + rtol·|x_i|) — within
//! 1 ε, by a step within `step_tolerance` ε, or at the integration's noise floor below
//! `closing_limit` ε. The monodromy in contact is only ~1e-3 accurate
//! (docs/periodic_orbits.md), so convergence is linear there; the residual, not the Jacobian,
//! decides.
//!
//! # Step control
//! Δs starts at `max_step` (parameter units: Δs σ_p ≈ |Δp| where the state moves little),
//! is halved on a failed correction (down to `min_step`, then the continuation stops and
//! returns what it has with the reason), grown ×1.5 after a correction of at most 4
//! iterations and shrunk ×0.7 after one within 2 of `max_iterations`, never above `max_step`.
//! Newton converges linearly here, so one iteration more on a longer step is cheaper than
//! more steps (measured on the reference four-bar: growing only after ≤ 2 iterations took
//! 1318 points over 0.5 → 0.057 mm).
//!
//! # Special points
//! [`special`]: between consecutive points, a change of a count of multipliers (real μ > 1:
//! fold; real μ < −1: period doubling; complex pairs outside the circle: Neimark–Sacker) or of
//! the impacts per period or the smallest gap's sign (grazing) is located by regula falsi in
//! Δs along the step, each trial a corrected point; the located point joins the branch with
//! its kind.
//!
//! # References
//! 1. H. B. Keller, "Numerical solution of bifurcation and nonlinear eigenvalue problems", in
//!    *Applications of Bifurcation Theory*, Academic Press, 1977, pp. 359–384.
//! 2. Yu. A. Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd ed., Springer, 2004,
//!    §10.2 (continuation), §10.3 (test functions for fixed points of maps).

mod corrector;
pub mod special;
mod switch;

use serde::Serialize;

use self::corrector::{Newton, Solved, augmented_jacobian, correct};
pub use self::special::SpecialKind;
use self::special::{Observed, changes, regula_falsi, signed_distance};
use self::switch::Halving;
pub use self::switch::{switch_branch, switch_branch_watched};
use super::coordinates::in_coordinates;
use super::floquet::{multipliers, restricted, split_trivial};
use crate::analysis::AnalysisError;
use crate::formulation::{Crossing, Formulation};
use crate::solve::{SolverOptions, SolverStats};

/// The period map's problem at one parameter value.
#[derive(Debug, Clone)]
pub struct OrbitAt<F> {
    /// The formulation at that value.
    pub f: F,
    /// Time of the section (s).
    pub t0: f64,
    /// Period (s).
    pub period: f64,
}

/// A family of period maps in one parameter p (a model field, a forcing frequency …). The
/// state layout must not depend on p.
pub trait OrbitFamily {
    /// The formulation.
    type F: Formulation + Clone;
    /// The formulation, section and period at `p`.
    ///
    /// Errors: `p` is not a valid value (the model's own message).
    fn at(&self, p: f64) -> Result<OrbitAt<Self::F>, AnalysisError>;
    /// How many of the formulation's first event functions are contacts whose g is the
    /// penetration δ (m): a rising crossing is an impact, −g the gap (default 0).
    fn contact_events(&self) -> usize {
        0
    }
}

/// Options of [`continue_orbit`], with written defaults ([`ContinuationOptions::new`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContinuationOptions {
    /// First parameter value: the branch starts with the orbit there.
    pub from: f64,
    /// Last parameter value: the branch ends with the orbit there.
    pub to: f64,
    /// Largest step Δs (parameter units; Δs σ_p ≈ |Δp| where the state moves little), > 0.
    pub max_step: f64,
    /// Smallest step before the continuation gives up (default `max_step`/1000).
    pub min_step: f64,
    /// Most points on the branch, special points included (default 10 000).
    pub max_points: usize,
    /// Newton iterations of the first point (default 20).
    pub first_iterations: usize,
    /// Newton iterations of a point after the first (default 12).
    pub max_iterations: usize,
    /// Halvings of a Newton step that does not lower the residual (default 8).
    pub max_halvings: usize,
    /// Newton has converged on a step of at most this many ε (default 1).
    pub step_tolerance: f64,
    /// Largest closing error of a point (units of ε; default 1000, as [`super::OrbitOptions`]).
    pub closing_limit: f64,
    /// Relative step of the finite difference in p, of max(|p|, |to − from|). Default `None`:
    /// √rtol of the solver, the step that balances the difference's truncation error against
    /// the period map's integration noise (relative accuracy ~rtol; J. E. Dennis and R. B.
    /// Schnabel, *Numerical Methods for Unconstrained Optimization and Nonlinear Equations*,
    /// SIAM, 1996, §5.4). A step of 1e-6 at rtol 1e-8 let the noise turn the tangent of the
    /// reference four-bar's branch round.
    pub fd_step: Option<f64>,
    /// Special points are located to this many parameter units of arclength (default
    /// 1e-6·|to − from|).
    pub locate_tolerance: f64,
    /// Corrected points tried when locating one special point (default 30).
    pub locate_evaluations: usize,
    /// A complex pair counts as outside the unit circle above 1 + this (default 1e-6: the
    /// pairs of a conservative system stay on the circle to the integration's accuracy).
    pub multiplier_tolerance: f64,
}

impl ContinuationOptions {
    /// The defaults for a branch from `from` to `to` with steps up to `max_step`.
    pub fn new(from: f64, to: f64, max_step: f64) -> Self {
        ContinuationOptions {
            from,
            to,
            max_step,
            min_step: max_step * 1e-3,
            max_points: 10_000,
            first_iterations: 20,
            max_iterations: 12,
            max_halvings: 8,
            step_tolerance: 1.0,
            closing_limit: 1e3,
            fd_step: None,
            locate_tolerance: 1e-6 * (to - from).abs(),
            locate_evaluations: 30,
            multiplier_tolerance: 1e-6,
        }
    }
}

/// One point of a branch.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BranchPoint {
    /// Parameter value.
    pub parameter: f64,
    /// The full state at the section.
    pub y0: Vec<f64>,
    /// Time of the section (s).
    pub t0: f64,
    /// Period (s).
    pub period: f64,
    /// Nontrivial Floquet multipliers (re, im), by decreasing modulus.
    pub multipliers: Vec<[f64; 2]>,
    /// Trivial multipliers removed ([`super::floquet`]).
    pub trivial_multipliers: usize,
    /// Largest |μ|.
    pub spectral_radius: f64,
    /// Every nontrivial |μ| < 1.
    pub stable: bool,
    /// Rising crossings of the contact events over one period.
    pub impacts_per_period: usize,
    /// Smallest gap −δ over the period (m; the deepest penetration located inside the steps),
    /// with contact events.
    pub min_gap: Option<f64>,
    /// Closing error max_i |P(x)_i − x_i|/ε_i of the point (units of ε).
    pub residual: f64,
    /// The corrector's residual by iteration.
    pub residual_history: Vec<f64>,
    /// The parameter's component of the unit tangent (scaled coordinates); its sign change
    /// is a fold.
    pub tangent_parameter: f64,
    /// The special point this is, for a located one.
    pub special: Option<SpecialKind>,
}

/// Why the continuation stopped.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "reason")]
pub enum BranchEnd {
    /// The last point is at `to`.
    Reached,
    /// The branch left the range at `from`: it turned back (a fold), or a period-2K branch
    /// ([`switch_branch`]) headed that way.
    TurnedBack,
    /// A period-2K branch rejoined the period-K branch it started from, at a period doubling
    /// of that branch (its last point, marked [`SpecialKind::PeriodDoubling`]).
    Rejoined {
        /// The parameter where the two halves of the period became one.
        parameter: f64,
    },
    /// `max_points` points.
    MaxPoints,
    /// The caller's watch asked to stop after the last point (an interrupt):
    /// [`continue_orbit_watched`].
    Stopped,
    /// The branch ended without reaching one of the ends above: no point beyond the last with
    /// the smallest step, no orbit at a junction, or a switched branch that returned to the
    /// period doubling it started from.
    Failed {
        /// Why, in words (for a step that found no point: "no orbit beyond it with the smallest
        /// step: " and the corrector's last message).
        message: String,
    },
}

/// A located fold, period doubling or Neimark–Sacker point must have a multiplier within this
/// distance of its crossing (+1, −1, the unit circle); else the change is reported unlocated.
/// Regula falsi ends closer on a true crossing (within 7e-3 on the reference four-bar at rtol
/// 1e-10, 2e-3 on the pendulum's meeting pair); at rtol 1e-8 the four-bar's counts changed with
/// no multiplier nearer than 0.17 along the step.
const LOCATED: f64 = 0.05;

/// A correction of at most this many Newton iterations lets the next step grow.
const GROW_BELOW: usize = 4;

/// A computed branch.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Branch {
    /// The points in order of arclength, located special points among them.
    pub points: Vec<BranchPoint>,
    /// Special points that were detected but could not be located: (kind, the parameter of
    /// the point after the change, why).
    pub unlocated: Vec<(SpecialKind, f64, String)>,
    /// Why it stopped.
    pub end: BranchEnd,
    /// Cost of every integration.
    pub stats: SolverStats,
}

/// Scales of the coordinates (module documentation).
#[derive(Debug, Clone)]
pub(crate) struct Scales {
    pub state: Vec<f64>,
    pub parameter: f64,
}

/// A corrected point with what the test functions read.
struct Point {
    solved: Solved,
    multipliers: Vec<[f64; 2]>,
    trivial: usize,
    impacts: usize,
    /// The unit tangent (scaled, states then p; zeros at inactive states).
    tangent: Vec<f64>,
    /// On a period-2K branch, x − P_half(x) ([`Halving::halves`]); empty otherwise.
    halves: Vec<f64>,
}

impl Point {
    fn observed(&self) -> Observed<'_> {
        Observed {
            multipliers: &self.multipliers,
            impacts: self.impacts,
            min_gap: self.solved.shot.min_gap,
        }
    }

    fn w(&self, scales: &Scales) -> Vec<f64> {
        let mut w: Vec<f64> = self
            .solved
            .y
            .iter()
            .zip(&scales.state)
            .map(|(y, s)| y / s)
            .collect();
        w.push(self.solved.p / scales.parameter);
        w
    }

    fn row(&self, special: Option<SpecialKind>) -> BranchPoint {
        let spectral_radius = self
            .multipliers
            .iter()
            .map(|z| z[0].hypot(z[1]))
            .fold(0.0, f64::max);
        let s = &self.solved;
        BranchPoint {
            parameter: s.p,
            y0: s.y.clone(),
            t0: s.t0,
            period: s.period,
            multipliers: self.multipliers.clone(),
            trivial_multipliers: self.trivial,
            spectral_radius,
            stable: spectral_radius < 1.0,
            impacts_per_period: self.impacts,
            min_gap: s.shot.min_gap,
            residual: s.rho,
            residual_history: s.history.clone(),
            tangent_parameter: self.tangent.last().copied().unwrap_or(0.0),
            special,
        }
    }
}

/// Continues the periodic orbit of `family` from p = `from` (guess `guess`, the state at the
/// section) to p = `to` (module documentation).
///
/// Errors: invalid options or guess; [`AnalysisError::NoConvergence`] with the residual history
/// when there is no orbit at `from`; a failed integration or model at `from`. A failure after
/// the first point ends the branch ([`BranchEnd::Failed`]) instead.
pub fn continue_orbit<Fam: OrbitFamily>(
    family: &Fam,
    guess: &[f64],
    options: &ContinuationOptions,
    solver: &SolverOptions,
) -> Result<Branch, AnalysisError> {
    continue_orbit_watched(family, guess, options, solver, &mut |_| true)
}

/// [`continue_orbit`], with `watch` called on every point as it joins the branch (progress);
/// when it returns false the branch ends there ([`BranchEnd::Stopped`]).
///
/// Errors: as [`continue_orbit`].
pub fn continue_orbit_watched<Fam: OrbitFamily>(
    family: &Fam,
    guess: &[f64],
    options: &ContinuationOptions,
    solver: &SolverOptions,
    watch: Watch<'_>,
) -> Result<Branch, AnalysisError> {
    validate(guess, options)?;
    let n = guess.len();
    let mut stats = SolverStats::default();
    let dir = (options.to - options.from).signum();
    let scales = Scales {
        state: guess.iter().map(|y| y.abs().max(1.0)).collect(),
        parameter: (options.to - options.from).abs(),
    };
    let e_p = parameter_direction(n);
    let start_direction: Vec<f64> = e_p.iter().map(|c| c * dir).collect();

    let first = correct(
        family,
        guess,
        options.from,
        &e_p,
        &scales,
        &newton(options, solver, options.first_iterations),
        solver,
        &mut stats,
    )
    .map_err(|e| match e {
        AnalysisError::NoConvergence {
            analysis,
            reason,
            history,
        } => AnalysisError::NoConvergence {
            analysis,
            reason: format!("at the start (p = {}): {reason}", options.from),
            history,
        },
        e => e,
    })?;
    let Some(first) = finish(first, &start_direction, &scales, family.contact_events()) else {
        return Err(AnalysisError::invalid(
            "continuation",
            "the tangent of the branch at the start cannot be formed (singular augmented Jacobian)",
        ));
    };
    let rows = vec![first.row(None)];
    let march = Marching {
        options,
        solver,
        scales: &scales,
        halves: None,
    };
    let (points, unlocated, end) = march.run(
        family,
        first,
        rows,
        options.max_step / scales.parameter,
        &mut stats,
        watch,
    );
    Ok(Branch {
        points,
        unlocated,
        end,
        stats,
    })
}

/// Called on every point as it joins a branch; false stops the branch there.
pub type Watch<'a> = &'a mut dyn FnMut(&BranchPoint) -> bool;

/// The corrector's settings for `iterations` iterations.
fn newton(options: &ContinuationOptions, solver: &SolverOptions, iterations: usize) -> Newton {
    Newton {
        max_iterations: iterations,
        max_halvings: options.max_halvings,
        step_tolerance: options.step_tolerance,
        closing_limit: options.closing_limit,
        fd_step: options
            .fd_step
            .unwrap_or_else(|| solver.controlled_tolerances().rtol.sqrt()),
    }
}

/// e_p: the condition that fixes the parameter (scaled coordinates, n states then p).
fn parameter_direction(n: usize) -> Vec<f64> {
    let mut e_p = vec![0.0; n + 1];
    e_p[n] = 1.0;
    e_p
}

/// What a march along a branch needs besides its family and first point.
struct Marching<'a> {
    options: &'a ContinuationOptions,
    solver: &'a SolverOptions,
    scales: &'a Scales,
    /// For a period-2K branch ([`switch`]): its halves, whose difference vanishing ends the
    /// branch where it rejoins the period-K branch.
    halves: Option<&'a dyn Halving>,
}

impl Marching<'_> {
    /// A corrected point with its tangent (oriented along `previous`) and, on a period-2K
    /// branch, its halves' difference.
    fn point<Fam: OrbitFamily>(
        &self,
        family: &Fam,
        solved: Solved,
        previous: &[f64],
        stats: &mut SolverStats,
    ) -> Result<Point, AnalysisError> {
        let halves = match self.halves {
            Some(h) => h.halves(&solved, stats)?,
            None => Vec::new(),
        };
        let mut pt = finished(solved, previous, self.scales, family.contact_events())?;
        pt.halves = halves;
        Ok(pt)
    }

    /// max_i |d_i|/ε_i of a point's halves' difference d (module [`switch`]).
    fn halves_apart(&self, pt: &Point) -> f64 {
        let tol = self.solver.controlled_tolerances();
        pt.halves
            .iter()
            .zip(&pt.solved.y)
            .map(|(d, y)| d.abs() / (tol.atol + tol.rtol * y.abs()))
            .fold(0.0, f64::max)
    }

    /// |d|² in scaled coordinates.
    fn scaled_square(&self, d: &[f64]) -> f64 {
        d.iter()
            .zip(&self.scales.state)
            .map(|(d, s)| (d / s).powi(2))
            .sum()
    }

    /// Marches from `first` (whose row `rows` ends with) with steps from `ds` (scaled
    /// arclength) until the branch reaches `to`, leaves the range at `from`, rejoins the
    /// period-K branch (a period-2K branch), or fails; every row, those given included, is
    /// given to `watch` once, in order, as it joins (it ends the branch when it answers
    /// false).
    fn run<Fam: OrbitFamily>(
        &self,
        family: &Fam,
        first: Point,
        mut rows: Vec<BranchPoint>,
        ds: f64,
        stats: &mut SolverStats,
        watch: Watch<'_>,
    ) -> (Vec<BranchPoint>, Vec<(SpecialKind, f64, String)>, BranchEnd) {
        let (options, scales, solver) = (self.options, self.scales, self.solver);
        // Rows given to `watch` so far: every row once, in order, the located special points
        // and the branch's ends included.
        let mut reported = 0;
        let mut report = |rows: &[BranchPoint]| -> bool {
            let mut go_on = true;
            while go_on && reported < rows.len() {
                go_on = watch(&rows[reported]);
                reported += 1;
            }
            go_on
        };
        if !report(&rows) {
            return (rows, Vec::new(), BranchEnd::Stopped);
        }
        let n = first.solved.y.len();
        let dir = (options.to - options.from).signum();
        let e_p = parameter_direction(n);
        let mut unlocated = Vec::new();
        let mut last = first;
        let ds_max = options.max_step / scales.parameter;
        let ds_min = options.min_step / scales.parameter;
        let mut ds = ds.clamp(ds_min, ds_max);
        // The parameter and halves' size of the point before `last` on a period-2K branch.
        let mut before_last: Option<(f64, f64)> = None;
        let end = loop {
            if rows.len() >= options.max_points {
                break BranchEnd::MaxPoints;
            }
            let v = last.tangent.clone();
            let w_last = last.w(scales);
            let p_last = last.solved.p;
            let p_at = |s: f64| (w_last[n] + s * v[n]) * scales.parameter;
            // The step that lands on `to`, when this one would pass it.
            let to_reach = if v[n] * dir > 0.0 && dir * (p_at(ds) - options.to) >= 0.0 {
                Some((options.to - p_last) / scales.parameter / v[n])
            } else {
                None
            };
            if to_reach.is_none() && dir * (p_at(ds) - options.from) < 0.0 {
                break BranchEnd::TurnedBack;
            }
            let (s_step, c) = match to_reach {
                Some(s) => (s, e_p.clone()),
                None => (ds, v.clone()),
            };
            let at = |s: f64, stats: &mut SolverStats| {
                let y: Vec<f64> = (0..n)
                    .map(|i| (w_last[i] + s * v[i]) * scales.state[i])
                    .collect();
                let p = if to_reach.is_some() && s == s_step {
                    options.to
                } else {
                    p_at(s)
                };
                correct(
                    family,
                    &y,
                    p,
                    &c,
                    scales,
                    &newton(options, solver, options.max_iterations),
                    solver,
                    stats,
                )
                .and_then(|solved| self.point(family, solved, &v, stats))
            };
            let next = match at(s_step, stats) {
                Ok(next) => next,
                Err(e) => {
                    ds *= 0.5;
                    if ds < ds_min {
                        break BranchEnd::Failed {
                            message: format!("no orbit beyond it with the smallest step: {e}"),
                        };
                    }
                    continue;
                }
            };
            // A period-2K branch that nears the period-K branch ends at the junction
            // ([`switch`], "Where it ends").
            if let Some(halving) = self.halves {
                let size = |d: &[f64]| self.scaled_square(d);
                let (a_last, a_next) = (size(&last.halves), size(&next.halves));
                let flipped = next
                    .halves
                    .iter()
                    .zip(&last.halves)
                    .map(|(a, b)| a * b)
                    .sum::<f64>()
                    < 0.0;
                let collapsed = self.halves_apart(&next) <= options.closing_limit;
                let near = switch::near_junction(&next.multipliers) && a_next < a_last;
                // A step that jumped past the junction is retried shorter: the square-root
                // law below is best from points near it.
                if (flipped || collapsed) && !near && ds > 4.0 * ds_min {
                    ds *= 0.25;
                    continue;
                }
                if flipped || collapsed || near {
                    // The square-root law through the last two points on the branch.
                    let (pair, at) = if near && !flipped && !collapsed {
                        rows.push(next.row(None));
                        (Some((last.solved.p, a_last)), &next)
                    } else {
                        (before_last, &last)
                    };
                    let a_at = size(&at.halves);
                    let p_junction = match pair {
                        Some((p1, a1)) if a1 > a_at && p1 != at.solved.p => {
                            at.solved.p - a_at * (at.solved.p - p1) / (a_at - a1)
                        }
                        _ => at.solved.p,
                    };
                    let mid: Vec<f64> = at
                        .solved
                        .y
                        .iter()
                        .zip(&at.halves)
                        .map(|(y, d)| y - 0.5 * d)
                        .collect();
                    let reach = (p_junction - at.solved.p).abs();
                    match halving.junction(p_junction, &mid, reach, stats) {
                        Ok(row) => {
                            let parameter = row.parameter;
                            rows.push(row);
                            break BranchEnd::Rejoined { parameter };
                        }
                        Err(e) => {
                            break BranchEnd::Failed {
                                message: format!(
                                    "the branch neared the period-K orbits, but none was found at the junction p = {p_junction} predicted by the square-root law: {e}"
                                ),
                            };
                        }
                    }
                }
                before_last = Some((last.solved.p, a_last));
            }
            // Special points within the step, each located along it.
            let mut found: Vec<(f64, Point, SpecialKind)> = Vec::new();
            let (lo, hi) = (last.observed(), next.observed());
            for kind in changes(&lo, &hi, options.multiplier_tolerance) {
                let tol = options.multiplier_tolerance;
                let psi_of = |o: &Observed<'_>| signed_distance(kind, &lo, &hi, o, tol);
                let mut best: Option<(f64, f64, Point)> = None;
                let mut failure = None;
                let seen = regula_falsi(
                    psi_of(&lo),
                    psi_of(&hi),
                    s_step,
                    options.locate_tolerance / scales.parameter,
                    options.locate_evaluations,
                    |s| match at(s, stats) {
                        Ok(pt) => {
                            let psi = psi_of(&pt.observed());
                            if best.as_ref().is_none_or(|b| psi.abs() < b.1.abs()) {
                                best = Some((s, psi, pt));
                            }
                            Some(psi)
                        }
                        Err(e) => {
                            failure = Some(e.to_string());
                            None
                        }
                    },
                );
                match best {
                    // A count that changes with no multiplier near the crossing along the step is a
                    // jump (noise in the multipliers), not a crossing.
                    Some((_, psi, _)) if kind != SpecialKind::Grazing && psi.abs() > LOCATED => {
                        unlocated.push((
                            kind,
                            next.solved.p,
                            format!(
                                "no point along the step has a multiplier within {LOCATED} of the crossing (closest {:.3}): a jump of the multipliers, not a crossing; tighten rtol",
                                psi.abs()
                            ),
                        ))
                    }
                    Some((s, _, pt)) => found.push((s, pt, kind)),
                    None => unlocated.push((
                        kind,
                        next.solved.p,
                        failure.unwrap_or_else(|| format!("{} trial points", seen.len())),
                    )),
                }
            }
            found.sort_by(|a, b| a.0.total_cmp(&b.0));
            for (_, pt, kind) in &found {
                rows.push(pt.row(Some(*kind)));
            }
            let iterations = next.solved.iterations;
            rows.push(next.row(None));
            last = next;
            let go_on = report(&rows);
            if to_reach.is_some() {
                break BranchEnd::Reached;
            }
            if !go_on {
                break BranchEnd::Stopped;
            }
            // Newton converges linearly here (the monodromy in contact is ~1e-3 accurate), so an
            // iteration more on a longer step is cheaper than more steps: grow unless the
            // correction came near its limit.
            if iterations <= GROW_BELOW {
                ds = (ds * 1.5).min(ds_max);
            } else if iterations >= options.max_iterations.saturating_sub(2) {
                ds *= 0.7;
            }
            ds = ds.max(ds_min);
        };
        // The rows of the last step (a junction, a failure) are shown too; the branch has
        // ended, so the answer does not matter.
        report(&rows);
        (rows, unlocated, end)
    }
}

/// [`finish`], its singular augmented Jacobian as an error.
fn finished(
    solved: Solved,
    previous: &[f64],
    scales: &Scales,
    contacts: usize,
) -> Result<Point, AnalysisError> {
    finish(solved, previous, scales, contacts)
        .ok_or_else(|| AnalysisError::invalid("continuation", "singular augmented Jacobian"))
}

/// Multipliers, impacts and the unit tangent of a corrected point (the tangent's sign: along
/// `previous`). None where the augmented Jacobian is singular.
fn finish(solved: Solved, previous: &[f64], scales: &Scales, contacts: usize) -> Option<Point> {
    let n = solved.y.len();
    let shot = &solved.shot;
    let active = &solved.active;
    let m = active.len();
    let jac = augmented_jacobian(&shot.monodromy, n, active, &solved.g_p, previous, scales);
    let mut rhs = nalgebra::DVector::zeros(m + 1);
    rhs[m] = 1.0;
    let t = jac.lu().solve(&rhs)?;
    let norm = t.norm();
    if !(norm.is_finite() && norm > 0.0) {
        return None;
    }
    let mut tangent = vec![0.0; n + 1];
    for (a, &i) in active.iter().enumerate() {
        tangent[i] = t[a] / norm;
    }
    tangent[n] = t[m] / norm;
    // Active bookkeeping states cleared by an event: one structural zero multiplier each
    // (only bookkeeping states are ever cleared).
    let cleared_active = active.iter().filter(|&&i| shot.cleared[i]).count();
    // A constrained state's multipliers: in its consistent directions W (the others are 0 by
    // construction of the shot's monodromy, and trivial).
    let (monodromy_in_coordinates, coordinates) = in_coordinates(
        restricted(&shot.monodromy, n, active),
        solved.basis.as_ref(),
    );
    let (multipliers, structural) =
        split_trivial(multipliers(&monodromy_in_coordinates), cleared_active);
    let impacts = shot
        .events
        .iter()
        .filter(|(_, k, crossing)| *k < contacts && *crossing == Crossing::Rising)
        .count();
    Some(Point {
        trivial: n - coordinates + structural,
        multipliers,
        impacts,
        tangent,
        solved,
        halves: Vec::new(),
    })
}

fn validate(guess: &[f64], options: &ContinuationOptions) -> Result<(), AnalysisError> {
    crate::analysis::error::check_finite("guess", guess)?;
    for (what, v) in [("from", options.from), ("to", options.to)] {
        if !v.is_finite() {
            return Err(AnalysisError::invalid(
                what,
                format!("expected a finite parameter value, got {v}"),
            ));
        }
    }
    if options.from == options.to {
        return Err(AnalysisError::invalid(
            "to",
            format!(
                "expected a value other than from = {} (a branch needs a range)",
                options.from
            ),
        ));
    }
    for (what, v) in [
        ("step", options.max_step),
        ("min_step", options.min_step),
        ("step_tolerance", options.step_tolerance),
        ("closing_limit", options.closing_limit),
        ("fd_step", options.fd_step.unwrap_or(1.0)),
        ("locate_tolerance", options.locate_tolerance),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(AnalysisError::invalid(
                what,
                format!("expected a finite value > 0, got {v}"),
            ));
        }
    }
    if options.min_step > options.max_step {
        return Err(AnalysisError::invalid(
            "min_step",
            format!(
                "expected at most the step {}, got {}",
                options.max_step, options.min_step
            ),
        ));
    }
    Ok(())
}
