//! A square sparse LU for matrices of one pattern factored again and again: the pattern analysed
//! once ([`SparseLuAnalysis`]: faer's COLAMD column order), each factorisation with the kept
//! pivots of the last pivoting one where they pass their check ([`super::sparse_refactor`]),
//! otherwise faer's left-looking LU with partial pivoting (simplicial), whose factors are kept.
//!
//! Users: Radau5's real and complex Newton matrices (`solve/radau5/sparse.rs`) and IDA's
//! iteration matrix on large models (`solve/ida/sparse.rs`, feature `ida`).
//!
//! Why simplicial and not supernodal: the factors of a linkage's Newton matrices stay nearly as
//! sparse as the matrix, and supernodes do not pay at the sizes met. Measured per real
//! factorisation on the N-four-bar chain (DAE, Radau5's augmented matrix; loaded 2-core
//! machine): 40 loops (971 unknowns, 8 450 non-zeros, 15 550 in L + U) 320 µs simplicial,
//! 350 µs supernodal, 310 µs with faer's own choice; 80 loops 670 / 820 / 680 µs; 10 loops
//! 80 / 97 / 75 µs; only at 200 loops (4 811 unknowns) do the supernodes gain, 1 950 / 1 770 /
//! 1 660 µs. The simplicial factor also shows its pivots, which the singularity check reads.
//!
//! **Singularity**: faer picks the largest remaining entry of each column as its pivot even when
//! it is zero; a zero or non-finite pivot is reported as [`SingularColumn`].

use super::sparse_refactor::{Entry, FixedPivotLu, PivotCheck};
use faer::dyn_stack::{MemStack, StackReq};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::lu::simplicial::{
    SimplicialLu, factorize_simplicial_numeric_lu, factorize_simplicial_numeric_lu_scratch,
};
use faer::sparse::linalg::lu::{LuSymbolicParams, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};

/// The pattern of a square sparse matrix (compressed columns) and its fill-reducing column
/// order, computed once for every factorisation of matrices of that pattern.
#[derive(Debug, Clone)]
pub(crate) struct SparseLuAnalysis {
    pattern: SymbolicSparseColMat<usize>,
    symbolic: SymbolicLu<usize>,
}

impl SparseLuAnalysis {
    /// Analyses the `dim` × `dim` pattern with column pointers `col_ptr` (length dim + 1) and
    /// row indices `row_idx` (ascending and distinct within each column). `None` if the pattern
    /// is malformed or faer cannot analyse it (out of memory): the caller keeps a dense LU.
    pub(crate) fn new(dim: usize, col_ptr: Vec<usize>, row_idx: Vec<usize>) -> Option<Self> {
        if !is_square_pattern(dim, &col_ptr, &row_idx) {
            return None;
        }
        let pattern = SymbolicSparseColMat::new_checked(dim, dim, col_ptr, None, row_idx);
        let symbolic = factorize_symbolic_lu(
            pattern.as_ref(),
            LuSymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
                ..Default::default()
            },
        )
        .ok()?;
        Some(SparseLuAnalysis { pattern, symbolic })
    }

    /// Dimension of the matrices.
    pub(crate) fn dim(&self) -> usize {
        self.pattern.nrows()
    }

    /// Number of structural non-zeros: the length of [`SparseLuFactors::values_mut`].
    pub(crate) fn nnz(&self) -> usize {
        self.pattern.row_idx().len()
    }

    /// faer's scratch for factorising matrices of entry type `T` of this pattern.
    pub(crate) fn scratch<T: Entry>(&self) -> StackReq {
        factorize_simplicial_numeric_lu_scratch::<usize, T>(self.dim(), self.dim())
    }

    /// The compressed-column pattern (for products with the stored values).
    #[cfg(test)]
    pub(crate) fn pattern(&self) -> &SymbolicSparseColMat<usize> {
        &self.pattern
    }

    fn col_perm(&self) -> &[usize] {
        self.symbolic.col_perm().arrays().0
    }
}

/// Whether (`col_ptr`, `row_idx`) is a `dim` × `dim` compressed-column pattern: dim + 1
/// non-decreasing offsets from 0 to the number of entries, and row indices below dim, ascending
/// and distinct within each column.
pub(crate) fn is_square_pattern(dim: usize, col_ptr: &[usize], row_idx: &[usize]) -> bool {
    col_ptr.len() == dim + 1
        && col_ptr.first() == Some(&0)
        && col_ptr.last() == Some(&row_idx.len())
        && col_ptr.windows(2).all(|w| {
            w[0] <= w[1]
                && row_idx.get(w[0]..w[1]).is_some_and(|rows| {
                    rows.windows(2).all(|r| r[0] < r[1]) && rows.iter().all(|&i| i < dim)
                })
        })
}

/// A factorisation failed at elimination step `column`: its pivot is zero, not finite or
/// refused by the caller's test; `row` is the row of the matrix it was taken from (the step
/// itself where faer found no pivot at all).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct SingularColumn {
    pub column: usize,
    pub row: usize,
}

/// The values of one matrix over a [`SparseLuAnalysis`]'s pattern and their LU factors.
#[derive(Debug, Clone)]
pub(crate) struct SparseLuFactors<T> {
    lu: SimplicialLu<usize, T>,
    row_fwd: Vec<usize>,
    row_inv: Vec<usize>,
    /// The last accepted factors; `None` before the first pivoting factorisation.
    fixed: Option<FixedPivotLu<T>>,
    values: Vec<T>,
    check: PivotCheck,
    factored: bool,
    pivoting_factorisations: usize,
    refactorisations: usize,
}

impl<T: Entry> SparseLuFactors<T> {
    /// No factors yet, zero values over `analysis`'s pattern; kept pivots are accepted by
    /// `check`.
    pub(crate) fn new(analysis: &SparseLuAnalysis, check: PivotCheck) -> Self {
        let dim = analysis.dim();
        SparseLuFactors {
            lu: SimplicialLu::new(),
            row_fwd: vec![0; dim],
            row_inv: vec![0; dim],
            fixed: None,
            values: vec![T::zero(); analysis.nnz()],
            check,
            factored: false,
            pivoting_factorisations: 0,
            refactorisations: 0,
        }
    }

    /// The matrix values in the pattern's order, to be written before [`Self::factor`].
    pub(crate) fn values_mut(&mut self) -> &mut [T] {
        self.factored = false;
        &mut self.values
    }

    /// The values last written.
    #[cfg(test)]
    pub(crate) fn values(&self) -> &[T] {
        &self.values
    }

    /// Factorisations with pivoting (faer) and with the kept pivots, in that order.
    #[cfg(test)]
    pub(crate) fn counts(&self) -> (usize, usize) {
        (self.pivoting_factorisations, self.refactorisations)
    }

    /// Factorises the values: with the kept pivots if every one passes the check, else by faer
    /// with partial pivoting, whose pivots are checked for zero or NaN and whose factors are
    /// kept for the next time. `stack` holds at least [`SparseLuAnalysis::scratch`].
    pub(crate) fn factor(
        &mut self,
        analysis: &SparseLuAnalysis,
        stack: &mut MemStack,
    ) -> Result<(), SingularColumn> {
        self.factor_accepting(analysis, stack, |_| true)
    }

    /// [`Self::factor`] with a further test every pivot must pass (`regular`), on both paths:
    /// kept pivots that fail it are factorised again with pivoting, and a pivoting
    /// factorisation with a pivot that fails it is [`SingularColumn`].
    pub(crate) fn factor_accepting(
        &mut self,
        analysis: &SparseLuAnalysis,
        stack: &mut MemStack,
        regular: impl Fn(T) -> bool,
    ) -> Result<(), SingularColumn> {
        self.factored = false;
        let matrix = SparseColMatRef::new(analysis.pattern.as_ref(), &self.values);
        if let Some(fixed) = &mut self.fixed
            && fixed
                .refactor(matrix, analysis.col_perm(), self.check)
                .is_ok()
            && fixed.pivots().all(|&p| regular(p))
        {
            self.refactorisations += 1;
            self.factored = true;
            return Ok(());
        }
        self.pivoting_factorisations += 1;
        // On any failure below the kept factors stay those of the last successful pivoting
        // factorisation: a refactorisation recomputes every value from the matrix, so they
        // serve the next attempt as well as before.
        if let Err(e) = factorize_simplicial_numeric_lu(
            &mut self.row_fwd,
            &mut self.row_inv,
            &mut self.lu,
            matrix,
            analysis.symbolic.col_perm(),
            stack,
        ) {
            let column = match e {
                faer::sparse::linalg::LuError::SymbolicSingular { index } => {
                    index.min(analysis.dim().saturating_sub(1))
                }
                faer::sparse::linalg::LuError::Generic(_) => 0,
            };
            return Err(SingularColumn {
                column,
                row: column,
            });
        }
        // faer stores the diagonal of U last in each of its columns and accepts a zero pivot
        // (the largest of a column of zeros): the test is ours. A NaN pivot fails it too.
        let u = self.lu.u_factor_unsorted();
        let bad = (0..analysis.dim()).find(|&j| {
            let pivot = u.val_of_col(j).last().copied().unwrap_or(T::zero());
            let size = pivot.modulus();
            size.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater)
                || size.is_infinite()
                || !regular(pivot)
        });
        if let Some(column) = bad {
            return Err(SingularColumn {
                column,
                row: self.row_fwd.get(column).copied().unwrap_or(column),
            });
        }
        self.fixed
            .get_or_insert_with(FixedPivotLu::default)
            .copy_from_faer(&self.lu, &self.row_fwd, &self.row_inv);
        self.factored = true;
        Ok(())
    }

    /// Solves A x = b in place (b of the matrix's dimension). Without factors from a successful
    /// [`Self::factor`] since the values were last written, `b` becomes NaN (never stale
    /// numbers) and the answer is `false`.
    pub(crate) fn solve(&mut self, analysis: &SparseLuAnalysis, b: &mut [T]) -> bool {
        match &mut self.fixed {
            Some(fixed) if self.factored => {
                fixed.solve(b, analysis.col_perm());
                true
            }
            _ => {
                b.fill(T::nan_impl());
                false
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [[4, 1, 0], [0, 3, 2], [1, 0, 5]] in compressed columns.
    fn three() -> (SparseLuAnalysis, Vec<f64>) {
        let col_ptr = vec![0, 2, 4, 6];
        let row_idx = vec![0, 2, 0, 1, 1, 2];
        let values = vec![4.0, 1.0, 1.0, 3.0, 2.0, 5.0];
        let Some(analysis) = SparseLuAnalysis::new(3, col_ptr, row_idx) else {
            panic!("analysis failed");
        };
        (analysis, values)
    }

    #[test]
    fn solves_refactorises_and_reports_singularity() -> Result<(), SingularColumn> {
        let (analysis, values) = three();
        let mut lu = SparseLuFactors::<f64>::new(&analysis, PivotCheck(0.1));
        let mut buffer = faer::dyn_stack::MemBuffer::new(analysis.scratch::<f64>());
        let scratch = MemStack::new(&mut buffer);
        lu.values_mut().copy_from_slice(&values);
        lu.factor(&analysis, scratch)?;
        // x = (1, −1, 2): A x = (4 − 1, −3 + 4, 1 + 10) = (3, 1, 11).
        let mut b = [3.0, 1.0, 11.0];
        assert!(lu.solve(&analysis, &mut b));
        for (x, e) in b.iter().zip([1.0, -1.0, 2.0]) {
            assert!((x - e).abs() < 1e-15, "{b:?}");
        }
        // Same pattern, doubled values: refactorised with the kept pivots, x halves.
        for (v, w) in lu.values_mut().iter_mut().zip(&values) {
            *v = 2.0 * w;
        }
        lu.factor(&analysis, scratch)?;
        assert_eq!(lu.counts(), (1, 1));
        let mut b = [3.0, 1.0, 11.0];
        assert!(lu.solve(&analysis, &mut b));
        for (x, e) in b.iter().zip([0.5, -0.5, 1.0]) {
            assert!((x - e).abs() < 1e-15, "{b:?}");
        }
        // Values written, not factored: NaN, not the old solution.
        lu.values_mut().fill(0.0);
        let mut b = [1.0, 1.0, 1.0];
        assert!(!lu.solve(&analysis, &mut b));
        assert!(b.iter().all(|x| x.is_nan()));
        // All zero: singular, and still no stale solve.
        assert!(lu.factor(&analysis, scratch).is_err());
        assert!(!lu.solve(&analysis, &mut b));
        Ok(())
    }
}
