//! Sparse Jacobians for implicit integrators on large models, in **augmented form**.
//!
//! The Newton matrices of an implicit method (Radau5's σ·I − J) have the sparsity of the
//! Jacobian J = ∂f/∂y. For the DAE that sparsity is lost: q̈ is the solution of the constraint
//! equations, so ∂q̈/∂q couples every body of a connected linkage with every other (the inverse
//! of the constraint matrix is full), and J is dense in half its rows. It is sparse again
//! before the constraint solve: with the eliminated unknowns z (for the DAE, q̈ and λ) kept as
//! unknowns, the equations are a semi-explicit system of index 1,
//!
//! ```text
//!     y' = g(t, y, z),    0 = k(t, y, z),
//! ```
//!
//! whose z follows from y through k = 0 (∂k/∂z invertible). A formulation that can say so
//! gives the (n + m) × (n + m) matrix of all partial derivatives (n = number of states, m =
//! number of algebraic unknowns z),
//!
//! ```text
//!     𝒥 = | ∂g/∂y  ∂g/∂z |
//!         | ∂k/∂y  ∂k/∂z |,
//! ```
//!
//! over a structural pattern fixed for the formulation's life ([`SparsePattern`]). Its Schur
//! complement is the ordinary Jacobian,
//!
//! ```text
//!     J = ∂g/∂y − ∂g/∂z (∂k/∂z)⁻¹ ∂k/∂y,
//! ```
//!
//! so for any σ (real or complex) the solution x of (σ·I − J) x = b is the first n components
//! of the solution of the sparse system
//!
//! ```text
//!     (σ·E − 𝒥) (x, w) = (b, 0),      E = diag(I_n, 0_m),
//! ```
//!
//! (the second block row gives w = −(∂k/∂z)⁻¹ (∂k/∂y) x, the first then (σ·I − J) x = b): the
//! Newton matrix of Radau IIA applied to the index-1 system with the singular mass matrix E
//! (ref. 1, Sec. VI.1), here used only for the linear algebra. With m = 0, 𝒥 is J itself, for a
//! formulation whose J is sparse as it stands.
//!
//! # References
//! 1. E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II: Stiff and
//!    Differential-Algebraic Problems*, 2nd ed., Springer, 1996, Sec. VI.1 (index-1 problems,
//!    the mass-matrix form of RADAU5).

use super::FormulationError;

/// The structural non-zeros of a square matrix in compressed sparse column form: the entries
/// of column j are at positions `col_ptr[j]..col_ptr[j + 1]`, their row indices ascending and
/// distinct. The values of a matrix over this pattern are a slice of length
/// [`SparsePattern::nnz`] in that order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SparsePattern {
    dim: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
}

impl SparsePattern {
    /// The pattern of a `dim` × `dim` matrix with the given (row, column) entries, in any order,
    /// repeats allowed (they are merged). Entries outside the matrix are left out (a caller's
    /// bug: `debug_assert!`).
    pub fn from_entries(dim: usize, entries: impl IntoIterator<Item = (usize, usize)>) -> Self {
        let mut by_col: Vec<Vec<usize>> = vec![Vec::new(); dim];
        for (row, col) in entries {
            debug_assert!(
                row < dim && col < dim,
                "entry ({row}, {col}) outside {dim}²"
            );
            if row < dim
                && let Some(rows) = by_col.get_mut(col)
            {
                rows.push(row);
            }
        }
        let mut col_ptr = Vec::with_capacity(dim + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for mut rows in by_col {
            rows.sort_unstable();
            rows.dedup();
            row_idx.extend_from_slice(&rows);
            col_ptr.push(row_idx.len());
        }
        SparsePattern {
            dim,
            col_ptr,
            row_idx,
        }
    }

    /// Number of rows (= columns).
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Number of structural non-zeros.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Column pointers (length dim + 1).
    pub fn col_ptr(&self) -> &[usize] {
        &self.col_ptr
    }

    /// Row indices, column by column (length [`SparsePattern::nnz`]).
    pub fn row_idx(&self) -> &[usize] {
        &self.row_idx
    }

    /// The row indices of column `col` (empty outside the matrix).
    pub fn rows_of(&self, col: usize) -> &[usize] {
        match (self.col_ptr.get(col), self.col_ptr.get(col + 1)) {
            (Some(&a), Some(&b)) => &self.row_idx[a..b],
            _ => &[],
        }
    }

    /// Position of entry (row, col) in the values, or `None` if it is not in the pattern
    /// (a binary search in its column).
    pub fn position(&self, row: usize, col: usize) -> Option<usize> {
        let start = *self.col_ptr.get(col)?;
        self.rows_of(col)
            .binary_search(&row)
            .ok()
            .map(|offset| start + offset)
    }
}

/// Values of a matrix over a [`SparsePattern`], filled entry by entry: [`Scatter::add`] adds to
/// an entry of the pattern and counts the entries outside it, which a correct formulation never
/// writes (its tests check [`Scatter::missed`] is 0).
pub struct Scatter<'a> {
    pattern: &'a SparsePattern,
    values: &'a mut [f64],
    missed: usize,
}

impl<'a> Scatter<'a> {
    /// Starts filling `values` (length [`SparsePattern::nnz`]) from zero.
    pub fn new(pattern: &'a SparsePattern, values: &'a mut [f64]) -> Self {
        values.fill(0.0);
        Scatter {
            pattern,
            values,
            missed: 0,
        }
    }

    /// Adds `value` to entry (row, col). A non-zero value outside the pattern (or outside
    /// `values`) is counted in [`Scatter::missed`] and dropped; a zero one is ignored.
    #[inline]
    pub fn add(&mut self, row: usize, col: usize, value: f64) {
        match self
            .pattern
            .position(row, col)
            .and_then(|p| self.values.get_mut(p))
        {
            Some(v) => *v += value,
            None if value != 0.0 => self.missed += 1,
            None => {}
        }
    }

    /// Number of non-zero values dropped because their entry is not in the pattern.
    pub fn missed(&self) -> usize {
        self.missed
    }
}

/// The augmented Jacobian 𝒥 of a formulation written as y' = g(t, y, z), 0 = k(t, y, z) (module
/// documentation), over a fixed sparsity pattern. The first n rows and columns are the states y
/// in the formulation's order, the last m the algebraic unknowns z.
///
/// Reached through [`Formulation::sparse_jacobian`](super::Formulation::sparse_jacobian);
/// wrappers that forward [`Formulation::jacobian`](super::Formulation::jacobian) forward this
/// too, or the implicit methods fall back to the dense Jacobian for them.
pub trait SparseJacobian {
    /// Number m of algebraic unknowns z (0: 𝒥 is J itself).
    fn n_algebraic(&self) -> usize;

    /// The structural non-zeros of 𝒥, of dimension n + m: every entry that
    /// [`SparseJacobian::jacobian_values`] may make non-zero at any state, and the whole
    /// diagonal. Fixed for the formulation's life; computed on each call (once per run).
    fn jacobian_pattern(&self) -> SparsePattern;

    /// Writes 𝒥 at (t, y) into `values` (length `jacobian_pattern().nnz()`, in its order).
    /// Returns the number of RHS calls made (0 for an analytic 𝒥). Fails as
    /// [`Formulation::rhs`](super::Formulation::rhs) does at (t, y).
    fn jacobian_values(
        &self,
        t: f64,
        y: &[f64],
        values: &mut [f64],
    ) -> Result<usize, FormulationError>;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pattern_sorts_and_merges_entries() {
        let p = SparsePattern::from_entries(3, [(2, 0), (0, 0), (2, 0), (1, 2), (0, 2)]);
        assert_eq!(p.col_ptr(), &[0, 2, 2, 4]);
        assert_eq!(p.row_idx(), &[0, 2, 0, 1]);
        assert_eq!(p.nnz(), 4);
        assert_eq!(p.position(2, 0), Some(1));
        assert_eq!(p.position(1, 2), Some(3));
        assert_eq!(p.position(1, 0), None, "not in the pattern");
        assert_eq!(p.position(0, 1), None, "empty column");
        assert_eq!(p.position(0, 3), None, "outside the matrix");
        assert!(p.rows_of(7).is_empty());
    }

    #[test]
    fn scatter_counts_entries_outside_the_pattern() {
        let p = SparsePattern::from_entries(2, [(0, 0), (1, 1)]);
        let mut values = vec![9.0; 2];
        let mut s = Scatter::new(&p, &mut values);
        s.add(0, 0, 1.5);
        s.add(0, 0, 0.5);
        s.add(1, 0, 0.0); // a structural zero written as zero: fine
        s.add(1, 0, 3.0); // outside
        assert_eq!(s.missed(), 1);
        assert_eq!(values, [2.0, 0.0]);
    }
}
