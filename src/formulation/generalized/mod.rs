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
//!     accelerations:  (Bᵀ M B) q̈_I = Bᵀ (Q − M c),   q̈_D = B_D q̈_I + c_D
//! ```
//!
//! with the velocity transformation q̇ = B q̇_I, B_I = I, B_D = −Φ_qD⁻¹ Φ_qI, and
//! c_D = Φ_qD⁻¹ γ (the Maggi / velocity-transformation form of the equations of motion, ref. 3
//! §6.5). The constraints hold to Newton's tolerance at every stage, output and event: there is
//! no constraint drift by construction and no Baumgarte term. The reduced mass matrix Bᵀ M B is
//! SPD whatever the rank of Φ_q, and B and c only use Φ_qD⁻¹, whose condition grows like 1/s at
//! a distance s from a singular position (against 1/s² for the DAE's Φ_q M⁻¹ Φ_qᵀ): along the
//! branch the motion is on, B and c stay bounded and smooth through the singular position, so
//! the step size does not collapse there. Joint reactions (outputs only) come from the DAE's
//! multiplier solve at the projected state (Baumgarte off); at a singular position they are not
//! unique, and the DAE's regularised pivots return a finite split of them (docs/formulations.md).
//!
//! **State.** y = (z, ż, the DAE's state (q, q̇, stored impact velocities, energy integrals),
//! the partition flags): z holds the f independent coordinates in the order of q, ż their
//! rates; the error norm covers z and ż only. The DAE's q and q̇ in y are bookkeeping: they are
//! integrated with the exact derivatives (q̇, q̈) of the projected state and are the warm start
//! of Newton for the dependent coordinates (within a local error of the solution, so one or two
//! iterations suffice and Newton stays on the branch the motion is on), never the result; their
//! independent entries are overwritten by z. The flags (1 = independent, 0 = dependent, one
//! per coordinate) hold the partition, a discrete state, in y like the stored impact velocities
//! (`contacts.rs`): the equations stay a pure function of (t, y). Their rates are 0 and they
//! are out of error control, and they are read as "independent" when above 1/2, so an implicit
//! solver that perturbs every unknown (IDA: Newton, predictor, interpolation) leaves the
//! partition as it is. Keeping the dependent entries
//! out of the error norm matters near a singular position, where their rates are 0/0 limits
//! computed to a relative accuracy of ε/s only.
//!
//! **Partition and repartitioning.** The first independent coordinates are those *not* chosen
//! as pivot columns by Gaussian elimination with complete pivoting of the scaled Jacobian
//! Φ̃_q = W Φ_q S⁻¹ (angles measured as arc lengths L·φ and angle rows as L·Φ, L the linkage's
//! length scale, so that metres and radians compete fairly; O(m² n), once). From then on the
//! partition is judged by the velocity transformation B it already has ([`partition`]):
//! ρ(J) = |det N_J| is the part of the tangent space of the motion that a set J of f
//! coordinates sees (N an orthonormal basis of the span of B̃ = S B S_I⁻¹), and where Φ_q has
//! full rank the ratio of ρ between two partitions is the ratio of |det Φ̃_qD| of their
//! dependent blocks. One event function,
//!
//! ```text
//!     g_rep(t, y) = ρ(current independent set) − τ ρ(best set J*),   τ = 0.1,
//! ```
//!
//! J* by complete pivoting of B̃ᵀ (f × n), costs O(n f²) and falls through zero when the best
//! available block has a ten times larger |det| than the current one (for f = 1: some coordinate
//! moves ten times faster, in scaled units, than the independent one). The event is located like
//! an impact, the state is projected, J* written into y as the new partition, and the integrator
//! restarts there: the switch happens at one located instant and no step straddles two
//! partitions. After the switch g_rep = (1 − τ)ρ(J*) > 0, so the factor 10 is also the
//! hysteresis that keeps it from switching back and forth. (Where the elimination of Φ̃_q and the
//! volumes disagree at the start, the start takes J*, so that g_rep starts positive.) Near a
//! position where Φ_q itself loses rank (a parallelogram passing its flat position) every block is
//! singular, but B̃ stays bounded along the branch and g_rep stays positive: no repartition helps
//! there, and none is made; Newton then works from the predictor on a block whose smallest pivot
//! shrinks with the distance to the singular position, which keeps it on the branch the predictor
//! is on. The dependent block is factored dense or sparse ([`block`]), the sparse pattern and
//! ordering made once per partition.
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
//! 3. J. García de Jalón, E. Bayo, *Kinematic and Dynamic Simulation of Multibody Systems: the
//!    Real-Time Challenge*, Springer, 1994, §6.5 (velocity transformations, Maggi's equations).

pub mod block;
pub mod partition;
pub mod sparse_lu;

pub use block::BlockSolver;

use super::contacts::ContactSites;
use super::dae::{Dae, DaeOptions};
use super::{
    Crossing, EventResponse, Formulation, FormulationError, Outputs, StepHooks, Tolerances,
};
use crate::linalg::dense_lu;
use crate::mechanics::AppliedForces;
use crate::mechanics::constraints::{ConstraintEval, ConstraintSet};
use crate::model::{Baumgarte, Model};
use block::DependentBlock;
use partition::{VolumeWork, Volumes};
use std::cell::RefCell;

/// Repartition when the current independent coordinates' volume ρ falls below this fraction of
/// the best set's (see the module documentation and [`partition`]).
pub const REPARTITION_FACTOR: f64 = 0.1;

/// Newton stops when every scaled residual |W Φ| is below this fraction of the length scale L
/// (1e-12 L: some 5 000 times the round-off of evaluating Φ on a linkage of size L).
pub const POSITION_TOLERANCE: f64 = 1e-12;

/// Most Newton iterations per projection. From a predictor within a local error of the
/// solution Newton needs one or two; more means the step was too large (the projection fails
/// recoverably and the integrator retries with a smaller step).
pub const MAX_NEWTON: usize = 8;

/// Whether a stored partition flag marks an independent coordinate. The flags are written as
/// exactly 1 (independent) and 0 (dependent), but an implicit solver treats every state as an
/// unknown: IDA's Newton corrections, predictor and interpolation bring a flag back as 1 ± ε or
/// ±ε (its rate is 0 and its error weight 0, so never further). The threshold halfway between
/// reads both the same as the written values; a test for exactly 0 flipped a dependent
/// coordinate to independent at the first perturbation.
fn independent_flag(flag: f64) -> bool {
    flag > 0.5
}

/// Buffers reused by every projection.
#[derive(Debug, Clone)]
struct Work {
    sin_cos: Vec<(f64, f64)>,
    eval: ConstraintEval,
    /// Dependent block Φ_qD of the partition in use and its LU factors.
    block: DependentBlock,
    rhs: Vec<f64>,
    /// Coordinate index of dependent column j.
    dep: Vec<usize>,
    /// Dependent column of each coordinate (usize::MAX = independent).
    col_of: Vec<usize>,
    /// Index among the independent coordinates of each coordinate (usize::MAX = dependent).
    indep_of: Vec<usize>,
    /// Scaled full Jacobian (m × n) for the partition choice.
    full: Vec<f64>,
    cols: Vec<usize>,
    col_perm: Vec<usize>,
    /// The projected DAE state and its derivative.
    y: Vec<f64>,
    dy: Vec<f64>,
    /// Independent coordinates.
    indep: Vec<usize>,
    /// m × (f + 1), column after column: B_D = −Φ_qD⁻¹ Φ_qI (column k for independent
    /// coordinate k), then c_D = Φ_qD⁻¹ γ.
    basis: Vec<f64>,
    /// B̃ᵀ and scratch of the partition's volumes ([`partition`]).
    volume: VolumeWork,
    /// Generalised forces Q (n).
    forces: Vec<f64>,
    /// Reduced mass matrix Bᵀ M B (f × f) and its right-hand side.
    reduced: Vec<f64>,
    reduced_piv: Vec<usize>,
    reduced_rhs: Vec<f64>,
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
    /// f: independent coordinates (degrees of freedom); the DAE's state starts at 2f.
    n_indep: usize,
    /// Diagonal of M: m, m, I per body.
    mass: Vec<f64>,
    applied: AppliedForces,
    contacts: ContactSites,
    /// Energy bookkeeping on: its rates come from the DAE's evaluation at the projected state.
    energy: bool,
    /// Largest |Φ| over the accepted step ends (m or rad).
    max_step_violation: f64,
    /// Repartitions made so far (see [`Generalized::repartitions`]).
    repartitions: usize,
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
        // Φ with the rounding of the arms, not of the coordinates: see the method's note.
        let constraints = dae.constraints().clone().with_centre_differences();
        let active = dae.active_rows().to_vec();
        let length_scale = dae.length_scale();
        let row_weight = active.iter().map(|&k| dae.row_length_weight(k)).collect();
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
                block: DependentBlock::new(m, BlockSolver::default()),
                rhs: vec![0.0; m],
                dep: vec![0; m],
                col_of: vec![usize::MAX; n],
                indep_of: vec![usize::MAX; n],
                full: vec![0.0; m * n],
                cols: vec![0; m],
                col_perm: vec![0; n],
                y: vec![0.0; n_dae],
                dy: vec![0.0; n_dae],
                indep: vec![0; n - m],
                basis: vec![0.0; m * (n - m + 1)],
                volume: VolumeWork::new(n - m, n),
                forces: vec![0.0; n],
                reduced: vec![0.0; (n - m) * (n - m)],
                reduced_piv: vec![0; n - m],
                reduced_rhs: vec![0.0; n - m],
                residual: 0.0,
            }),
            dae,
            constraints,
            active,
            length_scale,
            row_weight,
            n_dae,
            n_indep: n - m,
            mass: model
                .bodies
                .iter()
                .flat_map(|b| [b.mass, b.mass, b.inertia])
                .collect(),
            applied: AppliedForces::from_model(model),
            contacts: ContactSites::from_model(model),
            energy: options.energy,
            max_step_violation: 0.0,
            repartitions: 0,
        })
    }

    /// The same formulation with the dependent block factored as `solver` says (default
    /// [`BlockSolver::Auto`]: dense LU for small linkages, sparse from
    /// [`block::SPARSE_FROM`] dependent coordinates on). The results agree to round-off; only
    /// the cost differs.
    #[must_use]
    pub fn with_block_solver(self, solver: BlockSolver) -> Self {
        let m = self.active.len();
        self.work.borrow_mut().block = DependentBlock::new(m, solver);
        self
    }

    /// Whether the dependent block of the partition last used is factored by the sparse LU.
    pub fn uses_sparse_lu(&self) -> bool {
        self.work.borrow().block.is_sparse()
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

    /// Number of repartitions made so far: repartition events (falling g_rep) that chose a new
    /// set of independent coordinates and restarted the integrator. Kept across runs of the
    /// same value (a clone starts from the count of its original).
    pub fn repartitions(&self) -> usize {
        self.repartitions
    }

    /// Index of the repartition event (after the DAE's events: the clearance joints' δ, then
    /// their friction kinks where switched on).
    pub fn repartition_event(&self) -> usize {
        self.dae.n_events()
    }

    /// With `on`, the kinks of each clearance joint's friction law are event functions after
    /// the δ events, as in the DAE ([`Dae::friction_kink_events`], `contact/kinks.rs`), at the
    /// projected state; the repartition event follows them. A kink answers
    /// [`EventResponse::Continue`], so the driver keeps the state as it was (the projection that
    /// `apply_event` writes is discarded).
    #[must_use]
    pub fn friction_kink_events(mut self, on: bool) -> Self {
        self.dae = self.dae.friction_kink_events(on);
        self
    }

    /// The independent coordinates of the partition stored in `y` (indices into q).
    pub fn independent(&self, y: &[f64]) -> Vec<usize> {
        let n = self.n_coordinates();
        (0..n)
            .filter(|&i| independent_flag(y[self.flags_start() + i]))
            .collect()
    }

    /// Index in y of the DAE's state.
    fn dae_start(&self) -> usize {
        2 * self.n_indep
    }

    /// Index in y of the partition flags.
    fn flags_start(&self) -> usize {
        2 * self.n_indep + self.n_dae
    }

    /// z and ż in y: the entries of the DAE state `dae_state` (q, q̇, …) at the independent
    /// coordinates of the partition stored in y.
    fn write_independent(&self, dae_state: &[f64], y: &mut [f64]) {
        let (f, n, flags) = (self.n_indep, self.n_coordinates(), self.flags_start());
        let mut k = 0;
        for c in 0..n {
            if independent_flag(y[flags + c]) && k < f {
                y[k] = dae_state[c];
                y[f + k] = dae_state[n + c];
                k += 1;
            }
        }
    }

    /// Writes the DAE state in `work.y` back into y: its z, ż and the bookkeeping copy.
    fn store(&self, work: &Work, y: &mut [f64]) {
        let (f, n) = (self.n_indep, self.n_coordinates());
        for (k, &c) in work.indep.iter().enumerate() {
            y[k] = work.y[c];
            y[f + k] = work.y[n + c];
        }
        let start = self.dae_start();
        y[start..start + self.n_dae].copy_from_slice(&work.y);
    }

    /// Clearance joint `k` at the state y whose time derivative is `y_dot`: the DAE's
    /// [`Dae::contact_motion_state`] at the projected state, with q̈ from the DAE part of
    /// `y_dot` (the exact accelerations of the projected state).
    pub fn contact_motion_state(
        &self,
        k: usize,
        t: f64,
        y: &[f64],
        y_dot: &[f64],
    ) -> Result<(super::contacts::SiteState, [f64; 2], f64), FormulationError> {
        let projected = self.project(t, y)?;
        let start = self.dae_start();
        // y_dot comes from the integrator, with n_states entries like y.
        debug_assert_eq!(y_dot.len(), self.n_states());
        let dae_dot = &y_dot[start..start + self.n_dae];
        Ok(self.dae.contact_motion_state(k, &projected, dae_dot))
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

    /// Projects y onto the constraints into `work.y` (see the module documentation).
    fn project_into(&self, t: f64, y: &[f64], work: &mut Work) -> Result<(), FormulationError> {
        let n = self.n_coordinates();
        let m = self.active.len();
        let (f, start, flags) = (self.n_indep, self.dae_start(), self.flags_start());
        work.y.copy_from_slice(&y[start..start + self.n_dae]);
        // The partition from the flags.
        let mut j = 0;
        let mut k = 0;
        for c in 0..n {
            if !independent_flag(y[flags + c]) {
                if j == m {
                    return Err(self.bad_partition(m + 1));
                }
                work.dep[j] = c;
                work.col_of[c] = j;
                work.indep_of[c] = usize::MAX;
                j += 1;
            } else {
                work.col_of[c] = usize::MAX;
                work.indep_of[c] = k;
                if k < n - m {
                    work.indep[k] = c;
                }
                k += 1;
            }
        }
        if j != m {
            return Err(self.bad_partition(j));
        }
        // The independent coordinates and rates are z and ż.
        for (kk, &c) in work.indep.iter().enumerate() {
            work.y[c] = y[kk];
            work.y[n + c] = y[f + kk];
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
            if iterations == 0 {
                // The pattern only changes with the partition (a no-op otherwise).
                work.block.set_partition(
                    &work.dep,
                    &work.col_of,
                    &work.eval.rows,
                    &self.active,
                    &self.constraints,
                );
            }
            let (residual, worst) = self.scaled_residual(work);
            let factored = work.block.factor(&work.eval.rows);
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
            work.block.solve(&mut work.rhs);
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
        work.block.solve(&mut work.rhs);
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

    /// q̈ at the projected state in `work` (Maggi form, see the module documentation), with the
    /// LU factors of Φ_qD from the projection.
    fn accelerations_into(
        &self,
        t: f64,
        work: &mut Work,
        acc: &mut [f64],
    ) -> Result<(), FormulationError> {
        let n = self.n_coordinates();
        let m = self.active.len();
        let f = n - m;
        // γ at the projected velocities (the last evaluation used the predicted ones).
        self.evaluate_at_projection(t, work);
        let (q, rest) = work.y.split_at(n);
        let (v, stored) = rest.split_at(n);
        self.applied
            .evaluate_into(t, q, v, &work.sin_cos, &mut work.forces);
        if !self.contacts.is_empty() {
            self.contacts.add_forces_into(
                t,
                q,
                v,
                &work.sin_cos,
                &stored[..self.contacts.len()],
                &mut work.forces,
                false,
                |j| self.dae.model().joint(j).name.clone(),
            )?;
        }
        self.basis_into(work, f + 1);
        let (b_dep, c_dep) = work.basis.split_at(m * f);
        // Bᵀ M B and Bᵀ (Q − M c): O(m f²).
        work.reduced.fill(0.0);
        for (kk, &c) in work.indep.iter().enumerate() {
            work.reduced[kk * f + kk] = self.mass[c];
            work.reduced_rhs[kk] = work.forces[c];
        }
        for (i, &c) in work.dep.iter().enumerate() {
            let mass = self.mass[c];
            let load = work.forces[c] - mass * c_dep[i];
            for a in 0..f {
                let b_a = b_dep[a * m + i];
                work.reduced_rhs[a] += b_a * load;
                for b in 0..f {
                    work.reduced[a * f + b] += b_a * mass * b_dep[b * m + i];
                }
            }
        }
        if let Err(k) = dense_lu::factor(&mut work.reduced, f, &mut work.reduced_piv) {
            return Err(FormulationError::NonFinite {
                t,
                body: self.dae.model().bodies[work.indep[k] / 3].name.clone(),
                what: "reduced mass matrix".into(),
            });
        }
        dense_lu::solve(&work.reduced, f, &work.reduced_piv, &mut work.reduced_rhs);
        for (kk, &c) in work.indep.iter().enumerate() {
            acc[c] = work.reduced_rhs[kk];
        }
        for (i, &c) in work.dep.iter().enumerate() {
            acc[c] = c_dep[i]
                + work
                    .reduced_rhs
                    .iter()
                    .enumerate()
                    .map(|(a, z)| b_dep[a * m + i] * z)
                    .sum::<f64>();
        }
        for (i, body) in self.dae.model().bodies.iter().enumerate() {
            if !acc[3 * i..3 * i + 3].iter().all(|x| x.is_finite()) {
                return Err(FormulationError::NonFinite {
                    t,
                    body: body.name.clone(),
                    what: "acceleration".into(),
                });
            }
        }
        Ok(())
    }

    /// The first `ncols` columns of `work.basis` at the projection in `work`, with Φ_qD's
    /// factors from it: B_D's f columns (Φ_qD b = −Φ_q e_k for each independent coordinate k),
    /// then, for ncols = f + 1, c_D (Φ_qD c = γ). All columns in one pass over the factors.
    fn basis_into(&self, work: &mut Work, ncols: usize) {
        let m = self.active.len();
        let f = self.n_indep;
        let Work {
            basis,
            eval,
            indep_of,
            block,
            ..
        } = work;
        let basis = &mut basis[..m * ncols];
        basis.fill(0.0);
        for (i, &row) in self.active.iter().enumerate() {
            let r = &eval.rows[row];
            for (body, jac) in r.blocks() {
                let Some(b) = body else { continue };
                for (comp, value) in jac.iter().enumerate() {
                    let k = indep_of[3 * b + comp];
                    if k < ncols.min(f) {
                        basis[k * m + i] -= value;
                    }
                }
            }
            if ncols > f {
                basis[f * m + i] = eval.gamma[row];
            }
        }
        block.solve_columns(basis, ncols);
    }

    /// ρ of the current partition and of the best set of independent coordinates (into
    /// `work.volume.best`), from B at the projection in `work` ([`partition`]). `None` where
    /// B is not finite.
    fn volumes(&self, work: &mut Work) -> Option<Volumes> {
        let (m, f, n) = (self.active.len(), self.n_indep, self.n_coordinates());
        if f == 0 {
            return partition::volumes(&mut work.volume, 0, n);
        }
        self.basis_into(work, f);
        // B̃ = S B S_I⁻¹ (angles as arc lengths): B̃_ck = S_c B_ck / S_k.
        let scale = |c: usize| if c % 3 == 2 { self.length_scale } else { 1.0 };
        let Work {
            basis,
            volume,
            dep,
            indep,
            ..
        } = work;
        for (k, &ck) in indep.iter().enumerate() {
            let row = &mut volume.bt[k * n..k * n + n];
            row.fill(0.0);
            row[ck] = 1.0;
            let to = 1.0 / scale(ck);
            for (i, &c) in dep.iter().enumerate() {
                row[c] = scale(c) * basis[k * m + i] * to;
            }
        }
        partition::volumes(&mut work.volume, f, n)
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
    /// evaluation in `work`: two complete-pivoting eliminations, O(m² n), for the diagnosis of a
    /// stalled run only (the repartition event uses [`Self::volumes`]).
    fn partition_quality(&self, work: &mut Work) -> (f64, f64) {
        let n = self.n_coordinates();
        let m = self.active.len();
        if m == 0 {
            return (1.0, 1.0);
        }
        self.fill_full(work);
        let best =
            dense_lu::complete_pivoting(&mut work.full, m, n, &mut work.cols, &mut work.col_perm);
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
        let current = dense_lu::complete_pivoting(
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
        dense_lu::complete_pivoting(&mut work.full, m, n, &mut work.cols, &mut work.col_perm);
        for &c in &work.cols[..m] {
            flags[c] = 0.0;
        }
    }
}

impl StepHooks for Generalized {
    /// No statistics over the stages: every step end is projected.
    fn begin_step(&mut self, _t: f64, _y: &[f64]) {}

    /// Not reached: the generalised formulation has no residual form (IDA integrates it as an
    /// ODE, whose residuals are right-hand sides).
    fn residual_stages(&mut self, _min_pivot_ratio: f64) {}

    /// Keeps the largest |Φ| left by the projection of the step ends (Newton's tolerance:
    /// the formulation has no drift to bound).
    fn accept_step(
        &mut self,
        t: f64,
        y: &mut [f64],
        _tolerances: Tolerances,
    ) -> Result<EventResponse, FormulationError> {
        let mut work = self.work.borrow_mut();
        self.project_into(t, y, &mut work)?;
        let residual = work.residual;
        drop(work);
        self.max_step_violation = self.max_step_violation.max(residual);
        Ok(EventResponse::Continue)
    }
}

impl Formulation for Generalized {
    /// z and ż (f each), the DAE's states (q, q̇, stored impact velocities, energy integrals)
    /// and one partition flag per coordinate.
    fn n_states(&self) -> usize {
        self.flags_start() + self.n_coordinates()
    }

    fn initial_state(&self) -> Vec<f64> {
        let n = self.n_coordinates();
        let dae_state = self.dae.initial_state();
        let mut y = vec![0.0; self.n_states()];
        let (start, flags) = (self.dae_start(), self.flags_start());
        y[start..start + self.n_dae].copy_from_slice(&dae_state);
        let mut work = self.work.borrow_mut();
        work.y.copy_from_slice(&dae_state);
        self.evaluate_at_projection(self.dae.t0(), &mut work);
        self.best_partition(&mut work, &mut y[flags..flags + n]);
        self.write_independent(&dae_state, &mut y);
        // Greedy elimination of Φ̃_q and the volumes of B can disagree on the best set; start
        // on the side of the repartition event where no switch is due, or the first crossing
        // would never come.
        if self.project_into(self.dae.t0(), &y, &mut work).is_ok()
            && let Some(v) = self.volumes(&mut work)
            && v.current < REPARTITION_FACTOR * v.best
        {
            y[flags..flags + n].fill(0.0);
            for &c in &work.volume.best {
                y[flags + c] = 1.0;
            }
            self.write_independent(&dae_state, &mut y);
        }
        y
    }

    fn t0(&self) -> f64 {
        self.dae.t0()
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        let mut work = self.work.borrow_mut();
        self.project_into(t, y, &mut work)?;
        let (f, n) = (self.n_indep, self.n_coordinates());
        let start = self.dae_start();
        let (head, rest) = dy.split_at_mut(start);
        let (dae_dy, flags_dy) = rest.split_at_mut(self.n_dae);
        flags_dy.fill(0.0);
        if self.energy {
            // Only for the energy integrals' rates (q̇ and q̈ are overwritten below).
            let Work { y: yp, dy: dyp, .. } = &mut *work;
            self.dae.rhs(t, yp, dyp)?;
            dae_dy.copy_from_slice(dyp);
        } else {
            dae_dy[2 * n..].fill(0.0);
        }
        dae_dy[..n].copy_from_slice(&work.y[n..2 * n]);
        self.accelerations_into(t, &mut work, &mut dae_dy[n..2 * n])?;
        for (k, &c) in work.indep.iter().enumerate() {
            head[k] = dae_dy[c];
            head[f + k] = dae_dy[n + c];
        }
        Ok(())
    }

    /// z and ż are controlled; the DAE's copy of q and q̇ (Newton's warm start), its
    /// bookkeeping states and the partition flags are not.
    fn error_controlled(&self, controlled: &mut [bool]) {
        let (z, rest) = controlled.split_at_mut(self.dae_start());
        z.fill(true);
        rest.fill(false);
    }

    fn n_events(&self) -> usize {
        self.dae.n_events() + 1
    }

    /// The DAE's events at the projected state, then g_rep = ρ(I) − τ ρ(J*).
    ///
    /// Where the projection fails (the integrator's own rhs call reports it), the DAE's events
    /// are evaluated at the stored, unprojected state and g_rep takes its value just after a
    /// switch, (1 − τ): a dependent block singular to working precision is either at a position
    /// where Φ_q itself loses rank (no repartition helps there) or one that g_rep has announced
    /// already (ρ(I) falls like 1/|B̃| while B̃ grows without bound towards it).
    fn events(&self, t: f64, y: &[f64], g: &mut [f64]) {
        let nc = self.dae.n_events();
        let mut work = self.work.borrow_mut();
        let volumes = if self.project_into(t, y, &mut work).is_ok() {
            self.volumes(&mut work)
        } else {
            let start = self.dae_start();
            work.y.copy_from_slice(&y[start..start + self.n_dae]);
            self.evaluate_at_projection(t, &mut work);
            None
        };
        if nc > 0 {
            // (The DAE's contact events allocate their sines and cosines: only with contacts.)
            self.dae.events(t, &work.y, &mut g[..nc]);
        }
        g[nc] = volumes.map_or(1.0 - REPARTITION_FACTOR, |v| {
            v.current - REPARTITION_FACTOR * v.best
        });
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
        let n = self.n_coordinates();
        let (start, flags_at) = (self.dae_start(), self.flags_start());
        let mut w = self.work.borrow_mut();
        let projected = self.project_into(t, y, &mut w).is_ok();
        if projected {
            self.store(&w, y);
        }
        if index < nc {
            drop(w);
            let response =
                self.dae
                    .apply_event(t, &mut y[start..start + self.n_dae], index, crossing);
            return response;
        }
        if crossing != Crossing::Falling {
            return EventResponse::Continue;
        }
        // The best set J* of the volumes g_rep compares with; the dense complete pivoting of
        // Φ̃_q where B is not available.
        let mut flags = vec![0.0; n];
        if projected && self.volumes(&mut w).is_some() {
            for &c in &w.volume.best {
                flags[c] = 1.0;
            }
        } else {
            w.y.copy_from_slice(&y[start..start + self.n_dae]);
            self.evaluate_at_projection(t, &mut w);
            self.best_partition(&mut w, &mut flags);
        }
        let unchanged = flags
            .iter()
            .zip(&y[flags_at..flags_at + n])
            .all(|(&new, &stored)| independent_flag(new) == independent_flag(stored));
        if unchanged {
            return EventResponse::Continue;
        }
        y[flags_at..flags_at + n].copy_from_slice(&flags);
        self.repartitions += 1;
        self.write_independent(&w.y, y);
        EventResponse::Restart
    }

    /// The partition's condition (current and best pivot ratio, the independent coordinates
    /// by name), then the DAE's diagnosis at the projected state
    /// ([`super::dae::diagnosis::generalized`]).
    fn diagnose(&self, t: f64, y: &[f64]) -> Option<String> {
        let start = self.dae_start();
        let stored = y.get(start..start + self.n_dae)?;
        let mut work = self.work.borrow_mut();
        let projected = self.project_into(t, y, &mut work);
        if projected.is_err() {
            work.y.copy_from_slice(stored);
        }
        self.evaluate_at_projection(t, &mut work);
        let (current, best) = self.partition_quality(&mut work);
        let model = self.dae.model();
        let independent = self
            .independent(y)
            .iter()
            .map(|&c| {
                let body = model.bodies.get(c / 3).map_or("?", |b| b.name.as_str());
                format!("{body}.{}", ["x", "y", "phi"][c % 3])
            })
            .collect::<Vec<_>>();
        let independent = if independent.is_empty() {
            "none: the drivers fix every coordinate".to_string()
        } else {
            independent.join(", ")
        };
        let state = work.y.clone();
        drop(work);
        super::dae::diagnosis::generalized(
            &self.dae,
            t,
            projected.as_ref().map(|()| state.as_slice()),
            stored,
            Some((current, best, independent)),
        )
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
        let mut work = self.work.borrow_mut();
        self.project_into(t, y, &mut work)?;
        self.dae.outputs_into(t, &work.y, out)
    }

    fn step_constraint_violation(&self) -> f64 {
        self.max_step_violation
    }
}
