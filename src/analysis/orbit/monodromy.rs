//! One shot: the state after one period and the monodromy matrix M = ∂φ(t0 + T)/∂y0, from the
//! variational equations with saltation matrices ([`Variational`]).

use super::coordinates::step_end_corrections;
use super::variational::Variational;
use crate::analysis::AnalysisError;
use crate::formulation::{Crossing, Formulation};
use crate::solve::maximise::maximise;
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
    /// Smallest −g_k over the period for the watched events k, at the step ends and at the
    /// maxima of g_k located inside the steps ([`shoot_watching`];
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
        if watch == 0 {
            while stepper.step().map_err(solve)? != Stop::EndReached {}
            stepper.interpolate(t1, &mut end).map_err(solve)?;
        } else {
            let mut gaps = GapWatch::new(f, watch);
            gaps.at_step_end(t0, &start);
            while stepper.step().map_err(solve)? != Stop::EndReached {
                gaps.at_step_end(stepper.t(), stepper.y());
                gaps.peak_inside(&mut stepper).map_err(solve)?;
            }
            stepper.interpolate(t1, &mut end).map_err(solve)?;
            gaps.at_step_end(t1, &end);
            gaps.peak_inside(&mut stepper).map_err(solve)?;
            min_gap = gaps.min_gap;
        }
        stepper.stats().clone()
    };
    if let Some(e) = wrapped.failure() {
        return Err(AnalysisError::invalid("orbit", e.to_string()));
    }
    let corrected = step_end_corrections(wrapped.inner()).saturating_sub(step_end_corrections(f));
    if corrected > 0 {
        return Err(AnalysisError::invalid(
            "orbit",
            format!(
                "the formulation corrected its state at {corrected} step end{} of the period (projections near a singular position of the linkage); the variational equations do not follow such corrections, so the monodromy matrix would be wrong",
                if corrected == 1 { "" } else { "s" }
            ),
        ));
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

/// Width, relative to the step, to which a peak of g is located: about 60 golden-section
/// iterations.
const PEAK_WIDTH: f64 = 3e-13;

/// The smallest gap −g_k of the watched event functions over a shot: at the step ends, and at
/// the located maxima of g_k inside the steps (a journal that nears the bearing wall and turns
/// back inside a step; docs/periodic_orbits.md, "Continuation").
///
/// A maximum lies inside a step where ġ_k goes from positive at its start to negative at its
/// end; ġ_k is a forward difference of g_k along f at each step end (one evaluation of the
/// formulation's own right-hand side, not the variational equations'). The maximum is then
/// found by golden-section search ([`maximise`]) on the step's dense output.
struct GapWatch<'a, F> {
    f: &'a F,
    watch: usize,
    n: usize,
    /// Every event function at a point, and the watched ones at the step end.
    g: Vec<f64>,
    g_end: Vec<f64>,
    dy: Vec<f64>,
    probe: Vec<f64>,
    /// Times of the last step end and of the one before.
    t_last: Option<f64>,
    t_before: Option<f64>,
    /// Whether ġ_k > 0 there, for the watched k.
    rising_last: Vec<bool>,
    rising_before: Vec<bool>,
    min_gap: Option<f64>,
}

impl<'a, F: Formulation> GapWatch<'a, F> {
    fn new(f: &'a F, watch: usize) -> Self {
        let n = f.n_states();
        GapWatch {
            f,
            watch,
            n,
            g: vec![0.0; f.n_events()],
            g_end: vec![0.0; watch],
            dy: vec![0.0; n],
            probe: vec![0.0; n],
            t_last: None,
            t_before: None,
            rising_last: vec![false; watch],
            rising_before: vec![false; watch],
            min_gap: None,
        }
    }

    fn record(&mut self, gap: f64) {
        self.min_gap = Some(self.min_gap.map_or(gap, |m: f64| m.min(gap)));
    }

    /// g and the sign of ġ at a step end (y may be the augmented state: its first n).
    fn at_step_end(&mut self, t: f64, y: &[f64]) {
        let y = &y[..self.n];
        self.f.events(t, y, &mut self.g);
        self.g_end.copy_from_slice(&self.g[..self.watch]);
        let deepest = self.g_end.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        self.record(-deepest);
        std::mem::swap(&mut self.rising_before, &mut self.rising_last);
        self.t_before = self.t_last.replace(t);
        // ġ by a forward difference along f; where f cannot be evaluated, no peak is sought.
        if self.f.rhs(t, y, &mut self.dy).is_ok() {
            let scale = self.dy.iter().map(|d| d.abs()).fold(0.0, f64::max).max(1.0);
            let tau = 1e-7 / scale;
            for k in 0..self.n {
                self.probe[k] = y[k] + tau * self.dy[k];
            }
            self.f.events(t + tau, &self.probe, &mut self.g);
            for (k, up) in self.rising_last.iter_mut().enumerate() {
                *up = self.g[k] > self.g_end[k];
            }
        } else {
            self.rising_last.fill(false);
        }
    }

    /// The maxima of g_k inside the last step [before, last], located on the dense output.
    fn peak_inside<S: Formulation>(
        &mut self,
        stepper: &mut Stepper<'_, S>,
    ) -> Result<(), SolveError> {
        let (Some(a), Some(b)) = (self.t_before, self.t_last) else {
            return Ok(());
        };
        if b <= a {
            return Ok(());
        }
        let mut state = vec![0.0; stepper.n_states()];
        for k in 0..self.watch {
            // Rising at the step's start and no longer at its end: a peak inside.
            let peaks_inside = self.rising_before[k] && !self.rising_last[k];
            if !peaks_inside {
                continue;
            }
            let (f, n, g) = (self.f, self.n, &mut self.g);
            let (_, peak) = maximise(
                |t| {
                    stepper.interpolate(t, &mut state)?;
                    f.events(t, &state[..n], g);
                    Ok(g[k])
                },
                a,
                b,
                PEAK_WIDTH * (b - a),
            )?;
            self.record(-peak);
        }
        Ok(())
    }
}
