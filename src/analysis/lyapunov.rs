//! Largest Lyapunov exponent of a formulation by two nearby trajectories with periodic
//! renormalisation (Benettin et al. \[1\]), the test for chaos used for clearance joints \[3\].
//!
//! # Method
//! 1. **Transient.** The formulation is integrated alone from (t0, y0) for `t_transient` s, so
//!    that the estimate starts on the attractor; the reference state there is y_a.
//! 2. **Norm and perturbation.** Distances are measured in the weighted Euclidean norm
//!    ‖Δ‖ = √(Σ_{i ∉ B} (Δ_i/s_i)²) over the components not marked as bookkeeping (the set B,
//!    from the `bookkeeping` mask: stored impact velocities and other discrete state kept in y,
//!    which must be neither perturbed nor measured), with scales s_i (default 1, in the units of
//!    component i). The perturbed state is y_b = y_a + d0·u, u_i = s_i/√m for the m components
//!    outside B and u_i = 0 in B, so that ‖y_b − y_a‖ = d0.
//! 3. **Both trajectories with events.** The pair (y_a, y_b) is integrated as one system of
//!    2n states, each half with its own copy of the formulation (its own event functions,
//!    events and discrete state): contacts are located and applied for both, and both share
//!    the step sizes, so that their local errors are correlated and largely cancel in y_b − y_a.
//! 4. **Renormalisation.** Every τ seconds (t_i = t_start + iτ) the distance d_i = ‖y_b − y_a‖
//!    is measured and y_b is pulled back to y_a + (d0/d_i)(y_b − y_a) on the components outside
//!    B (those in B keep the perturbed trajectory's own values: its own contact history). The
//!    running estimate after k intervals is
//!
//!    λ_k = (1/(kτ)) Σ_{i=1}^{k} ln(d_i/d0),
//!
//!    and `history` holds (t_k, λ_k). The answer is λ_K after the last interval.
//! 5. **Uncertainty** (batch means \[2\]): the local exponents ℓ_i = ln(d_i/d0)/τ of the last half
//!    of the intervals are split into `n_blocks` consecutive blocks of equal length; the
//!    uncertainty is the standard deviation of the block means divided by √(n_blocks), the
//!    standard error of the last half's mean if blocks are longer than the correlation time.
//!    `drift` = |λ_K − λ_{⌊K/2⌋}| says whether the running estimate still moves.
//!
//! d0 must be small enough that the separation stays in the linear regime over τ
//! (d0·e^{λτ} ≪ the attractor's size) and large enough that the integration error (≈ rtol·|y|)
//! is far below it; 1e-8 with rtol ≤ 1e-10 suits states of order 1. For a formulation with
//! contacts whose bookkeeping states jump at impacts, the separation of the measured components
//! stays continuous (compliant contact forces), so the renormalisation sees no jump.
//!
//! # References
//! 1. G. Benettin, L. Galgani, A. Giorgilli, J.-M. Strelcyn, "Lyapunov characteristic exponents
//!    for smooth dynamical systems and for Hamiltonian systems; a method for computing all of
//!    them. Part 1: Theory; Part 2: Numerical application", *Meccanica* 15, 9–20 and 21–30,
//!    1980.
//! 2. H. Flyvbjerg, H. G. Petersen, "Error estimates on averages of correlated data", *Journal
//!    of Chemical Physics* 91, 461–466, 1989.
//! 3. S. Rahmanian, M. R. Ghazavi, "Bifurcation in planar slider-crank mechanism with revolute
//!    clearance joint", *Mechanism and Machine Theory* 91, 86–101, 2015.
//! 4. J. C. Sprott, *Chaos and Time-Series Analysis*, Oxford University Press, 2003 (Lorenz
//!    system: λ₁ ≈ 0.9056 for σ = 10, ρ = 28, β = 8/3; Appendix A).

use serde::Serialize;

use super::error::{AnalysisError, check_finite};
use crate::formulation::sparse_jacobian::{SparseJacobian, SparsePattern};
use crate::formulation::{
    Crossing, EventResponse, Formulation, FormulationError, StepHooks, Tolerances,
};
use crate::solve::{SolveError, SolverOptions, SolverStats, Stepper};

const WHAT: &str = "Lyapunov exponent";

/// Options of [`largest_lyapunov`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LyapunovOptions {
    /// Initial (and renormalised) separation d0 in the weighted norm (default 1e-8).
    pub d0: f64,
    /// Renormalisation interval τ (s), > 0 (default 1).
    pub tau: f64,
    /// Number of renormalisation intervals K ≥ 2 (default 1000); the run lasts Kτ after the
    /// transient.
    pub n_intervals: usize,
    /// Time integrated before the estimate starts (s), ≥ 0 (default 0).
    pub t_transient: f64,
    /// `true` for bookkeeping components (neither perturbed nor measured); empty for none
    /// (default), else one entry per state.
    pub bookkeeping: Vec<bool>,
    /// Scale s_i of each component in the norm (> 0); empty for all 1 (default), else one entry
    /// per state.
    pub scales: Vec<f64>,
    /// Number of blocks for the uncertainty (≥ 2, default 10).
    pub n_blocks: usize,
}

impl Default for LyapunovOptions {
    fn default() -> Self {
        Self {
            d0: 1e-8,
            tau: 1.0,
            n_intervals: 1000,
            t_transient: 0.0,
            bookkeeping: Vec::new(),
            scales: Vec::new(),
            n_blocks: 10,
        }
    }
}

/// The estimate and how far to trust it (see the module documentation).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LyapunovEstimate {
    /// λ_K, the largest Lyapunov exponent (1/s).
    pub exponent: f64,
    /// Batch-means standard error of the last half's local exponents (1/s).
    pub uncertainty: f64,
    /// |λ_K − λ_{⌊K/2⌋}| (1/s).
    pub drift: f64,
    /// (t_k, λ_k) after each renormalisation (s, 1/s).
    pub history: Vec<(f64, f64)>,
    /// Cost of all integrations (transient and pair), summed.
    pub stats: SolverStats,
}

/// Largest Lyapunov exponent of `f` started from (t0, y0) (see the module documentation).
///
/// `f` is cloned for the two trajectories (its discrete state is copied with it); `f` itself is
/// not changed.
///
/// Errors: invalid options (mask or scales of the wrong length, no component left to measure,
/// d0 or τ not positive), a failed integration ([`AnalysisError::Solve`], whose source says
/// when), or trajectories that collapse onto each other (d_i = 0) or blow up.
pub fn largest_lyapunov<F: Formulation + Clone>(
    f: &F,
    t0: f64,
    y0: &[f64],
    lopts: &LyapunovOptions,
    opts: &SolverOptions,
) -> Result<LyapunovEstimate, AnalysisError> {
    let n = f.n_states();
    let norm = Norm::new(n, lopts)?;
    validate(lopts, y0, n)?;
    let solve = |source| AnalysisError::Solve {
        analysis: WHAT,
        source,
    };

    // 1. Transient, on a copy so that the caller's formulation is not changed.
    let mut reference = f.clone();
    let mut stats = SolverStats::default();
    let t_start = t0 + lopts.t_transient;
    let mut ya = vec![0.0; n];
    let mut h0 = None;
    {
        let mut stepper = Stepper::new(&mut reference, t0, y0, t_start, opts).map_err(solve)?;
        run_to_end(&mut stepper, t_start, &mut ya).map_err(solve)?;
        stats.add_run(stepper.stats());
        h0 = positive(stepper.h_next()).or(h0);
    }

    // 2. Perturbation along u.
    let mut y = vec![0.0; 2 * n];
    y[..n].copy_from_slice(&ya);
    for i in 0..n {
        y[n + i] = ya[i] + lopts.d0 * norm.direction[i];
    }
    let mut pair = Pair {
        a: reference.clone(),
        b: reference,
        n,
    };

    // 3–4. Intervals of τ with renormalisation.
    let mut sum_log = 0.0;
    let mut local = Vec::with_capacity(lopts.n_intervals);
    let mut history = Vec::with_capacity(lopts.n_intervals);
    let mut y_end = vec![0.0; 2 * n];
    for k in 1..=lopts.n_intervals {
        let t_a = t_start + (k - 1) as f64 * lopts.tau;
        let t_b = t_start + k as f64 * lopts.tau;
        let seg_opts = match (opts.fixed_step, h0) {
            (None, Some(h)) => opts.clone().h0(h),
            _ => opts.clone(),
        };
        let mut stepper = Stepper::new(&mut pair, t_a, &y, t_b, &seg_opts).map_err(solve)?;
        run_to_end(&mut stepper, t_b, &mut y_end).map_err(solve)?;
        stats.add_run(stepper.stats());
        h0 = positive(stepper.h_next()).or(h0);
        drop(stepper);

        let (a, b) = y_end.split_at(n);
        let d = norm.distance(a, b);
        if !(d.is_finite() && d > 0.0) {
            return Err(AnalysisError::invalid(
                "trajectories",
                format!(
                    "the separation became {d:e} at t = {t_b} s (the trajectories {}); choose a smaller tau or a larger d0",
                    if d == 0.0 { "merged" } else { "blew up" }
                ),
            ));
        }
        let log = (d / lopts.d0).ln();
        sum_log += log;
        local.push(log / lopts.tau);
        history.push((t_b, sum_log / (k as f64 * lopts.tau)));
        // Renormalise the measured components; bookkeeping ones keep y_b's own values.
        let shrink = lopts.d0 / d;
        y.copy_from_slice(&y_end);
        for i in 0..n {
            if norm.measured[i] {
                y[n + i] = y[i] + shrink * (y_end[n + i] - y_end[i]);
            }
        }
    }

    let exponent = history.last().map_or(0.0, |h| h.1);
    let half = history
        .get(lopts.n_intervals / 2 - 1)
        .map_or(exponent, |h| h.1);
    Ok(LyapunovEstimate {
        exponent,
        uncertainty: batch_standard_error(&local[local.len() / 2..], lopts.n_blocks),
        drift: (exponent - half).abs(),
        history,
        stats,
    })
}

fn positive(h: f64) -> Option<f64> {
    (h.is_finite() && h > 0.0).then_some(h)
}

/// Steps to `t_end` and writes the state there into `out`.
fn run_to_end<F: Formulation>(
    stepper: &mut Stepper<'_, F>,
    t_end: f64,
    out: &mut [f64],
) -> Result<(), SolveError> {
    while stepper.step()? != crate::solve::Stop::EndReached {}
    stepper.interpolate(t_end, out)
}

/// Standard deviation of the means of `n_blocks` consecutive equal blocks of `x`, over
/// √(n_blocks); fewer blocks if `x` is shorter, 0 with fewer than 2.
fn batch_standard_error(x: &[f64], n_blocks: usize) -> f64 {
    let blocks = n_blocks.min(x.len());
    if blocks < 2 {
        return 0.0;
    }
    let len = x.len() / blocks;
    let means: Vec<f64> = x
        .chunks_exact(len)
        .take(blocks)
        .map(|c| c.iter().sum::<f64>() / len as f64)
        .collect();
    let mean = means.iter().sum::<f64>() / blocks as f64;
    let var = means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (blocks - 1) as f64;
    (var / blocks as f64).sqrt()
}

fn validate(lopts: &LyapunovOptions, y0: &[f64], n: usize) -> Result<(), AnalysisError> {
    if y0.len() != n {
        return Err(AnalysisError::invalid(
            "y0",
            format!(
                "the initial state has {} components but the formulation has {n} states",
                y0.len()
            ),
        ));
    }
    check_finite("y0", y0)?;
    if !(lopts.d0.is_finite() && lopts.d0 > 0.0) {
        return Err(AnalysisError::invalid(
            "d0",
            format!("expected a finite separation > 0, got {}", lopts.d0),
        ));
    }
    if !(lopts.tau.is_finite() && lopts.tau > 0.0) {
        return Err(AnalysisError::invalid(
            "tau",
            format!(
                "expected a finite renormalisation interval > 0 s, got {}",
                lopts.tau
            ),
        ));
    }
    if lopts.n_intervals < 2 {
        return Err(AnalysisError::invalid(
            "n_intervals",
            format!(
                "expected at least 2 renormalisation intervals, got {}",
                lopts.n_intervals
            ),
        ));
    }
    if !(lopts.t_transient.is_finite() && lopts.t_transient >= 0.0) {
        return Err(AnalysisError::invalid(
            "t_transient",
            format!("expected a finite time ≥ 0 s, got {}", lopts.t_transient),
        ));
    }
    Ok(())
}

/// The weighted norm over the measured components and the unit perturbation direction.
struct Norm {
    measured: Vec<bool>,
    inv_scale: Vec<f64>,
    direction: Vec<f64>,
}

impl Norm {
    fn new(n: usize, lopts: &LyapunovOptions) -> Result<Self, AnalysisError> {
        let measured: Vec<bool> = if lopts.bookkeeping.is_empty() {
            vec![true; n]
        } else if lopts.bookkeeping.len() == n {
            lopts.bookkeeping.iter().map(|b| !b).collect()
        } else {
            return Err(AnalysisError::invalid(
                "bookkeeping",
                format!(
                    "the mask has {} entries but the formulation has {n} states",
                    lopts.bookkeeping.len()
                ),
            ));
        };
        let scales = if lopts.scales.is_empty() {
            vec![1.0; n]
        } else if lopts.scales.len() == n {
            lopts.scales.clone()
        } else {
            return Err(AnalysisError::invalid(
                "scales",
                format!(
                    "{} scales given but the formulation has {n} states",
                    lopts.scales.len()
                ),
            ));
        };
        if let Some(i) = scales.iter().position(|s| !(s.is_finite() && *s > 0.0)) {
            return Err(AnalysisError::invalid(
                "scales",
                format!("scale {i} is {}; expected a finite value > 0", scales[i]),
            ));
        }
        let m = measured.iter().filter(|&&b| b).count();
        if m == 0 {
            return Err(AnalysisError::invalid(
                "bookkeeping",
                "every state is marked as bookkeeping: nothing is left to perturb",
            ));
        }
        let direction = (0..n)
            .map(|i| {
                if measured[i] {
                    scales[i] / (m as f64).sqrt()
                } else {
                    0.0
                }
            })
            .collect();
        Ok(Self {
            inv_scale: scales.iter().map(|s| 1.0 / s).collect(),
            measured,
            direction,
        })
    }

    fn distance(&self, a: &[f64], b: &[f64]) -> f64 {
        (0..a.len())
            .filter(|&i| self.measured[i])
            .map(|i| ((b[i] - a[i]) * self.inv_scale[i]).powi(2))
            .sum::<f64>()
            .sqrt()
    }
}

/// Two copies of a formulation integrated as one system: states [y_a, y_b], events
/// [g_a, g_b], each event handed to the copy it belongs to.
struct Pair<F> {
    a: F,
    b: F,
    n: usize,
}

/// Each copy is integrated exactly as it would be alone: its |Φ| check at every step end, its
/// projection near singular positions, its stage statistics.
impl<F: Formulation> StepHooks for Pair<F> {
    fn begin_step(&mut self, t: f64, y: &[f64]) {
        let (ya, yb) = y.split_at(self.n);
        self.a.begin_step(t, ya);
        self.b.begin_step(t, yb);
    }

    fn residual_stages(&mut self, min_pivot_ratio: f64) {
        self.a.residual_stages(min_pivot_ratio);
        self.b.residual_stages(min_pivot_ratio);
    }

    fn accept_step(
        &mut self,
        t: f64,
        y: &mut [f64],
        tolerances: Tolerances,
    ) -> Result<EventResponse, FormulationError> {
        let (ya, yb) = y.split_at_mut(self.n);
        let a = self.a.accept_step(t, ya, tolerances)?;
        let b = self.b.accept_step(t, yb, tolerances)?;
        Ok(
            if a == EventResponse::Restart || b == EventResponse::Restart {
                EventResponse::Restart
            } else {
                EventResponse::Continue
            },
        )
    }
}

impl<F: Formulation> Formulation for Pair<F> {
    fn n_states(&self) -> usize {
        2 * self.n
    }

    fn initial_state(&self) -> Vec<f64> {
        let mut y = self.a.initial_state();
        y.extend(self.b.initial_state());
        y
    }

    fn t0(&self) -> f64 {
        self.a.t0()
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        let (ya, yb) = y.split_at(self.n);
        let (da, db) = dy.split_at_mut(self.n);
        self.a.rhs(t, ya, da)?;
        self.b.rhs(t, yb, db)
    }

    fn n_events(&self) -> usize {
        self.a.n_events() + self.b.n_events()
    }

    fn events(&self, t: f64, y: &[f64], g: &mut [f64]) {
        let (ya, yb) = y.split_at(self.n);
        let (ga, gb) = g.split_at_mut(self.a.n_events());
        self.a.events(t, ya, ga);
        self.b.events(t, yb, gb);
    }

    fn apply_event(
        &mut self,
        t: f64,
        y: &mut [f64],
        index: usize,
        crossing: Crossing,
    ) -> EventResponse {
        let (ya, yb) = y.split_at_mut(self.n);
        let ne = self.a.n_events();
        if index < ne {
            self.a.apply_event(t, ya, index, crossing)
        } else {
            self.b.apply_event(t, yb, index - ne, crossing)
        }
    }

    fn max_step(&self, t: f64, y: &[f64]) -> f64 {
        let (ya, yb) = y.split_at(self.n);
        self.a.max_step(t, ya).min(self.b.max_step(t, yb))
    }

    // Everything a copy tells the integrator is forwarded: its bookkeeping states out of error
    // control, its step cap, its analytic Jacobian, its diagnosis. Two defaults stay on
    // purpose: `second_order_positions` is 0 (the pair's states [q_a, v_a, q_b, v_b] do not
    // start with all positions), and `residual_form` is none (IDA integrates the pair as an
    // ODE; its stages are then right-hand sides, which each copy observes itself).

    fn jacobian(
        &self,
        t: f64,
        y: &[f64],
        f_y: &[f64],
        out: &mut [f64],
        work: &mut [f64],
    ) -> Result<usize, FormulationError> {
        // J = diag(J_a, J_b), row-major 2n × 2n: each block is computed into its own n × n
        // buffer (the caller's scratch holds 4n values, enough for each copy's 2n but not for a
        // block; a Jacobian is evaluated once per many steps) and copied into its rows.
        let n = self.n;
        let (ya, yb) = y.split_at(n);
        let (fa, fb) = f_y.split_at(n);
        let mut block = vec![0.0; n * n];
        out.fill(0.0);
        let mut calls = 0;
        for (half, (f, yh, fh)) in [(&self.a, ya, fa), (&self.b, yb, fb)]
            .into_iter()
            .enumerate()
        {
            calls += f.jacobian(t, yh, fh, &mut block, work)?;
            let offset = half * n;
            for i in 0..n {
                let row = (offset + i) * 2 * n + offset;
                out[row..row + n].copy_from_slice(&block[i * n..(i + 1) * n]);
            }
        }
        Ok(calls)
    }

    /// Block diagonal, as the dense one, when both copies give one ([`SparseJacobian`] for
    /// `Pair`).
    fn sparse_jacobian(&self) -> Option<&dyn SparseJacobian> {
        (self.a.sparse_jacobian().is_some() && self.b.sparse_jacobian().is_some())
            .then_some(self as &dyn SparseJacobian)
    }

    fn error_controlled(&self, controlled: &mut [bool]) {
        let (ca, cb) = controlled.split_at_mut(self.n);
        self.a.error_controlled(ca);
        self.b.error_controlled(cb);
    }

    fn diagnose(&self, t: f64, y: &[f64]) -> Option<String> {
        let (ya, yb) = y.split_at(self.n);
        match (self.a.diagnose(t, ya), self.b.diagnose(t, yb)) {
            (Some(a), Some(b)) if a == b => Some(a),
            (Some(a), Some(b)) => Some(format!("reference trajectory: {a}; perturbed one: {b}")),
            (a, b) => a.or(b),
        }
    }
}

/// The pair's augmented Jacobian: unknowns (y_a, y_b, z_a, z_b), the copies' own 𝒥 on the
/// diagonal. The copies' patterns are asked for at every call (O(non-zeros), the order of the
/// values themselves). Reached only when both copies give one.
impl<F: Formulation> SparseJacobian for Pair<F> {
    fn n_algebraic(&self) -> usize {
        let m = |f: &F| f.sparse_jacobian().map_or(0, |s| s.n_algebraic());
        m(&self.a) + m(&self.b)
    }

    fn jacobian_pattern(&self) -> SparsePattern {
        let dim = 2 * self.n + self.n_algebraic();
        let mut entries = Vec::new();
        for half in 0..2 {
            let Some((f, index)) = self.half(half) else {
                continue;
            };
            let p = f.jacobian_pattern();
            for j in 0..p.dim() {
                for &i in p.rows_of(j) {
                    entries.push((index(i), index(j)));
                }
            }
        }
        SparsePattern::from_entries(dim, entries)
    }

    fn jacobian_values(
        &self,
        t: f64,
        y: &[f64],
        values: &mut [f64],
    ) -> Result<usize, FormulationError> {
        let pattern = self.jacobian_pattern();
        let (ya, yb) = y.split_at(self.n.min(y.len()));
        let mut calls = 0;
        values.fill(0.0);
        for (half, yh) in [(0, ya), (1, yb)] {
            let Some((f, index)) = self.half(half) else {
                continue;
            };
            let p = f.jacobian_pattern();
            let mut own = vec![0.0; p.nnz()];
            calls += f.jacobian_values(t, yh, &mut own)?;
            // Each column of a copy is one column of the pair, its rows in the same order.
            for j in 0..p.dim() {
                let start = p.col_ptr()[j];
                for (k, &i) in p.rows_of(j).iter().enumerate() {
                    if let Some(v) = pattern
                        .position(index(i), index(j))
                        .and_then(|at| values.get_mut(at))
                    {
                        *v = own[start + k];
                    }
                }
            }
        }
        Ok(calls)
    }
}

impl<F: Formulation> Pair<F> {
    /// Copy `half` (0 = a, 1 = b)'s sparse Jacobian and the map from its augmented numbering to
    /// the pair's.
    fn half(&self, half: usize) -> Option<(&dyn SparseJacobian, impl Fn(usize) -> usize + use<F>)> {
        let n = self.n;
        let m_a = self.a.sparse_jacobian().map_or(0, |s| s.n_algebraic());
        let f = if half == 0 { &self.a } else { &self.b };
        let index = move |i: usize| {
            if i < n {
                half * n + i
            } else {
                2 * n + half * m_a + (i - n)
            }
        };
        f.sparse_jacobian().map(|s| (s, index))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formulation::NoStepHooks;

    /// x' = v, v' = 0 with an event g = x − 1 that reverses v (a wall at x = 1) and counts its
    /// bounces.
    #[derive(Clone)]
    struct Wall {
        bounces: usize,
    }
    impl NoStepHooks for Wall {}

    impl Formulation for Wall {
        fn n_states(&self) -> usize {
            2
        }
        fn initial_state(&self) -> Vec<f64> {
            vec![0.0, 1.0]
        }
        fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
            dy[0] = y[1];
            dy[1] = 0.0;
            Ok(())
        }
        fn n_events(&self) -> usize {
            1
        }
        fn events(&self, _t: f64, y: &[f64], g: &mut [f64]) {
            g[0] = y[0] - 1.0;
        }
        fn apply_event(&mut self, _t: f64, y: &mut [f64], _i: usize, c: Crossing) -> EventResponse {
            if c == Crossing::Rising {
                y[1] = -y[1];
                self.bounces += 1;
            }
            EventResponse::Restart
        }
    }

    #[test]
    fn each_trajectory_of_the_pair_gets_its_own_events() {
        // a starts at x = 0 (hits the wall at t = 1), b at x = 0.5 (at t = 0.5).
        let mut pair = Pair {
            a: Wall { bounces: 0 },
            b: Wall { bounces: 0 },
            n: 2,
        };
        let y0 = [0.0, 1.0, 0.5, 1.0];
        let mut y = [0.0; 4];
        let result = Stepper::new(&mut pair, 0.0, &y0, 1.25, &SolverOptions::default())
            .and_then(|mut s| run_to_end(&mut s, 1.25, &mut y));
        assert!(result.is_ok(), "{result:?}");
        assert_eq!((pair.a.bounces, pair.b.bounces), (1, 1));
        // After the bounce each moves back: a from 1 at t = 1, b from 1 at t = 0.5.
        assert!(
            (y[0] - 0.75).abs() < 1e-9 && (y[2] - 0.25).abs() < 1e-9,
            "{y:?}"
        );
        assert!(y[1] == -1.0 && y[3] == -1.0, "{y:?}");
    }

    /// A formulation with a bookkeeping state, an analytic Jacobian and a step-end projection
    /// (x² + v² = 1 restored at every accepted step), to see that the pair forwards them.
    #[derive(Clone, Default)]
    struct Circle {
        projections: usize,
    }
    impl StepHooks for Circle {
        fn begin_step(&mut self, _t: f64, _y: &[f64]) {}
        fn residual_stages(&mut self, _min_pivot_ratio: f64) {}
        fn accept_step(
            &mut self,
            _t: f64,
            y: &mut [f64],
            _tolerances: Tolerances,
        ) -> Result<EventResponse, FormulationError> {
            let r = y[0].hypot(y[1]);
            y[0] /= r;
            y[1] /= r;
            self.projections += 1;
            Ok(EventResponse::Restart)
        }
    }

    impl Formulation for Circle {
        fn n_states(&self) -> usize {
            3
        }
        fn initial_state(&self) -> Vec<f64> {
            vec![1.0, 0.0, 0.0]
        }
        fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
            dy[0] = y[1];
            dy[1] = -y[0];
            dy[2] = 0.0;
            Ok(())
        }
        fn jacobian(
            &self,
            _t: f64,
            _y: &[f64],
            _f_y: &[f64],
            out: &mut [f64],
            _work: &mut [f64],
        ) -> Result<usize, FormulationError> {
            out.fill(0.0);
            out[1] = 1.0;
            out[3] = -1.0;
            Ok(0)
        }
        fn error_controlled(&self, controlled: &mut [bool]) {
            controlled[2] = false;
        }
        fn sparse_jacobian(&self) -> Option<&dyn SparseJacobian> {
            Some(self)
        }
    }

    /// The circle as y' = (v, z, 0), 0 = z + x: one algebraic unknown z = −x.
    impl SparseJacobian for Circle {
        fn n_algebraic(&self) -> usize {
            1
        }
        fn jacobian_pattern(&self) -> SparsePattern {
            SparsePattern::from_entries(4, [(0, 0), (1, 1), (2, 2), (3, 3), (0, 1), (1, 3), (3, 0)])
        }
        fn jacobian_values(
            &self,
            _t: f64,
            _y: &[f64],
            values: &mut [f64],
        ) -> Result<usize, FormulationError> {
            let p = self.jacobian_pattern();
            values.fill(0.0);
            for (i, j) in [(0, 1), (1, 3), (3, 0), (3, 3)] {
                if let Some(v) = p.position(i, j).and_then(|k| values.get_mut(k)) {
                    *v = 1.0;
                }
            }
            Ok(0)
        }
    }

    #[test]
    fn the_pair_forwards_the_sparse_jacobian_block_by_block() {
        let pair = Pair {
            a: Circle::default(),
            b: Circle::default(),
            n: 3,
        };
        let Some(sparse) = pair.sparse_jacobian() else {
            panic!("both copies give a sparse Jacobian: so does the pair");
        };
        assert_eq!(sparse.n_algebraic(), 2);
        let p = sparse.jacobian_pattern();
        let mut values = vec![9.0; p.nnz()];
        let y = [1.0, 0.0, 0.0, 0.5, 0.5, 0.0];
        assert_eq!(sparse.jacobian_values(0.0, &y, &mut values).ok(), Some(0));
        let mut full = nalgebra::DMatrix::<f64>::zeros(8, 8);
        for j in 0..8 {
            for (k, &i) in p.rows_of(j).iter().enumerate() {
                full[(i, j)] = values[p.col_ptr()[j] + k];
            }
        }
        // (y_a, y_b, z_a, z_b): z_a = 6 pairs with y_a = 0..3, z_b = 7 with y_b = 3..6.
        assert_eq!(
            (full[(1, 6)], full[(6, 0)], full[(4, 7)], full[(7, 3)]),
            (1.0, 1.0, 1.0, 1.0)
        );
        let d = full.view((6, 6), (2, 2)).clone_owned();
        let Some(d_inv_c) = d.lu().solve(&full.view((6, 0), (2, 6)).clone_owned()) else {
            panic!("∂k/∂z is the identity");
        };
        let schur = full.view((0, 0), (6, 6)) - full.view((0, 6), (6, 2)) * d_inv_c;
        let (mut dense, mut work) = ([0.0; 36], [0.0; 12]);
        assert_eq!(
            pair.jacobian(0.0, &y, &[0.0; 6], &mut dense, &mut work)
                .ok(),
            Some(0)
        );
        for i in 0..6 {
            for j in 0..6 {
                assert_eq!(schur[(i, j)], dense[i * 6 + j], "J[{i}][{j}]");
            }
        }
    }

    #[test]
    fn the_pair_forwards_every_step_hook_to_both_copies() {
        let mut pair = Pair {
            a: Circle::default(),
            b: Circle::default(),
            n: 3,
        };
        // Bookkeeping states of both copies out of error control.
        let mut controlled = [true; 6];
        pair.error_controlled(&mut controlled);
        assert_eq!(controlled, [true, true, false, true, true, false]);
        // The Jacobian is block diagonal with each copy's own (analytic: no RHS call).
        let (y, f_y) = ([1.0, 0.0, 0.0, 0.5, 0.5, 0.0], [0.0; 6]);
        // Scratch of 4n values, as the trait promises.
        let (mut jac, mut work) = ([9.0; 36], [0.0; 12]);
        let calls = pair.jacobian(0.0, &y, &f_y, &mut jac, &mut work);
        assert_eq!(calls.ok(), Some(0));
        let mut want = [0.0; 36];
        for offset in [0, 3] {
            want[offset * 6 + offset + 1] = 1.0;
            want[(offset + 1) * 6 + offset] = -1.0;
        }
        assert_eq!(jac, want);
        // Every accepted step end is projected in both halves.
        let y0 = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        let mut y_end = [0.0; 6];
        let mut stepper = Stepper::new(&mut pair, 0.0, &y0, 1.0, &SolverOptions::default())
            .unwrap_or_else(|e| panic!("{e}"));
        run_to_end(&mut stepper, 1.0, &mut y_end).unwrap_or_else(|e| panic!("{e}"));
        let steps = stepper.stats().steps as usize;
        drop(stepper);
        assert!(steps > 0);
        assert_eq!((pair.a.projections, pair.b.projections), (steps, steps));
        for half in [&y_end[..3], &y_end[3..]] {
            assert!(
                (half[0].hypot(half[1]) - 1.0).abs() < 1e-15,
                "on the circle: {half:?}"
            );
        }
    }

    #[test]
    fn batch_means_of_a_constant_have_no_spread() {
        // Equal means up to the rounding of their sums (≈ 1e-17).
        let se = batch_standard_error(&[0.3; 40], 10);
        assert!(se < 1e-15, "constant: se = {se}");
        // Block means 0, 1, 0, 1, … (10 blocks of 4): mean 0.5, variance 10·0.25/9,
        // standard error √(variance/10) = √(0.25/9).
        let x: Vec<f64> = (0..40).map(|i| ((i / 4) % 2) as f64).collect();
        let se = batch_standard_error(&x, 10);
        assert!((se - (0.25f64 / 9.0).sqrt()).abs() < 1e-12, "se = {se}");
    }
}
