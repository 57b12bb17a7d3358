//! The absolute-coordinate DAE in residual form F(t, Y, Ẏ) = 0, with the Lagrange multipliers
//! as algebraic unknowns: the equations SUNDIALS IDA integrates (`solve::ida`).
//!
//! Unknowns Y = (q, v, s, λ): coordinates q and velocities v (3 per body), the stored impact
//! velocity s of every clearance joint, then λ of the active constraint rows (redundant rows
//! found at assembly are left out, as in [`Dae`]). Residual
//!
//! ```text
//!     F_q = q̇ − v                                   (m/s, rad/s)
//!     F_v = M v̇ + Φ_qᵀ λ − Q(t, q, v, s)             (N, N·m)
//!     F_s = ṡ                                         (impact velocities are constant between events)
//!     F_λ = Φ_q v̇ − (γ − 2α Φ̇ − β² Φ) − Δ λ         (m/s², rad/s²)
//! ```
//!
//! with Δ = diag(Δ_k) the shifts of [`Dae`]'s regularised pivots at q
//! ([`Schur::factor_regularised`], [`Schur::regularisation`]): eliminating v̇ gives
//! (S + Δ) λ = b, the DAE's own multiplier solve, so the two forms have the same solution.
//!
//! Q holds gravity, the force elements and the contact forces of the clearance joints (which
//! enter as applied forces, exactly as in [`Dae`]). The three energy integrals e of
//! [`DaeOptions::energy`](super::DaeOptions::energy) are **quadratures**, not unknowns of F
//! ([`ResidualForm::n_quadratures`]):
//!
//! ```text
//!     ė = (P_driver, P_external, D)(t, q, v, s)      (W)
//! ```
//!
//! evaluated by [`Dae`] itself at (t, q, v, s), with its own multipliers λ(q, v) (the driver
//! power is −Σ_drivers λ_i (Φ_q v)_i): the rates of the explicit methods, so IDA's integrals
//! are as accurate as its trajectory. (IDA's own λ would not do: it satisfies the first block
//! row with the BDF derivative v̇ of the step, whose error is that of v divided by h, and the
//! driver work came out 1e-3 off DOP853's, converging to nothing as rtol shrank.)
//!
//! so IDA's Newton iteration, error test and norms are those of a run without them, and the
//! body states are the same to the last bit (`tests/ida_energy.rs`). The stored impact
//! velocities s stay unknowns (the contact forces read them) but with error weight 0, out of
//! the error and Newton tests (their rows, ṡ = 0, keep s at the value the event stored).
//!
//! # Which index form, and why
//! **Index 1 at acceleration level with Baumgarte's terms** (ref. 1), the last row above. Its
//! solution is the very trajectory of [`Dae`] (same equations, same α, β, so the two methods can
//! be compared at the tolerance level and IDA finds the same impacts), the consistent initial
//! values are what the assembly and one evaluation of [`Dae`] already give, and the iteration
//! matrix [[c M, Φ_qᵀ], [c Φ_q, 0]] is regular for any step size (index 1: BDF converges in the
//! usual way, λ is excluded from the error test without loss). The stabilised index-2 form of
//! Gear, Gupta and Leimkuhler (GGL, ref. 2) would hold Φ = 0 and Φ̇ = 0 to the Newton tolerance
//! instead of letting Baumgarte pull the drift back, but needs a second set of multipliers
//! (N grows by m), its algebraic variables must be excluded from the error test, and its
//! trajectory differs from [`Dae`]'s by the Baumgarte drift — so every comparison with the
//! explicit methods would carry that difference. On the clearance models the drift stays ten
//! times below its bound (`tests/constraint_violation_bound.rs`), so GGL buys nothing here.
//!
//! At a singular position of the linkage the plain iteration matrix [[c M, Φ_qᵀ], [c Φ_q, 0]]
//! is singular; with −Δ in the λ block its Schur complement is −(S + Δ) (up to the factor
//! (c + 2α)/c on S), regular as the DAE's. Δ_k ≈ μ_k²/d_k is below round-off of S_kk at a
//! healthy pivot (the regular models' equations are unchanged) and ≈ μ_k where a pivot d_k
//! collapses. Each residual factors S for it (≈ 9 % more time per IDA residual on
//! farahan2016), and records the smallest pivot ratio it saw
//! ([`ResidualForm::take_min_pivot_ratio`]), which IDA hands to the DAE
//! ([`StepHooks::residual_stages`](crate::formulation::StepHooks::residual_stages)) so that its
//! projection near singular positions acts
//! on IDA runs too (docs/formulations.md, "The DAE at singular positions").
//!
//! # Jacobian
//! J = ∂F/∂Y + c ∂F/∂Ẏ is written densely ([`ResidualForm::jacobian`]). ∂F_λ/∂λ = −Δ with Δ
//! held fixed, as the DAE's own Jacobian does (its q-derivative is below 1e-12 except within
//! ~1e-4 of a singular position). Analytic: the
//! identity and mass blocks, Φ_q and Φ_qᵀ, the Baumgarte terms 2α Φ_q and β² Φ_q, and the
//! curvature terms of revolute joints, ∂(Φ_qᵀ λ)/∂φ, ∂(Φ_q v̇)/∂φ, ∂γ/∂(φ, φ̇) and ∂Φ̇/∂φ, with
//! u = A(φ) s the rotated arm of a joint point and d u/dφ = perp(u). Driver rows are linear (no
//! curvature). **By finite differences**, locally: the curvature of prismatic rows (forward,
//! over the coordinates of their two bodies) and the generalised forces Q (central, over the
//! columns of the bodies they act on: the two bodies of every clearance joint and of every
//! force element) — contact forces are piecewise (δ > 0), with a friction ramp, and their
//! analytic derivatives would be long for little gain: each column costs two evaluations of the
//! forces, not of the residual. The energy integrals have no rows (quadratures, above).
//!
//! **Sparse** ([`ResidualForm::sparse_pattern`], [`ResidualForm::sparse_jacobian`]): each
//! constraint row touches at most two bodies and each force element or contact two, so J has
//! 3 × 3 blocks in the pattern of the linkage's graph plus the λ rows and columns. The same
//! code writes the same entries either densely or into the values over that pattern (built
//! once, from the bodies of each row, contact site, corner and force element), so the two are
//! equal bit for bit (`tests/ida_residual_form.rs`); an entry outside the pattern is an error,
//! never dropped. IDA factors the sparse one with faer on large models (`solve::ida`). The
//! differenced forces still visit every coordinate row per column (O(n) each, zero outside the
//! element's bodies): cheap while few bodies carry contacts or force elements.
//!
//! # References
//! 1. J. Baumgarte, Stabilization of constraints and integrals of motion in dynamical systems,
//!    *Computer Methods in Applied Mechanics and Engineering* 1 (1972) 1–16.
//! 2. C. W. Gear, B. Leimkuhler, G. K. Gupta, Automatic integration of Euler–Lagrange equations
//!    with constraints, *Journal of Computational and Applied Mathematics* 12–13 (1985) 77–90.
//! 3. K. E. Brenan, S. L. Campbell, L. R. Petzold, *Numerical Solution of Initial-Value Problems
//!    in Differential-Algebraic Equations*, SIAM, 1996, Ch. 5 (index and BDF).

use super::Dae;
use crate::formulation::contacts::ContactSites;
use crate::formulation::jacobian::increment;
use crate::formulation::residual::ResidualForm;
use crate::formulation::schur::{Schur, SchurSolver};
use crate::formulation::sparse_jacobian::{Scatter, SparsePattern};
use crate::formulation::{Formulation, FormulationError};
use crate::mechanics::AppliedForces;
use crate::mechanics::constraints::{ConstraintEval, ConstraintSet, RowSource};
use crate::mechanics::planar::{perp, point_state};
use crate::model::{Anchor, Baumgarte, ForceElement, Frame, Model};
use std::cell::{OnceCell, RefCell};

/// The residual form of a [`Dae`] (see the module documentation).
#[derive(Debug, Clone)]
pub struct DaeResidual {
    model: Model,
    constraints: ConstraintSet,
    /// Rows used in the dynamics (all but the redundant ones), ascending.
    active: Vec<usize>,
    /// Per active row: how its curvature terms are computed.
    kinds: Vec<RowKind>,
    applied: AppliedForces,
    contacts: ContactSites,
    mass: Vec<f64>,
    /// M⁻¹ (diagonal, 3 per body), for the Schur complement S = Φ_q M⁻¹ Φ_qᵀ.
    inv_mass: Vec<f64>,
    /// The DAE's pivot regularisation μ_k per active row ([`Dae::pivot_shift`]).
    shift: Vec<f64>,
    baumgarte: Baumgarte,
    energy: bool,
    /// Bodies whose coordinates Q depends on: the finite-difference columns.
    force_bodies: Vec<usize>,
    /// The (at most two) bodies of each active row, which do not change with q.
    row_bodies: Vec<[Option<usize>; 2]>,
    /// The sparse pattern of J, built on the first [`ResidualForm::sparse_jacobian`].
    pattern: OnceCell<SparsePattern>,
    /// With `--energy`: the DAE, for the rates of the energy integrals.
    dae: Option<Dae>,
    work: RefCell<Work>,
}

/// How the curvature terms of one active row are obtained.
#[derive(Debug, Clone, Copy)]
enum RowKind {
    /// Component `axis` of P_b − P_a for a revolute joint: analytic.
    Revolute {
        a: Frame,
        sa: [f64; 2],
        b: Frame,
        sb: [f64; 2],
        axis: usize,
    },
    /// A driver: linear in φ, no curvature.
    Linear,
    /// A prismatic row: forward differences.
    Differenced,
}

/// Scratch reused by every evaluation.
#[derive(Debug, Clone)]
struct Work {
    sin_cos: Vec<(f64, f64)>,
    forces: Vec<f64>,
    forces_pert: Vec<f64>,
    ce: ConstraintEval,
    ce_pert: ConstraintEval,
    q_pert: Vec<f64>,
    v_pert: Vec<f64>,
    s_pert: Vec<f64>,
    sin_cos_pert: Vec<(f64, f64)>,
    /// The DAE's state and its derivative, for the energy rates.
    y_dae: Vec<f64>,
    dy_dae: Vec<f64>,
    /// S = Φ_q M⁻¹ Φ_qᵀ of the active rows, factored with the DAE's regularised pivots at
    /// every residual (for Δ) and for the consistent λ.
    schur: Schur,
    /// Smallest pivot ratio of the residuals since the last
    /// [`ResidualForm::take_min_pivot_ratio`].
    min_pivot_ratio: f64,
}

impl DaeResidual {
    /// The residual form of `dae`: same model, constraint rows (without the redundant ones),
    /// Baumgarte factors, contacts and energy bookkeeping.
    pub fn new(dae: &Dae) -> Self {
        let model = dae.model().clone();
        let constraints = dae.constraints().clone();
        let redundant = dae.redundant_rows();
        let active: Vec<usize> = (0..constraints.n_rows())
            .filter(|k| !redundant.contains(k))
            .collect();
        let kinds = active
            .iter()
            .map(|&r| match constraints.sources()[r] {
                RowSource::JointAxis { joint, axis } => {
                    let j = model.joint(joint);
                    RowKind::Revolute {
                        a: j.a.frame,
                        sa: j.a.local,
                        b: j.b.frame,
                        sb: j.b.local,
                        axis,
                    }
                }
                RowSource::Driver(_) => RowKind::Linear,
                RowSource::PrismaticAngle(_) | RowSource::PrismaticNormal(_) => {
                    RowKind::Differenced
                }
            })
            .collect();
        let nb = model.bodies.len();
        let nc = 3 * nb;
        let energy = Formulation::n_states(dae) == 2 * nc + dae.n_clearance_joints() + 3;
        let contacts = dae.contacts().clone();
        let force_bodies = force_bodies(&model, &contacts);
        let m = constraints.n_rows();
        let mass: Vec<f64> = model
            .bodies
            .iter()
            .flat_map(|b| [b.mass, b.mass, b.inertia])
            .collect();
        // The structure of S from the rows at the initial state (which bodies a row touches
        // does not change with q), as the DAE's own right-hand side builds it.
        let (schur, row_bodies) = {
            let y0 = dae.initial_state();
            let (q0, v0) = (&y0[..nc], &y0[nc..2 * nc]);
            let mut sin_cos = vec![(0.0, 1.0); nb];
            sin_cos_into(q0, &mut sin_cos);
            let mut eval = ConstraintEval::with_rows(m);
            constraints.evaluate_into(dae.t0(), q0, v0, &sin_cos, &mut eval);
            let row_bodies = active
                .iter()
                .map(|&r| [eval.rows[r].body_a, eval.rows[r].body_b])
                .collect();
            (
                Schur::new(&eval.rows, &active, SchurSolver::Auto),
                row_bodies,
            )
        };
        DaeResidual {
            inv_mass: mass.iter().map(|m| 1.0 / m).collect(),
            shift: dae.pivot_shift().to_vec(),
            mass,
            applied: AppliedForces::from_model(&model),
            baumgarte: dae.baumgarte(),
            work: RefCell::new(Work {
                sin_cos: vec![(0.0, 1.0); nb],
                forces: vec![0.0; nc],
                forces_pert: vec![0.0; nc],
                ce: ConstraintEval::with_rows(m),
                ce_pert: ConstraintEval::with_rows(m),
                q_pert: vec![0.0; nc],
                v_pert: vec![0.0; nc],
                s_pert: vec![0.0; contacts.len()],
                sin_cos_pert: vec![(0.0, 1.0); nb],
                y_dae: vec![0.0; Formulation::n_states(dae)],
                dy_dae: vec![0.0; Formulation::n_states(dae)],
                schur,
                min_pivot_ratio: 1.0,
            }),
            dae: energy.then(|| dae.clone()),
            model,
            constraints,
            active,
            kinds,
            contacts,
            energy,
            force_bodies,
            row_bodies,
            pattern: OnceCell::new(),
        }
    }

    fn n_coordinates(&self) -> usize {
        3 * self.model.bodies.len()
    }

    /// Index of the first energy state in the formulation's state, and of λ in Y.
    fn energy_index(&self) -> usize {
        2 * self.n_coordinates() + self.contacts.len()
    }

    /// Q(t, q, v, s) into `out`. Fails where a penetration is too deep (recoverable) or a
    /// force is not finite.
    fn forces_into(
        &self,
        t: f64,
        q: &[f64],
        v: &[f64],
        s: &[f64],
        sin_cos: &[(f64, f64)],
        out: &mut [f64],
    ) -> Result<(), FormulationError> {
        self.applied.evaluate_into(t, q, v, sin_cos, out);
        if !self.contacts.is_empty() {
            self.contacts
                .add_forces_into(t, q, v, sin_cos, s, out, false, |j| {
                    self.model.joint(j).name.clone()
                })?;
        }
        if let Some(i) = out.iter().position(|x| !x.is_finite()) {
            return Err(FormulationError::NonFinite {
                t,
                body: self.model.bodies[i / 3].name.clone(),
                what: "force".into(),
            });
        }
        Ok(())
    }

    /// Factors A = S + diag(Δ) at the rows of `ce` with the DAE's regularised pivots
    /// ([`Schur::factor_regularised`]); Δ is then `schur.regularisation()`.
    fn factor(
        &self,
        t: f64,
        ce: &ConstraintEval,
        schur: &mut Schur,
    ) -> Result<(), FormulationError> {
        schur
            .factor_regularised(&ce.rows, &self.active, &self.inv_mass, &self.shift)
            .map_err(|k| FormulationError::SingularConstraints {
                t,
                constraint: self.constraints.row_name(&self.model, self.active[k]),
            })
    }

    /// The constraint part of F_λ for active row i, Φ_q v̇ − γ + 2α Φ̇ + β² Φ, at `ce`.
    fn constraint_row(&self, ce: &ConstraintEval, r: usize, acc: &[f64]) -> f64 {
        let Baumgarte { alpha, beta } = self.baumgarte;
        ce.rows[r].dot_velocity(acc) - ce.gamma[r]
            + 2.0 * alpha * ce.phi_dot[r]
            + beta * beta * ce.phi[r]
    }
}

/// Bodies that Q depends on, ascending.
fn force_bodies(model: &Model, contacts: &ContactSites) -> Vec<usize> {
    let nb = model.bodies.len();
    let mut touched = vec![false; nb];
    for corner in contacts.corners() {
        for b in corner.bodies() {
            touched[b] = true;
        }
    }
    let mut mark = |a: &Anchor| {
        if let Frame::Body(id) = a.frame {
            touched[id.0] = true;
        }
    };
    for site in contacts.sites() {
        mark(&site.bearing);
        mark(&site.journal);
    }

    for e in &model.forces {
        match e {
            ForceElement::SpringDamper { a, b, .. } => {
                mark(a);
                mark(b);
            }
            // The moment arm of a point force turns with its body.
            ForceElement::PointForce { at, .. } => mark(at),
            ForceElement::Torque { .. } => {}
            // An expression of time and state may read any body's coordinates.
            ForceElement::TorqueLaw { .. }
            | ForceElement::ForceLaw { .. }
            | ForceElement::Motor { .. } => return (0..nb).collect(),
        }
    }
    (0..nb).filter(|&b| touched[b]).collect()
}

/// (sin φ, cos φ) of every body into `out`.
fn sin_cos_into(q: &[f64], out: &mut [(f64, f64)]) {
    for (i, sc) in out.iter_mut().enumerate() {
        *sc = q[3 * i + 2].sin_cos();
    }
}

/// The coordinates (3 per body) of `bodies`.
fn coordinates_of(bodies: impl IntoIterator<Item = usize>) -> Vec<usize> {
    bodies
        .into_iter()
        .flat_map(|b| [3 * b, 3 * b + 1, 3 * b + 2])
        .collect()
}

fn body_of(frame: Frame) -> Option<usize> {
    match frame {
        Frame::Ground => None,
        Frame::Body(id) => Some(id.0),
    }
}

impl ResidualForm for DaeResidual {
    fn n_states(&self) -> usize {
        self.energy_index() + if self.energy { 3 } else { 0 }
    }

    fn n_unknowns(&self) -> usize {
        self.energy_index() + self.active.len()
    }

    /// The energy integrals, with `--energy`.
    fn n_quadratures(&self) -> usize {
        if self.energy { 3 } else { 0 }
    }

    /// (P_driver, P_external, D) at (t, q, v, s) (W), by the DAE's own right-hand side (see
    /// the module documentation).
    fn quadrature_rhs(
        &self,
        t: f64,
        yy: &[f64],
        _yp: &[f64],
        out: &mut [f64],
    ) -> Result<(), FormulationError> {
        let Some(dae) = &self.dae else {
            return Ok(());
        };
        let ke = self.energy_index();
        let mut work = self.work.borrow_mut();
        let Work { y_dae, dy_dae, .. } = &mut *work;
        y_dae[..ke].copy_from_slice(&yy[..ke]);
        y_dae[ke..].fill(0.0);
        dae.rhs(t, y_dae, dy_dae)?;
        out[..3].copy_from_slice(&dy_dae[ke..ke + 3]);
        Ok(())
    }

    /// Of the regularised factors of [`ResidualForm::residual`].
    fn take_min_pivot_ratio(&self) -> f64 {
        std::mem::replace(&mut self.work.borrow_mut().min_pivot_ratio, 1.0)
    }

    /// Everything but λ is differential.
    fn differential(&self, out: &mut [bool]) {
        let ns = self.energy_index();
        for (i, d) in out.iter_mut().enumerate() {
            *d = i < ns;
        }
    }

    /// λ of [`Dae`]'s own multiplier solve, (S + Δ) λ = Φ_q M⁻¹ Q − (γ − 2αΦ̇ − β²Φ) with the
    /// regularised pivots: with the q̈ of [`Dae`] (`dy`, from its right-hand side) both block
    /// rows of F then vanish, near a singular position too. Solved the same way: [`Schur`],
    /// structure found once at [`DaeResidual::new`],
    /// dense Cholesky for a few rows and the skyline for chains of many loops, instead of a
    /// dense m × m normal matrix (O(m³) per restart).
    fn consistent_values(
        &self,
        t: f64,
        y: &[f64],
        dy: &[f64],
        yy: &mut [f64],
        yp: &mut [f64],
    ) -> Result<(), FormulationError> {
        let n = self.energy_index();
        let nc = self.n_coordinates();
        yy[..n].copy_from_slice(&y[..n]);
        yp[..n].copy_from_slice(&dy[..n]);
        yp[n..].fill(0.0);
        let Baumgarte { alpha, beta } = self.baumgarte;
        let mut work = self.work.borrow_mut();
        let Work {
            sin_cos,
            forces,
            ce,
            schur,
            ..
        } = &mut *work;
        let (q, v, s) = (&y[..nc], &y[nc..2 * nc], &y[2 * nc..self.energy_index()]);
        sin_cos_into(q, sin_cos);
        self.forces_into(t, q, v, s, sin_cos, forces)?;
        self.constraints.evaluate_into(t, q, v, sin_cos, ce);
        self.factor(t, ce, schur)?;
        // b = Φ_q M⁻¹ Q − (γ − 2αΦ̇ − β²Φ) by row blocks, with M⁻¹ Φ_qᵀ as `factor` left it.
        let lambda = &mut yy[n..];
        for (i, &ri) in self.active.iter().enumerate() {
            let row = &ce.rows[ri];
            let w = &schur.weighted()[i];
            let mut rhs = -(ce.gamma[ri] - 2.0 * alpha * ce.phi_dot[ri] - beta * beta * ce.phi[ri]);
            for (side, body) in [row.body_a, row.body_b].into_iter().enumerate() {
                if let Some(b) = body {
                    for c in 0..3 {
                        rhs += w[side][c] * forces[3 * b + c];
                    }
                }
            }
            lambda[i] = rhs;
        }
        schur.solve(lambda);
        Ok(())
    }

    fn residual(
        &self,
        t: f64,
        yy: &[f64],
        yp: &[f64],
        res: &mut [f64],
    ) -> Result<(), FormulationError> {
        let nc = self.n_coordinates();
        let n = self.energy_index();
        let ke = n;
        let (q, v, s) = (&yy[..nc], &yy[nc..2 * nc], &yy[2 * nc..ke]);
        let lambda = &yy[n..];
        let (dq, acc) = (&yp[..nc], &yp[nc..2 * nc]);
        let mut work = self.work.borrow_mut();
        let Work {
            sin_cos,
            forces,
            ce,
            schur,
            min_pivot_ratio,
            ..
        } = &mut *work;
        sin_cos_into(q, sin_cos);
        self.forces_into(t, q, v, s, sin_cos, forces)?;
        self.constraints.evaluate_into(t, q, v, sin_cos, ce);
        // Δ of the DAE's regularised pivots at this q, and how near a singular position it is.
        self.factor(t, ce, schur)?;
        *min_pivot_ratio = min_pivot_ratio.min(schur.min_pivot_ratio());
        let delta = schur.regularisation();
        for k in 0..nc {
            res[k] = dq[k] - v[k];
            res[nc + k] = self.mass[k] * acc[k] - forces[k];
        }
        for (i, &r) in self.active.iter().enumerate() {
            let row = &ce.rows[r];
            let l = lambda[i];
            for (body, jac) in [(row.body_a, &row.jac_a), (row.body_b, &row.jac_b)] {
                if let Some(b) = body {
                    for c in 0..3 {
                        res[nc + 3 * b + c] += jac[c] * l;
                    }
                }
            }
            res[n + i] = self.constraint_row(ce, r, acc) - delta[i] * l;
        }
        res[2 * nc..ke].copy_from_slice(&yp[2 * nc..ke]);
        Ok(())
    }

    fn jacobian(
        &self,
        t: f64,
        yy: &[f64],
        yp: &[f64],
        _res: &[f64],
        c: f64,
        out: &mut [f64],
    ) -> Result<usize, FormulationError> {
        out.fill(0.0);
        let nn = self.n_unknowns();
        self.iteration_matrix(t, yy, yp, c, &mut Dense { out, nn })
    }

    fn sparse_pattern(&self) -> Option<SparsePattern> {
        Some(self.sparse_layout().clone())
    }

    fn sparse_jacobian(
        &self,
        t: f64,
        yy: &[f64],
        yp: &[f64],
        c: f64,
        values: &mut [f64],
    ) -> Result<usize, FormulationError> {
        let pattern = self.sparse_layout();
        if values.len() != pattern.nnz() {
            return Err(FormulationError::Unsupported {
                formulation: "DAE (residual form)".into(),
                reason: format!(
                    "sparse iteration matrix with {} values for a pattern of {}",
                    values.len(),
                    pattern.nnz()
                ),
            });
        }
        let mut scatter = Scatter::new(pattern, values);
        let calls = self.iteration_matrix(t, yy, yp, c, &mut scatter)?;
        if scatter.missed() > 0 {
            // The pattern misses an entry the dense matrix has: a bug, never silently dropped.
            return Err(FormulationError::Unsupported {
                formulation: "DAE (residual form)".into(),
                reason: format!(
                    "{} non-zero entries of the iteration matrix outside its sparse pattern",
                    scatter.missed()
                ),
            });
        }
        Ok(calls)
    }
}

/// Where [`DaeResidual::iteration_matrix`] puts its entries: the dense column-major N × N matrix
/// of [`ResidualForm::jacobian`] or the values over the sparse pattern.
trait Entries {
    fn add(&mut self, row: usize, col: usize, value: f64);
}

/// A dense column-major matrix of dimension `nn`, zero before the first entry.
struct Dense<'a> {
    out: &'a mut [f64],
    nn: usize,
}

impl Entries for Dense<'_> {
    #[inline]
    fn add(&mut self, row: usize, col: usize, value: f64) {
        self.out[col * self.nn + row] += value;
    }
}

impl Entries for Scatter<'_> {
    #[inline]
    fn add(&mut self, row: usize, col: usize, value: f64) {
        Scatter::add(self, row, col, value);
    }
}

impl DaeResidual {
    /// J = ∂F/∂Y + c ∂F/∂Ẏ at (t, Y, Ẏ) into `out` (which starts at zero): the analytic blocks,
    /// the differenced curvature of prismatic rows and the differenced forces (module
    /// documentation).
    fn iteration_matrix<E: Entries>(
        &self,
        t: f64,
        yy: &[f64],
        yp: &[f64],
        c: f64,
        out: &mut E,
    ) -> Result<usize, FormulationError> {
        let nc = self.n_coordinates();
        let n = self.energy_index();
        let Baumgarte { alpha, beta } = self.baumgarte;
        let (q, v) = (&yy[..nc], &yy[nc..2 * nc]);
        let lambda = &yy[n..];
        let acc = &yp[nc..2 * nc];
        let mut work = self.work.borrow_mut();
        let w = &mut *work;
        sin_cos_into(q, &mut w.sin_cos);
        self.constraints
            .evaluate_into(t, q, v, &w.sin_cos, &mut w.ce);
        // ∂F_λ/∂λ = −diag(Δ), Δ held fixed (as in the DAE's own Jacobian, `dae/jacobian.rs`).
        self.factor(t, &w.ce, &mut w.schur)?;
        for (i, d) in w.schur.regularisation().iter().enumerate() {
            out.add(n + i, n + i, -d);
        }

        // F_q = q̇ − v; F_v = M v̇ + …; F_s = ṡ
        for k in 0..nc {
            out.add(k, k, c);
            out.add(k, nc + k, -1.0);
            out.add(nc + k, nc + k, c * self.mass[k]);
        }
        for k in 2 * nc..n {
            out.add(k, k, c);
        }

        for (i, &r) in self.active.iter().enumerate() {
            let row = w.ce.rows[r];
            let li = n + i;
            for (body, jac) in [(row.body_a, row.jac_a), (row.body_b, row.jac_b)] {
                let Some(b) = body else { continue };
                for comp in 0..3 {
                    let col = 3 * b + comp;
                    // ∂F_v/∂λ = Φ_qᵀ.
                    out.add(nc + col, li, jac[comp]);
                    // ∂F_λ/∂v̇ = Φ_q, ∂(2αΦ̇)/∂v = 2α Φ_q, ∂(β²Φ)/∂q = β² Φ_q.
                    out.add(li, nc + col, (c + 2.0 * alpha) * jac[comp]);
                    out.add(li, col, beta * beta * jac[comp]);
                }
            }
            match self.kinds[i] {
                RowKind::Linear => {}
                RowKind::Revolute { a, sa, b, sb, axis } => {
                    // Φ_i = (P_b − P_a)_axis; for a point with arm u on a body with angle φ:
                    // ∂Φ_i/∂φ = ±perp(u)_axis, ∂²Φ_i/∂φ² = ∓u_axis, γ_i ∋ ±u_axis φ̇².
                    for (frame, local, sign) in [(a, sa, -1.0), (b, sb, 1.0)] {
                        let Some(body) = body_of(frame) else { continue };
                        let p = point_state(frame, local, q, v, &w.sin_cos);
                        let (u, pu, omega) = (p.arm[axis], perp(p.arm)[axis], p.omega);
                        let phi_col = 3 * body + 2;
                        // ∂(λ_i ∂Φ_i/∂φ)/∂φ.
                        out.add(nc + phi_col, phi_col, sign * (-u) * lambda[i]);
                        // ∂/∂φ of Φ_q v̇ − γ + 2α Φ̇.
                        let d_phi = sign
                            * (-u * acc[phi_col] - pu * omega * omega - 2.0 * alpha * u * omega);
                        out.add(li, phi_col, d_phi);
                        // ∂/∂φ̇ of −γ (Φ̇'s part 2α Φ_q is above).
                        out.add(li, nc + phi_col, sign * (-2.0 * u * omega));
                    }
                }
                RowKind::Differenced => self.difference_row(t, i, r, yy, yp, w, out),
            }
        }

        // ∂Q/∂(q, v, s) by central differences over the force bodies.
        let calls = self.difference_forces(t, yy, w, out)?;
        Ok(calls)
    }

    /// The pattern of J (built once): the diagonal, F_q's −I on v, and for each active row its
    /// bodies' coordinates and velocities in the λ row, the multiplier in their F_v rows and the
    /// curvature ∂(Φ_qᵀ λ)/∂q among them; for each contact site, corner and force element, its
    /// bodies' F_v rows against their coordinates and velocities (and the stored impact
    /// velocity of the site or corner): the groups whose forces the differenced columns move.
    fn sparse_layout(&self) -> &SparsePattern {
        self.pattern.get_or_init(|| {
            let nc = self.n_coordinates();
            let n = self.energy_index();
            let dim = self.n_unknowns();
            let mut entries: Vec<(usize, usize)> = (0..dim).map(|i| (i, i)).collect();
            entries.extend((0..nc).map(|k| (k, nc + k)));
            for (i, bodies) in self.row_bodies.iter().enumerate() {
                let li = n + i;
                let cols = coordinates_of(bodies.iter().flatten().copied());
                for &c in &cols {
                    entries.extend([(nc + c, li), (li, nc + c), (li, c)]);
                    entries.extend(cols.iter().map(|&p| (nc + c, p)));
                }
            }
            let mut couple = |cols: &[usize], stored: Option<usize>| {
                for &c in cols {
                    for &p in cols {
                        entries.extend([(nc + c, p), (nc + c, nc + p)]);
                    }
                    entries.extend(stored.map(|col| (nc + c, col)));
                }
            };
            for (k, site) in self.contacts.sites().iter().enumerate() {
                let bodies = [site.journal.frame, site.bearing.frame]
                    .into_iter()
                    .filter_map(body_of);
                couple(&coordinates_of(bodies), Some(2 * nc + k));
            }
            let first = self.contacts.sites().len();
            for (i, corner) in self.contacts.corners().iter().enumerate() {
                couple(&coordinates_of(corner.bodies()), Some(2 * nc + first + i));
            }
            for e in 0..self.applied.n_elements() {
                couple(&coordinates_of(self.applied.element_bodies(e)), None);
            }
            SparsePattern::from_entries(dim, entries)
        })
    }

    /// Curvature terms of active row i (constraint row r) by forward differences over the
    /// coordinates and velocities of its bodies: ∂(Φ_q v̇ − γ + 2αΦ̇ + β²Φ)/∂(q, v) and
    /// ∂(λ_i Φ_q,iᵀ)/∂q, minus the analytic first-order parts already written.
    #[allow(clippy::too_many_arguments)]
    fn difference_row<E: Entries>(
        &self,
        t: f64,
        i: usize,
        r: usize,
        yy: &[f64],
        yp: &[f64],
        w: &mut Work,
        out: &mut E,
    ) {
        let nc = self.n_coordinates();
        let n = self.energy_index();
        let li = n + i;
        let Baumgarte { alpha, beta } = self.baumgarte;
        let (q, v) = (&yy[..nc], &yy[nc..2 * nc]);
        let acc = &yp[nc..2 * nc];
        let l = yy[n + i];
        let row = w.ce.rows[r];
        let base = self.constraint_row(&w.ce, r, acc);
        let bodies: Vec<usize> = [row.body_a, row.body_b].into_iter().flatten().collect();
        for &b in &bodies {
            for comp in 0..3 {
                let col = 3 * b + comp;
                for velocity in [false, true] {
                    w.q_pert.copy_from_slice(q);
                    w.v_pert.copy_from_slice(v);
                    let x = if velocity { v[col] } else { q[col] };
                    let d = (x + increment(x)) - x;
                    if velocity {
                        w.v_pert[col] = x + d;
                    } else {
                        w.q_pert[col] = x + d;
                    }
                    w.sin_cos_pert.copy_from_slice(&w.sin_cos);
                    if !velocity && comp == 2 {
                        w.sin_cos_pert[b] = w.q_pert[col].sin_cos();
                    }
                    self.constraints.evaluate_into(
                        t,
                        &w.q_pert,
                        &w.v_pert,
                        &w.sin_cos_pert,
                        &mut w.ce_pert,
                    );
                    let first_order = if velocity {
                        2.0 * alpha * jac_entry(&row, b, comp)
                    } else {
                        beta * beta * jac_entry(&row, b, comp)
                    };
                    let value = self.constraint_row(&w.ce_pert, r, acc);
                    let col_y = if velocity { nc + col } else { col };
                    out.add(li, col_y, (value - base) / d - first_order);
                    if !velocity {
                        // ∂(λ Φ_q,iᵀ)/∂q_col onto the F_v rows of the row's bodies.
                        let pert = w.ce_pert.rows[r];
                        for &b2 in &bodies {
                            for c2 in 0..3 {
                                let dj = jac_entry(&pert, b2, c2) - jac_entry(&row, b2, c2);
                                out.add(nc + 3 * b2 + c2, col, l * dj / d);
                            }
                        }
                    }
                }
            }
        }
    }

    /// Columns q, v, s of −∂Q/∂(·) on the F_v rows, by central differences ([`force_step`]) over [`DaeResidual::force_bodies`] (and every stored
    /// impact velocity). Returns 0: these are force evaluations, not right-hand-side calls.
    fn difference_forces<E: Entries>(
        &self,
        t: f64,
        yy: &[f64],
        w: &mut Work,
        out: &mut E,
    ) -> Result<usize, FormulationError> {
        let nc = self.n_coordinates();
        let ke = self.energy_index();
        let (q, v, s) = (&yy[..nc], &yy[nc..2 * nc], &yy[2 * nc..ke]);
        let mut columns: Vec<usize> = Vec::new();
        for &b in &self.force_bodies {
            for comp in 0..3 {
                columns.push(3 * b + comp);
                columns.push(nc + 3 * b + comp);
            }
        }
        columns.extend(2 * nc..ke);
        for col in columns {
            let x = yy[col];
            let d = force_step(x);
            for (side, sign) in [(0, 1.0), (1, -1.0)] {
                w.q_pert.copy_from_slice(q);
                w.v_pert.copy_from_slice(v);
                w.s_pert.copy_from_slice(s);
                if col < nc {
                    w.q_pert[col] = x + sign * d;
                } else if col < 2 * nc {
                    w.v_pert[col - nc] = x + sign * d;
                } else {
                    w.s_pert[col - 2 * nc] = x + sign * d;
                }
                // Only a perturbed angle changes a body's (sin φ, cos φ): the others are the
                // base point's (the Jacobian's caller filled `w.sin_cos`), which saves most of
                // the sin_cos calls of the Jacobian.
                w.sin_cos_pert.copy_from_slice(&w.sin_cos);
                if col < nc && col % 3 == 2 {
                    w.sin_cos_pert[col / 3] = w.q_pert[col].sin_cos();
                }
                let target = if side == 0 {
                    &mut w.forces_pert
                } else {
                    &mut w.forces
                };
                self.forces_into(t, &w.q_pert, &w.v_pert, &w.s_pert, &w.sin_cos_pert, target)?;
            }
            for k in 0..nc {
                out.add(nc + k, col, -(w.forces_pert[k] - w.forces[k]) / (2.0 * d));
            }
        }
        Ok(0)
    }
}

/// Step of the central differences of the forces: 10⁻⁹·max(1, |x|) (m, rad, m/s, rad/s).
/// Contact forces vary on the scale of the penetration (micrometres) and of the friction ramp
/// (v₀ ≈ 10⁻⁴ m/s), not of |x|: a step of a nanometre keeps the truncation error
/// (δ/penetration)² below 10⁻⁶ for penetrations above a micrometre, while rounding,
/// ε·|F|/δ, stays ≈ 10⁻³ N/m against contact stiffnesses of 10⁷–10⁹ N/m.
fn force_step(x: f64) -> f64 {
    let d = 1e-9 * x.abs().max(1.0);
    (x + d) - x
}

/// ∂Φ_row/∂q of body `b`, component `comp` (0 if the row does not touch b).
fn jac_entry(row: &crate::mechanics::constraints::ConstraintRow, b: usize, comp: usize) -> f64 {
    let mut x = 0.0;
    if row.body_a == Some(b) {
        x += row.jac_a[comp];
    }
    if row.body_b == Some(b) {
        x += row.jac_b[comp];
    }
    x
}
