//! Every kernel of [`super`] held to the same contract through [`Factorisation`], on the same
//! matrices: it solves what nalgebra's LU solves, to round-off; it factors a second matrix of
//! the same pattern as well as the first (the sparse LU then refactorises with its kept
//! pivots); and it reports a matrix that is singular to working precision instead of solving
//! it.
//!
//! The matrices are shaped like a linkage's: banded with a few entries per row (the skyline's
//! and the sparse LU's patterns), scrambled so that the skyline must renumber, at the sizes
//! each kernel meets (1 to 40 for the dense kernels, up to 300 for the sparse ones).

use super::{
    DenseCholesky, DenseLu, Factorisation, ShiftedLu, Singular, SkylineCholesky, SparseLu,
};
use crate::formulation::test_rng::Lcg;

/// A random permutation of 0..n.
fn shuffled(n: usize, rng: &mut Lcg) -> Vec<usize> {
    let mut p: Vec<usize> = (0..n).collect();
    for k in (1..n).rev() {
        p.swap(k, rng.below(k + 1));
    }
    p
}

/// B: n × n, row k non-zero in columns k − 2 … k (a chain's coupling to its two neighbours),
/// rows and columns renumbered by `label`, the diagonal kept away from zero.
fn banded_factor(n: usize, label: &[usize], rng: &mut Lcg) -> Vec<f64> {
    let mut b = vec![0.0; n * n];
    for k in 0..n {
        for j in k.saturating_sub(2)..=k {
            let v = if j == k {
                rng.range(1.0, 2.0)
            } else {
                rng.range(-1.0, 1.0)
            };
            b[label[k] * n + label[j]] = v;
        }
    }
    b
}

/// A = B Bᵀ (SPD, banded of half-width 4 in the hidden numbering).
fn spd(b: &[f64], n: usize) -> Vec<f64> {
    let mut a = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            a[i * n + j] = (0..n).map(|k| b[i * n + k] * b[j * n + k]).sum();
        }
    }
    a
}

/// A general matrix of the pattern of B + Bᵀ, with random values and a dominant diagonal.
fn general(b: &[f64], n: usize, rng: &mut Lcg) -> Vec<f64> {
    let mut a = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            if b[i * n + j] != 0.0 || b[j * n + i] != 0.0 {
                a[i * n + j] = rng.range(-1.0, 1.0);
            }
        }
        a[i * n + i] = rng.range(4.0, 6.0) * if i % 2 == 0 { 1.0 } else { -1.0 };
    }
    a
}

/// The solution of A x = b by nalgebra's LU with partial pivoting.
fn reference(a: &[f64], n: usize, b: &[f64]) -> Vec<f64> {
    let m = nalgebra::DMatrix::from_row_slice(n, n, a);
    let rhs = nalgebra::DVector::from_column_slice(b);
    match m.lu().solve(&rhs) {
        Some(x) => x.iter().copied().collect(),
        None => panic!("the test matrix is singular for nalgebra"),
    }
}

fn times(a: &[f64], n: usize, x: &[f64]) -> Vec<f64> {
    (0..n)
        .map(|i| (0..n).map(|j| a[i * n + j] * x[j]).sum())
        .collect()
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// The kernels that apply to a matrix of this kind and size, built for its pattern.
fn kernels(a: &[f64], n: usize, spd: bool) -> Vec<(&'static str, Box<dyn Factorisation>)> {
    let mut k: Vec<(&'static str, Box<dyn Factorisation>)> = Vec::new();
    if n <= 40 {
        if spd {
            k.push(("dense Cholesky", Box::new(DenseCholesky::new(n))));
        }
        k.push(("dense LU", Box::new(DenseLu::new(n))));
        k.push(("shifted LU", Box::new(ShiftedLu::for_pattern_of(a, n))));
    }
    if spd {
        k.push((
            "skyline Cholesky",
            Box::new(SkylineCholesky::for_pattern_of(a, n)),
        ));
    }
    match SparseLu::for_pattern_of(a, n) {
        Some(lu) => k.push(("sparse LU", Box::new(lu))),
        None => panic!("faer could not analyse the pattern"),
    }
    k
}

/// Factors `a` with `kernel`, solves for a random right-hand side, and checks the solution
/// against nalgebra's and the residual against round-off.
fn check_solve(name: &str, kernel: &mut dyn Factorisation, a: &[f64], n: usize, rng: &mut Lcg) {
    assert_eq!(kernel.dim(), n, "{name}");
    if let Err(e) = kernel.factor(a) {
        panic!("{name}, n = {n}: {e:?} on a regular matrix");
    }
    let b: Vec<f64> = (0..n).map(|_| rng.range(-1.0, 1.0)).collect();
    let want = reference(a, n, &b);
    let mut x = b.clone();
    kernel.solve(&mut x);
    let scale = max_abs(&want).max(1.0);
    let off: Vec<f64> = x.iter().zip(&want).map(|(p, q)| p - q).collect();
    assert!(
        max_abs(&off) <= 1e-11 * scale,
        "{name}, n = {n}: differs from nalgebra by {:e}",
        max_abs(&off)
    );
    let r: Vec<f64> = times(a, n, &x).iter().zip(&b).map(|(p, q)| p - q).collect();
    let norm_a = max_abs(a) * n as f64;
    assert!(
        max_abs(&r) <= 64.0 * f64::EPSILON * norm_a * max_abs(&x).max(1.0),
        "{name}, n = {n}: residual {:e}",
        max_abs(&r)
    );
}

#[test]
fn every_kernel_solves_what_nalgebra_solves_and_refactors_its_pattern() {
    let mut rng = Lcg(2024);
    for n in [1, 2, 3, 5, 7, 10, 16, 17, 24, 40, 120, 300] {
        let label = shuffled(n, &mut rng);
        let b = banded_factor(n, &label, &mut rng);
        for spd_case in [true, false] {
            let first = if spd_case {
                spd(&b, n)
            } else {
                general(&b, n, &mut rng)
            };
            // A second matrix of the same pattern: values moved by up to 30 %.
            let second: Vec<f64> = first.iter().map(|v| v * rng.range(0.85, 1.15)).collect();
            let second = if spd_case {
                // Kept symmetric: the mean of it and its transpose.
                (0..n * n)
                    .map(|k| 0.5 * (second[k] + second[(k % n) * n + k / n]))
                    .collect()
            } else {
                second
            };
            for (name, mut kernel) in kernels(&first, n, spd_case) {
                check_solve(name, kernel.as_mut(), &first, n, &mut rng);
                check_solve(name, kernel.as_mut(), &second, n, &mut rng);
            }
        }
    }
}

/// A = B Bᵀ with row r of B a copy of another row s: rows r and s of A are equal, so A is
/// singular, and its last pivot in their elimination is round-off of the others. The kernels
/// with a relative singularity test (the Choleskys, 1e-13 of the diagonal entry; the dense LU,
/// 1e-14 of the largest entry) say so, the Choleskys naming one of the two rows.
#[test]
fn the_kernels_with_a_relative_pivot_test_report_a_matrix_singular_to_working_precision() {
    let mut rng = Lcg(99);
    for n in [3, 7, 16, 40, 200] {
        let label = shuffled(n, &mut rng);
        let mut b = banded_factor(n, &label, &mut rng);
        let (s, r) = (label[n / 2 - 1], label[n / 2]);
        for j in 0..n {
            b[r * n + j] = b[s * n + j];
        }
        let a = spd(&b, n);
        let mut checked: Vec<(&str, Box<dyn Factorisation>)> = vec![(
            "skyline Cholesky",
            Box::new(SkylineCholesky::for_pattern_of(&a, n)),
        )];
        if n <= 40 {
            checked.push(("dense Cholesky", Box::new(DenseCholesky::new(n))));
            checked.push(("dense LU", Box::new(DenseLu::new(n))));
        }
        for (name, mut kernel) in checked {
            match kernel.factor(&a) {
                Ok(()) => panic!("{name}, n = {n}: factored a singular matrix"),
                Err(Singular { column }) if name.contains("Cholesky") => assert!(
                    column == r || column == s,
                    "{name}, n = {n}: singular at row {column}, the repeated rows are {s} and {r}"
                ),
                Err(Singular { column }) => assert!(column < n, "{name}: column {column}"),
            }
        }
    }
}

/// A matrix with a column of zeros has no pivot there at all: every LU reports it (the
/// shifted and the sparse LU test for an exactly zero or non-finite pivot only, as Radau5's
/// and IDA's Newton iterations meet a nearly singular matrix by their own convergence test).
#[test]
fn every_lu_reports_an_exactly_singular_matrix() {
    let mut rng = Lcg(31);
    for n in [3, 7, 16, 40, 200] {
        let label = shuffled(n, &mut rng);
        let b = banded_factor(n, &label, &mut rng);
        let mut a = general(&b, n, &mut rng);
        let zero = label[n / 2];
        for i in 0..n {
            a[i * n + zero] = 0.0;
        }
        // The pattern from the regular matrix, as a model's Jacobian keeps its pattern.
        let regular = general(&b, n, &mut rng);
        let mut checked: Vec<(&str, Box<dyn Factorisation>)> = Vec::new();
        if n <= 40 {
            checked.push(("dense LU", Box::new(DenseLu::new(n))));
            checked.push((
                "shifted LU",
                Box::new(ShiftedLu::for_pattern_of(&regular, n)),
            ));
        }
        match SparseLu::for_pattern_of(&regular, n) {
            Some(lu) => checked.push(("sparse LU", Box::new(lu))),
            None => panic!("faer could not analyse the pattern"),
        }
        for (name, mut kernel) in checked {
            assert!(
                kernel.factor(&a).is_err(),
                "{name}, n = {n}: factored a matrix with a zero column"
            );
        }
    }
}

/// An indefinite symmetric matrix is no matrix for a Cholesky: both refuse it at the first
/// negative pivot, where the LUs solve it.
#[test]
fn the_choleskys_refuse_an_indefinite_matrix_the_lus_solve_it() {
    let n = 5;
    let mut a = vec![0.0; n * n];
    for i in 0..n {
        a[i * n + i] = if i == 2 { -1.0 } else { 2.0 };
        if i + 1 < n {
            a[i * n + i + 1] = 0.5;
            a[(i + 1) * n + i] = 0.5;
        }
    }
    let mut rng = Lcg(5);
    assert_eq!(
        DenseCholesky::new(n).factor(&a),
        Err(Singular { column: 2 })
    );
    let mut skyline = SkylineCholesky::for_pattern_of(&a, n);
    assert!(skyline.factor(&a).is_err());
    for (name, mut kernel) in kernels(&a, n, false) {
        check_solve(name, kernel.as_mut(), &a, n, &mut rng);
    }
}

/// A system with nothing to solve (a model without constraints, every component decoupled)
/// is no error and changes nothing.
#[test]
fn an_empty_system_solves_to_nothing() {
    let mut dense = DenseLu::new(0);
    assert_eq!(dense.factor(&[]), Ok(()));
    let mut b: [f64; 0] = [];
    dense.solve(&mut b);
    // One decoupled component: the coupled block is empty, the component a division.
    let mut shifted = ShiftedLu::for_pattern_of(&[4.0], 1);
    assert_eq!(shifted.factor(&[4.0]), Ok(()));
    let mut x = [2.0];
    shifted.solve(&mut x);
    assert_eq!(x, [0.5]);
}
