//! Second derivatives of the constraint rows, for analytic Jacobians of the equations of motion
//! (the DAE's ∂q̈/∂y in `formulation/dae/jacobian.rs`).
//!
//! For row k, over the six coordinates of its two bodies, ordered (x_a, y_a, φ_a, x_b, y_b, φ_b)
//! as [`ConstraintRow`](super::ConstraintRow)'s blocks (the entries of a ground side are zero
//! and belong to no column):
//!
//! * the Hessian H_k = ∂²Φ_k/∂q² (symmetric; ∂(Φ_q,k w)/∂q = H_k w for a fixed w);
//! * ∂γ_k/∂q and ∂γ_k/∂q̇ of the acceleration term γ (Φ_q q̈ = γ).
//!
//! Per element (P = r + A(φ) s, ∂(A s)/∂φ = perp(A s), perp(perp(v)) = −v):
//!
//! * revolute, axis i: Φ = P_b,i − P_a,i; H_φaφa = (A_a s_a)_i, H_φbφb = −(A_b s_b)_i;
//!   γ = (A_b s_b)_i φ̇_b² − (A_a s_a)_i φ̇_a², so ∂γ/∂φ_b = perp(A_b s_b)_i φ̇_b²,
//!   ∂γ/∂φ̇_b = 2 (A_b s_b)_i φ̇_b and likewise with the opposite sign for a;
//! * prismatic angle and driver rows are linear in q and their γ does not depend on the state:
//!   all zero;
//! * prismatic normal, Φ = n·d with n = A_a n̄, d = P_b − P_a: H_xa,φa = −n⊥, H_xb,φa = n⊥,
//!   H_φaφa = −n·(d + A_a s_a), H_φaφb = n·(A_b s_b), H_φbφb = −n·(A_b s_b) (n⊥ = perp(n));
//!   γ = φ̇_a² n·d − 2 φ̇_a n⊥·ḋ + n·c with c = A_b s_b φ̇_b² − A_a s_a φ̇_a², differentiated
//!   term by term with ∂n/∂φ_a = n⊥, ∂n⊥/∂φ_a = −n, ∂d/∂φ = ±perp(A s), ∂ḋ/∂φ = ∓φ̇ A s,
//!   ∂c/∂φ = ±φ̇² perp(A s), ∂ḋ/∂ṙ = ±1, ∂ḋ/∂φ̇ = ±perp(A s).
//!
//! Checked against central differences of [`ConstraintSet::evaluate_into`] in the tests below.
//!
//! # References
//! 1. P. E. Nikravesh, *Computer-Aided Analysis of Mechanical Systems*, 1988, §3.3–3.6, §4.4.

use super::{ConstraintSet, Element, angle_of};
use crate::mechanics::planar::{dot, perp, point_state, rotate};
use crate::model::Frame;

/// Second-order terms of one constraint row over its two bodies' six coordinates
/// (module documentation).
#[derive(Debug, Clone, Copy, Default)]
pub struct RowCurvature {
    /// H = ∂²Φ/∂q², row-major 6 × 6.
    pub hessian: [[f64; 6]; 6],
    /// ∂γ/∂q.
    pub gamma_q: [f64; 6],
    /// ∂γ/∂q̇.
    pub gamma_v: [f64; 6],
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

fn add(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] + b[0], a[1] + b[1]]
}

fn scale(v: [f64; 2], s: f64) -> [f64; 2] {
    [v[0] * s, v[1] * s]
}

impl ConstraintSet {
    /// Writes the [`RowCurvature`] of every row at (q, q̇) into `out` (length m, the rows in
    /// the order of [`ConstraintSet::evaluate_into`]). `sin_cos` holds (sin φ, cos φ) per body.
    pub fn curvature_into(
        &self,
        q: &[f64],
        v: &[f64],
        sin_cos: &[(f64, f64)],
        out: &mut [RowCurvature],
    ) {
        let mut k = 0;
        for e in &self.elements {
            match e {
                Element::Revolute { a, sa, b, sb, .. } => {
                    let pa = point_state(*a, *sa, q, v, sin_cos);
                    let pb = point_state(*b, *sb, q, v, sin_cos);
                    let (ua, ub) = (perp(pa.arm), perp(pb.arm));
                    for axis in 0..2 {
                        let c = &mut out[k + axis];
                        *c = RowCurvature::default();
                        c.hessian[2][2] = pa.arm[axis];
                        c.hessian[5][5] = -pb.arm[axis];
                        c.gamma_q[2] = -ua[axis] * pa.omega * pa.omega;
                        c.gamma_q[5] = ub[axis] * pb.omega * pb.omega;
                        c.gamma_v[2] = -2.0 * pa.arm[axis] * pa.omega;
                        c.gamma_v[5] = 2.0 * pb.arm[axis] * pb.omega;
                    }
                    k += 2;
                }
                Element::Prismatic {
                    a,
                    sa,
                    b,
                    sb,
                    normal,
                    ..
                } => {
                    out[k] = RowCurvature::default();
                    out[k + 1] = prismatic_normal(*a, *sa, *b, *sb, *normal, q, v, sin_cos);
                    k += 2;
                }
                Element::Driver { .. } => {
                    out[k] = RowCurvature::default();
                    k += 1;
                }
            }
        }
        debug_assert_eq!(k, self.n_rows(), "every element writes exactly its rows");
    }
}

/// The curvature of the normal row n·(P_b − P_a) of a prismatic joint (module documentation).
#[allow(clippy::too_many_arguments)] // the element's fields and the state
fn prismatic_normal(
    a: Frame,
    sa: [f64; 2],
    b: Frame,
    sb: [f64; 2],
    normal: [f64; 2],
    q: &[f64],
    v: &[f64],
    sin_cos: &[(f64, f64)],
) -> RowCurvature {
    let pa = point_state(a, sa, q, v, sin_cos);
    let pb = point_state(b, sb, q, v, sin_cos);
    let n = match a {
        Frame::Ground => normal,
        Frame::Body(id) => rotate(sin_cos[id.0], normal),
    };
    let np = perp(n);
    let d = sub(pb.position, pa.position);
    let d_dot = sub(pb.velocity, pa.velocity);
    let (_, wa) = angle_of(a, q, v);
    let (_, wb) = angle_of(b, q, v);
    let cent = sub(scale(pb.arm, wb * wb), scale(pa.arm, wa * wa));
    let mut c = RowCurvature::default();
    let h = &mut c.hessian;
    for i in 0..2 {
        h[i][2] = -np[i];
        h[2][i] = -np[i];
        h[3 + i][2] = np[i];
        h[2][3 + i] = np[i];
    }
    h[2][2] = -dot(n, add(d, pa.arm));
    h[2][5] = dot(n, pb.arm);
    h[5][2] = h[2][5];
    h[5][5] = -dot(n, pb.arm);

    // γ = wa² n·d − 2 wa n⊥·ḋ + n·cent; derivatives per local coordinate.
    // Positions: (∂n, ∂n⊥, ∂d, ∂ḋ, ∂cent) for x_a, y_a, φ_a, x_b, y_b, φ_b.
    let zero = [0.0; 2];
    let ex = [[1.0, 0.0], [0.0, 1.0]];
    for j in 0..6 {
        let (dn, dnp, dd, dd_dot, dcent) = match j {
            0 | 1 => (zero, zero, scale(ex[j], -1.0), zero, zero),
            2 => (
                np,
                scale(n, -1.0),
                scale(perp(pa.arm), -1.0),
                scale(pa.arm, wa),
                scale(perp(pa.arm), -wa * wa),
            ),
            3 | 4 => (zero, zero, ex[j - 3], zero, zero),
            _ => (
                zero,
                zero,
                perp(pb.arm),
                scale(pb.arm, -wb),
                scale(perp(pb.arm), wb * wb),
            ),
        };
        c.gamma_q[j] = wa * wa * (dot(dn, d) + dot(n, dd))
            - 2.0 * wa * (dot(dnp, d_dot) + dot(np, dd_dot))
            + dot(dn, cent)
            + dot(n, dcent);
    }
    // Velocities: ∂ḋ and ∂cent for ẋ_a, ẏ_a, φ̇_a, ẋ_b, ẏ_b, φ̇_b, plus the explicit wa terms.
    for j in 0..6 {
        let (dd_dot, dcent) = match j {
            0 | 1 => (scale(ex[j], -1.0), zero),
            2 => (scale(perp(pa.arm), -1.0), scale(pa.arm, -2.0 * wa)),
            3 | 4 => (ex[j - 3], zero),
            _ => (perp(pb.arm), scale(pb.arm, 2.0 * wb)),
        };
        let mut g = -2.0 * wa * dot(np, dd_dot) + dot(n, dcent);
        if j == 2 {
            g += 2.0 * wa * dot(n, d) - 2.0 * dot(np, d_dot);
        }
        c.gamma_v[j] = g;
    }
    c
}

#[cfg(test)]
mod tests {
    use super::super::ConstraintEval;
    use super::*;
    use crate::model::load_str;

    /// A pin to the ground, a prismatic joint between two bodies, a driver and a revolute joint
    /// between two bodies: every element and both ground and body sides.
    const MODEL: &str = r#"
[model]
name = "curvature"
[ground]
points = { O = [0.0, 0.0], Q = [1.0, 0.5] }
[[bodies]]
name = "arm"
mass = 1.0
inertia = 0.1
points = { O = [-0.3, 0.1], P = [0.4, -0.2], R = [0.1, 0.3] }
initial = { x = 0.3, y = -0.1, phi = 0.3 }
[[bodies]]
name = "slider"
mass = 1.0
inertia = 0.1
points = { P = [0.05, 0.02], S = [-0.2, 0.1] }
initial = { x = 0.7, y = 0.2, phi = 0.5 }
[[bodies]]
name = "link"
mass = 1.0
inertia = 0.1
points = { R = [-0.2, 0.05], S = [0.25, -0.1] }
initial = { x = 0.2, y = 0.4, phi = -0.4 }
[[joints]]
name = "pin"
type = "revolute"
body_a = "ground"
point_a = "O"
body_b = "arm"
point_b = "O"
[[joints]]
name = "slide"
type = "prismatic"
body_a = "arm"
point_a = "P"
body_b = "slider"
point_b = "P"
axis = [0.6, 0.8]
angle = 0.1
[[joints]]
name = "knee"
type = "revolute"
body_a = "slider"
point_a = "S"
body_b = "link"
point_b = "S"
[[joints]]
name = "rail"
type = "prismatic"
body_a = "ground"
point_a = "Q"
body_b = "link"
point_b = "R"
axis = [1.0, 0.2]
angle = 0.0
[[drivers]]
name = "motor"
type = "constant-speed"
joint = "pin"
speed = 3.0
initial_angle = 0.2
"#;

    fn eval(set: &ConstraintSet, q: &[f64], v: &[f64]) -> ConstraintEval {
        let sc: Vec<(f64, f64)> = (0..q.len() / 3).map(|i| q[3 * i + 2].sin_cos()).collect();
        let mut out = ConstraintEval::with_rows(set.n_rows());
        set.evaluate_into(0.4, q, v, &sc, &mut out);
        out
    }

    /// Global column of local coordinate `j` of row `k`, or None for a ground side.
    fn column(e: &ConstraintEval, k: usize, j: usize) -> Option<usize> {
        let body = if j < 3 {
            e.rows[k].body_a
        } else {
            e.rows[k].body_b
        };
        body.map(|b| 3 * b + j % 3)
    }

    fn local_jac(e: &ConstraintEval, k: usize, j: usize) -> f64 {
        let row = &e.rows[k];
        if j < 3 {
            row.jac_a[j]
        } else {
            row.jac_b[j - 3]
        }
    }

    /// H against central differences of the Jacobian blocks, ∂γ/∂q and ∂γ/∂q̇ against central
    /// differences of γ, at a generic state (all rows curved, every body moving). Increment
    /// 1e-6 gives an O(1e-12) truncation error and O(1e-10) rounding on entries of order 1, so
    /// 1e-7 relative to (1 + |entry|) has a margin of 1000. Several bodies sharing a column
    /// (none here: each row's two bodies differ) would need their blocks summed.
    #[test]
    fn curvature_matches_central_differences() {
        let model = match load_str(MODEL, "curvature.toml", &[]) {
            Ok(m) => m,
            Err(e) => panic!("{e}"),
        };
        let set = ConstraintSet::from_model(&model, false);
        let q: [f64; 9] = [0.3, -0.1, 0.3, 0.7, 0.2, 0.5, 0.2, 0.4, -0.4];
        let v = [0.5, -1.2, 2.0, -0.7, 0.9, -1.5, 0.3, 0.8, 1.1];
        let sc: Vec<(f64, f64)> = (0..3).map(|i| q[3 * i + 2].sin_cos()).collect();
        let base = eval(&set, &q, &v);
        let mut curv = vec![RowCurvature::default(); set.n_rows()];
        set.curvature_into(&q, &v, &sc, &mut curv);
        let h = 1e-6;
        let close = |fd: f64, an: f64| (fd - an).abs() <= 1e-7 * (1.0 + an.abs());
        for k in 0..set.n_rows() {
            for j in 0..6 {
                let Some(col) = column(&base, k, j) else {
                    continue;
                };
                let (mut qp, mut qm) = (q, q);
                qp[col] += h;
                qm[col] -= h;
                let (ep, em) = (eval(&set, &qp, &v), eval(&set, &qm, &v));
                for i in 0..6 {
                    if column(&base, k, i).is_none() {
                        continue;
                    }
                    let fd = (local_jac(&ep, k, i) - local_jac(&em, k, i)) / (2.0 * h);
                    let an = curv[k].hessian[i][j];
                    assert!(
                        close(fd, an),
                        "row {k}: H[{i}][{j}] fd {fd} vs analytic {an}"
                    );
                }
                let fd = (ep.gamma[k] - em.gamma[k]) / (2.0 * h);
                let an = curv[k].gamma_q[j];
                assert!(
                    close(fd, an),
                    "row {k}: dγ/dq[{j}] fd {fd} vs analytic {an}"
                );
                let (mut vp, mut vm) = (v, v);
                vp[col] += h;
                vm[col] -= h;
                let fd = (eval(&set, &q, &vp).gamma[k] - eval(&set, &q, &vm).gamma[k]) / (2.0 * h);
                let an = curv[k].gamma_v[j];
                assert!(
                    close(fd, an),
                    "row {k}: dγ/dv[{j}] fd {fd} vs analytic {an}"
                );
            }
        }
    }
}
