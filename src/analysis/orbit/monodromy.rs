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
    let n = f.n_states();
    let mut wrapped = Variational::new(f.clone(), time_scale);
    let start = wrapped.augmented(y0);
    let mut end = vec![0.0; start.len()];
    let solve = |source| AnalysisError::Solve {
        analysis: what,
        source,
    };
    let stats = {
        let mut stepper = Stepper::new(&mut wrapped, t0, &start, t1, opts).map_err(solve)?;
        run_to_end(&mut stepper, t1, &mut end).map_err(solve)?;
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
    })
}

fn run_to_end<F: Formulation>(
    stepper: &mut Stepper<'_, F>,
    t_end: f64,
    out: &mut [f64],
) -> Result<(), SolveError> {
    while stepper.step()? != Stop::EndReached {}
    stepper.interpolate(t_end, out)
}
