//! The validated model, in SI units, addressed by typed ids.

use super::expr::Expr;
use serde::Serialize;

/// Index of a body in [`Model::bodies`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub struct BodyId(pub usize);

/// Index of a joint in [`Model::joints`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub struct JointId(pub usize);

/// Where a point lives: on the ground (global coordinates) or on a body (body frame).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Frame {
    /// The fixed ground.
    Ground,
    /// A moving body.
    Body(BodyId),
}

/// A named point attached to the ground or to a body.
#[derive(Debug, Clone, Serialize)]
pub struct Anchor {
    /// Ground or body.
    pub frame: Frame,
    /// The point's name in the model file.
    pub point: String,
    /// Coordinates in the frame (m): body frame (origin at the centre of mass) or global.
    pub local: [f64; 2],
}

/// Planar pose and velocity of a body's centre of mass.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct BodyState {
    /// x (m).
    pub x: f64,
    /// y (m).
    pub y: f64,
    /// Orientation φ of the body x-axis (rad).
    pub phi: f64,
    /// ẋ (m/s).
    pub vx: f64,
    /// ẏ (m/s).
    pub vy: f64,
    /// φ̇ (rad/s).
    pub omega: f64,
}

/// A rigid body.
#[derive(Debug, Clone, Serialize)]
pub struct Body {
    /// Name as in the model file.
    pub name: String,
    /// Mass (kg), > 0.
    pub mass: f64,
    /// Moment of inertia about the centre of mass (kg·m²), > 0.
    pub inertia: f64,
    /// Named points in the body frame (m).
    pub points: Vec<(String, [f64; 2])>,
    /// Initial guess of pose and velocity; assembly makes it consistent.
    pub initial: BodyState,
    /// How the body is drawn (empty: lines between its points). No effect on the dynamics.
    pub shapes: Vec<Shape>,
}

/// A drawn shape of a body, in the body frame (m). Figures and animations only.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case", tag = "type")]
pub enum Shape {
    /// A bar of width `width` between two points, with round ends.
    Bar {
        /// One end.
        from: [f64; 2],
        /// The other end.
        to: [f64; 2],
        /// Width (m), > 0.
        width: f64,
    },
    /// A filled polygon (three or more corners, in order).
    Polygon {
        /// Corners.
        vertices: Vec<[f64; 2]>,
    },
    /// A filled disc.
    Disc {
        /// Centre.
        centre: [f64; 2],
        /// Radius (m), > 0.
        radius: f64,
    },
}

/// Which limit of Reynolds' equation a lubricated clearance joint's film follows (see
/// `contact::lubrication`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum FilmModel {
    /// The infinitely short bearing (Ocvirk; Pinkus & Sternlicht), π-film.
    Short,
    /// The infinitely long bearing (Sommerfeld), Gümbel's π-film.
    Long,
}

impl FilmModel {
    /// The name as written in model files.
    pub fn name(self) -> &'static str {
        match self {
            FilmModel::Short => "short",
            FilmModel::Long => "long",
        }
    }
}

/// `[joints.lubrication]` of a clearance joint: an oil film in the bearing (the bearing length
/// is the joint's `length`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LubricationSpec {
    /// Short or long bearing.
    pub model: FilmModel,
    /// Dynamic viscosity μ (Pa·s), > 0.
    pub viscosity: f64,
    /// Film thickness h_c (m) at which the dry contact begins, in (0, c/2].
    pub contact_film_thickness: f64,
}

/// `[joints.wear]` of a clearance joint: Archard wear of the bearing surface, accumulated by
/// `linkdyn wear` (`contact::wear`; the bearing length is the joint's `length`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WearSpec {
    /// Dimensional wear coefficient k_w = k/H (m²/N): Archard's dimensionless coefficient k
    /// over the hardness H of the softer surface (Pa). > 0.
    pub coefficient: f64,
    /// Number of angular bins of the bearing profile, in the bearing body's frame.
    pub bins: usize,
}

/// Contact-force law of a clearance joint (see `contact::laws`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ContactLawKind {
    /// Lankarani–Nikravesh (1990) hysteresis damping.
    LankaraniNikravesh,
    /// Hunt–Crossley (1975).
    HuntCrossley,
    /// Flores et al. (2011).
    Flores,
    /// Hertz: elastic, no damping.
    Hertz,
    /// Johnson's line contact of a cylinder in a cylindrical hole (needs the bearing length).
    Johnson,
    /// Liu et al.'s conformal line contact (needs the bearing length).
    Liu,
}

impl ContactLawKind {
    /// The name as written in model files.
    pub fn name(self) -> &'static str {
        match self {
            ContactLawKind::LankaraniNikravesh => "lankarani-nikravesh",
            ContactLawKind::HuntCrossley => "hunt-crossley",
            ContactLawKind::Flores => "flores",
            ContactLawKind::Hertz => "hertz",
            ContactLawKind::Johnson => "johnson",
            ContactLawKind::Liu => "liu",
        }
    }

    /// True for the line-contact laws, whose elastic part needs the bearing's axial length and
    /// whose hysteresis factor is chosen separately (`damping`).
    pub fn is_line_contact(self) -> bool {
        matches!(self, ContactLawKind::Johnson | ContactLawKind::Liu)
    }
}

/// Hysteresis damping factor χ(c_r) of a contact law (see `contact::laws`): fixed by each
/// point-contact law, chosen with `damping` for the line-contact laws.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum DampingKind {
    /// Lankarani–Nikravesh (1990): χ = 3(1 − c_r²)/4.
    LankaraniNikravesh,
    /// Hunt–Crossley (1975): χ = 3(1 − c_r)/2.
    HuntCrossley,
    /// Flores et al. (2011): χ = 8(1 − c_r)/(5 c_r).
    Flores,
    /// No damping: χ = 0.
    None,
}

/// Friction law of a clearance joint.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case", tag = "law")]
pub enum FrictionSpec {
    /// No friction.
    None,
    /// Ambrósio's modified Coulomb law.
    Ambrosio {
        /// Friction coefficient c_f.
        coefficient: f64,
        /// Tangential speed below which friction is off (m/s).
        v0: f64,
        /// Tangential speed above which friction is fully on (m/s).
        v1: f64,
    },
    /// The paper's eq. 11 exactly as printed (c_d = 1 below v0, 0 above v1): a reproduction
    /// aid, not physics (see `contact::friction::ambrosio_as_printed`).
    AmbrosioAsPrinted {
        /// Friction coefficient c_f.
        coefficient: f64,
        /// Tangential speed below which friction is fully on (m/s).
        v0: f64,
        /// Tangential speed above which friction is off (m/s).
        v1: f64,
    },
}

/// Young's modulus and Poisson ratio of one side of a contact.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Material {
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Poisson ratio ν.
    pub poisson_ratio: f64,
}

/// Data of a revolute joint with clearance (a contact-force law, not a constraint).
#[derive(Debug, Clone, Serialize)]
pub struct ClearanceSpec {
    /// Radial clearance c = R_B − R_J (m), > 0.
    pub clearance: f64,
    /// Journal radius R_J (m), > 0.
    pub journal_radius: f64,
    /// Bearing material.
    pub bearing_material: Material,
    /// Journal material.
    pub journal_material: Material,
    /// Generalised stiffness K (N/m^n) if given in the file; otherwise it follows from the materials.
    pub stiffness_override: Option<f64>,
    /// Normal-force law.
    pub law: ContactLawKind,
    /// Hysteresis factor of the law (fixed by the point-contact laws).
    pub damping: DampingKind,
    /// Axial length L of the bearing (m), if given; required by the line-contact laws.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub length: Option<f64>,
    /// Coefficient of restitution c_r ∈ (0, 1].
    pub restitution: f64,
    /// Exponent n of the penetration.
    pub exponent: f64,
    /// Friction law.
    pub friction: FrictionSpec,
    /// Initial eccentricity e = journal − bearing centre (m, global frame).
    pub initial_eccentricity: [f64; 2],
    /// Oil film, if the joint is lubricated.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lubrication: Option<LubricationSpec>,
    /// Archard wear of the bearing surface, if the joint has a `[joints.wear]` table.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wear: Option<WearSpec>,
}

/// Data of a translational (prismatic) joint with clearance: a rectangular slider of length L
/// and width w in a guide of width w + 2c, contacting the guide's two surfaces at its four
/// corners (see `contact::corner` and docs/translational_clearance.md).
#[derive(Debug, Clone, Serialize)]
pub struct PrismaticClearanceSpec {
    /// Unit direction of the guide's centreline in the frame of body a (the guide).
    pub axis: [f64; 2],
    /// Nominal relative angle φ_b − φ_a (rad) at which the slider lies along the guide.
    pub angle: f64,
    /// Clearance c (m), > 0: the gap between the slider and each guide surface when the slider
    /// is centred and aligned; the guide's width is w + 2c.
    pub clearance: f64,
    /// Slider length L (m), > 0: the distance between its front and rear corners.
    pub slider_length: f64,
    /// Slider width w (m), ≥ 0 (0: a thin blade between the surfaces).
    pub slider_width: f64,
    /// Generalised stiffness K (N/m^n) of each corner contact.
    pub stiffness: f64,
    /// Normal-force law (a point-contact law).
    pub law: ContactLawKind,
    /// Hysteresis factor of the law.
    pub damping: DampingKind,
    /// Coefficient of restitution c_r ∈ (0, 1].
    pub restitution: f64,
    /// Exponent n of the penetration.
    pub exponent: f64,
    /// Friction law.
    pub friction: FrictionSpec,
    /// Initial offset of the slider centre from the guide centreline along the guide normal
    /// perp(axis) (m).
    pub initial_offset: f64,
    /// Initial tilt of the slider from its nominal angle (rad).
    pub initial_tilt: f64,
    /// Rear end stop of the guide: position s₀ along `axis` from the guide's point a (m, guide
    /// frame) that the slider's rear face (corners c1, c4) may not pass; `None`: unbounded.
    pub guide_start: Option<f64>,
    /// Front end stop of the guide: position s₁ along `axis` from the guide's point a (m, guide
    /// frame) that the slider's front face (corners c2, c3) may not pass; `None`: unbounded.
    pub guide_end: Option<f64>,
}

/// What a joint is.
#[derive(Debug, Clone, Serialize)]
pub enum JointKind {
    /// Ideal pin: the two points coincide (2 constraints).
    Revolute,
    /// Ideal slider: no relative rotation and point b stays on the line through a along `axis`
    /// (2 constraints).
    Prismatic {
        /// Unit sliding direction in the frame of body a.
        axis: [f64; 2],
        /// Fixed relative angle φ_b − φ_a (rad).
        angle: f64,
    },
    /// Revolute joint with clearance: body a carries the bearing, body b the journal. No
    /// constraint: a contact-force law.
    Clearance(ClearanceSpec),
    /// Translational joint with clearance: body a carries the guide (two parallel surfaces),
    /// body b the rectangular slider. No constraint: four corner contacts.
    PrismaticClearance(PrismaticClearanceSpec),
}

impl JointKind {
    /// The type name as written in model files.
    pub fn type_name(&self) -> &'static str {
        match self {
            JointKind::Revolute => "revolute",
            JointKind::Prismatic { .. } => "prismatic",
            JointKind::Clearance(_) => "clearance",
            JointKind::PrismaticClearance(_) => "prismatic-clearance",
        }
    }
}

/// A joint between two anchors.
#[derive(Debug, Clone, Serialize)]
pub struct Joint {
    /// Name as in the model file.
    pub name: String,
    /// First point (for clearance joints: the bearing centre).
    pub a: Anchor,
    /// Second point (for clearance joints: the journal centre). Reactions are reported on b's body.
    pub b: Anchor,
    /// Joint type and data.
    pub kind: JointKind,
}

/// An expression from the model file, resolved: its text (for messages and provenance) and
/// its tree (see [`Expr`]).
#[derive(Debug, Clone, Serialize)]
pub struct Expression {
    /// As written.
    pub text: String,
    /// Resolved tree.
    #[serde(skip)]
    pub tree: Expr,
}

/// How a driver moves its joint: the relative angle θ(t) = φ_b − φ_a.
#[derive(Debug, Clone, Serialize)]
#[serde(rename_all = "kebab-case", tag = "type")]
pub enum DriverMotion {
    /// θ = θ0 + ω t.
    ConstantSpeed,
    /// The speed goes from `speed0` to `speed1` between `start` and `start + duration`:
    /// θ̇ = ω0 + (ω1 − ω0) s(τ), τ = (t − start)/duration clamped to [0, 1], with s(τ) = τ
    /// (linear) or 3τ² − 2τ³ (smooth: the angular acceleration is continuous).
    SpeedRamp {
        /// ω0 (rad/s).
        speed0: f64,
        /// ω1 (rad/s).
        speed1: f64,
        /// Start of the ramp (s).
        start: f64,
        /// Duration (s), > 0.
        duration: f64,
        /// Smooth (3τ² − 2τ³) rather than linear.
        smooth: bool,
    },
    /// θ = θ(t), an expression of t alone.
    PrescribedAngle(Expression),
}

/// A driver on a revolute joint: the relative angle φ_b − φ_a follows θ(t) (one constraint row).
#[derive(Debug, Clone, Serialize)]
pub struct Driver {
    /// Name as in the model file.
    pub name: String,
    /// The driven revolute joint.
    pub joint: JointId,
    /// Angular speed ω (rad/s): the constant speed, or the final speed of a ramp; 0 for a
    /// prescribed angle (which has no nominal speed, so runs need `t_end`, not turns).
    pub speed: f64,
    /// Relative angle θ0 at t = 0 (rad).
    pub initial_angle: f64,
    /// How θ(t) goes.
    pub motion: DriverMotion,
}

impl Driver {
    /// One line for `linkdyn check`: the motion and its data.
    pub fn describe(&self) -> String {
        use crate::numbers::format_for_people as people;
        let rpm = |w: f64| people(w * 30.0 / std::f64::consts::PI);
        match &self.motion {
            DriverMotion::ConstantSpeed => format!(
                "constant speed {} rad/s ({} rpm)",
                people(self.speed),
                rpm(self.speed)
            ),
            DriverMotion::SpeedRamp {
                speed0,
                speed1,
                start,
                duration,
                smooth,
            } => format!(
                "{} speed ramp {} → {} rad/s ({} → {} rpm) from t = {} s over {} s",
                if *smooth { "smooth" } else { "linear" },
                people(*speed0),
                people(*speed1),
                rpm(*speed0),
                rpm(*speed1),
                people(*start),
                people(*duration)
            ),
            DriverMotion::PrescribedAngle(e) => format!("prescribed angle θ(t) = {}", e.text),
        }
    }
}

/// A point on a body reported as output columns `name.x name.y name.vx name.vy name.ax name.ay`.
#[derive(Debug, Clone, Serialize)]
pub struct OutputPoint {
    /// Column prefix.
    pub name: String,
    /// The point (on a moving body).
    pub at: Anchor,
}

/// An applied force element.
#[derive(Debug, Clone, Serialize)]
pub enum ForceElement {
    /// Linear spring-damper between two points: tension F = k (ℓ − ℓ0) + c ℓ̇.
    SpringDamper {
        /// Name.
        name: String,
        /// First point.
        a: Anchor,
        /// Second point.
        b: Anchor,
        /// Stiffness k (N/m).
        stiffness: f64,
        /// Damping c (N·s/m).
        damping: f64,
        /// Free length ℓ0 (m).
        free_length: f64,
    },
    /// Constant torque on a body (N·m, counter-clockwise positive).
    Torque {
        /// Name.
        name: String,
        /// Body.
        body: BodyId,
        /// Torque (N·m).
        torque: f64,
    },
    /// Constant force at a body point, global frame (N).
    PointForce {
        /// Name.
        name: String,
        /// Point of application.
        at: Anchor,
        /// Force (N).
        force: [f64; 2],
    },
    /// Torque on a body given by an expression of time and state (N·m, counter-clockwise).
    TorqueLaw {
        /// Name.
        name: String,
        /// Body.
        body: BodyId,
        /// τ(t, state) (N·m).
        torque: Expression,
    },
    /// Force at a body point, global frame, given by expressions of time and state (N).
    ForceLaw {
        /// Name.
        name: String,
        /// Point of application.
        at: Anchor,
        /// F_x, F_y (N).
        force: [Expression; 2],
    },
    /// A motor on a revolute joint (a `torque` driver): +τ on the joint's second body, −τ on
    /// its first, τ an expression of t, θ = φ_b − φ_a and ω = θ̇ (N·m).
    Motor {
        /// Name.
        name: String,
        /// The joint.
        joint: JointId,
        /// Frame of the first body (receives −τ).
        a: Frame,
        /// Frame of the second body (receives +τ).
        b: Frame,
        /// τ(t, θ, ω) (N·m).
        torque: Expression,
    },
}

impl ForceElement {
    /// Name as in the model file.
    pub fn name(&self) -> &str {
        match self {
            ForceElement::SpringDamper { name, .. }
            | ForceElement::Torque { name, .. }
            | ForceElement::PointForce { name, .. }
            | ForceElement::TorqueLaw { name, .. }
            | ForceElement::ForceLaw { name, .. }
            | ForceElement::Motor { name, .. } => name,
        }
    }

    /// Type as written in the model file.
    pub fn type_name(&self) -> &'static str {
        match self {
            ForceElement::SpringDamper { .. } => "spring-damper",
            ForceElement::Torque { .. } | ForceElement::TorqueLaw { .. } => "torque",
            ForceElement::PointForce { .. } | ForceElement::ForceLaw { .. } => "force",
            ForceElement::Motor { .. } => "torque driver",
        }
    }
}

/// Baumgarte stabilisation: the constraint error obeys Φ̈ + 2αΦ̇ + β²Φ = 0.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Baumgarte {
    /// α (1/s).
    pub alpha: f64,
    /// β (1/s).
    pub beta: f64,
}

impl Default for Baumgarte {
    /// α = β = 10 s⁻¹: a critically damped constraint error with a 0.1 s time constant, slow
    /// enough not to stiffen the equations at crank speeds up to ~10⁴ rpm, fast enough to stop drift.
    fn default() -> Self {
        Baumgarte {
            alpha: 10.0,
            beta: 10.0,
        }
    }
}

/// Global settings.
#[derive(Debug, Clone, Serialize)]
pub struct Settings {
    /// Gravitational acceleration (m/s²).
    pub gravity: [f64; 2],
    /// Constraint stabilisation.
    pub baumgarte: Baumgarte,
}

/// Where a model came from (recorded in every result file).
#[derive(Debug, Clone, Serialize)]
pub struct ModelSource {
    /// File path as given.
    pub path: String,
    /// SHA-256 of the file's bytes.
    pub sha256: String,
    /// `--set` overrides applied, in order.
    pub overrides: Vec<String>,
}

/// A validated planar linkage.
#[derive(Debug, Clone, Serialize)]
pub struct Model {
    /// Model name.
    pub name: String,
    /// Description.
    pub description: String,
    /// Settings.
    pub settings: Settings,
    /// Named ground points (global, m).
    pub ground_points: Vec<(String, [f64; 2])>,
    /// Moving bodies.
    pub bodies: Vec<Body>,
    /// Joints (ideal and clearance).
    pub joints: Vec<Joint>,
    /// Drivers.
    pub drivers: Vec<Driver>,
    /// Applied force elements (gravity is in `settings`), torque drivers included.
    pub forces: Vec<ForceElement>,
    /// Points on bodies reported as output columns.
    pub outputs: Vec<OutputPoint>,
    /// Parameters as evaluated (name, value), sorted by name.
    pub parameters: Vec<(String, f64)>,
    /// Provenance.
    pub source: ModelSource,
    /// Things the user should know that are not errors, one sentence each, e.g. the fields a
    /// `--set` that switched a contact or friction law dropped. The CLI prints them.
    pub notes: Vec<String>,
    /// Values that are valid but more likely a unit slip than meant (an angle of more than a
    /// turn, a driver speed no linkage of this size runs at), one sentence each
    /// ([`plausibility`](super::plausibility)). The CLI prints them as warnings.
    pub warnings: Vec<String>,
}

impl Model {
    /// The smallest clearance c of the model's clearance joints (radial, or per side of a guide; m), `None` without
    /// any: the scale against which a constraint drift is judged (a drift of a tenth of the
    /// clearance already moves the journal as far as the physics under study does).
    pub fn smallest_clearance(&self) -> Option<f64> {
        self.joints
            .iter()
            .filter_map(|j| match &j.kind {
                JointKind::Clearance(c) => Some(c.clearance),
                JointKind::PrismaticClearance(p) => Some(p.clearance),
                _ => None,
            })
            .reduce(f64::min)
    }

    /// The body with this id.
    pub fn body(&self, id: BodyId) -> &Body {
        &self.bodies[id.0]
    }

    /// The joint with this id.
    pub fn joint(&self, id: JointId) -> &Joint {
        &self.joints[id.0]
    }

    /// Id of the body with this name.
    pub fn body_id(&self, name: &str) -> Option<BodyId> {
        self.bodies.iter().position(|b| b.name == name).map(BodyId)
    }

    /// Id of the joint with this name.
    pub fn joint_id(&self, name: &str) -> Option<JointId> {
        self.joints.iter().position(|j| j.name == name).map(JointId)
    }

    /// Name of a frame ("ground" or the body's name).
    pub fn frame_name(&self, frame: Frame) -> &str {
        match frame {
            Frame::Ground => "ground",
            Frame::Body(id) => &self.body(id).name,
        }
    }

    /// True if any joint is a revolute clearance joint (prismatic-clearance joints not counted:
    /// the animation's clearance circles and journal arrows are theirs).
    pub fn has_clearance_joints(&self) -> bool {
        self.joints
            .iter()
            .any(|j| matches!(j.kind, JointKind::Clearance(_)))
    }
}
