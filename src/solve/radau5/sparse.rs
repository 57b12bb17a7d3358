//! Sparse LU factorisations (faer) of the two Newton matrices of Radau IIA in augmented form:
//! the real σ₁·E − 𝒥 and the complex (α + iβ)·E − 𝒥, with 𝒥 the formulation's augmented
//! Jacobian and E = diag(I_n, 0_m) ([`crate::formulation::sparse_jacobian`]).
//!
//! **Once per pattern** (at [`SparseLu::new`]): the pattern of the Newton matrices (𝒥's with
//! its whole diagonal), where each value of 𝒥 and each diagonal entry lands in it, and the
//! column order ([`SparseLuAnalysis`]): one analysis serves every numeric factorisation, real
//! and complex, of the run. **Per factorisation**: the values are scattered into place and
//! factored by [`SparseLuFactors`] (the kept pivots of the last pivoting factorisation while
//! they pass their threshold check, else faer's LU with partial pivoting). On the 40-loop chain
//! (DAE, rtol 1e-8, to t = 2 s, callgrind) a pair of real and complex factorisations went from
//! 8.6 M to 3.7 M instructions with the kept pivots and the run from 2.42 G to 1.58 G; 7 of its
//! 176 factorisations of each kind pivoted again (a kept pivot below the threshold). The
//! buffers are allocated here; the factors keep their capacity between factorisations, so
//! stepping allocates only while a factor grows past its largest size so far.
//!
//! **Solving** (σ·I − J) x = b: the right-hand side (b, 0) of the augmented system, whose first
//! n components are x (module documentation of [`crate::formulation::sparse_jacobian`]).
//!
//! **Singularity**: a zero or non-finite pivot is reported as [`Singular`], as the dense LU
//! reports its own.

use crate::formulation::sparse_jacobian::SparsePattern;
use crate::linalg::Singular;
use crate::linalg::sparse_lu::{SingularColumn, SparseLuAnalysis, SparseLuFactors};
use crate::linalg::sparse_refactor::PivotCheck;
use faer::c64;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};

/// The sparse LU factors of both Newton matrices, over a pattern analysed once.
pub(super) struct SparseLu {
    /// Number of states n (the rows and columns with E = 1).
    n: usize,
    /// The Newton matrices' pattern (𝒥's and the diagonal) and its column order.
    analysis: SparseLuAnalysis,
    /// Where value k of 𝒥 lands in the Newton pattern.
    jac_position: Vec<usize>,
    /// Where the diagonal entry (i, i) lands, for i < n.
    diagonal: Vec<usize>,
    real: SparseLuFactors<f64>,
    complex: SparseLuFactors<c64>,
    /// Right-hand sides and solutions of the augmented systems.
    rhs_real: Vec<f64>,
    rhs_complex: Vec<c64>,
    /// faer's scratch for factorising, the larger of the two needs.
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
        let analysis =
            SparseLuAnalysis::new(dim, union.col_ptr().to_vec(), union.row_idx().to_vec())?;
        let req = StackReq::any_of(&[analysis.scratch::<f64>(), analysis.scratch::<c64>()]);
        let scratch = MemBuffer::try_new(req).ok()?;
        Some(SparseLu {
            n,
            real: SparseLuFactors::new(&analysis, KEPT_PIVOTS),
            complex: SparseLuFactors::new(&analysis, KEPT_PIVOTS),
            rhs_real: vec![0.0; dim],
            rhs_complex: vec![c64::new(0.0, 0.0); dim],
            analysis,
            jac_position,
            diagonal,
            scratch,
        })
    }

    /// Number of structural non-zeros of the Newton matrices.
    pub(super) fn nnz(&self) -> usize {
        self.analysis.nnz()
    }

    /// Factorises σ·E − 𝒥 with 𝒥's values `jac` (in its pattern's order).
    pub(super) fn factor_real(&mut self, sigma: f64, jac: &[f64]) -> Result<(), Singular> {
        let values = self.real.values_mut();
        values.fill(0.0);
        for (&p, &v) in self.jac_position.iter().zip(jac) {
            values[p] = -v;
        }
        for &p in &self.diagonal {
            values[p] += sigma;
        }
        self.real
            .factor(&self.analysis, MemStack::new(&mut self.scratch))
            .map_err(singular)
    }

    /// Factorises (α + iβ)·E − 𝒥 with 𝒥's values `jac`.
    pub(super) fn factor_complex(
        &mut self,
        alpha: f64,
        beta: f64,
        jac: &[f64],
    ) -> Result<(), Singular> {
        let values = self.complex.values_mut();
        values.fill(c64::new(0.0, 0.0));
        for (&p, &v) in self.jac_position.iter().zip(jac) {
            values[p] = c64::new(-v, 0.0);
        }
        for &p in &self.diagonal {
            values[p] += c64::new(alpha, beta);
        }
        self.complex
            .factor(&self.analysis, MemStack::new(&mut self.scratch))
            .map_err(singular)
    }

    /// Solves (σ₁·I − J) x = b in place (b of length n) with the real factors; NaN (which the
    /// Newton norm rejects) where there are none.
    pub(super) fn solve_real(&mut self, b: &mut [f64]) {
        let (head, tail) = self.rhs_real.split_at_mut(self.n);
        head.copy_from_slice(b);
        tail.fill(0.0);
        self.real.solve(&self.analysis, &mut self.rhs_real);
        b.copy_from_slice(&self.rhs_real[..self.n]);
    }

    /// Solves ((α + iβ)·I − J)(x_re + i x_im) = b_re + i b_im in place with the complex factors.
    pub(super) fn solve_complex(&mut self, b_re: &mut [f64], b_im: &mut [f64]) {
        for (r, (&re, &im)) in self
            .rhs_complex
            .iter_mut()
            .zip(b_re.iter().zip(b_im.iter()))
        {
            *r = c64::new(re, im);
        }
        self.rhs_complex[self.n..].fill(c64::new(0.0, 0.0));
        self.complex.solve(&self.analysis, &mut self.rhs_complex);
        for (k, r) in self.rhs_complex[..self.n].iter().enumerate() {
            b_re[k] = r.re;
            b_im[k] = r.im;
        }
    }
}

fn singular(e: SingularColumn) -> Singular {
    Singular { column: e.column }
}

/// The kept pivots' check: a threshold (measured on the 40-loop chain over 20 s: 7 of 176
/// factorisations pivoted again to t = 2 s; the chain's errors against its exact motion as
/// before, `tests/nfourbar_chain.rs`).
const KEPT_PIVOTS: PivotCheck = PivotCheck(0.1);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::shifted_lu::{ComplexLu, Partition, RealLu};

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

    /// A random pattern of dimension 40 for n = 25 states (each row a few entries besides the
    /// diagonal, the last 15 diagonal entries of 𝒥 zero so that σ·E − 𝒥 needs row pivots) and
    /// its values.
    fn random_system(seed: u64) -> (SparsePattern, Vec<f64>) {
        let mut rng = crate::formulation::test_rng::Lcg(seed);
        let (dim, n) = (40, 25);
        // Each constraint row i ≥ n couples to state i − n (and back), as a multiplier's row
        // of the augmented Jacobian does: structurally regular.
        let mut entries: Vec<(usize, usize)> = (0..dim).map(|i| (i, i)).collect();
        entries.extend((n..dim).flat_map(|i| [(i, i - n), (i - n, i)]));
        for i in 0..dim {
            for _ in 0..3 {
                entries.push((i, rng.below(dim)));
            }
        }
        let pattern = SparsePattern::from_entries(dim, entries.iter().copied());
        let mut values = vec![0.0; pattern.nnz()];
        for j in 0..dim {
            for &i in pattern.rows_of(j) {
                if let Some(p) = pattern.position(i, j)
                    && !(i == j && i >= n)
                {
                    values[p] = rng.range(-1.0, 1.0);
                }
            }
        }
        (pattern, values)
    }

    /// max |(σ·E − 𝒥) x − b| over the rows, x = (x_n, z) the augmented solution recomputed
    /// densely: the first n rows' residual is what the solve promises.
    fn residual_real(pattern: &SparsePattern, jac: &[f64], n: usize, sigma: f64, b: &[f64]) -> f64 {
        let Some(mut lu) = SparseLu::new(n, pattern) else {
            panic!("analysis failed");
        };
        if lu.factor_real(sigma, jac).is_err() {
            return f64::INFINITY;
        }
        lu.solve_real_augmented_for_test(b)
            .iter()
            .fold(0.0, |m, r| m.max(r.abs()))
    }

    impl SparseLu {
        /// Solves the full augmented system for right-hand side `b` (all dim rows) and returns
        /// the residual (σ·E − 𝒥) x − b, with σ and 𝒥 read back from the stored values.
        fn solve_real_augmented_for_test(&mut self, b: &[f64]) -> Vec<f64> {
            let mut x = b.to_vec();
            self.real.solve(&self.analysis, &mut x);
            let values = self.real.values();
            let pattern = self.analysis.pattern();
            let mut r: Vec<f64> = b.iter().map(|v| -v).collect();
            for j in 0..pattern.ncols() {
                let rows = pattern.row_idx_of_col_raw(j);
                let start = pattern.col_ptr()[j];
                for (k, &i) in rows.iter().enumerate() {
                    r[i] += values[start + k] * x[j];
                }
            }
            r
        }
    }

    #[test]
    fn refactorising_with_the_kept_pivots_gives_the_pivoting_factors_bit_for_bit()
    -> Result<(), Singular> {
        let (pattern, jac) = random_system(0x11_2026);
        let n = 25;
        let Some(mut lu) = SparseLu::new(n, &pattern) else {
            panic!("analysis failed");
        };
        let b: Vec<f64> = (0..n).map(|k| (k as f64 * 0.7).sin()).collect();
        lu.factor_real(3.0, &jac)?;
        lu.factor_complex(2.5, 1.5, &jac)?;
        let mut x_pivoting = b.clone();
        lu.solve_real(&mut x_pivoting);
        let (mut re_pivoting, mut im_pivoting) = (b.clone(), vec![0.5; n]);
        lu.solve_complex(&mut re_pivoting, &mut im_pivoting);
        // The same values again: the kept pivots are the largest, so faer would choose them too.
        lu.factor_real(3.0, &jac)?;
        lu.factor_complex(2.5, 1.5, &jac)?;
        assert_eq!(lu.real.counts(), (1, 1));
        assert_eq!(lu.complex.counts(), (1, 1));
        let mut x = b.clone();
        lu.solve_real(&mut x);
        let (mut re, mut im) = (b.clone(), vec![0.5; n]);
        lu.solve_complex(&mut re, &mut im);
        assert_eq!(x, x_pivoting);
        assert_eq!((re, im), (re_pivoting, im_pivoting));
        Ok(())
    }

    #[test]
    fn refactorised_solves_have_round_off_residuals() -> Result<(), Singular> {
        let (pattern, jac) = random_system(0x22_2026);
        let (n, dim) = (25, 40);
        let Some(mut lu) = SparseLu::new(n, &pattern) else {
            panic!("analysis failed");
        };
        lu.factor_real(3.0, &jac)?;
        // New values of the same pattern, as the next steps of a run bring them: σ and 𝒥 moved.
        let moved: Vec<f64> = jac
            .iter()
            .enumerate()
            .map(|(k, v)| v * (1.0 + 0.05 * ((k as f64) * 1.3).sin()))
            .collect();
        lu.factor_real(3.3, &moved)?;
        assert_eq!(lu.real.counts().1, 1, "the kept pivots pass their check");
        let b: Vec<f64> = (0..dim).map(|k| (k as f64 * 0.3).cos()).collect();
        let worst = lu
            .solve_real_augmented_for_test(&b)
            .iter()
            .fold(0.0, |m: f64, r| m.max(r.abs()));
        // Against a pivoting factorisation of the same values from scratch.
        let fresh = residual_real(&pattern, &moved, n, 3.3, &b);
        assert!(
            worst < 1e-13 && fresh < 1e-13,
            "refactor {worst:e}, fresh {fresh:e}"
        );
        Ok(())
    }

    #[test]
    fn a_kept_pivot_below_the_threshold_is_refactorised_with_pivoting() -> Result<(), Singular> {
        // σ·I − J = [[1, 0.01], [0.5, 1]] pivots on row 0 in column 0; then
        // [[0.01, 1], [1, 1]]: the kept pivot 0.01 is below 0.1 × 1, so rows swap.
        let pattern = SparsePattern::from_entries(2, [(0, 0), (1, 0), (0, 1), (1, 1)]);
        let jac_at = |a: [[f64; 2]; 2]| {
            // 𝒥 = σ·I − A with σ = 2, in the pattern's column order.
            let mut v = vec![0.0; 4];
            for (i, j) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                if let Some(p) = pattern.position(i, j) {
                    v[p] = if i == j { 2.0 } else { 0.0 } - a[i][j];
                }
            }
            v
        };
        let Some(mut lu) = SparseLu::new(2, &pattern) else {
            panic!("analysis failed");
        };
        lu.factor_real(2.0, &jac_at([[1.0, 0.01], [0.5, 1.0]]))?;
        let swapped = [[0.01, 1.0], [1.0, 1.0]];
        lu.factor_real(2.0, &jac_at(swapped))?;
        assert_eq!(lu.real.counts(), (2, 0));
        let mut x = [1.0, 2.0];
        lu.solve_real(&mut x);
        // Exact solution of [[0.01, 1], [1, 1]] x = (1, 2): x₀ = 1/0.99, x₁ = 2 − x₀.
        let exact = [1.0 / 0.99, 2.0 - 1.0 / 0.99];
        for k in 0..2 {
            assert!(
                (x[k] - exact[k]).abs() < 1e-15,
                "x{k} = {} vs {}",
                x[k],
                exact[k]
            );
        }
        // Back to the first matrix: the kept pivot (row 1 now, 0.5 against 1 below it) passes
        // the threshold, so no pivoting; the solution is still exact to round-off.
        lu.factor_real(2.0, &jac_at([[1.0, 0.01], [0.5, 1.0]]))?;
        assert_eq!(lu.real.counts(), (2, 1));
        let mut x = [1.0, 2.0];
        lu.solve_real(&mut x);
        // [[1, 0.01], [0.5, 1]] x = (1, 2): x₁ = 1.5 / 0.995, x₀ = 1 − 0.01 x₁.
        let x1 = 1.5 / 0.995;
        let exact = [1.0 - 0.01 * x1, x1];
        for k in 0..2 {
            assert!(
                (x[k] - exact[k]).abs() < 1e-15,
                "x{k} = {} vs {}",
                x[k],
                exact[k]
            );
        }
        Ok(())
    }
}
