//! The one safe wrapper around SUNDIALS IDA (`sundials-sys`): the only `unsafe` code of linkdyn.
//!
//! The library linked is IDAS, IDA with quadratures and sensitivities (same solver, same
//! names; `sundials-sys` feature `idas`): the bookkeeping integrals are IDAS quadratures
//! (`IDAQuadInit`, out of the error test), which IDA alone does not offer.
//!
//! [`Ida`] owns a SUNDIALS context, the IDA memory, the vectors Y, Ẏ, the id vector and the
//! quadratures, the matrix and linear solver (dense, or sparse: `sparse.rs`); [`Drop`] frees them in reverse order of creation. Every
//! return flag becomes an [`IdaFailure`] with the flag's name, its meaning
//! ([`flag_meaning`]) and IDA's own message (captured by an error handler pushed on the context,
//! so nothing is printed on stderr). The callbacks (residual, Jacobian, error weights) call a
//! [`Problem`] through a pointer that is set only for the duration of [`Ida::solve_one_step`];
//! they catch panics (`catch_unwind`) so that no unwinding crosses the C boundary, and answer
//! IDA's convention: 0 success, > 0 recoverable (IDA retries with a smaller step), < 0 fatal.

mod sparse;

use crate::formulation::sparse_jacobian::SparsePattern;
use std::ffi::{CStr, c_char, c_int, c_long, c_void};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::ptr;

use sundials_sys as sun;

/// What a callback of [`Problem`] reports back to IDA.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Callback {
    /// Evaluated.
    Ok,
    /// Failed at this trial point, a smaller step may avoid it (IDA retries).
    Recoverable,
    /// Failed for good (IDA stops with a fatal flag).
    Fatal,
}

impl Callback {
    fn code(self) -> c_int {
        match self {
            Callback::Ok => 0,
            Callback::Recoverable => 1,
            Callback::Fatal => -1,
        }
    }
}

/// The equations, as IDA's callbacks see them. Slices have length N (the Jacobian: N², column-major).
pub(super) trait Problem {
    /// F(t, Y, Ẏ) into `res`.
    fn residual(&mut self, t: f64, yy: &[f64], yp: &[f64], res: &mut [f64]) -> Callback;
    /// ∂F/∂Y + c ∂F/∂Ẏ into `jac` (column-major).
    fn jacobian(
        &mut self,
        t: f64,
        c: f64,
        yy: &[f64],
        yp: &[f64],
        res: &[f64],
        jac: &mut [f64],
    ) -> Callback;
    /// ∂F/∂Y + c ∂F/∂Ẏ into `values`, over the sparse pattern [`Ida::new`] was given.
    fn sparse_jacobian(
        &mut self,
        t: f64,
        c: f64,
        yy: &[f64],
        yp: &[f64],
        values: &mut [f64],
    ) -> Callback;
    /// Error weights (the reciprocals of the tolerated errors; 0 leaves a component out).
    fn weights(&mut self, yy: &[f64], ewt: &mut [f64]) -> Callback;
    /// Rates of the quadratures at a converged step into `out` (length n_Q).
    fn quadrature(&mut self, t: f64, yy: &[f64], yp: &[f64], out: &mut [f64]) -> Callback;
}

/// A failed IDA call: the flag by name, what it means and IDA's message.
#[derive(Debug, Clone)]
pub(super) struct IdaFailure {
    /// The flag's name ("IDA_CONV_FAIL").
    pub flag: String,
    /// Meaning and IDA's message.
    pub reason: String,
}

/// Result of one call of [`Ida::solve_one_step`].
#[derive(Debug, Clone, Copy)]
pub(super) struct StepReturn {
    /// Time reached.
    pub t: f64,
    /// Whether the stop time was reached (IDA_TSTOP_RETURN).
    pub at_stop: bool,
}

/// What a flag of IDA means, in a sentence (SUNDIALS 7 IDA user guide, §"IDASolve" and the
/// tables of return flags).
pub(super) fn flag_meaning(flag: c_int) -> &'static str {
    match flag {
        sun::IDA_TOO_MUCH_WORK => "IDA took too many internal steps before reaching the stop time",
        sun::IDA_TOO_MUCH_ACC => {
            "IDA could not satisfy the accuracy demanded (tolerances too tight)"
        }
        sun::IDA_ERR_FAIL => {
            "the error test failed repeatedly, or with |h| = hmin (a discontinuity or a singularity the step cannot resolve)"
        }
        sun::IDA_CONV_FAIL => {
            "the Newton iteration failed to converge repeatedly, or with |h| = hmin (a stiff transient, a poor Jacobian, or a singular constraint Jacobian)"
        }
        sun::IDA_LINIT_FAIL => "the linear solver's initialisation failed",
        sun::IDA_LSETUP_FAIL => {
            "the linear solver's setup failed: the iteration matrix is singular or the Jacobian could not be evaluated"
        }
        sun::IDA_LSOLVE_FAIL => "the linear solver's solve failed",
        sun::IDA_RES_FAIL => "the residual failed unrecoverably",
        sun::IDA_REP_RES_ERR => {
            "the residual failed recoverably again and again (a trial state the equations reject even with small steps)"
        }
        sun::IDA_RTFUNC_FAIL => "the root function failed",
        sun::IDA_CONSTR_FAIL => "the inequality constraints could not be met",
        sun::IDA_FIRST_RES_FAIL => "the first residual evaluation failed recoverably",
        sun::IDA_LINESEARCH_FAIL => "the line search of the initial-condition solver failed",
        sun::IDA_NO_RECOVERY => "a recoverable failure could not be recovered from",
        sun::IDA_NLS_INIT_FAIL => "the nonlinear solver's initialisation failed",
        sun::IDA_NLS_SETUP_FAIL => "the nonlinear solver's setup failed",
        sun::IDA_NLS_FAIL => "the nonlinear solver failed",
        sun::IDA_MEM_NULL => "the IDA memory is missing (an internal error of the wrapper)",
        sun::IDA_MEM_FAIL => "memory allocation failed",
        sun::IDA_ILL_INPUT => "an input to IDA was illegal",
        sun::IDA_NO_MALLOC => "IDA was not initialised (an internal error of the wrapper)",
        sun::IDA_BAD_EWT => "an error weight was not positive",
        sun::IDA_BAD_K => "the derivative order asked of the dense output is illegal",
        sun::IDA_BAD_T => "the time asked of the dense output lies outside the last step",
        sun::IDA_BAD_DKY => "the dense output vector is missing",
        sun::IDA_VECTOROP_ERR => "a vector operation failed",
        sun::IDA_QRHS_FAIL => {
            "the rate of a bookkeeping integral (quadrature) failed unrecoverably"
        }
        sun::IDA_FIRST_QRHS_ERR => {
            "the first rate of a bookkeeping integral (quadrature) failed recoverably"
        }
        sun::IDA_REP_QRHS_ERR => {
            "the rate of a bookkeeping integral (quadrature) failed recoverably again and again"
        }
        sun::IDA_NO_QUAD => "quadratures were not initialised (an internal error of the wrapper)",
        sun::IDA_CONTEXT_ERR => "the SUNDIALS context is invalid",
        _ => "unrecognised IDA return flag",
    }
}

/// The flag's name from IDA itself ("IDA_CONV_FAIL").
fn flag_name(flag: c_int) -> String {
    // SAFETY: IDAGetReturnFlagName returns a malloc'ed NUL-terminated string (or NULL), which
    // we copy and free.
    unsafe {
        let p = sun::IDAGetReturnFlagName(c_long::from(flag));
        if p.is_null() {
            return format!("IDA flag {flag}");
        }
        let name = CStr::from_ptr(p).to_string_lossy().into_owned();
        libc_free(p.cast());
        name
    }
}

unsafe extern "C" {
    #[link_name = "free"]
    fn libc_free(p: *mut c_void);
}

/// The pointer handed to IDA as user data during [`Ida::solve_one_step`].
type ProblemPtr<'a> = &'a mut dyn Problem;

/// An IDA integrator for N unknowns with a direct linear solver (dense, or sparse: `sparse.rs`)
/// and a user Jacobian.
pub(super) struct Ida {
    ctx: sun::SUNContext,
    mem: *mut c_void,
    yy: sun::N_Vector,
    yp: sun::N_Vector,
    id: sun::N_Vector,
    dky: sun::N_Vector,
    /// Quadratures (length n_Q; NULL when there are none) and their dense output.
    yq: sun::N_Vector,
    dkyq: sun::N_Vector,
    mat: sun::SUNMatrix,
    ls: sun::SUNLinearSolver,
    /// Whether `mat` and `ls` are the sparse matrix and solver (`sparse`), else dense.
    sparse: bool,
    n: usize,
    nq: usize,
    /// IDA's last error message. Boxed: the error handler holds the String's own address,
    /// which must not move when the `Ida` does.
    #[allow(clippy::box_collection)]
    message: Box<String>,
    initialised: bool,
}

/// Integrator counters of IDA.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(super) struct IdaCounts {
    pub steps: u64,
    pub residuals: u64,
    pub newton_iterations: u64,
    pub newton_failures: u64,
    pub jacobians: u64,
    pub error_test_failures: u64,
}

unsafe extern "C" fn error_handler(
    _line: c_int,
    func: *const c_char,
    _file: *const c_char,
    msg: *const c_char,
    _code: sun::SUNErrCode,
    user: *mut c_void,
    _ctx: sun::SUNContext,
) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        if user.is_null() || msg.is_null() {
            return;
        }
        // SAFETY: `user` is the Box<String> of the owning Ida, alive while its context is;
        // `msg` and `func` are NUL-terminated strings from SUNDIALS.
        unsafe {
            let target = &mut *user.cast::<String>();
            let func = if func.is_null() {
                String::new()
            } else {
                CStr::from_ptr(func).to_string_lossy().into_owned()
            };
            *target = format!("{func}: {}", CStr::from_ptr(msg).to_string_lossy().trim());
        }
    }));
}

/// The slice of an N_Vector (serial).
///
/// # Safety
/// `v` must be a live serial vector of length `n`, not aliased mutably for the slice's life.
unsafe fn slice<'a>(v: sun::N_Vector, n: usize) -> &'a mut [f64] {
    // SAFETY: per the function's contract.
    unsafe { std::slice::from_raw_parts_mut(sun::N_VGetArrayPointer(v), n) }
}

/// Recovers the problem from IDA's user data.
///
/// # Safety
/// `user` is null or the `*mut ProblemPtr` set by `solve_one_step`, alive during the call.
unsafe fn problem<'a>(user: *mut c_void) -> Option<&'a mut ProblemPtr<'a>> {
    if user.is_null() {
        None
    } else {
        // SAFETY: per the function's contract.
        Some(unsafe { &mut *user.cast::<ProblemPtr<'a>>() })
    }
}

unsafe extern "C" fn residual_cb(
    t: f64,
    yy: sun::N_Vector,
    yp: sun::N_Vector,
    rr: sun::N_Vector,
    user: *mut c_void,
) -> c_int {
    catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: IDA passes live serial vectors of its length N; user data as set by us.
        unsafe {
            let Some(p) = problem(user) else {
                return -1;
            };
            let n = sun::N_VGetLength(yy) as usize;
            p.residual(t, slice(yy, n), slice(yp, n), slice(rr, n))
                .code()
        }
    }))
    .unwrap_or(-1)
}

#[allow(clippy::too_many_arguments)] // IDA's signature
unsafe extern "C" fn jacobian_cb(
    t: f64,
    c: f64,
    yy: sun::N_Vector,
    yp: sun::N_Vector,
    rr: sun::N_Vector,
    jac: sun::SUNMatrix,
    user: *mut c_void,
    _t1: sun::N_Vector,
    _t2: sun::N_Vector,
    _t3: sun::N_Vector,
) -> c_int {
    catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: as in `residual_cb`; the dense matrix stores N² entries column-major.
        unsafe {
            let Some(p) = problem(user) else {
                return -1;
            };
            let n = sun::N_VGetLength(yy) as usize;
            let data = std::slice::from_raw_parts_mut(sun::SUNDenseMatrix_Data(jac), n * n);
            p.jacobian(t, c, slice(yy, n), slice(yp, n), slice(rr, n), data)
                .code()
        }
    }))
    .unwrap_or(-1)
}

#[allow(clippy::too_many_arguments)] // IDA's signature
unsafe extern "C" fn sparse_jacobian_cb(
    t: f64,
    c: f64,
    yy: sun::N_Vector,
    yp: sun::N_Vector,
    _rr: sun::N_Vector,
    jac: sun::SUNMatrix,
    user: *mut c_void,
    _t1: sun::N_Vector,
    _t2: sun::N_Vector,
    _t3: sun::N_Vector,
) -> c_int {
    catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: as in `residual_cb`; the sparse matrix was made by `sparse::new_matrix` with
        // the pattern's number of non-zeros.
        unsafe {
            let Some(p) = problem(user) else {
                return -1;
            };
            let n = sun::N_VGetLength(yy) as usize;
            let Ok(nnz) = usize::try_from(sun::SUNSparseMatrix_NNZ(jac)) else {
                return -1;
            };
            let data = std::slice::from_raw_parts_mut(sun::SUNSparseMatrix_Data(jac), nnz);
            p.sparse_jacobian(t, c, slice(yy, n), slice(yp, n), data)
                .code()
        }
    }))
    .unwrap_or(-1)
}

unsafe extern "C" fn quadrature_cb(
    t: f64,
    yy: sun::N_Vector,
    yp: sun::N_Vector,
    rq: sun::N_Vector,
    user: *mut c_void,
) -> c_int {
    catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: as in `residual_cb`; rq is the quadrature vector of length n_Q.
        unsafe {
            let Some(p) = problem(user) else {
                return -1;
            };
            let n = sun::N_VGetLength(yy) as usize;
            let nq = sun::N_VGetLength(rq) as usize;
            p.quadrature(t, slice(yy, n), slice(yp, n), slice(rq, nq))
                .code()
        }
    }))
    .unwrap_or(-1)
}

unsafe extern "C" fn weights_cb(y: sun::N_Vector, ewt: sun::N_Vector, user: *mut c_void) -> c_int {
    catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: as in `residual_cb`.
        unsafe {
            let Some(p) = problem(user) else {
                return -1;
            };
            let n = sun::N_VGetLength(y) as usize;
            // IDA's convention for the weight function: 0 success, nonzero failure.
            match p.weights(slice(y, n), slice(ewt, n)) {
                Callback::Ok => 0,
                _ => -1,
            }
        }
    }))
    .unwrap_or(-1)
}

impl Ida {
    /// Creates the context, memory, vectors, matrix and linear solver for N unknowns and `nq`
    /// quadratures; `differential` marks the differential unknowns (the rest are algebraic and
    /// left out of the error test). With a `sparse` pattern (N × N) the iteration matrix is
    /// sparse and factored by faer ([`Problem::sparse_jacobian`] fills it); without one, or if
    /// the pattern cannot be analysed, dense ([`Problem::jacobian`]).
    pub fn new(
        differential: &[bool],
        nq: usize,
        sparse: Option<&SparsePattern>,
    ) -> Result<Self, IdaFailure> {
        let n = differential.len();
        let mut ida = Ida {
            ctx: ptr::null_mut(),
            mem: ptr::null_mut(),
            yy: ptr::null_mut(),
            yp: ptr::null_mut(),
            id: ptr::null_mut(),
            dky: ptr::null_mut(),
            yq: ptr::null_mut(),
            dkyq: ptr::null_mut(),
            mat: ptr::null_mut(),
            ls: ptr::null_mut(),
            sparse: false,
            n,
            nq,
            message: Box::new(String::new()),
            initialised: false,
        };
        let len = n as sun::sunindextype;
        // SAFETY: each constructor is checked for NULL before use; Drop frees what was made.
        unsafe {
            let code = sun::SUNContext_Create(sun::SUN_COMM_NULL, &mut ida.ctx);
            if code != 0 || ida.ctx.is_null() {
                return Err(failure(
                    sun::IDA_MEM_FAIL,
                    "SUNContext_Create failed".into(),
                ));
            }
            sun::SUNContext_ClearErrHandlers(ida.ctx);
            let msg_ptr: *mut String = &mut *ida.message;
            sun::SUNContext_PushErrHandler(ida.ctx, Some(error_handler), msg_ptr.cast());
            ida.yy = sun::N_VNew_Serial(len, ida.ctx);
            ida.yp = sun::N_VNew_Serial(len, ida.ctx);
            ida.id = sun::N_VNew_Serial(len, ida.ctx);
            ida.dky = sun::N_VNew_Serial(len, ida.ctx);
            if ida.yy.is_null() || ida.yp.is_null() || ida.id.is_null() || ida.dky.is_null() {
                return Err(failure(sun::IDA_MEM_FAIL, "N_VNew_Serial failed".into()));
            }
            // Fused vector operations (one pass for a linear combination of k vectors instead
            // of k passes): IDA's predictor, dense output (IDAGetDky) and corrector use them,
            // and every vector IDA clones from these inherits them. Off by default in
            // SUNDIALS; they save 0.8 % of the instructions of a whole CLI run on farahan2016.
            for v in [ida.yy, ida.yp, ida.dky] {
                if sun::N_VEnableFusedOps_Serial(v, 1) != 0 {
                    return Err(failure(
                        sun::IDA_MEM_FAIL,
                        "N_VEnableFusedOps_Serial failed".into(),
                    ));
                }
            }
            for (x, &d) in slice(ida.id, n).iter_mut().zip(differential) {
                *x = if d { 1.0 } else { 0.0 };
            }
            slice(ida.yy, n).fill(0.0);
            slice(ida.yp, n).fill(0.0);
            if nq > 0 {
                let len_q = nq as sun::sunindextype;
                ida.yq = sun::N_VNew_Serial(len_q, ida.ctx);
                ida.dkyq = sun::N_VNew_Serial(len_q, ida.ctx);
                if ida.yq.is_null() || ida.dkyq.is_null() {
                    return Err(failure(sun::IDA_MEM_FAIL, "N_VNew_Serial failed".into()));
                }
                for v in [ida.yq, ida.dkyq] {
                    if sun::N_VEnableFusedOps_Serial(v, 1) != 0 {
                        return Err(failure(
                            sun::IDA_MEM_FAIL,
                            "N_VEnableFusedOps_Serial failed".into(),
                        ));
                    }
                }
                slice(ida.yq, nq).fill(0.0);
            }
            ida.mem = sun::IDACreate(ida.ctx);
            if ida.mem.is_null() {
                return Err(failure(sun::IDA_MEM_FAIL, "IDACreate failed".into()));
            }
            let system = sparse
                .filter(|p| p.dim() == n)
                .and_then(sparse::SparseSystem::new);
            if let Some(system) = system {
                ida.mat = sparse::new_matrix(&system, ida.ctx);
                if ida.mat.is_null() {
                    return Err(failure(sun::IDA_MEM_FAIL, "SUNSparseMatrix failed".into()));
                }
                ida.ls = sparse::new_solver(Box::new(system), ida.ctx);
                if ida.ls.is_null() {
                    return Err(failure(
                        sun::IDA_MEM_FAIL,
                        "the sparse linear solver could not be created".into(),
                    ));
                }
                ida.sparse = true;
                return Ok(ida);
            }
            ida.mat = sun::SUNDenseMatrix(len, len, ida.ctx);
            if ida.mat.is_null() {
                return Err(failure(sun::IDA_MEM_FAIL, "SUNDenseMatrix failed".into()));
            }
            ida.ls = sun::SUNLinSol_Dense(ida.yy, ida.mat, ida.ctx);
            if ida.ls.is_null() {
                return Err(failure(sun::IDA_MEM_FAIL, "SUNLinSol_Dense failed".into()));
            }
        }
        Ok(ida)
    }

    /// Number N of unknowns.
    pub fn len(&self) -> usize {
        self.n
    }

    /// Whether the iteration matrix is sparse (factored by faer) rather than dense.
    pub fn is_sparse(&self) -> bool {
        self.sparse
    }

    /// Number n_Q of quadratures.
    pub fn n_quadratures(&self) -> usize {
        self.nq
    }

    /// Turns a flag into `Ok` (≥ 0) or an [`IdaFailure`] with IDA's last message.
    fn check(&self, flag: c_int) -> Result<c_int, IdaFailure> {
        if flag >= 0 {
            return Ok(flag);
        }
        let mut reason = flag_meaning(flag).to_string();
        if !self.message.is_empty() {
            reason.push_str(" (IDA: ");
            reason.push_str(&self.message);
            reason.push(')');
        }
        Err(IdaFailure {
            flag: flag_name(flag),
            reason,
        })
    }

    /// (Re)initialises at t0 with consistent (Y, Ẏ) and the quadratures' values `yq` (IDAInit
    /// and IDAQuadInit the first time, IDAReInit and IDAQuadReInit after), with user error
    /// weights, the id vector, suppression of the algebraic unknowns from the error test, the
    /// quadratures out of it, the dense solver with the user Jacobian, a first step `h0` (0:
    /// IDA's own guess) and a largest step `h_max` (∞: none).
    pub fn init(
        &mut self,
        t0: f64,
        yy: &[f64],
        yp: &[f64],
        yq: &[f64],
        h0: f64,
        h_max: f64,
    ) -> Result<(), IdaFailure> {
        self.message.clear();
        let n = self.n;
        // SAFETY: the vectors have length n (n_Q); the memory is live.
        unsafe {
            slice(self.yy, n).copy_from_slice(&yy[..n]);
            slice(self.yp, n).copy_from_slice(&yp[..n]);
            if self.nq > 0 {
                slice(self.yq, self.nq).copy_from_slice(&yq[..self.nq]);
            }
            if self.initialised {
                self.check(sun::IDAReInit(self.mem, t0, self.yy, self.yp))?;
                if self.nq > 0 {
                    self.check(sun::IDAQuadReInit(self.mem, self.yq))?;
                }
            } else {
                self.check(sun::IDAInit(
                    self.mem,
                    Some(residual_cb),
                    t0,
                    self.yy,
                    self.yp,
                ))?;
                self.check(sun::IDAWFtolerances(self.mem, Some(weights_cb)))?;
                self.check(sun::IDASetId(self.mem, self.id))?;
                self.check(sun::IDASetSuppressAlg(self.mem, 1))?;
                self.check(sun::IDASetLinearSolver(self.mem, self.ls, self.mat))?;
                let jacobian = if self.sparse {
                    sparse_jacobian_cb
                } else {
                    jacobian_cb
                };
                self.check(sun::IDASetJacFn(self.mem, Some(jacobian)))?;
                self.check(sun::IDASetMaxNumSteps(self.mem, 100_000))?;
                if h_max.is_finite() {
                    self.check(sun::IDASetMaxStep(self.mem, h_max))?;
                }
                if self.nq > 0 {
                    self.check(sun::IDAQuadInit(self.mem, Some(quadrature_cb), self.yq))?;
                    // Bookkeeping: out of the error test (IDAS's default, made explicit).
                    self.check(sun::IDASetQuadErrCon(self.mem, 0))?;
                }
                self.initialised = true;
            }
            self.check(sun::IDASetInitStep(self.mem, h0))?;
        }
        Ok(())
    }

    /// One internal step of IDA towards `t_stop` (never past it), with `problem` as the
    /// equations. Fills `yy_out` (length N) with Y and `yq_out` (length n_Q) with the
    /// quadratures at the time returned.
    pub fn solve_one_step(
        &mut self,
        problem: &mut dyn Problem,
        t_stop: f64,
        yy_out: &mut [f64],
        yq_out: &mut [f64],
    ) -> Result<StepReturn, IdaFailure> {
        self.message.clear();
        let mut p: ProblemPtr<'_> = problem;
        let user: *mut ProblemPtr<'_> = &mut p;
        let mut t_ret = 0.0;
        // SAFETY: `user` points to `p`, which outlives the IDASolve call; it is unset right
        // after, so no callback can see a dangling pointer.
        let flag = unsafe {
            sun::IDASetUserData(self.mem, user.cast());
            let set = sun::IDASetStopTime(self.mem, t_stop);
            let flag = if set < 0 {
                set
            } else {
                sun::IDASolve(
                    self.mem,
                    t_stop,
                    &mut t_ret,
                    self.yy,
                    self.yp,
                    sun::IDA_ONE_STEP,
                )
            };
            sun::IDASetUserData(self.mem, ptr::null_mut());
            flag
        };
        let flag = self.check(flag)?;
        // SAFETY: yy has length n, yq n_Q; plain getter on live memory.
        unsafe {
            yy_out[..self.n].copy_from_slice(slice(self.yy, self.n));
            if self.nq > 0 {
                let mut t_q = 0.0;
                self.check(sun::IDAGetQuad(self.mem, &mut t_q, self.yq))?;
                yq_out[..self.nq].copy_from_slice(slice(self.yq, self.nq));
            }
        }
        Ok(StepReturn {
            t: t_ret,
            at_stop: flag == sun::IDA_TSTOP_RETURN,
        })
    }

    /// The interpolating polynomials of the last step at t: Y into `out` (length N), the
    /// quadratures into `out_q` (length n_Q).
    pub fn dense(&mut self, t: f64, out: &mut [f64], out_q: &mut [f64]) -> Result<(), IdaFailure> {
        // SAFETY: dky has length n, dkyq n_Q; the memory is live.
        unsafe {
            self.check(sun::IDAGetDky(self.mem, t, 0, self.dky))?;
            out[..self.n].copy_from_slice(slice(self.dky, self.n));
            if self.nq > 0 {
                self.check(sun::IDAGetQuadDky(self.mem, t, 0, self.dkyq))?;
                out_q[..self.nq].copy_from_slice(slice(self.dkyq, self.nq));
            }
        }
        Ok(())
    }

    /// (t_n, h_used, order used, h proposed next) of the last step.
    pub fn last_step(&self) -> Result<(f64, f64, usize, f64), IdaFailure> {
        let (mut tn, mut hu, mut k, mut hnext) = (0.0, 0.0, 0 as c_int, 0.0);
        // SAFETY: plain getters on live memory.
        unsafe {
            self.check(sun::IDAGetCurrentTime(self.mem, &mut tn))?;
            self.check(sun::IDAGetLastStep(self.mem, &mut hu))?;
            self.check(sun::IDAGetLastOrder(self.mem, &mut k))?;
            self.check(sun::IDAGetCurrentStep(self.mem, &mut hnext))?;
        }
        Ok((tn, hu, k.max(1) as usize, hnext))
    }

    /// IDA's counters since the first initialisation (IDAReInit resets them, see
    /// [`Ida::init`]: the caller keeps its own totals).
    pub fn counts(&self) -> Result<IdaCounts, IdaFailure> {
        let mut v: [c_long; 6] = [0; 6];
        // SAFETY: plain getters on live memory.
        unsafe {
            self.check(sun::IDAGetNumSteps(self.mem, &mut v[0]))?;
            self.check(sun::IDAGetNumResEvals(self.mem, &mut v[1]))?;
            self.check(sun::IDAGetNumNonlinSolvIters(self.mem, &mut v[2]))?;
            self.check(sun::IDAGetNumNonlinSolvConvFails(self.mem, &mut v[3]))?;
            self.check(sun::IDAGetNumJacEvals(self.mem, &mut v[4]))?;
            self.check(sun::IDAGetNumErrTestFails(self.mem, &mut v[5]))?;
        }
        let u = |x: c_long| u64::try_from(x).unwrap_or(0);
        Ok(IdaCounts {
            steps: u(v[0]),
            residuals: u(v[1]),
            newton_iterations: u(v[2]),
            newton_failures: u(v[3]),
            jacobians: u(v[4]),
            error_test_failures: u(v[5]),
        })
    }
}

/// An [`IdaFailure`] made by the wrapper itself.
fn failure(code: c_int, message: String) -> IdaFailure {
    IdaFailure {
        flag: flag_name(code),
        reason: format!("{}: {message}", flag_meaning(code)),
    }
}

impl Drop for Ida {
    fn drop(&mut self) {
        // SAFETY: each pointer is either NULL or owned by this struct; freed once, in reverse
        // order of creation, the context last.
        unsafe {
            if !self.mem.is_null() {
                sun::IDAFree(&mut self.mem);
            }
            if !self.ls.is_null() {
                sun::SUNLinSolFree(self.ls);
            }
            if !self.mat.is_null() {
                sun::SUNMatDestroy(self.mat);
            }
            for v in [self.dkyq, self.yq, self.dky, self.id, self.yp, self.yy] {
                if !v.is_null() {
                    sun::N_VDestroy(v);
                }
            }
            if !self.ctx.is_null() {
                sun::SUNContext_Free(&mut self.ctx);
            }
        }
    }
}
