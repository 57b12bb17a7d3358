//! Sparse LU of a square matrix with a fixed pattern, for the dependent block Φ_qD of a large
//! linkage: the symbolic analysis once, then one numeric factorisation per evaluation.
//!
//! [`SparseLu::analyse`] takes the pattern (compressed sparse columns) and computes the
//! fill-reducing column ordering (COLAMD, ref. 1) once; the pattern of Φ_qD changes only when the
//! partition does, so every later [`SparseLu::factor`] reuses it and only fills in the values.
//! The numeric factorisation is faer's simplicial left-looking LU with partial pivoting
//! (Gilbert–Peierls, ref. 2): its cost is proportional to the flops of the factors, which for a
//! linkage (every row touches at most two bodies, and a chain or a tree of loops fills in along
//! its length only) is linear in the number of bodies. The supernodal variant pays off for
//! factors with dense blocks, which planar linkages do not have.
//!
//! After the first, a factorisation reuses the row pivots and fill pattern of the last one with
//! pivoting (`src/linalg/sparse_refactor.rs`: no search for the pattern) as long as every
//! kept pivot is still one partial pivoting could choose (the largest in its column, or equal
//! to it) and is not singular to working precision; otherwise faer pivots again and its
//! factors are kept. On the 40-loop chain (20 s, defaults) 2 350 of 7 847 factorisations
//! pivoted again, and the run took 3.24 G instructions instead of 4.29 G.
//!
//! All buffers (factors, permutations, faer's scratch) are allocated on the first factorisation
//! and reused: the factors only grow, so after the first evaluation the numeric work allocates
//! nothing.
//!
//! # References
//! 1. T. A. Davis, J. R. Gilbert, S. I. Larimore, E. G. Ng, A column approximate minimum degree
//!    ordering algorithm, *ACM Transactions on Mathematical Software* 30 (2004) 353–376.
//! 2. J. R. Gilbert, T. Peierls, Sparse partial pivoting in time proportional to arithmetic
//!    operations, *SIAM Journal on Scientific and Statistical Computing* 9 (1988) 862–874.

use crate::linalg::dense_lu::SINGULAR_PIVOT;
use crate::linalg::sparse_lu::{SparseLuAnalysis, SparseLuFactors, is_square_pattern};
use crate::linalg::sparse_refactor::PivotCheck;
use faer::dyn_stack::{MemStack, StackReq};
use std::mem::MaybeUninit;

/// Why [`SparseLu::analyse`] could not prepare a factorisation.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum AnalyseError {
    /// The pattern is not a valid square CSC pattern with sorted, unique row indices.
    BadPattern,
    /// faer could not allocate its workspace.
    OutOfMemory,
}

/// faer's workspace: plain bytes, allocated once (sized for an unaligned start), and cloned
/// with the formulation.
#[derive(Clone)]
struct Scratch(Vec<MaybeUninit<u8>>);

impl Scratch {
    fn new(req: StackReq) -> Result<Self, AnalyseError> {
        let len = req.unaligned_bytes_required();
        let mut bytes = Vec::new();
        bytes
            .try_reserve_exact(len)
            .map_err(|_| AnalyseError::OutOfMemory)?;
        bytes.resize(len, MaybeUninit::uninit());
        Ok(Scratch(bytes))
    }

    fn stack(&mut self) -> &mut MemStack {
        MemStack::new(&mut self.0)
    }
}

impl std::fmt::Debug for Scratch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Scratch({} bytes)", self.0.len())
    }
}

/// Kept pivots that partial pivoting could have chosen only: near a singular position (a chain
/// at its flat position) the accelerations see the round-off of this solve amplified by 1/s²,
/// and Radau5's threshold of 0.1 moved the 10-loop chain's error at rtol 1e-10 from 1.8e-7 to
/// 5.0e-6 m (`tests/nfourbar_chain_generalized.rs`).
const KEPT_PIVOTS: PivotCheck = PivotCheck(1.0);

/// LU factors of an n × n sparse matrix with a fixed pattern (see the module documentation):
/// the analysis and the factors of `linalg::sparse_lu`, with the singularity test of
/// the dense [`crate::linalg::dense_lu::factor`].
#[derive(Debug, Clone)]
pub struct SparseLu {
    n: usize,
    analysis: SparseLuAnalysis,
    factors: SparseLuFactors<f64>,
    scratch: Scratch,
}

impl SparseLu {
    /// The symbolic analysis of the n × n pattern (`col_ptr`: n + 1 offsets into `row_idx`,
    /// row indices sorted and unique within each column): COLAMD column ordering and the
    /// workspace for factorisations.
    pub fn analyse(
        n: usize,
        col_ptr: Vec<usize>,
        row_idx: Vec<usize>,
    ) -> Result<Self, AnalyseError> {
        // Checked here as well as in the analysis, to tell a bad pattern from a failed one.
        if !is_square_pattern(n, &col_ptr, &row_idx) {
            return Err(AnalyseError::BadPattern);
        }
        let analysis =
            SparseLuAnalysis::new(n, col_ptr, row_idx).ok_or(AnalyseError::OutOfMemory)?;
        let scratch = Scratch::new(analysis.scratch::<f64>())?;
        Ok(SparseLu {
            n,
            factors: SparseLuFactors::new(&analysis, KEPT_PIVOTS),
            analysis,
            scratch,
        })
    }

    /// Order n of the matrix.
    pub fn n(&self) -> usize {
        self.n
    }

    /// The values, in the order of the pattern given to [`SparseLu::analyse`].
    pub fn values_mut(&mut self) -> &mut [f64] {
        self.factors.values_mut()
    }

    /// Numeric LU of the current values. Fails with the original index of the row whose pivot
    /// is below [`SINGULAR_PIVOT`] times the largest entry, or NaN (singular to working
    /// precision, as the dense [`crate::linalg::dense_lu::factor`]).
    pub fn factor(&mut self) -> Result<(), usize> {
        if self.n == 0 {
            return Ok(());
        }
        let scale = self
            .factors
            .values_mut()
            .iter()
            .fold(0.0_f64, |s, x| s.max(x.abs()));
        if !scale.is_finite() {
            return Err(0);
        }
        let regular = |pivot: f64| !pivot.is_nan() && pivot.abs() > SINGULAR_PIVOT * scale;
        self.factors
            .factor_accepting(&self.analysis, self.scratch.stack(), regular)
            .map_err(|e| e.row)
    }

    /// Solves A x = b in place (`b` becomes x) with the factors of the last successful
    /// [`SparseLu::factor`].
    pub fn solve(&mut self, b: &mut [f64]) {
        self.solve_columns(b, 1);
    }

    /// Solves A X = B in place for `ncols` right-hand sides stored column after column in `b`
    /// (n · ncols values), one after the other. Without factors (the last factorisation
    /// failed): NaN, not stale numbers.
    pub fn solve_columns(&mut self, b: &mut [f64], ncols: usize) {
        let n = self.n;
        if n == 0 || ncols == 0 {
            return;
        }
        // The callers size b as n × ncols; a shorter b solves the whole columns it holds.
        debug_assert!(b.len() >= n * ncols, "the caller sizes b as n × ncols");
        let ncols = ncols.min(b.len() / n);
        for column in b[..n * ncols].chunks_mut(n) {
            self.factors.solve(&self.analysis, column);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// CSC pattern and values of a dense row-major matrix's non-zeros.
    fn csc(a: &[f64], n: usize) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
        let (mut ptr, mut idx, mut val) = (vec![0], Vec::new(), Vec::new());
        for j in 0..n {
            for i in 0..n {
                if a[i * n + j] != 0.0 {
                    idx.push(i);
                    val.push(a[i * n + j]);
                }
            }
            ptr.push(idx.len());
        }
        (ptr, idx, val)
    }

    #[test]
    fn solves_a_system_that_needs_a_row_swap_and_reuses_the_analysis() {
        // a₀₀ = 0: without a row swap the elimination divides by zero.
        let a0 = [0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0];
        let (ptr, idx, val) = csc(&a0, 3);
        let mut lu = SparseLu::analyse(3, ptr, idx).unwrap_or_else(|e| panic!("{e:?}"));
        for scale in [1.0, -2.5] {
            // The same pattern with new values: the analysis is reused.
            for (v, w) in lu.values_mut().iter_mut().zip(&val) {
                *v = scale * w;
            }
            assert_eq!(lu.factor(), Ok(()));
            let x_true = [1.0, -2.0, 0.5, 3.0, 0.0, -1.0];
            let mut b = vec![0.0; 6];
            for (col, x) in x_true.chunks(3).enumerate() {
                for i in 0..3 {
                    b[3 * col + i] = (0..3).map(|j| scale * a0[i * 3 + j] * x[j]).sum();
                }
            }
            lu.solve_columns(&mut b, 2);
            for (k, (x, e)) in b.iter().zip(&x_true).enumerate() {
                // Data of size 1, condition number ~10: round-off only.
                assert!((x - e).abs() < 1e-14, "scale {scale}, x[{k}] = {x} vs {e}");
            }
        }
    }

    #[test]
    fn new_values_are_solved_whether_the_kept_pivots_do_or_not() {
        // One pattern, a sequence of values that move the largest entry of each column around:
        // some factorisations keep the last pivots, others must pivot again; every solve is
        // exact to round-off either way.
        let pattern = [1.0, 1.0, 1.0, 1.0, 1.0, 0.0, 1.0, 0.0, 1.0];
        let (ptr, idx, _) = csc(&pattern, 3);
        let mut lu = SparseLu::analyse(3, ptr, idx).unwrap_or_else(|e| panic!("{e:?}"));
        for k in 0..12 {
            let t = k as f64;
            let a = [
                (0.9 * t).sin() * 3.0,
                1.0 + (0.4 * t).cos(),
                2.0 - (1.3 * t).sin(),
                (0.7 * t).cos() * 2.0,
                1.5,
                0.0,
                1.0 + (1.1 * t).sin(),
                0.0,
                (0.3 * t).cos() - 2.0,
            ];
            // The values in the pattern's order (a zero value stays a structural entry).
            let val: Vec<f64> = (0..3)
                .flat_map(|j| (0..3).map(move |i| (i, j)))
                .filter(|&(i, j)| pattern[i * 3 + j] != 0.0)
                .map(|(i, j)| a[i * 3 + j])
                .collect();
            lu.values_mut().copy_from_slice(&val);
            assert_eq!(lu.factor(), Ok(()), "values {k}");
            let x_true = [1.0, -2.0, 0.5];
            let mut b: Vec<f64> = (0..3)
                .map(|i| (0..3).map(|j| a[i * 3 + j] * x_true[j]).sum())
                .collect();
            lu.solve(&mut b);
            for (i, (x, e)) in b.iter().zip(&x_true).enumerate() {
                assert!((x - e).abs() < 1e-13, "values {k}: x[{i}] = {x} vs {e}");
            }
        }
        // Both paths were taken (the counts, as measured: the sequence is fixed).
        let (pivoting, refactorisations) = lu.factors.counts();
        assert!(
            refactorisations > 0 && pivoting > 1,
            "{refactorisations} refactorisations, {pivoting} with pivoting"
        );
        assert_eq!(refactorisations + pivoting, 12);
    }

    #[test]
    fn a_singular_matrix_is_refused_with_a_row() {
        // Row 1 = 2 × row 0 (numerically singular, structurally not).
        let a = [1.0, 2.0, 2.0, 4.0];
        let (ptr, idx, val) = csc(&a, 2);
        let mut lu = SparseLu::analyse(2, ptr, idx).unwrap_or_else(|e| panic!("{e:?}"));
        lu.values_mut().copy_from_slice(&val);
        assert!(matches!(lu.factor(), Err(r) if r < 2));
        // Structurally singular: an empty column.
        let mut lu =
            SparseLu::analyse(2, vec![0, 2, 2], vec![0, 1]).unwrap_or_else(|e| panic!("{e:?}"));
        lu.values_mut().copy_from_slice(&[1.0, 1.0]);
        assert!(lu.factor().is_err());
        // NaN.
        let (ptr, idx, _) = csc(&[1.0, 0.0, 0.0, 1.0], 2);
        let mut lu = SparseLu::analyse(2, ptr, idx).unwrap_or_else(|e| panic!("{e:?}"));
        lu.values_mut().copy_from_slice(&[1.0, f64::NAN]);
        assert!(lu.factor().is_err());
    }

    #[test]
    fn a_bad_pattern_is_an_error_not_a_panic() {
        assert_eq!(
            SparseLu::analyse(2, vec![0, 2, 1], vec![0, 1]).err(),
            Some(AnalyseError::BadPattern)
        );
        assert_eq!(
            SparseLu::analyse(2, vec![0, 2, 3], vec![1, 0, 5]).err(),
            Some(AnalyseError::BadPattern)
        );
    }
}
