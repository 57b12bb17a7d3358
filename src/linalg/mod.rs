//! Linear algebra shared by the formulations and the integrators.
//!
//! - [`sparse_refactor`]: sparse LU factors refactorised with the pivots and fill pattern of an
//!   earlier pivoting factorisation (faer's), for matrices of one pattern factored again and
//!   again: Radau5's Newton matrices (`solve/radau5/sparse.rs`) and the generalised
//!   formulation's dependent block Φ_qD (`formulation/generalized/sparse_lu.rs`).
//!
//! - [`sparse_lu`]: a square sparse LU over a pattern analysed once, refactorised with
//!   [`sparse_refactor`]: Radau5's Newton matrices, IDA's iteration matrix on large models and
//!   the generalised formulation's dependent block Φ_qD (each with its own pivot threshold,
//!   measured where it is set).
//!
//! The other factorisations still live beside their one user, each kept where a measurement
//! showed it beating faer or nalgebra at its size (docs/measurements.md, "Small dense linear
//! algebra", "Hundreds of bodies: the DAE's Schur complement", "Radau5 with a sparse LU"):
//! the dense Cholesky of small Schur complements (`formulation/cholesky.rs`), the skyline
//! Cholesky of large ones with its regularised pivots (`formulation/schur.rs`), the dense LU of
//! the generalised formulation's small dependent blocks (`formulation/generalized/lu.rs`) and
//! Radau5's dense real and complex LUs (`solve/radau5/linalg.rs`).

pub(crate) mod sparse_lu;
pub(crate) mod sparse_refactor;
