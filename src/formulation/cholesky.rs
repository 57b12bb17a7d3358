//! In-place Cholesky factorisation and solve of a small dense SPD matrix (row-major).
//!
//! For the m ≲ 30 constraint rows of a linkage, a plain loop beats library calls (no allocation,
//! no dispatch); see "Small dense linear algebra" in `docs/measurements.md` for the measurements
//! that chose it.

/// Factors the SPD matrix `a` (m × m, row-major; only the lower triangle is read) in place
/// into L, lower triangle, with the *reciprocal* 1/L_jj stored on the diagonal so that
/// [`solve`] multiplies instead of dividing. Returns the index of the first pivot that is not
/// positive (relative to the diagonal), i.e. where the matrix is singular to working precision.
pub fn factor(a: &mut [f64], m: usize) -> Result<(), usize> {
    factor_with(a, m, |_, raw, diagonal| checked_pivot(raw, diagonal))
}

/// The pivot rule of [`factor`]: the raw pivot d = a_jj − Σ_k L_jk² itself, or `None` where
/// it is not positive relative to the diagonal entry a_jj (NaN, or d ≤ 1e-13 |a_jj|).
pub fn checked_pivot(raw: f64, diagonal: f64) -> Option<f64> {
    if raw.is_nan() || raw <= 1e-13 * diagonal.abs().max(f64::MIN_POSITIVE) {
        None
    } else {
        Some(raw)
    }
}

/// [`factor`] with the pivot rule given: `pivot(j, d, a_jj)` returns the pivot to use for
/// the raw pivot d of row j (diagonal entry a_jj), or `None` to stop with `Err(j)`. The
/// multiplier solve of the DAE regularises its pivots this way (`schur.rs`).
pub fn factor_with(
    a: &mut [f64],
    m: usize,
    mut pivot: impl FnMut(usize, f64, f64) -> Option<f64>,
) -> Result<(), usize> {
    debug_assert!(a.len() >= m * m, "matrix buffer holds m × m entries");
    for j in 0..m {
        let (row_j, below) = a[j * m..].split_at_mut(m);
        let (lj, tail_j) = row_j.split_at_mut(j);
        let diagonal = tail_j[0];
        let raw = diagonal - lj.iter().map(|x| x * x).sum::<f64>();
        let Some(d) = pivot(j, raw, diagonal) else {
            return Err(j);
        };
        let inv = 1.0 / d.sqrt();
        tail_j[0] = inv;
        for row_i in below.chunks_exact_mut(m) {
            let (li, tail_i) = row_i.split_at_mut(j);
            let dot: f64 = li.iter().zip(lj.iter()).map(|(x, y)| x * y).sum();
            tail_i[0] = (tail_i[0] - dot) * inv;
        }
    }
    Ok(())
}

/// Solves L Lᵀ x = b in place (`b` becomes x), with L from [`factor`].
pub fn solve(l: &[f64], m: usize, b: &mut [f64]) {
    for i in 0..m {
        let row = &l[i * m..i * m + m];
        let dot: f64 = row[..i].iter().zip(&b[..i]).map(|(x, y)| x * y).sum();
        b[i] = (b[i] - dot) * row[i];
    }
    for i in (0..m).rev() {
        let mut s = b[i];
        for k in (i + 1)..m {
            s -= l[k * m + i] * b[k];
        }
        b[i] = s * l[i * m + i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_spd_system_and_flags_singular_one() {
        // A = Bᵀ B + I for a fixed B; check A x = b.
        let a0 = [4.0, 2.0, 0.6, 2.0, 5.0, 1.5, 0.6, 1.5, 3.0];
        let mut a = a0;
        assert!(factor(&mut a, 3).is_ok());
        let mut x = [1.0, -2.0, 0.5];
        let b = x;
        solve(&a, 3, &mut x);
        for i in 0..3 {
            let r: f64 = (0..3).map(|k| a0[i * 3 + k] * x[k]).sum();
            assert!((r - b[i]).abs() < 1e-13, "row {i}: {r} vs {}", b[i]);
        }
        let mut singular = [1.0, 2.0, 2.0, 4.0];
        assert_eq!(factor(&mut singular, 2), Err(1));
    }
}
