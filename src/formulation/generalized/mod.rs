//! Generalised coordinates by coordinate partitioning, for any model (`--formulation
//! generalized`).
//!
//! The absolute coordinates q (x, y, φ per body) are split into *independent* ones q_I, as many
//! as the linkage has degrees of freedom (clearance joints add freedom, not constraints), and
//! *dependent* ones q_D, one per active constraint row (ref. 1). Only q_I and q̇_I carry the
//! motion: at every evaluation, from (q_I, q̇_I),
//!
//! ```text
//!     positions:      Φ(q_D, q_I, t) = 0            Newton, Φ_qD Δq_D = −Φ, from the stored q_D
//!     velocities:     Φ_qD q̇_D = −Φ_qI q̇_I − Φ_t    one linear solve with the same LU
//!     accelerations:  M q̈ + Φ_qᵀ λ = Q,  Φ_q q̈ = γ    the DAE's multiplier solve at that state
//! ```
//!
//! so the constraints hold to Newton's tolerance at every stage, output and event: there is no
//! constraint drift by construction and no Baumgarte term (the DAE's is switched off: at a
//! consistent state Φ = Φ̇ = 0 and q̈ is the exact constrained acceleration, so q̈_I is the
//! right-hand side of the reduced equations, ref. 1 §4).
//!
//! **State.** y = (q, q̇, the DAE's bookkeeping states, the partition flags): the same layout
//! as [`Dae`] followed by one flag per coordinate (1 = independent, 0 = dependent), so that the
//! partition, a discrete state, lives in y like the stored impact velocities
//! (`contacts.rs`): the equations stay a pure function of (t, y). The dependent components of q
//! and q̇ in y are integrated too, with the exact derivatives q̇_D and q̈_D of the projected
//! state: they are the warm start of Newton (within a local error of the solution, so one or
//! two iterations suffice and Newton stays on the branch the motion is on), never the result.
//! The error norm covers q and q̇ (the integrators fix their mask once per run, while the
//! partition changes); the flags are bookkeeping.
//!
//! **Partition and repartitioning.** Independent coordinates are those *not* chosen as pivot
//! columns by Gaussian elimination with complete pivoting of the scaled Jacobian
//! Φ̃_q = W Φ_q S⁻¹ (angles measured as arc lengths L·φ and angle rows as L·Φ, L the linkage's
//! length scale, so that metres and radians compete fairly). Its pivot ratio ρ = |u_mm|/|u_11|
//! estimates 1/cond of the dependent block Φ̃_qD. One event function,
//!
//! ```text
//!     g_rep(t, y) = ρ(current dependent block) − τ ρ(best dependent block),   τ = 0.1
//! ```
//!
//! falls through zero when the current block has become ten times worse conditioned than the
//! best available one. The event is located like an impact, the state is projected, the new
//! partition written into y, and the integrator restarts there: the switch happens at one
//! located instant and no step straddles two partitions. After the switch g_rep = (1 − τ)ρ > 0,
//! so the factor 10 is also the hysteresis that keeps it from switching back and forth. Near a
//! position where Φ_q itself loses rank (a parallelogram passing its flat position) every
//! block is poor and g_rep stays positive: no repartition helps there, and none is made;
//! Newton then works from the predictor on a block whose smallest pivot shrinks with the
//! distance to the singular position, which keeps it on the branch the predictor is on.
//!
//! **Events.** Clearance joints first (index k = joint k's δ, exactly as the DAE), then the
//! repartition event (index = number of clearance joints).
//!
//! # References
//! 1. R. A. Wehage, E. J. Haug, Generalized coordinate partitioning for dimension reduction in
//!    analysis of constrained dynamic systems, *Journal of Mechanical Design* 104 (1982)
//!    247–255.
//! 2. E. J. Haug, *Computer-Aided Kinematics and Dynamics of Mechanical Systems*, vol. 1,
//!    Allyn and Bacon, 1989, §6.3 (Newton with a fixed partition, repartitioning).

pub mod lu;

use super::dae::{Dae, DaeOptions};
use super::{Crossing, EventResponse, Formulation, FormulationError, Outputs};
use crate::mechanics::constraints::{ConstraintEval, ConstraintSet, RowSource};
use crate::model::{Baumgarte, Model};
use std::cell::RefCell;

/// Repartition when the current dependent block's pivot ratio falls below this fraction of
/// the best block's (see the module documentation).
pub const REPARTITION_FACTOR: f64 = 0.1;

/// Newton stops when every scaled residual |W Φ| is below this fraction of the length scale L
/// (1e-12 L: some 5 000 times the round-off of evaluating Φ on a linkage of size L).
pub const POSITION_TOLERANCE: f64 = 1e-12;

/// Most Newton iterations per projection. From a predictor within a local error of the
/// solution Newton needs one or two; more means the step was too large (the projection fails
/// recoverably and the integrator retries with a smaller step).
pub const MAX_NEWTON: usize = 8;

/// Buffers reused by every projection.
#[derive(Debug, Clone)]
struct Work {
    sin_cos: Vec<(f64, f64)>,
    eval: ConstraintEval,
    /// Dependent block Φ_qD (m × m, row-major), then its LU factors.
    block: Vec<f64>,
    piv: Vec<usize>,
    rhs: Vec<f64>,
    /// Coordinate index of dependent column j.
    dep: Vec<usize>,
    /// Dependent column of each coordinate (usize::MAX = independent).
    col_of: Vec<usize>,
    /// Scaled full Jacobian (m × n) for the partition choice.
    full: Vec<f64>,
    cols: Vec<usize>,
    col_perm: Vec<usize>,
    /// The projected DAE state and its derivative.
    y: Vec<f64>,
    dy: Vec<f64>,
    /// Largest |Φ| (m or rad) left by the last projection.
    residual: f64,
}

/// The coordinate-partitioning formulation of a model (see the module documentation).
#[derive(Debug, Clone)]
pub struct Generalized {
    /// The DAE without Baumgarte: forces, contacts, multiplier solve and outputs.
    dae: Dae,
    constraints: ConstraintSet,
    /// Active rows (the DAE's, redundant rows at t = 0 left out).
    active: Vec<usize>,
    /// L (m): arc-length scale of angles and angle rows.
    length_scale: f64,
    /// Row weights W: L for angle rows, 1 for position rows (active rows).
    row_weight: Vec<f64>,
    /// Number of the DAE's states (q, q̇, bookkeeping).
    n_dae: usize,
    /// Largest |Φ| over the accepted step ends (m or rad).
    max_step_violation: f64,
    work: RefCell<Work>,
}

impl Generalized {
    /// Assembles the model (as the DAE does) and chooses the initial partition.
    pub fn new(model: &Model, options: &DaeOptions) -> Result<Self, FormulationError> {
        let dae_options = DaeOptions {
            baumgarte: Some(Baumgarte {
                alpha: 0.0,
                beta: 0.0,
            }),
            ..*options
        };
        let dae = Dae::new(model, &dae_options)?;
        let constraints = dae.constraints().clone();
        let active: Vec<usize> = (0..constraints.n_rows())
            .filter(|k| !dae.redundant_rows().contains(k))
            .collect();
        let length_scale = dae.length_scale();
        let row_weight = active
            .iter()
            .map(|&k| match constraints.sources()[k] {
                RowSource::Driver(_) | RowSource::PrismaticAngle(_) => length_scale,
                _ => 1.0,
            })
            .collect();
        let n = dae.n_coordinates();
        let m = active.len();
        if m > n {
            return Err(FormulationError::Unsupported {
                formulation: "generalized".into(),
                reason: format!("{m} independent constraint rows on {n} coordinates"),
            });
        }
        let n_dae = dae.n_states();
        let nb = model.bodies.len();
        Ok(Generalized {
            work: RefCell::new(Work {
                sin_cos: vec![(0.0, 1.0); nb],
                eval: ConstraintEval::with_rows(constraints.n_rows()),
                block: vec![0.0; m * m],
                piv: vec![0; m],
                rhs: vec![0.0; m],
                dep: vec![0; m],
                col_of: vec![usize::MAX; n],
                full: vec![0.0; m * n],
                cols: vec![0; m],
                col_perm: vec![0; n],
                y: vec![0.0; n_dae],
                dy: vec![0.0; n_dae],
                residual: 0.0,
            }),
            dae,
            constraints,
            active,
            length_scale,
            row_weight,
            n_dae,
            max_step_violation: 0.0,
        })
    }

    /// The underlying DAE (Baumgarte off), whose outputs and contact laws this formulation uses.
    pub fn dae(&self) -> &Dae {
        &self.dae
    }

    /// Number of coordinates (3 per body).
    pub fn n_coordinates(&self) -> usize {
        self.dae.n_coordinates()
    }

    /// Degrees of freedom: coordinates − active constraint rows.
    pub fn dof(&self) -> usize {
        self.n_coordinates() - self.active.len()
    }

    /// Index of the repartition event (after the clearance joints' δ events).
    pub fn repartition_event(&self) -> usize {
        self.dae.n_clearance_joints()
    }

    /// The independent coordinates of the partition stored in `y` (indices into q).
    pub fn independent(&self, y: &[f64]) -> Vec<usize> {
        let n = self.n_coordinates();
        (0..n).filter(|&i| y[self.n_dae + i] != 0.0).collect()
    }

    /// The DAE state (q, q̇, bookkeeping) of `y` projected onto the constraints with the
    /// partition stored in `y`. Fails where Newton does not converge.
    pub fn project(&self, t: f64, y: &[f64]) -> Result<Vec<f64>, FormulationError> {
        let mut work = self.work.borrow_mut();
        self.project_into(t, y, &mut work)?;
        Ok(work.y.clone())
    }

    /// Scaled Jacobian entry of active row i for coordinate c: W_i ∂Φ/∂q_c / S_c.
    fn column_scale(&self, c: usize) -> f64 {
        if c % 3 == 2 {
            1.0 / self.length_scale
        } else {
            1.0
        }
    }

    /// Largest scaled residual |W Φ| over the active rows (NaN-aware: NaN counts as ∞).
    fn scaled_residual(&self, work: &Work) -> (f64, usize) {
        let mut worst = (0.0_f64, 0);
        for (i, &k) in self.active.iter().enumerate() {
            let r = (self.row_weight[i] * work.eval.phi[k]).abs();
            let r = if r.is_nan() { f64::INFINITY } else { r };
            if r > worst.0 {
                worst = (r, i);
            }
        }
        worst
    }

    /// Fills `work.block` with Φ_qD (unscaled) at the last evaluation.
    fn fill_block(&self, work: &mut Work) {
        let m = self.active.len();
        work.block.fill(0.0);
        for (i, &k) in self.active.iter().enumerate() {
            let row = work.eval.rows[k];
            for (body, jac) in [(row.body_a, row.jac_a), (row.body_b, row.jac_b)] {
                let Some(b) = body else { continue };
                for (c, value) in jac.iter().enumerate() {
                    let j = work.col_of[3 * b + c];
                    if j != usize::MAX {
                        work.block[i * m + j] += value;
                    }
                }
            }
        }
    }

    /// Projects y onto the constraints into `work.y` (see the module documentation).
    fn project_into(&self, t: f64, y: &[f64], work: &mut Work) -> Result<(), FormulationError> {
        let n = self.n_coordinates();
        let m = self.active.len();
        work.y.copy_from_slice(&y[..self.n_dae]);
        // The partition from the flags.
        let mut j = 0;
        for c in 0..n {
            if y[self.n_dae + c] == 0.0 {
                if j == m {
                    return Err(self.bad_partition(m + 1));
                }
                work.dep[j] = c;
                work.col_of[c] = j;
                j += 1;
            } else {
                work.col_of[c] = usize::MAX;
            }
        }
        if j != m {
            return Err(self.bad_partition(j));
        }
        if m == 0 {
            work.residual = 0.0;
            return Ok(());
        }
        let tolerance = POSITION_TOLERANCE * self.length_scale;
        let mut iterations = 0;
        // Newton on the dependent positions, from the stored (predicted) ones.
        loop {
            self.evaluate_at_projection(t, work);
            let (residual, worst) = self.scaled_residual(work);
            self.fill_block(work);
            let factored = lu::factor(&mut work.block, m, &mut work.piv);
            if residual <= tolerance {
                if let Err(pivot) = factored {
                    return Err(self.singular(t, pivot));
                }
                break;
            }
            if iterations == MAX_NEWTON || factored.is_err() {
                return Err(FormulationError::ProjectionFailed {
                    t,
                    constraint: self
                        .constraints
                        .row_name(self.dae.model(), self.active[worst]),
                    residual: residual / self.row_weight.get(worst).copied().unwrap_or(1.0),
                    iterations,
                });
            }
            iterations += 1;
            for (i, &k) in self.active.iter().enumerate() {
                work.rhs[i] = work.eval.phi[k];
            }
            lu::solve(&work.block, m, &work.piv, &mut work.rhs);
            for (jj, &c) in work.dep.iter().enumerate() {
                work.y[c] -= work.rhs[jj];
            }
        }
        // Velocities: Φ_qD q̇_D = −(Φ_qI q̇_I + Φ_t).
        for &c in &work.dep {
            work.y[n + c] = 0.0;
        }
        for (i, &k) in self.active.iter().enumerate() {
            let v = &work.y[n..2 * n];
            work.rhs[i] = -(work.eval.rows[k].dot_velocity(v) + work.eval.phi_t[k]);
        }
        lu::solve(&work.block, m, &work.piv, &mut work.rhs);
        for (jj, &c) in work.dep.iter().enumerate() {
            work.y[n + c] = work.rhs[jj];
        }
        work.residual = self
            .active
            .iter()
            .fold(0.0_f64, |r, &k| r.max(work.eval.phi[k].abs()));
        Ok(())
    }

    /// Evaluates the constraint rows at the positions and velocities in `work.y`.
    fn evaluate_at_projection(&self, t: f64, work: &mut Work) {
        let n = self.n_coordinates();
        for (i, sc) in work.sin_cos.iter_mut().enumerate() {
            *sc = work.y[3 * i + 2].sin_cos();
        }
        let (q, rest) = work.y.split_at(n);
        self.constraints
            .evaluate_into(t, q, &rest[..n], &work.sin_cos, &mut work.eval);
    }

    fn bad_partition(&self, dependent: usize) -> FormulationError {
        FormulationError::Unsupported {
            formulation: "generalized".into(),
            reason: format!(
                "the partition in the state has {dependent} dependent coordinates, the model {} constraint rows (a state not made by this formulation)",
                self.active.len()
            ),
        }
    }

    fn singular(&self, t: f64, pivot: usize) -> FormulationError {
        FormulationError::SingularConstraints {
            t,
            constraint: self.constraints.row_name(
                self.dae.model(),
                self.active[pivot.min(self.active.len() - 1)],
            ),
        }
    }

    /// Pivot ratio of the current dependent block and of the best block, at the constraint
    /// evaluation in `work`.
    fn partition_quality(&self, work: &mut Work) -> (f64, f64) {
        let n = self.n_coordinates();
        let m = self.active.len();
        if m == 0 {
            return (1.0, 1.0);
        }
        self.fill_full(work);
        let best = lu::complete_pivoting(&mut work.full, m, n, &mut work.cols, &mut work.col_perm);
        // The current block, scaled, in the first m columns of `full` (as an m × m matrix).
        work.full[..m * m].fill(0.0);
        for (i, &k) in self.active.iter().enumerate() {
            let row = work.eval.rows[k];
            for (body, jac) in [(row.body_a, row.jac_a), (row.body_b, row.jac_b)] {
                let Some(b) = body else { continue };
                for (c, value) in jac.iter().enumerate() {
                    let j = work.col_of[3 * b + c];
                    if j != usize::MAX {
                        work.full[i * m + j] +=
                            self.row_weight[i] * value * self.column_scale(3 * b + c);
                    }
                }
            }
        }
        let current = lu::complete_pivoting(
            &mut work.full[..m * m],
            m,
            m,
            &mut work.cols,
            &mut work.col_perm,
        );
        (current.ratio, best.ratio)
    }

    /// The scaled full Jacobian W Φ_q S⁻¹ of the active rows into `work.full` (m × n).
    fn fill_full(&self, work: &mut Work) {
        let n = self.n_coordinates();
        work.full.fill(0.0);
        for (i, &k) in self.active.iter().enumerate() {
            let row = work.eval.rows[k];
            for (body, jac) in [(row.body_a, row.jac_a), (row.body_b, row.jac_b)] {
                let Some(b) = body else { continue };
                for (c, value) in jac.iter().enumerate() {
                    work.full[i * n + 3 * b + c] +=
                        self.row_weight[i] * value * self.column_scale(3 * b + c);
                }
            }
        }
    }

    /// Writes the best partition at the constraint evaluation in `work` into `flags`
    /// (1 = independent).
    fn best_partition(&self, work: &mut Work, flags: &mut [f64]) {
        let n = self.n_coordinates();
        let m = self.active.len();
        flags.fill(1.0);
        if m == 0 {
            return;
        }
        self.fill_full(work);
        lu::complete_pivoting(&mut work.full, m, n, &mut work.cols, &mut work.col_perm);
        for &c in &work.cols[..m] {
            flags[c] = 0.0;
        }
    }
}

impl Formulation for Generalized {
    /// The DAE's states (q, q̇, stored impact velocities, energy integrals) and one partition
    /// flag per coordinate.
    fn n_states(&self) -> usize {
        self.n_dae + self.n_coordinates()
    }

    fn initial_state(&self) -> Vec<f64> {
        let mut y = self.dae.initial_state();
        let n = self.n_coordinates();
        y.resize(self.n_dae + n, 0.0);
        let mut work = self.work.borrow_mut();
        work.y.copy_from_slice(&y[..self.n_dae]);
        self.evaluate_at_projection(self.dae.t0(), &mut work);
        self.best_partition(&mut work, &mut y[self.n_dae..]);
        y
    }

    fn t0(&self) -> f64 {
        self.dae.t0()
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        let mut work = self.work.borrow_mut();
        self.project_into(t, y, &mut work)?;
        let Work { y: yp, dy: dyp, .. } = &mut *work;
        self.dae.rhs(t, yp, dyp)?;
        dy[..self.n_dae].copy_from_slice(dyp);
        dy[self.n_dae..].fill(0.0);
        Ok(())
    }

    /// q and q̇ are controlled (see the module documentation); the DAE's bookkeeping states and
    /// the partition flags are not.
    fn error_controlled(&self, controlled: &mut [bool]) {
        let (dae, flags) = controlled.split_at_mut(self.n_dae);
        self.dae.error_controlled(dae);
        flags.fill(false);
    }

    fn n_events(&self) -> usize {
        self.dae.n_events() + 1
    }

    fn events(&self, t: f64, y: &[f64], g: &mut [f64]) {
        let nc = self.dae.n_events();
        let mut work = self.work.borrow_mut();
        if self.project_into(t, y, &mut work).is_err() {
            // A failed projection is reported by the integrator's own rhs call; keep the
            // event functions defined (unprojected) meanwhile.
            work.y.copy_from_slice(&y[..self.n_dae]);
            self.evaluate_at_projection(t, &mut work);
        }
        self.dae.events(t, &work.y, &mut g[..nc]);
        let (current, best) = self.partition_quality(&mut work);
        g[nc] = current - REPARTITION_FACTOR * best;
    }

    /// A clearance joint's event as in the DAE, at the projected state; the repartition event
    /// (falling g_rep) writes the best partition into y and restarts.
    fn apply_event(
        &mut self,
        t: f64,
        y: &mut [f64],
        index: usize,
        crossing: Crossing,
    ) -> EventResponse {
        let nc = self.dae.n_events();
        let n_dae = self.n_dae;
        let n = self.n_coordinates();
        let mut w = self.work.borrow_mut();
        if self.project_into(t, y, &mut w).is_ok() {
            y[..n_dae].copy_from_slice(&w.y);
        }
        if index < nc {
            drop(w);
            return self.dae.apply_event(t, &mut y[..n_dae], index, crossing);
        }
        if crossing != Crossing::Falling {
            return EventResponse::Continue;
        }
        w.y.copy_from_slice(&y[..n_dae]);
        self.evaluate_at_projection(t, &mut w);
        let mut flags = vec![0.0; n];
        self.best_partition(&mut w, &mut flags);
        if flags[..] == y[n_dae..n_dae + n] {
            return EventResponse::Continue;
        }
        y[n_dae..n_dae + n].copy_from_slice(&flags);
        EventResponse::Restart
    }

    /// Keeps the largest |Φ| left by the projection of the step ends (Newton's tolerance:
    /// the formulation has no drift to bound).
    fn accept_step(
        &mut self,
        t: f64,
        y: &[f64],
        _rtol: f64,
        _atol: f64,
    ) -> Result<(), FormulationError> {
        let mut work = self.work.borrow_mut();
        self.project_into(t, y, &mut work)?;
        let residual = work.residual;
        drop(work);
        self.max_step_violation = self.max_step_violation.max(residual);
        Ok(())
    }

    /// The DAE's grazing guard at the projected state.
    fn max_step(&self, t: f64, y: &[f64]) -> f64 {
        if self.dae.n_events() == 0 {
            return f64::INFINITY;
        }
        let mut work = self.work.borrow_mut();
        if self.project_into(t, y, &mut work).is_err() {
            return f64::INFINITY;
        }
        self.dae.max_step(t, &work.y)
    }
}

impl Outputs for Generalized {
    /// The DAE's columns ([`Dae`]'s `output_names`).
    fn output_names(&self) -> Vec<String> {
        self.dae.output_names()
    }

    /// The DAE's outputs at the projected state (reactions from the multipliers without
    /// Baumgarte terms); returns the |Φ| left by the projection.
    fn outputs_into(&self, t: f64, y: &[f64], out: &mut Vec<f64>) -> Result<f64, FormulationError> {
        let projected = self.project(t, y)?;
        self.dae.outputs_into(t, &projected, out)
    }

    fn step_constraint_violation(&self) -> f64 {
        self.max_step_violation
    }
}
