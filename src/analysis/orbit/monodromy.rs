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
                let (t, y) = (stepper.t(), stepper.y().to_vec());
                gaps.at_step_end(t, &y);
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

/// Golden-section iterations for a located peak of g: 0.618⁶⁰ ≈ 3e-13 of the step.
const PEAK_ITERATIONS: usize = 60;

/// The smallest gap −g_k of the watched event functions over a shot: at the step ends, and at
/// the located maxima of g_k inside the steps (a journal that nears the bearing wall and turns
/// back inside a step; docs/periodic_orbits.md, "Continuation").
///
/// A maximum lies inside a step where ġ_k goes from positive at its start to negative at its
/// end; ġ_k is a forward difference of g_k along f at each step end (one evaluation of the
/// formulation's own right-hand side, not the variational equations'). The maximum is then
/// found by golden-section search on the step's dense output.
struct GapWatch<'a, F> {
    f: &'a F,
    watch: usize,
    n: usize,
    g: Vec<f64>,
    dy: Vec<f64>,
    probe: Vec<f64>,
    /// At the last step end: t, g_k and the sign of ġ_k for the watched k.
    last: Option<(f64, Vec<f64>, Vec<bool>)>,
    /// At the one before.
    before: Option<(f64, Vec<f64>, Vec<bool>)>,
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
            dy: vec![0.0; n],
            probe: vec![0.0; n],
            last: None,
            before: None,
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
        let g: Vec<f64> = self.g[..self.watch].to_vec();
        for gk in &g {
            self.record(-gk);
        }
        // ġ by a forward difference along f; where f cannot be evaluated, no peak is sought.
        let rising = if self.f.rhs(t, y, &mut self.dy).is_ok() {
            let scale = self.dy.iter().map(|d| d.abs()).fold(0.0, f64::max).max(1.0);
            let tau = 1e-7 / scale;
            for k in 0..self.n {
                self.probe[k] = y[k] + tau * self.dy[k];
            }
            self.f.events(t + tau, &self.probe, &mut self.g);
            g.iter().zip(&self.g).map(|(a, b)| b > a).collect()
        } else {
            vec![false; self.watch]
        };
        self.before = self.last.take();
        self.last = Some((t, g, rising));
    }

    /// The maxima of g_k inside the last step [before, last], located on the dense output.
    fn peak_inside<S: Formulation>(
        &mut self,
        stepper: &mut Stepper<'_, S>,
    ) -> Result<(), SolveError> {
        let (Some((a, _, up_a)), Some((b, _, up_b))) = (&self.before, &self.last) else {
            return Ok(());
        };
        let (a, b) = (*a, *b);
        let peaks: Vec<usize> = (0..self.watch).filter(|&k| up_a[k] && !up_b[k]).collect();
        if peaks.is_empty() || b <= a {
            return Ok(());
        }
        let mut state = vec![0.0; stepper.n_states()];
        for k in peaks {
            let mut g_at = |t: f64, g: &mut Vec<f64>| -> Result<f64, SolveError> {
                stepper.interpolate(t, &mut state)?;
                self.f.events(t, &state[..self.n], g);
                Ok(g[k])
            };
            let r = 0.5 * (5f64.sqrt() - 1.0);
            let (mut lo, mut hi) = (a, b);
            let mut x1 = hi - r * (hi - lo);
            let mut x2 = lo + r * (hi - lo);
            let mut g = std::mem::take(&mut self.g);
            let (mut g1, mut g2) = (g_at(x1, &mut g)?, g_at(x2, &mut g)?);
            for _ in 0..PEAK_ITERATIONS {
                if g1 > g2 {
                    hi = x2;
                    (x2, g2) = (x1, g1);
                    x1 = hi - r * (hi - lo);
                    g1 = g_at(x1, &mut g)?;
                } else {
                    lo = x1;
                    (x1, g1) = (x2, g2);
                    x2 = lo + r * (hi - lo);
                    g2 = g_at(x2, &mut g)?;
                }
            }
            self.g = g;
            self.record(-g1.max(g2));
        }
        Ok(())
    }
}
