//! The dependent block Φ_qD (m × m: active constraint rows × dependent coordinates) of one
//! partition and its LU factors, dense or sparse behind one interface.
//!
//! Every evaluation of the generalised formulation factors Φ_qD at least once (Newton's last
//! iterate, then the velocity solve and the f + 1 solves for B and c reuse the factors). The
//! dense LU ([`crate::linalg::dense_lu`]) costs m³/3 flops; the sparse one ([`super::sparse_lu`]) costs what its
//! factors cost, linear in the number of bodies for a linkage, after a symbolic analysis (the
//! pattern and its fill-reducing ordering) made once per partition. [`BlockSolver::Auto`] takes
//! the sparse LU from [`SPARSE_FROM`] dependent coordinates on.
//!
//! The pattern comes from the constraint rows: each row touches at most two bodies, and within a
//! body only the components [`ConstraintSet::structural_components`] allows (a revolute joint's x
//! row never depends on y). The same list of entries fills the dense matrix, so both solvers see
//! the same numbers.

use super::sparse_lu::SparseLu;
use crate::linalg::dense_lu;
use crate::mechanics::constraints::{ConstraintRow, ConstraintSet};

/// Which LU factors the dependent block Φ_qD (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BlockSolver {
    /// Dense below [`SPARSE_FROM`] dependent coordinates, sparse from there on (the default).
    #[default]
    Auto,
    /// Always the dense LU with partial pivoting.
    Dense,
    /// Always the sparse LU (faer, simplicial, COLAMD ordering).
    Sparse,
}

/// Number of dependent coordinates m from which [`BlockSolver::Auto`] takes the sparse LU.
///
/// Measured (2026-11-27, release build, on the 2-core development machine while other builds
/// ran on it: load average 4–5) as the cost of one right-hand side of the generalised
/// formulation on the N-loop chain `models/nfourbar_chain.toml` (m = 6N + 2 dependent
/// coordinates, one degree of freedom), from a warm start 1 ms ahead along the motion (one
/// Newton iteration, as at a stage), best of five batches:
///
/// | N loops | m    | dense (µs) | sparse (µs) |
/// |---------|------|------------|-------------|
/// | 1       | 8    | 1.3        | 1.7         |
/// | 2       | 14   | 3.0        | 3.3         |
/// | 3       | 20   | 4.9        | 4.7         |
/// | 4       | 26   | 7.4        | 5.6         |
/// | 10      | 62   | 34         | 12          |
/// | 40      | 242  | 480        | 48          |
/// | 80      | 482  | 1 940      | 105         |
/// | 200     | 1202 | —          | 260         |
///
/// The dense LU wins while m is small (no pattern to follow, no permutations: small linkages
/// such as the four-bar, m = 8 as in the first row), the two tie at m = 20, and from there on
/// the dense m³/3 overtakes the sparse LU, whose cost stays linear in m.
pub const SPARSE_FROM: usize = 20;

/// One structural entry of Φ_qD.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Entry {
    /// Dependent column (first, so that sorting gives column-major order).
    column: usize,
    /// Position of the row among the active rows.
    row: usize,
    /// Index of the row in the constraint evaluation.
    source: usize,
    /// Component (0 = x, 1 = y, 2 = φ) of the column's body.
    component: usize,
    /// Whether side a and side b of the row touch the column's body (both when a row joins
    /// a body to itself).
    sides: [bool; 2],
}

impl Entry {
    /// ∂Φ_row/∂q_column at the evaluation `rows`.
    #[inline]
    fn value(&self, rows: &[ConstraintRow]) -> f64 {
        let r = &rows[self.source];
        let mut v = 0.0;
        if self.sides[0] {
            v += r.jac_a[self.component];
        }
        if self.sides[1] {
            v += r.jac_b[self.component];
        }
        v
    }
}

#[derive(Debug, Clone)]
enum Factors {
    /// Row-major m × m, then its LU in place.
    Dense { a: Vec<f64>, piv: Vec<usize> },
    /// Boxed: the sparse factors carry faer's structures (~370 bytes) beside two vectors.
    Sparse(Box<SparseLu>),
}

/// Φ_qD of one partition and its factors (see the module documentation).
#[derive(Debug, Clone)]
pub struct DependentBlock {
    m: usize,
    solver: BlockSolver,
    /// Dependent coordinate of each column, for the partition the entries were built for;
    /// `None` before the first partition.
    partition: Option<Vec<usize>>,
    entries: Vec<Entry>,
    factors: Factors,
}

impl DependentBlock {
    /// A block of m rows and columns, factored as `solver` says.
    pub fn new(m: usize, solver: BlockSolver) -> Self {
        DependentBlock {
            m,
            solver,
            partition: None,
            entries: Vec::new(),
            factors: Factors::Dense {
                a: Vec::new(),
                piv: Vec::new(),
            },
        }
    }

    /// Whether the current partition's block is factored by the sparse LU.
    pub fn is_sparse(&self) -> bool {
        matches!(self.factors, Factors::Sparse(_))
    }

    /// Makes this the block of the partition whose dependent coordinates are `dep` (column
    /// j ↔ coordinate `dep[j]`; `col_of` is the inverse, `usize::MAX` for independent ones):
    /// nothing to do if the partition is the one already built, else the entries and (sparse)
    /// the symbolic analysis are made anew. `rows` is any evaluation of the constraint rows
    /// (only the bodies each row touches are read, which do not change).
    pub fn set_partition(
        &mut self,
        dep: &[usize],
        col_of: &[usize],
        rows: &[ConstraintRow],
        active: &[usize],
        constraints: &ConstraintSet,
    ) {
        if self.partition.as_deref() == Some(dep) {
            return;
        }
        let m = self.m;
        self.entries.clear();
        for (i, &k) in active.iter().enumerate() {
            let row = &rows[k];
            let mask = constraints.structural_components(k);
            for (side, body) in [row.body_a, row.body_b].into_iter().enumerate() {
                let Some(b) = body else { continue };
                for (component, &touches) in mask.iter().enumerate() {
                    let column = col_of.get(3 * b + component).copied().unwrap_or(usize::MAX);
                    if !touches || column == usize::MAX {
                        continue;
                    }
                    let mut sides = [false; 2];
                    sides[side] = true;
                    self.entries.push(Entry {
                        column,
                        row: i,
                        source: k,
                        component,
                        sides,
                    });
                }
            }
        }
        self.entries.sort_unstable();
        // A row that joins a body to itself gives the same (column, row) twice: merge them.
        self.entries.dedup_by(|later, kept| {
            let same = (later.column, later.row) == (kept.column, kept.row);
            if same {
                kept.sides[0] |= later.sides[0];
                kept.sides[1] |= later.sides[1];
            }
            same
        });
        let sparse = match self.solver {
            BlockSolver::Dense => false,
            BlockSolver::Sparse => true,
            BlockSolver::Auto => m >= SPARSE_FROM,
        };
        self.factors = sparse.then(|| self.analyse()).flatten().map_or_else(
            || Factors::Dense {
                a: vec![0.0; m * m],
                piv: vec![0; m],
            },
            |lu| Factors::Sparse(Box::new(lu)),
        );
        self.partition = Some(dep.to_vec());
    }

    /// The sparse symbolic analysis of the entries; `None` (use the dense LU) if faer cannot
    /// allocate its workspace.
    fn analyse(&self) -> Option<SparseLu> {
        let m = self.m;
        let mut col_ptr = vec![0; m + 1];
        for e in &self.entries {
            col_ptr[e.column + 1] += 1;
        }
        for j in 0..m {
            col_ptr[j + 1] += col_ptr[j];
        }
        let row_idx = self.entries.iter().map(|e| e.row).collect();
        SparseLu::analyse(m, col_ptr, row_idx).ok()
    }

    /// Fills Φ_qD from the evaluation `rows` and factors it. Fails with the position (among the
    /// active rows) of a row whose pivot vanished: the block is singular to working precision.
    pub fn factor(&mut self, rows: &[ConstraintRow]) -> Result<(), usize> {
        let m = self.m;
        match &mut self.factors {
            Factors::Dense { a, piv } => {
                a.fill(0.0);
                for e in &self.entries {
                    a[e.row * m + e.column] = e.value(rows);
                }
                dense_lu::factor(a, m, piv)
            }
            Factors::Sparse(lu) => {
                for (v, e) in lu.values_mut().iter_mut().zip(&self.entries) {
                    *v = e.value(rows);
                }
                lu.factor()
            }
        }
    }

    /// Solves Φ_qD x = b in place with the factors of the last successful [`Self::factor`].
    pub fn solve(&mut self, b: &mut [f64]) {
        self.solve_columns(b, 1);
    }

    /// Solves Φ_qD X = B in place for `ncols` right-hand sides stored column after column in `b`.
    pub fn solve_columns(&mut self, b: &mut [f64], ncols: usize) {
        let m = self.m;
        match &mut self.factors {
            Factors::Dense { a, piv } => {
                for column in b.chunks_mut(m.max(1)).take(ncols) {
                    dense_lu::solve(a, m, piv, column);
                }
            }
            Factors::Sparse(lu) => lu.solve_columns(b, ncols),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::load_str;

    /// A four-bar: 3 bodies, 9 coordinates, 8 rows (4 pins), one degree of freedom.
    const FOURBAR: &str = r#"
[model]
name = "fourbar"
[ground]
points = { O2 = [0.0, 0.0], O4 = [1.0, 0.0] }
[[bodies]]
name = "crank"
mass = 1.0
inertia = 0.1
points = { O = [-0.15, 0.0], A = [0.15, 0.0] }
initial = { x = 0.1061, y = 0.1061, phi = 0.7854 }
[[bodies]]
name = "coupler"
mass = 1.0
inertia = 0.1
points = { A = [-0.5, 0.0], B = [0.5, 0.0] }
initial = { x = 0.7, y = 0.4, phi = -0.1 }
[[bodies]]
name = "rocker"
mass = 1.0
inertia = 0.1
points = { B = [-0.4, 0.0], O = [0.4, 0.0] }
initial = { x = 1.1, y = 0.3, phi = 1.5 }
[[joints]]
name = "O2"
type = "revolute"
body_a = "ground"
point_a = "O2"
body_b = "crank"
point_b = "O"
[[joints]]
name = "A"
type = "revolute"
body_a = "crank"
point_a = "A"
body_b = "coupler"
point_b = "A"
[[joints]]
name = "B"
type = "revolute"
body_a = "coupler"
point_a = "B"
body_b = "rocker"
point_b = "B"
[[joints]]
name = "O4"
type = "revolute"
body_a = "rocker"
point_a = "O"
body_b = "ground"
point_b = "O4"
"#;

    /// Dense and sparse factors of the same block solve the same system to round-off, and the
    /// dense matrix built from the entries is Φ_q's dependent columns.
    #[test]
    fn dense_and_sparse_blocks_agree() {
        let model = load_str(FOURBAR, "fourbar.toml", &[]).unwrap_or_else(|e| panic!("{e}"));
        let set = ConstraintSet::from_model(&model, false);
        let q: Vec<f64> = model
            .bodies
            .iter()
            .flat_map(|b| [b.initial.x, b.initial.y, b.initial.phi])
            .collect();
        let sc: Vec<(f64, f64)> = (0..3).map(|i| q[3 * i + 2].sin_cos()).collect();
        let mut eval = crate::mechanics::constraints::ConstraintEval::with_rows(set.n_rows());
        set.evaluate_into(0.0, &q, &[0.0; 9], &sc, &mut eval);
        let active: Vec<usize> = (0..8).collect();
        // Crank angle independent.
        let dep = [0, 1, 3, 4, 5, 6, 7, 8];
        let mut col_of = vec![usize::MAX; 9];
        for (j, &c) in dep.iter().enumerate() {
            col_of[c] = j;
        }
        let mut x = Vec::new();
        for solver in [BlockSolver::Dense, BlockSolver::Sparse] {
            let mut block = DependentBlock::new(8, solver);
            block.set_partition(&dep, &col_of, &eval.rows, &active, &set);
            assert_eq!(block.is_sparse(), solver == BlockSolver::Sparse);
            assert_eq!(block.factor(&eval.rows), Ok(()), "{solver:?}");
            // Right-hand sides: the dependent columns' own entries of Φ_q times a known x.
            let x_true: Vec<f64> = (0..16).map(|k| (k as f64 * 0.37).sin()).collect();
            let mut b = vec![0.0; 16];
            for col in 0..2 {
                for (i, row) in eval.rows.iter().enumerate() {
                    for (body, jac) in [(row.body_a, row.jac_a), (row.body_b, row.jac_b)] {
                        let Some(bd) = body else { continue };
                        for c in 0..3 {
                            let j = col_of[3 * bd + c];
                            if j != usize::MAX {
                                b[8 * col + i] += jac[c] * x_true[8 * col + j];
                            }
                        }
                    }
                }
            }
            block.solve_columns(&mut b, 2);
            for (k, (got, want)) in b.iter().zip(&x_true).enumerate() {
                // Condition number of a four-bar block away from singular positions: ~10².
                assert!(
                    (got - want).abs() < 1e-12,
                    "{solver:?} x[{k}] = {got} vs {want}"
                );
            }
            x.push(b);
        }
        for (d, s) in x[0].iter().zip(&x[1]) {
            assert!((d - s).abs() < 1e-13, "dense {d} vs sparse {s}");
        }
    }
}
