//! Dense LU factorisations with partial pivoting of the two Newton matrices of Radau IIA:
//! the real E₁ = γ̂/h·I − J and the complex E₂ = (α̂ + iβ̂)/h·I − J (n×n, row-major).
//!
//! Hand-written for the sizes met here (n = 2 to ~40; from 40 states Radau5 takes the sparse LU
//! of [`super::sparse_lu`] where the formulation allows, `solve::radau5::SPARSE_MIN_STATES`):
//! the buffers are allocated once, and factorising or solving allocates nothing.
//!
//! Measured with nalgebra's and faer's LU on the same (fully coupled) matrices (`cargo bench
//! --bench linalg -- lu_small`, real factor + solve, 2026-11-28): 106, 202, 479 ns at n = 3,
//! 6, 10 against nalgebra's 82, 200, 382 ns and faer's 509, 848, 1 216 ns; 2.51 and 7.70 µs
//! at 24 and 39 against nalgebra's 1.84 and 6.33 µs. On a fully coupled matrix nalgebra's is
//! faster by up to a quarter. Kept for the decoupled components below, which nalgebra's LU
//! cannot use: they take the reference four-bar's Newton systems in contact from 10 to 9 rows
//! (DAE) and from 3 to 2 (reduced); for the complex matrix
//! E₂ as two real arrays (nalgebra would need complex storage); and for allocating nothing in
//! the step loop. Writing the block solve over slices instead of index loops (the same
//! operations in the same order, every result bit for bit) took the DAE + Radau5 run of the
//! reference four-bar from 38.5 to 35.5 ms (median of 3 each, one sitting). Complex numbers are kept as separate real and
//! imaginary arrays.
//!
//! **Decoupled components.** A component j whose Jacobian column is zero off the diagonal
//! (nothing else depends on it: an energy integral, a stored impact velocity while free) is
//! factored apart: the matrix is block lower-triangular with those components last, so the
//! other components are solved from their own block alone and each decoupled one by a scalar
//! division afterwards. Likewise a component whose row is zero off the diagonal (it depends on
//! nothing: a stored impact velocity in contact, whose rate is 0) comes first: a scalar
//! division, then its column moves to the others' right-hand side. On farahan2016 this takes
//! the Newton systems from 10 × 10 to 9 × 9 (DAE) and from 3 × 3 to 2 × 2 (reduced) in contact. The arithmetic on the coupled components is then exactly the same
//! whether bookkeeping states are present or not (`tests/energy_bookkeeping_leaves_trajectory.rs`).

use super::Singular;

/// Which components are coupled (`main`, in order) and which decoupled: `leading` (row zero
/// off the diagonal: depends on nothing, solved first) and `trailing` (column zero off the
/// diagonal: read by nothing, solved last).
#[derive(Debug, Clone)]
pub(crate) struct Partition {
    n: usize,
    leading: Vec<usize>,
    main: Vec<usize>,
    trailing: Vec<usize>,
}

impl Partition {
    /// All n components coupled.
    pub(crate) fn new(n: usize) -> Self {
        Partition {
            n,
            leading: Vec::with_capacity(n),
            main: (0..n).collect(),
            trailing: Vec::with_capacity(n),
        }
    }

    /// The number of components n.
    pub(crate) fn dim(&self) -> usize {
        self.n
    }

    /// Sorts the components of the Jacobian J (row-major, n²) into coupled and decoupled:
    /// trailing if the column is zero off the diagonal (an energy integral; also when the row
    /// is), else leading if the row is (a stored impact velocity in contact: f = 0).
    pub(crate) fn update(&mut self, jac: &[f64]) {
        let n = self.n;
        self.leading.clear();
        self.main.clear();
        self.trailing.clear();
        for j in 0..n {
            if (0..n).all(|i| i == j || jac[i * n + j] == 0.0) {
                self.trailing.push(j);
            } else if (0..n).all(|i| i == j || jac[j * n + i] == 0.0) {
                self.leading.push(j);
            } else {
                self.main.push(j);
            }
        }
    }
}

/// LU factors of s·I − J for real s, with row pivots (coupled block), and the rows of the
/// decoupled components.
#[derive(Debug, Clone)]
pub(crate) struct RealLu {
    n: usize,
    m: usize,
    lu: Vec<f64>,
    piv: Vec<usize>,
    s: f64,
    part: Partition,
    /// J (copied at factorisation) for the decoupled rows.
    jac: Vec<f64>,
    tmp: Vec<f64>,
}

impl RealLu {
    /// Buffers for n×n matrices.
    pub(crate) fn new(n: usize) -> Self {
        RealLu {
            n,
            m: n,
            lu: vec![0.0; n * n],
            piv: vec![0; n],
            s: 0.0,
            part: Partition::new(n),
            jac: vec![0.0; n * n],
            tmp: vec![0.0; n],
        }
    }

    /// Factorises s·I − J (J row-major, n²) with the partition `part` of J's components.
    pub(crate) fn factor(&mut self, s: f64, jac: &[f64], part: &Partition) -> Result<(), Singular> {
        let n_all = self.n;
        debug_assert_eq!(
            jac.len(),
            n_all * n_all,
            "Jacobian buffer is allocated with n²"
        );
        self.part.leading.clone_from(&part.leading);
        self.part.main.clone_from(&part.main);
        self.part.trailing.clone_from(&part.trailing);
        self.jac.copy_from_slice(jac);
        self.s = s;
        let n = part.main.len();
        self.m = n;
        for (a, &i) in part.main.iter().enumerate() {
            for (b, &j) in part.main.iter().enumerate() {
                self.lu[a * n + b] = -jac[i * n_all + j];
            }
            self.lu[a * n + a] += s;
        }
        for &j in part.leading.iter().chain(&part.trailing) {
            if s - jac[j * n_all + j] == 0.0 {
                return Err(Singular { column: j });
            }
        }
        // A NaN pivot (from a NaN Jacobian) is refused too.
        super::dense_lu::eliminate(&mut self.lu[..n * n], n, &mut self.piv, |best| best > 0.0)
            .map_err(|column| Singular { column })
    }

    /// Solves (s·I − J) x = b in place.
    pub(crate) fn solve(&mut self, b: &mut [f64]) {
        let n_all = self.n;
        debug_assert_eq!(b.len(), n_all, "right-hand sides are allocated with n");
        // Leading components first (their rows hold only the diagonal), then the coupled
        // block with their columns moved to the right-hand side, then the trailing ones.
        for &j in &self.part.leading {
            b[j] /= self.s - self.jac[j * n_all + j];
        }
        for (a, &i) in self.part.main.iter().enumerate() {
            let row = &self.jac[i * n_all..(i + 1) * n_all];
            let mut sum = b[i];
            for &j in &self.part.leading {
                sum += row[j] * b[j];
            }
            self.tmp[a] = sum;
        }
        Self::solve_block(self.m, &self.lu, &self.piv, &mut self.tmp[..self.m]);
        for &j in &self.part.trailing {
            let row = &self.jac[j * n_all..(j + 1) * n_all];
            let mut sum = b[j];
            for &i in &self.part.leading {
                sum += row[i] * b[i];
            }
            for (a, &i) in self.part.main.iter().enumerate() {
                sum += row[i] * self.tmp[a];
            }
            b[j] = sum / (self.s - row[j]);
        }
        for (a, &i) in self.part.main.iter().enumerate() {
            b[i] = self.tmp[a];
        }
    }

    /// Solves the factored m×m block in place.
    fn solve_block(n: usize, a: &[f64], piv: &[usize], b: &mut [f64]) {
        // Whole rows (multipliers included) were swapped while factorising, so all row
        // interchanges are applied to b first (as LAPACK's getrs does).
        for k in 0..n {
            let p = piv[k];
            if p != k {
                b.swap(k, p);
            }
        }
        if n == 0 {
            // Every component decoupled: nothing coupled to solve.
            return;
        }
        // Slices, not index loops: no bounds checks inside, the same operations in order.
        let (a, b) = (&a[..n * n], &mut b[..n]);
        for k in 0..n {
            let (head, below) = b.split_at_mut(k + 1);
            let bk = head[k];
            for (x, row) in below.iter_mut().zip(a[(k + 1) * n..].chunks_exact(n)) {
                *x -= row[k] * bk;
            }
        }
        for (k, row) in a.chunks_exact(n).enumerate().rev() {
            let (head, done) = b.split_at_mut(k + 1);
            let mut s = head[k];
            for (u, x) in row[k + 1..].iter().zip(done.iter()) {
                s -= u * x;
            }
            head[k] = s / row[k];
        }
    }
}

/// LU factors of (α + iβ)·I − J for real J, with row pivots.
#[derive(Debug, Clone)]
pub(crate) struct ComplexLu {
    n: usize,
    re: Vec<f64>,
    im: Vec<f64>,
    piv: Vec<usize>,
    m: usize,
    alpha: f64,
    beta: f64,
    part: Partition,
    /// A = A_re + i·A_im (copied at factorisation) for the decoupled rows.
    jac: Vec<f64>,
    jac_im: Vec<f64>,
    tmp_re: Vec<f64>,
    tmp_im: Vec<f64>,
}

impl ComplexLu {
    /// Buffers for n×n matrices.
    pub(crate) fn new(n: usize) -> Self {
        ComplexLu {
            n,
            re: vec![0.0; n * n],
            im: vec![0.0; n * n],
            piv: vec![0; n],
            m: n,
            alpha: 0.0,
            beta: 0.0,
            part: Partition::new(n),
            jac: vec![0.0; n * n],
            jac_im: vec![0.0; n * n],
            tmp_re: vec![0.0; n],
            tmp_im: vec![0.0; n],
        }
    }

    /// Factorises (α + iβ)·I − J (J row-major, n²) with the partition `part`.
    pub(crate) fn factor(
        &mut self,
        alpha: f64,
        beta: f64,
        jac: &[f64],
        part: &Partition,
    ) -> Result<(), Singular> {
        self.factor_complex(alpha, beta, (jac, None), part)
    }

    /// Factorises (α + iβ)·I − A for A = A_re + i·A_im (row-major, n²; A_im zero if `None`)
    /// with the partition `part` of A's components.
    pub(crate) fn factor_complex(
        &mut self,
        alpha: f64,
        beta: f64,
        (jac, jac_im): (&[f64], Option<&[f64]>),
        part: &Partition,
    ) -> Result<(), Singular> {
        let n_all = self.n;
        debug_assert_eq!(
            jac.len(),
            n_all * n_all,
            "Jacobian buffer is allocated with n²"
        );
        self.part.leading.clone_from(&part.leading);
        self.part.main.clone_from(&part.main);
        self.part.trailing.clone_from(&part.trailing);
        self.jac.copy_from_slice(jac);
        match jac_im {
            Some(im) => self.jac_im.copy_from_slice(im),
            None => self.jac_im.fill(0.0),
        }
        (self.alpha, self.beta) = (alpha, beta);
        let n = part.main.len();
        self.m = n;
        for (a, &i) in part.main.iter().enumerate() {
            for (b, &j) in part.main.iter().enumerate() {
                self.re[a * n + b] = -jac[i * n_all + j];
                self.im[a * n + b] = -self.jac_im[i * n_all + j];
            }
            self.re[a * n + a] += alpha;
            self.im[a * n + a] += beta;
        }
        for &j in part.leading.iter().chain(&part.trailing) {
            let d = j * n_all + j;
            if alpha - jac[d] == 0.0 && beta - self.jac_im[d] == 0.0 {
                return Err(Singular { column: j });
            }
        }
        let (re, im) = (&mut self.re, &mut self.im);
        for k in 0..n {
            let mut p = k;
            let mut best = re[k * n + k].abs() + im[k * n + k].abs();
            for i in k + 1..n {
                let v = re[i * n + k].abs() + im[i * n + k].abs();
                if v > best {
                    best = v;
                    p = i;
                }
            }
            self.piv[k] = p;
            if best.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                return Err(Singular { column: k });
            }
            if p != k {
                for j in 0..n {
                    re.swap(k * n + j, p * n + j);
                    im.swap(k * n + j, p * n + j);
                }
            }
            let (pr, pi) = (re[k * n + k], im[k * n + k]);
            let d = pr * pr + pi * pi;
            let (inv_r, inv_i) = (pr / d, -pi / d);
            // As in the real factorisation: rows below the pivot as slices.
            let (top_re, below_re) = re[..n * n].split_at_mut((k + 1) * n);
            let (top_im, below_im) = im[..n * n].split_at_mut((k + 1) * n);
            let pivot_re = &top_re[k * n + k + 1..(k + 1) * n];
            let pivot_im = &top_im[k * n + k + 1..(k + 1) * n];
            for (row_re, row_im) in below_re
                .chunks_exact_mut(n)
                .zip(below_im.chunks_exact_mut(n))
            {
                let (ar, ai) = (row_re[k], row_im[k]);
                let mr = ar * inv_r - ai * inv_i;
                let mi = ar * inv_i + ai * inv_r;
                row_re[k] = mr;
                row_im[k] = mi;
                if mr != 0.0 || mi != 0.0 {
                    for (((xr, xi), &br), &bi) in row_re[k + 1..]
                        .iter_mut()
                        .zip(row_im[k + 1..].iter_mut())
                        .zip(pivot_re)
                        .zip(pivot_im)
                    {
                        *xr -= mr * br - mi * bi;
                        *xi -= mr * bi + mi * br;
                    }
                }
            }
        }
        Ok(())
    }

    /// Solves ((α + iβ)·I − J)(x_re + i x_im) = b_re + i b_im in place.
    pub(crate) fn solve(&mut self, b_re: &mut [f64], b_im: &mut [f64]) {
        let n_all = self.n;
        debug_assert!(
            b_re.len() == n_all && b_im.len() == n_all,
            "allocated with n"
        );
        // As in the real solve: leading, coupled block, trailing.
        for &j in &self.part.leading {
            let (pr, pi) = (
                self.alpha - self.jac[j * n_all + j],
                self.beta - self.jac_im[j * n_all + j],
            );
            let d = pr * pr + pi * pi;
            let (sr, si) = (b_re[j], b_im[j]);
            b_re[j] = (sr * pr + si * pi) / d;
            b_im[j] = (si * pr - sr * pi) / d;
        }
        for (a, &i) in self.part.main.iter().enumerate() {
            let row = &self.jac[i * n_all..(i + 1) * n_all];
            let row_im = &self.jac_im[i * n_all..(i + 1) * n_all];
            let (mut sr, mut si) = (b_re[i], b_im[i]);
            for &j in &self.part.leading {
                let (tr, ti) = (b_re[j], b_im[j]);
                sr += row[j] * tr - row_im[j] * ti;
                si += row[j] * ti + row_im[j] * tr;
            }
            self.tmp_re[a] = sr;
            self.tmp_im[a] = si;
        }
        let m = self.m;
        Self::solve_block(
            m,
            (&self.re, &self.im),
            &self.piv,
            (&mut self.tmp_re[..m], &mut self.tmp_im[..m]),
        );
        for &j in &self.part.trailing {
            let row = &self.jac[j * n_all..(j + 1) * n_all];
            let row_im = &self.jac_im[j * n_all..(j + 1) * n_all];
            let (mut sr, mut si) = (b_re[j], b_im[j]);
            for &i in &self.part.leading {
                let (tr, ti) = (b_re[i], b_im[i]);
                sr += row[i] * tr - row_im[i] * ti;
                si += row[i] * ti + row_im[i] * tr;
            }
            for (a, &i) in self.part.main.iter().enumerate() {
                let (tr, ti) = (self.tmp_re[a], self.tmp_im[a]);
                sr += row[i] * tr - row_im[i] * ti;
                si += row[i] * ti + row_im[i] * tr;
            }
            let (pr, pi) = (self.alpha - row[j], self.beta - row_im[j]);
            let d = pr * pr + pi * pi;
            b_re[j] = (sr * pr + si * pi) / d;
            b_im[j] = (si * pr - sr * pi) / d;
        }
        for (a, &i) in self.part.main.iter().enumerate() {
            b_re[i] = self.tmp_re[a];
            b_im[i] = self.tmp_im[a];
        }
    }

    /// Solves the factored m×m block in place.
    fn solve_block(
        n: usize,
        (re, im): (&[f64], &[f64]),
        piv: &[usize],
        (b_re, b_im): (&mut [f64], &mut [f64]),
    ) {
        for k in 0..n {
            let p = piv[k];
            if p != k {
                b_re.swap(k, p);
                b_im.swap(k, p);
            }
        }
        for k in 0..n {
            let (br, bi) = (b_re[k], b_im[k]);
            for i in k + 1..n {
                let (mr, mi) = (re[i * n + k], im[i * n + k]);
                b_re[i] -= mr * br - mi * bi;
                b_im[i] -= mr * bi + mi * br;
            }
        }
        for k in (0..n).rev() {
            let (mut sr, mut si) = (b_re[k], b_im[k]);
            for j in k + 1..n {
                let (ar, ai) = (re[k * n + j], im[k * n + j]);
                sr -= ar * b_re[j] - ai * b_im[j];
                si -= ar * b_im[j] + ai * b_re[j];
            }
            let (pr, pi) = (re[k * n + k], im[k * n + k]);
            let d = pr * pr + pi * pi;
            b_re[k] = (sr * pr + si * pi) / d;
            b_im[k] = (si * pr - sr * pi) / d;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 4×4 Jacobian that needs pivoting (zero leading entry of s·I − J for s = 2).
    const JAC: [f64; 16] = [
        2.0, 1.0, -3.0, 0.5, //
        4.0, -1.0, 0.0, 2.0, //
        -1.0, 2.5, 1.0, 1.0, //
        0.0, 3.0, -2.0, 7.0,
    ];

    #[test]
    fn real_solve_inverts_the_matrix() -> Result<(), Singular> {
        let s = 2.0;
        let mut lu = RealLu::new(4);
        lu.factor(s, &JAC, &Partition::new(4))?;
        let x_true = [1.0, -2.0, 0.5, 3.0];
        let mut b = [0.0; 4];
        for i in 0..4 {
            b[i] = s * x_true[i] - (0..4).map(|j| JAC[i * 4 + j] * x_true[j]).sum::<f64>();
        }
        lu.solve(&mut b);
        for (x, t) in b.iter().zip(x_true) {
            // Condition number of this matrix is ~30: a few hundred ulps at most.
            assert!((x - t).abs() < 1e-13, "x = {x} vs {t}");
        }
        Ok(())
    }

    #[test]
    fn complex_solve_inverts_the_matrix() -> Result<(), Singular> {
        let (alpha, beta) = (2.0, 0.7);
        let mut lu = ComplexLu::new(4);
        lu.factor(alpha, beta, &JAC, &Partition::new(4))?;
        let (xr, xi) = ([1.0, -2.0, 0.5, 3.0], [0.25, 1.0, -1.5, 0.0]);
        let (mut br, mut bi) = ([0.0; 4], [0.0; 4]);
        for i in 0..4 {
            let jr: f64 = (0..4).map(|j| JAC[i * 4 + j] * xr[j]).sum();
            let ji: f64 = (0..4).map(|j| JAC[i * 4 + j] * xi[j]).sum();
            br[i] = alpha * xr[i] - beta * xi[i] - jr;
            bi[i] = alpha * xi[i] + beta * xr[i] - ji;
        }
        lu.solve(&mut br, &mut bi);
        for i in 0..4 {
            assert!(
                (br[i] - xr[i]).abs() < 1e-13 && (bi[i] - xi[i]).abs() < 1e-13,
                "component {i}: {} + {}i vs {} + {}i",
                br[i],
                bi[i],
                xr[i],
                xi[i]
            );
        }
        Ok(())
    }

    #[test]
    fn decoupled_components_are_solved_apart() -> Result<(), Singular> {
        // Component 1 is read by nobody (column 1 zero off the diagonal), like an energy
        // integral: it is factored apart, and the solution must equal the full solve.
        let jac = [2.0, 0.0, -1.0, 3.0, 0.5, 4.0, 1.0, 0.0, -2.0];
        let mut part = Partition::new(3);
        part.update(&jac);
        assert_eq!(
            (part.main.clone(), part.trailing.clone()),
            (vec![0, 2], vec![1])
        );
        split_solves_equal_full_ones(&jac, &part, &[1.0, -2.0, 0.5], &[0.3, 0.0, -1.0])?;
        Ok(())
    }

    /// Factors s·I − J (s = 3) and (3 + 1.5i)·I − J once whole and once through `part`, and
    /// checks that both give the same solutions of (b_re) and (b_re + i b_im): two elimination
    /// orders of a well-conditioned small system, a few ulps apart.
    fn split_solves_equal_full_ones(
        jac: &[f64],
        part: &Partition,
        b_re: &[f64],
        b_im: &[f64],
    ) -> Result<(), Singular> {
        let n = b_re.len();
        let (mut full, mut split) = (RealLu::new(n), RealLu::new(n));
        full.factor(3.0, jac, &Partition::new(n))?;
        split.factor(3.0, jac, part)?;
        let (mut a, mut b) = (b_re.to_vec(), b_re.to_vec());
        full.solve(&mut a);
        split.solve(&mut b);
        let (mut cf, mut cs) = (ComplexLu::new(n), ComplexLu::new(n));
        cf.factor(3.0, 1.5, jac, &Partition::new(n))?;
        cs.factor(3.0, 1.5, jac, part)?;
        let (mut ar, mut ai) = (b_re.to_vec(), b_im.to_vec());
        let (mut br, mut bi) = (ar.clone(), ai.clone());
        cf.solve(&mut ar, &mut ai);
        cs.solve(&mut br, &mut bi);
        for k in 0..n {
            assert!(
                (a[k] - b[k]).abs() < 1e-15,
                "real x{k}: {} vs {}",
                a[k],
                b[k]
            );
            assert!(
                (ar[k] - br[k]).abs() < 1e-15 && (ai[k] - bi[k]).abs() < 1e-15,
                "complex x{k}: {} + {}i vs {} + {}i",
                ar[k],
                ai[k],
                br[k],
                bi[k]
            );
        }
        Ok(())
    }

    #[test]
    fn leading_and_trailing_components_are_solved_apart() -> Result<(), Singular> {
        // Component 1 depends on nothing (row 1 zero off the diagonal), like a stored impact
        // velocity, and component 3 is read by nobody (column 3 zero off the diagonal): both
        // are taken out of the factored block, and the solution must equal the full solve.
        let jac = [
            2.0, 1.5, -1.0, 0.0, //
            0.0, -0.5, 0.0, 0.0, //
            1.0, -2.0, -2.0, 0.0, //
            0.5, 3.0, 1.0, 0.7,
        ];
        let mut part = Partition::new(4);
        part.update(&jac);
        assert_eq!(
            (
                part.leading.clone(),
                part.main.clone(),
                part.trailing.clone()
            ),
            (vec![1], vec![0, 2], vec![3])
        );
        split_solves_equal_full_ones(&jac, &part, &[1.0, -2.0, 0.5, 0.25], &[0.3, 0.0, -1.0, 2.0])?;
        let mut split = RealLu::new(4);
        // A leading component whose diagonal vanishes (s = J_11) is a singular matrix.
        assert!(split.factor(-0.5, &jac, &part).is_err());
        Ok(())
    }

    #[test]
    fn singular_matrix_is_reported() {
        // s·I − J = 0 for J = I, s = 1.
        let jac = [1.0, 0.0, 0.0, 1.0];
        assert_eq!(
            RealLu::new(2).factor(1.0, &jac, &Partition::new(2)),
            Err(Singular { column: 0 })
        );
        assert_eq!(
            ComplexLu::new(2).factor(1.0, 0.0, &jac, &Partition::new(2)),
            Err(Singular { column: 0 })
        );
    }
}
