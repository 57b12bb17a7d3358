//! The Newton matrices of Radau IIA, dense or sparse ([`LinearSolver`]): the Jacobian they are
//! built from, their factorisation at a step size, and the solves with them.
//!
//! [`NewtonMatrices::new`] picks the storage once per run, from the setting and the formulation
//! ([`Formulation::sparse_jacobian`]); the core sees only evaluate / factor / solve.

use super::settings::{LinearSolver, SPARSE_MIN_STATES};
use super::sparse::SparseLu;
use crate::formulation::{Formulation, FormulationError};
use crate::linalg::Singular;
use crate::linalg::shifted_lu::{ComplexLu, Partition, RealLu};

/// The dense path: J row-major (n²), its decoupled components, the two dense LUs.
///
/// **Second-order structure** (Hairer's `M1` option \[1, Sec. IV.8\]). When the formulation
/// says that its first m states are positions whose derivatives are the next m states exactly
/// ([`Formulation::second_order_positions`]: f_i = y_{m+i}, so row i of J is the unit row
/// e_{m+i}), the n × n system (s·I − J) x = b is solved through the k × k one, k = n − m, for
/// the other components u = x_{m..n}: the first m rows give x_i = (b_i + u_i)/s, and
/// substituted into the others,
///
/// (s·I − J_u − J_q/s) u = b_u + J_q b_q / s,
///
/// with J_u = J\[m.., m..\] and J_q = J\[m.., ..m\] padded with zero columns to k. The factored
/// matrices are k × k (for m = n/2 half the size: an eighth of the LU work, a quarter of the
/// solves'); for complex s = α + iβ the reduced matrix is complex.
///
/// # References
/// 1. E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II*, 2nd ed., Springer,
///    1996, Sec. IV.8 (RADAU5's `M1`, `M2` arguments).
struct Dense {
    n: usize,
    /// Positions m of the second-order structure (0: none, the full system is factored).
    m: usize,
    jac: Vec<f64>,
    jac_work: Vec<f64>,
    /// The reduced matrix J_u + J_q/s (k²), its imaginary part for complex s.
    red: Vec<f64>,
    red_im: Vec<f64>,
    /// Decoupled components of the factored matrix (J, or the reduced one).
    part: Partition,
    e1: RealLu,
    e2: ComplexLu,
    /// 1/s of the real and of the complex factorisation.
    inv_real: f64,
    inv_complex: (f64, f64),
}

/// The sparse path: the values of the augmented Jacobian 𝒥 and the sparse LUs.
struct Sparse {
    jac: Vec<f64>,
    lu: SparseLu,
}

/// Jacobian and LU factors of the two Newton matrices.
pub(super) struct NewtonMatrices(Storage);

enum Storage {
    /// Dense LU of J ([`crate::linalg::shifted_lu`]).
    Dense(Box<Dense>),
    /// Sparse LU of the augmented Jacobian ([`super::sparse`]).
    Sparse(Box<Sparse>),
}

impl NewtonMatrices {
    /// Dense buffers for n states, the first m of them positions of a second-order structure
    /// (m = 0: none; m ≤ n/2, else none).
    pub(super) fn dense(n: usize, m: usize) -> Self {
        let m = if 2 * m <= n { m } else { 0 };
        let k = n - m;
        let red_len = if m > 0 { k * k } else { 0 };
        NewtonMatrices(Storage::Dense(Box::new(Dense {
            n,
            m,
            jac: vec![0.0; n * n],
            jac_work: vec![0.0; 2 * n],
            red: vec![0.0; red_len],
            red_im: vec![0.0; red_len],
            part: Partition::new(k),
            e1: RealLu::new(k),
            e2: ComplexLu::new(k),
            inv_real: 0.0,
            inv_complex: (0.0, 0.0),
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
        Self::dense(n, f.second_order_positions())
    }

    /// Whether the sparse LU is in use.
    #[must_use]
    pub(super) fn is_sparse(&self) -> bool {
        matches!(self.0, Storage::Sparse(_))
    }

    /// Structural non-zeros of one Newton matrix: k² for the dense LU (k = n − m unknowns).
    #[must_use]
    pub(super) fn stored_entries(&self) -> usize {
        match &self.0 {
            Storage::Dense(d) => (d.n - d.m).pow(2),
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
                if d.m == 0 {
                    d.part.update(&d.jac);
                } else {
                    // The pattern of J_u + J_q/s for any s (sums of magnitudes: no cancellation).
                    let (n, m, k) = (d.n, d.m, d.n - d.m);
                    debug_assert!(
                        (0..m).all(|i| (0..n).all(|j| d.jac[i * n + j] == f64::from(j == m + i))),
                        "the formulation's second-order rows are unit rows"
                    );
                    for a in 0..k {
                        let row = &d.jac[(m + a) * n..(m + a + 1) * n];
                        for c in 0..k {
                            let q = if c < m { row[c].abs() } else { 0.0 };
                            d.red[a * k + c] = row[m + c].abs() + q;
                        }
                    }
                    d.part.update(&d.red);
                }
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
            Storage::Dense(d) if d.m == 0 => {
                d.e1.factor(fac1, &d.jac, &d.part)?;
                d.e2.factor(alphn, betan, &d.jac, &d.part)
            }
            Storage::Dense(d) => {
                let (n, m, k) = (d.n, d.m, d.n - d.m);
                let inv = 1.0 / fac1;
                let norm = alphn * alphn + betan * betan;
                let (ir, ii) = (alphn / norm, -betan / norm);
                d.inv_real = inv;
                d.inv_complex = (ir, ii);
                for a in 0..k {
                    let row = &d.jac[(m + a) * n..(m + a + 1) * n];
                    for c in 0..k {
                        let q = if c < m { row[c] } else { 0.0 };
                        d.red[a * k + c] = row[m + c] + q * inv;
                    }
                }
                d.e1.factor(fac1, &d.red, &d.part)?;
                for a in 0..k {
                    let row = &d.jac[(m + a) * n..(m + a + 1) * n];
                    for c in 0..k {
                        let q = if c < m { row[c] } else { 0.0 };
                        d.red[a * k + c] = row[m + c] + q * ir;
                        d.red_im[a * k + c] = q * ii;
                    }
                }
                d.e2.factor_complex(alphn, betan, (&d.red, Some(&d.red_im)), &d.part)
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
            Storage::Dense(d) if d.m == 0 => d.e1.solve(b),
            Storage::Dense(d) => {
                let (n, m, inv) = (d.n, d.m, d.inv_real);
                let (bq, bu) = b.split_at_mut(m);
                for (a, u) in bu.iter_mut().enumerate() {
                    let row = &d.jac[(m + a) * n..(m + a) * n + m];
                    let mut sum = 0.0;
                    for (&j, &q) in row.iter().zip(bq.iter()) {
                        sum += j * q;
                    }
                    *u += sum * inv;
                }
                d.e1.solve(bu);
                for (q, &u) in bq.iter_mut().zip(bu.iter()) {
                    *q = (*q + u) * inv;
                }
            }
            Storage::Sparse(s) => s.lu.solve_real(b),
        }
    }

    /// Solves ((α̂ + iβ̂)/h·I − J)(x_re + i x_im) = b_re + i b_im in place.
    pub(super) fn solve_complex(&mut self, b_re: &mut [f64], b_im: &mut [f64]) {
        match &mut self.0 {
            Storage::Dense(d) if d.m == 0 => d.e2.solve(b_re, b_im),
            Storage::Dense(d) => {
                let (n, m, (ir, ii)) = (d.n, d.m, d.inv_complex);
                let (q_re, u_re) = b_re.split_at_mut(m);
                let (q_im, u_im) = b_im.split_at_mut(m);
                // b_q/s, kept in place until the back-substitution.
                for (qr, qi) in q_re.iter_mut().zip(q_im.iter_mut()) {
                    (*qr, *qi) = (*qr * ir - *qi * ii, *qr * ii + *qi * ir);
                }
                for (a, (ur, ui)) in u_re.iter_mut().zip(u_im.iter_mut()).enumerate() {
                    let row = &d.jac[(m + a) * n..(m + a) * n + m];
                    let (mut sr, mut si) = (0.0, 0.0);
                    for ((&j, &qr), &qi) in row.iter().zip(q_re.iter()).zip(q_im.iter()) {
                        sr += j * qr;
                        si += j * qi;
                    }
                    *ur += sr;
                    *ui += si;
                }
                d.e2.solve(u_re, u_im);
                // x_q = (b_q + u)/s = b_q/s + u/s.
                for (((qr, qi), &ur), &ui) in q_re
                    .iter_mut()
                    .zip(q_im.iter_mut())
                    .zip(u_re.iter())
                    .zip(u_im.iter())
                {
                    *qr += ur * ir - ui * ii;
                    *qi += ur * ii + ui * ir;
                }
            }
            Storage::Sparse(s) => s.lu.solve_complex(b_re, b_im),
        }
    }
}
