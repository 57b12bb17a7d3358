//! Dense LU factorisations with partial pivoting of the two Newton matrices of Radau IIA:
//! the real E₁ = γ̂/h·I − J and the complex E₂ = (α̂ + iβ̂)/h·I − J (n×n, row-major).
//!
//! Hand-written for the sizes met here (n = 4 to ~40): the buffers are allocated once, and
//! factorising or solving allocates nothing. Complex numbers are kept as separate real and
//! imaginary arrays.

/// The matrix became (numerically) singular: a zero pivot in column `column`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Singular {
    /// Column of the zero pivot.
    pub column: usize,
}

/// LU factors of s·I − J for real s, with row pivots.
#[derive(Debug, Clone)]
pub(super) struct RealLu {
    n: usize,
    lu: Vec<f64>,
    piv: Vec<usize>,
}

impl RealLu {
    /// Buffers for n×n matrices.
    pub(super) fn new(n: usize) -> Self {
        RealLu {
            n,
            lu: vec![0.0; n * n],
            piv: vec![0; n],
        }
    }

    /// Factorises s·I − J (J row-major, n²).
    pub(super) fn factor(&mut self, s: f64, jac: &[f64]) -> Result<(), Singular> {
        let n = self.n;
        debug_assert_eq!(jac.len(), n * n, "Jacobian buffer is allocated with n²");
        for (o, &j) in self.lu.iter_mut().zip(jac) {
            *o = -j;
        }
        for i in 0..n {
            self.lu[i * n + i] += s;
        }
        let a = &mut self.lu;
        for k in 0..n {
            let mut p = k;
            let mut best = a[k * n + k].abs();
            for i in k + 1..n {
                let v = a[i * n + k].abs();
                if v > best {
                    best = v;
                    p = i;
                }
            }
            self.piv[k] = p;
            // A NaN pivot (from a NaN Jacobian) fails this test too.
            if best.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                return Err(Singular { column: k });
            }
            if p != k {
                for j in 0..n {
                    a.swap(k * n + j, p * n + j);
                }
            }
            let inv = 1.0 / a[k * n + k];
            for i in k + 1..n {
                let m = a[i * n + k] * inv;
                a[i * n + k] = m;
                if m != 0.0 {
                    for j in k + 1..n {
                        a[i * n + j] -= m * a[k * n + j];
                    }
                }
            }
        }
        Ok(())
    }

    /// Solves (s·I − J) x = b in place.
    pub(super) fn solve(&self, b: &mut [f64]) {
        let n = self.n;
        debug_assert_eq!(b.len(), n, "right-hand sides are allocated with n");
        let a = &self.lu;
        // Whole rows (multipliers included) were swapped while factorising, so all row
        // interchanges are applied to b first (as LAPACK's getrs does).
        for k in 0..n {
            let p = self.piv[k];
            if p != k {
                b.swap(k, p);
            }
        }
        for k in 0..n {
            let bk = b[k];
            for i in k + 1..n {
                b[i] -= a[i * n + k] * bk;
            }
        }
        for k in (0..n).rev() {
            let mut s = b[k];
            for j in k + 1..n {
                s -= a[k * n + j] * b[j];
            }
            b[k] = s / a[k * n + k];
        }
    }
}

/// LU factors of (α + iβ)·I − J for real J, with row pivots.
#[derive(Debug, Clone)]
pub(super) struct ComplexLu {
    n: usize,
    re: Vec<f64>,
    im: Vec<f64>,
    piv: Vec<usize>,
}

impl ComplexLu {
    /// Buffers for n×n matrices.
    pub(super) fn new(n: usize) -> Self {
        ComplexLu {
            n,
            re: vec![0.0; n * n],
            im: vec![0.0; n * n],
            piv: vec![0; n],
        }
    }

    /// Factorises (α + iβ)·I − J (J row-major, n²).
    pub(super) fn factor(&mut self, alpha: f64, beta: f64, jac: &[f64]) -> Result<(), Singular> {
        let n = self.n;
        debug_assert_eq!(jac.len(), n * n, "Jacobian buffer is allocated with n²");
        for (o, &j) in self.re.iter_mut().zip(jac) {
            *o = -j;
        }
        self.im.fill(0.0);
        for i in 0..n {
            self.re[i * n + i] += alpha;
            self.im[i * n + i] = beta;
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
            for i in k + 1..n {
                let (ar, ai) = (re[i * n + k], im[i * n + k]);
                let mr = ar * inv_r - ai * inv_i;
                let mi = ar * inv_i + ai * inv_r;
                re[i * n + k] = mr;
                im[i * n + k] = mi;
                if mr != 0.0 || mi != 0.0 {
                    for j in k + 1..n {
                        let (br, bi) = (re[k * n + j], im[k * n + j]);
                        re[i * n + j] -= mr * br - mi * bi;
                        im[i * n + j] -= mr * bi + mi * br;
                    }
                }
            }
        }
        Ok(())
    }

    /// Solves ((α + iβ)·I − J)(x_re + i x_im) = b_re + i b_im in place.
    pub(super) fn solve(&self, b_re: &mut [f64], b_im: &mut [f64]) {
        let n = self.n;
        debug_assert!(b_re.len() == n && b_im.len() == n, "allocated with n");
        let (re, im) = (&self.re, &self.im);
        for k in 0..n {
            let p = self.piv[k];
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
        lu.factor(s, &JAC)?;
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
        lu.factor(alpha, beta, &JAC)?;
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
    fn singular_matrix_is_reported() {
        // s·I − J = 0 for J = I, s = 1.
        let jac = [1.0, 0.0, 0.0, 1.0];
        assert_eq!(
            RealLu::new(2).factor(1.0, &jac),
            Err(Singular { column: 0 })
        );
        assert_eq!(
            ComplexLu::new(2).factor(1.0, 0.0, &jac),
            Err(Singular { column: 0 })
        );
    }
}
