//! Newton's method on P(x) − x = 0, P the flow over one period, with the monodromy matrix as
//! its Jacobian (module documentation of [`super`]).

use serde::Serialize;

use super::coordinates::{
    angular_states, in_coordinates, less_whole_turns, make_consistent, tangent_basis,
};
use super::floquet::{active_states, multipliers, restricted, split_trivial};
use super::monodromy::{Shot, shoot_watching};
use crate::analysis::AnalysisError;
use crate::analysis::error::check_finite;
use crate::formulation::{Crossing, Formulation};
use crate::solve::{SolverOptions, SolverStats};

const WHAT: &str = "periodic orbit";

/// Options of [`periodic_orbit`], with written defaults ([`OrbitOptions::new`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OrbitOptions {
    /// Period T (s), > 0: K driver turns for a driven linkage.
    pub period: f64,
    /// Time scale of the motion (s), > 0: the step of the saltation matrices' differences in
    /// time is 1e-5 of it. Default T/(2π) (1/|ω| for one driver turn).
    pub time_scale: f64,
    /// Newton iterations allowed (default 20).
    pub max_iterations: usize,
    /// Newton has converged when its step is at most this many integration tolerances
    /// ε_i = atol + rtol·|x_i| in every unknown (default 1), or when the residual itself is.
    pub step_tolerance: f64,
    /// Largest closing error |P(x) − x| (units of ε_i) of a converged orbit (default 1000,
    /// the tolerance within which `linkdyn poincare` calls two section points equal).
    pub closing_limit: f64,
    /// Halvings of a Newton step that does not lower the residual (default 8).
    pub max_halvings: usize,
    /// The first this many event functions of the formulation are contact penetrations whose
    /// smallest gap over the period is located ([`PeriodicOrbit::min_gap`]; default 0: none,
    /// at no cost).
    pub watched_gaps: usize,
}

impl OrbitOptions {
    /// The defaults for period `period` (s).
    pub fn new(period: f64) -> Self {
        OrbitOptions {
            period,
            time_scale: period / std::f64::consts::TAU,
            max_iterations: 20,
            step_tolerance: 1.0,
            closing_limit: 1e3,
            max_halvings: 8,
            watched_gaps: 0,
        }
    }
}

/// A periodic orbit found by shooting, with its stability.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PeriodicOrbit {
    /// Start time of the period (s): the section.
    pub t0: f64,
    /// The full state at the section (the formulation's layout).
    pub y0: Vec<f64>,
    /// Period T (s).
    pub period: f64,
    /// Newton iterations done.
    pub iterations: usize,
    /// max_i |P(x)_i − x_i|/ε_i over the unknowns of each iterate (the orbit returned is the
    /// iterate with the smallest, [`PeriodicOrbit::closing_error`]).
    pub residual_history: Vec<f64>,
    /// Closing error of the orbit returned: max_i |P(x)_i − x_i|/ε_i over the unknowns, from
    /// the integration of one period from it.
    pub closing_error: f64,
    /// The monodromy matrix M at the orbit, row-major n × n (all states).
    pub monodromy: Vec<f64>,
    /// The unknowns of the shooting (state indices; [`super::floquet`]).
    pub unknowns: Vec<usize>,
    /// Floquet multipliers: the eigenvalues of M restricted to the unknowns (for a
    /// constrained state, of Wᵀ M W over its consistent directions W,
    /// [`super::coordinates`]), (re, im), by decreasing modulus.
    pub multipliers: Vec<[f64; 2]>,
    /// Trivial multipliers removed: one per inactive bookkeeping state, one per active one
    /// cleared by an event of the period ([`super::floquet`]), and one per constraint
    /// direction of a constrained state.
    pub trivial_multipliers: usize,
    /// The events of one period (time, event index, crossing) along the orbit.
    pub events: Vec<(f64, usize, Crossing)>,
    /// Smallest gap −g_k over the period of the orbit returned for the watched event functions
    /// ([`OrbitOptions::watched_gaps`]), at the step ends and at the maxima of g_k located
    /// inside the steps ([`super::Shot::min_gap`]); `None` when none were watched.
    pub min_gap: Option<f64>,
    /// Cost of every integration, summed.
    pub stats: SolverStats,
}

impl PeriodicOrbit {
    /// True if every nontrivial multiplier lies strictly inside the unit circle.
    pub fn stable(&self) -> bool {
        self.multipliers.iter().all(|z| z[0].hypot(z[1]) < 1.0)
    }
}

/// The periodic orbit of `f` through the section at `t0` near the state `guess`, by Newton's
/// method on P(x) − x = 0 with the monodromy matrix (module documentation of [`super`]).
///
/// Errors: invalid options; [`AnalysisError::NoConvergence`] with the residual history when
/// Newton's method stops without an orbit (too many iterations, M − I singular, a step that
/// no halving makes lower the residual, or an orbit that does not close within
/// `closing_limit`); a failed integration.
pub fn periodic_orbit<F: Formulation + Clone>(
    f: &F,
    t0: f64,
    guess: &[f64],
    options: &OrbitOptions,
    solver: &SolverOptions,
) -> Result<PeriodicOrbit, AnalysisError> {
    validate(f, t0, guess, options)?;
    let n = f.n_states();
    let mut controlled = vec![true; n];
    f.error_controlled(&mut controlled);
    let tol = solver.controlled_tolerances();
    let eps = |a: f64, b: f64| tol.atol + tol.rtol * a.abs().max(b.abs());
    let t1 = t0 + options.period;
    let mut stats = SolverStats::default();
    let run = |y: &[f64], stats: &mut SolverStats| -> Result<Shot, AnalysisError> {
        let shot = shoot_watching(
            f,
            t0,
            y,
            t1,
            options.time_scale,
            solver,
            WHAT,
            options.watched_gaps,
        )?;
        stats.add_run(&shot.stats);
        Ok(shot)
    };
    let angular = angular_states(f);
    // P(x)_i − x_i, angles modulo whole turns.
    let closing =
        |y: &[f64], shot: &Shot, i: usize| less_whole_turns(angular[i], shot.y_end[i] - y[i]);
    // max_i |r_i|/ε_i over `active`.
    let residual = |y: &[f64], shot: &Shot, active: &[usize]| {
        active
            .iter()
            .map(|&i| closing(y, shot, i).abs() / eps(y[i], shot.y_end[i]))
            .fold(0.0, f64::max)
    };
    let fail = |reason: String, history: &[f64]| AnalysisError::NoConvergence {
        analysis: WHAT,
        reason,
        history: history.to_vec(),
    };

    let mut y = guess.to_vec();
    make_consistent(f, t0, &mut y)?;
    let mut shot = run(&y, &mut stats)?;
    let mut active = active_states(&shot.monodromy, &controlled);
    let mut rho = residual(&y, &shot, &active);
    let mut history = vec![rho];
    let mut iterations = 0;
    // Converged: within 1 ε, a step within `step_tolerance` ε, or at the noise floor of the
    // integration (within `closing_limit` ε and no longer improving fourfold per iteration,
    // where Newton's quadratic convergence would).
    let mut done = rho <= 1.0;
    while !done {
        if iterations == options.max_iterations {
            return Err(fail(
                format!(
                    "Newton's method did not converge in {iterations} iteration{}",
                    if iterations == 1 { "" } else { "s" }
                ),
                &history,
            ));
        }
        iterations += 1;
        // (M_AA − I) Δ = −(P(x) − x) on the unknowns; for a constrained state in the
        // consistent directions W only: Δ = W ξ, (Wᵀ M_AA W − I) ξ = −Wᵀ (P(x) − x).
        let m = active.len();
        let m_aa = restricted(&shot.monodromy, n, &active);
        let r = nalgebra::DVector::from_iterator(m, active.iter().map(|&i| -closing(&y, &shot, i)));
        let solved = match tangent_basis(f, t0, &y, &active)? {
            None => (m_aa - nalgebra::DMatrix::identity(m, m)).lu().solve(&r),
            Some(w) => {
                let k = w.ncols();
                let wmw = w.transpose() * m_aa * &w;
                let jac = wmw - nalgebra::DMatrix::identity(k, k);
                jac.lu().solve(&(w.transpose() * &r)).map(|xi| w * xi)
            }
        };
        let Some(delta) = solved else {
            return Err(fail(
                "M − I is singular (a Floquet multiplier is 1: a fold, or a family of orbits)"
                    .into(),
                &history,
            ));
        };
        let step = active
            .iter()
            .zip(delta.iter())
            .map(|(&i, d)| d.abs() / eps(y[i], y[i]))
            .fold(0.0, f64::max);
        // Far from the orbit, the step is halved until the residual drops; at the noise floor
        // (within `closing_limit`) it is taken whole, and the better of the two iterates kept.
        let near = rho <= options.closing_limit;
        let mut lambda = 1.0;
        let mut halvings = 0;
        loop {
            let mut trial = y.clone();
            for (&i, d) in active.iter().zip(delta.iter()) {
                trial[i] += lambda * d;
            }
            // Inactive bookkeeping states: nothing depends on them; take the period's end.
            for i in (0..n).filter(|i| !active.contains(i)) {
                trial[i] = shot.y_end[i];
            }
            let shot_of_trial =
                make_consistent(f, t0, &mut trial).and_then(|()| run(&trial, &mut stats));
            match shot_of_trial {
                Ok(next) => {
                    let next_active = active_states(&next.monodromy, &controlled);
                    let next_rho = residual(&trial, &next, &next_active);
                    if near {
                        history.push(next_rho);
                        done = true;
                        if next_rho < rho {
                            (y, shot, active, rho) = (trial, next, next_active, next_rho);
                        }
                        break;
                    }
                    if next_rho < rho {
                        history.push(next_rho);
                        done = next_rho <= 1.0
                            || lambda * step <= options.step_tolerance
                            || (next_rho <= options.closing_limit && next_rho > rho / 4.0);
                        (y, shot, active, rho) = (trial, next, next_active, next_rho);
                        break;
                    }
                    if halvings == options.max_halvings {
                        history.push(next_rho);
                        return Err(fail(
                            format!(
                                "a Newton step halved {halvings} times still raises the residual"
                            ),
                            &history,
                        ));
                    }
                }
                Err(e) if halvings == options.max_halvings => return Err(e),
                // A step too long for the integration (a penetration too deep): shorter.
                Err(_) => {}
            }
            lambda *= 0.5;
            halvings += 1;
        }
    }
    if rho.is_nan() || rho > options.closing_limit {
        return Err(fail(
            format!(
                "Newton's steps fell below {} integration tolerances but the orbit closes only to {rho:.3e} of them (above {:e}): the period map is not smooth enough at this tolerance; tighten rtol",
                options.step_tolerance, options.closing_limit
            ),
            &history,
        ));
    }
    let cleared_active = active
        .iter()
        .filter(|&&i| !controlled[i] && shot.cleared[i])
        .count();
    // The unknowns' coordinates: the active states, or the consistent directions among them.
    let (monodromy_in_coordinates, coordinates) = in_coordinates(
        restricted(&shot.monodromy, n, &active),
        tangent_basis(f, t0, &y, &active)?.as_ref(),
    );
    let (mu, structural) = split_trivial(multipliers(&monodromy_in_coordinates), cleared_active);
    Ok(PeriodicOrbit {
        t0,
        period: options.period,
        iterations,
        closing_error: rho,
        residual_history: history,
        trivial_multipliers: n - coordinates + structural,
        unknowns: active,
        multipliers: mu,
        monodromy: shot.monodromy,
        events: shot.events,
        min_gap: shot.min_gap,
        y0: y,
        stats,
    })
}

fn validate<F: Formulation>(
    f: &F,
    t0: f64,
    guess: &[f64],
    options: &OrbitOptions,
) -> Result<(), AnalysisError> {
    if guess.len() != f.n_states() {
        return Err(AnalysisError::invalid(
            "guess",
            format!(
                "the initial guess has {} components but the formulation has {} states",
                guess.len(),
                f.n_states()
            ),
        ));
    }
    check_finite("guess", guess)?;
    if !t0.is_finite() {
        return Err(AnalysisError::invalid(
            "t0",
            format!("expected a finite time, got {t0}"),
        ));
    }
    for (what, v) in [
        ("period", options.period),
        ("time_scale", options.time_scale),
        ("step_tolerance", options.step_tolerance),
        ("closing_limit", options.closing_limit),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(AnalysisError::invalid(
                what,
                format!("expected a finite value > 0, got {v}"),
            ));
        }
    }
    Ok(())
}
