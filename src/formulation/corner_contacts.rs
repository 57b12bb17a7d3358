//! The corner contacts of prismatic-clearance joints in absolute coordinates: where each
//! corner and the guide's material point under it are, and the site state the revolute
//! joint's contact code reads (`contact/corner.rs` for the geometry).
//!
//! A prismatic-clearance joint becomes four contact sites, one per slider corner, each with its
//! own δ event, stored impact velocity δ̇⁽⁻⁾ and output columns; [`super::contacts::ContactSites`]
//! numbers them after the revolute clearance joints.

use super::contacts::SiteState;
use crate::contact::corner::{CornerMotion, coriolis_term, corner_kinematics, corner_offset};
use crate::contact::{ClearanceJoint, ContactForces, ContactLaw, impact_velocity};
use crate::mechanics::planar::{
    PointState, cross, perp, point_acceleration, point_state_with, rotate,
};
use crate::model::{Frame, JointId, JointKind, Model, PrismaticClearanceSpec};

/// Names of the four corners, in order (`contact/corner.rs`): output columns `J.c1.delta` ….
pub const CORNER_NAMES: [&str; 4] = ["c1", "c2", "c3", "c4"];

/// Deepest penetration a corner contact is used at, as a fraction of the slider length: the
/// point-contact laws assume a penetration small against the bodies' size.
const MAX_PENETRATION_OF_LENGTH: f64 = 0.01;

/// One corner of a prismatic-clearance joint's slider against its guide surface.
#[derive(Debug, Clone)]
pub struct CornerSite {
    /// The joint in the model.
    pub joint: JointId,
    /// Which corner (0..4 for c1..c4).
    pub corner: usize,
    /// The guide's frame (body a of the joint).
    pub guide: Frame,
    /// The centreline point O in the guide's frame (m).
    pub centreline: [f64; 2],
    /// Outward unit normal of the corner's surface in the guide's frame.
    pub normal: [f64; 2],
    /// Distance h = w/2 + c of the surface from the centreline (m).
    pub half_width: f64,
    /// The slider's frame (body b of the joint).
    pub slider: Frame,
    /// The corner in the slider's frame (m).
    pub point: [f64; 2],
    /// Contact law and friction (radius 0, clearance c).
    pub contact: ClearanceJoint,
    /// Deepest penetration the law is used at (m).
    pub max_penetration: f64,
}

impl CornerSite {
    /// The four corner sites of a prismatic-clearance joint `joint` of `model`.
    pub fn of_joint(model: &Model, joint: JointId) -> Vec<CornerSite> {
        let j = model.joint(joint);
        let JointKind::PrismaticClearance(spec) = &j.kind else {
            return Vec::new();
        };
        let PrismaticClearanceSpec {
            axis,
            angle,
            clearance,
            slider_length,
            slider_width,
            ..
        } = *spec;
        let contact = ClearanceJoint {
            law: ContactLaw::power(
                spec.law,
                spec.damping,
                spec.stiffness,
                spec.exponent,
                spec.restitution,
            ),
            friction: spec.friction,
            journal_radius: 0.0,
            clearance,
            // No oil film in a guide (a lubricated guide is not modelled).
            lubrication: None,
        };
        // The slider's long direction in its own frame: the guide axis turned by −angle.
        let long = rotate((-angle).sin_cos(), axis);
        (0..4)
            .map(|i| {
                let (offset, side) = corner_offset(long, slider_length, slider_width, i);
                let n = perp(axis);
                CornerSite {
                    joint,
                    corner: i,
                    guide: j.a.frame,
                    centreline: j.a.local,
                    normal: [side * n[0], side * n[1]],
                    half_width: 0.5 * slider_width + clearance,
                    slider: j.b.frame,
                    point: [j.b.local[0] + offset[0], j.b.local[1] + offset[1]],
                    contact,
                    max_penetration: MAX_PENETRATION_OF_LENGTH * slider_length,
                }
            })
            .collect()
    }

    /// The site's name: the joint's name and the corner's, `J.c1`.
    pub fn name(&self, model: &Model) -> String {
        format!(
            "{}.{}",
            model.joint(self.joint).name,
            CORNER_NAMES[self.corner.min(3)]
        )
    }

    /// The bodies whose coordinates the site's forces depend on.
    pub fn bodies(&self) -> impl Iterator<Item = usize> {
        [self.slider, self.guide]
            .into_iter()
            .filter_map(|f| match f {
                Frame::Body(id) => Some(id.0),
                Frame::Ground => None,
            })
    }

    /// State of the corner at (q, q̇) with the stored impact velocity `stored` (0 = none), from
    /// the (sin φ, cos φ) of the slider's and the guide's bodies: the corner as the "journal",
    /// the guide's material point under it as the "bearing".
    pub fn state_with(
        &self,
        q: &[f64],
        v: &[f64],
        slider_sin_cos: (f64, f64),
        guide_sin_cos: (f64, f64),
        stored: f64,
    ) -> SiteState {
        let corner = point_state_with(self.slider, self.point, q, v, slider_sin_cos);
        let origin = point_state_with(self.guide, self.centreline, q, v, guide_sin_cos);
        let guide = match self.guide {
            Frame::Ground => PointState {
                position: corner.position,
                ..PointState::default()
            },
            Frame::Body(id) => {
                let k = 3 * id.0;
                let arm = [corner.position[0] - q[k], corner.position[1] - q[k + 1]];
                let omega = v[k + 2];
                let u = perp(arm);
                PointState {
                    position: corner.position,
                    velocity: [v[k] + omega * u[0], v[k + 1] + omega * u[1]],
                    arm,
                    omega,
                }
            }
        };
        let kinematics = corner_kinematics(&CornerMotion {
            corner: corner.position,
            corner_velocity: corner.velocity,
            guide_velocity: guide.velocity,
            centreline: origin.position,
            normal: match self.guide {
                Frame::Ground => self.normal,
                Frame::Body(_) => rotate(guide_sin_cos, self.normal),
            },
            half_width: self.half_width,
        });
        let forces = if kinematics.delta > 0.0 {
            self.contact
                .forces(&kinematics, impact_velocity(stored, kinematics.delta_dot))
        } else {
            ContactForces::default()
        };
        SiteState {
            bearing: guide,
            journal: corner,
            kinematics,
            forces,
            film: ContactForces::default(),
        }
    }

    /// [`CornerSite::state_with`] from the sines and cosines of every body.
    pub fn state(&self, q: &[f64], v: &[f64], sin_cos: &[(f64, f64)], stored: f64) -> SiteState {
        let of = |f: Frame| match f {
            Frame::Body(id) => sin_cos[id.0],
            Frame::Ground => (0.0, 1.0),
        };
        self.state_with(q, v, of(self.slider), of(self.guide), stored)
    }

    /// [`CornerSite::state_with`] evaluating the two bodies' sines and cosines only.
    pub fn state_alone(&self, q: &[f64], v: &[f64], stored: f64) -> SiteState {
        let of = |f: Frame| match f {
            Frame::Body(id) => q[3 * id.0 + 2].sin_cos(),
            Frame::Ground => (0.0, 1.0),
        };
        self.state_with(q, v, of(self.slider), of(self.guide), stored)
    }

    /// The state and the acceleration ë to hand to
    /// [`ContactKinematics::delta_ddot`](crate::contact::ContactKinematics::delta_ddot) for the
    /// body accelerations `acc` = q̈: a_C − a_Q plus the Coriolis term of the turning surface
    /// ([`coriolis_term`]), so that it returns the corner's exact δ̈.
    pub fn motion(&self, q: &[f64], v: &[f64], acc: &[f64], stored: f64) -> (SiteState, [f64; 2]) {
        let s = self.state_alone(q, v, stored);
        let a_c = body_point_acceleration(self.slider, &s.journal, acc);
        let a_q = body_point_acceleration(self.guide, &s.bearing, acc);
        let cor = coriolis_term(&s.kinematics, s.bearing.omega);
        (s, [a_c[0] - a_q[0] + cor[0], a_c[1] - a_q[1] + cor[1]])
    }
}

impl CornerSite {
    /// The corner's contribution to Q (3 per body: force x, y and moment about the centre of
    /// mass) on the slider and on the guide at (q, q̇), zero while free or on the ground.
    pub fn generalised_forces(&self, q: &[f64], v: &[f64], stored: f64) -> [[f64; 3]; 2] {
        let s = self.state_alone(q, v, stored);
        let on = |p: &PointState, f: [f64; 2]| [f[0], f[1], cross(p.arm, f)];
        [
            on(&s.journal, s.forces.on_journal),
            on(&s.bearing, s.forces.on_bearing),
        ]
    }
}

/// Acceleration of a body point (zero on the ground).
fn body_point_acceleration(frame: Frame, p: &PointState, acc: &[f64]) -> [f64; 2] {
    match frame {
        Frame::Ground => [0.0, 0.0],
        Frame::Body(id) => {
            let k = 3 * id.0;
            point_acceleration(p, [acc[k], acc[k + 1], acc[k + 2]])
        }
    }
}
