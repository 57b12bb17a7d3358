//! Each linear-algebra kernel of `linkdyn::linalg` against faer and nalgebra at the sizes it
//! meets, factor + solve of one right-hand side per iteration (the kernels' reason to exist:
//! module documentation of `src/linalg/`, numbers in docs/measurements.md, "One place for the
//! linear algebra"):
//!
//! * `spd_small`: SPD, m = 7 (the four-bar's Schur complement) and 16 (the dense limit):
//!   the hand-written Cholesky, nalgebra's, faer's;
//! * `spd_chain`: SPD with a chain's band (half-width 4, rows scrambled), m = 62, 242, 1202:
//!   the skyline Cholesky after reverse Cuthill–McKee, faer's sparse Cholesky (AMD and symbolic
//!   analysis once, numeric factor and solve per iteration), faer's dense one (m ≤ 242);
//! * `lu_small`: general square, n = 3, 6, 10 (the generalized formulation's dependent blocks)
//!   and 24, 39 (Radau5's dense Newton matrices below its sparse switch): the dense LU, the
//!   shifted LU, nalgebra's, faer's;
//! * `lu_chain`: general with a chain's pattern, n = 24, 40, 120, 480: the sparse LU
//!   (refactorised with its kept pivots), the shifted dense LU, faer's sparse LU (analysis
//!   once, numeric factor with pivoting per iteration).
//!
//! Matrices are fixed pseudo-random ones, diagonally dominant (LU) or B Bᵀ (SPD). faer runs
//! single-threaded (`Par::Seq`): with its default parallelism it was 2–3× slower on 2 cores.
//!
//! Run: `cargo bench --bench linalg`.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::linalg::solvers::{Llt, PartialPivLu, Solve};
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Mat, Par, Side};
use linkdyn::linalg::{
    DenseCholesky, DenseLu, Factorisation, ShiftedLu, SkylineCholesky, SparseLu,
};
use std::hint::black_box;
use std::time::Duration;

/// Knuth's MMIX linear congruential generator: the same matrices on every run.
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
    fn below(&mut self, n: usize) -> usize {
        ((self.next() * n as f64) as usize).min(n - 1)
    }
}

/// B with a chain's coupling (row k: columns k − 2 … k), rows and columns scrambled.
fn chain_factor(n: usize, rng: &mut Lcg) -> Vec<f64> {
    let mut label: Vec<usize> = (0..n).collect();
    for k in (1..n).rev() {
        label.swap(k, rng.below(k + 1));
    }
    let mut b = vec![0.0; n * n];
    for k in 0..n {
        for j in k.saturating_sub(2)..=k {
            b[label[k] * n + label[j]] = if j == k {
                rng.range(1.0, 2.0)
            } else {
                rng.range(-1.0, 1.0)
            };
        }
    }
    b
}

/// B Bᵀ over the non-zeros of B's rows.
fn spd(n: usize, rng: &mut Lcg) -> Vec<f64> {
    let b = chain_factor(n, rng);
    let rows: Vec<Vec<(usize, f64)>> = (0..n)
        .map(|i| {
            (0..n)
                .filter(|&k| b[i * n + k] != 0.0)
                .map(|k| (k, b[i * n + k]))
                .collect()
        })
        .collect();
    let mut a = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            a[i * n + j] = rows[i].iter().map(|&(k, v)| v * b[j * n + k]).sum::<f64>();
        }
    }
    a
}

/// Random values over the pattern of B + Bᵀ (a chain's), or dense, with a dominant diagonal.
fn general(n: usize, dense: bool, rng: &mut Lcg) -> Vec<f64> {
    let b = chain_factor(n, rng);
    let mut a = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            if dense || b[i * n + j] != 0.0 || b[j * n + i] != 0.0 {
                a[i * n + j] = rng.range(-1.0, 1.0);
            }
        }
        a[i * n + i] = rng.range(4.0, 6.0) + if dense { n as f64 } else { 0.0 };
    }
    a
}

fn rhs(n: usize) -> Vec<f64> {
    (0..n).map(|i| 1.0 + (i % 7) as f64).collect()
}

/// Factor + solve through the common interface.
fn ours(kernel: &mut dyn Factorisation, a: &[f64], b: &[f64], x: &mut [f64]) {
    x.copy_from_slice(b);
    if kernel.factor(black_box(a)).is_ok() {
        kernel.solve(x);
    }
    black_box(&x);
}

fn faer_dense(a: &[f64], n: usize) -> Mat<f64> {
    Mat::from_fn(n, n, |i, j| a[i * n + j])
}

fn triplets(a: &[f64], n: usize) -> Vec<Triplet<usize, usize, f64>> {
    let mut t = Vec::new();
    for i in 0..n {
        for j in 0..n {
            if i == j || a[i * n + j] != 0.0 {
                t.push(Triplet::new(i, j, a[i * n + j]));
            }
        }
    }
    t
}

fn spd_small(c: &mut Criterion) {
    let mut group = c.benchmark_group("spd_small");
    let mut rng = Lcg(7);
    for n in [7, 16] {
        let a = spd(n, &mut rng);
        let b = rhs(n);
        let mut x = vec![0.0; n];
        let mut kernel = DenseCholesky::new(n);
        group.bench_with_input(BenchmarkId::new("linkdyn_cholesky", n), &n, |bench, _| {
            bench.iter(|| ours(&mut kernel, &a, &b, &mut x))
        });
        let na = nalgebra::DMatrix::from_row_slice(n, n, &a);
        let nb = nalgebra::DVector::from_column_slice(&b);
        group.bench_with_input(BenchmarkId::new("nalgebra_cholesky", n), &n, |bench, _| {
            bench.iter(|| black_box(na.clone().cholesky().map(|l| l.solve(&nb))))
        });
        let fa = faer_dense(&a, n);
        let fb = Mat::from_fn(n, 1, |i, _| b[i]);
        group.bench_with_input(BenchmarkId::new("faer_llt", n), &n, |bench, _| {
            bench.iter(|| black_box(Llt::new(fa.as_ref(), Side::Lower).map(|l| l.solve(&fb))))
        });
    }
    group.finish();
}

fn spd_chain(c: &mut Criterion) {
    let mut group = c.benchmark_group("spd_chain");
    group.measurement_time(Duration::from_secs(2));
    let mut rng = Lcg(11);
    for n in [62, 242, 1202] {
        let a = spd(n, &mut rng);
        let b = rhs(n);
        let mut x = vec![0.0; n];
        let mut kernel = SkylineCholesky::for_pattern_of(&a, n);
        group.bench_with_input(BenchmarkId::new("linkdyn_skyline", n), &n, |bench, _| {
            bench.iter(|| ours(&mut kernel, &a, &b, &mut x))
        });
        // faer's sparse Cholesky of the lower triangle: AMD and the symbolic analysis once.
        let lower: Vec<_> = triplets(&a, n)
            .into_iter()
            .filter(|t| t.row >= t.col)
            .collect();
        let Ok(sparse) = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &lower) else {
            panic!("triplets")
        };
        let Ok(symbolic) = factorize_symbolic_cholesky(
            sparse.symbolic(),
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        ) else {
            panic!("faer symbolic Cholesky")
        };
        let mut l_values = vec![0.0; symbolic.len_val()];
        let mut buffer = MemBuffer::new(
            symbolic
                .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
                .or(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq)),
        );
        group.bench_with_input(BenchmarkId::new("faer_sparse_llt", n), &n, |bench, _| {
            bench.iter(|| {
                let stack = MemStack::new(&mut buffer);
                if let Ok(llt) = symbolic.factorize_numeric_llt::<f64>(
                    &mut l_values,
                    sparse.as_ref(),
                    Side::Lower,
                    LltRegularization::default(),
                    Par::Seq,
                    stack,
                    Default::default(),
                ) {
                    let mut rhs = Mat::from_fn(n, 1, |i, _| b[i]);
                    let stack = MemStack::new(&mut buffer);
                    llt.solve_in_place_with_conj(Conj::No, rhs.as_mut(), Par::Seq, stack);
                    black_box(rhs);
                }
            })
        });
        if n <= 242 {
            let fa = faer_dense(&a, n);
            let fb = Mat::from_fn(n, 1, |i, _| b[i]);
            group.bench_with_input(BenchmarkId::new("faer_dense_llt", n), &n, |bench, _| {
                bench.iter(|| black_box(Llt::new(fa.as_ref(), Side::Lower).map(|l| l.solve(&fb))))
            });
        }
    }
    group.finish();
}

fn lu_small(c: &mut Criterion) {
    let mut group = c.benchmark_group("lu_small");
    let mut rng = Lcg(13);
    for n in [3, 6, 10, 24, 39] {
        let a = general(n, true, &mut rng);
        let b = rhs(n);
        let mut x = vec![0.0; n];
        let mut dense = DenseLu::new(n);
        group.bench_with_input(BenchmarkId::new("linkdyn_dense_lu", n), &n, |bench, _| {
            bench.iter(|| ours(&mut dense, &a, &b, &mut x))
        });
        let mut shifted = ShiftedLu::for_pattern_of(&a, n);
        group.bench_with_input(BenchmarkId::new("linkdyn_shifted_lu", n), &n, |bench, _| {
            bench.iter(|| ours(&mut shifted, &a, &b, &mut x))
        });
        let na = nalgebra::DMatrix::from_row_slice(n, n, &a);
        let nb = nalgebra::DVector::from_column_slice(&b);
        group.bench_with_input(BenchmarkId::new("nalgebra_lu", n), &n, |bench, _| {
            bench.iter(|| black_box(na.clone().lu().solve(&nb)))
        });
        let fa = faer_dense(&a, n);
        let fb = Mat::from_fn(n, 1, |i, _| b[i]);
        group.bench_with_input(BenchmarkId::new("faer_lu", n), &n, |bench, _| {
            bench.iter(|| black_box(PartialPivLu::new(fa.as_ref()).solve(&fb)))
        });
    }
    group.finish();
}

fn lu_chain(c: &mut Criterion) {
    let mut group = c.benchmark_group("lu_chain");
    group.measurement_time(Duration::from_secs(2));
    let mut rng = Lcg(17);
    for n in [24, 40, 120, 480] {
        let a = general(n, false, &mut rng);
        let b = rhs(n);
        let mut x = vec![0.0; n];
        let Some(mut sparse) = SparseLu::for_pattern_of(&a, n) else {
            panic!("faer could not analyse the pattern")
        };
        group.bench_with_input(BenchmarkId::new("linkdyn_sparse_lu", n), &n, |bench, _| {
            bench.iter(|| ours(&mut sparse, &a, &b, &mut x))
        });
        if n <= 120 {
            let mut shifted = ShiftedLu::for_pattern_of(&a, n);
            group.bench_with_input(BenchmarkId::new("linkdyn_shifted_lu", n), &n, |bench, _| {
                bench.iter(|| ours(&mut shifted, &a, &b, &mut x))
            });
        }
        // faer's sparse LU: COLAMD and the symbolic analysis once, each numeric factorisation
        // with partial pivoting (what the kept pivots save).
        let Ok(matrix) = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &triplets(&a, n))
        else {
            panic!("triplets")
        };
        let Ok(symbolic) = SymbolicLu::try_new(matrix.symbolic()) else {
            panic!("faer symbolic LU")
        };
        let fb = Mat::from_fn(n, 1, |i, _| b[i]);
        group.bench_with_input(BenchmarkId::new("faer_sparse_lu", n), &n, |bench, _| {
            bench.iter(|| {
                let lu = Lu::try_new_with_symbolic(symbolic.clone(), matrix.as_ref());
                black_box(lu.map(|lu| lu.solve(&fb)))
            })
        });
    }
    group.finish();
}

fn single_threaded_faer(c: &mut Criterion) {
    faer::set_global_parallelism(Par::Seq);
    let _ = c;
}

criterion_group!(
    benches,
    single_threaded_faer,
    spd_small,
    spd_chain,
    lu_small,
    lu_chain
);
criterion_main!(benches);
