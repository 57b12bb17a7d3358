//! In-place Cholesky factorisation and solve of a small dense SPD matrix (row-major).
//!
//! Users: the DAE's Schur complement up to `formulation::schur::DENSE_MAX_ROWS` (16) rows, the
//! assembly's row basis.
//!
//! Kept by measurement (`cargo bench --bench linalg -- spd_small`, factor + solve of one
//! right-hand side, 2026-11-28, docs/measurements.md "One place for the linear algebra"):
//! 104 ns at m = 7 (the four-bar's Schur complement) against 281 ns for nalgebra's Cholesky
//! and 651 ns for faer's; 641 ns at m = 16 against 1.03 µs and 1.40 µs. No allocation, no
//! dispatch, and the loops unrolled for each m up to 10.

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
    pivot: impl FnMut(usize, f64, f64) -> Option<f64>,
) -> Result<(), usize> {
    debug_assert!(a.len() >= m * m, "matrix buffer holds m × m entries");
    // The few rows of a small linkage (7 for a four-bar) get a copy of the loops for their
    // exact count, which the compiler unrolls: the general loops over rows of 1 to 7 entries
    // were mostly loop overhead (a sixth of a DAE run). The same operations in the same order
    // either way, so the factor is the same to the bit.
    match m {
        1 => factor_fixed::<1>(a, pivot),
        2 => factor_fixed::<2>(a, pivot),
        3 => factor_fixed::<3>(a, pivot),
        4 => factor_fixed::<4>(a, pivot),
        5 => factor_fixed::<5>(a, pivot),
        6 => factor_fixed::<6>(a, pivot),
        7 => factor_fixed::<7>(a, pivot),
        8 => factor_fixed::<8>(a, pivot),
        9 => factor_fixed::<9>(a, pivot),
        10 => factor_fixed::<10>(a, pivot),
        _ => factor_any(a, m, pivot),
    }
}

/// [`factor_with`] for m = M.
fn factor_fixed<const M: usize>(
    a: &mut [f64],
    mut pivot: impl FnMut(usize, f64, f64) -> Option<f64>,
) -> Result<(), usize> {
    // A slice of known length: with the loops unrolled, every index is a constant in bounds.
    let a = &mut a[..M * M];
    // One copy of the column step per column index, written out: the compiler does not unroll
    // the nest of loops whole (their bounds depend on the column), and their counters and
    // exits were a third of a DAE factorisation. Columns j ≥ M are compiled away.
    macro_rules! columns {
        ($($j:literal)*) => {$(
            if $j < M {
                let j: usize = $j;
                let diagonal = a[j * M + j];
                // Sums start at −0, as `Iterator::sum` does (the same zeros as `factor_any`).
                let mut sum = -0.0;
                for k in 0..j {
                    sum += a[j * M + k] * a[j * M + k];
                }
                let raw = diagonal - sum;
                let Some(d) = pivot(j, raw, diagonal) else {
                    return Err(j);
                };
                let inv = 1.0 / d.sqrt();
                a[j * M + j] = inv;
                for i in j + 1..M {
                    let mut dot = -0.0;
                    for k in 0..j {
                        dot += a[i * M + k] * a[j * M + k];
                    }
                    a[i * M + j] = (a[i * M + j] - dot) * inv;
                }
            }
        )*};
    }
    columns!(0 1 2 3 4 5 6 7 8 9);
    debug_assert!(M <= 10, "fixed sizes up to 10 rows");
    Ok(())
}

/// [`factor_with`] for any m.
fn factor_any(
    a: &mut [f64],
    m: usize,
    mut pivot: impl FnMut(usize, f64, f64) -> Option<f64>,
) -> Result<(), usize> {
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
    // Fixed sizes for small m, as in `factor_with` (the same operations in the same order).
    match m {
        1 => solve_fixed::<1>(l, b),
        2 => solve_fixed::<2>(l, b),
        3 => solve_fixed::<3>(l, b),
        4 => solve_fixed::<4>(l, b),
        5 => solve_fixed::<5>(l, b),
        6 => solve_fixed::<6>(l, b),
        7 => solve_fixed::<7>(l, b),
        8 => solve_fixed::<8>(l, b),
        9 => solve_fixed::<9>(l, b),
        10 => solve_fixed::<10>(l, b),
        _ => solve_any(l, m, b),
    }
}

/// [`solve`] for m = M.
fn solve_fixed<const M: usize>(l: &[f64], b: &mut [f64]) {
    let (l, b) = (&l[..M * M], &mut b[..M]);
    // Rows written out as in `factor_fixed`.
    macro_rules! forward {
        ($($i:literal)*) => {$(
            if $i < M {
                let i: usize = $i;
                let mut dot = -0.0;
                for k in 0..i {
                    dot += l[i * M + k] * b[k];
                }
                b[i] = (b[i] - dot) * l[i * M + i];
            }
        )*};
    }
    macro_rules! backward {
        ($($i:literal)*) => {$(
            if $i < M {
                let i: usize = $i;
                let mut s = b[i];
                for k in (i + 1)..M {
                    s -= l[k * M + i] * b[k];
                }
                b[i] = s * l[i * M + i];
            }
        )*};
    }
    forward!(0 1 2 3 4 5 6 7 8 9);
    backward!(9 8 7 6 5 4 3 2 1 0);
    debug_assert!(M <= 10, "fixed sizes up to 10 rows");
}

/// [`solve`] for any m.
fn solve_any(l: &[f64], m: usize, b: &mut [f64]) {
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
    use crate::formulation::test_rng::Lcg;

    /// The copies for fixed sizes factor and solve as the general loops do, to the bit, for
    /// every size they cover and beyond; and they stop at the same pivot.
    #[test]
    fn fixed_sizes_equal_the_general_loops_bit_for_bit() {
        let mut rng = Lcg(7);
        for m in 1..=12 {
            // A = Bᵀ B + I/10: SPD, well enough conditioned.
            let b: Vec<f64> = (0..m * m).map(|_| rng.range(-1.0, 1.0)).collect();
            let mut a = vec![0.0; m * m];
            for i in 0..m {
                for j in 0..m {
                    a[i * m + j] = (0..m).map(|k| b[k * m + i] * b[k * m + j]).sum::<f64>()
                        + if i == j { 0.1 } else { 0.0 };
                }
            }
            let (mut fast, mut plain) = (a.clone(), a.clone());
            assert_eq!(factor(&mut fast, m), Ok(()));
            assert_eq!(
                factor_any(&mut plain, m, |_, r, d| checked_pivot(r, d)),
                Ok(())
            );
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&fast), bits(&plain), "factor, m = {m}");
            let rhs: Vec<f64> = (0..m).map(|_| rng.range(-1.0, 1.0)).collect();
            let (mut x_fast, mut x_plain) = (rhs.clone(), rhs.clone());
            solve(&fast, m, &mut x_fast);
            solve_any(&plain, m, &mut x_plain);
            assert_eq!(bits(&x_fast), bits(&x_plain), "solve, m = {m}");
            // A singular last row stops both at the same pivot.
            if m > 1 {
                let mut singular = a.clone();
                for j in 0..m {
                    singular[(m - 1) * m + j] = singular[(m - 2) * m + j];
                    singular[j * m + m - 1] = singular[j * m + m - 2];
                }
                let mut other = singular.clone();
                assert_eq!(factor(&mut singular, m), Err(m - 1), "m = {m}");
                assert_eq!(
                    factor_any(&mut other, m, |_, r, d| checked_pivot(r, d)),
                    Err(m - 1)
                );
            }
        }
    }

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
