//! The envelope (skyline) Cholesky of S by 2 × 2 blocks.
//!
//! A joint gives its rows in twos on the same pair of bodies (a revolute joint's x and y rows,
//! a prismatic joint's normal and angle rows), and two such rows couple to exactly the same
//! other rows. Grouping them makes S a matrix of 2 × 2 blocks with half as many block rows, each
//! with about half as many entries in its envelope as a scalar row: the loops of the
//! factorisation and the solves run a quarter as many times, over four products each. On a
//! chain of linkage loops the scalar envelope rows held about four entries, and the loop
//! bookkeeping around those few products was most of the cost (200 loops: 1202 rows; measured
//! in `docs/benchmarks.md`). A row with no partner is padded with a row of its own that couples
//! to nothing (S = 1 on its diagonal, 0 elsewhere, right-hand side 0), which the factorisation
//! carries through unchanged.
//!
//! The elimination is that of the scalar envelope Cholesky on the rows in block order (row 2P
//! before row 2P + 1); only the order of the sums inside each entry differs.

use super::reverse_cuthill_mckee;
use std::collections::HashMap;
use std::hash::Hash;

/// S stored by 2 × 2 blocks in an envelope: block row P holds the blocks of columns
/// `first[P]..=P`, four values each (row-major: S[2P][2J], S[2P][2J+1], S[2P+1][2J],
/// S[2P+1][2J+1]) from `values[start[P]]` on; the diagonal block's upper entry is unused.
#[derive(Debug, Clone)]
pub(super) struct Paired {
    /// The caller's row at each scalar position 2P + r, `None` for a padding row.
    rows_at: Vec<Option<usize>>,
    /// Each caller row's scalar position.
    position_of: Vec<usize>,
    first: Vec<usize>,
    start: Vec<usize>,
    values: Vec<f64>,
    /// Storage index of each padding row's diagonal.
    padding: Vec<usize>,
    /// The right-hand side in block order.
    x: Vec<f64>,
}

impl Paired {
    /// Groups the m rows (row k acts on `bodies[k]`; `adjacency[k]` lists the rows it shares
    /// a body with) in twos that act on the same bodies, orders the
    /// blocks by reverse Cuthill–McKee where that makes the envelope smaller, and lays out the
    /// envelope.
    pub(super) fn new<B: Hash + Eq>(bodies: &[B], adjacency: &[Vec<usize>]) -> Self {
        let m = bodies.len();
        // Rows on the same bodies pair up in the order they come (a third on the same bodies
        // starts a new pair); the groups keep the order of their first rows.
        let mut groups: Vec<[Option<usize>; 2]> = Vec::with_capacity(m);
        // The group of each row still waiting for a partner, by its bodies.
        let mut open: HashMap<&B, usize> = HashMap::new();
        for (k, key) in bodies.iter().enumerate() {
            match open.remove(key) {
                Some(g) => groups[g][1] = Some(k),
                None => {
                    open.insert(key, groups.len());
                    groups.push([Some(k), None]);
                }
            }
        }
        let nb = groups.len();
        let mut group_of = vec![0; m];
        for (g, pair) in groups.iter().enumerate() {
            for &k in pair.iter().flatten() {
                group_of[k] = g;
            }
        }
        let mut block_adjacency: Vec<Vec<usize>> = vec![Vec::new(); nb];
        for (k, neighbours) in adjacency.iter().enumerate() {
            for &j in neighbours {
                let (a, b) = (group_of[k], group_of[j]);
                if a != b {
                    block_adjacency[a].push(b);
                }
            }
        }
        for a in &mut block_adjacency {
            a.sort_unstable();
            a.dedup();
        }
        let natural: Vec<usize> = (0..nb).collect();
        let rcm = reverse_cuthill_mckee(&block_adjacency);
        let order = if super::envelope_size(&block_adjacency, &rcm)
            < super::envelope_size(&block_adjacency, &natural)
        {
            rcm
        } else {
            natural
        };
        let mut block_at = vec![0; nb];
        for (p, &g) in order.iter().enumerate() {
            block_at[g] = p;
        }
        let first: Vec<usize> = order
            .iter()
            .enumerate()
            .map(|(p, &g)| {
                block_adjacency[g]
                    .iter()
                    .map(|&h| block_at[h])
                    .fold(p, usize::min)
            })
            .collect();
        let mut start = Vec::with_capacity(nb + 1);
        let mut total = 0;
        for (p, f) in first.iter().enumerate() {
            start.push(total);
            total += 4 * (p - f + 1);
        }
        start.push(total);
        let mut rows_at = vec![None; 2 * nb];
        let mut position_of = vec![0; m];
        for (p, &g) in order.iter().enumerate() {
            for (r, row) in groups[g].iter().enumerate() {
                rows_at[2 * p + r] = *row;
                if let Some(k) = row {
                    position_of[*k] = 2 * p + r;
                }
            }
        }
        let mut paired = Paired {
            rows_at,
            position_of,
            first,
            start,
            values: vec![0.0; total],
            padding: Vec::new(),
            x: vec![0.0; 2 * nb],
        };
        paired.padding = (0..2 * nb)
            .filter(|&s| paired.rows_at[s].is_none())
            .map(|s| paired.index(s, s))
            .collect();
        paired
    }

    /// Storage index of S_ij, caller's rows i and j (either order: the lower triangle).
    pub(super) fn index_of_rows(&self, i: usize, j: usize) -> usize {
        self.index(self.position_of[i], self.position_of[j])
    }

    /// Storage index of the entry at scalar positions (a, b), either order.
    fn index(&self, a: usize, b: usize) -> usize {
        let (hi, lo) = (a.max(b), a.min(b));
        let (p, r) = (hi / 2, hi % 2);
        let (j, c) = (lo / 2, lo % 2);
        self.start[p] + 4 * (j - self.first[p]) + 2 * r + c
    }

    /// The caller's rows in the order the factorisation takes them.
    pub(super) fn rows_in_order(&self) -> impl Iterator<Item = usize> + '_ {
        self.rows_at.iter().flatten().copied()
    }

    /// The values, for forming S into them.
    pub(super) fn values_mut(&mut self) -> &mut [f64] {
        &mut self.values
    }

    pub(super) fn stored_entries(&self) -> usize {
        self.values.len()
    }

    /// Zeroes S but for the padding rows' unit diagonal.
    pub(super) fn clear(&mut self) {
        self.values.fill(0.0);
        for &d in &self.padding {
            self.values[d] = 1.0;
        }
    }

    /// Factors the formed S in place into L Lᵀ, row by row of the scalar positions:
    /// `pivot(k, d, S_kk)` gives the pivot to use for the raw pivot d of the caller's row k
    /// (padding rows keep their pivot 1), or `None` to stop with `Err(k)`.
    /// Each diagonal block becomes [1/L₀₀, ·, L₁₀, 1/L₁₁].
    pub(super) fn factor_with(
        &mut self,
        mut pivot: impl FnMut(usize, f64, f64) -> Option<f64>,
    ) -> Result<(), usize> {
        let (first, start, values) = (&self.first, &self.start, &mut self.values);
        for p in 0..first.len() {
            let fp = first[p];
            // L_PK is the block at values[base_p + 4K].
            let base_p = start[p] - 4 * fp;
            for j in fp..p {
                let fj = first[j];
                let base_j = start[j] - 4 * fj;
                let at = base_p + 4 * j;
                let mut x = [values[at], values[at + 1], values[at + 2], values[at + 3]];
                for k in fp.max(fj)..j {
                    let a = &values[base_p + 4 * k..base_p + 4 * k + 4];
                    let b = &values[base_j + 4 * k..base_j + 4 * k + 4];
                    // (L_PK L_JKᵀ)[r][c] = Σ_s L_PK[r][s] L_JK[c][s]
                    x[0] -= a[0] * b[0] + a[1] * b[1];
                    x[1] -= a[0] * b[2] + a[1] * b[3];
                    x[2] -= a[2] * b[0] + a[3] * b[1];
                    x[3] -= a[2] * b[2] + a[3] * b[3];
                }
                // Y L_JJᵀ = X, L_JJ = [[L₀₀, 0], [L₁₀, L₁₁]] kept as [1/L₀₀, ·, L₁₀, 1/L₁₁].
                let d = base_j + 4 * j;
                let (r00, l10, r11) = (values[d], values[d + 2], values[d + 3]);
                let y0 = x[0] * r00;
                let y2 = x[2] * r00;
                values[at] = y0;
                values[at + 1] = (x[1] - y0 * l10) * r11;
                values[at + 2] = y2;
                values[at + 3] = (x[3] - y2 * l10) * r11;
            }
            let at = base_p + 4 * p;
            let (s0, s1) = (values[at], values[at + 3]);
            let (mut d00, mut d10, mut d11) = (s0, values[at + 2], s1);
            for k in fp..p {
                let a = &values[base_p + 4 * k..base_p + 4 * k + 4];
                d00 -= a[0] * a[0] + a[1] * a[1];
                d10 -= a[2] * a[0] + a[3] * a[1];
                d11 -= a[2] * a[2] + a[3] * a[3];
            }
            let (row0, row1) = (self.rows_at[2 * p], self.rows_at[2 * p + 1]);
            // A padding row's pivot is its 1 (never `None`, so the rows in errors are real).
            let Some(p0) = row0.map_or(Some(d00), |k| pivot(k, d00, s0)) else {
                return Err(row0.unwrap_or(0));
            };
            let r00 = 1.0 / p0.sqrt();
            let l10 = d10 * r00;
            let raw1 = d11 - l10 * l10;
            let Some(p1) = row1.map_or(Some(raw1), |k| pivot(k, raw1, s1)) else {
                return Err(row1.unwrap_or(0));
            };
            values[at] = r00;
            values[at + 2] = l10;
            values[at + 3] = 1.0 / p1.sqrt();
        }
        Ok(())
    }

    /// Solves L Lᵀ x = b in place (`b` in the caller's row order) with the factor of
    /// [`Paired::factor_with`].
    pub(super) fn solve(&mut self, b: &mut [f64]) {
        for (x, row) in self.x.iter_mut().zip(&self.rows_at) {
            *x = row.map_or(0.0, |k| b[k]);
        }
        let (first, start, values, x) = (&self.first, &self.start, &self.values, &mut self.x);
        for p in 0..first.len() {
            let fp = first[p];
            let base = start[p] - 4 * fp;
            let (mut y0, mut y1) = (x[2 * p], x[2 * p + 1]);
            for j in fp..p {
                let a = &values[base + 4 * j..base + 4 * j + 4];
                y0 -= a[0] * x[2 * j] + a[1] * x[2 * j + 1];
                y1 -= a[2] * x[2 * j] + a[3] * x[2 * j + 1];
            }
            let d = base + 4 * p;
            let y0 = y0 * values[d];
            x[2 * p] = y0;
            x[2 * p + 1] = (y1 - values[d + 2] * y0) * values[d + 3];
        }
        // Lᵀ x = y by block rows of L from the last: x_P is final once the rows below have
        // been subtracted, then scattered into the blocks it couples to.
        for p in (0..first.len()).rev() {
            let fp = first[p];
            let base = start[p] - 4 * fp;
            let d = base + 4 * p;
            let x1 = x[2 * p + 1] * values[d + 3];
            let x0 = (x[2 * p] - values[d + 2] * x1) * values[d];
            x[2 * p] = x0;
            x[2 * p + 1] = x1;
            for j in fp..p {
                let a = &values[base + 4 * j..base + 4 * j + 4];
                x[2 * j] -= a[0] * x0 + a[2] * x1;
                x[2 * j + 1] -= a[1] * x0 + a[3] * x1;
            }
        }
        for (x, row) in self.x.iter().zip(&self.rows_at) {
            if let Some(k) = row {
                b[*k] = *x;
            }
        }
    }
}
