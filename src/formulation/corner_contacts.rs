//! The corner contacts of prismatic-clearance joints in absolute coordinates: where each
//! corner and the guide's material point under it are, and the site state the revolute
//! joint's contact code reads (`contact/corner.rs` for the geometry).
//!
//! A prismatic-clearance joint becomes four contact sites, one per slider corner, each with its
//! own δ event, stored impact velocity δ̇⁽⁻⁾ and output columns, and two more per guide end it
//! has (the two corners of the slider's face against that end stop, the same point-on-plane
//! contact with the plane across the guide); [`super::contacts::ContactSites`] numbers them
//! after the revolute clearance joints.

use super::contacts::SiteState;
use crate::contact::corner::{CornerMotion, coriolis_term, corner_kinematics, corner_offset};
use crate::contact::{ClearanceJoint, ContactForces, ContactLaw, impact_velocity};
use crate::mechanics::planar::{
    PointState, cross, perp, point_acceleration, point_state_with, rotate,
};
use crate::model::{Frame, JointId, JointKind, Model, PrismaticClearanceSpec};

/// Names of a joint's contact sites by [`CornerSite::corner`]: the four corners against the
/// guide surfaces (`contact/corner.rs`), then each corner against the guide's end stop on its
/// side, e1, e4 at `guide_start` (rear face) and e2, e3 at `guide_end` (front face). Output
/// columns `J.c1.delta` …, `J.e2.delta` ….
pub const SITE_NAMES: [&str; 8] = ["c1", "c2", "c3", "c4", "e1", "e2", "e3", "e4"];

/// The names of the contact sites of a prismatic-clearance joint with data `spec`, in the
/// order [`CornerSite::of_joint`] makes them: c1 … c4, then the end-stop sites its guide ends
/// give (e1 … e4, [`SITE_NAMES`]).
pub fn site_names(spec: &PrismaticClearanceSpec) -> impl Iterator<Item = &'static str> {
    (0..SITE_NAMES.len())
        .filter(move |&k| k < 4 || end_stop(spec, k - 4).is_some())
        .filter_map(|k| SITE_NAMES.get(k).copied())
}

/// The end stop that corner `i` (0..4 for c1..c4) meets, if the guide has it: the outward
/// normal's sign along the axis (+1 at `guide_end`, for the front corners c2, c3; −1 at
/// `guide_start`, for the rear corners c1, c4) and the stop's position s (m).
fn end_stop(spec: &PrismaticClearanceSpec, i: usize) -> Option<(f64, f64)> {
    match i {
        1 | 2 => spec.guide_end.map(|s| (1.0, s)),
        _ => spec.guide_start.map(|s| (-1.0, s)),
    }
}

/// Deepest penetration a corner contact is used at, as a fraction of the slider length: the
/// point-contact laws assume a penetration small against the bodies' size.
const MAX_PENETRATION_OF_LENGTH: f64 = 0.01;

/// One corner of a prismatic-clearance joint's slider against its guide surface.
#[derive(Debug, Clone)]
pub struct CornerSite {
    /// The joint in the model.
    pub joint: JointId,
    /// Which site: 0..4 for the corners c1..c4 against the guide surfaces, 4..8 for c1..c4
    /// against the guide's end stops (e1..e4, [`SITE_NAMES`]).
    pub corner: usize,
    /// The guide's frame (body a of the joint).
    pub guide: Frame,
    /// The centreline point O in the guide's frame (m).
    pub centreline: [f64; 2],
    /// Outward unit normal of the corner's surface in the guide's frame: ∓N for a guide surface,
    /// ±u for an end stop.
    pub normal: [f64; 2],
    /// Signed distance of the surface from O along the normal (m): h = w/2 + c for a guide
    /// surface, s₁ at the front end stop, −s₀ at the rear one.
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
        let site = |corner: usize, normal: [f64; 2], half_width: f64| {
            let (offset, _) = corner_offset(long, slider_length, slider_width, corner % 4);
            CornerSite {
                joint,
                corner,
                guide: j.a.frame,
                centreline: j.a.local,
                normal,
                half_width,
                slider: j.b.frame,
                point: [j.b.local[0] + offset[0], j.b.local[1] + offset[1]],
                contact,
                max_penetration: MAX_PENETRATION_OF_LENGTH * slider_length,
            }
        };
        let n = perp(axis);
        let surfaces = (0..4).map(|i| {
            let (_, side) = corner_offset(long, slider_length, slider_width, i);
            site(
                i,
                [side * n[0], side * n[1]],
                0.5 * slider_width + clearance,
            )
        });
        // An end stop is the plane s = s_k across the guide, outward normal ±u: with the normal
        // m = σ u, δ = (C − O)·m − σ s_k is the corner's distance past it.
        let ends = (0..4).filter_map(|i| {
            end_stop(spec, i)
                .map(|(sign, s)| site(4 + i, [sign * axis[0], sign * axis[1]], sign * s))
        });
        surfaces.chain(ends).collect()
    }

    /// True for a site against one of the guide's end stops (e1 … e4).
    pub fn is_end_stop(&self) -> bool {
        self.corner >= 4
    }

    /// True for the end-stop sites of the front face (e2, e3, at `guide_end`).
    pub fn normal_is_forward(&self) -> bool {
        matches!(self.corner, 5 | 6)
    }

    /// The site's name: the joint's name and the corner's, `J.c1`.
    pub fn name(&self, model: &Model) -> String {
        format!(
            "{}.{}",
            model.joint(self.joint).name,
            SITE_NAMES[self.corner.min(SITE_NAMES.len() - 1)]
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A slider (L = 0.1, w = 0.04) on a guide body turned by 0.3 rad with its axis at 30° in
    /// the guide's frame and stops at s₀ = −0.07, s₁ = 0.08: the sites are c1 … c4 then e1 … e4,
    /// and each end-stop site's δ is, by hand, the corner's position along the turned axis
    /// minus s₁ (front corners) or s₀ minus it (rear corners).
    #[test]
    fn end_stop_sites_measure_the_corners_past_the_stops() {
        let text = r#"
[model]
name = "stops"
[settings]
gravity = [0.0, 0.0]
[[bodies]]
name = "guide"
mass = 1.0
inertia = 0.01
points = { O = [0.0, 0.0] }
initial = { x = 0.0, y = 0.0, phi = 0.3 }
[[bodies]]
name = "slider"
mass = 1.0
inertia = 0.001
points = { C = [0.0, 0.0] }
initial = { x = 0.0, y = 0.0, phi = 0.3 }
[[joints]]
name = "rail"
type = "prismatic-clearance"
body_a = "guide"
point_a = "O"
body_b = "slider"
point_b = "C"
axis = [0.8660254037844386, 0.5]
angle = 0.0
clearance = 1e-3
slider_length = 0.1
slider_width = 0.04
stiffness = 1e9
guide_start = -0.07
guide_end = 0.08
"#;
        let model =
            crate::model::load_str(text, "stops.toml", &[]).unwrap_or_else(|e| panic!("{e}"));
        let Some(JointKind::PrismaticClearance(spec)) = model.joints.first().map(|j| &j.kind)
        else {
            panic!("no prismatic-clearance joint");
        };
        let names: Vec<&str> = site_names(spec).collect();
        assert_eq!(names, SITE_NAMES.to_vec());
        let sites = CornerSite::of_joint(&model, JointId(0));
        assert_eq!(sites.len(), 8);
        // Slider centre moved by (0.01, −0.02), slider turned 0.3 + 0.01 rad; guide at rest.
        let (phi_g, phi_s) = (0.3_f64, 0.31_f64);
        let q = [0.0, 0.0, phi_g, 0.01, -0.02, phi_s];
        let v = [0.0; 6];
        let u = rotate(phi_g.sin_cos(), [0.866_025_403_784_438_6, 0.5]);
        // The slider's long direction: the axis in its own frame (angle 0), turned by φ_s.
        let long = rotate(phi_s.sin_cos(), [0.866_025_403_784_438_6, 0.5]);
        let short = perp(long);
        for site in sites.iter().filter(|s| s.is_end_stop()) {
            let i = site.corner - 4;
            let (x, y) = [(-0.05, -0.02), (0.05, -0.02), (0.05, 0.02), (-0.05, 0.02)][i];
            let c = [
                0.01 + x * long[0] + y * short[0],
                -0.02 + x * long[1] + y * short[1],
            ];
            let along = c[0] * u[0] + c[1] * u[1];
            let by_hand = if matches!(i, 1 | 2) {
                along - 0.08
            } else {
                -0.07 - along
            };
            let delta = site.state_alone(&q, &v, 0.0).kinematics.delta;
            assert!(
                (delta - by_hand).abs() < 1e-15,
                "{}: δ = {delta}, by hand {by_hand}",
                SITE_NAMES[site.corner]
            );
            assert_eq!(site.normal_is_forward(), matches!(i, 1 | 2));
        }
    }
}
