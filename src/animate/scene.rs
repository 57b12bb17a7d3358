//! The mechanism at one instant as a backend-neutral scene: [`draw`] turns a model and an
//! [`Instant`] into [`Item`]s in world coordinates (m); a [`View`] maps them to a [`Picture`]
//! of pixel [`Mark`]s that the PNG, SVG, HTML and GIF writers draw as they are. Every still
//! figure and every animation frame comes from [`draw`], so they look alike.

use crate::model::{Anchor, Frame, Joint, JointKind, Model, Shape};

/// An sRGB colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Colour(pub u8, pub u8, pub u8);

impl Colour {
    /// `#rrggbb`.
    pub fn hex(self) -> String {
        format!("#{:02x}{:02x}{:02x}", self.0, self.1, self.2)
    }
}

/// Body colours in model order (the "tab10" palette of the other figures), repeating.
pub const BODY_COLOURS: [Colour; 6] = [
    Colour(31, 119, 180),
    Colour(214, 39, 40),
    Colour(44, 160, 44),
    Colour(255, 127, 14),
    Colour(148, 103, 189),
    Colour(140, 86, 75),
];
/// Background.
pub const BACKGROUND: Colour = Colour(255, 255, 255);
/// Text, outlines of pins and clearance circles.
pub const INK: Colour = Colour(40, 40, 40);
/// Ground pivots.
pub const GROUND: Colour = Colour(120, 120, 120);
/// Magnified journal centre of a clearance joint.
pub const JOURNAL: Colour = Colour(23, 190, 207);
/// The journal centre's path inside the clearance circle.
pub const TRAIL: Colour = Colour(188, 189, 34);
/// Contact-force arrows.
pub const FORCE: Colour = Colour(227, 0, 140);

/// The colour of body number `k`.
pub fn body_colour(k: usize) -> Colour {
    BODY_COLOURS[k % BODY_COLOURS.len()]
}

/// Width of the lines that draw a body without shapes (px).
pub const BODY_LINE_PX: f64 = 5.0;
/// Radius of a ground-pivot dot (px).
pub const GROUND_DOT_PX: f64 = 8.0;
/// Radius of a pin (joint) dot (px).
pub const PIN_DOT_PX: f64 = 4.0;
/// Font size of the caption lines (px).
pub const TEXT_PX: f64 = 15.0;
/// Height of the caption band above the mechanism and of the legend band below it (px).
const TOP_BAND_PX: f64 = 50.0;
const BOTTOM_BAND_PX: f64 = 30.0;
/// Margin left and right of the mechanism (px).
const SIDE_PX: f64 = 16.0;
/// Width of the line that draws a prismatic joint's rail (px).
pub const RAIL_PX: f64 = 3.0;
/// Side of the square that draws a body with one point (or none) and no shapes, such as a
/// slider, as a fraction of the model's longest body (the largest distance between two points
/// of one body): a block in proportion to the linkage at any scale.
pub const SLIDER_BLOCK_FRACTION: f64 = 0.15;
/// That side where no body has two points (m): a model of lone sliders has no length to take.
const SLIDER_BLOCK_M: f64 = 0.05;
/// Points on a drawn circle or round bar end.
const ARC_POINTS: usize = 16;

/// The state of a mechanism at one time, as [`draw`] needs it.
#[derive(Debug, Clone, PartialEq)]
pub struct Instant {
    /// Time (s).
    pub t: f64,
    /// Pose (x, y, φ) of each body of the model, in model order (m, m, rad).
    pub poses: Vec<[f64; 3]>,
    /// Per joint of the model: (F_N, F_T) of a clearance joint when known (N); see
    /// [`crate::contact::kinematics`] for the signs.
    pub contact: Vec<Option<[f64; 2]>>,
    /// Per joint: the eccentricities e = journal − bearing centre (m, global) from the start to
    /// `t`, the last one at `t` (empty for joints without clearance).
    pub history: Vec<Vec<[f64; 2]>>,
    /// Per joint: of a prismatic joint, the least and the greatest [`slide`] over the whole
    /// run (m), so that its rail is drawn the same length in every frame; `None` for other
    /// joints (and where unknown: the rail then spans the slider's place at `t`).
    pub travel: Vec<Option<[f64; 2]>>,
}

/// What [`draw`] is asked to show besides the mechanism.
#[derive(Debug, Clone, PartialEq)]
pub struct DrawOptions {
    /// Title (the model name by default).
    pub title: String,
    /// Factor on clearance circles, journal offsets and journal paths (≥ 1).
    pub magnify: f64,
    /// Contact-force arrows: metres of arrow per newton; `None` draws no arrows.
    pub force_scale: Option<f64>,
}

/// A drawing element in world coordinates (m); sizes in `_px` are in pixels.
#[derive(Debug, Clone, PartialEq)]
pub enum Item {
    /// A polyline (closed: back to its first point).
    Line {
        /// Points (m).
        points: Vec<[f64; 2]>,
        /// Closed.
        closed: bool,
        /// Colour.
        colour: Colour,
        /// Width (px).
        width_px: f64,
    },
    /// A filled polygon with an outline.
    Area {
        /// Corners (m).
        points: Vec<[f64; 2]>,
        /// Fill.
        fill: Colour,
        /// Outline (1.5 px).
        outline: Colour,
    },
    /// A circle of radius `radius` (m), outlined.
    Ring {
        /// Centre (m).
        centre: [f64; 2],
        /// Radius (m).
        radius: f64,
        /// Outline colour.
        colour: Colour,
        /// Outline width (px).
        width_px: f64,
    },
    /// A dot of a fixed size in pixels.
    Dot {
        /// Centre (m).
        centre: [f64; 2],
        /// Radius (px).
        radius_px: f64,
        /// Fill.
        fill: Colour,
        /// Outline (1.5 px), if any.
        outline: Option<Colour>,
    },
    /// An arrow from `from` to `to` (m); left out of the view's bounds.
    Arrow {
        /// Tail (m).
        from: [f64; 2],
        /// Tip (m).
        to: [f64; 2],
        /// Colour.
        colour: Colour,
    },
    /// A path given as an origin and offsets from it (m): the journal centre's path drawn
    /// around the current bearing centre. Offsets of a later instant extend those of an
    /// earlier one, which the HTML and SVG writers use to store the path once.
    Trail {
        /// Origin (m).
        origin: [f64; 2],
        /// Offsets (m).
        offsets: Vec<[f64; 2]>,
        /// Colour.
        colour: Colour,
    },
}

/// The mechanism at one instant, in world coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Elements, drawn in order.
    pub items: Vec<Item>,
    /// Caption lines above the mechanism (title and time first).
    pub caption: Vec<String>,
    /// Body names with their colours (legend below the mechanism).
    pub legend: Vec<(String, Colour)>,
    /// Metres of arrow per newton, when contact-force arrows are drawn.
    pub force_scale: Option<f64>,
}

/// Global position of an anchor given the poses (x, y, φ) of the bodies:
/// r = (x, y) + R(φ)·s for a body point s, the point itself on the ground.
pub fn global(anchor: &Anchor, poses: &[[f64; 3]]) -> Option<[f64; 2]> {
    match anchor.frame {
        Frame::Ground => Some(anchor.local),
        Frame::Body(id) => Some(to_global(*poses.get(id.0)?, anchor.local)),
    }
}

/// r = (x, y) + R(φ)·s for the body-frame point s of a body at `pose` (x, y, φ).
pub fn to_global(pose: [f64; 3], s: [f64; 2]) -> [f64; 2] {
    let [x, y, phi] = pose;
    let (sn, c) = phi.sin_cos();
    [x + c * s[0] - sn * s[1], y + sn * s[0] + c * s[1]]
}

/// The global direction (unit) of a prismatic joint's axis, given in the frame of its body a.
fn rail_direction(joint: &Joint, axis: [f64; 2], poses: &[[f64; 3]]) -> Option<[f64; 2]> {
    let phi = match joint.a.frame {
        Frame::Ground => 0.0,
        Frame::Body(id) => poses.get(id.0)?[2],
    };
    let (sn, c) = phi.sin_cos();
    Some([c * axis[0] - sn * axis[1], sn * axis[0] + c * axis[1]])
}

/// How far point b of a prismatic joint is from point a along the joint's axis (m): the
/// slider's place on its rail. `None` for other joints.
pub fn slide(joint: &Joint, poses: &[[f64; 3]]) -> Option<f64> {
    let axis = rail_axis(joint)?;
    let (a, b) = (global(&joint.a, poses)?, global(&joint.b, poses)?);
    let u = rail_direction(joint, axis, poses)?;
    Some((b[0] - a[0]) * u[0] + (b[1] - a[1]) * u[1])
}

/// The sliding axis of a prismatic or prismatic-clearance joint (frame of its body a).
pub fn rail_axis(joint: &Joint) -> Option<[f64; 2]> {
    match &joint.kind {
        JointKind::Prismatic { axis, .. } => Some(*axis),
        JointKind::PrismaticClearance(p) => Some(p.axis),
        _ => None,
    }
}

/// Offsets of a joint's rail lines from its centreline (m): one line (0) for a prismatic
/// joint, the guide's two surfaces ±(w/2 + c) for a prismatic-clearance joint.
fn rail_offsets(joint: &Joint) -> Vec<f64> {
    match &joint.kind {
        JointKind::PrismaticClearance(p) => {
            let h = 0.5 * p.slider_width + p.clearance;
            vec![-h, h]
        }
        _ => vec![0.0],
    }
}

/// The side of a slider block (m): [`SLIDER_BLOCK_FRACTION`] of the model's longest body.
pub fn slider_block_side(model: &Model) -> f64 {
    let longest = model
        .bodies
        .iter()
        .flat_map(|b| {
            b.points.iter().flat_map(|(_, p)| {
                b.points
                    .iter()
                    .map(move |(_, q)| (p[0] - q[0]).hypot(p[1] - q[1]))
            })
        })
        .fold(0.0, f64::max);
    if longest > 0.0 {
        SLIDER_BLOCK_FRACTION * longest
    } else {
        SLIDER_BLOCK_M
    }
}

/// The crank angle (degrees in [0, 360)): the relative angle φ_b − φ_a of the joint of the
/// model's first driver (the ground counts φ = 0); `None` without a driver.
pub fn crank_angle(model: &Model, poses: &[[f64; 3]]) -> Option<f64> {
    let driver = model.drivers.first()?;
    let joint = model.joints.get(driver.joint.0)?;
    let phi = |f: Frame| match f {
        Frame::Ground => Some(0.0),
        Frame::Body(id) => poses.get(id.0).map(|p| p[2]),
    };
    let rel = phi(joint.b.frame)? - phi(joint.a.frame)?;
    Some(rel.to_degrees().rem_euclid(360.0))
}

/// Points on a circle of radius `r` around `c`.
fn circle(c: [f64; 2], r: f64) -> Vec<[f64; 2]> {
    (0..ARC_POINTS * 2)
        .map(|i| {
            let q = std::f64::consts::TAU * i as f64 / (ARC_POINTS * 2) as f64;
            [c[0] + r * q.cos(), c[1] + r * q.sin()]
        })
        .collect()
}

/// The outline of a bar of width `w` from `a` to `b` with round ends (a stadium).
fn stadium(a: [f64; 2], b: [f64; 2], w: f64) -> Vec<[f64; 2]> {
    let r = w / 2.0;
    let q0 = (b[1] - a[1]).atan2(b[0] - a[0]);
    let half = |centre: [f64; 2], start: f64| {
        (0..=ARC_POINTS).map(move |i| {
            let q = start + std::f64::consts::PI * i as f64 / ARC_POINTS as f64;
            [centre[0] + r * q.cos(), centre[1] + r * q.sin()]
        })
    };
    let quarter = std::f64::consts::FRAC_PI_2;
    half(b, q0 - quarter).chain(half(a, q0 + quarter)).collect()
}

/// The mechanism of `model` at `now`: first each prismatic joint's rail, a grey line along its
/// axis over the slider's travel and a block beyond either end (a guide with clearance: its two
/// surfaces, reaching its end stops, and each stop a grey line across it); each body as its shapes
/// (filled in the body's colour), or without shapes as a line through its points (closed when
/// it has three or more), a body with one point or none as a square block of side
/// [`slider_block_side`] about it (a slider); then
/// ground points as grey dots and pins as white dots; each clearance joint's clearance circle (radius c)
/// around the bearing centre, the journal centre's path and the journal centre itself at
/// `magnify` times their true offsets; the contact force on each journal as an arrow from the
/// magnified journal centre, F_J = −F_N n + F_T t (n from bearing to journal centre), at
/// `force_scale` m/N.
///
/// The items come in the same order and number at every instant (an arrow of zero force has
/// zero length), so frames of an animation correspond item by item.
pub fn draw(model: &Model, now: &Instant, options: &DrawOptions) -> Scene {
    let poses = &now.poses;
    let mut items = Vec::new();
    let mut legend = Vec::new();
    let block = slider_block_side(model);
    // Rails first, under the bodies that slide on them.
    for (k, j) in model.joints.iter().enumerate() {
        let Some(axis) = rail_axis(j) else {
            continue;
        };
        let (Some(a), Some(u), Some(here)) = (
            global(&j.a, poses),
            rail_direction(j, axis, poses),
            slide(j, poses),
        ) else {
            continue;
        };
        let [lo, hi] = now.travel.get(k).copied().flatten().unwrap_or([here, here]);
        let n = [-u[1], u[0]];
        // A guide with clearance: its two surfaces, the slider drawn between them.
        let reach = match &j.kind {
            JointKind::PrismaticClearance(p) => 0.5 * p.slider_length + block,
            _ => block,
        };
        // The guide's end stops, where it has them: the rails reach them, and each is a line
        // across the guide between its two surfaces.
        let stops = match &j.kind {
            JointKind::PrismaticClearance(p) => [p.guide_start, p.guide_end],
            _ => [None, None],
        };
        let from = stops[0].map_or(lo.min(here) - reach, |s| s.min(lo.min(here) - reach));
        let to = stops[1].map_or(hi.max(here) + reach, |s| s.max(hi.max(here) + reach));
        let at = |s: f64, off: f64| [a[0] + s * u[0] + off * n[0], a[1] + s * u[1] + off * n[1]];
        let offsets = rail_offsets(j);
        for &off in &offsets {
            items.push(Item::Line {
                points: vec![at(from, off), at(to, off)],
                closed: false,
                colour: GROUND,
                width_px: RAIL_PX,
            });
        }
        let (first, last) = (
            offsets.first().copied().unwrap_or(0.0),
            offsets.last().copied().unwrap_or(0.0),
        );
        for stop in stops.into_iter().flatten() {
            items.push(Item::Line {
                points: vec![at(stop, first), at(stop, last)],
                closed: false,
                colour: GROUND,
                width_px: RAIL_PX,
            });
        }
    }
    for (k, (body, pose)) in model.bodies.iter().zip(poses).enumerate() {
        let colour = body_colour(k);
        legend.push((body.name.clone(), colour));
        let outline = Colour(colour.0 / 2, colour.1 / 2, colour.2 / 2);
        let g = |s: [f64; 2]| to_global(*pose, s);
        if body.shapes.is_empty() && body.points.len() <= 1 {
            // A slider (or a lone mass): a line through one point would not show.
            let c = body.points.first().map_or([0.0, 0.0], |(_, s)| *s);
            let h = block / 2.0;
            items.push(Item::Area {
                points: [[-h, -h], [h, -h], [h, h], [-h, h]]
                    .iter()
                    .map(|d| g([c[0] + d[0], c[1] + d[1]]))
                    .collect(),
                fill: colour,
                outline,
            });
        } else if body.shapes.is_empty() {
            items.push(Item::Line {
                points: body.points.iter().map(|(_, s)| g(*s)).collect(),
                closed: body.points.len() >= 3,
                colour,
                width_px: BODY_LINE_PX,
            });
        }
        for shape in &body.shapes {
            let points = match shape {
                Shape::Bar { from, to, width } => stadium(g(*from), g(*to), *width),
                Shape::Polygon { vertices } => vertices.iter().map(|v| g(*v)).collect(),
                Shape::Disc { centre, radius } => circle(g(*centre), *radius),
            };
            items.push(Item::Area {
                points,
                fill: colour,
                outline,
            });
        }
    }
    // Ground pivots over the bodies, so that a bar does not hide where it is pinned.
    for (_, p) in &model.ground_points {
        items.push(Item::Dot {
            centre: *p,
            radius_px: GROUND_DOT_PX,
            fill: GROUND,
            outline: None,
        });
    }
    let mut clearance = Vec::new();
    for (k, j) in model.joints.iter().enumerate() {
        let (Some(a), Some(b)) = (global(&j.a, poses), global(&j.b, poses)) else {
            continue;
        };
        match &j.kind {
            JointKind::Clearance(spec) => clearance.push((k, a, b, spec.clearance)),
            _ => items.push(Item::Dot {
                centre: b,
                radius_px: PIN_DOT_PX,
                fill: BACKGROUND,
                outline: Some(INK),
            }),
        }
    }
    let m = options.magnify;
    for (k, a, b, c) in clearance {
        let e = [b[0] - a[0], b[1] - a[1]];
        let journal = [a[0] + m * e[0], a[1] + m * e[1]];
        items.push(Item::Ring {
            centre: a,
            radius: m * c,
            colour: INK,
            width_px: 1.5,
        });
        let offsets = now
            .history
            .get(k)
            .map(|h| h.iter().map(|e| [m * e[0], m * e[1]]).collect())
            .unwrap_or_default();
        items.push(Item::Trail {
            origin: a,
            offsets,
            colour: TRAIL,
        });
        items.push(Item::Dot {
            centre: journal,
            radius_px: PIN_DOT_PX,
            fill: JOURNAL,
            outline: Some(INK),
        });
        if let Some(scale) = options.force_scale {
            let [f_n, f_t] = now.contact.get(k).copied().flatten().unwrap_or([0.0, 0.0]);
            let len = e[0].hypot(e[1]);
            // A centred journal has no normal; no force acts on it then.
            let n = if len > 0.0 {
                [e[0] / len, e[1] / len]
            } else {
                [1.0, 0.0]
            };
            let t = [-n[1], n[0]];
            let f = [-f_n * n[0] + f_t * t[0], -f_n * n[1] + f_t * t[1]];
            let f = if f[0].is_finite() && f[1].is_finite() {
                f
            } else {
                [0.0, 0.0]
            };
            items.push(Item::Arrow {
                from: journal,
                to: [journal[0] + scale * f[0], journal[1] + scale * f[1]],
                colour: FORCE,
            });
        }
    }
    let mut head = format!("{}   t = {:.4} s", options.title, now.t);
    if let Some(angle) = crank_angle(model, poses) {
        head.push_str(&format!("   crank {angle:.1}°"));
    }
    let mut caption = vec![head];
    if model.has_clearance_joints() {
        caption.push(format!(
            "clearance circles, journal offsets and paths × {}",
            crate::numbers::format_number(m)
        ));
    }
    Scene {
        items,
        caption,
        legend,
        force_scale: options.force_scale,
    }
}

/// An axis-aligned box in world coordinates (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    /// Lower-left corner.
    pub min: [f64; 2],
    /// Upper-right corner.
    pub max: [f64; 2],
}

impl Default for Bounds {
    fn default() -> Self {
        Bounds {
            min: [f64::INFINITY; 2],
            max: [f64::NEG_INFINITY; 2],
        }
    }
}

impl Bounds {
    /// Widens the box to hold `p` (non-finite points are ignored).
    pub fn add(&mut self, p: [f64; 2]) {
        if p[0].is_finite() && p[1].is_finite() {
            for i in 0..2 {
                self.min[i] = self.min[i].min(p[i]);
                self.max[i] = self.max[i].max(p[i]);
            }
        }
    }

    /// Widens the box to hold `other`.
    pub fn join(&mut self, other: &Bounds) {
        self.add(other.min);
        self.add(other.max);
    }

    /// True if no point was added.
    pub fn is_empty(&self) -> bool {
        !(self.min[0] <= self.max[0] && self.min[1] <= self.max[1])
    }
}

impl Scene {
    /// The box around everything but the force arrows (whose length follows the force, not the
    /// mechanism) and the pixel-sized dots' radii.
    pub fn bounds(&self) -> Bounds {
        let mut b = Bounds::default();
        for item in &self.items {
            match item {
                Item::Line { points, .. } | Item::Area { points, .. } => {
                    points.iter().for_each(|p| b.add(*p))
                }
                Item::Ring { centre, radius, .. } => {
                    b.add([centre[0] - radius, centre[1] - radius]);
                    b.add([centre[0] + radius, centre[1] + radius]);
                }
                Item::Dot { centre, .. } => b.add(*centre),
                Item::Arrow { .. } => {}
                Item::Trail {
                    origin, offsets, ..
                } => offsets
                    .iter()
                    .for_each(|o| b.add([origin[0] + o[0], origin[1] + o[1]])),
            }
        }
        b
    }

    /// The scene in pixels through `view`.
    pub fn to_picture(&self, view: &View) -> Picture {
        let px = |p: &[f64; 2]| view.to_px(*p);
        let mut marks = Vec::with_capacity(self.items.len() + 8);
        for item in &self.items {
            match item {
                Item::Line {
                    points,
                    closed,
                    colour,
                    width_px,
                } => marks.push(Mark::Path {
                    points: points.iter().map(px).collect(),
                    closed: *closed,
                    stroke: *colour,
                    width: *width_px,
                }),
                Item::Area {
                    points,
                    fill,
                    outline,
                } => marks.push(Mark::Polygon {
                    points: points.iter().map(px).collect(),
                    fill: *fill,
                    stroke: Some((*outline, 1.5)),
                }),
                Item::Ring {
                    centre,
                    radius,
                    colour,
                    width_px,
                } => marks.push(Mark::Circle {
                    centre: px(centre),
                    radius: radius * view.scale,
                    fill: None,
                    stroke: Some((*colour, *width_px)),
                }),
                Item::Dot {
                    centre,
                    radius_px,
                    fill,
                    outline,
                } => marks.push(Mark::Circle {
                    centre: px(centre),
                    radius: *radius_px,
                    fill: Some(*fill),
                    stroke: outline.map(|c| (c, 1.5)),
                }),
                Item::Arrow { from, to, colour } => {
                    let (shaft, head) = arrow(px(from), px(to));
                    marks.push(Mark::Path {
                        points: shaft,
                        closed: false,
                        stroke: *colour,
                        width: 2.5,
                    });
                    marks.push(Mark::Polygon {
                        points: head,
                        fill: *colour,
                        stroke: None,
                    });
                }
                Item::Trail {
                    origin,
                    offsets,
                    colour,
                } => marks.push(Mark::Trail {
                    origin: px(origin),
                    offsets: offsets
                        .iter()
                        .map(|o| [o[0] * view.scale, -o[1] * view.scale])
                        .collect(),
                    stroke: *colour,
                    width: 1.0,
                }),
            }
        }
        let (w, h) = (f64::from(view.size.0), f64::from(view.size.1));
        for (i, line) in self.caption.iter().enumerate() {
            marks.push(Mark::Text {
                at: [SIDE_PX * 0.75, 20.0 + 20.0 * i as f64],
                text: line.clone(),
                size: TEXT_PX,
                colour: INK,
            });
        }
        let base = h - 10.0;
        let mut x = SIDE_PX * 0.75;
        for (name, colour) in &self.legend {
            marks.push(Mark::Polygon {
                points: vec![
                    [x, base - 10.0],
                    [x + 14.0, base - 10.0],
                    [x + 14.0, base],
                    [x, base],
                ],
                fill: *colour,
                stroke: None,
            });
            marks.push(Mark::Text {
                at: [x + 18.0, base],
                text: name.clone(),
                size: TEXT_PX,
                colour: INK,
            });
            x += 30.0 + text_width(name, TEXT_PX);
        }
        if let Some(scale) = self.force_scale {
            let (force, len) = legend_force(scale * view.scale);
            let label = format!("contact force {} N", crate::numbers::format_number(force));
            let x1 = w - SIDE_PX * 0.75;
            let x0 = x1 - len;
            let (shaft, head) = arrow([x0, base - 5.0], [x1, base - 5.0]);
            marks.push(Mark::Path {
                points: shaft,
                closed: false,
                stroke: FORCE,
                width: 2.5,
            });
            marks.push(Mark::Polygon {
                points: head,
                fill: FORCE,
                stroke: None,
            });
            marks.push(Mark::Text {
                at: [x0 - 8.0 - text_width(&label, TEXT_PX), base],
                text: label,
                size: TEXT_PX,
                colour: INK,
            });
        }
        Picture {
            size: view.size,
            marks,
        }
    }
}

/// A width estimate of `text` at `size` px (DejaVu Sans averages about 0.6 em per character),
/// for laying out the legend without measuring glyphs.
fn text_width(text: &str, size: f64) -> f64 {
    0.6 * size * text.chars().count() as f64
}

/// The force the legend arrow stands for (1, 2 or 5 × 10^k N) and its length (px), given the
/// pixels per newton: the round force whose arrow is between 40 and 100 px.
fn legend_force(px_per_newton: f64) -> (f64, f64) {
    if !(px_per_newton.is_finite() && px_per_newton > 0.0) {
        return (0.0, 0.0);
    }
    let target = 60.0 / px_per_newton;
    let decade = 10f64.powf(target.log10().floor());
    let force = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * decade)
        .find(|f| f * px_per_newton >= 40.0)
        .unwrap_or(10.0 * decade);
    (force, force * px_per_newton)
}

/// The shaft (two points) and head (triangle) of an arrow from `a` to `b` in pixels. The head
/// is at most 12 px long and at most 40 % of the arrow, so a zero force draws nothing visible.
fn arrow(a: [f64; 2], b: [f64; 2]) -> (Vec<[f64; 2]>, Vec<[f64; 2]>) {
    let d = [b[0] - a[0], b[1] - a[1]];
    let len = d[0].hypot(d[1]);
    let (u, head) = if len > 0.0 {
        ([d[0] / len, d[1] / len], (0.4 * len).min(12.0))
    } else {
        ([1.0, 0.0], 0.0)
    };
    let base = [b[0] - head * u[0], b[1] - head * u[1]];
    let side = [-u[1] * head * 0.45, u[0] * head * 0.45];
    (
        vec![a, base],
        vec![
            b,
            [base[0] + side[0], base[1] + side[1]],
            [base[0] - side[0], base[1] - side[1]],
        ],
    )
}

/// A drawing element in pixels (y down), as every writer draws it.
#[derive(Debug, Clone, PartialEq)]
pub enum Mark {
    /// A polyline.
    Path {
        /// Points (px).
        points: Vec<[f64; 2]>,
        /// Back to the first point.
        closed: bool,
        /// Colour.
        stroke: Colour,
        /// Width (px).
        width: f64,
    },
    /// A filled polygon, optionally outlined (colour, width px).
    Polygon {
        /// Corners (px).
        points: Vec<[f64; 2]>,
        /// Fill.
        fill: Colour,
        /// Outline.
        stroke: Option<(Colour, f64)>,
    },
    /// A circle, filled and/or outlined (colour, width px).
    Circle {
        /// Centre (px).
        centre: [f64; 2],
        /// Radius (px).
        radius: f64,
        /// Fill.
        fill: Option<Colour>,
        /// Outline.
        stroke: Option<(Colour, f64)>,
    },
    /// A polyline through origin + offsets (px).
    Trail {
        /// Origin (px).
        origin: [f64; 2],
        /// Offsets (px, y down).
        offsets: Vec<[f64; 2]>,
        /// Colour.
        stroke: Colour,
        /// Width (px).
        width: f64,
    },
    /// Text, left-aligned on its baseline.
    Text {
        /// Left end of the baseline (px).
        at: [f64; 2],
        /// The text.
        text: String,
        /// Font size (px).
        size: f64,
        /// Colour.
        colour: Colour,
    },
}

impl Mark {
    /// The kind's name, for matching frames mark by mark.
    pub fn kind(&self) -> &'static str {
        match self {
            Mark::Path { .. } => "path",
            Mark::Polygon { .. } => "polygon",
            Mark::Circle { .. } => "circle",
            Mark::Trail { .. } => "trail",
            Mark::Text { .. } => "text",
        }
    }
}

/// A picture in pixels: what a writer draws, on a white background.
#[derive(Debug, Clone, PartialEq)]
pub struct Picture {
    /// Width and height (px).
    pub size: (u32, u32),
    /// Marks, drawn in order.
    pub marks: Vec<Mark>,
}

/// World (m, y up) to pixels (y down) with equal scales: p_px = origin + scale·(x, −y).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// Pixels per metre.
    pub scale: f64,
    /// Pixel position of the world origin.
    pub origin: [f64; 2],
    /// Picture size (px).
    pub size: (u32, u32),
}

impl View {
    /// The view that shows `bounds` as large as fits in a picture of `size`, centred between
    /// a caption band at the top, a legend band at the bottom and margins at the sides, with
    /// room for the largest dot. An empty or single-point box gets a 1 m extent.
    pub fn fit(bounds: &Bounds, size: (u32, u32)) -> View {
        let (w, h) = (f64::from(size.0), f64::from(size.1));
        let pad = SIDE_PX + GROUND_DOT_PX;
        let (x_lo, x_hi) = (pad, (w - pad).max(pad + 1.0));
        let (y_lo, y_hi) = (
            TOP_BAND_PX + GROUND_DOT_PX,
            (h - BOTTOM_BAND_PX - GROUND_DOT_PX).max(TOP_BAND_PX + GROUND_DOT_PX + 1.0),
        );
        let (min, max) = if bounds.is_empty() {
            ([-0.5, -0.5], [0.5, 0.5])
        } else {
            (bounds.min, bounds.max)
        };
        let span = |i: usize| {
            let s = max[i] - min[i];
            if s > 0.0 { s } else { 1.0 }
        };
        let scale = ((x_hi - x_lo) / span(0)).min((y_hi - y_lo) / span(1));
        let centre = [(min[0] + max[0]) / 2.0, (min[1] + max[1]) / 2.0];
        let px_centre = [(x_lo + x_hi) / 2.0, (y_lo + y_hi) / 2.0];
        View {
            scale,
            origin: [
                px_centre[0] - scale * centre[0],
                px_centre[1] + scale * centre[1],
            ],
            size,
        }
    }

    /// The pixel position of world point `p` (m).
    pub fn to_px(&self, p: [f64; 2]) -> [f64; 2] {
        [
            self.origin[0] + self.scale * p[0],
            self.origin[1] - self.scale * p[1],
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_centres_the_box_with_equal_scales() {
        let b = Bounds {
            min: [0.0, -0.1],
            max: [0.8, 0.3],
        };
        let v = View::fit(&b, (800, 600));
        // Width limits: (800 − 2·24) px over 0.8 m.
        let expected = (800.0 - 2.0 * (SIDE_PX + GROUND_DOT_PX)) / 0.8;
        assert!(
            (v.scale - expected).abs() < 1e-9,
            "scale {} px/m, expected {expected}",
            v.scale
        );
        let lo = v.to_px([0.0, 0.3]);
        let hi = v.to_px([0.8, -0.1]);
        assert!(
            (lo[0] - 24.0).abs() < 1e-9 && (hi[0] - 776.0).abs() < 1e-9,
            "x edges at {} and {} px, expected 24 and 776",
            lo[0],
            hi[0]
        );
        // Vertically centred in the band between caption and legend.
        let mid = (lo[1] + hi[1]) / 2.0;
        let band = (TOP_BAND_PX + GROUND_DOT_PX + 600.0 - BOTTOM_BAND_PX - GROUND_DOT_PX) / 2.0;
        assert!(
            (mid - band).abs() < 1e-9,
            "middle at {mid} px, expected {band}"
        );
    }

    #[test]
    fn legend_force_is_round_and_40_to_100_px() {
        for ppn in [1e-4, 0.37, 1.0, 3.3, 123.0] {
            let (f, len) = legend_force(ppn);
            let mantissa = f / 10f64.powf(f.log10().floor());
            assert!(
                [1.0, 2.0, 5.0].iter().any(|m| (m - mantissa).abs() < 1e-9),
                "{ppn} px/N: {f} N is not 1, 2 or 5 × 10^k"
            );
            assert!((40.0..=100.0).contains(&len), "{ppn} px/N: arrow {len} px");
        }
    }

    #[test]
    fn zero_arrow_has_no_extent() {
        let (shaft, head) = arrow([5.0, 5.0], [5.0, 5.0]);
        assert!(shaft.iter().chain(&head).all(|p| *p == [5.0, 5.0]));
    }
}
