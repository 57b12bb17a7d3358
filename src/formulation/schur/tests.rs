//! The skyline factorisation against the dense one on random rows with the structure of linkage
//! constraints, and the reverse Cuthill–McKee order on a chain.

use super::*;
use crate::formulation::test_rng::Lcg;

/// Rows of `n_bodies` bodies joined like a linkage: each "joint" gives two rows between two
/// bodies (or a body and ground), with random Jacobian blocks; bodies are shuffled so that the
/// row order is far from banded.
fn random_rows(rng: &mut Lcg, n_bodies: usize, n_joints: usize) -> Vec<ConstraintRow> {
    let mut label: Vec<usize> = (0..n_bodies).collect();
    for k in (1..n_bodies).rev() {
        label.swap(k, rng.below(k + 1));
    }
    let mut rows = Vec::new();
    for j in 0..n_joints {
        // Mostly neighbours along a chain (as in a chain of loops), now and then a long link.
        let a = j % n_bodies;
        let b = if rng.next() < 0.8 {
            (a + 1 + rng.below(2)) % n_bodies
        } else {
            rng.below(n_bodies)
        };
        let ground = j % 7 == 0;
        for _ in 0..2 {
            let mut block = || [rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5];
            let (jac_a, jac_b) = (block(), block());
            rows.push(ConstraintRow {
                body_a: if ground { None } else { Some(label[a]) },
                jac_a,
                body_b: Some(label[b]),
                jac_b,
            });
        }
    }
    rows
}

/// S x for the rows, straight from the definition S = Φ_q M⁻¹ Φ_qᵀ with a dense Φ_q.
fn schur_times(rows: &[ConstraintRow], inv_mass: &[f64], x: &[f64]) -> Vec<f64> {
    let n = inv_mass.len();
    let mut force = vec![0.0; n];
    for (row, xi) in rows.iter().zip(x) {
        for (body, jac) in row.blocks() {
            if let Some(b) = body {
                for c in 0..3 {
                    force[3 * b + c] += jac[c] * xi;
                }
            }
        }
    }
    rows.iter()
        .map(|row| {
            row.blocks()
                .iter()
                .filter_map(|(body, jac)| {
                    body.map(|b| {
                        (0..3)
                            .map(|c| jac[c] * inv_mass[3 * b + c] * force[3 * b + c])
                            .sum::<f64>()
                    })
                })
                .sum()
        })
        .collect()
}

#[test]
fn skyline_solves_as_the_dense_cholesky_on_random_linkage_rows() {
    let mut rng = Lcg(12);
    let mut solved = 0;
    for case in 0..40 {
        let n_bodies = 5 + rng.below(60);
        // At most one joint (two rows) per body, fewer rows than coordinates in every group of
        // neighbouring bodies, so S is almost surely positive definite.
        let n_joints = n_bodies / 2 + rng.below(n_bodies / 2 + 1);
        let rows = random_rows(&mut rng, n_bodies, n_joints);
        let active: Vec<usize> = (0..rows.len()).collect();
        let inv_mass: Vec<f64> = (0..3 * n_bodies).map(|_| 0.5 + 2.0 * rng.next()).collect();
        let b: Vec<f64> = active.iter().map(|_| rng.next() - 0.5).collect();
        let mut dense = Schur::new(&rows, &active, SchurSolver::Dense);
        let mut skyline = Schur::new(&rows, &active, SchurSolver::Skyline);
        assert!(
            !dense.is_skyline() && skyline.is_skyline(),
            "case {case}: storages"
        );
        let dense_ok = dense.factor(&rows, &active, &inv_mass, 0.0);
        let skyline_ok = skyline.factor(&rows, &active, &inv_mass, 0.0);
        assert_eq!(
            dense_ok.is_ok(),
            skyline_ok.is_ok(),
            "case {case}: dense {dense_ok:?} vs skyline {skyline_ok:?}"
        );
        if dense_ok.is_err() {
            continue;
        }
        solved += 1;
        let (mut x_dense, mut x_skyline) = (b.clone(), b.clone());
        dense.solve(&mut x_dense);
        skyline.solve(&mut x_skyline);
        // Both are backward stable: the residual of each is round-off of |S| |x|, and they
        // agree to the condition number times that; 1e-9 relative leaves room for the
        // condition numbers (≲ 1e5) of these random matrices.
        let scale = x_dense.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        for (k, (xd, xs)) in x_dense.iter().zip(&x_skyline).enumerate() {
            assert!(
                (xd - xs).abs() <= 1e-9 * scale,
                "case {case} ({n_bodies} bodies, {} rows), row {k}: dense {xd:e} vs skyline {xs:e}",
                rows.len()
            );
        }
        let residual = schur_times(&rows, &inv_mass, &x_skyline);
        let b_scale = b.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        for (k, (r, bk)) in residual.iter().zip(&b).enumerate() {
            assert!(
                (r - bk).abs() <= 1e-9 * b_scale.max(scale),
                "case {case}, row {k}: S x = {r:e} vs b = {bk:e}"
            );
        }
    }
    // Random blocks of full rank almost surely: the comparison is not vacuous.
    assert!(
        solved >= 30,
        "only {solved} of 40 random cases were positive definite"
    );
}

#[test]
fn a_repeated_row_is_reported_by_both_storages() {
    let mut rng = Lcg(3);
    let mut rows = random_rows(&mut rng, 40, 30);
    // Row 41 repeats row 17: S is singular, and the pivot of one of the two is zero.
    rows[41] = rows[17];
    let active: Vec<usize> = (0..rows.len()).collect();
    let inv_mass = vec![1.0; 120];
    let mut dense = Schur::new(&rows, &active, SchurSolver::Dense);
    // Row order: the later copy is the combination of the rows before it.
    assert_eq!(dense.factor(&rows, &active, &inv_mass, 0.0), Err(41));
    let mut skyline = Schur::new(&rows, &active, SchurSolver::Skyline);
    let failed = skyline.factor(&rows, &active, &inv_mass, 0.0);
    assert!(
        failed == Err(17) || failed == Err(41),
        "skyline names one of the two copies (17, 41), got {failed:?}"
    );
    // A relative shift makes the same matrix positive definite (the assembly's use).
    assert_eq!(skyline.factor(&rows, &active, &inv_mass, 1e-10), Ok(()));
}

#[test]
fn reverse_cuthill_mckee_makes_a_shuffled_chain_banded() {
    // Rows of a chain of 300 bodies, two rows per joint, numbered in a scrambled order.
    let n = 300;
    let mut rng = Lcg(7);
    let mut label: Vec<usize> = (0..n).collect();
    for k in (1..n).rev() {
        label.swap(k, rng.below(k + 1));
    }
    let rows: Vec<ConstraintRow> = (0..n - 1)
        .flat_map(|j| {
            let row = ConstraintRow {
                body_a: Some(label[j]),
                jac_a: [1.0, 0.0, 0.5],
                body_b: Some(label[j + 1]),
                jac_b: [-1.0, 0.0, 0.5],
            };
            [row, row]
        })
        .collect();
    let mut order: Vec<usize> = (0..rows.len()).collect();
    for k in (1..order.len()).rev() {
        order.swap(k, rng.below(k + 1));
    }
    let skyline = Schur::new(&rows, &order, SchurSolver::Skyline);
    // Banded after renumbering: each row couples to the rows of its own joint and the two
    // joints beside it, so its envelope reaches back at most 3 rows (4 entries with the
    // diagonal); scrambled it would be about m/3 on average.
    let m = rows.len();
    assert!(
        skyline.stored_entries() <= 4 * m,
        "envelope {} entries for {m} rows (band ≤ 4 per row expected)",
        skyline.stored_entries()
    );
}

/// The regularised pivots of [`Schur::factor_regularised`] (μ = 1e-10 of each row's
/// translational diagonal; the DAE uses 1e-8): on positive definite S they change the solution by (μ/r)² relative (r the pivot
/// ratios), below round-off; on a singular S (a repeated row) both storages factor and the
/// solution is finite, bounded by ~|b|/μ, and satisfies S x = b along the rows that are
/// independent (the other copy's residual is what the shift absorbs).
#[test]
fn regularised_pivots_leave_a_regular_solve_alone_and_bound_a_singular_one() {
    let mut rng = Lcg(12);
    let mut checked = 0;
    for case in 0..20 {
        let n_bodies = 5 + rng.below(30);
        let n_joints = n_bodies / 2 + rng.below(n_bodies / 2 + 1);
        let rows = random_rows(&mut rng, n_bodies, n_joints);
        let active: Vec<usize> = (0..rows.len()).collect();
        let inv_mass: Vec<f64> = (0..3 * n_bodies).map(|_| 0.5 + 2.0 * rng.next()).collect();
        let shift: Vec<f64> = translational_diagonal(&rows, &active, &inv_mass)
            .iter()
            .map(|d| 1e-10 * d)
            .collect();
        let b: Vec<f64> = active.iter().map(|_| rng.next() - 0.5).collect();
        for solver in [SchurSolver::Dense, SchurSolver::Skyline] {
            let mut plain = Schur::new(&rows, &active, solver);
            if plain.factor(&rows, &active, &inv_mass, 0.0).is_err() {
                continue;
            }
            let mut regularised = Schur::new(&rows, &active, solver);
            assert_eq!(
                regularised.factor_regularised(&rows, &active, &inv_mass, &shift),
                Ok(()),
                "case {case}, {solver:?}"
            );
            let (mut x, mut x_reg) = (b.clone(), b.clone());
            plain.solve(&mut x);
            regularised.solve(&mut x_reg);
            // Round-off of the two factorisations times the condition number, far above the
            // regularisation's (μ/r)², where S is well conditioned: |x| ≤ 1e4 |b| (a random
            // case now and then is nearly singular, and then its own kind of test, below).
            let scale = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            if scale > 1e4 {
                continue;
            }
            for (k, (a, r)) in x.iter().zip(&x_reg).enumerate() {
                assert!(
                    (a - r).abs() <= 1e-9 * scale,
                    "case {case}, {solver:?}, row {k}: plain {a:e} vs regularised {r:e}"
                );
            }
            checked += 1;
        }
    }
    assert!(checked >= 30, "only {checked} regular cases compared");

    let mut rows = random_rows(&mut Lcg(3), 40, 30);
    rows[41] = rows[17];
    let active: Vec<usize> = (0..rows.len()).collect();
    let inv_mass = vec![1.0; 120];
    let shift: Vec<f64> = translational_diagonal(&rows, &active, &inv_mass)
        .iter()
        .map(|d| 1e-10 * d)
        .collect();
    let mut rng = Lcg(5);
    let mut b: Vec<f64> = active.iter().map(|_| rng.next() - 0.5).collect();
    // A consistent right-hand side (the two copies ask the same), as the DAE's on the
    // motion; then x is the minimum-norm-like solution with the two copies sharing.
    b[41] = b[17];
    for solver in [SchurSolver::Dense, SchurSolver::Skyline] {
        let mut s = Schur::new(&rows, &active, solver);
        assert_eq!(
            s.factor_regularised(&rows, &active, &inv_mass, &shift),
            Ok(()),
            "{solver:?}"
        );
        let mut x = b.clone();
        s.solve(&mut x);
        assert!(x.iter().all(|v| v.is_finite()), "{solver:?}: {x:?}");
        // Along the null direction (x_17 − x_41) the consistent b has no component, so x
        // stays of the size of a regular solve: bound 1e3, far below |b|/μ ~ 1e10.
        let size = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        assert!(size < 1e3, "{solver:?}: |x| = {size:e}");
        let residual = schur_times(&rows, &inv_mass, &x);
        for (k, (r, bk)) in residual.iter().zip(&b).enumerate() {
            assert!(
                (r - bk).abs() <= 1e-6,
                "{solver:?}, row {k}: S x = {r:e} vs b = {bk:e}"
            );
        }
    }
}
