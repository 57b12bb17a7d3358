//! The constraint-based DAE in absolute coordinates, reduced to an ODE by Baumgarte's method.
//!
//! State y = (q, q̇), q = (xᵢ, yᵢ, φᵢ) for every body. Equations of motion
//!
//! ```text
//!     M q̈ + Φ_qᵀ λ = Q(q, q̇, t)
//!     Φ_q q̈ = γ − 2α Φ̇ − β² Φ
//! ```
//!
//! so that the constraint error obeys Φ̈ + 2αΦ̇ + β²Φ = 0 (ref. 1). M is diagonal, so λ follows
//! from the Schur complement S λ = b, b = Φ_q M⁻¹ Q − (γ − 2αΦ̇ − β²Φ), S = Φ_q M⁻¹ Φ_qᵀ (SPD
//! when the rows are independent; redundant rows found at assembly are left out), factored by
//! Cholesky each evaluation ([`super::schur`]: dense for a few rows, skyline over a
//! reverse Cuthill–McKee order computed once for many); then q̈ = M⁻¹ (Q − Φ_qᵀ λ).
//!
//! # Singular positions: regularised pivots
//!
//! At a distance s from a singular position (a toggle, a parallelogram's flat position) S's
//! smallest eigenvalue goes like s², and a drift ε in Φ or Φ̇ gives λ a part ε/s² along the
//! near-null direction u, a constraint force ε/s: a pole that the step-size control cannot
//! step over. So S is factored with every pivot regularised ([`Schur::factor_regularised`]),
//!
//! ```text
//!     d_p  →  d_p + μ_p³ / (d_p + μ_p)²,      μ_p = 1e-8 D_p
//! ```
//!
//! the exact factor of A = S + diag(Δ), and λ = A⁻¹ b. A healthy pivot moves by a relative
//! (μ_p/d_p)³ (below round-off), a collapsing one stays ≥ 0.89 μ_p, which bounds the force along u
//! by ~ε/√μ; smooth in q (no threshold), one division per pivot. Within ~√μ of the singular
//! position the motion is free along u and inertia carries it through on the branch it is on;
//! at a true lock (b not in the range of Φ_q: no motion can go on) the force grows like 1/μ and
//! the step size collapses there, which the stall diagnosis reports
//! ([`diagnosis`]). A drift on arrival at a crossing of two branches leaves it as a
//! deflection ~1e3 times larger, which the Baumgarte terms at their default 10 s⁻¹ do not damp
//! before the next passage: the step ends near singular positions are therefore projected onto
//! the constraints ([`projection`]), and the passages are reported (`dae/passages.rs`,
//! [`Dae::singular_passages`]; docs/formulations.md, "The DAE at singular positions", with the
//! measurements and the alternatives tried).
//!
//! Joint reactions near a singular position are finite but not unique: their sum over a loop's
//! ground joints is (Newton's law), their split is up to a self-stress that the near-null
//! direction carries, of the order of (drift)/s in the reported values.
//!
//! Sign conventions: −Φ_qᵀ λ is the constraint force. The reaction of a joint reported on its
//! second body b is −(∂Φ/∂r_b)ᵀ λ over the joint's rows; a driver's torque on body b is −λ.
//!
//! # References
//! 1. J. Baumgarte, Stabilization of constraints and integrals of motion in dynamical systems,
//!    *Computer Methods in Applied Mechanics and Engineering* 1 (1972) 1–16.
//! 2. P. E. Nikravesh, *Computer-Aided Analysis of Mechanical Systems*, 1988, §6.

use super::assembly::{Assembly, assemble};
use super::contacts::ContactSites;
use super::{
    Crossing, EventResponse, Formulation, FormulationError, Outputs, StepHooks, Tolerances,
};
use crate::mechanics::AppliedForces;
use crate::mechanics::constraints::{ConstraintEval, ConstraintSet, RowSource};
use crate::mechanics::planar::{point_acceleration, point_state};
use crate::model::{Baumgarte, Frame, JointKind, Model};
use std::cell::RefCell;

use super::schur::{Schur, SchurSolver};

mod consistency;
pub mod diagnosis;
mod jacobian;
mod passages;
pub mod projection;
pub mod residual;
mod sparse_jacobian;
use projection::PROJECTION_RATIO;

/// Options of the DAE formulation.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct DaeOptions {
    /// Baumgarte factors; `None` takes the model's `[settings.baumgarte]`.
    pub baumgarte: Option<Baumgarte>,
    /// Integrate the energy bookkeeping too: driver work, work of applied torques and forces,
    /// and energy dissipated by contacts and dampers, as three extra states, with the output
    /// columns `energy.kinetic energy.potential energy.contact_elastic energy.driver_work
    /// energy.external_work energy.dissipated energy.balance`.
    pub energy: bool,
}

impl Default for DaeOptions {
    /// Baumgarte from the model file (whose own default is α = β = 10 s⁻¹); no energy bookkeeping.
    fn default() -> Self {
        DaeOptions {
            baumgarte: None,
            energy: false,
        }
    }
}

/// Names of the energy columns, in order (see [`DaeOptions::energy`]).
pub const ENERGY_COLUMNS: [&str; 7] = [
    "energy.kinetic",
    "energy.potential",
    "energy.contact_elastic",
    "energy.driver_work",
    "energy.external_work",
    "energy.dissipated",
    "energy.balance",
];

/// Buffers reused by every evaluation.
#[derive(Debug, Clone)]
struct Work {
    sin_cos: Vec<(f64, f64)>,
    forces: Vec<f64>,
    constraints: ConstraintEval,
    /// S = Φ_q M⁻¹ Φ_qᵀ over the active rows: structure fixed at construction, values per call.
    schur: Schur,
    lambda: Vec<f64>,
    /// Rates of the energy states: driver power, external power, dissipation (W).
    energy_rates: [f64; 3],
    /// The last evaluation's (t, y) and q̈, for the grazing guard (only kept with clearance joints).
    last_t: f64,
    last_y: Vec<f64>,
    /// The bodies' (sin φ, cos φ) at `last_y`: the event functions and the grazing guard at
    /// a step end, where the FSAL stage was the last evaluation, take them from here.
    last_sin_cos: Vec<(f64, f64)>,
    last_acc: Vec<f64>,
    /// Smallest [`Schur::min_pivot_ratio`] of the right-hand sides since the start of the step
    /// ([`StepHooks::begin_step`]; stages of rejected
    /// attempts included, evaluations for
    /// output samples not): how close the step came to a singular position.
    min_pivot_ratio: f64,
    /// (t, pivot ratio) of the stages since the start of the step that came near a singular
    /// position (ratio below [`PROJECTION_RATIO`]): more samples of the approach than the step
    /// ends for [`passages::Episode`].
    stage_ratios: Vec<(f64, f64)>,
}

/// The absolute-coordinate DAE of a model.
#[derive(Debug, Clone)]
pub struct Dae {
    model: Model,
    constraints: ConstraintSet,
    /// Rows used in the dynamics (all but the redundant ones).
    active: Vec<usize>,
    /// Rows left out as combinations of earlier rows.
    redundant: Vec<usize>,
    applied: AppliedForces,
    /// Clearance joints (contact-force laws, no constraint rows).
    contacts: ContactSites,
    inv_mass: Vec<f64>,
    /// The pivot regularisation μ_k = [`PIVOT_REGULARISATION`] · D_k (D_k the translational part
    /// of S_kk) of the multiplier solve, per active row.
    shift: Vec<f64>,
    baumgarte: Baumgarte,
    /// Energy bookkeeping states are integrated.
    energy: bool,
    /// T + U + V_contact at the initial state (J), the reference of the energy balance.
    initial_energy: f64,
    assembly: Assembly,
    /// Length scale L of the linkage (m): see [`Dae::length_scale`].
    length_scale: f64,
    /// Mass-to-rotational-inertia ratio κ = max over bodies of m L²/I, at least 1: see
    /// [`roundoff_floor`].
    conditioning: f64,
    /// Largest |Φ| over the accepted step ends so far (m or rad).
    max_step_violation: f64,
    /// Times (s) at which accepted steps came within [`SINGULAR_PASSAGE_RATIO`] of a singular
    /// position, one per passage (see [`Dae::singular_passages`]).
    singular_passages: Vec<f64>,
    /// The steps of the current approach to a singular position ([`passages`]).
    episode: passages::Episode,
    /// Step ends projected onto the constraints near singular positions ([`projection`]).
    projections: usize,
    /// Which step ends of the approach are projected ([`projection::Spacing`]).
    spacing: projection::Spacing,
    work: RefCell<Work>,
    /// Buffers of the analytic Jacobian (`dae/jacobian.rs`).
    jacobian_scratch: RefCell<jacobian::JacobianScratch>,
    /// The pattern of the sparse augmented Jacobian (`dae/sparse_jacobian.rs`), built when an
    /// implicit method first asks for it.
    sparse: std::cell::OnceCell<sparse_jacobian::SparseLayout>,
}

/// Everything one evaluation yields beyond q̈: multipliers over all rows (0 for redundant ones).
#[derive(Debug, Clone)]
pub struct DaeEvaluation {
    /// q̈ (3 per body).
    pub acceleration: Vec<f64>,
    /// λ for every constraint row.
    pub lambda: Vec<f64>,
    /// Φ for every constraint row.
    pub phi: Vec<f64>,
}

impl Dae {
    /// Assembles the model (consistent positions and velocities at t = 0) and prepares the
    /// equations.
    pub fn new(model: &Model, options: &DaeOptions) -> Result<Self, FormulationError> {
        let assembly_set = ConstraintSet::from_model(model, true);
        let constraints = ConstraintSet::from_model(model, false);
        let assembly = assemble(model, &assembly_set, &constraints, 0.0)?;
        let m = constraints.n_rows();
        // The dynamic set's own redundancy at the assembled state (the assembly set has extra
        // rows for the clearance joints); a conflicting row is an error, never dropped.
        let redundant = super::assembly::redundant_rows_checked(
            model,
            &constraints,
            &assembly.q,
            &assembly.v,
            0.0,
        )?;
        let active: Vec<usize> = (0..m).filter(|k| !redundant.contains(k)).collect();
        let inv_mass: Vec<f64> = model
            .bodies
            .iter()
            .flat_map(|b| [1.0 / b.mass, 1.0 / b.mass, 1.0 / b.inertia])
            .collect();
        let nb = model.bodies.len();
        let ma = active.len();
        let scale = length_scale(model, &assembly.q);
        let conditioning = model
            .bodies
            .iter()
            .map(|b| b.mass * scale * scale / b.inertia)
            .fold(1.0_f64, f64::max);
        let schur = schur_at(&constraints, &active, &assembly, SchurSolver::Auto);
        let shift = shift_at(&constraints, &active, &assembly, &inv_mass);
        let mut dae = Dae {
            model: model.clone(),
            active,
            redundant,
            applied: AppliedForces::from_model(model),
            contacts: ContactSites::from_model(model),
            inv_mass,
            shift,
            baumgarte: options.baumgarte.unwrap_or(model.settings.baumgarte),
            energy: options.energy,
            initial_energy: 0.0,
            length_scale: scale,
            conditioning,
            max_step_violation: 0.0,
            singular_passages: Vec::new(),
            projections: 0,
            spacing: projection::Spacing::default(),
            episode: passages::Episode::default(),
            assembly,
            work: RefCell::new(Work {
                sin_cos: vec![(0.0, 1.0); nb],
                forces: vec![0.0; 3 * nb],
                constraints: ConstraintEval::with_rows(m),
                schur,
                lambda: vec![0.0; ma],
                energy_rates: [0.0; 3],
                last_t: f64::NAN,
                last_y: Vec::new(),
                last_sin_cos: Vec::new(),
                last_acc: vec![0.0; 3 * nb],
                min_pivot_ratio: 1.0,
                stage_ratios: Vec::new(),
            }),
            jacobian_scratch: RefCell::default(),
            sparse: std::cell::OnceCell::new(),
            constraints,
        };
        dae.contacts
            .check_end_stops_open(model, &dae.assembly.q, &dae.assembly.v)?;
        if dae.energy {
            let [kinetic, potential, elastic, ..] = dae.energy_columns(&dae.initial_state());
            dae.initial_energy = kinetic + potential + elastic;
        }
        Ok(dae)
    }

    /// With `on`, the kinks of each clearance joint's friction law (slip speeds ±v0, ±v1) are
    /// event functions after the δ events while that joint's contact is open, so that Radau5
    /// ends its steps at them (`contact/kinks.rs`); off (the default), the δ are the only
    /// event functions. [`crate::simulation::Simulation`] switches them on for Radau5, and for
    /// the explicit pairs where they cut their steps at events.
    #[must_use]
    pub fn friction_kink_events(mut self, on: bool) -> Self {
        self.contacts.set_kink_events(on);
        self
    }

    /// Chooses how the Schur complement is stored and factored (default
    /// [`SchurSolver::Auto`]); the same accelerations to round-off either way.
    #[must_use]
    pub fn with_schur_solver(mut self, solver: SchurSolver) -> Self {
        let schur = schur_at(&self.constraints, &self.active, &self.assembly, solver);
        self.work.get_mut().schur = schur;
        self
    }

    /// The Schur complement's storage in use (see [`Dae::with_schur_solver`]).
    pub fn schur_is_skyline(&self) -> bool {
        self.work.borrow().schur.is_skyline()
    }

    /// Entries stored for the Schur complement's factor (m² dense; the envelope for the skyline).
    pub fn schur_stored_entries(&self) -> usize {
        self.work.borrow().schur.stored_entries()
    }

    /// The model.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The assembly result (consistent initial state, rank, redundant rows, DOF).
    pub fn assembly(&self) -> &Assembly {
        &self.assembly
    }

    /// Rows of [`Dae::constraints`] left out of the dynamics as redundant.
    pub fn redundant_rows(&self) -> &[usize] {
        &self.redundant
    }

    /// The dynamic constraint rows.
    pub fn constraints(&self) -> &ConstraintSet {
        &self.constraints
    }

    /// Baumgarte factors in use.
    pub fn baumgarte(&self) -> Baumgarte {
        self.baumgarte
    }

    /// The pivot regularisation μ_k of the multiplier solve per active row (see
    /// [`PIVOT_REGULARISATION`]), for the residual form's algebraic rows.
    pub(super) fn pivot_shift(&self) -> &[f64] {
        &self.shift
    }

    /// Times (s) at which the run passed a singular position of the linkage (the constraint
    /// Jacobian losing rank: the pivot ratio, observed or fitted over the steps of the
    /// approach, below [`SINGULAR_PASSAGE_RATIO`]; `dae/passages.rs`), one per passage. The DAE goes
    /// through such positions with regularised pivots and keeps the assembly branch by
    /// projecting the step ends near them ([`projection`]); the joint reactions there are not
    /// unique (docs/formulations.md, "The DAE at singular positions").
    pub fn singular_passages(&self) -> Vec<f64> {
        let mut all = self.singular_passages.clone();
        all.extend(self.episode.passage());
        all
    }

    /// How many step ends were projected onto the constraints near singular positions so far
    /// ([`projection`]).
    pub fn projections(&self) -> usize {
        self.projections
    }

    /// Length scale L of the linkage (m): the largest distance between two of its points at
    /// the assembled position (body centres of mass and both ends of every joint), at least
    /// [`MIN_LENGTH_SCALE`]. It sets the bound on the constraint violation
    /// ([`violation_limit`]).
    pub fn length_scale(&self) -> f64 {
        self.length_scale
    }

    /// Checks |Φ| of every row at (t, y) against [`violation_limit`] with the tolerances
    /// `rtol`, `atol` the method controls (positions in m, angles in rad) and returns the
    /// largest |Φ| (mixed units, as [`Outputs::outputs_into`] reports it). Used at every
    /// accepted step end ([`StepHooks::accept_step`])
    /// and at every output sample
    /// ([`Outputs::check_constraints`]): a state between step ends, interpolated by the dense
    /// output, can be further off the joints than both ends (`linkdyn run
    /// models/double_pendulum.toml --t-end 2 --rtol 0.1 --atol 1` reported samples 2.02 m off
    /// while every step end passed). Costs one evaluation of the constraint rows.
    pub fn check_violation(
        &self,
        t: f64,
        y: &[f64],
        rtol: f64,
        atol: f64,
    ) -> Result<f64, FormulationError> {
        let mut guard = self.work.borrow_mut();
        let work = &mut *guard;
        self.constraints_at(t, y, work);
        let (limit_m, limit_rad) = self.violation_limits(rtol, atol);
        let mut max = 0.0_f64;
        let mut worst: Option<(usize, f64)> = None;
        for (k, phi) in work.constraints.phi.iter().enumerate() {
            let value = phi.abs();
            max = max.max(value);
            let angle = self
                .constraints
                .sources()
                .get(k)
                .is_some_and(|&source| is_angle_row(source));
            let limit = if angle { limit_rad } else { limit_m };
            // A NaN violation is a violation too.
            if (value.is_nan() || value > limit) && worst.is_none_or(|(_, w)| value > w) {
                worst = Some((k, value));
            }
        }
        let Some((k, value)) = worst else {
            return Ok(max);
        };
        let angle = self
            .constraints
            .sources()
            .get(k)
            .is_some_and(|&source| is_angle_row(source));
        drop(guard);
        // A violation near a lock or singular position says which rows lost independence.
        let diagnosis = diagnosis::dae(self, t, y)
            .map(|d| format!(". At t = {t:.9} s: {d}"))
            .unwrap_or_default()
            .into_boxed_str();
        Err(FormulationError::ConstraintViolation {
            t,
            diagnosis,
            constraint: self.constraints.row_name(&self.model, k).into_boxed_str(),
            value,
            limit: if angle { limit_rad } else { limit_m },
            unit: if angle {
                super::ViolationUnit::Radian
            } else {
                super::ViolationUnit::Metre
            },
            bound: if angle {
                format!(
                    "min({VIOLATION_CAP}, {VIOLATION_FACTOR}·(rtol + atol)) with the controlled tolerances rtol = {rtol:e}, atol = {atol:e}, at least the round-off floor {ROUNDOFF_FACTOR} ε κ with κ = {:.3e}",
                    self.conditioning
                )
            } else {
                format!(
                    "min({VIOLATION_CAP} L, {VIOLATION_FACTOR}·(rtol·L + atol)) with the length scale L = {:.3e} m and the controlled tolerances rtol = {rtol:e}, atol = {atol:e}, at least the round-off floor {ROUNDOFF_FACTOR} ε κ L with κ = {:.3e}",
                    self.length_scale, self.conditioning
                )
            }
            .into_boxed_str(),
        })
    }

    /// The bound of [`Dae::check_violation`] at the tolerances `rtol`, `atol` the method
    /// controls, (metres, radians): the larger of [`violation_limit`] and
    /// [`roundoff_floor`] for this linkage.
    pub fn violation_limits(&self, rtol: f64, atol: f64) -> (f64, f64) {
        let (m, rad) = violation_limit(self.length_scale, rtol, atol);
        let (floor_m, floor_rad) = roundoff_floor(self.length_scale, self.conditioning);
        (m.max(floor_m), rad.max(floor_rad))
    }

    /// The constraint rows the DAE solves for (those found redundant at assembly left out).
    pub fn active_rows(&self) -> &[usize] {
        &self.active
    }

    /// The weight that makes constraint row k's value a length, as the coordinate partitioning
    /// and the diagnosis scale it: [`Dae::length_scale`] for an angle row (rad), 1 for a
    /// position row (m).
    pub fn row_length_weight(&self, k: usize) -> f64 {
        match self.constraints.sources().get(k) {
            Some(&source) if is_angle_row(source) => self.length_scale,
            _ => 1.0,
        }
    }

    /// Number of coordinates (3 per body).
    pub fn n_coordinates(&self) -> usize {
        3 * self.model.bodies.len()
    }

    /// Core evaluation: q̈ into `acc`, λ of the active rows into the work buffer.
    fn accelerations_into(
        &self,
        t: f64,
        y: &[f64],
        acc: &mut [f64],
        work: &mut Work,
    ) -> Result<(), FormulationError> {
        let n = self.n_coordinates();
        let (q, rest) = y.split_at(n);
        let (v, stored) = rest.split_at(n);
        for (i, sc) in work.sin_cos.iter_mut().enumerate() {
            *sc = q[3 * i + 2].sin_cos();
        }
        self.applied
            .evaluate_into(t, q, v, &work.sin_cos, &mut work.forces);
        let contact_dissipation = if self.contacts.is_empty() {
            0.0
        } else {
            self.contacts.add_forces_into(
                t,
                q,
                v,
                &work.sin_cos,
                &stored[..self.contacts.len()],
                &mut work.forces,
                self.energy,
                |j| self.model.joint(j).name.clone(),
            )?
        };
        self.constraints
            .evaluate_into(t, q, v, &work.sin_cos, &mut work.constraints);

        let ce = &work.constraints;
        let Baumgarte { alpha, beta } = self.baumgarte;
        // S = Φ_q M⁻¹ Φ_qᵀ over its structural non-zeros, factored in place with regularised
        // pivots: A = S + diag(Δ) (module documentation).
        if let Err(k) =
            work.schur
                .factor_regularised(&ce.rows, &self.active, &self.inv_mass, &self.shift)
        {
            return Err(FormulationError::SingularConstraints {
                t,
                constraint: self.constraints.row_name(&self.model, self.active[k]),
            });
        }
        // The right-hand side b = Φ_q M⁻¹ Q − (γ − 2αΦ̇ − β²Φ), with W = M⁻¹ Φ_qᵀ by row
        // blocks.
        for (i, &ri) in self.active.iter().enumerate() {
            let row = &ce.rows[ri];
            let mut rhs = -(ce.gamma[ri] - 2.0 * alpha * ce.phi_dot[ri] - beta * beta * ce.phi[ri]);
            let w = &work.schur.weighted()[i];
            for (side, body) in [row.body_a, row.body_b].into_iter().enumerate() {
                if let Some(b) = body {
                    for c in 0..3 {
                        rhs += w[side][c] * work.forces[3 * b + c];
                    }
                }
            }
            work.lambda[i] = rhs;
        }
        // λ = A⁻¹ b.
        work.schur.solve(&mut work.lambda);
        // q̈ = M⁻¹ (Q − Φ_qᵀ λ).
        acc.copy_from_slice(&work.forces);
        subtract_constraint_forces(&ce.rows, &self.active, &work.lambda, acc);
        for (a, im) in acc.iter_mut().zip(&self.inv_mass) {
            *a *= im;
        }
        for (i, body) in self.model.bodies.iter().enumerate() {
            if !acc[3 * i..3 * i + 3].iter().all(|x| x.is_finite()) {
                return Err(FormulationError::NonFinite {
                    t,
                    body: body.name.clone(),
                    what: "acceleration".into(),
                });
            }
        }
        if self.energy {
            // Driver power: −λ (Φ_q q̇) over the driver rows (the work of the motor torque).
            let mut driver_power = 0.0;
            for (i, &ri) in self.active.iter().enumerate() {
                if let RowSource::Driver(_) = self.constraints.sources()[ri] {
                    driver_power -= work.lambda[i] * ce.rows[ri].dot_velocity(v);
                }
            }
            let (external, damping) = self.applied.power_split(t, q, v, &work.sin_cos);
            work.energy_rates = [driver_power, external, contact_dissipation + damping];
        }
        if !self.contacts.is_empty() {
            work.last_t = t;
            work.last_y.clear();
            work.last_y.extend_from_slice(y);
            work.last_acc.copy_from_slice(acc);
            let Work {
                last_sin_cos,
                sin_cos,
                ..
            } = &mut *work;
            last_sin_cos.clone_from(sin_cos);
        }
        Ok(())
    }

    /// The energy columns at y (requires [`DaeOptions::energy`]): kinetic, potential (gravity and
    /// springs), contact elastic, driver work, external work, dissipated, and the balance
    /// driver + external work − (ΔT + ΔU + ΔV_contact + dissipated), which is 0 for exact
    /// solutions (J).
    pub fn energy_columns(&self, y: &[f64]) -> [f64; 7] {
        let n = self.n_coordinates();
        let (q, v) = (&y[..n], &y[n..2 * n]);
        let sin_cos = sin_cos_of(q);
        let kinetic: f64 = self
            .model
            .bodies
            .iter()
            .enumerate()
            .map(|(i, b)| {
                0.5 * b.mass * (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1])
                    + 0.5 * b.inertia * v[3 * i + 2] * v[3 * i + 2]
            })
            .sum();
        let potential = self.applied.potential_energy(q, &sin_cos);
        let elastic = self.contacts.elastic_energy(q, v, &sin_cos);
        let k = 2 * n + self.contacts.len();
        let (driver, external, dissipated) = match y.get(k..k + 3) {
            Some(e) => (e[0], e[1], e[2]),
            None => (0.0, 0.0, 0.0),
        };
        let stored = kinetic + potential + elastic;
        let e0 = self.initial_energy;
        [
            kinetic,
            potential,
            elastic,
            driver,
            external,
            dissipated,
            driver + external - (stored - e0) - dissipated,
        ]
    }

    /// Number of clearance joints.
    pub fn n_clearance_joints(&self) -> usize {
        self.contacts.len()
    }

    /// The clearance joints.
    pub fn contacts(&self) -> &ContactSites {
        &self.contacts
    }

    /// Sets the worn bearing profile of revolute clearance joint `k` (model order among the
    /// clearance joints) for the runs that follow ([`ContactSites::set_wear_profile`]; the
    /// analytic Jacobians leave the profile's slope out, an approximation for the implicit
    /// methods' Newton iterations only).
    ///
    /// Errors: no revolute clearance joint `k`.
    pub fn set_wear_profile(
        &mut self,
        k: usize,
        profile: &crate::contact::wear::WearProfile,
    ) -> Result<(), FormulationError> {
        self.contacts.set_wear_profile(k, profile)
    }

    /// State of clearance joint `k` (in [`Dae::contacts`] order) at (t, y).
    pub fn contact_state(&self, k: usize, y: &[f64]) -> super::contacts::SiteState {
        let n = self.n_coordinates();
        self.contacts
            .site_state_alone(k, &y[..n], &y[n..2 * n], y[2 * n + k])
    }

    /// Clearance joint `k` at the state y whose time derivative is `y_dot` (length
    /// [`Formulation::n_states`]): its state, the relative acceleration ë of its centres
    /// (m/s²) from the accelerations q̈ in `y_dot`, and its stored impact velocity (m/s).
    pub fn contact_motion_state(
        &self,
        k: usize,
        y: &[f64],
        y_dot: &[f64],
    ) -> (super::contacts::SiteState, [f64; 2], f64) {
        let n = self.n_coordinates();
        let stored = y[2 * n + k];
        let (state, e_ddot) =
            self.contacts
                .site_motion(k, &y[..n], &y[n..2 * n], &y_dot[n..2 * n], stored);
        (state, e_ddot, stored)
    }

    /// Full evaluation at (t, y): accelerations, multipliers of every row and Φ.
    pub fn evaluate(&self, t: f64, y: &[f64]) -> Result<DaeEvaluation, FormulationError> {
        let mut work = self.work.borrow_mut();
        let mut acceleration = vec![0.0; self.n_coordinates()];
        self.accelerations_into(t, y, &mut acceleration, &mut work)?;
        let mut lambda = vec![0.0; self.constraints.n_rows()];
        for (i, &ri) in self.active.iter().enumerate() {
            lambda[ri] = work.lambda[i];
        }
        Ok(DaeEvaluation {
            acceleration,
            lambda,
            phi: work.constraints.phi.clone(),
        })
    }

    /// Reaction force (N, global) of each joint on its second body, and each driver's torque
    /// (N·m) on the second body of its joint, from the multipliers of an evaluation.
    /// Revolute clearance joints get no entry here (their force is the contact force); a
    /// prismatic-clearance joint's is the sum of its corners' contact forces on the slider.
    pub fn reactions(&self, t: f64, y: &[f64], eval: &DaeEvaluation) -> (Vec<[f64; 2]>, Vec<f64>) {
        let n = self.n_coordinates();
        let (q, v) = (&y[..n], &y[n..2 * n]);
        let sin_cos = sin_cos_of(q);
        let mut ce = ConstraintEval::with_rows(self.constraints.n_rows());
        self.constraints.evaluate_into(t, q, v, &sin_cos, &mut ce);
        let mut joint_forces = vec![[0.0; 2]; self.model.joints.len()];
        let mut driver_torques = vec![0.0; self.model.drivers.len()];
        for (k, source) in self.constraints.sources().iter().enumerate() {
            let l = eval.lambda[k];
            let jb = ce.rows[k].jac_b;
            match source {
                RowSource::JointAxis { joint, .. }
                | RowSource::PrismaticAngle(joint)
                | RowSource::PrismaticNormal(joint) => {
                    let f = &mut joint_forces[joint.0];
                    f[0] -= jb[0] * l;
                    f[1] -= jb[1] * l;
                }
                RowSource::Driver(d) => driver_torques[*d] = -jb[2] * l,
            }
        }
        // A prismatic-clearance joint's reaction on the slider: its corners' contact forces.
        let first = self.contacts.sites().len();
        for (i, corner) in self.contacts.corners().iter().enumerate() {
            let f = self.contact_state(first + i, y).forces.on_journal;
            if let Some(total) = joint_forces.get_mut(corner.joint.0) {
                total[0] += f[0];
                total[1] += f[1];
            }
        }
        (joint_forces, driver_torques)
    }
}

impl Outputs for Dae {
    /// Names of the output columns, in order: per body `B.x B.y B.phi B.vx B.vy B.omega B.ax B.ay
    /// B.alpha`, per ideal or prismatic-clearance joint `J.fx J.fy`, per driver `D.torque`, per
    /// clearance joint `J.ex J.ey J.delta J.fn J.ft`, per slider corner `J.c1.delta J.c1.fn
    /// J.c1.ft`, the energy columns if kept, and last per output point `P.x P.y P.vx P.vy P.ax P.ay`.
    fn output_names(&self) -> Vec<String> {
        let mut names = Vec::new();
        for b in &self.model.bodies {
            for c in ["x", "y", "phi", "vx", "vy", "omega", "ax", "ay", "alpha"] {
                names.push(format!("{}.{c}", b.name));
            }
        }
        for j in &self.model.joints {
            if !matches!(j.kind, JointKind::Clearance(_)) {
                names.push(format!("{}.fx", j.name));
                names.push(format!("{}.fy", j.name));
            }
        }
        for d in &self.model.drivers {
            names.push(format!("{}.torque", d.name));
        }
        for site in self.contacts.sites() {
            let j = &self.model.joint(site.joint).name;
            for c in ["ex", "ey", "delta", "fn", "ft"] {
                names.push(format!("{j}.{c}"));
            }
            if site.contact.lubrication.is_some() {
                names.push(format!("{j}.fn_film"));
            }
        }
        // Corners of prismatic-clearance joints: `J.c1.delta J.c1.fn J.c1.ft` ….
        for corner in self.contacts.corners() {
            let c = corner.name(&self.model);
            for q in ["delta", "fn", "ft"] {
                names.push(format!("{c}.{q}"));
            }
        }
        if self.energy {
            names.extend(ENERGY_COLUMNS.iter().map(|c| c.to_string()));
        }
        for o in &self.model.outputs {
            for c in ["x", "y", "vx", "vy", "ax", "ay"] {
                names.push(format!("{}.{c}", o.name));
            }
        }
        names
    }

    /// Output values at (t, y) in the order of [`Outputs::output_names`]; also returns the largest
    /// |Φ| over the rows.
    fn outputs_into(&self, t: f64, y: &[f64], out: &mut Vec<f64>) -> Result<f64, FormulationError> {
        let eval = self.evaluate(t, y)?;
        let n = self.n_coordinates();
        out.clear();
        for i in 0..self.model.bodies.len() {
            out.extend_from_slice(&y[3 * i..3 * i + 3]);
            out.extend_from_slice(&y[n + 3 * i..n + 3 * i + 3]);
            out.extend_from_slice(&eval.acceleration[3 * i..3 * i + 3]);
        }
        let (joint_forces, driver_torques) = self.reactions(t, y, &eval);
        for (j, f) in self.model.joints.iter().zip(&joint_forces) {
            if !matches!(j.kind, JointKind::Clearance(_)) {
                out.extend_from_slice(f);
            }
        }
        out.extend_from_slice(&driver_torques);
        for k in 0..self.contacts.len() {
            let s = self.contact_state(k, y);
            if k < self.contacts.sites().len() {
                out.extend_from_slice(&s.kinematics.e);
            }
            out.extend_from_slice(&[
                s.kinematics.delta,
                s.total_normal_force(),
                s.total_tangential_force(),
            ]);
            // Sites after the revolute joints are corners, which carry no film.
            let lubricated = self.contacts.sites().get(k);
            if lubricated.is_some_and(|site| site.contact.lubrication.is_some()) {
                out.push(s.film.normal_force);
            }
        }
        if self.energy {
            out.extend_from_slice(&self.energy_columns(y));
        }
        // Output points ([[outputs]]): position, velocity and acceleration of a body point.
        for o in &self.model.outputs {
            let Frame::Body(id) = o.at.frame else {
                continue;
            };
            let i = 3 * id.0;
            let sin_cos = [y[i + 2].sin_cos()];
            let local_q = [y[i], y[i + 1], y[i + 2]];
            let local_v = [y[n + i], y[n + i + 1], y[n + i + 2]];
            let local = Frame::Body(crate::model::BodyId(0));
            let p = point_state(local, o.at.local, &local_q, &local_v, &sin_cos);
            let acc = [
                eval.acceleration[i],
                eval.acceleration[i + 1],
                eval.acceleration[i + 2],
            ];
            let a = point_acceleration(&p, acc);
            out.extend_from_slice(&[
                p.position[0],
                p.position[1],
                p.velocity[0],
                p.velocity[1],
                a[0],
                a[1],
            ]);
        }
        Ok(eval.phi.iter().fold(0.0_f64, |m, p| m.max(p.abs())))
    }

    fn step_constraint_violation(&self) -> f64 {
        self.max_step_violation
    }

    /// [`Dae::check_violation`] at the sample.
    fn check_constraints(
        &self,
        t: f64,
        y: &[f64],
        tolerances: Tolerances,
    ) -> Result<(), FormulationError> {
        self.check_violation(t, y, tolerances.rtol, tolerances.atol)
            .map(|_| ())
    }

    fn singular_passages(&self) -> Vec<f64> {
        Dae::singular_passages(self)
    }
}

/// The Schur complement of the active rows, its structure read from the rows at the assembled
/// state (which bodies a row touches does not change with q).
fn schur_at(
    set: &ConstraintSet,
    active: &[usize],
    assembly: &Assembly,
    solver: SchurSolver,
) -> Schur {
    let mut eval = ConstraintEval::with_rows(set.n_rows());
    let sin_cos = sin_cos_of(&assembly.q);
    set.evaluate_into(0.0, &assembly.q, &assembly.v, &sin_cos, &mut eval);
    Schur::new(&eval.rows, active, solver)
}

/// The pivot regularisation of the multiplier solve, μ_k = [`PIVOT_REGULARISATION`] · D_k with
/// D_k the translational part of S_kk ([`super::schur::translational_diagonal`]): a scale in
/// the row's units that does not change as the bodies turn. (S_kk itself, or the pivots at the
/// assembled state, vary with the orientation by m·arm²/I: for a body of almost no rotational
/// inertia, 2.5e8 in `tests/pendulum_pivot_reaction.rs`, which would let μ reach a relative 1e-2
/// of a pivot elsewhere on the motion.)
fn shift_at(
    set: &ConstraintSet,
    active: &[usize],
    assembly: &Assembly,
    inv_mass: &[f64],
) -> Vec<f64> {
    let mut eval = ConstraintEval::with_rows(set.n_rows());
    let sin_cos = sin_cos_of(&assembly.q);
    set.evaluate_into(0.0, &assembly.q, &assembly.v, &sin_cos, &mut eval);
    super::schur::translational_diagonal(&eval.rows, active, inv_mass)
        .into_iter()
        .map(|d| PIVOT_REGULARISATION * d)
        .collect()
}

/// Relative regularisation of the pivots of the multiplier solve (module documentation): a
/// pivot that collapses at a singular position stays at least 1e-8 of its row's diagonal, and
/// the motion is left free along the near-null direction within ~√μ = 1e-4 (relative) of the
/// singular position, where inertia carries it through on its branch.
///
/// Why this size, measured on models/nfourbar_chain.toml (N parallelogram loops, 20 s, 20 flat
/// positions; tip against the exact pendulum, DOP853; 2026-11-27):
///
/// | μ | 2 loops | 10 loops | 40 loops | 80 loops |
/// |---|---|---|---|---|
/// | 1e-10, rtol 1e-8 | 1.4e-6 m | 3.5e-5 m | stall at 0.72 s | — |
/// | 1e-10, rtol 1e-10 | — | — | stall at 0.72 s | — |
/// | 1e-8, rtol 1e-8 | 1.4e-6 m | 1.4e-6 m | 2.2e-6 m (0.30 s) | 5.6e-6 m |
/// | 1e-8, rtol 1e-10 | 8.4e-8 m | 8.0e-8 m | 2.9e-7 m | 3.1e-6 m |
/// | 1e-6, rtol 1e-10 | — | 1.7e-5 m | 1.2e-5 m | — |
///
/// (1e-6 was measured with the earlier shift μ²/(d + μ); the 1e-8 rows with the shift
/// μ³/(d + μ)² of [`Schur::factor_regularised`], which leaves the regular models' arithmetic
/// bit for bit as it was at 1e-10: the shift μ²/(d + μ) at 1e-8 changed farahan2016 by
/// rounding, enough to move two rounding-sensitive tests.)
///
/// With 1e-10 the chains of 20 loops and more stalled ("no progress", steps of 1e-8 s) at the
/// first flat position at every tolerance: the exact multipliers along the near-null
/// directions of a chain grow like 1/s (unlike a single parallelogram's), the regularisation
/// takes that force away within a region a few microseconds wide, and the step size had to
/// resolve the jump. A wider region (1e-8) lets the steps stride over it; the force it leaves
/// out is orthogonal to the branch's tangent, so what it costs is the error of the next step
/// end's projection, not a drift of the motion; wider still (1e-6) that starts to show. Still
/// small enough that a healthy pivot d moves by a relative (μD/d)² ≤ 1e-12 for d ≳ 1e-2 D (the
/// regular models: farahan2016 6.1e-2 D, (μD/d)² = 3e-14). The earlier measurement that 1e-8
/// "costs 1e-7 rad per passage" on the chain of three was made before the step ends near
/// singular positions were projected.
pub const PIVOT_REGULARISATION: f64 = 1e-8;

/// An approach whose smallest pivot ratio ([`Schur::min_pivot_ratio`]: the squared sine of the
/// angle between a constraint row and the span of the others), observed at a stage or fitted
/// over the step ends (`dae/passages.rs`), falls below this passed a singular position for
/// [`Dae::singular_passages`]: within ~7e-3 (relative) of one, where the ratio falls like s².
/// The shipped models stay well above it (smallest ratio over two turns or 3 s, measured
/// 2026-11-25: 4.1e-4 quick_return, 7.6e-3 watt_sixbar, ≥ 2e-2 the others). Why not lower:
/// where the steps stride over a passage (DOP853, models/nfourbar_chain.toml, 2 loops, rtol
/// 1e-8) the parabola through the samples nearest the minimum (r ≈ 1e-4 there) has its vertex
/// at up to 1.4e-5, not 0 (r is sin²-like, not exactly parabolic, that far out); with 1e-6,
/// 6 of the 20 passages went uncounted (measured 2026-11-27).
pub const SINGULAR_PASSAGE_RATIO: f64 = 5e-5;

/// f −= Φ_qᵀ x over the active rows.
fn subtract_constraint_forces(
    rows: &[crate::mechanics::constraints::ConstraintRow],
    active: &[usize],
    x: &[f64],
    f: &mut [f64],
) {
    for (&ri, &l) in active.iter().zip(x) {
        let row = &rows[ri];
        if let Some(a) = row.body_a {
            for c in 0..3 {
                f[3 * a + c] -= row.jac_a[c] * l;
            }
        }
        if let Some(b) = row.body_b {
            for c in 0..3 {
                f[3 * b + c] -= row.jac_b[c] * l;
            }
        }
    }
}

/// Smallest length scale (m) used for the violation bound, for a linkage whose points all
/// coincide (a body pinned at its own centre of mass): 1 mm, below any shipped link.
pub const MIN_LENGTH_SCALE: f64 = 1e-3;

/// Multiple of the tolerance-scaled error `rtol·L + atol` that the violation may reach (see
/// [`violation_limit`]).
pub const VIOLATION_FACTOR: f64 = 100.0;

/// Largest violation bound as a fraction of the linkage's length scale L (metres) or in
/// radians: beyond a tenth of the linkage (5.7 ° of angle) the joints are visibly apart and no
/// tolerance makes a result meaningful.
pub const VIOLATION_CAP: f64 = 0.1;

/// Bound on the constraint violation |Φ| of a reported state (every accepted step end and
/// every output sample): metres for position rows, radians for angle rows (driver and
/// prismatic-angle rows),
///
/// ```text
///     |Φ|_max = min(0.1 L, 100 (rtol L + atol))      (m)
///     |Φ|_max = min(0.1,   100 (rtol + atol))        (rad)
/// ```
///
/// with L the length scale of the linkage ([`Dae::length_scale`]) and `rtol`, `atol` the
/// tolerances the method controls ([`SolverOptions::controlled_tolerances`]: Radau5 controls
/// 0.1·rtol^(2/3), Hairer's transformation, not the rtol asked for). Why these numbers: an
/// integration to `rtol`, `atol` puts a local error of about `rtol·L + atol` on the positions
/// each step, which Baumgarte's term (ref. 1) pulls back within a few 1/β; a hundred times
/// that leaves room for the accumulation over those steps. Measured on every shipped model,
/// every method, rtol from 1e-3 to 1e-12 with atol = rtol and rtol/100 (2 turns;
/// `cargo run --release --example violation_survey`, docs/numerics.md, "The
/// constraint-violation bound"): the largest max |Φ| is 2.0 (rtol·L + atol), a factor of 49
/// below the bound, and no tolerance-independent floor is needed down to rtol 1e-12 except the
/// round-off of ill-conditioned linkages ([`roundoff_floor`], applied by
/// [`Dae::violation_limits`]). The cap 0.1 L applies at tolerances so loose that the bound
/// would pass it.
///
/// [`SolverOptions::controlled_tolerances`]: crate::solve::SolverOptions::controlled_tolerances
pub fn violation_limit(length_scale: f64, rtol: f64, atol: f64) -> (f64, f64) {
    let l = length_scale;
    let metres = (VIOLATION_FACTOR * (rtol * l + atol)).min(VIOLATION_CAP * l);
    let radians = (VIOLATION_FACTOR * (rtol + atol)).min(VIOLATION_CAP);
    (metres, radians)
}

/// Multiple of ε κ L below which no tolerance can hold the violation (see [`roundoff_floor`]).
pub const ROUNDOFF_FACTOR: f64 = 100.0;

/// The round-off floor of the violation bound, (metres, radians) = (100 ε κ L, 100 ε κ), with
/// κ = max over bodies of m L²/I (at least 1) and L the length scale. The constraint solve's
/// Schur complement Φ_q M⁻¹ Φ_qᵀ has a condition number of the order of κ — a nearly point-like
/// body rotates with almost no inertia — and loses that many ulps in the multipliers, which
/// Baumgarte's term turns into a drift of the order of ε κ L whatever the tolerance. Measured on
/// `models/pendulum.toml` with I = 1e-9 kg·m² (κ = 2.5e8, ε κ L = 2.8e-8 m), released at 170 °
/// (`tests/pendulum_pivot_reaction.rs`): max |Φ| = 1.6e-8 m at rtol 1e-8 and 5.6e-9 m at rtol
/// 1e-10, beyond 100 (rtol L + atol) = 5.1e-9 m there; the floor 2.8e-6 m leaves a factor 175.
/// For a uniform rod (κ = 12 at L = its length) the floor is 2.6e-13 L, below every tolerance
/// bound.
pub fn roundoff_floor(length_scale: f64, conditioning: f64) -> (f64, f64) {
    let radians = ROUNDOFF_FACTOR * f64::EPSILON * conditioning.max(1.0);
    (radians * length_scale, radians)
}

/// Whether a constraint row is an angle (rad) rather than a position (m).
fn is_angle_row(source: RowSource) -> bool {
    matches!(source, RowSource::Driver(_) | RowSource::PrismaticAngle(_))
}

/// The length scale of [`Dae::length_scale`] at the assembled coordinates `q`.
fn length_scale(model: &Model, q: &[f64]) -> f64 {
    let sin_cos = sin_cos_of(q);
    let zero = vec![0.0; q.len()];
    let mut points: Vec<[f64; 2]> = (0..q.len() / 3).map(|i| [q[3 * i], q[3 * i + 1]]).collect();
    for j in &model.joints {
        for end in [&j.a, &j.b] {
            points.push(point_state(end.frame, end.local, q, &zero, &sin_cos).position);
        }
    }
    // The largest pairwise distance, from the convex hull in O(p log p) (O(p²) over all pairs
    // took 5 ms at 401 bodies), the same value to the last bit.
    let diameter = super::assembly::diameter::diameter(&points);
    // A NaN distance (never from an assembled model) falls back to the floor.
    diameter.max(MIN_LENGTH_SCALE)
}

/// (sin φ, cos φ) of every body.
pub(super) fn sin_cos_of(q: &[f64]) -> Vec<(f64, f64)> {
    (0..q.len() / 3).map(|i| q[3 * i + 2].sin_cos()).collect()
}

impl Work {
    /// Whether the kept evaluation (`last_y`, its q̈ and sines) is the one at (t, y).
    fn holds_evaluation_at(&self, t: f64, y: &[f64]) -> bool {
        self.last_t == t && self.last_y.as_slice() == y
    }
}

impl Dae {
    /// `use_them` with the bodies' (sin φ, cos φ) at (t, y): the last evaluation's where it was
    /// at (t, y) (a step end, after the FSAL stage), else computed.
    fn with_sin_cos<R>(&self, t: f64, y: &[f64], use_them: impl FnOnce(&[(f64, f64)]) -> R) -> R {
        let n = self.n_coordinates();
        {
            let work = self.work.borrow();
            if work.holds_evaluation_at(t, y) {
                return use_them(&work.last_sin_cos);
            }
        }
        use_them(&sin_cos_of(&y[..n]))
    }
}

impl StepHooks for Dae {
    /// The stages of the step start counting towards [`Dae::singular_passages`] and the
    /// projection near singular positions.
    fn begin_step(&mut self, _t: f64, _y: &[f64]) {
        let work = self.work.get_mut();
        work.min_pivot_ratio = 1.0;
        work.stage_ratios.clear();
    }

    /// The residual form's evaluations in an attempt (IDA's Newton iterates) are the stages of
    /// the step: their smallest pivot ratio counts as [`Formulation::rhs`]'s do.
    fn residual_stages(&mut self, min_pivot_ratio: f64) {
        let work = self.work.get_mut();
        work.min_pivot_ratio = work.min_pivot_ratio.min(min_pivot_ratio);
    }

    /// Near a singular position (a stage of the step with a pivot ratio below
    /// [`PROJECTION_RATIO`]) projects the step end onto the constraints and asks for a restart
    /// ([`projection`]). Then checks |Φ| of every row at the step end against
    /// [`violation_limit`] (positions in m, angles in rad) and keeps the largest |Φ| seen
    /// ([`Outputs::step_constraint_violation`]). Costs one evaluation of the constraint rows per
    /// step, a fraction of one RHS call.
    fn accept_step(
        &mut self,
        t: f64,
        y: &mut [f64],
        tolerances: Tolerances,
    ) -> Result<EventResponse, FormulationError> {
        let stage_min = self.work.get_mut().min_pivot_ratio;
        let mut response = EventResponse::Continue;
        if stage_min < PROJECTION_RATIO {
            // Spaced projections for every method ([`projection::Spacing`]).
            let mut spacing = self.spacing;
            spacing.saw(stage_min);
            let (r_end, projected) =
                self.project_state(t, y, &mut self.work.borrow_mut(), |r| spacing.wanted(r))?;
            spacing.ended(r_end, projected);
            self.spacing = spacing;
            let stages = std::mem::take(&mut self.work.get_mut().stage_ratios);
            self.episode.add(t, r_end, stage_min, &stages);
            self.work.get_mut().stage_ratios = stages;
            if projected {
                self.projections += 1;
                response = EventResponse::Restart;
            }
        } else if !self.episode.is_empty() {
            self.singular_passages.extend(self.episode.finish());
            self.spacing = projection::Spacing::default();
        }
        let max = self.check_violation(t, y, tolerances.rtol, tolerances.atol)?;
        self.max_step_violation = self.max_step_violation.max(max);
        Ok(response)
    }
}

impl Formulation for Dae {
    /// q, q̇ (3 per body each), then the stored impact velocity of each clearance joint.
    /// With energy bookkeeping, three more: driver work, external work, dissipated energy.
    fn n_states(&self) -> usize {
        2 * self.n_coordinates() + self.contacts.len() + if self.energy { 3 } else { 0 }
    }

    fn initial_state(&self) -> Vec<f64> {
        let mut y = self.assembly.q.clone();
        y.extend_from_slice(&self.assembly.v);
        // No impact recorded yet (an initial contact uses its current δ̇ as impact velocity);
        // the energy integrals start at 0.
        y.resize(self.n_states(), 0.0);
        y
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        let n = self.n_coordinates();
        let mut work = self.work.borrow_mut();
        let (dq, rest) = dy.split_at_mut(n);
        let (dv, dstored) = rest.split_at_mut(n);
        dq.copy_from_slice(&y[n..2 * n]);
        dstored.fill(0.0);
        self.accelerations_into(t, y, dv, &mut work)?;
        // Only the integrator's own calls count towards how near a step came to a singular
        // position: evaluations for output samples must not change the run (projections).
        let ratio = work.schur.min_pivot_ratio();
        work.min_pivot_ratio = work.min_pivot_ratio.min(ratio);
        if ratio < PROJECTION_RATIO {
            work.stage_ratios.push((t, ratio));
        }
        if self.energy {
            let nc = self.contacts.len();
            dstored[nc..nc + 3].copy_from_slice(&work.energy_rates);
        }
        Ok(())
    }

    /// q' = q̇, copied in [`Formulation::rhs`].
    fn second_order_positions(&self) -> usize {
        self.n_coordinates()
    }

    /// Only q and q̇ are error-controlled: the stored impact velocities (constant between
    /// events) and the energy integrals (which feed back into nothing) are bookkeeping, so
    /// `energy` on or off gives the same steps and the same trajectory.
    fn error_controlled(&self, controlled: &mut [bool]) {
        let bookkeeping = controlled.iter_mut().skip(2 * self.n_coordinates());
        for c in bookkeeping {
            *c = false;
        }
    }

    /// Every body's φ (the third coordinate of each body).
    fn angular_states(&self, angular: &mut [bool]) {
        for body in angular[..self.n_coordinates()].chunks_mut(3) {
            body[2] = true;
        }
    }

    /// Events 0..n_c: the penetration δ of each clearance joint (m); after them, with
    /// [`Dae::friction_kink_events`], four per joint whose friction law has kinks: v_t ∓ v0,
    /// v_t ∓ v1 (m/s) while its contact is open ([`ContactSites::events_into`]).
    fn n_events(&self) -> usize {
        self.contacts.n_events()
    }

    fn events(&self, t: f64, y: &[f64], g: &mut [f64]) {
        let n = self.n_coordinates();
        let stored = &y[2 * n..2 * n + self.contacts.len()];
        self.with_sin_cos(t, y, |sin_cos| {
            self.contacts
                .events_into(&y[..n], &y[n..2 * n], sin_cos, stored, g);
        });
    }

    /// Rising δ (impact): store δ̇⁽⁻⁾ = δ̇ at the located instant for the whole contact.
    /// Falling δ (separation): clear it. Either way the force law changed: restart. A friction
    /// kink changes nothing: continue.
    fn apply_event(
        &mut self,
        _t: f64,
        y: &mut [f64],
        index: usize,
        crossing: Crossing,
    ) -> EventResponse {
        let n = self.n_coordinates();
        if index >= self.contacts.len() {
            return EventResponse::Continue;
        }
        y[2 * n + index] = match crossing {
            Crossing::Rising => self.contact_state(index, y).kinematics.delta_dot.max(0.0),
            Crossing::Falling => 0.0,
        };
        EventResponse::Restart
    }

    /// Analytic: see `dae/jacobian.rs` (no RHS call).
    fn jacobian(
        &self,
        t: f64,
        y: &[f64],
        _f_y: &[f64],
        out: &mut [f64],
        _work: &mut [f64],
    ) -> Result<usize, FormulationError> {
        self.analytic_jacobian(t, y, out)?;
        Ok(0)
    }

    /// In augmented form with q̈ and λ as unknowns: see `dae/sparse_jacobian.rs`.
    fn sparse_jacobian(&self) -> Option<&dyn super::sparse_jacobian::SparseJacobian> {
        Some(self)
    }

    /// Near-dependent constraint rows and clearance joints at their contact boundary
    /// ([`diagnosis::dae`]).
    fn diagnose(&self, t: f64, y: &[f64]) -> Option<String> {
        diagnosis::dae(self, t, y)
    }

    /// Φ = 0 and Φ̇ = 0 over the active rows (`dae/consistency.rs`).
    fn constrained_state(&self) -> Option<&dyn super::ConstrainedState> {
        Some(self)
    }

    /// With λ as algebraic unknowns ([`residual`]).
    fn residual_form(&self) -> Option<Box<dyn super::residual::ResidualForm>> {
        Some(Box::new(residual::DaeResidual::new(self)))
    }

    /// The grazing guard of the free clearance joints (∞ without clearance joints).
    fn max_step(&self, t: f64, y: &[f64]) -> f64 {
        if self.contacts.is_empty() {
            return f64::INFINITY;
        }
        let n = self.n_coordinates();
        let (q, v) = (&y[..n], &y[n..2 * n]);
        if self.with_sin_cos(t, y, |sin_cos| self.contacts.all_in_contact(q, v, sin_cos)) {
            return f64::INFINITY; // no free joint to guard: q̈ is not needed
        }
        let mut work = self.work.borrow_mut();
        // The integrators evaluate f at the step's end (FSAL), so q̈ is usually at hand.
        if !work.holds_evaluation_at(t, y) {
            let mut acc = vec![0.0; n];
            if self.accelerations_into(t, y, &mut acc, &mut work).is_err() {
                // The failing evaluation is reported by the integrator's own rhs call.
                return f64::INFINITY;
            }
        }
        // The evaluation at (t, y), cached or just made, kept its sines beside q̈.
        self.contacts
            .max_step(q, v, &work.last_acc, &work.last_sin_cos)
    }
}
