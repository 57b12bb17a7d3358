//! How well a set of independent coordinates parametrises the motion, judged from the velocity
//! transformation B of the current partition in O(n f²), for the repartition event and the
//! choice of a new partition.
//!
//! In scaled coordinates (angles as arc lengths L·φ, as in the partition's choice), let B̃
//! (n × f) be the velocity transformation of the current partition I: q̃̇ = B̃ q̃̇_I, B̃_I = 1, so
//! its columns span the velocities the constraints allow (the tangent space of the motion's
//! branch), and N = B̃ (B̃ᵀB̃)^(−1/2) is an orthonormal basis of it. For any set J of f
//! coordinates,
//!
//! ```text
//!     ρ(J) = |det N_J| = |det B̃_J| / det(B̃ᵀB̃)^(1/2),    ρ(I) = det(B̃ᵀB̃)^(−1/2)
//! ```
//!
//! is the part of the tangent space that the coordinates J see (the product of the cosines of
//! the principal angles between it and span{e_j : j ∈ J}), with ρ ∈ [0, 1] and Σ_J ρ(J)² = 1
//! (Cauchy–Binet). J parametrises the motion if and only if ρ(J) > 0.
//!
//! **Why it ranks dependent blocks.** Where Φ̃_q (m × n) has full rank, write Φ̃_q = R Qᵀ with
//! Q (n × m) orthonormal: [Q N] is orthogonal, and for complementary sets D (m rows) and J
//! (f rows) its blocks Q_D and N_J have the same singular values other than 1 (the CS
//! decomposition, ref. 1 §2.5.4), so |det Φ̃_D| = |det R| · |det Q_D| = |det R| · ρ(J). The ratio
//! of ρ between two partitions is the ratio of |det| of their dependent blocks, obtained without
//! forming any m × m block: the best block by volume is the complement of the J that maximises
//! |det B̃_J|. Where Φ_q loses rank (a parallelogram in its flat position) every dependent
//! block is singular, but B̃ stays bounded along the branch the motion is on, and ρ still says
//! whether J parametrises that branch, which is what the integration needs there.
//!
//! [`volumes`] finds J* by Gaussian elimination with complete pivoting of B̃ᵀ (f × n, the greedy
//! maximum-volume choice, ref. 2; for f = 1 exactly the coordinate of largest |B̃_c|), and returns
//! ρ(I) and ρ(J*). For f = 1 the repartition event ρ(I) − τ ρ(J*) falls through zero where some
//! coordinate starts moving 1/τ times faster (in scaled units) than the independent one.
//!
//! # References
//! 1. G. H. Golub, C. F. Van Loan, *Matrix Computations*, 4th ed., Johns Hopkins, 2013.
//! 2. S. A. Goreinov, I. V. Oseledets, D. V. Savostyanov, E. E. Tyrtyshnikov,
//!    N. L. Zamarashkin, How to find a good submatrix, in *Matrix Methods: Theory, Algorithms
//!    and Applications*, World Scientific, 2010, 247–256.

use crate::linalg::dense_lu;

/// ρ of the current independent coordinates and of the best set found (see the module
/// documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Volumes {
    /// ρ(I) of the current partition, in (0, 1].
    pub current: f64,
    /// ρ(J*) of the best set found, in (0, 1]; ≥ `current` for f = 1.
    pub best: f64,
}

/// Scratch for [`volumes`], sized once.
#[derive(Debug, Clone)]
pub struct VolumeWork {
    /// B̃ᵀ (f × n, row-major): row k is B̃'s column of independent coordinate k.
    pub bt: Vec<f64>,
    gram: Vec<f64>,
    gram_piv: Vec<usize>,
    /// After [`volumes`]: the best set J* (f coordinate indices).
    pub best: Vec<usize>,
    col_perm: Vec<usize>,
}

impl VolumeWork {
    /// Buffers for f independent among n coordinates.
    pub fn new(f: usize, n: usize) -> Self {
        VolumeWork {
            bt: vec![0.0; f * n],
            gram: vec![0.0; f * f],
            gram_piv: vec![0; f],
            best: vec![0; f],
            col_perm: vec![0; n],
        }
    }
}

/// ρ(I) and ρ(J*) from B̃ᵀ in `work.bt` (f × n, destroyed); J* into `work.best`. `None` where
/// B̃ is not finite.
pub fn volumes(work: &mut VolumeWork, f: usize, n: usize) -> Option<Volumes> {
    if f == 0 {
        // Nothing to parametrise: every (empty) set sees all of a zero-dimensional space.
        return Some(Volumes {
            current: 1.0,
            best: 1.0,
        });
    }
    let bt = &mut work.bt[..f * n];
    if !bt.iter().all(|x| x.is_finite()) {
        return None;
    }
    // B̃ᵀB̃ ≥ 1 (B̃ holds the identity in the rows of I), so its LU has no small pivot.
    for a in 0..f {
        for b in 0..=a {
            let dot: f64 = bt[a * n..a * n + n]
                .iter()
                .zip(&bt[b * n..b * n + n])
                .map(|(x, y)| x * y)
                .sum();
            work.gram[a * f + b] = dot;
            work.gram[b * f + a] = dot;
        }
    }
    dense_lu::factor(&mut work.gram, f, &mut work.gram_piv).ok()?;
    let det: f64 = (0..f).map(|k| work.gram[k * f + k].abs()).product();
    let current = 1.0 / det.sqrt();
    let chosen = dense_lu::complete_pivoting(bt, f, n, &mut work.best, &mut work.col_perm);
    let best = chosen.volume * current;
    (current.is_finite() && best.is_finite()).then_some(Volumes { current, best })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// f = 1: ρ(I) = 1/|B̃|, and the best coordinate is the one of largest |B̃_c|.
    #[test]
    fn one_degree_of_freedom_picks_the_fastest_coordinate() {
        let b = [1.0, -3.0, 0.5, 2.0];
        let mut w = VolumeWork::new(1, 4);
        w.bt.copy_from_slice(&b);
        let v = volumes(&mut w, 1, 4).unwrap_or_else(|| panic!("finite"));
        let norm = b.iter().map(|x| x * x).sum::<f64>().sqrt();
        assert!((v.current - 1.0 / norm).abs() < 1e-15, "{v:?}");
        assert!((v.best - 3.0 / norm).abs() < 1e-15, "{v:?}");
        assert_eq!(w.best, vec![1]);
    }

    /// ρ(J) = |det B̃_J| ρ(I) does not depend on the partition I it is computed from: the ρ(J)
    /// of every pair J of a 2-dimensional subspace of R⁵, found from I = {0, 1}, is the ρ(I)
    /// computed from J's own B̃; they sum in squares to 1; and the greedy best lies between
    /// the current partition's and the largest.
    #[test]
    fn volumes_do_not_depend_on_the_partition_they_are_computed_from() {
        // A basis T (5 × 2) of the subspace, row-major.
        let t = [0.3, -1.1, 2.0, 0.4, -0.7, 0.9, 0.1, 1.5, 1.2, -0.2];
        let n = 5;
        // B̃ᵀ for independent set {a, b}: (T T_{ab}⁻¹)ᵀ.
        let bt_of = |a: usize, b: usize| -> Vec<f64> {
            let (p, q, r, s) = (t[2 * a], t[2 * a + 1], t[2 * b], t[2 * b + 1]);
            let det = p * s - q * r;
            let inv = [s / det, -q / det, -r / det, p / det];
            let mut bt = vec![0.0; 2 * n];
            for c in 0..n {
                let (x, y) = (t[2 * c], t[2 * c + 1]);
                bt[c] = x * inv[0] + y * inv[2];
                bt[n + c] = x * inv[1] + y * inv[3];
            }
            bt
        };
        let volumes_of = |a: usize, b: usize| -> Volumes {
            let mut w = VolumeWork::new(2, n);
            w.bt = bt_of(a, b);
            volumes(&mut w, 2, n).unwrap_or_else(|| panic!("finite"))
        };
        let from_01 = volumes_of(0, 1);
        let bt = bt_of(0, 1);
        let (mut sum, mut largest) = (0.0, 0.0_f64);
        for a in 0..n {
            for b in a + 1..n {
                let own = volumes_of(a, b).current;
                let det = bt[a] * bt[n + b] - bt[b] * bt[n + a];
                let via_01 = det.abs() * from_01.current;
                assert!(
                    (own - via_01).abs() < 1e-12,
                    "ρ({a}, {b}): {own} vs {via_01}"
                );
                sum += own * own;
                largest = largest.max(own);
            }
        }
        assert!((sum - 1.0).abs() < 1e-12, "Σρ² = {sum}");
        assert!(
            from_01.best >= from_01.current && from_01.best <= largest + 1e-12,
            "{from_01:?}, largest {largest}"
        );
    }

    #[test]
    fn no_freedom_and_non_finite_input() {
        let mut w = VolumeWork::new(0, 3);
        assert_eq!(
            volumes(&mut w, 0, 3),
            Some(Volumes {
                current: 1.0,
                best: 1.0
            })
        );
        let mut w = VolumeWork::new(1, 2);
        w.bt.copy_from_slice(&[1.0, f64::NAN]);
        assert_eq!(volumes(&mut w, 1, 2), None);
    }
}
