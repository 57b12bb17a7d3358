//! In-place Cholesky factorisation and solve of a small dense SPD matrix (row-major).
//!
//! For the m ≲ 30 constraint rows of a linkage, a plain loop beats library calls (no allocation,
//! no dispatch); see `../shared/reference/ida_and_speed.md` for the measurements that chose it.

/// Factors the SPD matrix `a` (m × m, row-major) in place into L (lower triangle).
/// Returns the index of the first pivot that is not positive (relative to the diagonal), i.e.
/// where the matrix is singular to working precision.
pub fn factor(a: &mut [f64], m: usize) -> Result<(), usize> {
    for j in 0..m {
        let mut d = a[j * m + j];
        for k in 0..j {
            d -= a[j * m + k] * a[j * m + k];
        }
        let scale = a[j * m + j].abs().max(f64::MIN_POSITIVE);
        if d.is_nan() || d <= 1e-13 * scale {
            return Err(j);
        }
        let d = d.sqrt();
        a[j * m + j] = d;
        let inv = 1.0 / d;
        for i in (j + 1)..m {
            let mut s = a[i * m + j];
            for k in 0..j {
                s -= a[i * m + k] * a[j * m + k];
            }
            a[i * m + j] = s * inv;
        }
    }
    Ok(())
}

/// Solves L Lᵀ x = b in place (`b` becomes x), with L from [`factor`].
pub fn solve(l: &[f64], m: usize, b: &mut [f64]) {
    for i in 0..m {
        let mut s = b[i];
        for k in 0..i {
            s -= l[i * m + k] * b[k];
        }
        b[i] = s / l[i * m + i];
    }
    for i in (0..m).rev() {
        let mut s = b[i];
        for k in (i + 1)..m {
            s -= l[k * m + i] * b[k];
        }
        b[i] = s / l[i * m + i];
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
