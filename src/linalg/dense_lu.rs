//! Small dense LU factorisations for coordinate partitioning, in place, allocation-free.
//!
//! * [`complete_pivoting`]: Gaussian elimination with complete (row and column) pivoting of an
//!   m × c matrix, m ≤ c. The pivot columns are the best-conditioned choice of m columns that a
//!   greedy elimination finds (ref. 1, §3.4.8); the ratio of the last pivot to the first is a
//!   cheap estimate of 1/cond of the chosen m × m block (ref. 1, §3.5.4: complete pivoting is
//!   rank-revealing in practice).
//! * [`factor`] / [`solve`]: LU with partial (row) pivoting of the square dependent block, for
//!   the Newton iterations and the velocity solve.
//!
//! User: the generalized formulation (`formulation/generalized/`), for dependent blocks below
//! `generalized::block::SPARSE_FROM` (20) rows and for its coordinate partition.
//!
//! Measured against nalgebra's and faer's LU (`cargo bench --bench linalg -- lu_small`,
//! factor + solve of one right-hand side, 2026-11-28, docs/measurements.md "One place for the
//! linear algebra"): 75, 178, 431 ns at n = 3, 6, 10 against nalgebra's 82, 200, 382 ns and
//! faer's 509, 848, 1 216 ns; 2.21 and 6.68 µs at 24 and 39 against nalgebra's 1.84 and
//! 6.33 µs. Faster than both up to 6 rows, 6–20 % slower than
//! nalgebra from 10 rows. Kept for what nalgebra's LU does not do: it works in the
//! formulation's own buffers without allocating (nalgebra's takes the matrix by value and
//! allocates its permutation and solution), and it stops at a pivot below 1e-14 of the
//! largest entry ([`SINGULAR_PIVOT`]), where nalgebra's reports only an exact zero; the
//! partition's choice of coordinates relies on that test.
//!
//! # References
//! 1. G. H. Golub, C. F. Van Loan, *Matrix Computations*, 4th ed., Johns Hopkins, 2013.

/// Result of [`complete_pivoting`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PivotQuality {
    /// |last pivot| / |first pivot| (0 for a matrix of lower rank or all zero; 1 when m = 0).
    pub ratio: f64,
    /// Product of the |pivots|: |det| of the chosen m × m block (0 for a matrix of lower rank;
    /// 1 when m = 0).
    pub volume: f64,
}

/// Gaussian elimination with complete pivoting of the m × c matrix `a` (row-major, destroyed).
/// Writes into `cols[..m]` the original indices of the pivot columns, in pivot order, and
/// returns the pivot ratio. `col_perm` is scratch of length ≥ c.
pub fn complete_pivoting(
    a: &mut [f64],
    m: usize,
    c: usize,
    cols: &mut [usize],
    col_perm: &mut [usize],
) -> PivotQuality {
    debug_assert!(a.len() >= m * c && m <= c && col_perm.len() >= c && cols.len() >= m);
    if m == 0 {
        return PivotQuality {
            ratio: 1.0,
            volume: 1.0,
        };
    }
    for (j, p) in col_perm.iter_mut().enumerate().take(c) {
        *p = j;
    }
    let mut first = 0.0_f64;
    let mut last = 0.0_f64;
    let mut volume = 1.0_f64;
    for k in 0..m {
        // Largest remaining entry (rows k.., columns k.. of the permuted matrix).
        let (mut bi, mut bj, mut best) = (k, k, -1.0_f64);
        for i in k..m {
            let row = &a[i * c..i * c + c];
            for (j, &p) in col_perm.iter().enumerate().take(c).skip(k) {
                let v = row[p].abs();
                if v > best {
                    (bi, bj, best) = (i, j, v);
                }
            }
        }
        if k == 0 {
            first = best;
        }
        last = best;
        volume *= best;
        if best.is_nan() || best <= 0.0 {
            // Rank below m (or NaN): fill the remaining choices in order.
            for (slot, &p) in cols.iter_mut().zip(col_perm.iter()).skip(k).take(m - k) {
                *slot = p;
            }
            return PivotQuality {
                ratio: 0.0,
                volume: 0.0,
            };
        }
        if bi != k {
            for j in 0..c {
                a.swap(k * c + j, bi * c + j);
            }
        }
        col_perm.swap(k, bj);
        let pc = col_perm[k];
        cols[k] = pc;
        let pivot = a[k * c + pc];
        for i in k + 1..m {
            let factor = a[i * c + pc] / pivot;
            if factor == 0.0 {
                continue;
            }
            for &p in col_perm.iter().take(c).skip(k) {
                a[i * c + p] -= factor * a[k * c + p];
            }
        }
    }
    PivotQuality {
        ratio: if first > 0.0 { last / first } else { 0.0 },
        volume,
    }
}

/// Relative size below which a pivot of [`factor`] counts as zero (the block is singular to
/// working precision).
pub const SINGULAR_PIVOT: f64 = 1e-14;

/// LU factorisation with partial pivoting of the m × m matrix `a` (row-major) in place; row
/// swaps in `piv`. Fails with the elimination step whose pivot is below [`SINGULAR_PIVOT`]
/// times the largest entry, or NaN.
pub fn factor(a: &mut [f64], m: usize, piv: &mut [usize]) -> Result<(), usize> {
    debug_assert!(a.len() >= m * m && piv.len() >= m);
    let a = &mut a[..m * m];
    let scale = a.iter().fold(0.0_f64, |s, x| s.max(x.abs()));
    eliminate(a, m, piv, |best| {
        !(best.is_nan() || best <= SINGULAR_PIVOT * scale)
    })
}

/// Gaussian elimination with partial (row) pivoting of the m × m matrix `a` (row-major,
/// exactly m² entries) in place: L below the diagonal (unit diagonal not stored), U on and
/// above it, row swaps in `piv`. `usable(|pivot|)` judges each pivot, the largest entry of its
/// column below the diagonal; the first it refuses stops the elimination with `Err(k)`, its
/// step. Shared by [`factor`] and Radau5's shifted LU (`linalg::shifted_lu`), which judge
/// their pivots differently.
pub(crate) fn eliminate(
    a: &mut [f64],
    m: usize,
    piv: &mut [usize],
    usable: impl Fn(f64) -> bool,
) -> Result<(), usize> {
    // Rows as chunks of a slice of known length: no index checks in the inner loops (the
    // same operations in the same order as index loops, so the same factors to the bit).
    for k in 0..m {
        let mut p = k;
        let mut best = a[k * m + k].abs();
        for i in k + 1..m {
            let v = a[i * m + k].abs();
            if v > best {
                (p, best) = (i, v);
            }
        }
        if !usable(best) {
            return Err(k);
        }
        piv[k] = p;
        if p != k {
            let (top, bottom) = a.split_at_mut(p * m);
            top[k * m..(k + 1) * m].swap_with_slice(&mut bottom[..m]);
        }
        let inv = 1.0 / a[k * m + k];
        let (top, below) = a.split_at_mut((k + 1) * m);
        let pivot_row = &top[k * m + k + 1..];
        for row in below.chunks_exact_mut(m) {
            let l = row[k] * inv;
            row[k] = l;
            if l != 0.0 {
                for (x, &u) in row[k + 1..].iter_mut().zip(pivot_row) {
                    *x -= l * u;
                }
            }
        }
    }
    Ok(())
}

/// Solves A x = b in place (`b` becomes x) with the factors of [`factor`].
pub fn solve(a: &[f64], m: usize, piv: &[usize], b: &mut [f64]) {
    if m == 0 {
        return;
    }
    for k in 0..m {
        b.swap(k, piv[k]);
    }
    let (a, b) = (&a[..m * m], &mut b[..m]);
    for (i, row) in a.chunks_exact(m).enumerate() {
        let (done, rest) = b.split_at_mut(i);
        let dot: f64 = row[..i].iter().zip(done.iter()).map(|(l, x)| l * x).sum();
        rest[0] -= dot;
    }
    for (i, row) in a.chunks_exact(m).enumerate().rev() {
        let (head, done) = b.split_at_mut(i + 1);
        let dot: f64 = row[i + 1..]
            .iter()
            .zip(done.iter())
            .map(|(u, x)| u * x)
            .sum();
        head[i] = (head[i] - dot) / row[i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partial_pivoting_solves_a_system_that_needs_a_row_swap() {
        // a₀₀ = 0: without the swap the elimination divides by zero.
        let a0 = [0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0];
        let mut a = a0;
        let mut piv = [0; 3];
        assert_eq!(factor(&mut a, 3, &mut piv), Ok(()));
        let x_true = [1.0, -2.0, 0.5];
        let mut b: Vec<f64> = (0..3)
            .map(|i| (0..3).map(|j| a0[i * 3 + j] * x_true[j]).sum())
            .collect();
        solve(&a, 3, &piv, &mut b);
        for i in 0..3 {
            // Exact data of size 1, condition number ~10: round-off only.
            assert!(
                (b[i] - x_true[i]).abs() < 1e-14,
                "x[{i}] = {} vs {}",
                b[i],
                x_true[i]
            );
        }
        let mut singular = [1.0, 2.0, 2.0, 4.0];
        assert_eq!(factor(&mut singular, 2, &mut piv), Err(1));
    }

    #[test]
    fn complete_pivoting_picks_the_independent_columns() {
        // Column 1 = 2 × column 0: at most one of them can be a pivot column; columns 2, 3
        // are independent of each other and of column 0.
        let mut a = [1.0, 2.0, 0.0, 0.5, 0.5, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 3.0];
        let mut cols = [0; 3];
        let mut perm = [0; 4];
        let q = complete_pivoting(&mut a, 3, 4, &mut cols, &mut perm);
        let mut sorted = cols;
        sorted.sort_unstable();
        assert!(!(sorted.contains(&0) && sorted.contains(&1)), "{cols:?}");
        assert!(q.ratio > 0.0 && q.ratio <= 1.0, "{q:?}");
        // |det| of the chosen block is the product of the pivots: greedy takes 3 (column 3),
        // then 2 (column 1), then 1 (column 2), and |det| of columns 1, 2, 3 is 3·(2·1 − 0·1)
        // = 6, the largest of any three columns (columns 0, 2, 3 give 3).
        assert!((q.volume - 6.0).abs() < 1e-12, "{q:?}");
        // Rank 1: the second pivot is zero.
        let mut b = [1.0, 2.0, 2.0, 4.0];
        let q = complete_pivoting(&mut b, 2, 2, &mut cols, &mut perm);
        assert_eq!(q.ratio, 0.0);
        assert_eq!(q.volume, 0.0);
    }
}
