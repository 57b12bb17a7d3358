//! Coefficients of the 3-stage Radau IIA method (order 5) and of the transformation T that
//! block-diagonalises its inverse Butcher matrix, as in Hairer's `radau5.f` \[1, Sec. IV.8\].
//!
//! A⁻¹ has one real eigenvalue γ̂ and a complex pair α̂ ± iβ̂; with the columns of T
//!
//! T⁻¹ A⁻¹ T = Λ = [[γ̂, 0, 0], [0, α̂, −β̂], [0, β̂, α̂]],
//!
//! so the 3n×3n Newton matrix h⁻¹A⁻¹⊗I − I⊗J splits into the real n×n matrix γ̂/h·I − J and the
//! complex n×n matrix (α̂ + iβ̂)/h·I − J. The digits of T and T⁻¹ are Hairer's (20 significant
//! digits); the unit test checks Λ against A⁻¹ computed from the tableau.
//!
//! # References
//! 1. E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II*, 2nd ed., Springer,
//!    1996, Sec. IV.8 (Table 5.6 for the tableau, eq. (8.15)–(8.19) for T and the error
//!    estimate); code `radau5.f`.

/// √6.
const SQ6: f64 = 2.449_489_742_783_178;

/// Nodes c₁ = (4 − √6)/10, c₂ = (4 + √6)/10 (c₃ = 1).
pub(super) const C1: f64 = (4.0 - SQ6) / 10.0;
/// Node c₂.
pub(super) const C2: f64 = (4.0 + SQ6) / 10.0;
/// c₁ − 1.
pub(super) const C1M1: f64 = C1 - 1.0;
/// c₂ − 1.
pub(super) const C2M1: f64 = C2 - 1.0;
/// c₁ − c₂.
pub(super) const C1MC2: f64 = C1 - C2;

/// Error-estimate weights (e₁, e₂, e₃)/h of Hairer's embedded formula: −(13 + 7√6)/3,
/// (−13 + 7√6)/3, −1/3.
pub(super) const DD: [f64; 3] = [
    -(13.0 + 7.0 * SQ6) / 3.0,
    (-13.0 + 7.0 * SQ6) / 3.0,
    -1.0 / 3.0,
];

/// Eigenvalues of A⁻¹: γ̂ (real) and α̂ ± iβ̂, from the closed forms in `radau5.f`
/// (computed once; `f64::cbrt` is not `const`).
#[derive(Debug, Clone, Copy)]
pub(super) struct Eigen {
    /// Real eigenvalue γ̂ ≈ 3.6378.
    pub gamma: f64,
    /// Real part α̂ ≈ 2.6811 of the complex pair.
    pub alpha: f64,
    /// Imaginary part β̂ ≈ 3.0504 of the complex pair.
    pub beta: f64,
}

impl Eigen {
    /// γ̂ = 30/(6 + 81^{1/3} − 9^{1/3}); α̂ + iβ̂ = 1/(a + ib) with a = (12 − 81^{1/3} + 9^{1/3})/60,
    /// b = (81^{1/3} + 9^{1/3})·√3/60.
    pub(super) fn new() -> Self {
        let c81 = 81f64.cbrt();
        let c9 = 9f64.cbrt();
        let u1 = (6.0 + c81 - c9) / 30.0;
        let a = (12.0 - c81 + c9) / 60.0;
        let b = (c81 + c9) * 3f64.sqrt() / 60.0;
        let norm = a * a + b * b;
        Eigen {
            gamma: 1.0 / u1,
            alpha: a / norm,
            beta: b / norm,
        }
    }
}

/// T (row-major); T₃₂ = 1, T₃₃ = 0. Hairer's 20 digits are kept for the record.
#[allow(clippy::excessive_precision)]
pub(super) const T: [[f64; 3]; 3] = [
    [
        9.123_239_487_089_294_279_2e-2,
        -0.141_255_295_020_954_208_43,
        -3.002_919_410_514_742_449_2e-2,
    ],
    [
        0.241_717_932_707_107_018_96,
        0.204_129_352_293_799_931_99,
        0.382_942_112_757_261_937_79,
    ],
    [0.966_048_182_615_092_936_19, 1.0, 0.0],
];

/// T⁻¹ (row-major).
#[allow(clippy::excessive_precision)]
pub(super) const TI: [[f64; 3]; 3] = [
    [
        4.325_579_890_063_155_351_0,
        0.339_199_251_815_809_869_54,
        0.541_770_539_935_874_871_19,
    ],
    [
        -4.178_718_591_551_904_727_3,
        -0.327_682_820_761_062_387_08,
        0.476_623_554_500_550_451_96,
    ],
    [
        -0.502_872_634_945_786_875_95,
        2.571_926_949_855_605_429_2,
        -0.596_039_204_828_224_924_97,
    ],
];

/// Butcher matrix A of Radau IIA order 5 \[1, Table IV.5.6\] (row-major), for tests.
#[cfg(test)]
pub(super) fn butcher_a() -> [[f64; 3]; 3] {
    [
        [
            (88.0 - 7.0 * SQ6) / 360.0,
            (296.0 - 169.0 * SQ6) / 1800.0,
            (-2.0 + 3.0 * SQ6) / 225.0,
        ],
        [
            (296.0 + 169.0 * SQ6) / 1800.0,
            (88.0 + 7.0 * SQ6) / 360.0,
            (-2.0 - 3.0 * SQ6) / 225.0,
        ],
        [(16.0 - SQ6) / 36.0, (16.0 + SQ6) / 36.0, 1.0 / 9.0],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    type M3 = [[f64; 3]; 3];

    fn mul(a: &M3, b: &M3) -> M3 {
        let mut c = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                c[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
            }
        }
        c
    }

    fn inverse(a: &M3) -> M3 {
        let det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
            - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
        let mut inv = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                // Cofactor of (j, i) over det.
                let (r0, r1) = ((j + 1) % 3, (j + 2) % 3);
                let (c0, c1) = ((i + 1) % 3, (i + 2) % 3);
                inv[i][j] = (a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]) / det;
            }
        }
        inv
    }

    fn max_diff(a: &M3, b: &M3) -> f64 {
        let mut d: f64 = 0.0;
        for i in 0..3 {
            for j in 0..3 {
                d = d.max((a[i][j] - b[i][j]).abs());
            }
        }
        d
    }

    #[test]
    fn t_block_diagonalises_the_inverse_butcher_matrix() {
        let e = Eigen::new();
        let lambda = [
            [e.gamma, 0.0, 0.0],
            [0.0, e.alpha, -e.beta],
            [0.0, e.beta, e.alpha],
        ];
        let a_inv = inverse(&butcher_a());
        let got = mul(&TI, &mul(&a_inv, &T));
        // Entries of A⁻¹ are up to ~11 and T, T⁻¹ carry 20 digits: a few ulps of 11·4.
        let d = max_diff(&got, &lambda);
        assert!(d < 1e-13, "T⁻¹A⁻¹T − Λ: max |diff| = {d:e}; got {got:?}");
        let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let d = max_diff(&mul(&TI, &T), &identity);
        assert!(d < 1e-14, "T⁻¹T − I: max |diff| = {d:e}");
    }

    #[test]
    fn tableau_has_the_radau_iia_properties() {
        let a = butcher_a();
        let c = [C1, C2, 1.0];
        // Row sums are the nodes; the last row is b (stiffly accurate), and b sums to 1.
        for i in 0..3 {
            let s: f64 = a[i].iter().sum();
            assert!(
                (s - c[i]).abs() < 1e-15,
                "row {i}: Σa = {s} vs c = {}",
                c[i]
            );
        }
        let b_sum: f64 = a[2].iter().sum();
        assert!((b_sum - 1.0).abs() < 1e-15, "Σb = {b_sum}");
        // Quadrature order 5: Σ b_j c_j^{k−1} = 1/k for k = 1..5.
        for k in 1..=5 {
            let q: f64 = (0..3).map(|j| a[2][j] * c[j].powi(k - 1)).sum();
            let exact = 1.0 / f64::from(k);
            assert!((q - exact).abs() < 1e-15, "k = {k}: {q} vs {exact}");
        }
        let e = Eigen::new();
        // Independent closed forms (the eigenvalues of A⁻¹ as SciPy's `radau.py` writes them):
        // γ̂ = 3 + 3^{2/3} − 3^{1/3}, α̂ = 3 + (3^{1/3} − 3^{2/3})/2, β̂ = (3^{5/6} + 3^{7/6})/2.
        let (c3, c3sq) = (3f64.cbrt(), 3f64.cbrt().powi(2));
        let gamma = 3.0 + c3sq - c3;
        let alpha = 3.0 + 0.5 * (c3 - c3sq);
        let beta = 0.5 * (3f64.powf(5.0 / 6.0) + 3f64.powf(7.0 / 6.0));
        for (name, got, want) in [
            ("gamma", e.gamma, gamma),
            ("alpha", e.alpha, alpha),
            ("beta", e.beta, beta),
        ] {
            // Two roundings of cube roots of O(1) numbers: a few ulps of ~4.
            assert!((got - want).abs() < 1e-14, "{name}: {got} vs {want}");
        }
    }
}
