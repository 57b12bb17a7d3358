//! The linear algebra of the formulations and the integrators, in one place.
//!
//! Each kernel's module documentation gives its users and its measurement against faer and
//! nalgebra at the sizes it meets (docs/measurements.md, "One place for the linear algebra"):
//! the two Choleskys and the sparse LU are faster than both at every size they meet; the dense
//! LUs are up to 6 rows, and are kept above for what the libraries' LUs do not do (a relative
//! singularity test, decoupled components, no allocation in the step loop), each module says
//! which.
//!
//! | kernel | matrices | sizes met | user |
//! |---|---|---|---|
//! | [`cholesky`] | dense SPD, small | m ≤ 16 | the DAE's Schur complement of one or two loops; the model assembly's row basis |
//! | [`skyline`] | sparse SPD, envelope after reverse Cuthill–McKee | m > 16 | the DAE's Schur complement of larger linkages |
//! | [`regularised`] | a pivot rule for both Choleskys | | the DAE through singular positions |
//! | [`dense_lu`] | dense square (partial pivoting) and rectangular (complete pivoting) | m < 20 | the generalized formulation's dependent block and coordinate partition |
//! | `shifted_lu` | dense s·I − J, real and complex s, decoupled components apart | n < 40 | Radau5's Newton matrices |
//! | `sparse_lu` (with `sparse_refactor`) | sparse square, one pattern factored again and again | larger models | Radau5's and IDA's Newton matrices, the generalized formulation's large dependent blocks |
//!
//! [`Factorisation`] is the one interface they share: factor a square matrix, report the
//! first row or column where it is singular to working precision, solve in place. The
//! formulations call the kernels' own functions on their own storage (no copy into a common
//! matrix type on the hot paths); the interface is what the tests hold every kernel to, on
//! the same matrices (`conformance.rs`); `benches/linalg.rs` measures each against faer and
//! nalgebra at the sizes it meets.

pub mod cholesky;
#[cfg(test)]
mod conformance;
pub mod dense_lu;
mod interface;
pub mod regularised;
pub(crate) mod shifted_lu;
pub mod skyline;
pub(crate) mod sparse_lu;
pub(crate) mod sparse_refactor;

pub use interface::{
    DenseCholesky, DenseLu, Factorisation, ShiftedLu, Singular, SkylineCholesky, SparseLu,
};
