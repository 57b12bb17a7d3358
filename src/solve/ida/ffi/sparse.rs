//! IDA's sparse direct linear solver: a SUNDIALS compressed-column matrix (`SUNSparseMatrix`)
//! that the Jacobian callback fills over the residual form's fixed pattern, and a custom
//! `SUNLinearSolver` of type DIRECT that factors it with faer ([`SparseLuFactors`]: the
//! column order analysed once, then the kept pivots of the last pivoting factorisation while
//! they pass their check), the way SUNDIALS' own KLU module works, without SuiteSparse.
//!
//! IDA drives it as any matrix-based direct solver: at each of its `lsetup` calls (new
//! Jacobian: IDA decides when, from its convergence rate and the change of c) it zeroes the
//! matrix, calls the Jacobian callback, then `setup` here, which factors; `solve` solves with
//! the factors of the last setup, and IDA rescales the solution when c has changed since
//! (its `scalesol`, on for matrix-based solvers). A zero pivot is reported as
//! `SUNLS_LUFACT_FAIL`, recoverable, as SUNDIALS' dense LU reports it: IDA retries with a
//! smaller step.

use super::{slice, sun};
use crate::formulation::sparse_jacobian::SparsePattern;
use crate::linalg::sparse_lu::{SparseLuAnalysis, SparseLuFactors};
use crate::linalg::sparse_refactor::PivotCheck;
use faer::dyn_stack::{MemBuffer, MemStack};
use std::ffi::{c_int, c_void};
use std::panic::{AssertUnwindSafe, catch_unwind};

/// The kept pivots' check: UMFPACK's threshold, as Radau5's sparse LU uses.
const KEPT_PIVOTS: PivotCheck = PivotCheck(0.1);

/// The content of the custom linear solver.
pub(super) struct SparseSystem {
    /// The pattern in SUNDIALS' index type, written back into the matrix before each
    /// factorisation (IDA's `SUNMatZero` clears the indices with the values).
    col_ptr: Vec<sun::sunindextype>,
    row_idx: Vec<sun::sunindextype>,
    analysis: SparseLuAnalysis,
    factors: SparseLuFactors<f64>,
    scratch: MemBuffer,
}

impl SparseSystem {
    /// Analyses `pattern` (square, dimension N); `None` if faer cannot, or an index does not fit
    /// SUNDIALS' index type: the caller keeps the dense solver.
    pub(super) fn new(pattern: &SparsePattern) -> Option<Self> {
        let to_index = |v: &[usize]| -> Option<Vec<sun::sunindextype>> {
            v.iter()
                .map(|&x| sun::sunindextype::try_from(x).ok())
                .collect()
        };
        let col_ptr = to_index(pattern.col_ptr())?;
        let row_idx = to_index(pattern.row_idx())?;
        let analysis = SparseLuAnalysis::new(
            pattern.dim(),
            pattern.col_ptr().to_vec(),
            pattern.row_idx().to_vec(),
        )?;
        let scratch = MemBuffer::try_new(analysis.scratch::<f64>()).ok()?;
        Some(SparseSystem {
            col_ptr,
            row_idx,
            factors: SparseLuFactors::new(&analysis, KEPT_PIVOTS),
            analysis,
            scratch,
        })
    }

    /// Number of structural non-zeros.
    pub(super) fn nnz(&self) -> usize {
        self.analysis.nnz()
    }

    /// Writes the pattern into the compressed-column matrix `a` (of this pattern's size).
    ///
    /// # Safety
    /// `a` is a live CSC `SUNSparseMatrix` with N columns and room for `nnz` entries.
    unsafe fn write_pattern(&self, a: sun::SUNMatrix) {
        // SAFETY: per the function's contract.
        unsafe {
            let ptrs = sun::SUNSparseMatrix_IndexPointers(a);
            let rows = sun::SUNSparseMatrix_IndexValues(a);
            std::slice::from_raw_parts_mut(ptrs, self.col_ptr.len()).copy_from_slice(&self.col_ptr);
            std::slice::from_raw_parts_mut(rows, self.row_idx.len()).copy_from_slice(&self.row_idx);
        }
    }
}

/// Creates the compressed-column matrix of `system`'s pattern.
///
/// # Safety
/// `ctx` is a live SUNDIALS context. The result is NULL or owned by the caller
/// (`SUNMatDestroy`).
pub(super) unsafe fn new_matrix(system: &SparseSystem, ctx: sun::SUNContext) -> sun::SUNMatrix {
    let Ok(n) = sun::sunindextype::try_from(system.analysis.dim()) else {
        return std::ptr::null_mut();
    };
    let Ok(nnz) = sun::sunindextype::try_from(system.nnz()) else {
        return std::ptr::null_mut();
    };
    // SAFETY: per the function's contract; the pattern is written only into a matrix made.
    unsafe {
        let a = sun::SUNSparseMatrix(n, n, nnz, sun::CSC_MAT as c_int, ctx);
        if !a.is_null() {
            system.write_pattern(a);
        }
        a
    }
}

/// Creates the custom linear solver owning `system`.
///
/// # Safety
/// `ctx` is a live SUNDIALS context. The result is NULL or owned by the caller
/// (`SUNLinSolFree`, which drops `system`).
pub(super) unsafe fn new_solver(
    system: Box<SparseSystem>,
    ctx: sun::SUNContext,
) -> sun::SUNLinearSolver {
    // SAFETY: per the function's contract; `SUNLinSolNewEmpty` allocates the ops table, which
    // is filled before the solver is handed out.
    unsafe {
        let ls = sun::SUNLinSolNewEmpty(ctx);
        if ls.is_null() {
            return ls;
        }
        let ops = (*ls).ops;
        (*ops).gettype = Some(get_type);
        (*ops).getid = Some(get_id);
        (*ops).setup = Some(setup);
        (*ops).solve = Some(solve);
        (*ops).free = Some(free);
        (*ls).content = Box::into_raw(system).cast::<c_void>();
        ls
    }
}

/// The solver's content.
///
/// # Safety
/// `ls` is a solver made by [`new_solver`] and not yet freed; no other reference to its
/// content is alive.
unsafe fn system<'a>(ls: sun::SUNLinearSolver) -> Option<&'a mut SparseSystem> {
    // SAFETY: per the function's contract.
    unsafe {
        let content = (*ls).content.cast::<SparseSystem>();
        content.as_mut()
    }
}

unsafe extern "C" fn get_type(_ls: sun::SUNLinearSolver) -> sun::SUNLinearSolver_Type {
    sun::SUNLinearSolver_Type_SUNLINEARSOLVER_DIRECT
}

unsafe extern "C" fn get_id(_ls: sun::SUNLinearSolver) -> sun::SUNLinearSolver_ID {
    sun::SUNLinearSolver_ID_SUNLINEARSOLVER_CUSTOM
}

/// Factors the matrix the Jacobian callback just filled.
unsafe extern "C" fn setup(ls: sun::SUNLinearSolver, a: sun::SUNMatrix) -> c_int {
    catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: IDA passes our solver and the sparse matrix of its pattern (made by
        // `new_matrix` for this solver), with `nnz` values.
        unsafe {
            let Some(sys) = system(ls) else {
                return -1;
            };
            sys.write_pattern(a);
            let values = std::slice::from_raw_parts(sun::SUNSparseMatrix_Data(a), sys.nnz());
            sys.factors.values_mut().copy_from_slice(values);
            match sys
                .factors
                .factor(&sys.analysis, MemStack::new(&mut sys.scratch))
            {
                Ok(()) => 0,
                Err(_) => sun::SUNLS_LUFACT_FAIL as c_int,
            }
        }
    }))
    .unwrap_or(-1)
}

/// x = A⁻¹ b with the factors of the last setup.
unsafe extern "C" fn solve(
    ls: sun::SUNLinearSolver,
    _a: sun::SUNMatrix,
    x: sun::N_Vector,
    b: sun::N_Vector,
    _tol: f64,
) -> c_int {
    catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: IDA passes serial vectors of length N, x and b distinct.
        unsafe {
            let Some(sys) = system(ls) else {
                return -1;
            };
            let n = sys.analysis.dim();
            let x = slice(x, n);
            x.copy_from_slice(slice(b, n));
            if sys.factors.solve(&sys.analysis, x) {
                0
            } else {
                sun::SUNLS_PACKAGE_FAIL_REC as c_int
            }
        }
    }))
    .unwrap_or(-1)
}

/// Drops the content, then frees the ops table and the solver.
unsafe extern "C" fn free(ls: sun::SUNLinearSolver) -> sun::SUNErrCode {
    if ls.is_null() {
        return 0;
    }
    // SAFETY: `ls` was made by `new_solver`; its content is the boxed system, taken once.
    unsafe {
        let content = (*ls).content.cast::<SparseSystem>();
        if !content.is_null() {
            drop(Box::from_raw(content));
            (*ls).content = std::ptr::null_mut();
        }
        sun::SUNLinSolFreeEmpty(ls);
    }
    0
}
