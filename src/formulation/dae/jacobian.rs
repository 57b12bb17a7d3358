//! Analytic Jacobian J = ∂f/∂y of the DAE's right-hand side (used by Radau5 through
//! [`Formulation::jacobian`](crate::formulation::Formulation::jacobian)): no RHS call.
//!
//! With y = (q, q̇, δ̇⁽⁻⁾, energy) and f = (q̇, q̈, 0, energy rates), the rows of q are (0 I 0),
//! those of the stored impact velocities zero, and the rows of q̈ follow from differentiating
//! the two equations that define it (module documentation of [`super`]),
//!
//! ```text
//!     M q̈ + Φ_qᵀ λ = Q(t, q, q̇, δ̇⁽⁻⁾),    Φ_q q̈ = c,   c = γ − 2α Φ̇ − β² Φ,
//! ```
//!
//! along a state component y_j:
//!
//! ```text
//!     M ∂q̈ + Φ_qᵀ ∂λ = r_j := ∂Q/∂y_j − (Σ_k λ_k H_k)·e_j          (q columns only)
//!     Φ_q ∂q̈        = s_j := ∂c/∂y_j − H_k q̈ · e_j, row by row    (q columns only)
//! ```
//!
//! with H_k = ∂²Φ_k/∂q² ([`RowCurvature`]), ∂c/∂q = ∂γ/∂q − 2α H v − β² Φ_q and
//! ∂c/∂q̇ = ∂γ/∂q̇ − 2α Φ_q (Φ_t depends on t only). So each column costs one solve with the
//! matrix A = S + diag(Δ) that the right-hand side factors too (S = Φ_q M⁻¹ Φ_qᵀ with its
//! regularised pivots, module documentation of [`super`]):
//! ∂λ = A⁻¹ (Φ_q M⁻¹ r_j − s_j), ∂q̈ = M⁻¹ (r_j − Φ_qᵀ ∂λ).
//!
//! This is the exact derivative of λ = A⁻¹ b with the shifts Δ_p held fixed. They also move
//! with q, through the pivots d_p they regularise, at the rate ∂Δ_p/∂d_p = −2μ_p³/(d_p + μ_p)³:
//! below 2e-12 wherever every pivot exceeds 1e-4 D_p (μ_p = 1e-8 D_p, D_p the row's scale),
//! that is everywhere but within about 1e-2 (relative) of a singular position. There the
//! term is left out: Radau5's Newton iteration, the Jacobian's only user, converges with it
//! (`tests/singular_parallelogram.rs` passes the flat positions with Radau5 at rtol down to
//! 1e-10), and computing it would need one extra solve with the leading block of the factor
//! per pivot.
//!
//! ∂Q/∂y: gravity and constant loads contribute nothing; the contact forces of each clearance
//! joint in contact exactly in their kinematics and by central differences of the scalar laws
//! alone ([`LawSlopes`], shared with the reduced formulation): with the journal centre
//! r_J = r_j + A_j s_J on body j and the bearing centre r_B on body b, ∂e/∂r_j = I,
//! ∂e/∂φ_j = perp(A_j s_J), ∂ė/∂φ_j = −φ̇_j A_j s_J, ∂ė/∂ṙ_j = I, ∂ė/∂φ̇_j = perp(A_j s_J),
//! ∂(R_J ω_J − R_B ω_B)/∂φ̇_j = R_J (the bearing's likewise with the signs and R_B), and the
//! moment arm's own turn ∂(A s × F)/∂φ = perp(A s) × F. The model's force elements (springs,
//! dampers, expression loads and torques, torque drivers), where there are any, by central
//! differences of the applied-force vector Q alone (cheap: no constraint solve).
//!
//! The energy rates (with [`DaeOptions::energy`](super::DaeOptions::energy)) get zero rows:
//! those states feed back into nothing, so the Newton iteration's matrix is block triangular
//! and their stage values converge with the others' (one iteration behind); they are not
//! error-controlled.

use super::{Dae, sin_cos_of};
use crate::formulation::FormulationError;
use crate::formulation::contact_slopes::{Direction, LawSlopes};
use crate::mechanics::constraints::{ConstraintRow, RowCurvature};
use crate::mechanics::planar::{cross, perp};
use crate::model::{Baumgarte, Frame};

/// ∂Q/∂y of one slider corner in contact (`formulation/corner_contacts.rs`), handed to
/// `add(row, column, value)`, by central differences of the corner's two body forces alone over
/// the columns of its bodies (q, q̇) and its stored impact velocity (column `stored_col`).
/// Increments sized on the contact, not on the coordinates: a position moves by 1e-4 δ (the
/// force goes as δⁿ, so the truncation error is ~1e-8 of the slope and the rounding ~1e-12), an
/// angle by that over the corner's arm; a velocity by 1e-7 m/s, far below the friction law's
/// ramp v0 (1e-4 m/s in the reference data); the stored velocity by 1e-6 of itself.
fn corner_force_derivatives(
    corner: &crate::formulation::contacts::CornerSite,
    y: &[f64],
    n: usize,
    stored_col: usize,
    add: &mut impl FnMut(usize, usize, f64),
) {
    let stored = y.get(stored_col).copied().unwrap_or(0.0);
    let s = corner.state_alone(&y[..n], &y[n..2 * n], stored);
    if s.kinematics.delta <= 0.0 {
        return;
    }
    let bodies: Vec<usize> = corner.bodies().collect();
    let arm = |p: &crate::mechanics::planar::PointState| p.arm[0].hypot(p.arm[1]);
    let reach = arm(&s.journal).max(arm(&s.bearing)).max(1e-3);
    let dq = 1e-4 * s.kinematics.delta;
    let dv = 1e-7;
    let mut columns: Vec<(usize, f64)> = Vec::with_capacity(13);
    for &b in &bodies {
        columns.extend([
            (3 * b, dq),
            (3 * b + 1, dq),
            (3 * b + 2, dq / reach),
            (n + 3 * b, dv),
            (n + 3 * b + 1, dv),
            (n + 3 * b + 2, dv / reach),
        ]);
    }
    if stored > 0.0 {
        columns.push((stored_col, 1e-6 * stored));
    }
    let mut state = y.to_vec();
    let force_at = |state: &[f64]| {
        let stored = state.get(stored_col).copied().unwrap_or(0.0);
        corner.generalised_forces(&state[..n], &state[n..2 * n], stored)
    };
    let sides = [corner.slider, corner.guide];
    for (col, h) in columns {
        let y0 = state[col];
        state[col] = y0 + h;
        let plus = force_at(&state);
        state[col] = y0 - h;
        let minus = force_at(&state);
        state[col] = y0;
        for (side, frame) in sides.iter().enumerate() {
            let Frame::Body(id) = frame else { continue };
            for c in 0..3 {
                add(
                    3 * id.0 + c,
                    col,
                    (plus[side][c] - minus[side][c]) / (2.0 * h),
                );
            }
        }
    }
}

/// Relative increment of the central differences of the force elements (about u^{1/3}, the
/// optimum for central differences of smooth functions).
const FORCE_REL: f64 = 6e-6;

impl Dae {
    /// Writes J = ∂f/∂y at (t, y) row-major into `out` (length n_states²). Fails as
    /// [`Formulation::rhs`](crate::formulation::Formulation::rhs) does.
    pub(super) fn analytic_jacobian(
        &self,
        t: f64,
        y: &[f64],
        out: &mut [f64],
    ) -> Result<(), FormulationError> {
        use crate::formulation::Formulation;
        let ny = self.n_states();
        if out.len() != ny * ny || y.len() != ny {
            return Err(FormulationError::Unsupported {
                formulation: "DAE".into(),
                reason: format!(
                    "Jacobian buffer of length {} and state of length {} for {ny} states",
                    out.len(),
                    y.len()
                ),
            });
        }
        let n = self.n_coordinates();
        let nc = self.contacts.len();
        let n_cols = 2 * n + nc;
        let m = self.constraints.n_rows();
        let ma = self.active.len();
        let v = &y[n..2 * n];
        let mut scratch = self.jacobian_scratch.borrow_mut();
        let JacobianScratch {
            acc,
            force_y,
            lambda_h,
            curvature,
            rows,
            rhs,
            column,
            constraint,
        } = &mut *scratch;
        acc.resize(n, 0.0);
        curvature.resize(m, RowCurvature::default());
        for (buffer, len) in [
            (&mut *force_y, n * n_cols),
            (&mut *lambda_h, n * n),
            (&mut *rhs, ma * n_cols),
            (&mut *constraint, n * n_cols),
        ] {
            // Sized once; zeroed by `fill` (a memset) on every call.
            buffer.resize(len, 0.0);
            buffer.fill(0.0);
        }
        column.resize(ma, 0.0);

        // q̈ and λ at (t, y); this leaves the constraint rows in `work.constraints` and
        // A = S + diag(Δ), S = Φ_q M⁻¹ Φ_qᵀ, factored in `work.schur` with the right-hand
        // side's own regularised pivots: the solves below are with that same matrix.
        let mut work = self.work.borrow_mut();
        self.accelerations_into(t, y, acc, &mut work)?;
        let work = &mut *work;
        let sin_cos = &work.sin_cos;

        // ∂Q/∂y over the columns q, q̇, δ̇⁽⁻⁾ (n × n_cols, row-major).
        self.contact_force_derivatives(y, sin_cos, &mut |row, col, d| {
            force_y[row * n_cols + col] += d;
        });
        if !self.model.forces.is_empty() {
            self.applied_force_derivatives(t, y, force_y);
        }
        self.constraints
            .curvature_into(&y[..n], v, sin_cos, curvature);

        // Per active row i: its terms over its (at most six) local columns, Σ_k λ_k H_k into
        // `lambda_h` (n × n), and into column `col` of `rhs` (n_cols × ma, column-major so that
        // each column is one solve) Φ_q M⁻¹ ∂Q/∂y_col. Only a row's local columns are touched:
        // Φ_q is zero elsewhere, and they are visited in increasing order so that every sum
        // adds its terms in the order of a dense pass over the coordinates.
        let ce = &work.constraints;
        rows.clear();
        for (i, &k) in self.active.iter().enumerate() {
            let terms = row_terms(&ce.rows[k], &curvature[k], acc, v, self.baumgarte);
            let h = &curvature[k].hessian;
            let lambda = work.lambda[i];
            for (l, cl) in terms.cols.iter().enumerate() {
                let Some(cl) = *cl else { continue };
                for (p, cp) in terms.cols.iter().enumerate() {
                    if let Some(cp) = cp {
                        lambda_h[cl * n + cp] += lambda * h[l][p];
                    }
                }
            }
            rows.push(LocalTerms::of(&terms));
        }
        // r_col = ∂Q/∂y_col − (Σ λ H)·e_col, in place of ∂Q/∂y.
        for (r_row, lh_row) in force_y
            .chunks_exact_mut(n_cols)
            .zip(lambda_h.chunks_exact(n))
        {
            for (r, &lh) in r_row.iter_mut().zip(lh_row) {
                *r -= lh;
            }
        }
        let r_mat = &*force_y;
        for (row, b_row) in rows.iter().zip(rhs.chunks_exact_mut(n_cols)) {
            for &LocalTerm { col: cl, jac, .. } in row.iter() {
                let w = jac * self.inv_mass[cl];
                let r_row = &r_mat[cl * n_cols..(cl + 1) * n_cols];
                for (b, &r) in b_row.iter_mut().zip(r_row) {
                    *b += w * r;
                }
            }
            for &LocalTerm {
                col: cl, c_q, c_v, ..
            } in row.iter()
            {
                b_row[cl] -= c_q;
                b_row[n + cl] -= c_v;
            }
        }
        // ∂λ = A⁻¹ b, one column at a time.
        for col in 0..n_cols {
            for (x, b_row) in column.iter_mut().zip(rhs.chunks_exact(n_cols)) {
                *x = b_row[col];
            }
            work.schur.solve(column);
            for (&x, b_row) in column.iter().zip(rhs.chunks_exact_mut(n_cols)) {
                b_row[col] = x;
            }
        }
        // Φ_qᵀ ∂λ, again over the local columns of each row, rows in order.
        for (row, x_row) in rows.iter().zip(rhs.chunks_exact(n_cols)) {
            for &LocalTerm { col: cl, jac, .. } in row.iter() {
                let c_row = &mut constraint[cl * n_cols..(cl + 1) * n_cols];
                for (c, &x) in c_row.iter_mut().zip(x_row) {
                    *c += jac * x;
                }
            }
        }

        // ∂q̈ = M⁻¹ (r − Φ_qᵀ ∂λ) in the rows of q̇; q̇ in those of q.
        out.fill(0.0);
        for c in 0..n {
            out[c * ny + n + c] = 1.0;
        }
        for (c, (r_row, c_row)) in r_mat
            .chunks_exact(n_cols)
            .zip(constraint.chunks_exact(n_cols))
            .enumerate()
        {
            let im = self.inv_mass[c];
            let out_row = &mut out[(n + c) * ny..(n + c) * ny + n_cols];
            for ((o, &r), &k) in out_row.iter_mut().zip(r_row).zip(c_row) {
                *o = im * (r - k);
            }
        }
        Ok(())
    }

    /// Hands ∂Q/∂y of the contact forces to `add(row, column, value)`: row a coordinate
    /// (0..n), column a state (q, q̇, δ̇⁽⁻⁾: 0..2n + n_c); each entry may come in several parts.
    /// Only the rows and columns of the two bodies of a clearance joint in contact (and its
    /// stored impact velocity) are touched.
    pub(super) fn contact_force_derivatives(
        &self,
        y: &[f64],
        sin_cos: &[(f64, f64)],
        add: &mut impl FnMut(usize, usize, f64),
    ) {
        let n = self.n_coordinates();
        let (q, v) = (&y[..n], &y[n..2 * n]);
        for (k, site) in self.contacts.sites().iter().enumerate() {
            let stored = y[2 * n + k];
            let s = self.contacts.site_state(k, q, v, sin_cos, stored);
            let kin = &s.kinematics;
            if let Some(film) = &site.contact.lubrication {
                // The film at every eccentricity, by central differences of its own part of Q.
                let gap = (film.clearance - kin.distance).max(0.5 * film.contact_film_thickness);
                self.film_force_derivatives(k, y, gap, add);
            }
            if !(kin.delta > 0.0 && kin.distance > 0.0) {
                continue;
            }
            let (f_n, f_t) = (s.forces.normal_force, s.forces.friction_force);
            let slopes = LawSlopes::at(&site.contact, kin, stored, f_n);
            // Directions per column: journal with sign +1, bearing with −1.
            let mut dirs: Vec<(usize, Direction)> = Vec::with_capacity(13);
            let mut push = |col: usize, d: Direction| match dirs.iter_mut().find(|(c, _)| *c == col)
            {
                Some((_, e)) => {
                    e.e = [e.e[0] + d.e[0], e.e[1] + d.e[1]];
                    e.e_dot = [e.e_dot[0] + d.e_dot[0], e.e_dot[1] + d.e_dot[1]];
                    e.spin += d.spin;
                    e.stored += d.stored;
                }
                None => dirs.push((col, d)),
            };
            for (frame, point, sign, radius) in [
                (site.journal.frame, &s.journal, 1.0, kin.journal_radius),
                (site.bearing.frame, &s.bearing, -1.0, -kin.bearing_radius),
            ] {
                let Frame::Body(id) = frame else { continue };
                let b = 3 * id.0;
                let arm = point.arm;
                let u = perp(arm);
                for axis in 0..2 {
                    let mut unit = [0.0; 2];
                    unit[axis] = sign;
                    push(
                        b + axis,
                        Direction {
                            e: unit,
                            ..Direction::default()
                        },
                    );
                    push(
                        n + b + axis,
                        Direction {
                            e_dot: unit,
                            ..Direction::default()
                        },
                    );
                }
                push(
                    b + 2,
                    Direction {
                        e: [sign * u[0], sign * u[1]],
                        e_dot: [-sign * point.omega * arm[0], -sign * point.omega * arm[1]],
                        ..Direction::default()
                    },
                );
                push(
                    n + b + 2,
                    Direction {
                        e_dot: [sign * u[0], sign * u[1]],
                        spin: radius,
                        ..Direction::default()
                    },
                );
            }
            push(
                2 * n + k,
                Direction {
                    stored: 1.0,
                    ..Direction::default()
                },
            );

            let on_journal = s.forces.on_journal;
            for (col, d) in &dirs {
                let df = slopes.derivative(kin, f_n, f_t, d);
                for (frame, point, sign, moment_arm, force) in [
                    (
                        site.journal.frame,
                        &s.journal,
                        1.0,
                        kin.journal_radius,
                        on_journal,
                    ),
                    (
                        site.bearing.frame,
                        &s.bearing,
                        -1.0,
                        -kin.bearing_radius,
                        s.forces.on_bearing,
                    ),
                ] {
                    let Frame::Body(id) = frame else { continue };
                    let b = 3 * id.0;
                    let d_force = [sign * df.on_journal[0], sign * df.on_journal[1]];
                    add(b, *col, d_force[0]);
                    add(b + 1, *col, d_force[1]);
                    let mut d_moment = cross(point.arm, d_force) + moment_arm * df.friction;
                    if *col == b + 2 {
                        // The arm turns with its body.
                        d_moment += cross(perp(point.arm), force);
                    }
                    add(b + 2, *col, d_moment);
                }
            }
        }
        let first = self.contacts.sites().len();
        for (i, corner) in self.contacts.corners().iter().enumerate() {
            corner_force_derivatives(corner, y, n, 2 * n + first + i, add);
        }
    }

    /// Hands ∂Q/∂(q, q̇) of the film of lubricated joint `k` to `add(row, column, value)`, by
    /// central differences over the coordinates and speeds of its two bodies. The film varies
    /// on the scale of its thickness `gap` (m), far below the coordinates' own: positions move
    /// by [`FORCE_REL`]·gap, angles by that over the centre's arm, speeds by
    /// [`FORCE_REL`]·max(|y_j|, 1) (the force is homogeneous of degree one in the speeds).
    fn film_force_derivatives(
        &self,
        k: usize,
        y: &[f64],
        gap: f64,
        add: &mut impl FnMut(usize, usize, f64),
    ) {
        let n = self.n_coordinates();
        let site = &self.contacts.sites()[k];
        let mut bodies: Vec<(usize, f64)> = Vec::with_capacity(2);
        for anchor in [&site.journal, &site.bearing] {
            if let Frame::Body(id) = anchor.frame
                && !bodies.iter().any(|(b, _)| *b == id.0)
            {
                let arm = anchor.local[0].hypot(anchor.local[1]);
                bodies.push((id.0, arm));
            }
        }
        let mut state = y[..2 * n].to_vec();
        let (mut plus, mut minus) = (vec![0.0; n], vec![0.0; n]);
        let radius = site.contact.journal_radius;
        for &(body, arm) in &bodies {
            for c in 3 * body..3 * body + 3 {
                let position_step = if c % 3 == 2 {
                    FORCE_REL * gap / arm.max(radius)
                } else {
                    FORCE_REL * gap
                };
                for (col, h) in [
                    (c, position_step),
                    (n + c, FORCE_REL * state[n + c].abs().max(1.0)),
                ] {
                    let x = state[col];
                    plus.fill(0.0);
                    minus.fill(0.0);
                    state[col] = x + h;
                    let (q, v) = state.split_at(n);
                    self.contacts.add_film_into(k, q, v, &mut plus);
                    state[col] = x - h;
                    let (q, v) = state.split_at(n);
                    self.contacts.add_film_into(k, q, v, &mut minus);
                    state[col] = x;
                    for &(row_body, _) in &bodies {
                        for row in 3 * row_body..3 * row_body + 3 {
                            add(row, col, (plus[row] - minus[row]) / (2.0 * h));
                        }
                    }
                }
            }
        }
    }

    /// Adds ∂Q/∂(q, q̇) of gravity and the force elements to `dq` by central differences of
    /// the applied-force vector alone (increment [`FORCE_REL`]·max(|y_j|, 1)).
    fn applied_force_derivatives(&self, t: f64, y: &[f64], dq: &mut [f64]) {
        let n = self.n_coordinates();
        let n_cols = 2 * n + self.contacts.len();
        let mut state = y[..2 * n].to_vec();
        let (mut plus, mut minus) = (vec![0.0; n], vec![0.0; n]);
        let eval = |state: &[f64], out: &mut [f64]| {
            let (q, v) = state.split_at(n);
            self.applied.evaluate_into(t, q, v, &sin_cos_of(q), out);
        };
        for col in 0..2 * n {
            let x = state[col];
            let h = FORCE_REL * x.abs().max(1.0);
            state[col] = x + h;
            eval(&state, &mut plus);
            state[col] = x - h;
            eval(&state, &mut minus);
            state[col] = x;
            for c in 0..n {
                dq[c * n_cols + col] += (plus[c] - minus[c]) / (2.0 * h);
            }
        }
    }
}

/// The buffers of [`Dae::analytic_jacobian`], kept between calls (sized on first use).
#[derive(Debug, Clone, Default)]
pub(super) struct JacobianScratch {
    /// q̈ at the Jacobian's state.
    acc: Vec<f64>,
    /// ∂Q/∂y over the columns q, q̇, δ̇⁽⁻⁾ (n × n_cols, row-major), then r = ∂Q/∂y − Σ λ H.
    force_y: Vec<f64>,
    /// Σ_k λ_k H_k (n × n).
    lambda_h: Vec<f64>,
    curvature: Vec<RowCurvature>,
    /// Each active row's local terms in increasing column order.
    rows: Vec<LocalTerms>,
    /// Φ_q M⁻¹ r_j − s_j, then ∂λ, for every column j (active rows × n_cols, row-major).
    rhs: Vec<f64>,
    /// One column of `rhs` for the solve.
    column: Vec<f64>,
    /// Φ_qᵀ ∂λ (n × n_cols, row-major).
    constraint: Vec<f64>,
}

/// One local column of a constraint row: its global column, Φ_q, ∂c/∂q and ∂c/∂q̇ there.
#[derive(Debug, Clone, Copy, Default)]
struct LocalTerm {
    col: usize,
    jac: f64,
    c_q: f64,
    c_v: f64,
}

/// A row's [`LocalTerm`]s (at most six) in increasing column order.
#[derive(Debug, Clone, Copy, Default)]
struct LocalTerms {
    terms: [LocalTerm; 6],
    len: usize,
}

impl LocalTerms {
    fn of(row: &RowTerms) -> Self {
        let mut out = LocalTerms::default();
        for (l, c) in row.cols.iter().enumerate() {
            if let Some(col) = *c {
                out.terms[out.len] = LocalTerm {
                    col,
                    jac: row.jac[l],
                    c_q: row.c_q[l],
                    c_v: row.c_v[l],
                };
                out.len += 1;
            }
        }
        out.terms[..out.len].sort_unstable_by_key(|t| t.col);
        out
    }

    fn iter(&self) -> std::slice::Iter<'_, LocalTerm> {
        self.terms[..self.len].iter()
    }
}

/// The global columns of a row's six local coordinates (None on the ground).
pub(super) fn local_columns(a: Option<usize>, b: Option<usize>) -> [Option<usize>; 6] {
    let mut cols = [None; 6];
    for (side, body) in [a, b].into_iter().enumerate() {
        if let Some(body) = body {
            for c in 0..3 {
                cols[3 * side + c] = Some(3 * body + c);
            }
        }
    }
    cols
}

/// One active constraint row's terms over its six local columns ([`local_columns`], `None`
/// where a side is the ground): Φ_q, ∂c/∂q = ∂γ/∂q − 2α H q̇ − β² Φ_q − H q̈ and
/// ∂c/∂q̇ = ∂γ/∂q̇ − 2α Φ_q (module documentation), the same for the dense Jacobian and the
/// sparse augmented one (`dae/sparse_jacobian.rs`).
pub(super) struct RowTerms {
    pub cols: [Option<usize>; 6],
    pub jac: [f64; 6],
    pub c_q: [f64; 6],
    pub c_v: [f64; 6],
}

/// [`RowTerms`] of `row` with curvature `curvature`, at the accelerations `acc` and speeds `v`
/// (over all coordinates).
pub(super) fn row_terms(
    row: &ConstraintRow,
    curvature: &RowCurvature,
    acc: &[f64],
    v: &[f64],
    Baumgarte { alpha, beta }: Baumgarte,
) -> RowTerms {
    let cols = local_columns(row.body_a, row.body_b);
    let local = |w: &[f64]| {
        let mut out = [0.0; 6];
        for (l, c) in cols.iter().enumerate() {
            if let Some(c) = c {
                out[l] = w[*c];
            }
        }
        out
    };
    let (acc_l, v_l) = (local(acc), local(v));
    let h = &curvature.hessian;
    let mut terms = RowTerms {
        cols,
        jac: [0.0; 6],
        c_q: [0.0; 6],
        c_v: [0.0; 6],
    };
    for l in 0..6 {
        let jac_l = if l < 3 {
            row.jac_a[l]
        } else {
            row.jac_b[l - 3]
        };
        let h_acc: f64 = (0..6).map(|p| h[l][p] * acc_l[p]).sum();
        let h_v: f64 = (0..6).map(|p| h[l][p] * v_l[p]).sum();
        terms.jac[l] = jac_l;
        terms.c_q[l] = curvature.gamma_q[l] - 2.0 * alpha * h_v - beta * beta * jac_l - h_acc;
        terms.c_v[l] = curvature.gamma_v[l] - 2.0 * alpha * jac_l;
    }
    terms
}

#[cfg(test)]
mod tests;
