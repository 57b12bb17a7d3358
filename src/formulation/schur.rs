//! The Schur complement S = Φ_q M⁻¹ Φ_qᵀ of a set of constraint rows: formed over its
//! structural non-zeros, factored by Cholesky, solved in place, without allocating.
//!
//! Row k of Φ_q has two 3-blocks, one per body it touches, so S_ij ≠ 0 only where rows i and j
//! share a body. Which bodies a row touches does not change with q, so the sparsity of S (the
//! pairs of blocks that meet, and where each lands in the factor) is worked out once, at
//! [`Schur::new`]; every evaluation then only sums the 3-vector products
//! S_ij = Σ (M⁻¹ Φ_q,i)ᵀ Φ_q,j over those pairs, factors and solves.
//!
//! Two storages (see [`SchurSolver`]), each factored by a kernel of [`crate::linalg`]:
//!
//! * **dense**: the m × m lower triangle in row order and the hand-written Cholesky of
//!   [`crate::linalg::cholesky`]: as fast for the few rows of one or two loops, cubic beyond;
//! * **skyline**: the rows renumbered once by reverse Cuthill–McKee so that the non-zeros
//!   gather near the diagonal, and the envelope Cholesky of [`crate::linalg::skyline`]: linear
//!   in m for a chain of loops.
//!
//! A pivot that is not positive (relative 1e-13 of its diagonal, as in
//! [`crate::linalg::cholesky`]) reports its row, in the caller's numbering: the row that is, to
//! working precision, a combination of the rows eliminated before it (in row order for the
//! dense storage, in the reverse Cuthill–McKee order for the skyline).

use crate::linalg::cholesky;
use crate::linalg::regularised::{regularised, shift_of};
use crate::linalg::skyline;
use crate::mechanics::constraints::{ConstraintRow, pairs_on_common_bodies};

/// Number of rows up to which [`SchurSolver::Auto`] takes the dense Cholesky. Measured on chains
/// of parallel four-bars ("Hundreds of bodies" in `docs/measurements.md`), form + factor +
/// solve: 0.5–0.8 µs dense against 0.4–0.6 µs skyline at m = 8, 1.0–1.2 against 0.9 µs at
/// m = 14, 2.0 against 1.3 µs at m = 20, 6 against 2.4 µs at m = 32. Up to 16 rows (every
/// single- and double-loop model shipped) the two are within a fraction of a microsecond, and
/// the dense path keeps those models' arithmetic exactly as it was; above, the skyline.
pub const DENSE_MAX_ROWS: usize = 16;

/// Which storage and factorisation of S to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
pub enum SchurSolver {
    /// Dense up to [`DENSE_MAX_ROWS`] rows, skyline above (the default).
    #[default]
    Auto,
    /// Dense Cholesky in row order: cubic in the number of rows.
    Dense,
    /// Skyline Cholesky after a reverse Cuthill–McKee renumbering computed once.
    Skyline,
}

/// One pair of row blocks that act on the same body: S_ij gets their weighted product. Blocks
/// are numbered 2k + side (side 0 = body a, 1 = body b of row k, caller's numbering), their
/// index into [`Schur::weighted`] and the copied Jacobian blocks flattened: three small
/// integers keep the list, walked at every evaluation, compact.
#[derive(Debug, Clone, Copy)]
struct Coupling {
    /// Block of row i whose weighted values enter.
    block_i: u32,
    /// Block of row j whose plain values enter.
    block_j: u32,
    /// Where S_ij lands in the storage (lower triangle).
    pos: u32,
}

/// How S is stored and factored.
#[derive(Debug, Clone)]
enum Storage {
    /// Row-major m × m, lower triangle used.
    Dense { a: Vec<f64> },
    /// Envelope storage in the renumbered order: row p holds columns `first[p]..=p` at
    /// `values[start[p]..start[p + 1]]`.
    Skyline {
        /// `perm[p]` = caller's row at position p.
        perm: Vec<usize>,
        first: Vec<usize>,
        start: Vec<usize>,
        values: Vec<f64>,
        /// The right-hand side in the renumbered order.
        x: Vec<f64>,
    },
}

/// The Schur complement of a fixed set of constraint rows, ready to be formed and factored at
/// any q.
#[derive(Debug, Clone)]
pub struct Schur {
    m: usize,
    storage: Storage,
    couplings: Vec<Coupling>,
    /// M⁻¹ times each row's two Jacobian blocks, from the last [`Schur::factor`].
    weighted: Vec<[[f64; 3]; 2]>,
    /// Each row's two Jacobian blocks as of the last [`Schur::factor`], copied beside
    /// `weighted` so that the couplings read both from two short arrays.
    blocks: Vec<[[f64; 3]; 2]>,
    /// Diagonal position of each row (caller's numbering), for the shift of [`Schur::factor`].
    diagonal: Vec<usize>,
    /// Smallest raw pivot of the last [`Schur::factor_regularised`] over its row's diagonal
    /// entry (1 for a row independent of the earlier ones, → 0 as it becomes dependent).
    min_pivot_ratio: f64,
    /// Δ_k of the last [`Schur::factor_regularised`] per row (caller's numbering): the factor
    /// is that of S + diag(Δ).
    added: Vec<f64>,
}

/// An orientation-free scale of S's diagonal for the rows `rows[active[k]]`: the part of
/// S_kk = Φ_q,k M⁻¹ Φ_q,kᵀ from the translations, Σ_bodies (∂Φ_k/∂x² + ∂Φ_k/∂y²)/m, which for
/// a joint row (unit directions) does not change as the bodies turn, where the rotational part
/// (∂Φ_k/∂φ)²/I does, by the ratio of m·arm² to I; for a row with no translational part (an
/// angle row: a driver) its rotational part, constant too.
pub fn translational_diagonal(
    rows: &[ConstraintRow],
    active: &[usize],
    inv_mass: &[f64],
) -> Vec<f64> {
    active
        .iter()
        .map(|&r| {
            let part = |cs: &[usize]| -> f64 {
                rows[r]
                    .blocks()
                    .into_iter()
                    .filter_map(|(body, jac)| body.map(|b| (b, jac)))
                    .map(|(b, jac)| {
                        cs.iter()
                            .map(|&c| jac[c] * jac[c] * inv_mass[3 * b + c])
                            .sum::<f64>()
                    })
                    .sum()
            };
            let translational = part(&[0, 1]);
            if translational > 0.0 {
                translational
            } else {
                part(&[2])
            }
        })
        .collect()
}

impl Schur {
    /// Prepares S for the rows `rows[active[k]]`, k = 0 … m − 1 (their bodies are read; the
    /// Jacobian values are not): finds the structural non-zeros and, for the skyline, the
    /// renumbering and the envelope.
    pub fn new(rows: &[ConstraintRow], active: &[usize], solver: SchurSolver) -> Self {
        let m = active.len();
        let mut pairs = pairs_on_common_bodies(active.iter().map(|&r| &rows[r]));
        pairs.sort_unstable();
        let mut adjacency: Vec<Vec<usize>> = vec![Vec::new(); m];
        for &(i, j, _, _) in &pairs {
            if i != j {
                adjacency[i].push(j);
                adjacency[j].push(i);
            }
        }
        for a in &mut adjacency {
            a.sort_unstable();
            a.dedup();
        }
        let dense = match solver {
            SchurSolver::Dense => true,
            SchurSolver::Skyline => false,
            SchurSolver::Auto => m <= DENSE_MAX_ROWS,
        };
        let (storage, position): (Storage, Box<dyn Fn(usize, usize) -> usize>) = if dense {
            (
                Storage::Dense {
                    a: vec![0.0; m * m],
                },
                Box::new(move |i, j| i * m + j),
            )
        } else {
            let envelope = skyline::Envelope::new(&adjacency);
            let total = envelope.len();
            let skyline::Envelope {
                perm, first, start, ..
            } = envelope.clone();
            (
                Storage::Skyline {
                    perm,
                    first,
                    start,
                    values: vec![0.0; total],
                    x: vec![0.0; m],
                },
                Box::new(move |i, j| envelope.position(i, j)),
            )
        };
        let couplings = pairs
            .iter()
            .map(|&(i, j, side_i, side_j)| Coupling {
                block_i: block_index(i, side_i),
                block_j: block_index(j, side_j),
                pos: to_u32(position(i, j)),
            })
            .collect();
        let diagonal = (0..m).map(|k| position(k, k)).collect();
        Schur {
            m,
            storage,
            couplings,
            weighted: vec![[[0.0; 3]; 2]; m],
            blocks: vec![[[0.0; 3]; 2]; m],
            diagonal,
            min_pivot_ratio: 1.0,
            added: vec![0.0; m],
        }
    }

    /// Number of rows m.
    pub fn n_rows(&self) -> usize {
        self.m
    }

    /// Whether the skyline storage is in use (else dense).
    pub fn is_skyline(&self) -> bool {
        matches!(self.storage, Storage::Skyline { .. })
    }

    /// Number of stored entries of the factor (m(m+1)/2 … m² for dense, the envelope for the
    /// skyline).
    pub fn stored_entries(&self) -> usize {
        match &self.storage {
            Storage::Dense { a } => a.len(),
            Storage::Skyline { values, .. } => values.len(),
        }
    }

    /// M⁻¹ times each row's two Jacobian blocks (block order body a, body b; zero for ground),
    /// as of the last [`Schur::factor`] or [`Schur::factor_regularised`].
    pub fn weighted(&self) -> &[[[f64; 3]; 2]] {
        &self.weighted
    }

    /// Forms S = Φ_q M⁻¹ Φ_qᵀ for the rows `rows[active[k]]` (the same rows as at
    /// [`Schur::new`], now with their values) and the diagonal inverse mass matrix `inv_mass`
    /// (3 per body), adds `shift` × its own diagonal to every diagonal entry (a relative
    /// regularisation; 0 for the plain S, and a zero diagonal then becomes `shift`), and factors
    /// it. `Err(k)`: the pivot of row k (caller's numbering) is not positive, S is singular to
    /// working precision there.
    pub fn factor(
        &mut self,
        rows: &[ConstraintRow],
        active: &[usize],
        inv_mass: &[f64],
        shift: f64,
    ) -> Result<(), usize> {
        self.form(rows, active, inv_mass);
        if shift > 0.0 {
            let values = match &mut self.storage {
                Storage::Dense { a } => a,
                Storage::Skyline { values, .. } => values,
            };
            for &d in &self.diagonal {
                values[d] += if values[d] == 0.0 {
                    shift
                } else {
                    shift * values[d]
                };
            }
        }
        self.factor_formed()
    }

    /// Forms S as [`Schur::factor`] does and factors it with every pivot regularised,
    ///
    /// ```text
    ///     d_p  →  d_p + Δ_p,   Δ_p = μ_p³ / (d_p + μ_p)²,   μ_p = shift[p] > 0
    /// ```
    ///
    /// (row p in the caller's numbering): a smooth modified Cholesky. Adding Δ_p to pivot p
    /// is adding it to S_pp before the elimination, so the factor is exact for
    /// A = S + diag(Δ). A healthy pivot d_p ≫ μ_p moves by μ_p³/d_p² only, a relative
    /// (μ_p/d_p)³; a pivot that collapses at a singular position, d_p → 0, becomes μ_p (and
    /// stays ≥ 0.89 μ_p on the way: d + μ³/(d + μ)² is smallest at d = 0.26 μ), so that
    /// A⁻¹ stays bounded by ~1/μ_p along the near-null direction. Smooth in d_p (no
    /// threshold) for d_p > −μ_p. `Err(k)`: a pivot at or below −μ_p or not finite (never
    /// from a positive semi-definite S but by round-off far below μ_p).
    pub fn factor_regularised(
        &mut self,
        rows: &[ConstraintRow],
        active: &[usize],
        inv_mass: &[f64],
        shift: &[f64],
    ) -> Result<(), usize> {
        self.form(rows, active, inv_mass);
        let mut min_ratio = 1.0_f64;
        // Positions whose `added` holds d + μ (turned into Δ below).
        let mut seen = 0;
        let added = &mut self.added;
        let factored = match &mut self.storage {
            Storage::Dense { a } => cholesky::factor_with(a, self.m, |j, raw, diagonal| {
                seen = j + 1;
                regularised(&mut min_ratio, raw, diagonal, shift[j], &mut added[j])
            }),
            Storage::Skyline {
                perm,
                first,
                start,
                values,
                ..
            } => skyline::factor_with(first, start, values, |p, raw, diagonal| {
                seen = p + 1;
                regularised(
                    &mut min_ratio,
                    raw,
                    diagonal,
                    shift[perm[p]],
                    &mut added[perm[p]],
                )
            })
            .map_err(|p| perm[p]),
        };
        // Δ = μ³/(d + μ)² for the rows factored, after the elimination rather than inside it,
        // where the division held up the next row (the same expression, so the same value).
        let rows_seen: &mut dyn Iterator<Item = usize> = match &self.storage {
            Storage::Dense { .. } => &mut (0..seen),
            Storage::Skyline { perm, .. } => &mut perm[..seen].iter().copied(),
        };
        for k in rows_seen {
            let (mu, sum) = (shift[k], added[k]);
            added[k] = shift_of(mu, sum);
        }
        self.min_pivot_ratio = min_ratio;
        factored
    }

    /// The smallest ratio of a raw (unregularised) pivot to its row's diagonal entry in the
    /// last [`Schur::factor_regularised`]: the squared sine of the angle between that row of
    /// Φ_q (in the M⁻¹ metric) and the span of the rows before it. O(1) at regular positions,
    /// falling like s² at a distance s from a position where Φ_q loses rank. 1 before any
    /// regularised factorisation.
    pub fn min_pivot_ratio(&self) -> f64 {
        self.min_pivot_ratio
    }

    /// The diagonal Δ (caller's numbering) that the last [`Schur::factor_regularised`] added to
    /// S: its factor is the exact Cholesky factor of S + diag(Δ), Δ_k = μ_k³/(d_k + μ_k)² with
    /// d_k the raw pivot of row k (≈ μ_k³/d_k², below round-off of S_kk, at a healthy pivot).
    /// Rows after a pivot that broke down keep their previous values.
    pub fn regularisation(&self) -> &[f64] {
        &self.added
    }

    /// Computes the weighted blocks M⁻¹ Φ_q,iᵀ and sums S over its structural non-zeros into
    /// the storage (not factored).
    fn form(&mut self, rows: &[ConstraintRow], active: &[usize], inv_mass: &[f64]) {
        debug_assert_eq!(active.len(), self.m, "the rows given at construction");
        for ((w, plain), &r) in self.weighted.iter_mut().zip(&mut self.blocks).zip(active) {
            for (side, (body, jac)) in rows[r].blocks().into_iter().enumerate() {
                w[side] = match body {
                    Some(b) => [
                        jac[0] * inv_mass[3 * b],
                        jac[1] * inv_mass[3 * b + 1],
                        jac[2] * inv_mass[3 * b + 2],
                    ],
                    None => [0.0; 3],
                };
                plain[side] = *jac;
            }
        }
        let values = match &mut self.storage {
            Storage::Dense { a } => a,
            Storage::Skyline { values, .. } => values,
        };
        values.fill(0.0);
        let (weighted, plain) = (self.weighted.as_flattened(), self.blocks.as_flattened());
        for c in &self.couplings {
            let w = &weighted[c.block_i as usize];
            let jac = &plain[c.block_j as usize];
            values[c.pos as usize] += w[0] * jac[0] + w[1] * jac[1] + w[2] * jac[2];
        }
    }

    /// Factors the formed (and shifted) storage in place.
    fn factor_formed(&mut self) -> Result<(), usize> {
        match &mut self.storage {
            Storage::Dense { a } => cholesky::factor(a, self.m),
            Storage::Skyline {
                perm,
                first,
                start,
                values,
                ..
            } => skyline::factor(first, start, values).map_err(|p| perm[p]),
        }
    }

    /// Solves S x = b in place (`b` becomes x, caller's numbering) with the factor of the last
    /// successful [`Schur::factor`] (or A x = b after [`Schur::factor_regularised`]).
    pub fn solve(&mut self, b: &mut [f64]) {
        match &mut self.storage {
            Storage::Dense { a } => cholesky::solve(a, self.m, b),
            Storage::Skyline {
                perm,
                first,
                start,
                values,
                x,
            } => {
                for (xp, &k) in x.iter_mut().zip(perm.iter()) {
                    *xp = b[k];
                }
                skyline::solve(first, start, values, x);
                for (xp, &k) in x.iter().zip(perm.iter()) {
                    b[k] = *xp;
                }
            }
        }
    }
}

/// The index of block `side` of row k in the flattened per-row block arrays.
fn block_index(k: usize, side: u8) -> u32 {
    to_u32(2 * k + side as usize)
}

/// An index of the Schur structure as u32: constraint rows and stored entries stay far below
/// 2³² (a model of 10⁶ rows would need terabytes for its envelope first).
fn to_u32(k: usize) -> u32 {
    u32::try_from(k).unwrap_or(u32::MAX)
}

#[cfg(test)]
mod tests;
