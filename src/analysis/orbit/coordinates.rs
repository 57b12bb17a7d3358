//! The shooting's coordinates for a formulation whose state is constrained (the DAE: Φ = 0 and
//! Φ̇ = 0, [`ConstrainedState`]).
//!
//! Such a state has 2m directions that the motion does not have: the DAE's coordinates and
//! velocities across its m constraint rows (the driven crank's angle among them). The shooting
//! therefore steps only in the directions a consistent state can move in, the null space of
//! ∂C/∂y over its unknowns, and makes every iterate consistent again before it integrates it;
//! the Floquet multipliers are the eigenvalues of Wᵀ M W, with W an orthonormal basis of that
//! null space. At an orbit the flow maps consistent directions at x to consistent directions
//! at P(x) = x, so Wᵀ M W is the monodromy of the motion itself, in coordinates of W: its
//! eigenvalues do not depend on the basis, and they are the reduced formulation's on the same
//! orbit (`tests/orbit_dae.rs`).

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use super::floquet::restricted;
use crate::analysis::AnalysisError;
use crate::formulation::{ConstrainedState, Formulation};

/// An orthonormal basis (columns) of the directions in which the unknowns `active` of the
/// consistent state y at t can move: the null space of ∂C/∂y restricted to `active`, in the
/// coordinates of `active` (|active| rows). `None` where `f` has no constrained state.
///
/// Errors: conditions that are dependent at (t, y) (a singular position at the section).
pub fn tangent_basis<F: Formulation>(
    f: &F,
    t: f64,
    y: &[f64],
    active: &[usize],
) -> Result<Option<DMatrix<f64>>, AnalysisError> {
    let Some(cs) = f.constrained_state() else {
        return Ok(None);
    };
    let r = cs.n_conditions();
    if r == 0 {
        return Ok(None);
    }
    let n = f.n_states();
    let mut jac = vec![0.0; r * n];
    cs.condition_jacobian(t, y, &mut jac)
        .map_err(|e| AnalysisError::invalid("orbit", e.to_string()))?;
    let c = DMatrix::from_fn(r, active.len(), |i, a| jac[i * n + active[a]]);
    // P = I − Cᵀ (C Cᵀ)⁻¹ C, the orthogonal projector onto the null space: eigenvalues 1 on it
    // and 0 across it, well apart however C is scaled.
    let dependent = || {
        AnalysisError::invalid(
            "orbit",
            format!(
                "the state's {r} constraint conditions are dependent at the section (t = {t} s: a singular position of the linkage); choose another section (`guess_from_turn`)"
            ),
        )
    };
    let gram = &c * c.transpose();
    let Some(inverse) = gram.cholesky().map(|ch| ch.inverse()) else {
        return Err(dependent());
    };
    let m = active.len();
    let projector = DMatrix::identity(m, m) - c.transpose() * inverse * &c;
    let eigen = SymmetricEigen::new(projector);
    let columns: Vec<DVector<f64>> = eigen
        .eigenvalues
        .iter()
        .enumerate()
        .filter(|(_, l)| **l > 0.5)
        .map(|(i, _)| eigen.eigenvectors.column(i).into_owned())
        .collect();
    if columns.len() + r != m {
        return Err(dependent());
    }
    if columns.is_empty() {
        return Ok(Some(DMatrix::zeros(m, 0)));
    }
    Ok(Some(DMatrix::from_columns(&columns)))
}

/// M with its block over `active` replaced by P M_AA P, P = W Wᵀ the orthogonal projector onto
/// the consistent directions W at (t, y), where `f` has a constrained state; returns W (None,
/// M unchanged, otherwise). P M_AA P acts as Wᵀ M_AA W on the consistent directions and as 0
/// across them, so a Newton step with it, (P M_AA P − I) Δ = −r, takes the consistent part
/// of Δ from Wᵀ M_AA W and removes the residual across them (the iterate is made consistent
/// anyway); its eigenvalues are Wᵀ M_AA W's and 2m zeros. For code written for M over the
/// unknowns (the continuation), which then needs no other change.
pub fn in_consistent_directions<F: Formulation>(
    f: &F,
    t: f64,
    y: &[f64],
    monodromy: &mut [f64],
    active: &[usize],
) -> Result<Option<DMatrix<f64>>, AnalysisError> {
    let Some(w) = tangent_basis(f, t, y, active)? else {
        return Ok(None);
    };
    let n = y.len();
    let m_aa = restricted(monodromy, n, active);
    let projector = &w * w.transpose();
    let projected = &projector * m_aa * &projector;
    for (a, &i) in active.iter().enumerate() {
        for (b, &j) in active.iter().enumerate() {
            monodromy[i * n + j] = projected[(a, b)];
        }
    }
    Ok(Some(w))
}

/// M_AA (M restricted to the unknowns) in the shooting's coordinates, and their number: M_AA
/// itself over the unknowns, or Wᵀ M_AA W over the consistent directions `basis` of a
/// constrained state. Its eigenvalues are the nontrivial Floquet multipliers (and the
/// structural zeros of [`super::floquet::split_trivial`]).
pub fn in_coordinates(m_aa: DMatrix<f64>, basis: Option<&DMatrix<f64>>) -> (DMatrix<f64>, usize) {
    match basis {
        None => {
            let k = m_aa.ncols();
            (m_aa, k)
        }
        Some(w) => (w.transpose() * m_aa * w, w.ncols()),
    }
}

/// Which states of `f` are angles ([`Formulation::angular_states`]).
pub fn angular_states<F: Formulation>(f: &F) -> Vec<bool> {
    let mut angular = vec![false; f.n_states()];
    f.angular_states(&mut angular);
    angular
}

/// The change `d` of a state over a period, less whole turns where the state is an angle.
pub fn less_whole_turns(angular: bool, d: f64) -> f64 {
    if angular && d.abs() > std::f64::consts::PI {
        d - std::f64::consts::TAU * (d / std::f64::consts::TAU).round()
    } else {
        d
    }
}

/// Makes y consistent at t where `f` has a constrained state (no change otherwise).
pub fn make_consistent<F: Formulation>(f: &F, t: f64, y: &mut [f64]) -> Result<(), AnalysisError> {
    match f.constrained_state() {
        Some(cs) => cs
            .make_consistent(t, y)
            .map_err(|e| AnalysisError::invalid("orbit", e.to_string())),
        None => Ok(()),
    }
}

/// Step-end corrections of the state that `f` has made so far (0 without a constrained state).
pub fn step_end_corrections<F: Formulation>(f: &F) -> usize {
    f.constrained_state()
        .map_or(0, ConstrainedState::step_end_corrections)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_formulation_without_conditions_keeps_its_states_as_coordinates() {
        struct Free;
        impl crate::formulation::NoStepHooks for Free {}
        impl Formulation for Free {
            fn n_states(&self) -> usize {
                2
            }
            fn initial_state(&self) -> Vec<f64> {
                vec![0.0; 2]
            }
            fn rhs(
                &self,
                _t: f64,
                y: &[f64],
                dy: &mut [f64],
            ) -> Result<(), crate::formulation::FormulationError> {
                dy[0] = y[1];
                dy[1] = -y[0];
                Ok(())
            }
        }
        assert!(
            tangent_basis(&Free, 0.0, &[0.0, 0.0], &[0, 1])
                .unwrap_or_else(|e| panic!("{e}"))
                .is_none()
        );
    }
}
