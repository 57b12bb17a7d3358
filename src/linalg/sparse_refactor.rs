//! Sparse LU factors that refactorise in place with the pivot sequence and fill pattern of an
//! earlier pivoting factorisation (KLU's "refactor", Davis & Palamadai Natarajan, ACM TOMS 37,
//! 2010, §2.5).
//!
//! Why: faer's left-looking LU with partial pivoting (Gilbert–Peierls) finds each column's
//! pattern by a depth-first search through L before it computes a single value, and Radau5
//! factorises Newton matrices of one pattern thousands of times a run (the generalised
//! formulation its dependent block at every right-hand side), with values that change little
//! from one factorisation to the next. Measured on the 40-loop N-four-bar chain (DAE,
//! Radau5, `perf record`): the search alone was 27 % of the run, faer's numeric work 29 %.
//! Here the patterns of L and U, the row pivots and each column's elimination order are kept
//! from the last pivoting factorisation, and a refactorisation is the numeric work alone.
//!
//! **Pivot check** ([`PivotCheck`]). The kept pivot of a column is accepted if it is finite,
//! non-zero and at least a fraction of the largest entry below it (threshold partial
//! pivoting); otherwise [`FixedPivotLu::refactor`] gives up and the caller factorises with
//! pivoting again. When the kept pivot is the column's largest, the factors are those faer's
//! pivoting factorisation would compute, bit for bit: the same operations in the same order
//! (tested in `solve/radau5/sparse.rs`).

use faer::c64;
use faer::sparse::SparseColMatRef;
use faer::sparse::linalg::lu::simplicial::SimplicialLu;
use faer::traits::ComplexField;
use std::ops::{AddAssign, Mul, SubAssign};

/// The entries the factors hold: real (the real Newton matrix) or complex (the complex one),
/// with faer's own reciprocal and modulus so that the factors match faer's bit for bit.
pub(crate) trait Entry:
    ComplexField + Copy + AddAssign + SubAssign + Mul<Output = Self>
{
    fn zero() -> Self;
    fn recip(self) -> Self;
    fn modulus(self) -> f64;
}

impl Entry for f64 {
    fn zero() -> Self {
        0.0
    }
    fn recip(self) -> Self {
        1.0 / self
    }
    fn modulus(self) -> f64 {
        self.abs()
    }
}

impl Entry for c64 {
    fn zero() -> Self {
        c64::new(0.0, 0.0)
    }
    fn recip(self) -> Self {
        <c64 as ComplexField>::recip_impl(&self)
    }
    fn modulus(self) -> f64 {
        <c64 as ComplexField>::abs_impl(&self)
    }
}

/// When a kept pivot is good enough: at least this fraction of the largest entry below it.
/// 0.1 is UMFPACK's default for unsymmetric matrices (Davis, ACM TOMS 30, 2004, §2): each
/// accepted pivot can grow the entries of the factors by at most 10 per elimination step,
/// against partial pivoting's 1. 1.0 accepts only a pivot partial pivoting could have chosen
/// (the largest, or one of equal size).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PivotCheck(pub f64);

impl PivotCheck {
    fn accepts(self, size: f64, below: f64) -> bool {
        size.is_finite() && size > 0.0 && size >= self.0 * below
    }
}

/// Why a refactorisation stopped: the kept pivot of column `column` failed the check.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct PivotRejected {
    pub column: usize,
}

/// L (unit lower, its diagonal stored first in each column) and U (upper, its diagonal stored
/// last, the other rows in elimination order) of P·A·Q, with the row pivots P, in compressed
/// columns over the pivot numbering of the rows.
#[derive(Debug, Clone)]
pub(crate) struct FixedPivotLu<T> {
    /// `row_fwd[k]`: the row of A that is pivot row k; `row_inv` its inverse.
    row_fwd: Vec<usize>,
    row_inv: Vec<usize>,
    l_ptr: Vec<usize>,
    l_idx: Vec<usize>,
    l_val: Vec<T>,
    u_ptr: Vec<usize>,
    u_idx: Vec<usize>,
    u_val: Vec<T>,
    /// A dense column in pivot numbering, zero between uses.
    work: Vec<T>,
}

/// No factors yet: empty buffers (no bound on the entries, as a derived `Default` would ask).
impl<T> Default for FixedPivotLu<T> {
    fn default() -> Self {
        FixedPivotLu {
            row_fwd: Vec::new(),
            row_inv: Vec::new(),
            l_ptr: Vec::new(),
            l_idx: Vec::new(),
            l_val: Vec::new(),
            u_ptr: Vec::new(),
            u_idx: Vec::new(),
            u_val: Vec::new(),
            work: Vec::new(),
        }
    }
}

impl<T: Entry> FixedPivotLu<T> {
    /// Replaces the factors by faer's simplicial LU and its row pivots (`row_fwd`, `row_inv` as
    /// faer returned them); the buffers keep their capacity, so once they are large enough this
    /// allocates nothing. Start from [`FixedPivotLu::default`] (no factors).
    pub(crate) fn copy_from_faer(
        &mut self,
        lu: &SimplicialLu<usize, T>,
        row_fwd: &[usize],
        row_inv: &[usize],
    ) {
        let copy = |dst: &mut Vec<usize>, src: &[usize]| {
            dst.clear();
            dst.extend_from_slice(src);
        };
        copy(&mut self.row_fwd, row_fwd);
        copy(&mut self.row_inv, row_inv);
        let l = lu.l_factor_unsorted();
        copy(&mut self.l_ptr, l.symbolic().col_ptr());
        copy(&mut self.l_idx, l.symbolic().row_idx());
        self.l_val.clear();
        self.l_val.extend_from_slice(l.val());
        let u = lu.u_factor_unsorted();
        copy(&mut self.u_ptr, u.symbolic().col_ptr());
        copy(&mut self.u_idx, u.symbolic().row_idx());
        self.u_val.clear();
        self.u_val.extend_from_slice(u.val());
        self.work.clear();
        self.work.resize(row_fwd.len(), T::zero());
    }

    /// The pivots, U's diagonal, in column order.
    pub(crate) fn pivots(&self) -> impl Iterator<Item = &T> + '_ {
        self.u_ptr[1..].iter().map(|&end| &self.u_val[end - 1])
    }

    /// Factorises `a` (the pattern the kept factors came from, new values) with the kept row
    /// pivots, column order `col_perm` (column j of P·A·Q is column `col_perm[j]` of A) and
    /// fill pattern, each pivot accepted by `check`. On a rejected pivot the factors are left
    /// unusable: factorise with pivoting next.
    pub(crate) fn refactor(
        &mut self,
        a: SparseColMatRef<'_, usize, T>,
        col_perm: &[usize],
        check: PivotCheck,
    ) -> Result<(), PivotRejected> {
        let work = &mut self.work;
        for (j, &pj) in col_perm.iter().enumerate() {
            for (&i, v) in a.row_idx_of_col_raw(pj).iter().zip(a.val_of_col(pj)) {
                work[self.row_inv[i]] += *v;
            }
            let (u0, u1) = (self.u_ptr[j], self.u_ptr[j + 1] - 1);
            // Columns k of L in the order the pivoting factorisation eliminated them.
            for &k in &self.u_idx[u0..u1] {
                let ukj = work[k];
                let (l0, l1) = (self.l_ptr[k] + 1, self.l_ptr[k + 1]);
                for (&r, &lrk) in self.l_idx[l0..l1].iter().zip(&self.l_val[l0..l1]) {
                    work[r] -= lrk * ukj;
                }
            }
            let pivot = work[j];
            let (l0, l1) = (self.l_ptr[j] + 1, self.l_ptr[j + 1]);
            let below = self.l_idx[l0..l1]
                .iter()
                .map(|&r| work[r].modulus())
                .fold(0.0, f64::max);
            let size = pivot.modulus();
            if check.accepts(size, below) {
                for (p, &k) in (u0..u1).zip(&self.u_idx[u0..u1]) {
                    self.u_val[p] = work[k];
                    work[k] = T::zero();
                }
                self.u_val[u1] = pivot;
                let inverse = pivot.recip();
                for (q, &r) in (l0..l1).zip(&self.l_idx[l0..l1]) {
                    self.l_val[q] = work[r] * inverse;
                    work[r] = T::zero();
                }
                work[j] = T::zero();
            } else {
                for &k in self.u_idx[u0..=u1].iter().chain(&self.l_idx[l0..l1]) {
                    work[k] = T::zero();
                }
                return Err(PivotRejected { column: j });
            }
        }
        Ok(())
    }

    /// Solves A x = b in place (`b` of the factors' dimension), with `col_perm` as in
    /// [`FixedPivotLu::refactor`].
    pub(crate) fn solve(&mut self, b: &mut [T], col_perm: &[usize]) {
        let y = &mut self.work;
        for (yk, &i) in y.iter_mut().zip(&self.row_fwd) {
            *yk = b[i];
        }
        for j in 0..y.len() {
            let yj = y[j];
            let (l0, l1) = (self.l_ptr[j] + 1, self.l_ptr[j + 1]);
            for (&r, &lrj) in self.l_idx[l0..l1].iter().zip(&self.l_val[l0..l1]) {
                y[r] -= lrj * yj;
            }
        }
        for j in (0..y.len()).rev() {
            let (u0, u1) = (self.u_ptr[j], self.u_ptr[j + 1] - 1);
            let yj = y[j] * self.u_val[u1].recip();
            y[j] = yj;
            for (&k, &ukj) in self.u_idx[u0..u1].iter().zip(&self.u_val[u0..u1]) {
                y[k] -= ukj * yj;
            }
        }
        for (j, &q) in col_perm.iter().enumerate() {
            b[q] = y[j];
            y[j] = T::zero();
        }
    }
}
