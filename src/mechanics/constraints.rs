//! Ideal joints and drivers as constraint rows Φ(q, t) = 0.
//!
//! Each row touches at most two bodies, so its Jacobian is stored as two 3-blocks (∂Φ/∂q_a,
//! ∂Φ/∂q_b); the DAE assembles Φ_q M⁻¹ Φ_qᵀ from them without a general sparse matrix.
//! γ is the part of Φ̈ that does not contain q̈, with the sign convention Φ_q q̈ = γ:
//! γ = −(Φ_q q̇)_q q̇ − 2 Φ_qt q̇ − Φ_tt.
//!
//! Rows per element:
//! - revolute (2): P_b − P_a − e₀ = 0, P = r + A(φ) s (e₀ = 0 except when a clearance joint is
//!   assembled as a revolute joint with a prescribed initial eccentricity);
//! - prismatic (2): φ_b − φ_a − θ = 0 and n_a · (P_b − P_a) = 0 with n_a = A(φ_a) n̄, n̄ ⟂ axis;
//! - driver (1): φ_b − φ_a − θ(t) = 0, θ(t) from [`super::drivers::driver_angle`] (θ₀ + ω t at
//!   constant speed), so Φ_t = −θ̇ and γ = θ̈.
//!
//! # References
//! 1. P. E. Nikravesh, *Computer-Aided Analysis of Mechanical Systems*, 1988, §3.3–3.6 (joint
//!    constraints), §4.4 (γ).

use super::planar::{dot, perp, point_state, rotate};
use crate::model::{Frame, JointId, JointKind, Model};

mod curvature;
pub use curvature::RowCurvature;

/// What a constraint row enforces, for messages and output.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RowSource {
    /// x or y component of a revolute (or assembling clearance) joint.
    JointAxis {
        /// Joint.
        joint: JointId,
        /// 0 = x, 1 = y.
        axis: usize,
    },
    /// Prismatic joint: fixed relative angle.
    PrismaticAngle(JointId),
    /// Prismatic joint: point b on the sliding line.
    PrismaticNormal(JointId),
    /// Driver (index into `Model::drivers`).
    Driver(usize),
}

/// Jacobian row of one constraint: two 3-blocks, for the bodies it touches (None = ground).
#[derive(Debug, Clone, Copy, Default)]
pub struct ConstraintRow {
    /// Body index of the first block.
    pub body_a: Option<usize>,
    /// ∂Φ/∂(x_a, y_a, φ_a).
    pub jac_a: [f64; 3],
    /// Body index of the second block.
    pub body_b: Option<usize>,
    /// ∂Φ/∂(x_b, y_b, φ_b).
    pub jac_b: [f64; 3],
}

impl ConstraintRow {
    /// The row's two blocks with their bodies: (body a, ∂Φ/∂q_a), (body b, ∂Φ/∂q_b).
    #[inline]
    pub fn blocks(&self) -> [(Option<usize>, &[f64; 3]); 2] {
        [(self.body_a, &self.jac_a), (self.body_b, &self.jac_b)]
    }

    /// Φ_q v for this row.
    #[inline]
    pub fn dot_velocity(&self, v: &[f64]) -> f64 {
        let mut s = 0.0;
        if let Some(a) = self.body_a {
            s += self.jac_a[0] * v[3 * a]
                + self.jac_a[1] * v[3 * a + 1]
                + self.jac_a[2] * v[3 * a + 2];
        }
        if let Some(b) = self.body_b {
            s += self.jac_b[0] * v[3 * b]
                + self.jac_b[1] * v[3 * b + 1]
                + self.jac_b[2] * v[3 * b + 2];
        }
        s
    }
}

/// The pairs of blocks of `rows` that act on a common body, as (i, j, side_i, side_j) with
/// i ≥ j the rows' positions in the iteration and side 0 = body a, 1 = body b of the row: the
/// structural non-zeros of Φ_q W Φ_qᵀ for any block-diagonal W (the DAE's S = Φ_q M⁻¹ Φ_qᵀ, the
/// assembly's G = Φ_q Φ_qᵀ). Found through the rows on each body, without an m² scan; unsorted.
pub fn pairs_on_common_bodies<'a>(
    rows: impl IntoIterator<Item = &'a ConstraintRow>,
) -> Vec<(usize, usize, u8, u8)> {
    let bodies: Vec<[Option<usize>; 2]> = rows
        .into_iter()
        .map(|row| [row.body_a, row.body_b])
        .collect();
    let n_bodies = bodies.iter().flatten().flatten().max().map_or(0, |b| b + 1);
    let mut on_body: Vec<Vec<(usize, u8)>> = vec![Vec::new(); n_bodies];
    for (k, pair) in bodies.iter().enumerate() {
        for (side, b) in pair.iter().enumerate() {
            if let Some(b) = b {
                on_body[*b].push((k, side as u8));
            }
        }
    }
    let mut pairs = Vec::new();
    for list in &on_body {
        for &(i, side_i) in list {
            for &(j, side_j) in list {
                if j <= i {
                    pairs.push((i, j, side_i, side_j));
                }
            }
        }
    }
    pairs
}

#[derive(Debug, Clone)]
enum Element {
    Revolute {
        a: Frame,
        sa: [f64; 2],
        b: Frame,
        sb: [f64; 2],
        offset: [f64; 2],
    },
    Prismatic {
        a: Frame,
        sa: [f64; 2],
        b: Frame,
        sb: [f64; 2],
        normal: [f64; 2],
        angle: f64,
    },
    Driver {
        a: Frame,
        b: Frame,
        driver: Box<crate::model::Driver>,
    },
}

/// All constraint rows of a model.
#[derive(Debug, Clone)]
pub struct ConstraintSet {
    elements: Vec<Element>,
    sources: Vec<RowSource>,
    /// Revolute rows as (r_b − r_a) + (A_b s_b − A_a s_a) ([`ConstraintSet::with_centre_differences`]).
    centre_differences: bool,
}

/// Values of the constraint rows at one (t, q, q̇).
#[derive(Debug, Clone, Default)]
pub struct ConstraintEval {
    /// Φ.
    pub phi: Vec<f64>,
    /// Φ̇ = Φ_q q̇ + Φ_t.
    pub phi_dot: Vec<f64>,
    /// Φ_t.
    pub phi_t: Vec<f64>,
    /// Jacobian rows Φ_q.
    pub rows: Vec<ConstraintRow>,
    /// γ (Φ_q q̈ = γ).
    pub gamma: Vec<f64>,
}

impl ConstraintEval {
    /// Buffers for `m` rows.
    pub fn with_rows(m: usize) -> Self {
        ConstraintEval {
            phi: vec![0.0; m],
            phi_dot: vec![0.0; m],
            phi_t: vec![0.0; m],
            rows: vec![ConstraintRow::default(); m],
            gamma: vec![0.0; m],
        }
    }
}

fn body_index(frame: Frame) -> Option<usize> {
    match frame {
        Frame::Ground => None,
        Frame::Body(id) => Some(id.0),
    }
}

impl ConstraintSet {
    /// The constraint rows of the model's ideal joints and drivers. With `assembling`, every
    /// clearance joint is added as a revolute joint held at its initial eccentricity (the
    /// initial state is the ideal-joint assembly); otherwise clearance joints add no rows.
    pub fn from_model(model: &Model, assembling: bool) -> Self {
        let mut elements = Vec::new();
        let mut sources = Vec::new();
        for (i, j) in model.joints.iter().enumerate() {
            let joint = JointId(i);
            let (a, sa, b, sb) = (j.a.frame, j.a.local, j.b.frame, j.b.local);
            match &j.kind {
                JointKind::Revolute => {
                    elements.push(Element::Revolute {
                        a,
                        sa,
                        b,
                        sb,
                        offset: [0.0; 2],
                    });
                }
                JointKind::Clearance(spec) if assembling => {
                    elements.push(Element::Revolute {
                        a,
                        sa,
                        b,
                        sb,
                        offset: spec.initial_eccentricity,
                    });
                }
                JointKind::Clearance(_) => continue,
                // Assembled as the ideal prismatic joint with the slider centre moved by the
                // initial offset along the guide normal and turned by the initial tilt.
                JointKind::PrismaticClearance(p) if assembling => {
                    let normal = perp(p.axis);
                    elements.push(Element::Prismatic {
                        a,
                        sa: [
                            sa[0] + p.initial_offset * normal[0],
                            sa[1] + p.initial_offset * normal[1],
                        ],
                        b,
                        sb,
                        normal,
                        angle: p.angle + p.initial_tilt,
                    });
                }
                JointKind::PrismaticClearance(_) => continue,
                JointKind::Prismatic { axis, angle } => {
                    elements.push(Element::Prismatic {
                        a,
                        sa,
                        b,
                        sb,
                        normal: perp(*axis),
                        angle: *angle,
                    });
                }
            }
            match j.kind {
                JointKind::Prismatic { .. } | JointKind::PrismaticClearance(_) => {
                    sources.push(RowSource::PrismaticAngle(joint));
                    sources.push(RowSource::PrismaticNormal(joint));
                }
                _ => {
                    sources.push(RowSource::JointAxis { joint, axis: 0 });
                    sources.push(RowSource::JointAxis { joint, axis: 1 });
                }
            }
        }
        for (k, d) in model.drivers.iter().enumerate() {
            let j = model.joint(d.joint);
            elements.push(Element::Driver {
                a: j.a.frame,
                b: j.b.frame,
                driver: Box::new(d.clone()),
            });
            sources.push(RowSource::Driver(k));
        }
        ConstraintSet {
            elements,
            sources,
            centre_differences: false,
        }
    }

    /// The same rows, with a revolute joint's Φ evaluated as (r_b − r_a) + (A_b s_b − A_a s_a)
    /// instead of P_b − P_a (the same value in exact arithmetic). The centres of two
    /// neighbouring bodies far from the origin subtract exactly (Sterbenz's lemma), so Φ carries
    /// the round-off of the arms (ε × the link's size) instead of that of the coordinates
    /// (ε × the distance from the origin). The generalised formulation solves Φ = 0 for the
    /// dependent coordinates, and near a singular position that round-off reaches its
    /// accelerations amplified by about 1/s³ (s the distance to the singular position;
    /// `docs/formulations.md`, "Generalized at scale"); on the 40-loop chain
    /// (`models/nfourbar_chain.toml`, points up to 40 m from the origin) the error of ẍ
    /// 1e-4 rad from the flat position fell from 2e-2 to 1e-5 with it. Off by default: the
    /// DAE's detection of singular passages is tuned on the rounding of P_b − P_a.
    #[must_use]
    pub fn with_centre_differences(mut self) -> Self {
        self.centre_differences = true;
        self
    }

    /// Number of rows m.
    pub fn n_rows(&self) -> usize {
        self.sources.len()
    }

    /// What each row enforces.
    pub fn sources(&self) -> &[RowSource] {
        &self.sources
    }

    /// Which components (x, y, φ) of its bodies row `k`'s Jacobian can be non-zero in, whatever
    /// the state: a revolute joint's x row never depends on y (nor its y row on x), angle rows
    /// and drivers only on φ. A sparse matrix of Φ_q built from this pattern stays valid at
    /// every state (an entry that is zero only at some states, such as ∂Φ/∂φ of a pin whose arm
    /// is momentarily along an axis, is kept), with a third fewer entries than all six.
    /// Out-of-range `k` touches all three.
    pub fn structural_components(&self, k: usize) -> [bool; 3] {
        match self.sources.get(k) {
            Some(RowSource::JointAxis { axis: 0, .. }) => [true, false, true],
            Some(RowSource::JointAxis { .. }) => [false, true, true],
            Some(RowSource::PrismaticAngle(_) | RowSource::Driver(_)) => [false, false, true],
            Some(RowSource::PrismaticNormal(_)) | None => [true, true, true],
        }
    }

    /// Human-readable name of row `k` ("A.x", "slider.angle", "motor").
    pub fn row_name(&self, model: &Model, k: usize) -> String {
        match self.sources.get(k) {
            Some(RowSource::JointAxis { joint, axis }) => {
                format!(
                    "{}.{}",
                    model.joint(*joint).name,
                    if *axis == 0 { "x" } else { "y" }
                )
            }
            Some(RowSource::PrismaticAngle(j)) => format!("{}.angle", model.joint(*j).name),
            Some(RowSource::PrismaticNormal(j)) => format!("{}.normal", model.joint(*j).name),
            Some(RowSource::Driver(d)) => model.drivers[*d].name.clone(),
            None => format!("row {k}"),
        }
    }

    /// Evaluates Φ, Φ_t, Φ_q, Φ̇ and γ at (t, q, q̇) into `out` (sized by [`ConstraintEval::with_rows`]).
    /// `sin_cos` holds (sin φ, cos φ) of every body.
    pub fn evaluate_into(
        &self,
        t: f64,
        q: &[f64],
        v: &[f64],
        sin_cos: &[(f64, f64)],
        out: &mut ConstraintEval,
    ) {
        let mut k = 0;
        for e in &self.elements {
            match e {
                Element::Revolute {
                    a,
                    sa,
                    b,
                    sb,
                    offset,
                    ..
                } => {
                    let pa = point_state(*a, *sa, q, v, sin_cos);
                    let pb = point_state(*b, *sb, q, v, sin_cos);
                    for axis in 0..2 {
                        let row = &mut out.rows[k + axis];
                        row.body_a = body_index(*a);
                        row.body_b = body_index(*b);
                        // ∂(r + A s)/∂φ = perp(A s).
                        let (ua, ub) = (perp(pa.arm), perp(pb.arm));
                        row.jac_a = if axis == 0 {
                            [-1.0, 0.0, -ua[0]]
                        } else {
                            [0.0, -1.0, -ua[1]]
                        };
                        row.jac_b = if axis == 0 {
                            [1.0, 0.0, ub[0]]
                        } else {
                            [0.0, 1.0, ub[1]]
                        };
                        out.phi[k + axis] = if self.centre_differences {
                            let (oa, ob) = (frame_origin(*a, *sa, q), frame_origin(*b, *sb, q));
                            (ob[axis] - oa[axis]) + (pb.arm[axis] - pa.arm[axis]) - offset[axis]
                        } else {
                            pb.position[axis] - pa.position[axis] - offset[axis]
                        };
                        out.phi_t[k + axis] = 0.0;
                        out.phi_dot[k + axis] = pb.velocity[axis] - pa.velocity[axis];
                        // d²(A s)/dt² = perp(A s) φ̈ − A s φ̇²: the φ̇² terms move to γ.
                        out.gamma[k + axis] =
                            pb.arm[axis] * pb.omega * pb.omega - pa.arm[axis] * pa.omega * pa.omega;
                    }
                    k += 2;
                }
                Element::Prismatic {
                    a,
                    sa,
                    b,
                    sb,
                    normal,
                    angle,
                    ..
                } => {
                    let pa = point_state(*a, *sa, q, v, sin_cos);
                    let pb = point_state(*b, *sb, q, v, sin_cos);
                    let (phi_a, w_a) = angle_of(*a, q, v);
                    let (phi_b, w_b) = angle_of(*b, q, v);
                    // Relative angle row.
                    let row = &mut out.rows[k];
                    row.body_a = body_index(*a);
                    row.body_b = body_index(*b);
                    row.jac_a = [0.0, 0.0, -1.0];
                    row.jac_b = [0.0, 0.0, 1.0];
                    out.phi[k] = phi_b - phi_a - angle;
                    out.phi_t[k] = 0.0;
                    out.phi_dot[k] = w_b - w_a;
                    out.gamma[k] = 0.0;
                    // Normal row: n · d, n = A_a n̄, d = P_b − P_a.
                    let n = match a {
                        Frame::Ground => *normal,
                        Frame::Body(id) => rotate(sin_cos[id.0], *normal),
                    };
                    let d = [
                        pb.position[0] - pa.position[0],
                        pb.position[1] - pa.position[1],
                    ];
                    let d_dot = [
                        pb.velocity[0] - pa.velocity[0],
                        pb.velocity[1] - pa.velocity[1],
                    ];
                    let n_perp = perp(n);
                    let row = &mut out.rows[k + 1];
                    row.body_a = body_index(*a);
                    row.body_b = body_index(*b);
                    row.jac_a = [-n[0], -n[1], dot(n_perp, d) - dot(n, perp(pa.arm))];
                    row.jac_b = [n[0], n[1], dot(n, perp(pb.arm))];
                    out.phi[k + 1] = dot(n, d);
                    out.phi_t[k + 1] = 0.0;
                    out.phi_dot[k + 1] = w_a * dot(n_perp, d) + dot(n, d_dot);
                    // Φ̈ = φ̈_a n⊥·d − φ̇_a² n·d + 2 φ̇_a n⊥·ḋ + n·d̈, d̈ ∋ −A_b s_b φ̇_b² + A_a s_a φ̇_a².
                    let centripetal = [
                        pb.arm[0] * pb.omega * pb.omega - pa.arm[0] * pa.omega * pa.omega,
                        pb.arm[1] * pb.omega * pb.omega - pa.arm[1] * pa.omega * pa.omega,
                    ];
                    out.gamma[k + 1] = w_a * w_a * dot(n, d) - 2.0 * w_a * dot(n_perp, d_dot)
                        + dot(n, centripetal);
                    k += 2;
                }
                Element::Driver { a, b, driver } => {
                    let [theta, theta_dot, theta_ddot] = super::drivers::driver_angle(driver, t);
                    let (phi_a, w_a) = angle_of(*a, q, v);
                    let (phi_b, w_b) = angle_of(*b, q, v);
                    let row = &mut out.rows[k];
                    row.body_a = body_index(*a);
                    row.body_b = body_index(*b);
                    row.jac_a = [0.0, 0.0, -1.0];
                    row.jac_b = [0.0, 0.0, 1.0];
                    out.phi[k] = phi_b - phi_a - theta;
                    out.phi_t[k] = -theta_dot;
                    out.phi_dot[k] = w_b - w_a - theta_dot;
                    // Φ_tt = −θ̈, and γ = −Φ_tt.
                    out.gamma[k] = theta_ddot;
                    k += 1;
                }
            }
        }
        debug_assert_eq!(k, self.n_rows(), "every element writes exactly its rows");
    }
}

/// The reference point of a joint end's frame: the body's centre of mass (x, y), or on the
/// ground the joint's ground point itself (whose arm `PointState::arm` is zero), so that
/// P = origin + arm on both.
#[inline]
fn frame_origin(frame: Frame, s: [f64; 2], q: &[f64]) -> [f64; 2] {
    match frame {
        Frame::Ground => s,
        Frame::Body(id) => [q[3 * id.0], q[3 * id.0 + 1]],
    }
}

/// φ and φ̇ of a frame (0 for the ground).
#[inline]
fn angle_of(frame: Frame, q: &[f64], v: &[f64]) -> (f64, f64) {
    match frame {
        Frame::Ground => (0.0, 0.0),
        Frame::Body(id) => (q[3 * id.0 + 2], v[3 * id.0 + 2]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::load_str;

    const MODEL: &str = r#"
[model]
name = "jac"
[ground]
points = { O = [0.0, 0.0] }
[[bodies]]
name = "arm"
mass = 1.0
inertia = 0.1
points = { O = [-0.3, 0.1], P = [0.4, -0.2] }
initial = { x = 0.3, y = -0.1, phi = 0.3 }
[[bodies]]
name = "slider"
mass = 1.0
inertia = 0.1
points = { P = [0.05, 0.02] }
initial = { x = 0.7, y = 0.2, phi = 0.5 }
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
[[drivers]]
name = "motor"
type = "constant-speed"
joint = "pin"
speed = 3.0
initial_angle = 0.2
"#;

    fn eval(set: &ConstraintSet, t: f64, q: &[f64], v: &[f64]) -> ConstraintEval {
        let sc: Vec<(f64, f64)> = (0..q.len() / 3).map(|i| q[3 * i + 2].sin_cos()).collect();
        let mut out = ConstraintEval::with_rows(set.n_rows());
        set.evaluate_into(t, q, v, &sc, &mut out);
        out
    }

    fn dense_jac(row: &ConstraintRow, n: usize) -> Vec<f64> {
        let mut j = vec![0.0; n];
        if let Some(a) = row.body_a {
            for c in 0..3 {
                j[3 * a + c] += row.jac_a[c];
            }
        }
        if let Some(b) = row.body_b {
            for c in 0..3 {
                j[3 * b + c] += row.jac_b[c];
            }
        }
        j
    }

    /// Every Jacobian entry outside [`ConstraintSet::structural_components`] is exactly zero,
    /// at states spread over the circle (a pattern built from it would otherwise drop an entry).
    #[test]
    fn jacobian_entries_outside_the_structural_pattern_are_zero() {
        let model = load_str(MODEL, "jac.toml", &[]).unwrap_or_else(|e| panic!("{e}"));
        let set = ConstraintSet::from_model(&model, false);
        for step in 0..24 {
            let a = step as f64 * 0.29;
            let q = [0.3 * a.cos(), -0.1 + a, a, 0.7, 0.2 * a.sin(), 2.0 * a];
            let v = [0.5, -1.2, 2.0 - a, -0.7, 0.9, -1.5 * a];
            let e = eval(&set, 0.1 * a, &q, &v);
            for k in 0..set.n_rows() {
                let mask = set.structural_components(k);
                let row = &e.rows[k];
                for c in 0..3 {
                    if !mask[c] {
                        assert!(
                            row.jac_a[c] == 0.0 && row.jac_b[c] == 0.0,
                            "row {k} component {c} at angle {a}: {row:?}"
                        );
                    }
                }
            }
        }
    }

    /// Φ_q against central differences of Φ, and γ against d/dt(Φ̇) along a path with q̈ = 0
    /// (then Φ̈ = (Φ_q q̇)_q q̇ + … = −γ exactly). Tolerance 1e-6: O(h²) difference error with h = 1e-5.
    #[test]
    fn jacobian_and_gamma_match_finite_differences() {
        let model = load_str(MODEL, "jac.toml", &[]).map_err(|e| e.to_string());
        let model = match model {
            Ok(m) => m,
            Err(e) => panic!("{e}"),
        };
        let set = ConstraintSet::from_model(&model, false);
        let q = [0.3, -0.1, 0.3, 0.7, 0.2, 0.5];
        let v = [0.5, -1.2, 2.0, -0.7, 0.9, -1.5];
        let t = 0.4;
        let base = eval(&set, t, &q, &v);
        let h = 1e-5;
        for k in 0..set.n_rows() {
            let jac = dense_jac(&base.rows[k], 6);
            for i in 0..6 {
                let (mut qp, mut qm) = (q, q);
                qp[i] += h;
                qm[i] -= h;
                let fd =
                    (eval(&set, t, &qp, &v).phi[k] - eval(&set, t, &qm, &v).phi[k]) / (2.0 * h);
                assert!(
                    (fd - jac[i]).abs() < 1e-6,
                    "row {k} coord {i}: fd {fd} vs {}",
                    jac[i]
                );
            }
            // Φ̇ = Φ_q v + Φ_t
            let pd: f64 = jac.iter().zip(&v).map(|(a, b)| a * b).sum::<f64>() + base.phi_t[k];
            assert!((pd - base.phi_dot[k]).abs() < 1e-12, "row {k}: phi_dot");
            // d/dt Φ̇(t, q + v t, v) = −γ for q̈ = 0.
            let qp: Vec<f64> = q.iter().zip(&v).map(|(a, b)| a + h * b).collect();
            let qm: Vec<f64> = q.iter().zip(&v).map(|(a, b)| a - h * b).collect();
            let dd = (eval(&set, t + h, &qp, &v).phi_dot[k]
                - eval(&set, t - h, &qm, &v).phi_dot[k])
                / (2.0 * h);
            assert!(
                (dd + base.gamma[k]).abs() < 1e-6,
                "row {k}: d/dt phi_dot {dd} vs -gamma {}",
                -base.gamma[k]
            );
        }
    }
}
