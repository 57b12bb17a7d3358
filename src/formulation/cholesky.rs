//! In-place Cholesky factorisation and solve of a small dense SPD matrix (row-major).
//!
//! For the m ≲ 30 constraint rows of a linkage, a plain loop beats library calls (no allocation,
//! no dispatch); see "Small dense linear algebra" in `docs/measurements.md` for the measurements
//! that chose it.

/// Smallest relative pivot floor ε of [`factor`] (callers may pass a larger one): 1e-10, rows
/// within 1e-5 rad of dependence.
pub const PIVOT_FLOOR: f64 = 1e-10;

/// Factors the symmetric positive semi-definite matrix `a` (m × m, row-major; only the lower
/// triangle is read) in place into L, lower triangle, with the *reciprocal* 1/L_jj stored on
/// the diagonal so that [`solve`] multiplies instead of dividing.
///
/// **Rank-robust.** A pivot d_j = S_jj − Σ_k L_jk² that falls below ε S_jj (`floor` = ε, at
/// least [`PIVOT_FLOOR`]: row j is, to within √ε in angle, a combination of the rows before
/// it) is raised to ε S_jj. This is the modified Cholesky factorisation of Gill and Murray
/// (ref. 1, §4.4.2.2): it factors S + E exactly, with E ≥ 0 diagonal and non-zero only at the
/// raised pivots, is continuous in S (no jump when a pivot crosses the floor) and leaves every
/// well-conditioned S untouched (bit for bit). Where S is singular (a linkage at a singular
/// position: Φ_q has lost rank), the multipliers are not unique; the floor picks finite ones
/// (the component of λ along the lost direction is at most |r_j|/(ε S_jj)) and the constraint
/// forces Φ_qᵀ λ, which are unique, are recovered to O(ε) relative.
///
/// Returns the smallest pivot ratio d_j / S_jj before raising (in [0, 1]; 1 for m = 0): the
/// squared sine of the angle, in the M⁻¹ metric, between the row closest to dependence and the
/// rows before it, so that a ratio below ε means a raised pivot. Fails with the index of the
/// first pivot whose diagonal is not positive or is NaN (a zero row of Φ_q, or a non-finite
/// state).
///
/// # References
/// 1. P. E. Gill, W. Murray, M. H. Wright, *Practical Optimization*, Academic Press, 1981.
pub fn factor(a: &mut [f64], m: usize, floor: f64) -> Result<f64, usize> {
    let floor = floor.max(PIVOT_FLOOR);
    debug_assert!(a.len() >= m * m, "matrix buffer holds m × m entries");
    let mut smallest = 1.0_f64;
    for j in 0..m {
        let (done, rest) = a.split_at_mut(j * m);
        let (row_j, below) = rest.split_at_mut(m);
        let _ = done;
        let (lj, tail_j) = row_j.split_at_mut(j);
        let diagonal = tail_j[0];
        let d = diagonal - lj.iter().map(|x| x * x).sum::<f64>();
        if d.is_nan() || diagonal.is_nan() || diagonal <= 0.0 {
            return Err(j);
        }
        smallest = smallest.min((d / diagonal).max(0.0));
        let d = d.max(floor * diagonal);
        let inv = 1.0 / d.sqrt();
        tail_j[0] = inv;
        for row_i in below.chunks_exact_mut(m) {
            let (li, tail_i) = row_i.split_at_mut(j);
            let dot: f64 = li.iter().zip(lj.iter()).map(|(x, y)| x * y).sum();
            tail_i[0] = (tail_i[0] - dot) * inv;
        }
    }
    Ok(smallest)
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
    fn solves_spd_system_and_flags_a_zero_row() {
        // A = Bᵀ B + I for a fixed B; check A x = b.
        let a0 = [4.0, 2.0, 0.6, 2.0, 5.0, 1.5, 0.6, 1.5, 3.0];
        let mut a = a0;
        let ratio = factor(&mut a, 3, 0.0);
        assert!(
            matches!(ratio, Ok(r) if r > 0.5),
            "a well-conditioned matrix has no small pivot: {ratio:?}"
        );
        let mut x = [1.0, -2.0, 0.5];
        let b = x;
        solve(&a, 3, &mut x);
        for i in 0..3 {
            let r: f64 = (0..3).map(|k| a0[i * 3 + k] * x[k]).sum();
            assert!((r - b[i]).abs() < 1e-13, "row {i}: {r} vs {}", b[i]);
        }
        let mut zero_row = [1.0, 0.0, 0.0, 0.0];
        assert_eq!(factor(&mut zero_row, 2, 0.0), Err(1));
    }
}
