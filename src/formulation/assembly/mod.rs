//! Kinematic assembly: consistent positions and velocities from the model's initial guesses.
//!
//! Positions: Newton's method on Φ(q, t₀) = 0 with least-squares minimum-norm steps
//! Δq = −Φ_q⁺ Φ, so that each step moves the guess as little as possible and the branch reached
//! is the one nearest the guess; a backtracking line search keeps |Φ| decreasing.
//! Velocities: the minimum-norm correction of the guessed velocities onto Φ_q q̇ = −Φ_t (its
//! least-squares answer on inconsistent rows decides which rows the velocities are fitted to,
//! see [`assemble`]). Rank and redundant rows: row k is redundant when it lies within 1e-9 of
//! its length of the span of the independent rows before it.
//!
//! Two paths compute these ([`RankSolver`]):
//!
//! * **dense**, up to [`DENSE_MAX_ROWS`] rows (one or two loops, every shipped model but the
//!   chain): Gram–Schmidt over the dense rows of Φ_q for the rank, the dense SVD for the
//!   velocities and the Newton steps. It costs microseconds there and keeps the small models'
//!   assembled states and messages exactly as they were. (Forced above 16 rows, its Newton steps
//!   take the sparse Schur complement Φ_q Φ_qᵀ of [`super::schur`] with the diagonal raised by
//!   the relative shift [`LEAST_NORM_SHIFT`] (Levenberg–Marquardt, ref. 1), whose error is
//!   shift · |Φ_q|² / σ_min² relative, and the SVD's step where r is not in the range of Φ_q.)
//! * **sparse**, above: the row-order sparse Cholesky of Φ_q Φ_qᵀ of [`RowBasis`], which declares
//!   the same rows redundant, gives the same least-squares steps Φ_q⁺ r as the SVD (to its
//!   accuracy) and the fits of the redundant rows for the conflict check, in O(m) for a chain of
//!   loops, without allocating inside the Newton loop after the first iteration.
//!
//! # References
//! 1. J. Nocedal, S. J. Wright, *Numerical Optimization*, 2nd ed., Springer, 2006, §10.3
//!    (Levenberg–Marquardt as regularised least norm).

pub(crate) mod diameter;
pub mod row_basis;
#[cfg(test)]
mod tests;

pub use row_basis::RowBasis;

use super::FormulationError;
use super::schur::{DENSE_MAX_ROWS, Schur, SchurSolver};
use crate::mechanics::constraints::{ConstraintEval, ConstraintRow, ConstraintSet, RowSource};
use crate::model::Model;
use nalgebra::{DMatrix, DVector};

/// Relative size below which a row of Φ_q counts as a combination of the rows before it.
const RANK_TOLERANCE: f64 = 1e-9;
/// |Φ| (m or rad) below which the positions count as assembled.
const POSITION_TOLERANCE: f64 = 1e-12;
const MAX_ITERATIONS: usize = 100;
/// Velocity residual |Φ_q q̇ + Φ_t| (relative to 1 + max |Φ_t|) above which the ideal-joint
/// velocity analysis counts as inconsistent.
const VELOCITY_TOLERANCE: f64 = 1e-10;

/// Result of assembling a model.
#[derive(Debug, Clone)]
pub struct Assembly {
    /// Consistent coordinates (x, y, φ per body).
    pub q: Vec<f64>,
    /// Consistent velocities.
    pub v: Vec<f64>,
    /// Rank of Φ_q.
    pub rank: usize,
    /// Rows of the constraint set that are combinations of earlier rows.
    pub redundant_rows: Vec<usize>,
    /// Degrees of freedom: coordinates − rank.
    pub dof: usize,
    /// Newton iterations used.
    pub iterations: usize,
    /// Largest |Φ| after assembly.
    pub residual: f64,
}

/// How assembly finds the rank of Φ_q and takes its least-norm steps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RankSolver {
    /// Dense up to [`DENSE_MAX_ROWS`] rows (every one- and two-loop model), sparse above (the
    /// default).
    #[default]
    Auto,
    /// Gram–Schmidt over the dense rows of Φ_q for the rank, the dense SVD for velocities and
    /// for the Newton steps that the shifted normal equations cannot take: cubic in the rows.
    Dense,
    /// The sparse row-order Cholesky of Φ_q Φ_qᵀ of [`RowBasis`] for all three: linear in the
    /// rows for a chain of loops.
    Sparse,
}

impl RankSolver {
    /// Whether `m` rows take the sparse path.
    fn is_sparse(self, m: usize) -> bool {
        match self {
            RankSolver::Auto => m > DENSE_MAX_ROWS,
            RankSolver::Dense => false,
            RankSolver::Sparse => true,
        }
    }
}

fn dense_jacobian(eval: &ConstraintEval, n: usize) -> DMatrix<f64> {
    let m = eval.rows.len();
    let mut jac = DMatrix::zeros(m, n);
    for (k, row) in eval.rows.iter().enumerate() {
        if let Some(a) = row.body_a {
            for c in 0..3 {
                jac[(k, 3 * a + c)] += row.jac_a[c];
            }
        }
        if let Some(b) = row.body_b {
            for c in 0..3 {
                jac[(k, 3 * b + c)] += row.jac_b[c];
            }
        }
    }
    jac
}

/// Relative shift of the diagonal of Φ_q Φ_qᵀ for the least-norm steps: large enough that
/// the pivot of a redundant row (its round-off is ~ m · 1e-16 of the diagonal) stays above
/// the 1e-13 breakdown threshold of the Cholesky, small enough that the step's relative
/// error (the shift over the squared relative smallest singular value) stays far below the
/// 1e-12 position tolerance over the Newton iterations.
pub const LEAST_NORM_SHIFT: f64 = 1e-10;

/// Largest |Φ_q x − r| relative to max |r| for which the shifted least-norm solution counts as
/// solving Φ_q x = r: the shift alone leaves ~ shift / σ_min² (relative), and Newton converges
/// from any step this close, linearly at this rate at worst.
const LEAST_NORM_RESIDUAL: f64 = 1e-6;

/// The minimum-norm solution x = Φ_qᵀ (Φ_q Φ_qᵀ + shift)⁻¹ r of Φ_q x = r over the rows of
/// `eval` (see the module doc), with `normal` prepared for those rows; the dense SVD's
/// pseudo-inverse for the few rows of one or two loops (where `normal` is dense), and its
/// least-squares solution where the shifted Φ_q Φ_qᵀ does not factor or r is not in
/// the range of Φ_q (to [`LEAST_NORM_RESIDUAL`]).
fn least_norm(normal: &mut Schur, eval: &ConstraintEval, r: &[f64], n: usize) -> Option<Vec<f64>> {
    let m = eval.rows.len();
    let all: Vec<usize> = (0..m).collect();
    let unit = vec![1.0; n];
    let mut lambda = r.to_vec();
    let mut x = vec![0.0; n];
    // A few rows (one or two loops): the dense SVD costs microseconds, and keeping it keeps the
    // assembled state of the shipped small models bit for bit (a clearance run at 3500 rpm
    // carries a 1e-17 change of the initial state to 1e-8 rad by its impacts).
    if normal.is_skyline()
        && normal
            .factor(&eval.rows, &all, &unit, LEAST_NORM_SHIFT)
            .is_ok()
    {
        normal.solve(&mut lambda);
        for (row, l) in eval.rows.iter().zip(&lambda) {
            scatter(row, *l, &mut x);
        }
        // r outside the range of Φ_q (a guess at a singular position, rows that cannot all
        // hold) has no exact solution: there the least-squares step of the SVD, as before.
        let off = eval.rows.iter().zip(r).fold(0.0_f64, |w, (row, rk)| {
            w.max((row.dot_velocity(&x) - rk).abs())
        });
        if off <= LEAST_NORM_RESIDUAL * max_abs(r) {
            return Some(x);
        }
    }
    let jac = dense_jacobian(eval, n);
    let svd = bounded_svd(jac, true, true)?;
    let eps = 1e-12 * svd.singular_values.max().max(1e-300);
    let step = svd.solve(&DVector::from_column_slice(r), eps).ok()?;
    Some(step.iter().copied().collect())
}

/// Largest number of implicit-shift QR iterations of [`bounded_svd`] per singular value.
/// nalgebra's `svd` iterates until it converges, with no limit: on a matrix with an infinite
/// entry (a driver speed of 1e308 rpm, infinite in rad/s) it never did, and `linkdyn check`
/// hung. A converging bidiagonal QR needs two or three iterations per singular value (LAPACK's
/// `dbdsqr` allows six per value and sweep); a hundred is far beyond any converging case.
pub(crate) const SVD_ITERATIONS_PER_VALUE: usize = 100;

/// The SVD of `m`, or `None` where an entry is not finite or the iteration does not converge
/// within [`SVD_ITERATIONS_PER_VALUE`] per singular value.
pub(crate) fn bounded_svd(
    m: DMatrix<f64>,
    compute_u: bool,
    compute_v: bool,
) -> Option<nalgebra::SVD<f64, nalgebra::Dyn, nalgebra::Dyn>> {
    if !m.iter().all(|x| x.is_finite()) {
        return None;
    }
    let values = m.nrows().min(m.ncols()).max(1);
    // nalgebra's `svd` convergence threshold (5 ε), so that a converging SVD is the same to the
    // last bit as before the limit.
    m.try_svd(
        compute_u,
        compute_v,
        5.0 * f64::EPSILON,
        SVD_ITERATIONS_PER_VALUE * values,
    )
}

/// x += l · (row of Φ_q)ᵀ.
fn scatter(row: &ConstraintRow, l: f64, x: &mut [f64]) {
    for (body, jac) in [(row.body_a, &row.jac_a), (row.body_b, &row.jac_b)] {
        if let Some(b) = body {
            for c in 0..3 {
                x[3 * b + c] += jac[c] * l;
            }
        }
    }
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |m, x| m.max(x.abs()))
}

fn evaluate(set: &ConstraintSet, t: f64, q: &[f64], v: &[f64], out: &mut ConstraintEval) {
    let mut sin_cos = vec![(0.0, 1.0); q.len() / 3];
    evaluate_with(set, t, q, v, &mut sin_cos, out);
}

/// [`evaluate`] with the caller's buffer for (sin φ, cos φ) of each body: no allocation.
fn evaluate_with(
    set: &ConstraintSet,
    t: f64,
    q: &[f64],
    v: &[f64],
    sin_cos: &mut [(f64, f64)],
    out: &mut ConstraintEval,
) {
    for (sc, body) in sin_cos.iter_mut().zip(q.chunks_exact(3)) {
        *sc = body[2].sin_cos();
    }
    set.evaluate_into(t, q, v, sin_cos, out);
}

/// Assembles `model` at time `t0`: positions with the constraint rows of `set` (the ideal-joint
/// rows, clearance joints held at their initial eccentricity), velocities with the same rows
/// where they are consistent, otherwise with the rows of the dynamics, `dynamic`
/// ([`RankSolver::Auto`]).
pub fn assemble(
    model: &Model,
    set: &ConstraintSet,
    dynamic: &ConstraintSet,
    t0: f64,
) -> Result<Assembly, FormulationError> {
    assemble_with(model, set, dynamic, t0, RankSolver::Auto)
}

/// The least-norm machinery of one assembly: the dense one of the module doc, or the sparse
/// [`RowBasis`] with its step buffer.
enum Steps {
    Dense(Box<Schur>),
    Sparse {
        basis: Box<RowBasis>,
        step: Vec<f64>,
    },
}

/// [`assemble`] with the rank and least-norm machinery chosen by `solver`.
///
/// On the sparse path each Newton step is the dense path's least-squares minimum-norm step
/// Δq = −Φ_q⁺ Φ, computed from the factor of Φ_q,I Φ_q,Iᵀ over the independent rows I that
/// [`RowBasis`] finds at that iterate and the fits of the dependent rows
/// ([`RowBasis::least_squares_into`]): for consistent redundant rows it is
/// −Φ_q,Iᵀ (Φ_q,I Φ_q,Iᵀ)⁻¹ Φ_I; for rows that cannot all hold (an iterate off the solution of an
/// over-constrained linkage, a linkage that cannot be assembled) the misfit is shared out as the
/// SVD shares it. The velocities are the guess corrected by the same solve with Φ_q q̇ + Φ_t
/// on the right. Nothing allocates inside the Newton loop after its first iteration.
pub fn assemble_with(
    model: &Model,
    set: &ConstraintSet,
    dynamic: &ConstraintSet,
    t0: f64,
    solver: RankSolver,
) -> Result<Assembly, FormulationError> {
    assemble_steps(model, set, dynamic, t0, solver, SchurSolver::Auto)
}

/// [`assemble_with`], the dense path's shifted normal equations stored as `normal` says
/// (`SchurSolver::Dense`: never used, every dense step is the SVD's pseudo-inverse, the
/// reference the tests compare the sparse steps with).
fn assemble_steps(
    model: &Model,
    set: &ConstraintSet,
    dynamic: &ConstraintSet,
    t0: f64,
    solver: RankSolver,
    normal: SchurSolver,
) -> Result<Assembly, FormulationError> {
    let n = 3 * model.bodies.len();
    let m = set.n_rows();
    let mut q: Vec<f64> = model
        .bodies
        .iter()
        .flat_map(|b| [b.initial.x, b.initial.y, b.initial.phi])
        .collect();
    let v_guess: Vec<f64> = model
        .bodies
        .iter()
        .flat_map(|b| [b.initial.vx, b.initial.vy, b.initial.omega])
        .collect();
    let mut eval = ConstraintEval::with_rows(m);
    let mut trial_eval = ConstraintEval::with_rows(m);
    let mut sin_cos = vec![(0.0, 1.0); model.bodies.len()];
    let mut trial = vec![0.0; n];
    let zero = vec![0.0; n];
    evaluate_with(set, t0, &q, &zero, &mut sin_cos, &mut eval);
    let mut residual = max_abs(&eval.phi);
    let mut iterations = 0;
    let mut steps = if solver.is_sparse(m) {
        Steps::Sparse {
            basis: Box::new(RowBasis::new(&eval.rows, n)),
            step: vec![0.0; n],
        }
    } else {
        let all: Vec<usize> = (0..m).collect();
        Steps::Dense(Box::new(Schur::new(&eval.rows, &all, normal)))
    };
    while residual > POSITION_TOLERANCE && iterations < MAX_ITERATIONS {
        iterations += 1;
        let dense_step;
        let step: &[f64] = match &mut steps {
            Steps::Dense(normal) => {
                let Some(s) = least_norm(normal, &eval, &eval.phi, n) else {
                    break;
                };
                dense_step = s;
                &dense_step
            }
            Steps::Sparse { basis, step } => {
                basis.factor(&eval.rows, RANK_TOLERANCE);
                basis.least_squares_into(&eval.rows, &eval.phi, step);
                step
            }
        };
        // Backtracking: accept the first step length that reduces |Φ|.
        let mut length = 1.0;
        let mut accepted = false;
        while length > 1e-6 {
            for ((ti, qi), si) in trial.iter_mut().zip(&q).zip(step) {
                *ti = qi - length * si;
            }
            evaluate_with(set, t0, &trial, &zero, &mut sin_cos, &mut trial_eval);
            let r = max_abs(&trial_eval.phi);
            if r < residual || r <= POSITION_TOLERANCE {
                std::mem::swap(&mut q, &mut trial);
                std::mem::swap(&mut eval, &mut trial_eval);
                residual = r;
                accepted = true;
                break;
            }
            length *= 0.5;
        }
        if !accepted {
            break;
        }
    }
    if residual > POSITION_TOLERANCE * 1e3 {
        let worst = eval
            .phi
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .map_or(0, |(k, _)| k);
        let joint = set.row_name(model, worst);
        return Err(FormulationError::Unassemblable {
            joint: joint.split('.').next().unwrap_or(&joint).to_string(),
            residual,
            iterations,
        });
    }

    // Velocities: the ideal-joint velocity analysis on the same rows; where that is inconsistent
    // (a clearance joint held as a revolute joint while a driver moves its journal relative to
    // its bearing), only the rows of the dynamics, `dynamic`.
    let consistent =
        |defect: f64, phi_t: &[f64]| defect <= VELOCITY_TOLERANCE * (1.0 + max_abs(phi_t));
    let (redundant_rows, v) = match &mut steps {
        Steps::Dense(_) => {
            let jac = dense_jacobian(&eval, n);
            let redundant_rows = redundant_rows(&jac);
            let v_guess_vec = DVector::from_column_slice(&v_guess);
            let (v, defect) = project_velocities(&jac, &eval.phi_t, &v_guess_vec);
            let v = if consistent(defect, &eval.phi_t) {
                v
            } else {
                let mut dyn_eval = ConstraintEval::with_rows(dynamic.n_rows());
                evaluate(dynamic, t0, &q, &zero, &mut dyn_eval);
                project_velocities(&dense_jacobian(&dyn_eval, n), &dyn_eval.phi_t, &v_guess_vec).0
            };
            (redundant_rows, v)
        }
        Steps::Sparse { basis, .. } => {
            basis.factor(&eval.rows, RANK_TOLERANCE);
            let redundant_rows = basis.dependent_rows();
            let (v, defect) = project_velocities_sparse(basis, &eval, &v_guess);
            let v = if consistent(defect, &eval.phi_t) {
                v
            } else {
                let mut dyn_eval = ConstraintEval::with_rows(dynamic.n_rows());
                evaluate(dynamic, t0, &q, &zero, &mut dyn_eval);
                let mut dyn_basis = RowBasis::new(&dyn_eval.rows, n);
                dyn_basis.factor(&dyn_eval.rows, RANK_TOLERANCE);
                project_velocities_sparse(&mut dyn_basis, &dyn_eval, &v_guess).0
            };
            (redundant_rows, v)
        }
    };
    let rank = m - redundant_rows.len();

    Ok(Assembly {
        q,
        v,
        rank,
        redundant_rows,
        dof: n - rank,
        iterations,
        residual,
    })
}

/// The sparse twin of [`project_velocities`] with `basis` factored at the rows of `eval`:
/// q̇ = guess − Φ_q,Iᵀ G_II⁻¹ (Φ_q guess + Φ_t)_I, and the largest |Φ_q q̇ + Φ_t| over all rows.
fn project_velocities_sparse(
    basis: &mut RowBasis,
    eval: &ConstraintEval,
    guess: &[f64],
) -> (Vec<f64>, f64) {
    let defect: Vec<f64> = eval
        .rows
        .iter()
        .zip(&eval.phi_t)
        .map(|(row, pt)| row.dot_velocity(guess) + pt)
        .collect();
    let mut correction = vec![0.0; guess.len()];
    basis.least_squares_into(&eval.rows, &defect, &mut correction);
    let v: Vec<f64> = guess.iter().zip(&correction).map(|(g, c)| g - c).collect();
    let residual = eval
        .rows
        .iter()
        .zip(&eval.phi_t)
        .fold(0.0_f64, |w, (row, pt)| {
            w.max((row.dot_velocity(&v) + pt).abs())
        });
    (v, residual)
}

/// The minimum-norm correction of `guess` onto Φ_q q̇ = −Φ_t, and the largest residual
/// |Φ_q q̇ + Φ_t| left (non-zero where the rows are inconsistent).
fn project_velocities(jac: &DMatrix<f64>, phi_t: &[f64], guess: &DVector<f64>) -> (Vec<f64>, f64) {
    if jac.nrows() == 0 {
        // No constraints (free bodies only): the guess is consistent.
        return (guess.iter().copied().collect(), 0.0);
    }
    let phi_t = DVector::from_column_slice(phi_t);
    let defect = jac * guess + &phi_t;
    // An SVD that does not converge leaves the guess, reported as inconsistent (∞).
    let Some(svd) = bounded_svd(jac.clone(), true, true) else {
        return (guess.iter().copied().collect(), f64::INFINITY);
    };
    let eps = 1e-12 * svd.singular_values.max().max(1e-300);
    let correction = svd
        .solve(&defect, eps)
        .unwrap_or_else(|_| DVector::zeros(guess.len()));
    let v = guess - correction;
    let residual = (jac * &v + phi_t).amax();
    (v.iter().copied().collect(), residual)
}

/// Redundant rows of `set` at the coordinates `q` (velocities `v` only fill Φ̇).
pub fn redundant_rows_at(set: &ConstraintSet, q: &[f64], v: &[f64]) -> Vec<usize> {
    let mut eval = ConstraintEval::with_rows(set.n_rows());
    evaluate(set, 0.0, q, v, &mut eval);
    redundant_rows(&dense_jacobian(&eval, q.len()))
}

/// Relative size of a coefficient below which a row does not count among those a dependent
/// row is a combination of (it is round-off of the least-squares fit). The dense fit over
/// hundreds of rows is noisy in the chain's ill-conditioned directions: on the 40-loop
/// parallelogram chain (377 independent rows before the dependent one) it gave six spurious
/// coefficients of 4e-8 to 1.8e-7 beside the true ones (±0.34, ±0.5, ±1), whose products with
/// γ made a consistent redundancy look like a conflict (defect 3e-8); the sparse fit gave none.
/// True coefficients are ratios of the linkage's lengths, far above 1e-6 of the largest.
const COEFFICIENT_TOLERANCE: f64 = 1e-6;
/// Relative defect of a dependent row's velocity or acceleration right-hand side above which it
/// contradicts the rows it depends on (the assembled state is consistent to ~1e-12, so a
/// defect of 1e-8 relative to the largest right-hand side is a real conflict).
const CONFLICT_TOLERANCE: f64 = 1e-8;

/// The redundant rows of `set` at the assembled state (q, v) at time `t0`, after making sure
/// that each is a consistent redundancy that can be left out (a doubled pin, the extra crank
/// of an over-constrained parallelogram). A redundant row is a conflict, and an error naming it
/// and the rows it is a combination of, if
///
/// * it is a driver: a driver is never dropped, since the motion it prescribes would then be
///   whatever the other rows allow (two drivers on one loop, a driver on a degenerate body);
/// * its velocity or acceleration right-hand side differs from the same combination of the
///   others': with Φ_q,k = Σ cᵢ Φ_q,i, consistency needs Φ_t,k = Σ cᵢ Φ_t,i and
///   γ_k = Σ cᵢ γᵢ (ref. 2 of [`crate::formulation::dae`], §3.7).
pub fn redundant_rows_checked(
    model: &Model,
    set: &ConstraintSet,
    q: &[f64],
    v: &[f64],
    t0: f64,
) -> Result<Vec<usize>, FormulationError> {
    redundant_rows_checked_with(model, set, q, v, t0, RankSolver::Auto)
}

/// The rows of Φ_q and what fits a dependent row by the independent rows before it.
enum RowFit {
    /// Dense Φ_q: Gram–Schmidt for the rank, the SVD for the fit.
    Dense(DMatrix<f64>),
    /// The sparse factor: the fit by its leading block (module doc of [`RowBasis`]).
    Sparse(Box<RowBasis>),
}

impl RowFit {
    /// (row, coefficient) over the independent rows before k of the least-squares fit of
    /// Φ_q,k; `redundant` lists the dependent rows.
    fn fit(&mut self, rows: &[ConstraintRow], k: usize, redundant: &[usize]) -> Vec<(usize, f64)> {
        let independent: Vec<usize> = (0..k)
            .filter(|i| redundant.binary_search(i).is_err())
            .collect();
        match self {
            RowFit::Dense(jac) => {
                let c = combination(jac, k, &independent);
                independent.into_iter().zip(c).collect()
            }
            RowFit::Sparse(basis) => {
                let mut c = vec![0.0; k];
                basis.combination_into(rows, k, &mut c);
                independent.into_iter().map(|i| (i, c[i])).collect()
            }
        }
    }
}

/// [`redundant_rows_checked`] with the rank and fitting machinery chosen by `solver`.
pub fn redundant_rows_checked_with(
    model: &Model,
    set: &ConstraintSet,
    q: &[f64],
    v: &[f64],
    t0: f64,
    solver: RankSolver,
) -> Result<Vec<usize>, FormulationError> {
    let mut eval = ConstraintEval::with_rows(set.n_rows());
    evaluate(set, t0, q, v, &mut eval);
    let (mut fit, redundant) = if solver.is_sparse(set.n_rows()) {
        let mut basis = RowBasis::new(&eval.rows, q.len());
        basis.factor(&eval.rows, RANK_TOLERANCE);
        let redundant = basis.dependent_rows();
        (RowFit::Sparse(Box::new(basis)), redundant)
    } else {
        let jac = dense_jacobian(&eval, q.len());
        let redundant = redundant_rows(&jac);
        (RowFit::Dense(jac), redundant)
    };
    let rhs_scale = |x: &[f64]| 1.0 + max_abs(x);
    let (scale_t, scale_gamma) = (rhs_scale(&eval.phi_t), rhs_scale(&eval.gamma));
    // Drivers first: a dependent driver is the root of any other inconsistency (a pin that
    // locks a driven body makes the pin's acceleration term disagree too).
    let is_driver = |k: usize| matches!(set.sources()[k], RowSource::Driver(_));
    let ordered = redundant
        .iter()
        .filter(|&&k| is_driver(k))
        .chain(redundant.iter().filter(|&&k| !is_driver(k)));
    for &k in ordered {
        let coefficients = fit.fit(&eval.rows, k, &redundant);
        let largest = coefficients.iter().fold(0.0_f64, |m, c| m.max(c.1.abs()));
        let terms: Vec<(usize, f64)> = coefficients
            .into_iter()
            .filter(|(_, c)| c.abs() > COEFFICIENT_TOLERANCE * largest)
            .collect();
        let combined = |x: &[f64]| terms.iter().map(|&(i, c)| c * x[i]).sum::<f64>();
        let velocity_defect = (eval.phi_t[k] - combined(&eval.phi_t)).abs();
        let acceleration_defect = (eval.gamma[k] - combined(&eval.gamma)).abs();
        let reason = if is_driver(k) {
            Some(
                "a driver must prescribe a motion the other constraints leave free, but at the assembled position this one is a combination of them (its angle is already fixed by them: two drivers on one loop, or a link of zero length)"
                    .to_string(),
            )
        } else if velocity_defect > CONFLICT_TOLERANCE * scale_t {
            Some(format!(
                "its prescribed velocity differs from theirs by {velocity_defect:.3e} (m/s or rad/s): the drivers prescribe incompatible speeds"
            ))
        } else if acceleration_defect > CONFLICT_TOLERANCE * scale_gamma {
            Some(format!(
                "its acceleration term γ differs from theirs by {acceleration_defect:.3e} (m/s² or rad/s²): the rows cannot all hold as the linkage moves"
            ))
        } else {
            None
        };
        if let Some(reason) = reason {
            let depends_on = if terms.is_empty() {
                "no other row (it is zero: it constrains nothing)".to_string()
            } else {
                terms
                    .iter()
                    .map(|&(i, _)| format!("\"{}\"", set.row_name(model, i)))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            return Err(FormulationError::ConflictingConstraints {
                row: set.row_name(model, k),
                depends_on,
                reason,
            });
        }
    }
    Ok(redundant)
}

/// Least-squares coefficients c with Σ cᵢ J_rowsᵢ ≈ J_k (SVD, minimum norm).
fn combination(jac: &DMatrix<f64>, k: usize, rows: &[usize]) -> Vec<f64> {
    if rows.is_empty() {
        return Vec::new();
    }
    let basis = DMatrix::from_fn(jac.ncols(), rows.len(), |c, r| jac[(rows[r], c)]);
    let target: DVector<f64> = jac.row(k).transpose();
    let Some(svd) = bounded_svd(basis, true, true) else {
        return vec![0.0; rows.len()];
    };
    let eps = 1e-12 * svd.singular_values.max().max(1e-300);
    match svd.solve(&target, eps) {
        Ok(c) => c.iter().copied().collect(),
        // Only fails without U/V, which were asked for: treat as "no combination found".
        Err(_) => vec![0.0; rows.len()],
    }
}

/// Rows of `jac` that lie (to [`RANK_TOLERANCE`]) in the span of the rows before them.
fn redundant_rows(jac: &DMatrix<f64>) -> Vec<usize> {
    let mut basis: Vec<DVector<f64>> = Vec::new();
    let mut redundant = Vec::new();
    for k in 0..jac.nrows() {
        let row: DVector<f64> = jac.row(k).transpose();
        let norm = row.norm();
        let mut r = row.clone();
        // Two passes of modified Gram–Schmidt for numerical orthogonality.
        for _ in 0..2 {
            for b in &basis {
                let c = b.dot(&r);
                r -= b * c;
            }
        }
        let rn = r.norm();
        if norm == 0.0 || rn <= RANK_TOLERANCE * norm {
            redundant.push(k);
        } else {
            basis.push(r / rn);
        }
    }
    redundant
}
