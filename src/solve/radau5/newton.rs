//! The Newton matrices of Radau IIA, dense or sparse ([`LinearSolver`]): the Jacobian they are
//! built from, their factorisation at a step size, and the solves with them.
//!
//! [`NewtonMatrices::new`] picks the storage once per run, from the setting and the formulation
//! ([`Formulation::sparse_jacobian`]); the core sees only evaluate / factor / solve.

use super::linalg::{ComplexLu, Partition, RealLu, Singular};
use super::settings::{LinearSolver, SPARSE_MIN_STATES};
use super::sparse::SparseLu;
use crate::formulation::{Formulation, FormulationError};

/// The dense path: J row-major (n²), its decoupled components, the two dense LUs.
struct Dense {
    jac: Vec<f64>,
    jac_work: Vec<f64>,
    part: Partition,
    e1: RealLu,
    e2: ComplexLu,
}

/// The sparse path: the values of the augmented Jacobian 𝒥 and the sparse LUs.
struct Sparse {
    jac: Vec<f64>,
    lu: SparseLu,
}

/// Jacobian and LU factors of the two Newton matrices.
pub(super) struct NewtonMatrices(Storage);

enum Storage {
    /// Dense LU of J ([`super::linalg`]).
    Dense(Box<Dense>),
    /// Sparse LU of the augmented Jacobian ([`super::sparse`]).
    Sparse(Box<Sparse>),
}

impl NewtonMatrices {
    /// Dense buffers for n states.
    pub(super) fn dense(n: usize) -> Self {
        NewtonMatrices(Storage::Dense(Box::new(Dense {
            jac: vec![0.0; n * n],
            jac_work: vec![0.0; 2 * n],
            part: Partition::new(n),
            e1: RealLu::new(n),
            e2: ComplexLu::new(n),
        })))
    }

    /// The storage that `solver` asks for with formulation `f` (n states): sparse if `f` has a
    /// sparse Jacobian and `solver` is [`LinearSolver::Sparse`], or [`LinearSolver::Auto`] with
    /// n ≥ [`SPARSE_MIN_STATES`]; dense otherwise (also if the sparse analysis fails).
    pub(super) fn new<F: Formulation + ?Sized>(f: &F, n: usize, solver: LinearSolver) -> Self {
        let wanted = match solver {
            LinearSolver::Dense => false,
            LinearSolver::Sparse => true,
            LinearSolver::Auto => n >= SPARSE_MIN_STATES,
        };
        if wanted && let Some(sj) = f.sparse_jacobian() {
            let pattern = sj.jacobian_pattern();
            if pattern.dim() == n + sj.n_algebraic()
                && let Some(lu) = SparseLu::new(n, &pattern)
            {
                return NewtonMatrices(Storage::Sparse(Box::new(Sparse {
                    jac: vec![0.0; pattern.nnz()],
                    lu,
                })));
            }
        }
        Self::dense(n)
    }

    /// Whether the sparse LU is in use.
    #[must_use]
    pub(super) fn is_sparse(&self) -> bool {
        matches!(self.0, Storage::Sparse(_))
    }

    /// Structural non-zeros of one Newton matrix: n² for the dense LU.
    #[must_use]
    pub(super) fn stored_entries(&self) -> usize {
        match &self.0 {
            Storage::Dense(d) => d.jac.len(),
            Storage::Sparse(s) => s.lu.nnz(),
        }
    }

    /// Evaluates the Jacobian (J or 𝒥) at (t, y), with f0 = f(t, y); returns the RHS calls made.
    pub(super) fn evaluate<F: Formulation + ?Sized>(
        &mut self,
        f: &F,
        t: f64,
        y: &[f64],
        f0: &[f64],
    ) -> Result<usize, FormulationError> {
        match &mut self.0 {
            Storage::Dense(d) => {
                let calls = f.jacobian(t, y, f0, &mut d.jac, &mut d.jac_work)?;
                d.part.update(&d.jac);
                Ok(calls)
            }
            Storage::Sparse(s) => {
                match f.sparse_jacobian() {
                    Some(sj) => sj.jacobian_values(t, y, &mut s.jac),
                    // The formulation gave a sparse Jacobian when this was built and cannot stop
                    // giving one; should it, the run stops here, saying so.
                    None => Err(FormulationError::Unsupported {
                        formulation: "Radau5 with a sparse LU".into(),
                        reason: "the formulation no longer gives a sparse Jacobian".into(),
                    }),
                }
            }
        }
    }

    /// Factorises γ̂/h·I − J (`fac1` = γ̂/h) and (α̂ + iβ̂)/h·I − J with the last Jacobian.
    pub(super) fn factor(&mut self, fac1: f64, alphn: f64, betan: f64) -> Result<(), Singular> {
        match &mut self.0 {
            Storage::Dense(d) => {
                d.e1.factor(fac1, &d.jac, &d.part)?;
                d.e2.factor(alphn, betan, &d.jac, &d.part)
            }
            Storage::Sparse(s) => {
                s.lu.factor_real(fac1, &s.jac)?;
                s.lu.factor_complex(alphn, betan, &s.jac)
            }
        }
    }

    /// Solves (γ̂/h·I − J) x = b in place.
    pub(super) fn solve_real(&mut self, b: &mut [f64]) {
        match &mut self.0 {
            Storage::Dense(d) => d.e1.solve(b),
            Storage::Sparse(s) => s.lu.solve_real(b),
        }
    }

    /// Solves ((α̂ + iβ̂)/h·I − J)(x_re + i x_im) = b_re + i b_im in place.
    pub(super) fn solve_complex(&mut self, b_re: &mut [f64], b_im: &mut [f64]) {
        match &mut self.0 {
            Storage::Dense(d) => d.e2.solve(b_re, b_im),
            Storage::Sparse(s) => s.lu.solve_complex(b_re, b_im),
        }
    }
}
