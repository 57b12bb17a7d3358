//! Applied forces as a generalised force vector Q (3 entries per body: Fx, Fy, moment).
//!
//! A force F at a body point with arm A s from the centre of mass contributes (F_x, F_y, (A s) × F).
//! Sign convention: counter-clockwise moments are positive.
//!
//! Forces and torques given as expressions of time and state (`torque = "-k*crank.phi"`,
//! `force = ["-gas(mod(theta, 4*pi))", 0]`) are evaluated at every call from (t, q, q̇): the
//! variables are read by [`state_variable`]. A torque driver (motor) on a revolute joint
//! applies +τ(t, θ, ω) to the joint's second body and −τ to its first, with θ = φ_b − φ_a and
//! ω = θ̇: the pair does no net work on the ground, and its power is τ ω.

use super::planar::{cross, point_state};
use crate::model::{Anchor, Expr, ForceElement, Frame, Model, Variable};

/// Value of a run-time variable of an expression at (t, q, q̇).
pub fn state_variable(var: Variable, t: f64, q: &[f64], v: &[f64]) -> f64 {
    let angle = |f: Frame, s: &[f64]| match f {
        Frame::Ground => 0.0,
        Frame::Body(id) => s.get(3 * id.0 + 2).copied().unwrap_or(f64::NAN),
    };
    match var {
        Variable::Time => t,
        Variable::Body { body, field } => {
            let (s, k) = if field < 3 {
                (q, field)
            } else {
                (v, field - 3)
            };
            s.get(3 * body.0 + k).copied().unwrap_or(f64::NAN)
        }
        Variable::JointAngle { a, b } => angle(b, q) - angle(a, q),
        Variable::JointSpeed { a, b } => angle(b, v) - angle(a, v),
    }
}

/// An expression evaluated at (t, q, q̇).
#[inline]
fn at_state(e: &Expr, t: f64, q: &[f64], v: &[f64]) -> f64 {
    e.eval(&|var| state_variable(var, t, q, v))
}

/// Gravity and the model's force elements, ready to evaluate.
#[derive(Debug, Clone)]
pub struct AppliedForces {
    /// m g per body (constant).
    weights: Vec<[f64; 2]>,
    elements: Vec<ForceElement>,
}

impl AppliedForces {
    /// From the model's masses, gravity and force elements.
    pub fn from_model(model: &Model) -> Self {
        let g = model.settings.gravity;
        AppliedForces {
            weights: model
                .bodies
                .iter()
                .map(|b| [b.mass * g[0], b.mass * g[1]])
                .collect(),
            elements: model.forces.clone(),
        }
    }

    /// Writes Q(t, q, q̇) into `out` (length 3 × bodies), overwriting it.
    pub fn evaluate_into(
        &self,
        t: f64,
        q: &[f64],
        v: &[f64],
        sin_cos: &[(f64, f64)],
        out: &mut [f64],
    ) {
        for (i, w) in self.weights.iter().enumerate() {
            out[3 * i] = w[0];
            out[3 * i + 1] = w[1];
            out[3 * i + 2] = 0.0;
        }
        for e in &self.elements {
            add_element_into(e, t, q, v, sin_cos, out);
        }
    }

    /// Number of force elements (gravity not counted).
    pub fn n_elements(&self) -> usize {
        self.elements.len()
    }

    /// Adds force element k's part of Q(t, q, q̇) to `out` (length 3 × bodies); nothing for an
    /// index out of range. Touches only the entries of [`AppliedForces::element_bodies`].
    pub fn add_element_into(
        &self,
        k: usize,
        t: f64,
        q: &[f64],
        v: &[f64],
        sin_cos: &[(f64, f64)],
        out: &mut [f64],
    ) {
        if let Some(e) = self.elements.get(k) {
            add_element_into(e, t, q, v, sin_cos, out);
        }
    }

    /// The bodies (indices) that force element k acts on or reads: the bodies of its points and
    /// of its joint, and those whose coordinates or speeds its expressions read (a joint
    /// angle's two bodies), sorted, without repeats. Its part of Q lies in the rows of these
    /// bodies and depends on their coordinates and speeds only (and t). Empty for an index out
    /// of range.
    pub fn element_bodies(&self, k: usize) -> Vec<usize> {
        let mut bodies = Vec::new();
        let mut frame = |f: Frame| {
            if let Frame::Body(id) = f {
                bodies.push(id.0);
            }
        };
        let reads = |e: &crate::model::Expr, frame: &mut dyn FnMut(Frame)| {
            e.for_each_variable(&mut |var| match var {
                Variable::Time => {}
                Variable::Body { body, .. } => frame(Frame::Body(body)),
                Variable::JointAngle { a, b } | Variable::JointSpeed { a, b } => {
                    frame(a);
                    frame(b);
                }
            });
        };
        match self.elements.get(k) {
            None => {}
            Some(ForceElement::SpringDamper { a, b, .. }) => {
                frame(a.frame);
                frame(b.frame);
            }
            Some(ForceElement::Torque { body, .. }) => frame(Frame::Body(*body)),
            Some(ForceElement::PointForce { at, .. }) => frame(at.frame),
            Some(ForceElement::TorqueLaw { body, torque, .. }) => {
                frame(Frame::Body(*body));
                reads(&torque.tree, &mut frame);
            }
            Some(ForceElement::ForceLaw { at, force, .. }) => {
                frame(at.frame);
                for f in force {
                    reads(&f.tree, &mut frame);
                }
            }
            Some(ForceElement::Motor { a, b, torque, .. }) => {
                frame(*a);
                frame(*b);
                reads(&torque.tree, &mut frame);
            }
        }
        bodies.sort_unstable();
        bodies.dedup();
        bodies
    }

    /// Power of the constant torques and point forces (W) and the rate at which the dampers of
    /// spring-dampers dissipate energy (W, ≥ 0), for energy bookkeeping. Gravity and spring
    /// stiffness are conservative: see [`AppliedForces::potential_energy`].
    pub fn power_split(&self, t: f64, q: &[f64], v: &[f64], sin_cos: &[(f64, f64)]) -> (f64, f64) {
        let (mut external, mut damping) = (0.0, 0.0);
        for e in &self.elements {
            match e {
                ForceElement::Torque { body, torque, .. } => external += torque * v[3 * body.0 + 2],
                ForceElement::PointForce { at, force, .. } => {
                    let p = point_state(at.frame, at.local, q, v, sin_cos);
                    external += force[0] * p.velocity[0] + force[1] * p.velocity[1];
                }
                ForceElement::TorqueLaw { body, torque, .. } => {
                    external += at_state(&torque.tree, t, q, v) * v[3 * body.0 + 2]
                }
                ForceElement::ForceLaw { at, force, .. } => {
                    let p = point_state(at.frame, at.local, q, v, sin_cos);
                    external += at_state(&force[0].tree, t, q, v) * p.velocity[0]
                        + at_state(&force[1].tree, t, q, v) * p.velocity[1];
                }
                ForceElement::Motor { a, b, torque, .. } => {
                    let omega = state_variable(Variable::JointSpeed { a: *a, b: *b }, t, q, v);
                    external += at_state(&torque.tree, t, q, v) * omega;
                }
                ForceElement::SpringDamper {
                    a, b, damping: c, ..
                } => {
                    if let Some(s) = SpringState::of(a, b, q, v, sin_cos) {
                        damping += c * s.rate * s.rate;
                    }
                }
            }
        }
        (external, damping)
    }

    /// Potential energy of gravity and springs (J), for energy checks.
    pub fn potential_energy(&self, q: &[f64], sin_cos: &[(f64, f64)]) -> f64 {
        let mut u = 0.0;
        for (i, w) in self.weights.iter().enumerate() {
            u -= w[0] * q[3 * i] + w[1] * q[3 * i + 1];
        }
        let zero = vec![0.0; q.len()];
        for e in &self.elements {
            if let ForceElement::SpringDamper {
                a,
                b,
                stiffness,
                free_length,
                ..
            } = e
            {
                let length = SpringState::of(a, b, q, &zero, sin_cos).map_or(0.0, |s| s.length);
                let stretch = length - free_length;
                u += 0.5 * stiffness * stretch * stretch;
            }
        }
        u
    }
}

/// Adds one force element's part of Q(t, q, q̇) to `out`.
fn add_element_into(
    e: &ForceElement,
    t: f64,
    q: &[f64],
    v: &[f64],
    sin_cos: &[(f64, f64)],
    out: &mut [f64],
) {
    match e {
        ForceElement::Torque { body, torque, .. } => out[3 * body.0 + 2] += torque,
        ForceElement::PointForce { at, force, .. } => {
            add_point_force(at, *force, q, v, sin_cos, out)
        }
        ForceElement::TorqueLaw { body, torque, .. } => {
            out[3 * body.0 + 2] += at_state(&torque.tree, t, q, v)
        }
        ForceElement::ForceLaw { at, force, .. } => {
            let f = [
                at_state(&force[0].tree, t, q, v),
                at_state(&force[1].tree, t, q, v),
            ];
            add_point_force(at, f, q, v, sin_cos, out)
        }
        ForceElement::Motor { a, b, torque, .. } => {
            let tau = at_state(&torque.tree, t, q, v);
            if let Frame::Body(id) = b {
                out[3 * id.0 + 2] += tau;
            }
            if let Frame::Body(id) = a {
                out[3 * id.0 + 2] -= tau;
            }
        }
        ForceElement::SpringDamper {
            a,
            b,
            stiffness,
            damping,
            free_length,
            ..
        } => {
            // Coincident points leave the direction undefined: no force, as for any
            // element of zero length.
            let Some(s) = SpringState::of(a, b, q, v, sin_cos) else {
                return;
            };
            let tension = stiffness * (s.length - free_length) + damping * s.rate;
            let u = s.direction;
            // Tension pulls b towards a and a towards b.
            add_point_force(a, [tension * u[0], tension * u[1]], q, v, sin_cos, out);
            add_point_force(b, [-tension * u[0], -tension * u[1]], q, v, sin_cos, out);
        }
    }
}

/// Length, rate of extension and unit direction (a → b) of a spring-damper.
struct SpringState {
    length: f64,
    rate: f64,
    direction: [f64; 2],
}

impl SpringState {
    /// `None` when the two points coincide (direction undefined).
    fn of(a: &Anchor, b: &Anchor, q: &[f64], v: &[f64], sin_cos: &[(f64, f64)]) -> Option<Self> {
        let pa = point_state(a.frame, a.local, q, v, sin_cos);
        let pb = point_state(b.frame, b.local, q, v, sin_cos);
        let d = [
            pb.position[0] - pa.position[0],
            pb.position[1] - pa.position[1],
        ];
        let length = d[0].hypot(d[1]);
        if length < 1e-12 {
            return None;
        }
        let direction = [d[0] / length, d[1] / length];
        let rate = direction[0] * (pb.velocity[0] - pa.velocity[0])
            + direction[1] * (pb.velocity[1] - pa.velocity[1]);
        Some(SpringState {
            length,
            rate,
            direction,
        })
    }
}

/// Adds force F at an anchor (nothing if on the ground).
#[inline]
pub fn add_point_force(
    at: &Anchor,
    force: [f64; 2],
    q: &[f64],
    v: &[f64],
    sin_cos: &[(f64, f64)],
    out: &mut [f64],
) {
    if let Frame::Body(id) = at.frame {
        let p = point_state(at.frame, at.local, q, v, sin_cos);
        out[3 * id.0] += force[0];
        out[3 * id.0 + 1] += force[1];
        out[3 * id.0 + 2] += cross(p.arm, force);
    }
}
