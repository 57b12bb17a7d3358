//! Sparse LU factorisations (faer) of the two Newton matrices of Radau IIA in augmented form:
//! the real σ₁·E − 𝒥 and the complex (α + iβ)·E − 𝒥, with 𝒥 the formulation's augmented
//! Jacobian and E = diag(I_n, 0_m) ([`crate::formulation::sparse_jacobian`]).
//!
//! **Once per pattern** (at [`SparseLu::new`]): the pattern of the Newton matrices (𝒥's with
//! its whole diagonal), where each value of 𝒥 and each diagonal entry lands in it, and the
//! fill-reducing column order (COLAMD, faer's `factorize_symbolic_lu`): one symbolic analysis
//! serves every numeric factorisation, real and complex, of the run. **Per factorisation**:
//! the values are scattered into place and factored by faer's left-looking (Gilbert–Peierls)
//! LU with partial pivoting in that column order, the simplicial variant. Why simplicial: the
//! factors stay nearly as sparse as the matrix, and supernodes do not pay at the sizes met.
//! Measured per real factorisation on the N-four-bar chain (DAE; loaded 2-core machine):
//! 40 loops (971 unknowns, 8 450 non-zeros, 15 550 in L + U) 320 µs simplicial, 350 µs
//! supernodal, 310 µs with faer's own choice; 80 loops 670 / 820 / 680 µs; 10 loops 80 / 97 /
//! 75 µs; only at 200 loops (4 811 unknowns) do the supernodes gain, 1 950 / 1 770 / 1 660 µs.
//! The simplicial factor also shows its pivots, which the singularity check below reads. The
//! buffers (values, row permutations, faer's scratch) are allocated here; the factors
//! keep their capacity between factorisations, so stepping allocates only while a factor grows
//! past its largest size so far.
//!
//! **Solving** (σ·I − J) x = b: the right-hand side (b, 0) of the augmented system, whose first
//! n components are x (module documentation of [`crate::formulation::sparse_jacobian`]).
//!
//! **Singularity**: faer picks the largest remaining entry of each column as its pivot even when
//! it is zero; a zero or non-finite pivot is reported as [`Singular`] here, as the dense LU
//! reports its own.

use super::linalg::Singular;
use crate::formulation::sparse_jacobian::SparsePattern;
use faer::c64;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::perm::PermRef;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::lu::simplicial::{
    SimplicialLu, factorize_simplicial_numeric_lu, factorize_simplicial_numeric_lu_scratch,
    solve_in_place_scratch,
};
use faer::sparse::linalg::lu::{LuSymbolicParams, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par};

/// One numeric LU (real or complex) with its row permutation.
struct Numeric<T> {
    lu: SimplicialLu<usize, T>,
    row_fwd: Vec<usize>,
    row_inv: Vec<usize>,
    /// The matrix values over the Newton pattern.
    values: Vec<T>,
    /// Right-hand side and solution of the augmented system.
    rhs: Vec<T>,
    factored: bool,
}

impl<T: Clone> Numeric<T> {
    fn new(dim: usize, nnz: usize, zero: T) -> Self {
        Numeric {
            lu: SimplicialLu::new(),
            row_fwd: vec![0; dim],
            row_inv: vec![0; dim],
            values: vec![zero.clone(); nnz],
            rhs: vec![zero; dim],
            factored: false,
        }
    }
}

/// The sparse LU factors of both Newton matrices, over a pattern analysed once.
pub(super) struct SparseLu {
    /// Number of states n (the rows and columns with E = 1).
    n: usize,
    /// The Newton matrices' pattern: 𝒥's and the diagonal.
    pattern: SymbolicSparseColMat<usize>,
    /// Where value k of 𝒥 lands in the Newton pattern.
    jac_position: Vec<usize>,
    /// Where the diagonal entry (i, i) lands, for i < n.
    diagonal: Vec<usize>,
    /// The column order (COLAMD), computed once.
    symbolic: SymbolicLu<usize>,
    real: Numeric<f64>,
    complex: Numeric<c64>,
    /// faer's scratch for factorising and solving, the largest of its needs.
    scratch: MemBuffer,
}

impl SparseLu {
    /// Analyses the pattern of 𝒥 (dimension n + m) for n states; `None` if faer cannot (out of
    /// memory), and the caller stays with the dense LU.
    pub(super) fn new(n: usize, jac: &SparsePattern) -> Option<Self> {
        let dim = jac.dim();
        if dim < n {
            return None;
        }
        let union = SparsePattern::from_entries(
            dim,
            (0..dim)
                .flat_map(|j| jac.rows_of(j).iter().map(move |&i| (i, j)))
                .chain((0..dim).map(|i| (i, i))),
        );
        let mut jac_position = Vec::with_capacity(jac.nnz());
        for j in 0..dim {
            for &i in jac.rows_of(j) {
                jac_position.push(union.position(i, j)?);
            }
        }
        let diagonal = (0..n)
            .map(|i| union.position(i, i))
            .collect::<Option<Vec<usize>>>()?;
        let nnz = union.nnz();
        let pattern = SymbolicSparseColMat::new_checked(
            dim,
            dim,
            union.col_ptr().to_vec(),
            None,
            union.row_idx().to_vec(),
        );
        let symbolic = factorize_symbolic_lu(
            pattern.as_ref(),
            LuSymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
                ..Default::default()
            },
        )
        .ok()?;
        let req = StackReq::any_of(&[
            factorize_simplicial_numeric_lu_scratch::<usize, f64>(dim, dim),
            factorize_simplicial_numeric_lu_scratch::<usize, c64>(dim, dim),
            solve_in_place_scratch::<usize, f64>(dim, 1, Par::Seq),
            solve_in_place_scratch::<usize, c64>(dim, 1, Par::Seq),
        ]);
        let scratch = MemBuffer::try_new(req).ok()?;
        Some(SparseLu {
            n,
            pattern,
            jac_position,
            diagonal,
            symbolic,
            real: Numeric::new(dim, nnz, 0.0),
            complex: Numeric::new(dim, nnz, c64::new(0.0, 0.0)),
            scratch,
        })
    }

    /// Number of structural non-zeros of the Newton matrices.
    pub(super) fn nnz(&self) -> usize {
        self.real.values.len()
    }

    /// Factorises σ·E − 𝒥 with 𝒥's values `jac` (in its pattern's order).
    pub(super) fn factor_real(&mut self, sigma: f64, jac: &[f64]) -> Result<(), Singular> {
        let num = &mut self.real;
        num.factored = false;
        num.values.fill(0.0);
        for (&p, &v) in self.jac_position.iter().zip(jac) {
            num.values[p] = -v;
        }
        for &p in &self.diagonal {
            num.values[p] += sigma;
        }
        factor(
            &self.pattern,
            &self.symbolic,
            num,
            &mut self.scratch,
            |x: &f64| x.abs(),
        )
    }

    /// Factorises (α + iβ)·E − 𝒥 with 𝒥's values `jac`.
    pub(super) fn factor_complex(
        &mut self,
        alpha: f64,
        beta: f64,
        jac: &[f64],
    ) -> Result<(), Singular> {
        let num = &mut self.complex;
        num.factored = false;
        num.values.fill(c64::new(0.0, 0.0));
        for (&p, &v) in self.jac_position.iter().zip(jac) {
            num.values[p] = c64::new(-v, 0.0);
        }
        for &p in &self.diagonal {
            num.values[p] += c64::new(alpha, beta);
        }
        factor(
            &self.pattern,
            &self.symbolic,
            num,
            &mut self.scratch,
            |x: &c64| x.norm(),
        )
    }

    /// Solves (σ₁·I − J) x = b in place (b of length n) with the real factors.
    pub(super) fn solve_real(&mut self, b: &mut [f64]) {
        let num = &mut self.real;
        if !num.factored {
            // Never after a successful factorisation: NaN, which the Newton norm rejects.
            b.fill(f64::NAN);
            return;
        }
        let (head, tail) = num.rhs.split_at_mut(self.n);
        head.copy_from_slice(b);
        tail.fill(0.0);
        solve(&self.symbolic, num, &mut self.scratch);
        b.copy_from_slice(&num.rhs[..self.n]);
    }

    /// Solves ((α + iβ)·I − J)(x_re + i x_im) = b_re + i b_im in place with the complex factors.
    pub(super) fn solve_complex(&mut self, b_re: &mut [f64], b_im: &mut [f64]) {
        let num = &mut self.complex;
        if !num.factored {
            b_re.fill(f64::NAN);
            b_im.fill(f64::NAN);
            return;
        }
        for (r, (&re, &im)) in num.rhs.iter_mut().zip(b_re.iter().zip(b_im.iter())) {
            *r = c64::new(re, im);
        }
        num.rhs[self.n..].fill(c64::new(0.0, 0.0));
        solve(&self.symbolic, num, &mut self.scratch);
        for (k, r) in num.rhs[..self.n].iter().enumerate() {
            b_re[k] = r.re;
            b_im[k] = r.im;
        }
    }
}

/// Numeric LU of the values in `num` over `pattern` in the column order of `symbolic`; checks
/// every pivot (the last entry of each column of U, as faer stores it) for zero or NaN.
fn factor<T: faer::traits::ComplexField>(
    pattern: &SymbolicSparseColMat<usize>,
    symbolic: &SymbolicLu<usize>,
    num: &mut Numeric<T>,
    scratch: &mut MemBuffer,
    magnitude: impl Fn(&T) -> f64,
) -> Result<(), Singular> {
    let matrix = SparseColMatRef::new(pattern.as_ref(), &num.values);
    let stack = MemStack::new(scratch);
    if let Err(e) = factorize_simplicial_numeric_lu(
        &mut num.row_fwd,
        &mut num.row_inv,
        &mut num.lu,
        matrix,
        symbolic.col_perm(),
        stack,
    ) {
        let column = match e {
            faer::sparse::linalg::LuError::SymbolicSingular { index } => index,
            faer::sparse::linalg::LuError::Generic(_) => 0,
        };
        return Err(Singular { column });
    }
    let u = num.lu.u_factor_unsorted();
    for j in 0..u.ncols() {
        let pivot = u.val_of_col(j).last().map_or(0.0, &magnitude);
        // A NaN pivot (from a NaN Jacobian) fails this test too.
        if pivot.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) || pivot.is_infinite() {
            return Err(Singular { column: j });
        }
    }
    num.factored = true;
    Ok(())
}

/// Solves with the factors in `num`, the right-hand side in `num.rhs`.
fn solve<T: faer::traits::ComplexField>(
    symbolic: &SymbolicLu<usize>,
    num: &mut Numeric<T>,
    scratch: &mut MemBuffer,
) {
    let dim = num.rhs.len();
    let stack = MemStack::new(scratch);
    let row_perm = PermRef::new_checked(&num.row_fwd, &num.row_inv, dim);
    num.lu.solve_in_place_with_conj(
        row_perm,
        symbolic.col_perm(),
        Conj::No,
        MatMut::from_column_major_slice_mut(&mut num.rhs, dim, 1),
        Par::Seq,
        stack,
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solve::radau5::linalg::{ComplexLu, Partition, RealLu};

    /// 𝒥 of y' = g = (y₁, z₀), 0 = k = z₀ + 2y₀ + y₁ − z₁, 0 = z₁ − 3y₁ + y₀ (n = 2, m = 2):
    /// eliminating z gives z₁ = 3y₁ − y₀, z₀ = −3y₀ + 2y₁, so J = [[0, 1], [−3, 2]].
    fn augmented() -> (SparsePattern, Vec<f64>, [f64; 4]) {
        let entries = [
            (0, 0, 0.0),
            (1, 1, 0.0),
            (0, 1, 1.0),
            (1, 2, 1.0),
            (2, 0, 2.0),
            (2, 1, 1.0),
            (2, 2, 1.0),
            (2, 3, -1.0),
            (3, 0, 1.0),
            (3, 1, -3.0),
            (3, 3, 1.0),
        ];
        let pattern = SparsePattern::from_entries(4, entries.iter().map(|&(i, j, _)| (i, j)));
        let mut values = vec![0.0; pattern.nnz()];
        for &(i, j, v) in &entries {
            if let Some(p) = pattern.position(i, j) {
                values[p] = v;
            }
        }
        (pattern, values, [0.0, 1.0, -3.0, 2.0])
    }

    #[test]
    fn augmented_solves_match_the_dense_lu_of_the_schur_complement() -> Result<(), Singular> {
        let (pattern, values, jac) = augmented();
        let Some(mut sparse) = SparseLu::new(2, &pattern) else {
            panic!("analysis failed");
        };
        let (sigma, alpha, beta) = (1.7, 2.1, 0.9);
        sparse.factor_real(sigma, &values)?;
        sparse.factor_complex(alpha, beta, &values)?;
        let mut dense_re = RealLu::new(2);
        dense_re.factor(sigma, &jac, &Partition::new(2))?;
        let mut dense_c = ComplexLu::new(2);
        dense_c.factor(alpha, beta, &jac, &Partition::new(2))?;
        let (mut a, mut b) = ([0.3, -1.2], [0.3, -1.2]);
        sparse.solve_real(&mut a);
        dense_re.solve(&mut b);
        let (mut ar, mut ai) = ([1.0, 0.5], [-0.25, 2.0]);
        let (mut br, mut bi) = (ar, ai);
        sparse.solve_complex(&mut ar, &mut ai);
        dense_c.solve(&mut br, &mut bi);
        for k in 0..2 {
            // 2×2 systems of condition ~10, two elimination orders: a few ulps.
            assert!(
                (a[k] - b[k]).abs() < 1e-14,
                "real x{k}: {} vs {}",
                a[k],
                b[k]
            );
            assert!(
                (ar[k] - br[k]).abs() < 1e-14 && (ai[k] - bi[k]).abs() < 1e-14,
                "complex x{k}: {} + {}i vs {} + {}i",
                ar[k],
                ai[k],
                br[k],
                bi[k]
            );
        }
        Ok(())
    }

    #[test]
    fn a_zero_pivot_is_reported() {
        // σ·I − J = 0 for J = I, σ = 1 (m = 0).
        let pattern = SparsePattern::from_entries(2, [(0, 0), (1, 1)]);
        let Some(mut sparse) = SparseLu::new(2, &pattern) else {
            panic!("analysis failed");
        };
        assert!(sparse.factor_real(1.0, &[1.0, 1.0]).is_err());
        assert!(sparse.factor_complex(1.0, 0.0, &[1.0, 1.0]).is_err());
        assert!(sparse.factor_complex(1.0, 0.5, &[1.0, 1.0]).is_ok());
        let mut b = [1.0, 2.0];
        sparse.solve_real(&mut b);
        assert!(
            b.iter().all(|x| x.is_nan()),
            "no factors: NaN, not stale numbers"
        );
    }
}
