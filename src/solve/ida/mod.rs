//! SUNDIALS IDA (variable-order, variable-step BDF for F(t, Y, Ẏ) = 0, ref. 1) as an
//! [`Integrator`]: `--method ida`, only with the cargo feature `ida`.
//!
//! IDA integrates the formulation's residual form
//! ([`Formulation::residual_form`]; the DAE:
//! λ as algebraic unknowns, [`crate::formulation::dae::residual`]) with the analytic iteration
//! matrix, factored by IDA's dense direct solver on small models and by a sparse LU (faer,
//! `ffi/sparse.rs`) over the residual form's pattern from [`SPARSE_MIN_UNKNOWNS`] unknowns
//! on ([`IdaMethod::linear_solver`], [`IdaSettings`](crate::solve::IdaSettings)); other
//! formulations as Ẏ − f(t, Y) ([`OdeResidual`]). All `unsafe` code is in `ffi` (private), the one wrapper around
//! `sundials-sys`.
//!
//! # Why an `Integrator`, not a driver of its own
//! IDA plugs into the same driver ([`Stepper`](crate::solve::Stepper)) as every other method:
//! one [`Integrator::attempt`] is IDA in one-step mode with the stop time at the driver's step
//! end, so the driver's clamps (`t_end`, `h_max`, and the grazing guard of
//! [`Formulation::max_step`], the per-step
//! maximum step of the clearance joints) reach IDA as stop times. Events are then located by
//! the driver on IDA's own interpolating polynomial (the one IDA's root finder would use, read
//! through `IDAGetDky`) with the same root finder, tolerance and sign rules as every other
//! method, and handled by the same
//! [`Formulation::apply_event`]: the impact
//! velocity δ̇⁽⁻⁾ is stored at the root exactly as with DOP853, and every method finds the same
//! impacts. A driver of its own with `IDARootInit` would have duplicated the event rules, the
//! restarts, the sampling, the step hook, the run limits and the result files. After each
//! event the driver calls [`Integrator::restart`], which re-initialises IDA (`IDAReInit`) from
//! consistent values at the event time.
//!
//! # What differs from the other methods
//! * IDA chooses its own steps: the driver's step [t, t_new] is one IDA step when IDA's own
//!   step reaches t_new, and several when IDA shortens a step itself (an error-test or Newton
//!   failure, retried inside IDA). The dense output then covers each internal step by its own
//!   polynomial (kept as a snapshot of k + 1 values at Chebyshev points, which reproduces
//!   IDA's degree-k interpolant), so events and samples anywhere in [t, t_new] are exact.
//!   `SolverStats::steps` counts the driver's steps; IDA's internal rejections are added to
//!   `rejected`, `error_test_failures` and `newton_failures`.
//! * Error control: IDA's weighted RMS norm over all N unknowns gets weights
//!   √(N/m)/(rtol·|y_i| + atol) on the m error-controlled states and 0 on bookkeeping ones
//!   (stored impact velocities), which is the norm of
//!   [`ErrorWeights`]. λ has weight 0: it is out of the error test (`IDASetSuppressAlg`) and
//!   out of the Newton test, where the velocities judge it: an error Δλ moves v̇ by
//!   M⁻¹Φ_qᵀΔλ and the Newton correction of v by that over c, so converged velocities mean a
//!   λ converged on its natural scale c·M·(tolerance of v). (A weight 1/(rtol·|λ|) made
//!   Newton fail on round-off of λ near configurations where the KKT matrix is ill
//!   conditioned.) λ feeds nothing but the energy rates: output columns recompute it from
//!   (q, v).
//! * Bookkeeping integrals (the energy of `--energy`,
//!   [`ResidualForm::n_quadratures`]) are IDAS quadratures: integrated by the same BDF
//!   formulas after each converged step, outside the Newton iteration and the error test
//!   (`IDASetQuadErrCon(false)`), so IDA's unknowns, norms and steps are those of a run
//!   without them and the body states are bit-identical (`tests/ida_energy.rs`). Their dense
//!   output is IDA's (`IDAGetQuadDky`).
//! * A residual that fails recoverably (a trial state deep in a contact,
//!   [`FormulationError::is_recoverable`]) is returned to IDA as recoverable (> 0): IDA retries
//!   with a smaller step. If IDA gives up, the error goes to the driver as it is, which retries
//!   with a quarter of the step from the last accepted state (IDA re-initialised).
//! * A formulation that controls none of its states (the generalized formulation of a linkage
//!   whose drivers fix every coordinate: no independent coordinate, only the bookkeeping of the
//!   projection) would leave IDA's norm empty: every step passes the error test and every
//!   Newton iteration its convergence test (IDA never evaluates the residual at the corrected
//!   state), the step doubles each time, and the warm start of the projection drifts until
//!   Newton cannot recover the coordinates from it (on the ideal four-bar: radians off after
//!   0.26 s). [`ErrorWeights::new`] therefore controls every state of such a formulation, for
//!   every method, so that the steps resolve the warm start (smooth kinematics) to the
//!   tolerance (`tests/ida_formulations.rs`: the ideal four-bar's closed form to 2e-15).
//! * Fixed steps (`--fixed-step`) are not available: IDA always controls its error.
//!
//! # References
//! 1. A. C. Hindmarsh, P. N. Brown, K. E. Grant, S. L. Lee, R. Serban, D. E. Shumaker,
//!    C. S. Woodward, SUNDIALS: Suite of nonlinear and differential/algebraic equation
//!    solvers, *ACM Transactions on Mathematical Software* 31(3) (2005) 363–396; IDA user
//!    guide, SUNDIALS 7.1.
//! 2. K. E. Brenan, S. L. Campbell, L. R. Petzold, *Numerical Solution of Initial-Value
//!    Problems in Differential-Algebraic Equations*, SIAM, 1996 (DASSL, the ancestor of IDA).

mod ffi;

use super::error::SolveError;
use super::integrator::{Attempt, ErrorWeights, Integrator, Start, Trial};
use super::options::Method;
use super::radau5::LinearSolver;
use super::stats::SolverStats;
use crate::formulation::residual::{OdeResidual, ResidualForm};
use crate::formulation::{Formulation, FormulationError};
use ffi::{Callback, Ida, IdaCounts, IdaFailure, Problem};

/// Most internal IDA steps inside one driver step before the attempt is abandoned as
/// [`SolveError::MethodFailed`] (IDA shortens a step only after failures; thousands in a row
/// mean it cannot make progress).
const MAX_SUBSTEPS: usize = 10_000;

/// The dense output of one internal IDA step: IDA's interpolant of degree k, kept as its values
/// at k + 1 Chebyshev points of [t_lo, t_hi] and evaluated by the barycentric formula.
#[derive(Debug, Clone, Default)]
struct Piece {
    t_lo: f64,
    t_hi: f64,
    nodes: Vec<f64>,
    weights: Vec<f64>,
    /// values[j * n + i]: component i at node j.
    values: Vec<f64>,
}

impl Piece {
    /// Barycentric Lagrange interpolation at t (ref.: Berrut & Trefethen, SIAM Review 46, 2004).
    fn eval(&self, t: f64, n: usize, out: &mut [f64]) {
        if let Some(j) = self.nodes.iter().position(|&x| x == t) {
            out[..n].copy_from_slice(&self.values[j * n..j * n + n]);
            return;
        }
        let mut denom = 0.0;
        out[..n].fill(0.0);
        for (j, (&x, &w)) in self.nodes.iter().zip(&self.weights).enumerate() {
            let c = w / (t - x);
            denom += c;
            for (o, v) in out[..n].iter_mut().zip(&self.values[j * n..j * n + n]) {
                *o += c * v;
            }
        }
        for o in &mut out[..n] {
            *o /= denom;
        }
    }
}

/// The equations as IDA's callbacks call them, for one `solve_one_step`.
struct Equations<'a> {
    form: &'a dyn ResidualForm,
    weights: &'a ErrorWeights,
    /// Number of the formulation's states in Y (n − n_Q): the unknowns after them are λ.
    n: usize,
    /// √(N/m): IDA's norm divides by N, linkdyn's by the m controlled components.
    scale: f64,
    /// The last failure of the equations and the time of the failed evaluation.
    error: Option<(f64, FormulationError)>,
    /// Right-hand-side calls made by Jacobians (the ODE fallback's finite differences).
    jacobian_rhs_calls: u64,
}

impl Equations<'_> {
    fn failed(&mut self, t: f64, e: FormulationError) -> Callback {
        let answer = if e.is_recoverable() {
            Callback::Recoverable
        } else {
            Callback::Fatal
        };
        self.error = Some((t, e));
        answer
    }
}

impl Problem for Equations<'_> {
    fn residual(&mut self, t: f64, yy: &[f64], yp: &[f64], res: &mut [f64]) -> Callback {
        match self.form.residual(t, yy, yp, res) {
            Ok(()) => Callback::Ok,
            Err(e) => self.failed(t, e),
        }
    }

    fn jacobian(
        &mut self,
        t: f64,
        c: f64,
        yy: &[f64],
        yp: &[f64],
        res: &[f64],
        jac: &mut [f64],
    ) -> Callback {
        match self.form.jacobian(t, yy, yp, res, c, jac) {
            Ok(calls) => {
                self.jacobian_rhs_calls += calls as u64;
                Callback::Ok
            }
            Err(e) => self.failed(t, e),
        }
    }

    fn sparse_jacobian(
        &mut self,
        t: f64,
        c: f64,
        yy: &[f64],
        yp: &[f64],
        values: &mut [f64],
    ) -> Callback {
        match self.form.sparse_jacobian(t, yy, yp, c, values) {
            Ok(calls) => {
                self.jacobian_rhs_calls += calls as u64;
                Callback::Ok
            }
            Err(e) => self.failed(t, e),
        }
    }

    fn weights(&mut self, yy: &[f64], ewt: &mut [f64]) -> Callback {
        let (rtol, atol) = (self.weights.rtol, self.weights.atol);
        for (i, (w, y)) in ewt.iter_mut().zip(yy).enumerate() {
            *w = if i >= self.n {
                // λ: out of the error test and the Newton test (see the module documentation).
                0.0
            } else if self.weights.mask.get(i).copied().unwrap_or(0.0) > 0.0 {
                self.scale / (rtol * y.abs() + atol)
            } else {
                0.0
            };
        }
        Callback::Ok
    }

    fn quadrature(&mut self, t: f64, yy: &[f64], yp: &[f64], out: &mut [f64]) -> Callback {
        match self.form.quadrature_rhs(t, yy, yp, out) {
            Ok(()) => Callback::Ok,
            Err(e) => self.failed(t, e),
        }
    }
}

/// A (re)start waiting for the next attempt: the state and, from the driver, f(t, y).
#[derive(Debug, Clone)]
struct Pending {
    t: f64,
    y: Vec<f64>,
    f0: Option<Vec<f64>>,
}

/// SUNDIALS IDA behind the [`Integrator`] trait (see the module documentation).
pub struct IdaMethod {
    /// The formulation's states: n = n_s + n_Q (states in Y, then the quadratures).
    n: usize,
    n_s: usize,
    weights: ErrorWeights,
    h_max: f64,
    ida: Option<Ida>,
    /// The formulation's own residual form (the DAE), built at the first attempt; `None` with
    /// `ode` set: Ẏ − f(t, Y).
    form: Option<Box<dyn ResidualForm>>,
    ode: bool,
    pending: Option<Pending>,
    /// Time of IDA's state (the end of the last accepted attempt).
    t_ida: f64,
    yy: Vec<f64>,
    yp: Vec<f64>,
    /// The quadratures (length n_Q).
    yq: Vec<f64>,
    solution: Vec<f64>,
    pieces: Vec<Piece>,
    n_pieces: usize,
    scratch: Scratch,
    counts: IdaCounts,
    /// The smallest pivot ratio over the residuals of the last attempt, until the driver takes
    /// it ([`Integrator::take_residual_stages`]).
    stage_pivot_ratio: Option<f64>,
    /// Dense or sparse iteration matrix ([`IdaMethod::linear_solver`]).
    linear_solver: LinearSolver,
}

/// Fewest unknowns of the residual form for which [`LinearSolver::Auto`] takes the sparse LU.
/// Measured per IDA step on the N-four-bar chain (docs/measurements.md, "IDA with a sparse
/// LU"): see there for the crossing.
pub const SPARSE_MIN_UNKNOWNS: usize = 60;

impl IdaMethod {
    /// IDA for a formulation with n states and error weights `weights`, largest step `h_max`.
    pub fn new(n: usize, weights: ErrorWeights, h_max: f64) -> Self {
        IdaMethod {
            n,
            n_s: n,
            weights,
            h_max,
            ida: None,
            form: None,
            ode: false,
            pending: None,
            t_ida: f64::NAN,
            yy: Vec::new(),
            yp: Vec::new(),
            yq: Vec::new(),
            solution: vec![0.0; n],
            pieces: Vec::new(),
            n_pieces: 0,
            scratch: Scratch::default(),
            counts: IdaCounts::default(),
            stage_pivot_ratio: None,
            linear_solver: LinearSolver::Auto,
        }
    }

    /// How the iteration matrix is factored: [`LinearSolver::Auto`] (the default) takes the
    /// sparse LU where the residual form has a sparse pattern and at least
    /// [`SPARSE_MIN_UNKNOWNS`] unknowns, IDA's dense LU otherwise; `Sparse` wherever it has a
    /// pattern; `Dense` always dense.
    #[must_use]
    pub fn linear_solver(mut self, choice: LinearSolver) -> Self {
        self.linear_solver = choice;
        self
    }

    /// Whether IDA factors a sparse iteration matrix (known after the first attempt).
    pub fn uses_sparse_lu(&self) -> bool {
        self.ida.as_ref().is_some_and(Ida::is_sparse)
    }

    /// Adds IDA's counters since the last call to `stats`.
    fn add_counts(&mut self, stats: &mut SolverStats) {
        let Some(ida) = &self.ida else { return };
        let Ok(now) = ida.counts() else { return };
        let d = |a: u64, b: u64| a.saturating_sub(b);
        let c = self.counts;
        stats.rhs_evals += d(now.residuals, c.residuals);
        stats.newton_iterations += d(now.newton_iterations, c.newton_iterations);
        stats.jacobian_evals += d(now.jacobians, c.jacobians);
        let etf = d(now.error_test_failures, c.error_test_failures);
        let ncf = d(now.newton_failures, c.newton_failures);
        stats.error_test_failures += etf;
        stats.newton_failures += ncf;
        stats.rejected += etf + ncf;
        self.counts = now;
    }

    /// Creates IDA for the formulation's residual form at the first attempt.
    fn setup<F: Formulation + ?Sized>(&mut self, f: &F, t: f64) -> Result<(), SolveError> {
        if self.ida.is_some() {
            return Ok(());
        }
        self.form = f.residual_form();
        self.ode = self.form.is_none();
        let ode_form;
        let form: &dyn ResidualForm = match &self.form {
            Some(b) => &**b,
            None => {
                ode_form = OdeResidual::new(f);
                &ode_form
            }
        };
        if form.n_states() != self.n {
            return Err(SolveError::StateLength {
                what: "residual form",
                expected: self.n,
                got: form.n_states(),
            });
        }
        let nn = form.n_unknowns();
        let nq = form.n_quadratures().min(self.n);
        self.n_s = self.n - nq;
        let mut differential = vec![true; nn];
        form.differential(&mut differential);
        self.yy = vec![0.0; nn];
        self.yp = vec![0.0; nn];
        self.yq = vec![0.0; nq];
        let sparse = match self.linear_solver {
            LinearSolver::Dense => false,
            LinearSolver::Sparse => true,
            LinearSolver::Auto => nn >= SPARSE_MIN_UNKNOWNS,
        };
        let pattern = if sparse { form.sparse_pattern() } else { None };
        self.ida =
            Some(Ida::new(&differential, nq, pattern.as_ref()).map_err(|e| method_failure(t, e))?);
        Ok(())
    }

    /// Re-initialises IDA at a pending (re)start: consistent values from (t, y, f(t, y)).
    fn reinit<F: Formulation + ?Sized>(
        &mut self,
        f: &F,
        h0: f64,
        stats: &mut SolverStats,
    ) -> Result<(), SolveError> {
        let Some(p) = self.pending.take() else {
            return Ok(());
        };
        let f0 = match p.f0 {
            Some(f0) => f0,
            None => {
                let mut f0 = vec![0.0; self.n];
                stats.rhs_evals += 1;
                f.rhs(p.t, &p.y, &mut f0)
                    .map_err(|source| SolveError::Formulation { t: p.t, source })?;
                f0
            }
        };
        let ode_form;
        let form: &dyn ResidualForm = match &self.form {
            Some(b) => &**b,
            None => {
                ode_form = OdeResidual::new(f);
                &ode_form
            }
        };
        form.consistent_values(p.t, &p.y, &f0, &mut self.yy, &mut self.yp)
            .map_err(|source| SolveError::Formulation { t: p.t, source })?;
        self.yq.copy_from_slice(&p.y[self.n_s..]);
        self.add_counts(stats);
        let h_max = self.h_max;
        let Some(ida) = self.ida.as_mut() else {
            return Ok(());
        };
        let result = ida.init(p.t, &self.yy, &self.yp, &self.yq, h0, h_max);
        // IDAReInit resets IDA's counters.
        self.counts = IdaCounts::default();
        result.map_err(|e| method_failure(p.t, e))?;
        self.t_ida = p.t;
        Ok(())
    }
}

/// Scratch of [`snapshot`]: Y and the quadratures at one node (reused, no allocation per step).
#[derive(Debug, Clone, Default)]
struct Scratch {
    full: Vec<f64>,
    quad: Vec<f64>,
}

/// Snapshot of IDA's last internal step into `pieces[index]`: the formulation's n = n_s + n_Q
/// states, Y\[..n_s\] then the quadratures.
fn snapshot(
    ida: &mut Ida,
    pieces: &mut Vec<Piece>,
    index: usize,
    (n, n_s): (usize, usize),
    scratch: &mut Scratch,
) -> Result<(), IdaFailure> {
    let (tn, hu, k, _) = ida.last_step()?;
    let (lo, hi) = (tn - hu.abs(), tn);
    if pieces.len() <= index {
        pieces.push(Piece::default());
    }
    let piece = &mut pieces[index];
    piece.t_lo = lo;
    piece.t_hi = hi;
    piece.nodes.clear();
    piece.weights.clear();
    piece.values.resize((k + 1) * n, 0.0);
    let Scratch { full, quad } = scratch;
    full.resize(ida.len(), 0.0);
    quad.resize(ida.n_quadratures(), 0.0);
    // Chebyshev points of the second kind, x_j = mid − half cos(jπ/k), with the barycentric
    // weights (−1)^j, halved at both ends.
    let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
    for j in 0..=k {
        let x = if j == 0 {
            lo
        } else if j == k {
            hi
        } else {
            mid - half * (std::f64::consts::PI * j as f64 / k as f64).cos()
        };
        let sign = if j % 2 == 0 { 1.0 } else { -1.0 };
        let w = if j == 0 || j == k { 0.5 * sign } else { sign };
        ida.dense(x, full, quad)?;
        piece.nodes.push(x);
        piece.weights.push(w);
        let values = &mut piece.values[j * n..(j + 1) * n];
        values[..n_s].copy_from_slice(&full[..n_s]);
        values[n_s..].copy_from_slice(quad);
    }
    Ok(())
}

/// An IDA failure as the run's error.
fn method_failure(t: f64, e: IdaFailure) -> SolveError {
    SolveError::MethodFailed {
        t,
        method: "ida",
        flag: e.flag,
        reason: e.reason,
    }
}

impl<F: Formulation + ?Sized> Integrator<F> for IdaMethod {
    fn method(&self) -> Method {
        Method::Ida
    }

    fn restart(&mut self, t: f64, y: &[f64], f0: &[f64]) {
        self.pending = Some(Pending {
            t,
            y: y.to_vec(),
            f0: Some(f0.to_vec()),
        });
    }

    /// A first step of 1 µs (at most the driver's cap): IDA starts at order 1 and grows its
    /// step and order itself within a few steps.
    fn initial_step(
        &mut self,
        _f: &F,
        start: &Start<'_>,
        _stats: &mut SolverStats,
    ) -> Result<f64, SolveError> {
        Ok(start.h_cap.min(1e-6))
    }

    fn attempt(
        &mut self,
        f: &F,
        trial: &Trial<'_>,
        stats: &mut SolverStats,
    ) -> Result<Attempt, SolveError> {
        if !trial.error_control {
            return Err(SolveError::invalid(
                "fixed_step",
                "IDA always controls its error and chooses its own steps: use it without a fixed step size",
            ));
        }
        self.setup(f, trial.t)?;
        if self.pending.is_none() && self.t_ida != trial.t {
            // The driver moved on without a restart (not expected): start afresh from its state.
            self.pending = Some(Pending {
                t: trial.t,
                y: trial.y.to_vec(),
                f0: None,
            });
        }
        self.reinit(f, trial.h, stats)?;
        let ode_form;
        let form: &dyn ResidualForm = match &self.form {
            Some(b) => &**b,
            None => {
                ode_form = OdeResidual::new(f);
                &ode_form
            }
        };
        // Controlled states (all of them where the formulation marks none: `ErrorWeights::new`).
        let m = self.weights.len().max(1);
        let mut equations = Equations {
            form,
            weights: &self.weights,
            n: self.n_s,
            scale: (self.yy.len() as f64 / m as f64).sqrt(),
            error: None,
            jacobian_rhs_calls: 0,
        };
        self.n_pieces = 0;
        let mut outcome = Err(None);
        for _ in 0..MAX_SUBSTEPS {
            let Some(ida) = self.ida.as_mut() else {
                break;
            };
            match ida.solve_one_step(&mut equations, trial.t_new, &mut self.yy, &mut self.yq) {
                Ok(ret) => {
                    let sizes = (self.n, self.n_s);
                    let piece = snapshot(
                        ida,
                        &mut self.pieces,
                        self.n_pieces,
                        sizes,
                        &mut self.scratch,
                    );
                    if let Err(e) = piece {
                        outcome = Err(Some((ret.t, e)));
                        break;
                    }
                    self.n_pieces += 1;
                    if ret.at_stop || ret.t >= trial.t_new {
                        outcome = Ok(());
                        break;
                    }
                }
                Err(e) => {
                    let t = ida.last_step().map(|s| s.0).unwrap_or(trial.t);
                    outcome = Err(Some((t, e)));
                    break;
                }
            }
        }
        // IDA's residuals are the stages of this step (rejected ones included), for the
        // formulation's checks at the step end (the DAE's projection near singular positions):
        // the driver hands them on (`take_residual_stages`).
        self.stage_pivot_ratio = Some(form.take_min_pivot_ratio());
        stats.rhs_evals += equations.jacobian_rhs_calls;
        stats.jacobian_rhs_evals += equations.jacobian_rhs_calls;
        let formulation_error = equations.error.take();
        self.add_counts(stats);
        match outcome {
            Ok(()) => {
                self.solution[..self.n_s].copy_from_slice(&self.yy[..self.n_s]);
                self.solution[self.n_s..].copy_from_slice(&self.yq);
                self.t_ida = trial.t_new;
                let h_next = self
                    .ida
                    .as_ref()
                    .and_then(|ida| ida.last_step().ok())
                    .map_or(trial.h, |s| s.3);
                Ok(Attempt::Accepted { h_next })
            }
            Err(failure) => {
                // Start the retry (or nothing) afresh from the driver's state.
                self.pending = Some(Pending {
                    t: trial.t,
                    y: trial.y.to_vec(),
                    f0: None,
                });
                match (failure, formulation_error) {
                    (Some(_), Some((t, source))) => Err(SolveError::Formulation { t, source }),
                    (Some((t, e)), None) => Err(method_failure(t, e)),
                    (None, _) => Err(SolveError::MethodFailed {
                        t: trial.t,
                        method: "ida",
                        flag: "too many internal steps".into(),
                        reason: format!(
                            "IDA took {MAX_SUBSTEPS} internal steps inside one step of the driver from t = {} s to {} s without reaching its end",
                            trial.t, trial.t_new
                        ),
                    }),
                }
            }
        }
    }

    fn solution(&self) -> &[f64] {
        &self.solution
    }

    fn take_residual_stages(&mut self) -> Option<f64> {
        self.stage_pivot_ratio.take()
    }

    fn interpolate(
        &mut self,
        _f: &F,
        t: f64,
        out: &mut [f64],
        _stats: &mut SolverStats,
    ) -> Result<(), SolveError> {
        let pieces = &self.pieces[..self.n_pieces];
        let piece = pieces
            .iter()
            .find(|p| t <= p.t_hi)
            .or_else(|| pieces.last());
        match piece {
            Some(p) => p.eval(t, self.n, out),
            None => out.copy_from_slice(&self.solution),
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The snapshot of a polynomial of degree k at k + 1 Chebyshev points reproduces it.
    #[test]
    fn a_piece_reproduces_a_polynomial_of_its_degree() {
        let p = |t: f64| 1.0 - 2.0 * t + 0.5 * t.powi(3) - 0.1 * t.powi(5);
        let (lo, hi, k) = (0.3, 0.8, 5);
        let mut piece = Piece {
            t_lo: lo,
            t_hi: hi,
            ..Piece::default()
        };
        for j in 0..=k {
            let x = 0.5 * (lo + hi)
                - 0.5 * (hi - lo) * (std::f64::consts::PI * j as f64 / k as f64).cos();
            let sign = if j % 2 == 0 { 1.0 } else { -1.0 };
            piece.nodes.push(x);
            piece
                .weights
                .push(if j == 0 || j == k { 0.5 * sign } else { sign });
            piece.values.push(p(x));
        }
        let mut out = [0.0];
        for t in [0.3, 0.41, 0.555, 0.8, 0.81] {
            piece.eval(t, 1, &mut out);
            // Round-off of the barycentric formula: a few ulps times the Lebesgue constant (< 3).
            assert!(
                (out[0] - p(t)).abs() < 1e-14,
                "t = {t}: {} vs {}",
                out[0],
                p(t)
            );
        }
    }
}
