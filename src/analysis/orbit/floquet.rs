//! Which states are the unknowns of the shooting, and the Floquet multipliers: the
//! eigenvalues of the monodromy matrix restricted to them.
//!
//! A bookkeeping state (a stored impact velocity, out of error control) is *inactive* over a
//! period when nothing else depends on it: its column of the monodromy matrix M is zero off
//! the diagonal. That is exact, not a threshold: while a joint is free its stored velocity
//! enters no equation (the analytic Jacobian has a zero column), and an impact or a separation
//! overwrites it (the saltation matrix's column is zero). After permuting the inactive states
//! last, M = [[M_AA, 0], [M_IA, D]] with D diagonal, so the spectrum of M is that of M_AA
//! together with the D_jj (0 when the state was overwritten, 1 when it never was): those are
//! the trivial multipliers. A stored velocity of a joint that is in contact at the section is
//! *active* (the contact force depends on it until the joint separates), and it is a true
//! coordinate of the map and an unknown of the shooting. If that joint separates within the
//! period, the separation's saltation matrix has a zero row (the velocity is cleared): M then
//! factors through a state with that component 0, has rank one less, and one of the
//! eigenvalues of M_AA is 0 up to rounding. It is trivial too ([`split_trivial`]).
//!
//! A stored velocity of a joint that stays in contact over the whole period is read all along
//! but never overwritten: its row of M is exactly e_jᵀ (its rate is 0 and no event touches it),
//! so P(x)_j = x_j whatever x is, and its multiplier is exactly 1. The periodic orbits then
//! form a family that this value parameterises (the contact law's damping depends on the
//! velocity of the impact that started the contact, however long ago): it is a parameter of
//! the orbit, kept at the guess's value, not an unknown, and its multiplier is trivial. As an
//! unknown it would make M − I singular.

use nalgebra::DMatrix;

/// The unknowns of the shooting: every error-controlled state, and every bookkeeping state on
/// which M has a nonzero off-diagonal entry in its column, unless the period leaves it as it
/// was (module documentation).
pub fn active_states(monodromy: &[f64], controlled: &[bool]) -> Vec<usize> {
    let n = controlled.len();
    let read = |j: usize| (0..n).any(|i| i != j && monodromy[i * n + j] != 0.0);
    // Its row is e_j: no event of the period overwrote it (a joint in contact all along).
    let kept = |j: usize| {
        monodromy[j * n + j] == 1.0 && (0..n).all(|k| k == j || monodromy[j * n + k] == 0.0)
    };
    (0..n)
        .filter(|&j| controlled[j] || (read(j) && !kept(j)))
        .collect()
}

/// M restricted to the states `active` (rows and columns), as a matrix.
pub fn restricted(monodromy: &[f64], n: usize, active: &[usize]) -> DMatrix<f64> {
    let m = active.len();
    DMatrix::from_fn(m, m, |a, b| monodromy[active[a] * n + active[b]])
}

/// Eigenvalues of `m` as (re, im), by decreasing modulus.
pub fn multipliers(m: &DMatrix<f64>) -> Vec<[f64; 2]> {
    let mut mu: Vec<[f64; 2]> = m
        .clone()
        .complex_eigenvalues()
        .iter()
        .map(|z| [z.re, z.im])
        .collect();
    mu.sort_by(|a, b| b[0].hypot(b[1]).total_cmp(&a[0].hypot(a[1])));
    mu
}

/// Splits the eigenvalues `mu` of M_AA (by decreasing modulus) into the nontrivial ones and
/// the count of trivial ones: one per active bookkeeping state that an event of the period
/// cleared, each the smallest remaining eigenvalue, provided its modulus is below
/// [`ZERO_MULTIPLIER`] (a structural zero; module documentation). A larger one is kept.
pub fn split_trivial(mut mu: Vec<[f64; 2]>, cleared_active: usize) -> (Vec<[f64; 2]>, usize) {
    let mut removed = 0;
    while removed < cleared_active {
        match mu.last() {
            Some(z) if z[0].hypot(z[1]) < ZERO_MULTIPLIER => {
                mu.pop();
                removed += 1;
            }
            _ => break,
        }
    }
    (mu, removed)
}

/// Modulus below which an eigenvalue expected to be a structural zero is taken as one: the
/// rounding of M's entries (finite-difference saltation rows, about 1e-10 relative) leaves
/// it near 1e-9 on the reference four-bar, while the smallest physical multipliers found there
/// are near 1e-5.
pub const ZERO_MULTIPLIER: f64 = 1e-7;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_overwritten_bookkeeping_state_is_trivial_and_an_active_one_is_not() {
        // States (x, v, s): s bookkeeping. Column 2 zero off the diagonal: inactive.
        let m = [0.5, 0.1, 0.0, -0.2, 0.3, 0.0, 0.7, 0.4, 0.0];
        assert_eq!(active_states(&m, &[true, true, false]), vec![0, 1]);
        // The same with s feeding x: active.
        let m = [0.5, 0.1, 0.2, -0.2, 0.3, 0.0, 0.7, 0.4, 0.0];
        assert_eq!(active_states(&m, &[true, true, false]), vec![0, 1, 2]);
    }

    #[test]
    fn a_bookkeeping_state_that_the_period_leaves_as_it_was_is_a_parameter() {
        // s feeds x, and its row is e_3: kept, not an unknown.
        let m = [0.5, 0.1, 0.2, -0.2, 0.3, 0.0, 0.0, 0.0, 1.0];
        assert_eq!(active_states(&m, &[true, true, false]), vec![0, 1]);
        // The same s overwritten from x by an event of the period: an unknown.
        let m = [0.5, 0.1, 0.2, -0.2, 0.3, 0.0, 0.4, 0.0, 0.0];
        assert_eq!(active_states(&m, &[true, true, false]), vec![0, 1, 2]);
    }

    #[test]
    fn multipliers_of_a_rotation_are_a_conjugate_pair_on_the_circle() {
        let (s, c) = 0.3f64.sin_cos();
        let m = DMatrix::from_row_slice(2, 2, &[0.5 * c, -0.5 * s, 0.5 * s, 0.5 * c]);
        let mu = multipliers(&m);
        assert_eq!(mu.len(), 2);
        for z in &mu {
            assert!((z[0].hypot(z[1]) - 0.5).abs() < 1e-15, "{z:?}");
            assert!((z[1].abs() - 0.5 * s).abs() < 1e-15, "{z:?}");
        }
    }
}
