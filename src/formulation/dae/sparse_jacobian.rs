//! The DAE's Jacobian in sparse augmented form ([`SparseJacobian`]): the same derivatives as
//! `dae/jacobian.rs`, before the constraint solve instead of after it.
//!
//! The dense Jacobian's q̈ rows are full for a connected linkage (q̈ depends on every body
//! through λ = A⁻¹ b), and it costs one constraint solve per column: O(n²) entries and
//! O(n² m) work. Kept as unknowns, z = (q̈, λ) follow from y = (q, q̇, δ̇⁽⁻⁾,
//! energy) by the two equations the right-hand side solves (module documentation of
//! [`super`]), scaled by M⁻¹ so that their rows are accelerations (m/s², rad/s²),
//!
//! ```text
//!     k₁ = q̈ + M⁻¹ (Φ_qᵀ λ − Q(t, q, q̇, δ̇⁽⁻⁾)) = 0
//!     k₂ = Φ_q q̈ − Δ λ − (γ − 2α Φ̇ − β² Φ) = 0
//! ```
//!
//! with Δ = diag(Δ_k) the shifts of the regularised pivots at q, held fixed as the dense
//! Jacobian holds them; and g = (q̇, q̈, 0, 0). Every block of 𝒥 = ∂(g, k)/∂(y, z) is then local:
//!
//! | rows \ columns | q | q̇ | δ̇⁽⁻⁾ | q̈ | λ |
//! |---|---|---|---|---|---|
//! | q | | I | | | |
//! | q̇ | | | | I | |
//! | k₁ | M⁻¹ (Σ λ_k H_k − ∂Q/∂q) | −M⁻¹ ∂Q/∂q̇ | −M⁻¹ ∂Q/∂δ̇⁽⁻⁾ | I | M⁻¹ Φ_qᵀ |
//! | k₂ | −(∂c/∂q − H q̈) | −∂c/∂q̇ | | Φ_q | −Δ |
//!
//! with H_k = ∂²Φ_k/∂q² and c = γ − 2αΦ̇ − β²Φ, as in `dae/jacobian.rs`. The structural
//! non-zeros, fixed for the run: each constraint row couples the coordinates of its (at most)
//! two bodies; each clearance joint the coordinates and speeds of its journal's and bearing's
//! bodies and its stored impact velocity; each force element the coordinates and speeds of the
//! bodies it acts on or reads ([`AppliedForces::element_bodies`](crate::mechanics::AppliedForces::element_bodies)).
//! The constraint and contact terms are analytic, as in the dense Jacobian; the force elements
//! by central differences of each element's own part of Q over the columns it reads (the dense
//! Jacobian differences the whole Q over every column). Eliminating z reproduces the dense
//! Jacobian to round-off (`dae/jacobian/tests.rs`). Cost: one right-hand side, the constraint
//! curvature, and O(1) work per row, contact and element: linear in the size of the linkage.
//! Measured on the N-four-bar chain at its initial state (plain loop, loaded 2-core machine):
//! 20 µs against 0.91 ms for the dense Jacobian at 10 loops (21 bodies), 76 µs against 48 ms at
//! 40 loops (81 bodies).

use super::{Dae, sin_cos_of};
use crate::formulation::sparse_jacobian::{Scatter, SparseJacobian, SparsePattern};
use crate::formulation::{Formulation, FormulationError};
use crate::mechanics::constraints::{ConstraintEval, RowCurvature};
use crate::model::Frame;

use super::jacobian::{local_columns, row_terms};

/// Relative increment of the central differences of a force element (about u^{1/3}, as in the
/// dense Jacobian).
const FORCE_REL: f64 = 6e-6;

/// What the values need besides the pattern: built once, at the first call.
#[derive(Debug, Clone)]
pub(super) struct SparseLayout {
    pattern: SparsePattern,
    /// The coordinates (3 per body) of each force element's bodies.
    element_coordinates: Vec<Vec<usize>>,
}

impl Dae {
    /// Index of the first algebraic unknown (q̈₀) in the augmented numbering: n_states.
    fn z_start(&self) -> usize {
        self.n_states()
    }

    /// The layout of 𝒥 (module documentation), built on the first call and kept.
    pub(super) fn sparse_layout(&self) -> &SparseLayout {
        self.sparse.get_or_init(|| self.build_layout())
    }

    fn build_layout(&self) -> SparseLayout {
        let n = self.n_coordinates();
        let ny = self.n_states();
        let (za, zl) = (ny, ny + n);
        let dim = ny + n + self.active.len();
        let mut entries: Vec<(usize, usize)> = (0..dim).map(|i| (i, i)).collect();
        for c in 0..n {
            entries.push((c, n + c));
            entries.push((n + c, za + c));
        }
        // The rows' bodies do not change with q: read them at the assembled state.
        let q0 = &self.assembly.q;
        let mut ce = ConstraintEval::with_rows(self.constraints.n_rows());
        self.constraints
            .evaluate_into(0.0, q0, &self.assembly.v, &sin_cos_of(q0), &mut ce);
        for (i, &k) in self.active.iter().enumerate() {
            let row = &ce.rows[k];
            let cols: Vec<usize> = local_columns(row.body_a, row.body_b)
                .into_iter()
                .flatten()
                .collect();
            for &c in &cols {
                entries.push((za + c, zl + i));
                entries.push((zl + i, za + c));
                entries.push((zl + i, c));
                entries.push((zl + i, n + c));
                for &p in &cols {
                    entries.push((za + c, p));
                }
            }
        }
        let mut couple = |coords: &[usize], extra: Option<usize>| {
            for &c in coords {
                for &p in coords {
                    entries.push((za + c, p));
                    entries.push((za + c, n + p));
                }
                if let Some(col) = extra {
                    entries.push((za + c, col));
                }
            }
        };
        for (k, site) in self.contacts.sites().iter().enumerate() {
            let coords = body_coordinates(
                [site.journal.frame, site.bearing.frame]
                    .into_iter()
                    .filter_map(|f| match f {
                        Frame::Body(id) => Some(id.0),
                        Frame::Ground => None,
                    }),
            );
            couple(&coords, Some(2 * n + k));
        }
        let first = self.contacts.sites().len();
        for (i, corner) in self.contacts.corners().iter().enumerate() {
            let coords = body_coordinates(corner.bodies());
            couple(&coords, Some(2 * n + first + i));
        }
        let element_coordinates: Vec<Vec<usize>> = (0..self.applied.n_elements())
            .map(|e| body_coordinates(self.applied.element_bodies(e)))
            .collect();
        for coords in &element_coordinates {
            couple(coords, None);
        }
        SparseLayout {
            pattern: SparsePattern::from_entries(dim, entries),
            element_coordinates,
        }
    }

    /// Writes 𝒥 at (t, y) over `layout` into `values`; returns the entries written outside the
    /// pattern (0 unless the pattern is wrong).
    pub(super) fn augmented_jacobian(
        &self,
        t: f64,
        y: &[f64],
        layout: &SparseLayout,
        values: &mut [f64],
    ) -> Result<usize, FormulationError> {
        let n = self.n_coordinates();
        let ny = self.n_states();
        if y.len() != ny || values.len() != layout.pattern.nnz() {
            return Err(FormulationError::Unsupported {
                formulation: "DAE".into(),
                reason: format!(
                    "sparse Jacobian with {} values and a state of length {} for {ny} states (expected {} values)",
                    values.len(),
                    y.len(),
                    layout.pattern.nnz()
                ),
            });
        }
        let (za, zl) = (self.z_start(), self.z_start() + n);
        let (q, v) = (&y[..n], &y[n..2 * n]);
        let sin_cos = sin_cos_of(q);
        let mut acc = vec![0.0; n];
        let mut work = self.work.borrow_mut();
        self.accelerations_into(t, y, &mut acc, &mut work)?;
        let ce = &work.constraints;
        let mut curvature = vec![RowCurvature::default(); self.constraints.n_rows()];
        self.constraints
            .curvature_into(q, v, &sin_cos, &mut curvature);
        let im = &self.inv_mass;

        let mut out = Scatter::new(&layout.pattern, values);
        for c in 0..n {
            out.add(c, n + c, 1.0);
            out.add(n + c, za + c, 1.0);
            out.add(za + c, za + c, 1.0);
        }
        let shifts = work.schur.regularisation();
        for (i, &k) in self.active.iter().enumerate() {
            let terms = row_terms(&ce.rows[k], &curvature[k], &acc, v, self.baumgarte);
            let h = &curvature[k].hessian;
            let lambda = work.lambda[i];
            out.add(zl + i, zl + i, -shifts.get(i).copied().unwrap_or(0.0));
            for (l, cl) in terms.cols.iter().enumerate() {
                let Some(cl) = *cl else { continue };
                let jac_l = terms.jac[l];
                out.add(za + cl, zl + i, im[cl] * jac_l);
                out.add(zl + i, za + cl, jac_l);
                out.add(zl + i, cl, -terms.c_q[l]);
                out.add(zl + i, n + cl, -terms.c_v[l]);
                for (p, cp) in terms.cols.iter().enumerate() {
                    if let Some(cp) = cp {
                        out.add(za + cl, *cp, im[cl] * lambda * h[l][p]);
                    }
                }
            }
        }
        drop(work);
        self.contact_force_derivatives(y, &sin_cos, &mut |c, col, d| {
            out.add(za + c, col, -im[c] * d);
        });
        if !layout.element_coordinates.is_empty() {
            self.element_force_derivatives(t, y, layout, &mut |c, col, d| {
                out.add(za + c, col, -im[c] * d);
            });
        }
        Ok(out.missed())
    }

    /// Hands ∂Q/∂(q, q̇) of each force element to `add(row, column, value)` (row a coordinate,
    /// column a state), by central differences of the element's own part of Q over the
    /// coordinates and speeds of its bodies (increment [`FORCE_REL`]·max(|y_j|, 1)).
    fn element_force_derivatives(
        &self,
        t: f64,
        y: &[f64],
        layout: &SparseLayout,
        add: &mut impl FnMut(usize, usize, f64),
    ) {
        let n = self.n_coordinates();
        let mut state = y[..2 * n].to_vec();
        let mut sin_cos = sin_cos_of(&y[..n]);
        let (mut plus, mut minus) = (vec![0.0; n], vec![0.0; n]);
        for (e, coords) in layout.element_coordinates.iter().enumerate() {
            for col in coords.iter().flat_map(|&c| [c, n + c]) {
                let x = state[col];
                let h = FORCE_REL * x.abs().max(1.0);
                for (sign, out) in [(1.0, &mut plus), (-1.0, &mut minus)] {
                    state[col] = x + sign * h;
                    if col % 3 == 2 && col < n {
                        sin_cos[col / 3] = state[col].sin_cos();
                    }
                    for &c in coords {
                        out[c] = 0.0;
                    }
                    let (q, v) = state.split_at(n);
                    self.applied.add_element_into(e, t, q, v, &sin_cos, out);
                }
                state[col] = x;
                if col % 3 == 2 && col < n {
                    sin_cos[col / 3] = x.sin_cos();
                }
                for &c in coords {
                    add(c, col, (plus[c] - minus[c]) / (2.0 * h));
                }
            }
        }
    }
}

/// The coordinates 3b, 3b + 1, 3b + 2 of each body b.
fn body_coordinates(bodies: impl IntoIterator<Item = usize>) -> Vec<usize> {
    bodies
        .into_iter()
        .flat_map(|b| [3 * b, 3 * b + 1, 3 * b + 2])
        .collect()
}

impl SparseJacobian for Dae {
    /// q̈ (3 per body), then λ of the active constraint rows.
    fn n_algebraic(&self) -> usize {
        self.n_coordinates() + self.active.len()
    }

    fn jacobian_pattern(&self) -> SparsePattern {
        self.sparse_layout().pattern.clone()
    }

    fn jacobian_values(
        &self,
        t: f64,
        y: &[f64],
        values: &mut [f64],
    ) -> Result<usize, FormulationError> {
        let missed = self.augmented_jacobian(t, y, self.sparse_layout(), values)?;
        debug_assert_eq!(missed, 0, "the pattern holds every entry written");
        Ok(0)
    }
}
