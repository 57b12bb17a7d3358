//! One shot: the state after one period and the monodromy matrix M = ∂φ(t0 + T)/∂y0, from the
//! variational equations with saltation matrices ([`Variational`]).

use super::variational::Variational;
use crate::analysis::AnalysisError;
use crate::formulation::{Crossing, Formulation};
use crate::solve::{SolveError, SolverOptions, SolverStats, Stepper, Stop};

/// What one shot over [t0, t0 + T] gives.
#[derive(Debug, Clone)]
pub struct Shot {
    /// φ(t0 + T; t0, y0).
    pub y_end: Vec<f64>,
    /// M = ∂φ(t0 + T)/∂y0, row-major n × n.
    pub monodromy: Vec<f64>,
    /// Events met (time, index, crossing) whose saltation was applied.
    pub events: Vec<(f64, usize, Crossing)>,
    /// States cleared by an event of the period ([`Variational::cleared`]).
    pub cleared: Vec<bool>,
    /// Cost of the integration.
    pub stats: SolverStats,
    /// Smallest −g_k over the step ends of the period and the watched events k ([`shoot_watching`];
    /// for contact events, whose g is the penetration δ, the smallest gap, m). `None` when none
    /// were watched.
    pub min_gap: Option<f64>,
}

/// Integrates `f` with its variational equations from (t0, y0) to t1 (module documentation).
/// `time_scale` (s) is the step of the saltation matrices' differences in time.
///
/// Errors: a failed integration, or an event whose saltation matrix cannot be formed (a
/// grazing contact), as [`AnalysisError`]s naming `what`.
pub fn shoot<F: Formulation + Clone>(
    f: &F,
    t0: f64,
    y0: &[f64],
    t1: f64,
    time_scale: f64,
    opts: &SolverOptions,
    what: &'static str,
) -> Result<Shot, AnalysisError> {
    shoot_watching(f, t0, y0, t1, time_scale, opts, what, 0)
}

/// [`shoot`], also recording the smallest −g_k over the step ends for the first `watch` event
/// functions of `f` ([`Shot::min_gap`]; `watch` 0 costs nothing).
#[allow(clippy::too_many_arguments)]
pub fn shoot_watching<F: Formulation + Clone>(
    f: &F,
    t0: f64,
    y0: &[f64],
    t1: f64,
    time_scale: f64,
    opts: &SolverOptions,
    what: &'static str,
    watch: usize,
) -> Result<Shot, AnalysisError> {
    let n = f.n_states();
    let watch = watch.min(f.n_events());
    let mut wrapped = Variational::new(f.clone(), time_scale);
    let start = wrapped.augmented(y0);
    let mut end = vec![0.0; start.len()];
    let solve = |source| AnalysisError::Solve {
        analysis: what,
        source,
    };
    let mut min_gap = None;
    let stats = {
        let mut stepper = Stepper::new(&mut wrapped, t0, &start, t1, opts).map_err(solve)?;
        let mut g = vec![0.0; if watch > 0 { f.n_events() } else { 0 }];
        let mut watcher = |t: f64, y: &[f64]| {
            if watch > 0 {
                f.events(t, &y[..n], &mut g);
                for gk in g.iter().take(watch) {
                    min_gap = Some(min_gap.map_or(-gk, |m: f64| m.min(-gk)));
                }
            }
        };
        watcher(t0, &start);
        run_to_end(&mut stepper, t1, &mut end, &mut watcher).map_err(solve)?;
        stepper.stats().clone()
    };
    if let Some(e) = wrapped.failure() {
        return Err(AnalysisError::invalid("orbit", e.to_string()));
    }
    let monodromy = end.split_off(n);
    Ok(Shot {
        y_end: end,
        monodromy,
        events: wrapped.events().to_vec(),
        cleared: wrapped.cleared().to_vec(),
        stats,
        min_gap,
    })
}

fn run_to_end<F: Formulation>(
    stepper: &mut Stepper<'_, F>,
    t_end: f64,
    out: &mut [f64],
    at_step_end: &mut impl FnMut(f64, &[f64]),
) -> Result<(), SolveError> {
    while stepper.step()? != Stop::EndReached {
        at_step_end(stepper.t(), stepper.y());
    }
    stepper.interpolate(t_end, out)?;
    at_step_end(t_end, out);
    Ok(())
}
