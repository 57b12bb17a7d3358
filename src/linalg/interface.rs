//! [`Factorisation`]: the one interface of the kernels, and an adapter per kernel that keeps
//! the kernel's own storage (row-major dense matrices in, the kernel's layout inside).
//!
//! The formulations and integrators call the kernels' functions on their own buffers; these
//! adapters are what the conformance tests (`linalg/conformance.rs`) and the benchmark against
//! faer and nalgebra (`benches/linalg.rs`) hold every kernel to, through the same calls.

use super::shifted_lu::{Partition, RealLu};
use super::skyline::{self, Envelope};
use super::sparse_lu::{SparseLuAnalysis, SparseLuFactors};
use super::sparse_refactor::PivotCheck;
use super::{cholesky, dense_lu};
use faer::dyn_stack::{MemBuffer, MemStack};

/// A matrix singular to working precision: the pivot of this column (for a Cholesky, this row)
/// failed, in the kernel's elimination order mapped back to the caller's numbering where the
/// kernel renumbers (the skyline), in the kernel's own where it pivots (the LUs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Singular {
    /// Column (row) of the failed pivot.
    pub column: usize,
}

/// A square linear system A x = b, factored once and solved in place as often as needed.
pub trait Factorisation {
    /// The dimension n.
    fn dim(&self) -> usize;

    /// Factors the n × n matrix `a` (row-major). A kernel built for a sparsity pattern reads
    /// only the entries of that pattern; a Cholesky reads only the lower triangle.
    ///
    /// Errors: [`Singular`], the first pivot that is not usable: for the Choleskys one not
    /// positive relative to its diagonal entry (1e-13), for the dense LU one below 1e-14 of
    /// the largest entry, for the shifted and the sparse LU one exactly zero; NaN for all.
    fn factor(&mut self, a: &[f64]) -> Result<(), Singular>;

    /// Solves A x = b in place (`b` becomes x) with the last successful [`Self::factor`].
    fn solve(&mut self, b: &mut [f64]);
}

/// Dense Cholesky of a small SPD matrix ([`cholesky`]).
#[derive(Debug, Clone)]
pub struct DenseCholesky {
    n: usize,
    l: Vec<f64>,
}

impl DenseCholesky {
    /// Buffers for n × n matrices.
    pub fn new(n: usize) -> Self {
        DenseCholesky {
            n,
            l: vec![0.0; n * n],
        }
    }
}

impl Factorisation for DenseCholesky {
    fn dim(&self) -> usize {
        self.n
    }
    fn factor(&mut self, a: &[f64]) -> Result<(), Singular> {
        self.l.copy_from_slice(&a[..self.n * self.n]);
        cholesky::factor(&mut self.l, self.n).map_err(|column| Singular { column })
    }
    fn solve(&mut self, b: &mut [f64]) {
        cholesky::solve(&self.l, self.n, b);
    }
}

/// Envelope Cholesky of a sparse SPD matrix after reverse Cuthill–McKee ([`skyline`]).
#[derive(Debug, Clone)]
pub struct SkylineCholesky {
    envelope: Envelope,
    /// For each stored entry, its index in the row-major matrix.
    source: Vec<usize>,
    values: Vec<f64>,
    x: Vec<f64>,
}

impl SkylineCholesky {
    /// For the symmetric pattern of the non-zeros of `a` (n × n, row-major; either triangle).
    pub fn for_pattern_of(a: &[f64], n: usize) -> Self {
        let mut adjacency = vec![Vec::new(); n];
        for (i, neighbours) in adjacency.iter_mut().enumerate() {
            for j in 0..n {
                if i != j && (a[i * n + j] != 0.0 || a[j * n + i] != 0.0) {
                    neighbours.push(j);
                }
            }
        }
        let envelope = Envelope::new(&adjacency);
        let mut source = vec![0; envelope.len()];
        for p in 0..n {
            for c in envelope.first[p]..=p {
                let (row, col) = (envelope.perm[p], envelope.perm[c]);
                // The lower triangle in the caller's numbering.
                source[envelope.start[p] + c - envelope.first[p]] = row.max(col) * n + row.min(col);
            }
        }
        SkylineCholesky {
            values: vec![0.0; envelope.len()],
            x: vec![0.0; n],
            envelope,
            source,
        }
    }

    /// Entries stored for the factor (the envelope).
    pub fn stored_entries(&self) -> usize {
        self.values.len()
    }
}

impl Factorisation for SkylineCholesky {
    fn dim(&self) -> usize {
        self.x.len()
    }
    fn factor(&mut self, a: &[f64]) -> Result<(), Singular> {
        for (v, &k) in self.values.iter_mut().zip(&self.source) {
            *v = a[k];
        }
        let e = &self.envelope;
        skyline::factor(&e.first, &e.start, &mut self.values)
            .map_err(|p| Singular { column: e.perm[p] })
    }
    fn solve(&mut self, b: &mut [f64]) {
        let e = &self.envelope;
        for (x, &k) in self.x.iter_mut().zip(&e.perm) {
            *x = b[k];
        }
        skyline::solve(&e.first, &e.start, &self.values, &mut self.x);
        for (x, &k) in self.x.iter().zip(&e.perm) {
            b[k] = *x;
        }
    }
}

/// Dense LU with partial pivoting of a small square matrix ([`dense_lu`]).
#[derive(Debug, Clone)]
pub struct DenseLu {
    n: usize,
    lu: Vec<f64>,
    piv: Vec<usize>,
}

impl DenseLu {
    /// Buffers for n × n matrices.
    pub fn new(n: usize) -> Self {
        DenseLu {
            n,
            lu: vec![0.0; n * n],
            piv: vec![0; n],
        }
    }
}

impl Factorisation for DenseLu {
    fn dim(&self) -> usize {
        self.n
    }
    fn factor(&mut self, a: &[f64]) -> Result<(), Singular> {
        self.lu.copy_from_slice(&a[..self.n * self.n]);
        dense_lu::factor(&mut self.lu, self.n, &mut self.piv).map_err(|column| Singular { column })
    }
    fn solve(&mut self, b: &mut [f64]) {
        dense_lu::solve(&self.lu, self.n, &self.piv, b);
    }
}

/// Radau5's dense LU of s·I − J (`linalg::shifted_lu`), here with s = 0 and J = −A, its
/// decoupled components found once from the pattern it is built for (as Radau5 finds them once
/// per Jacobian, for every factorisation with it).
#[derive(Debug, Clone)]
pub struct ShiftedLu {
    lu: RealLu,
    part: Partition,
    negated: Vec<f64>,
}

impl ShiftedLu {
    /// For the pattern of the non-zeros of `a` (n × n, row-major). The matrices factored
    /// later must keep zero where it is zero off the diagonal: a component decoupled in the
    /// pattern is solved by a division, whatever its row or column then holds.
    pub fn for_pattern_of(a: &[f64], n: usize) -> Self {
        let negated: Vec<f64> = a[..n * n].iter().map(|v| -v).collect();
        let mut part = Partition::new(n);
        part.update(&negated);
        ShiftedLu {
            lu: RealLu::new(n),
            part,
            negated,
        }
    }
}

impl Factorisation for ShiftedLu {
    fn dim(&self) -> usize {
        self.part.dim()
    }
    fn factor(&mut self, a: &[f64]) -> Result<(), Singular> {
        for (m, v) in self.negated.iter_mut().zip(a) {
            *m = -v;
        }
        self.lu.factor(0.0, &self.negated, &self.part)
    }
    fn solve(&mut self, b: &mut [f64]) {
        self.lu.solve(b);
    }
}

/// Sparse LU over a pattern analysed once, refactorised with its kept pivots while they pass
/// UMFPACK's threshold 0.1 (`linalg::sparse_lu`), as Radau5 and IDA use it.
pub struct SparseLu {
    analysis: SparseLuAnalysis,
    factors: SparseLuFactors<f64>,
    scratch: MemBuffer,
    /// For each stored entry (compressed columns), its index in the row-major matrix.
    source: Vec<usize>,
}

impl SparseLu {
    /// For the pattern of the non-zeros of `a` (n × n, row-major) and its diagonal. `None`
    /// where faer cannot analyse it.
    pub fn for_pattern_of(a: &[f64], n: usize) -> Option<Self> {
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        let mut source = Vec::new();
        for j in 0..n {
            for i in 0..n {
                if i == j || a[i * n + j] != 0.0 {
                    row_idx.push(i);
                    source.push(i * n + j);
                }
            }
            col_ptr.push(row_idx.len());
        }
        let analysis = SparseLuAnalysis::new(n, col_ptr, row_idx)?;
        let factors = SparseLuFactors::new(&analysis, PivotCheck(0.1));
        let scratch = MemBuffer::new(analysis.scratch::<f64>());
        Some(SparseLu {
            analysis,
            factors,
            scratch,
            source,
        })
    }

    /// Non-zeros of the pattern.
    pub fn nnz(&self) -> usize {
        self.source.len()
    }
}

impl std::fmt::Debug for SparseLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseLu")
            .field("dim", &self.analysis.dim())
            .field("nnz", &self.source.len())
            .finish_non_exhaustive()
    }
}

impl Factorisation for SparseLu {
    fn dim(&self) -> usize {
        self.analysis.dim()
    }
    fn factor(&mut self, a: &[f64]) -> Result<(), Singular> {
        for (v, &k) in self.factors.values_mut().iter_mut().zip(&self.source) {
            *v = a[k];
        }
        let stack = MemStack::new(&mut self.scratch);
        self.factors
            .factor(&self.analysis, stack)
            .map_err(|e| Singular { column: e.column })
    }
    fn solve(&mut self, b: &mut [f64]) {
        self.factors.solve(&self.analysis, b);
    }
}
