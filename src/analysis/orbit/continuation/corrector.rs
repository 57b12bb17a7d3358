//! The corrector: Newton's method on the periodic-orbit equations augmented with one linear
//! condition, P_p(x) − x = 0 and c·(w − w_pred) = 0 in scaled coordinates w (module
//! documentation of [`super`]).

use nalgebra::{DMatrix, DVector};

use super::{OrbitFamily, Scales};
use crate::analysis::AnalysisError;
use crate::analysis::orbit::coordinates::{
    angular_states, in_consistent_directions, less_whole_turns, make_consistent,
};
use crate::analysis::orbit::floquet::{active_states, restricted};
use crate::analysis::orbit::monodromy::{Shot, shoot_watching};
use crate::formulation::Formulation;
use crate::solve::{SolveError, SolverOptions, SolverStats, Stepper, Stop};

pub(super) const WHAT: &str = "continuation";

/// Newton settings of the corrector.
#[derive(Debug, Clone, Copy)]
pub(super) struct Newton {
    pub max_iterations: usize,
    pub max_halvings: usize,
    pub step_tolerance: f64,
    pub closing_limit: f64,
    /// Relative step of the parameter's finite difference.
    pub fd_step: f64,
}

/// A point on the branch: the orbit at one parameter value.
#[derive(Debug, Clone)]
pub(super) struct Solved {
    pub p: f64,
    pub y: Vec<f64>,
    pub t0: f64,
    pub period: f64,
    pub shot: Shot,
    pub active: Vec<usize>,
    /// Closing error max_i |P(x)_i − x_i|/ε_i over the unknowns.
    pub rho: f64,
    pub history: Vec<f64>,
    pub iterations: usize,
    /// ∂(P_p(x) − x)/∂p by a forward difference at the last iterate before the point (full
    /// state length; raw units per unit p).
    pub g_p: Vec<f64>,
    /// The consistent directions over `active` of a constrained state (the DAE;
    /// [`in_consistent_directions`], which has put the shot's monodromy in them), or `None`.
    pub basis: Option<DMatrix<f64>>,
}

/// Integrates `f` without variational equations from (t0, y0) to t1.
pub(super) fn plain<F: Formulation + Clone>(
    f: &F,
    t0: f64,
    y0: &[f64],
    t1: f64,
    solver: &SolverOptions,
    stats: &mut SolverStats,
) -> Result<Vec<f64>, AnalysisError> {
    let solve = |source: SolveError| AnalysisError::Solve {
        analysis: WHAT,
        source,
    };
    let mut g = f.clone();
    let mut y = y0.to_vec();
    let mut stepper = Stepper::new(&mut g, t0, y0, t1, solver).map_err(solve)?;
    while stepper.step().map_err(solve)? != Stop::EndReached {}
    stepper.interpolate(t1, &mut y).map_err(solve)?;
    stats.add_run(stepper.stats());
    Ok(y)
}

/// One evaluation: the shot of the orbit equations at (y, p).
struct Eval {
    t0: f64,
    period: f64,
    shot: Shot,
    active: Vec<usize>,
    rho: f64,
    basis: Option<DMatrix<f64>>,
    /// Which states are angles ([`angular_states`]), compared modulo whole turns.
    angular: Vec<bool>,
}

/// Solves the augmented system from the predicted point (`y_pred`, `p_pred`) with the condition
/// `c`·(w − w_pred) = 0 (`c` in scaled coordinates: states then the parameter; entries of
/// inactive states ignored). Returns the point, or why Newton's method stopped.
#[allow(clippy::too_many_arguments)]
pub(super) fn correct<Fam: OrbitFamily>(
    family: &Fam,
    y_pred: &[f64],
    p_pred: f64,
    c: &[f64],
    scales: &Scales,
    newton: &Newton,
    solver: &SolverOptions,
    stats: &mut SolverStats,
) -> Result<Solved, AnalysisError> {
    let n = y_pred.len();
    let tol = solver.controlled_tolerances();
    let eps = |a: f64, b: f64| tol.atol + tol.rtol * a.abs().max(b.abs());
    let watch = family.contact_events();
    // The shot at (y, p), y first made consistent at p where the state is constrained.
    let evaluate =
        |y: &mut [f64], p: f64, stats: &mut SolverStats| -> Result<Eval, AnalysisError> {
            let at = family.at(p)?;
            make_consistent(&at.f, at.t0, y)?;
            let mut controlled = vec![true; n];
            at.f.error_controlled(&mut controlled);
            let mut shot = shoot_watching(
                &at.f,
                at.t0,
                y,
                at.t0 + at.period,
                at.period / std::f64::consts::TAU,
                solver,
                WHAT,
                watch,
            )?;
            stats.add_run(&shot.stats);
            let active = active_states(&shot.monodromy, &controlled);
            let basis = in_consistent_directions(&at.f, at.t0, y, &mut shot.monodromy, &active)?;
            let angular = angular_states(&at.f);
            let rho = active
                .iter()
                .map(|&i| {
                    less_whole_turns(angular[i], shot.y_end[i] - y[i]).abs()
                        / eps(y[i], shot.y_end[i])
                })
                .fold(0.0, f64::max);
            Ok(Eval {
                t0: at.t0,
                period: at.period,
                shot,
                active,
                rho,
                basis,
                angular,
            })
        };
    let fail = |reason: String, history: &[f64]| AnalysisError::NoConvergence {
        analysis: WHAT,
        reason,
        history: history.to_vec(),
    };

    let (mut y, mut p) = (y_pred.to_vec(), p_pred);
    let mut ev = evaluate(&mut y, p, stats)?;
    if !ev.rho.is_finite() {
        return Err(fail("the period map is not finite".into(), &[ev.rho]));
    }
    // ∂G/∂p by a forward difference at every iterate (one plain integration each). Kept from
    // the predicted point through the correction (a chord in that column), it stalled the
    // first point of a branch switched to at a period doubling, where the amplitude is fixed
    // and p is the unknown that moves: there ∂G/∂p's part along the near-null direction of
    // M − I is of the order of the amplitude and changes with p. On the four-bar's bubble a
    // switch then failed in 9 of 14 runs at tolerances around 1e-10, and in 1 now
    // (docs/periodic_orbits.md, "The parameter's column").
    // A constrained state (the DAE) is made consistent at p + h first, and the column is the
    // change of P(x) − x: the consistent states move with p where the parameter enters the
    // constraints (a driver's speed, a link's length).
    let column = |y: &[f64], p: f64, ev: &Eval, stats: &mut SolverStats| {
        let (y_end, angular) = (&ev.shot.y_end, &ev.angular);
        let h = newton.fd_step * p.abs().max(scales.parameter);
        let at_h = family.at(p + h)?;
        if at_h.f.constrained_state().is_none() {
            let shifted = plain(&at_h.f, at_h.t0, y, at_h.t0 + at_h.period, solver, stats)?;
            return Ok::<_, AnalysisError>(
                (0..n)
                    .map(|i| (shifted[i] - y_end[i]) / h)
                    .collect::<Vec<_>>(),
            );
        }
        let mut y_h = y.to_vec();
        make_consistent(&at_h.f, at_h.t0, &mut y_h)?;
        let shifted = plain(&at_h.f, at_h.t0, &y_h, at_h.t0 + at_h.period, solver, stats)?;
        Ok((0..n)
            .map(|i| {
                let moved = less_whole_turns(angular[i], shifted[i] - y_h[i]);
                let before = less_whole_turns(angular[i], y_end[i] - y[i]);
                (moved - before) / h
            })
            .collect::<Vec<_>>())
    };
    let mut g_p = column(&y, p, &ev, stats)?;
    let mut history = vec![ev.rho];
    let mut iterations = 0;
    let mut done = ev.rho <= 1.0;
    while !done {
        if iterations == newton.max_iterations {
            return Err(fail(
                format!("the corrector did not converge in {iterations} iterations"),
                &history,
            ));
        }
        iterations += 1;
        if iterations > 1 {
            g_p = column(&y, p, &ev, stats)?;
        }
        let delta = newton_step(&ev, &y, p, y_pred, p_pred, c, &g_p, scales)
            .ok_or_else(|| fail("the augmented Jacobian is singular".into(), &history))?;
        // The step in units of ε, the parameter's included (ε_p = rtol·max(|p|, σ_p)): with
        // the amplitude fixed (a switched branch's first point) the state hardly moves while p
        // does.
        let step = ev
            .active
            .iter()
            .zip(delta.iter())
            .map(|(&i, d)| d.abs() / eps(y[i], y[i]))
            .fold(0.0, f64::max)
            .max(delta[ev.active.len()].abs() / (tol.rtol * p.abs().max(scales.parameter)));
        let near = ev.rho <= newton.closing_limit;
        let mut lambda = 1.0;
        let mut halvings = 0;
        loop {
            let mut trial = y.clone();
            for (&i, d) in ev.active.iter().zip(delta.iter()) {
                trial[i] += lambda * d;
            }
            for i in (0..n).filter(|i| !ev.active.contains(i)) {
                trial[i] = ev.shot.y_end[i];
            }
            let trial_p = p + lambda * delta[ev.active.len()];
            match evaluate(&mut trial, trial_p, stats) {
                Ok(next) if next.rho.is_finite() => {
                    if near {
                        history.push(next.rho);
                        done = true;
                        if next.rho < ev.rho {
                            (y, p, ev) = (trial, trial_p, next);
                        }
                        break;
                    }
                    if next.rho < ev.rho {
                        history.push(next.rho);
                        done = next.rho <= 1.0
                            || lambda * step <= newton.step_tolerance
                            || (next.rho <= newton.closing_limit && next.rho > ev.rho / 4.0);
                        (y, p, ev) = (trial, trial_p, next);
                        break;
                    }
                    if halvings == newton.max_halvings {
                        history.push(next.rho);
                        return Err(fail(
                            format!(
                                "a Newton step halved {halvings} times still raises the residual"
                            ),
                            &history,
                        ));
                    }
                }
                Ok(next) if halvings == newton.max_halvings => {
                    history.push(next.rho);
                    return Err(fail("the period map is not finite".into(), &history));
                }
                Err(e) if halvings == newton.max_halvings => return Err(e),
                // A step too long for the integration or the model: shorter.
                _ => {}
            }
            lambda *= 0.5;
            halvings += 1;
        }
    }
    if ev.rho > newton.closing_limit {
        return Err(fail(
            format!(
                "the corrector's steps became small but the orbit closes only to {:.3e} integration tolerances (above {:e})",
                ev.rho, newton.closing_limit
            ),
            &history,
        ));
    }
    Ok(Solved {
        p,
        t0: ev.t0,
        period: ev.period,
        active: ev.active,
        rho: ev.rho,
        shot: ev.shot,
        y,
        history,
        iterations,
        g_p,
        basis: ev.basis,
    })
}

/// The Newton step (Δx over the unknowns, then Δp) of the augmented system at (y, p).
#[allow(clippy::too_many_arguments)]
fn newton_step(
    ev: &Eval,
    y: &[f64],
    p: f64,
    y_pred: &[f64],
    p_pred: f64,
    c: &[f64],
    g_p: &[f64],
    scales: &Scales,
) -> Option<Vec<f64>> {
    let n = y.len();
    let active = &ev.active;
    let m = active.len();
    let jac = augmented_jacobian(&ev.shot.monodromy, n, active, g_p, c, scales);
    let mut rhs = DVector::zeros(m + 1);
    for (a, &i) in active.iter().enumerate() {
        rhs[a] = -less_whole_turns(ev.angular[i], ev.shot.y_end[i] - y[i]) / scales.state[i];
    }
    let offset: f64 = active
        .iter()
        .map(|&i| c[i] * (y[i] - y_pred[i]) / scales.state[i])
        .sum::<f64>()
        + c[n] * (p - p_pred) / scales.parameter;
    rhs[m] = -offset;
    let dw = jac.lu().solve(&rhs)?;
    let mut delta: Vec<f64> = active
        .iter()
        .enumerate()
        .map(|(a, &i)| dw[a] * scales.state[i])
        .collect();
    delta.push(dw[m] * scales.parameter);
    delta.iter().all(|d| d.is_finite()).then_some(delta)
}

/// [[D⁻¹(M_AA − I)D, D⁻¹ G_p σ_p], [c_A, c_p]] in scaled coordinates (D = diag σ_A).
pub(super) fn augmented_jacobian(
    monodromy: &[f64],
    n: usize,
    active: &[usize],
    g_p: &[f64],
    c: &[f64],
    scales: &Scales,
) -> DMatrix<f64> {
    let m = active.len();
    let r = restricted(monodromy, n, active);
    DMatrix::from_fn(m + 1, m + 1, |a, b| {
        if a == m {
            if b == m { c[n] } else { c[active[b]] }
        } else {
            let sa = scales.state[active[a]];
            if b == m {
                g_p[active[a]] * scales.parameter / sa
            } else {
                let identity = if a == b { 1.0 } else { 0.0 };
                (r[(a, b)] - identity) * scales.state[active[b]] / sa
            }
        }
    })
}
