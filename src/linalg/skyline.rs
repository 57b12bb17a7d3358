//! Envelope (skyline, profile) Cholesky of a sparse SPD matrix, in place, and the reverse
//! Cuthill–McKee renumbering that makes a linkage's envelope narrow.
//!
//! Row p of the factor L is stored from its first structural non-zero f_p to the diagonal at
//! `values[start[p]..start[p + 1]]`; Cholesky fills only inside this envelope (ref. 2, §4.2),
//! so the factor costs Σ_p (p − f_p)² / 2 multiply-adds: linear in the rows for a chain of
//! loops, whose envelope stays a few rows wide however long the chain. The diagonal holds the
//! reciprocal 1/L_pp, as the dense [`super::cholesky`] does.
//!
//! User: the DAE's Schur complement (`formulation/schur.rs`) above `DENSE_MAX_ROWS` (16) rows.
//!
//! Kept against faer by measurement (`cargo bench --bench linalg -- spd_chain`, factor + solve
//! of one right-hand side on SPD matrices with a chain's band, rows scrambled, 2026-11-28;
//! docs/measurements.md "One place for the linear algebra"): 1.95, 7.88, 39.5 µs at m = 62,
//! 242, 1202 against 3.52, 12.9, 66.7 µs for faer's sparse Cholesky (AMD and its symbolic
//! analysis done once, outside the loop) and 18.8, 189 µs for faer's dense one (`Par::Seq`).
//! Both sparse factors fill about the same after their orderings (about four entries per row);
//! the skyline's contiguous dot products of a few entries beat faer's general kernels.
//!
//! # References
//! 1. A. George, J. W. H. Liu, *Computer Solution of Large Sparse Positive Definite Systems*,
//!    Prentice-Hall, 1981, §4.3 (reverse Cuthill–McKee, pseudo-peripheral nodes).
//! 2. A. Jennings, A compact storage scheme for the solution of symmetric linear simultaneous
//!    equations, *The Computer Journal* 9 (1966) 281–285.

use std::collections::VecDeque;

/// The envelope of a symmetric sparsity pattern under the better of its natural order and the
/// reverse Cuthill–McKee one: where each entry of the factor is stored.
#[derive(Debug, Clone)]
pub struct Envelope {
    /// `perm[p]` = the caller's row at position p.
    pub perm: Vec<usize>,
    /// `inverse[k]` = the position of the caller's row k.
    pub inverse: Vec<usize>,
    /// First stored column of each position's row.
    pub first: Vec<usize>,
    /// Where each position's row starts in the values; `start[m]` is their number.
    pub start: Vec<usize>,
}

impl Envelope {
    /// The envelope of the pattern with off-diagonal neighbours `adjacency[k]` of row k
    /// (symmetric): renumbered by reverse Cuthill–McKee unless the natural order is already as
    /// tight (a single loop).
    pub fn new(adjacency: &[Vec<usize>]) -> Self {
        let m = adjacency.len();
        let natural: Vec<usize> = (0..m).collect();
        let rcm = reverse_cuthill_mckee(adjacency);
        let perm = if envelope_size(adjacency, &rcm) < envelope_size(adjacency, &natural) {
            rcm
        } else {
            natural
        };
        let mut inverse = vec![0; m];
        for (p, &k) in perm.iter().enumerate() {
            inverse[k] = p;
        }
        let first: Vec<usize> = (0..m)
            .map(|p| {
                adjacency[perm[p]]
                    .iter()
                    .map(|&k| inverse[k])
                    .fold(p, usize::min)
            })
            .collect();
        let mut start = Vec::with_capacity(m + 1);
        let mut total = 0;
        for (p, f) in first.iter().enumerate() {
            start.push(total);
            total += p - f + 1;
        }
        start.push(total);
        Envelope {
            perm,
            inverse,
            first,
            start,
        }
    }

    /// Number of stored entries.
    pub fn len(&self) -> usize {
        self.start.last().copied().unwrap_or(0)
    }

    /// Whether nothing is stored (no rows).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Where the entry of the caller's rows i and j (either order) is stored; it must lie in
    /// the envelope (i and j neighbours, or equal).
    pub fn position(&self, i: usize, j: usize) -> usize {
        let (a, b) = (self.inverse[i], self.inverse[j]);
        let (r, c) = (a.max(b), a.min(b));
        self.start[r] + c - self.first[r]
    }
}

/// Envelope Cholesky in place: row p of `values` (columns `first[p]..=p`) becomes row p of L,
/// with the reciprocal 1/L_pp on the diagonal as in [`super::cholesky::factor`]. Row-oriented
/// (ref. 2): L_pj = (S_pj − Σ_{k ≥ max(f_p, f_j)} L_pk L_jk) / L_jj, every sum a dot product of
/// two contiguous slices. `Err(p)`: the first pivot that is not positive
/// ([`super::cholesky::checked_pivot`]).
pub fn factor(first: &[usize], start: &[usize], values: &mut [f64]) -> Result<(), usize> {
    factor_with(first, start, values, |_, raw, diagonal| {
        super::cholesky::checked_pivot(raw, diagonal)
    })
}

/// [`factor`] with the pivot rule given, as [`super::cholesky::factor_with`]:
/// `pivot(p, d, S_pp)` returns the pivot to use for the raw pivot d at position p of the
/// renumbered order, or `None` to stop with `Err(p)`.
pub fn factor_with(
    first: &[usize],
    start: &[usize],
    values: &mut [f64],
    mut pivot: impl FnMut(usize, f64, f64) -> Option<f64>,
) -> Result<(), usize> {
    // L_pk is `values[base_p + k]` with base_p = start[p] − f_p (≥ 0: row p starts after p
    // earlier rows of at least one entry each, and f_p ≤ p). Plain index loops: the envelope
    // rows of a linkage hold about four entries, and the slices and zipped iterators of a
    // general dot product cost more than the few products in them. Sums run from −0.0 in
    // increasing k, as `Iterator::sum` does, so the factor is the same to the bit.
    for p in 0..first.len() {
        let fp = first[p];
        let base_p = start[p] - fp;
        for j in fp..p {
            let fj = first[j];
            let base_j = start[j] - fj;
            let mut dot = -0.0;
            for k in fp.max(fj)..j {
                dot += values[base_p + k] * values[base_j + k];
            }
            values[base_p + j] = (values[base_p + j] - dot) * values[base_j + j];
        }
        let mut squares = -0.0;
        for k in fp..p {
            squares += values[base_p + k] * values[base_p + k];
        }
        let s = values[base_p + p];
        let Some(d) = pivot(p, s - squares, s) else {
            return Err(p);
        };
        values[base_p + p] = 1.0 / d.sqrt();
    }
    Ok(())
}

/// Solves L Lᵀ x = b in place with L from [`factor`] (indexing as there).
pub fn solve(first: &[usize], start: &[usize], values: &[f64], x: &mut [f64]) {
    for p in 0..first.len() {
        let fp = first[p];
        let base = start[p] - fp;
        let mut dot = -0.0;
        for k in fp..p {
            dot += values[base + k] * x[k];
        }
        x[p] = (x[p] - dot) * values[base + p];
    }
    // Lᵀ x = y by columns of Lᵀ (rows of L): x_p is final once the rows below have been
    // subtracted, then scattered into the rows it couples to.
    for p in (0..first.len()).rev() {
        let fp = first[p];
        let base = start[p] - fp;
        let xp = x[p] * values[base + p];
        x[p] = xp;
        for k in fp..p {
            x[k] -= values[base + k] * xp;
        }
    }
}

/// Entries of the envelope of the lower triangle under the ordering `order` (`order[p]` = the
/// node at position p).
pub fn envelope_size(adjacency: &[Vec<usize>], order: &[usize]) -> usize {
    let mut position = vec![0; order.len()];
    for (p, &k) in order.iter().enumerate() {
        position[k] = p;
    }
    order
        .iter()
        .enumerate()
        .map(|(p, &k)| {
            let f = adjacency[k]
                .iter()
                .map(|&j| position[j])
                .fold(p, usize::min);
            p - f + 1
        })
        .sum()
}

/// Breadth-first levels from `start` over the nodes not yet `placed`: (order visited, the
/// level of each node, usize::MAX where not reached).
fn bfs(adjacency: &[Vec<usize>], start: usize, placed: &[bool], level: &mut [usize]) -> Vec<usize> {
    level.fill(usize::MAX);
    let mut order = vec![start];
    level[start] = 0;
    let mut queue = VecDeque::from([start]);
    while let Some(k) = queue.pop_front() {
        let mut next: Vec<usize> = adjacency[k]
            .iter()
            .copied()
            .filter(|&j| !placed[j] && level[j] == usize::MAX)
            .collect();
        // Cuthill–McKee: neighbours by increasing degree.
        next.sort_by_key(|&j| (adjacency[j].len(), j));
        for j in next {
            level[j] = level[k] + 1;
            order.push(j);
            queue.push_back(j);
        }
    }
    order
}

/// Reverse Cuthill–McKee ordering of a graph given by its adjacency lists (ref. 1, §4.3): each
/// connected component from a pseudo-peripheral node (George–Liu: restart from a node of least
/// degree on the last level while the eccentricity grows), breadth first, neighbours by
/// increasing degree; the whole order reversed.
pub fn reverse_cuthill_mckee(adjacency: &[Vec<usize>]) -> Vec<usize> {
    let m = adjacency.len();
    let mut placed = vec![false; m];
    let mut level = vec![usize::MAX; m];
    let mut order = Vec::with_capacity(m);
    while let Some(seed) = (0..m)
        .filter(|&k| !placed[k])
        .min_by_key(|&k| (adjacency[k].len(), k))
    {
        let mut visit = bfs(adjacency, seed, &placed, &mut level);
        let mut eccentricity = visit.last().map_or(0, |&k| level[k]);
        // A handful of restarts finds a pseudo-peripheral node on the graphs of linkages.
        for _ in 0..8 {
            let Some(candidate) = visit
                .iter()
                .copied()
                .filter(|&k| level[k] == eccentricity)
                .min_by_key(|&k| (adjacency[k].len(), k))
            else {
                break;
            };
            let trial = bfs(adjacency, candidate, &placed, &mut level);
            let e = trial.last().map_or(0, |&k| level[k]);
            if e <= eccentricity {
                break;
            }
            (visit, eccentricity) = (trial, e);
        }
        for &k in &visit {
            placed[k] = true;
        }
        order.extend(visit);
    }
    order.reverse();
    order
}
