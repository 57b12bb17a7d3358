//! Independent rows of Φ_q, and least-norm solves on them, from a sparse Cholesky factor of
//! G = Φ_q Φ_qᵀ taken in row order.
//!
//! **The rule.** Row k of Φ_q is redundant when its distance to the span of the independent rows
//! before it is at most 1e-9 of its own length (`RANK_TOLERANCE` of the assembly, the rule of
//! its dense Gram–Schmidt pass). Cholesky of G in row order computes exactly that distance: with
//! P the independent rows before k, the pivot is
//!
//! ```text
//!     d_k = G_kk − G_kP G_PP⁻¹ G_Pk = |Φ_q,k − proj_P Φ_q,k|² ,       G_kk = |Φ_q,k|²
//! ```
//!
//! (the Schur complement of G_PP is the squared residual of the least-squares fit of row k by the
//! rows of P). A redundant row is then dropped from the factor (its row and column of L set to
//! zero, 1/L_kk = 0), so the next pivots again measure distances to the independent rows only.
//! The same rows as the dense pass are declared redundant (ref. 1, §5.3 for Cholesky of the
//! normal equations as orthogonalisation).
//!
//! **Round-off.** d_k is computed with an absolute error of a few ε G_kk (ε = 2.2e-16), far
//! above the (1e-9)² G_kk of the rule: the pivot alone cannot tell a dependent row (d_k ~ ±ε G_kk)
//! from one at a relative distance 1e-8. So a pivot with d_k > (1e-6)² G_kk is independent outright
//! (its distance is at least 1e-6 relative, a thousand times the rule's), and a **borderline**
//! pivot, d_k ≤ (1e-6)² G_kk, is decided by the rule itself: the residual
//! r = Φ_q,k − Φ_q,Pᵀ c, c = G_PP⁻¹ Φ_q,P Φ_q,kᵀ, is formed in coordinate space and projected
//! again while that shrinks it (as the dense pass orthogonalises twice: "twice is enough",
//! ref. 2), and row k is redundant iff |r| ≤ 1e-9 |Φ_q,k|; an independent borderline row takes
//! L_kk = |r|, the accurate value of √d_k.
//!
//! **Sparsity.** G_ij ≠ 0 only where rows i and j touch a common body, fixed by the model. The
//! structure of L (elimination tree, and the pattern of each row of L as the reach of row k's
//! non-zeros in that tree, ref. 3, §4) is found once, at [`RowBasis::new`]; each
//! [`RowBasis::factor`] is then the up-looking sparse Cholesky over that fixed pattern and
//! allocates nothing. The order must stay the row order (the rule depends on it), so no fill
//! reducing renumbering is made: for a chain of loops written joint by joint, as the model files
//! are, the fill stays a few entries per row and the factor costs O(m).
//!
//! # References
//! 1. G. H. Golub, C. F. Van Loan, *Matrix Computations*, 4th ed., Johns Hopkins, 2013, §5.3
//!    (normal equations), §5.4.1 (rank-revealing elimination in a fixed order).
//! 2. L. Giraud, J. Langou, M. Rozložník, The loss of orthogonality in the Gram–Schmidt
//!    orthogonalization process, *Computers & Mathematics with Applications* 50 (2005) 1069–1075.
//! 3. T. A. Davis, *Direct Methods for Sparse Linear Systems*, SIAM, 2006, §4.1–4.4
//!    (elimination tree, row patterns by `ereach`, up-looking Cholesky).
//! 4. Å. Björck, *Numerical Methods for Least Squares Problems*, SIAM, 1996, §2.8.4 (the
//!    corrected semi-normal equations) and §1.2.5 (pseudo-inverse of a product).

use crate::linalg::cholesky;
use crate::mechanics::constraints::{ConstraintRow, pairs_on_common_bodies};

/// Relative distance (of a row from the span of the rows before it) below which the pivot is
/// re-checked by the exact rule: a thousand times the rank tolerance, so that the pivot's
/// round-off (a few 1e-8 in relative distance) can never decide a row near the rule.
const BORDERLINE: f64 = 1e-6;
/// Projection passes of the exact re-check: two, as the dense Gram–Schmidt makes ("twice is
/// enough", ref. 2), unless the first already leaves nothing to project.
const MAX_PASSES: usize = 2;

/// One pair of row blocks on the same body: G_ij gets their product.
#[derive(Debug, Clone, Copy)]
struct Coupling {
    i: usize,
    j: usize,
    side_i: u8,
    side_j: u8,
    /// Where G_ij lands in `g_values`.
    pos: usize,
}

/// Sparse row-order Cholesky of Φ_q Φ_qᵀ with the dependent rows left out (see the module doc).
#[derive(Debug, Clone)]
pub struct RowBasis {
    m: usize,
    /// Lower triangle of G by rows: row k holds columns `g_col[g_start[k]..g_start[k + 1]]`
    /// (j ≤ k, the diagonal last).
    g_start: Vec<usize>,
    g_col: Vec<usize>,
    g_values: Vec<f64>,
    couplings: Vec<Coupling>,
    /// Row k of L (off the diagonal): columns `l_col[l_start[k]..l_start[k + 1]]` in the
    /// topological order of the up-looking factor, each stored at `l_pos` in column storage.
    l_start: Vec<usize>,
    l_col: Vec<usize>,
    l_pos: Vec<usize>,
    /// Column j of L (below the diagonal): rows `col_row[col_start[j]..col_start[j + 1]]`,
    /// increasing, values in `values`.
    col_start: Vec<usize>,
    col_row: Vec<usize>,
    values: Vec<f64>,
    /// 1 / L_kk; 0 for a dependent row.
    inv_diag: Vec<f64>,
    dependent: Vec<bool>,
    /// Dense workspaces: m (rows) and n (coordinates).
    x: Vec<f64>,
    y: Vec<f64>,
    r: Vec<f64>,
    /// Buffers of [`RowBasis::least_squares_into`] (grown once, then reused).
    fits: Fits,
}

/// The fits Φ_q,k = Σ_i c_ki Φ_q,i of the dependent rows k (the matrix C of
/// [`RowBasis::least_squares_into`]) and the d × d system I + C Cᵀ.
#[derive(Debug, Clone, Default)]
struct Fits {
    rows: Vec<usize>,
    start: Vec<usize>,
    column: Vec<usize>,
    value: Vec<f64>,
    /// A row-length scratch vector (zero between uses) and the right-hand side w.
    dense: Vec<f64>,
    w: Vec<f64>,
    u: Vec<f64>,
    h: Vec<f64>,
    /// Whether C and h belong to the current factor, and whether h factored.
    ready: bool,
    factored: bool,
    /// The refinement's residual (rows) and correction (coordinates).
    s: Vec<f64>,
    dx: Vec<f64>,
}

impl RowBasis {
    /// Prepares the factor for `rows` (only which bodies each touches is read) over `n`
    /// coordinates: the structure of G, its elimination tree and the pattern of L.
    pub fn new(rows: &[ConstraintRow], n: usize) -> Self {
        let m = rows.len();
        // Pairs (i ≥ j) of blocks on one body, sorted below by row then column.
        let mut pairs = pairs_on_common_bodies(rows);
        // Every diagonal present, even for a row that touches only ground (G_kk = 0).
        for k in 0..m {
            pairs.push((k, k, u8::MAX, u8::MAX));
        }
        pairs.sort_unstable();
        let mut g_start = Vec::with_capacity(m + 1);
        let mut g_col: Vec<usize> = Vec::new();
        let mut couplings = Vec::new();
        let mut next = 0;
        for k in 0..m {
            g_start.push(g_col.len());
            while let Some(&(i, j, side_i, side_j)) = pairs.get(next).filter(|p| p.0 == k) {
                // Blocks meeting on two bodies (or a repeated body) add to one entry.
                if g_col.len() == g_start[k] || g_col.last() != Some(&j) {
                    g_col.push(j);
                }
                if side_i != u8::MAX {
                    couplings.push(Coupling {
                        i,
                        j,
                        side_i,
                        side_j,
                        pos: g_col.len() - 1,
                    });
                }
                next += 1;
            }
        }
        g_start.push(g_col.len());

        // Elimination tree of G (ref. 3, §4.1), with path compression through `ancestor`.
        let none = usize::MAX;
        let mut parent = vec![none; m];
        let mut ancestor = vec![none; m];
        for k in 0..m {
            for &j in &g_col[g_start[k]..g_start[k + 1]] {
                let mut i = j;
                while i != none && i < k {
                    let next = ancestor[i];
                    ancestor[i] = k;
                    if next == none {
                        parent[i] = k;
                    }
                    i = next;
                }
            }
        }
        // Pattern of each row of L: the reach of its non-zeros up the tree (ref. 3, §4.2),
        // in topological order (each path pushed so that descendants come first).
        let mut flag = vec![none; m];
        let mut path = Vec::new();
        let mut l_start = Vec::with_capacity(m + 1);
        let mut l_col = Vec::new();
        let mut col_count = vec![0usize; m];
        for k in 0..m {
            l_start.push(l_col.len());
            flag[k] = k;
            let mut stack: Vec<usize> = Vec::new();
            for &j in &g_col[g_start[k]..g_start[k + 1]] {
                let mut i = j;
                path.clear();
                while i != none && flag[i] != k {
                    path.push(i);
                    flag[i] = k;
                    i = parent[i];
                }
                stack.extend(path.iter().rev());
            }
            // `stack` read from its end is the topological order of cs_ereach.
            for &j in stack.iter().rev() {
                l_col.push(j);
                col_count[j] += 1;
            }
        }
        l_start.push(l_col.len());
        let mut col_start = Vec::with_capacity(m + 1);
        let mut total = 0;
        for c in &col_count {
            col_start.push(total);
            total += c;
        }
        col_start.push(total);
        let mut fill = col_start.clone();
        let mut col_row = vec![0; total];
        let mut l_pos = vec![0; l_col.len()];
        for k in 0..m {
            for e in l_start[k]..l_start[k + 1] {
                let j = l_col[e];
                l_pos[e] = fill[j];
                col_row[fill[j]] = k;
                fill[j] += 1;
            }
        }
        RowBasis {
            m,
            g_values: vec![0.0; g_col.len()],
            g_start,
            g_col,
            couplings,
            l_start,
            l_col,
            l_pos,
            col_start,
            col_row,
            values: vec![0.0; total],
            inv_diag: vec![0.0; m],
            dependent: vec![false; m],
            x: vec![0.0; m],
            y: vec![0.0; m],
            r: vec![0.0; n],
            fits: Fits {
                dense: vec![0.0; m],
                w: vec![0.0; m],
                s: vec![0.0; m],
                dx: vec![0.0; n],
                ..Fits::default()
            },
        }
    }

    /// Number of rows m.
    pub fn n_rows(&self) -> usize {
        self.m
    }

    /// Stored entries of L below the diagonal (its fill).
    pub fn stored_entries(&self) -> usize {
        self.values.len()
    }

    /// Whether row k was found dependent by the last [`RowBasis::factor`].
    pub fn is_dependent(&self, k: usize) -> bool {
        self.dependent.get(k).copied().unwrap_or(false)
    }

    /// The dependent rows of the last [`RowBasis::factor`], increasing.
    pub fn dependent_rows(&self) -> Vec<usize> {
        (0..self.m).filter(|&k| self.dependent[k]).collect()
    }

    /// Forms G = Φ_q Φ_qᵀ for `rows` (the rows given to [`RowBasis::new`], now with their
    /// values) and factors it in row order, leaving out each row within the rank tolerance of
    /// the span of the independent rows before it (module doc).
    pub fn factor(&mut self, rows: &[ConstraintRow], rank_tolerance: f64) {
        debug_assert_eq!(rows.len(), self.m, "the rows given at construction");
        self.fits.ready = false;
        self.g_values.fill(0.0);
        for c in &self.couplings {
            let a = rows[c.i].blocks()[c.side_i as usize].1;
            let b = rows[c.j].blocks()[c.side_j as usize].1;
            self.g_values[c.pos] += a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        }
        for k in 0..self.m {
            // x = G(0..=k, k), then the sparse triangular solve over the pattern of row k.
            for e in self.g_start[k]..self.g_start[k + 1] {
                self.x[self.g_col[e]] += self.g_values[e];
            }
            let g_kk = self.x[k];
            self.x[k] = 0.0;
            let mut d = g_kk;
            for e in self.l_start[k]..self.l_start[k + 1] {
                let j = self.l_col[e];
                let pos = self.l_pos[e];
                let l_kj = self.x[j] * self.inv_diag[j];
                self.x[j] = 0.0;
                if l_kj != 0.0 {
                    // Column j's entries above row k are stored before `pos`.
                    for p in self.col_start[j]..pos {
                        self.x[self.col_row[p]] -= self.values[p] * l_kj;
                    }
                }
                d -= l_kj * l_kj;
                self.values[pos] = l_kj;
            }
            let independent = if g_kk.is_nan() || g_kk <= 0.0 {
                // A zero row (or NaN): constrains nothing.
                None
            } else if d > BORDERLINE * BORDERLINE * g_kk {
                Some(d.sqrt())
            } else {
                let (distance, norm) = self.distance_to_earlier(rows, k);
                (distance > rank_tolerance * norm).then_some(distance)
            };
            match independent {
                Some(l_kk) => {
                    self.inv_diag[k] = 1.0 / l_kk;
                    self.dependent[k] = false;
                }
                None => {
                    self.inv_diag[k] = 0.0;
                    self.dependent[k] = true;
                    for e in self.l_start[k]..self.l_start[k + 1] {
                        self.values[self.l_pos[e]] = 0.0;
                    }
                }
            }
        }
    }

    /// |Φ_q,k − its projection onto the independent rows before k| and |Φ_q,k|, in coordinate
    /// space, with the factor of the rows before k (module doc: the exact rule).
    fn distance_to_earlier(&mut self, rows: &[ConstraintRow], k: usize) -> (f64, f64) {
        self.r.fill(0.0);
        scatter(&rows[k], 1.0, &mut self.r);
        let length = norm(&self.r);
        let mut distance = length;
        for _ in 0..MAX_PASSES {
            for (i, row) in rows[..k].iter().enumerate() {
                self.y[i] = row.dot_velocity(&self.r);
            }
            solve_leading(
                &self.col_start,
                &self.col_row,
                &self.values,
                &self.inv_diag,
                &mut self.y[..k],
            );
            for (i, row) in rows[..k].iter().enumerate() {
                scatter(row, -self.y[i], &mut self.r);
            }
            let next = norm(&self.r);
            let shrunk = next < 0.5 * distance;
            distance = next;
            if !shrunk {
                break;
            }
        }
        (distance, length)
    }

    /// x = Φ_q,Iᵀ G_II⁻¹ r_I over the independent rows I of the last factor: the minimum-norm
    /// solution of Φ_q,I x = r_I (for r consistent with the dependent rows, of Φ_q x = r).
    pub fn least_norm_into(&mut self, rows: &[ConstraintRow], r: &[f64], x: &mut [f64]) {
        self.y.copy_from_slice(r);
        solve_leading(
            &self.col_start,
            &self.col_row,
            &self.values,
            &self.inv_diag,
            &mut self.y,
        );
        x.fill(0.0);
        for (row, l) in rows.iter().zip(&self.y) {
            scatter(row, *l, x);
        }
    }

    /// x = Φ_q⁺ r, the minimum-norm least-squares solution of Φ_q x = r over all rows, as the
    /// dense SVD's pseudo-inverse gives it, where r need not be consistent with the dependent
    /// rows (a Newton iterate off the solution of an over-constrained linkage, a linkage that
    /// cannot be assembled).
    ///
    /// With I the independent rows, D the dependent ones and C their fits (Φ_q,D = C Φ_q,I),
    /// Φ_q = B Φ_q,I with B = [1; C] of full column rank and Φ_q,I of full row rank, so
    /// Φ_q⁺ = Φ_q,I⁺ B⁺ (ref. 4, §1.2.5) and
    ///
    /// ```text
    ///     x = Φ_q,Iᵀ G_II⁻¹ w,   (1 + Cᵀ C) w = r_I + Cᵀ r_D,
    ///     (1 + Cᵀ C)⁻¹ = 1 − Cᵀ (1 + C Cᵀ)⁻¹ C        (Sherman–Morrison–Woodbury)
    /// ```
    ///
    /// with 1 + C Cᵀ of the size of D (one row per redundant joint) and positive definite.
    /// For r consistent (r_D = C r_I) it is [`RowBasis::least_norm_into`]'s step.
    ///
    /// The normal equations square the condition number of Φ_q, so one step of iterative
    /// refinement in coordinate space follows (the corrected semi-normal equations, ref. 4):
    /// x += Φ_q⁺ (r − Φ_q x) with the same factors. It brings the step to the accuracy of the
    /// SVD's near a position where a singular value of Φ_q is small (an iterate approaching the
    /// solution of an over-constrained linkage, where the rank drops), as long as
    /// cond(Φ_q) < 1/√ε.
    pub fn least_squares_into(&mut self, rows: &[ConstraintRow], r: &[f64], x: &mut [f64]) {
        self.least_squares_once(rows, r, x);
        let mut s = std::mem::take(&mut self.fits.s);
        let mut dx = std::mem::take(&mut self.fits.dx);
        for ((sk, row), rk) in s.iter_mut().zip(rows).zip(r) {
            *sk = rk - row.dot_velocity(x);
        }
        self.least_squares_once(rows, &s, &mut dx);
        for (xi, di) in x.iter_mut().zip(&dx) {
            *xi += di;
        }
        self.fits.s = s;
        self.fits.dx = dx;
    }

    /// One application of the formula of [`RowBasis::least_squares_into`] (C and the
    /// factor of 1 + C Cᵀ computed at the first call after [`RowBasis::factor`]).
    fn least_squares_once(&mut self, rows: &[ConstraintRow], r: &[f64], x: &mut [f64]) {
        if !self.fits.ready {
            self.prepare_fits(rows);
        }
        let mut f = std::mem::take(&mut self.fits);
        let d = f.rows.len();
        if d > 0 {
            // w = r_I + Cᵀ r_D (zero on D), u = C w, w −= Cᵀ (1 + C Cᵀ)⁻¹ u.
            f.w.copy_from_slice(r);
            for (a, &k) in f.rows.iter().enumerate() {
                f.w[k] = 0.0;
                for e in f.start[a]..f.start[a + 1] {
                    f.w[f.column[e]] += f.value[e] * r[k];
                }
            }
            if f.factored {
                f.u.clear();
                for a in 0..d {
                    let ua = (f.start[a]..f.start[a + 1])
                        .map(|e| f.value[e] * f.w[f.column[e]])
                        .sum();
                    f.u.push(ua);
                }
                cholesky::solve(&f.h, d, &mut f.u);
                for a in 0..d {
                    for e in f.start[a]..f.start[a + 1] {
                        f.w[f.column[e]] -= f.value[e] * f.u[a];
                    }
                }
            }
        }
        let w = std::mem::take(&mut f.w);
        self.fits = f;
        if d > 0 {
            self.least_norm_into(rows, &w, x);
        } else {
            self.least_norm_into(rows, r, x);
        }
        self.fits.w = w;
    }

    /// C (the fit of each dependent row by the independent rows before it) and the Cholesky
    /// factor of 1 + C Cᵀ, for the factor of the last [`RowBasis::factor`].
    fn prepare_fits(&mut self, rows: &[ConstraintRow]) {
        let mut f = std::mem::take(&mut self.fits);
        f.ready = true;
        f.rows.clear();
        f.rows.extend((0..self.m).filter(|&k| self.dependent[k]));
        let d = f.rows.len();
        f.start.clear();
        f.column.clear();
        f.value.clear();
        for &k in &f.rows {
            f.start.push(f.column.len());
            self.combination_into(rows, k, &mut f.dense[..k]);
            for (i, c) in f.dense[..k].iter_mut().enumerate() {
                if *c != 0.0 && !self.dependent[i] {
                    f.column.push(i);
                    f.value.push(*c);
                }
                *c = 0.0;
            }
        }
        f.start.push(f.column.len());
        // 1 + C Cᵀ (lower triangle), by scattering each row of C once.
        f.h.clear();
        f.h.resize(d * d, 0.0);
        for a in 0..d {
            for e in f.start[a]..f.start[a + 1] {
                f.dense[f.column[e]] = f.value[e];
            }
            for b in 0..=a {
                let dot: f64 = (f.start[b]..f.start[b + 1])
                    .map(|e| f.value[e] * f.dense[f.column[e]])
                    .sum();
                f.h[a * d + b] = dot + if a == b { 1.0 } else { 0.0 };
            }
            for e in f.start[a]..f.start[a + 1] {
                f.dense[f.column[e]] = 0.0;
            }
        }
        // Positive definite (eigenvalues ≥ 1) unless a value is NaN: then the consistent step.
        f.factored = cholesky::factor(&mut f.h, d).is_ok();
        self.fits = f;
    }

    /// Coefficients c of the least-squares fit Φ_q,k ≈ Σ_{i<k} c_i Φ_q,i by the independent
    /// rows before k (0 for the dependent ones), into `c[..k]`.
    pub fn combination_into(&mut self, rows: &[ConstraintRow], k: usize, c: &mut [f64]) {
        // c = G_PP⁻¹ Φ_q,P Φ_q,kᵀ, then once more on the residual Φ_q,k − Φ_q,Pᵀ c in
        // coordinate space (the corrected semi-normal equations, ref. 4), which the normal
        // equations alone get wrong by ε cond(Φ_q,P)² relative.
        c[..k].fill(0.0);
        self.r.fill(0.0);
        scatter(&rows[k], 1.0, &mut self.r);
        for _ in 0..2 {
            for (yi, row) in self.y[..k].iter_mut().zip(&rows[..k]) {
                *yi = row.dot_velocity(&self.r);
            }
            solve_leading(
                &self.col_start,
                &self.col_row,
                &self.values,
                &self.inv_diag,
                &mut self.y[..k],
            );
            for ((ci, yi), row) in c[..k].iter_mut().zip(&self.y[..k]).zip(rows) {
                *ci += yi;
                scatter(row, -yi, &mut self.r);
            }
        }
    }
}

/// Solves L Lᵀ y = b in place for the leading rows 0 … b.len() − 1 of the factor (the factor
/// of those rows alone, since the order is the row order); dependent rows get 0.
fn solve_leading(
    col_start: &[usize],
    col_row: &[usize],
    values: &[f64],
    inv_diag: &[f64],
    y: &mut [f64],
) {
    let k = y.len();
    for j in 0..k {
        let yj = y[j] * inv_diag[j];
        y[j] = yj;
        if yj != 0.0 {
            for p in col_start[j]..col_start[j + 1] {
                let i = col_row[p];
                if i >= k {
                    break;
                }
                y[i] -= values[p] * yj;
            }
        }
    }
    for j in (0..k).rev() {
        let mut s = y[j];
        for p in col_start[j]..col_start[j + 1] {
            let i = col_row[p];
            if i >= k {
                break;
            }
            s -= values[p] * y[i];
        }
        y[j] = s * inv_diag[j];
    }
}

/// x += l · (row of Φ_q)ᵀ.
fn scatter(row: &ConstraintRow, l: f64, x: &mut [f64]) {
    for (body, jac) in row.blocks() {
        if let Some(b) = body {
            for c in 0..3 {
                x[3 * b + c] += jac[c] * l;
            }
        }
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}
