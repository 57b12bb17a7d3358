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
    let scale = a[..m * m].iter().fold(0.0_f64, |s, x| s.max(x.abs()));
    for k in 0..m {
        let mut p = k;
        let mut best = a[k * m + k].abs();
        for i in k + 1..m {
            let v = a[i * m + k].abs();
            if v > best {
                (p, best) = (i, v);
            }
        }
        if best.is_nan() || best <= SINGULAR_PIVOT * scale {
            return Err(k);
        }
        piv[k] = p;
        if p != k {
            for j in 0..m {
                a.swap(k * m + j, p * m + j);
            }
        }
        let inv = 1.0 / a[k * m + k];
        for i in k + 1..m {
            let l = a[i * m + k] * inv;
            a[i * m + k] = l;
            if l != 0.0 {
                for j in k + 1..m {
                    a[i * m + j] -= l * a[k * m + j];
                }
            }
        }
    }
    Ok(())
}

/// Solves A x = b in place (`b` becomes x) with the factors of [`factor`].
pub fn solve(a: &[f64], m: usize, piv: &[usize], b: &mut [f64]) {
    for k in 0..m {
        b.swap(k, piv[k]);
    }
    for i in 0..m {
        let dot: f64 = (0..i).map(|j| a[i * m + j] * b[j]).sum();
        b[i] -= dot;
    }
    for i in (0..m).rev() {
        let dot: f64 = (i + 1..m).map(|j| a[i * m + j] * b[j]).sum();
        b[i] = (b[i] - dot) / a[i * m + i];
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
