//! The model file as written: serde structs that mirror the TOML tables one to one.
//!
//! Nothing here is checked beyond TOML syntax and field types; [`super::build`] turns a
//! [`ModelFile`] into a validated [`super::Model`] in SI units. These structs never leave `model/`.
//!
//! Every value that validation may complain about is `Spanned`, so the complaint can name its
//! line and column.

use serde::Deserialize;
use std::collections::BTreeMap;
use toml::Spanned;

/// A spanned string (name of a body, point, joint …).
pub type Name = Spanned<String>;
/// A spanned number.
pub type Num = Spanned<f64>;
/// A spanned planar vector `[x, y]`, read as a list of any length and any element type so that
/// validation can refuse a wrong number of components (a fixed `[f64; 2]` would silently drop a
/// third one) and name the element that is not a number.
pub type Vec2 = Spanned<Vec<Spanned<toml::Value>>>;

/// The whole file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelFile {
    /// `[model]`: name and description.
    pub model: ModelInfo,
    /// `[settings]`: gravity and constraint stabilisation.
    #[serde(default)]
    pub settings: SettingsFile,
    /// `[ground]`: named fixed points.
    #[serde(default)]
    pub ground: GroundFile,
    /// `[[bodies]]`.
    #[serde(default)]
    pub bodies: Vec<BodyFile>,
    /// `[[joints]]`.
    #[serde(default)]
    pub joints: Vec<JointFile>,
    /// `[[drivers]]`.
    #[serde(default)]
    pub drivers: Vec<DriverFile>,
    /// `[[forces]]`.
    #[serde(default)]
    pub forces: Vec<ForceFile>,
}

/// `[model]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelInfo {
    /// Short name, used in result files.
    pub name: Name,
    /// Free text.
    #[serde(default)]
    pub description: String,
}

/// `[settings]`.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SettingsFile {
    /// Gravitational acceleration vector (m/s²). Default `[0, -9.81]`.
    pub gravity: Option<Vec2>,
    /// `[settings.baumgarte]`.
    pub baumgarte: Option<Spanned<BaumgarteFile>>,
}

/// `[settings.baumgarte]`: either `alpha`, `beta` (1/s) or `omega` (rad/s), `zeta` (–).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BaumgarteFile {
    /// Damping factor α (1/s).
    pub alpha: Option<Num>,
    /// Stiffness factor β (1/s).
    pub beta: Option<Num>,
    /// Natural frequency ω of the constraint error (rad/s): β = ω.
    pub omega: Option<Num>,
    /// Damping ratio ζ of the constraint error: α = ζ ω.
    pub zeta: Option<Num>,
}

/// `[ground]`.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroundFile {
    /// Named points in the global frame (m).
    #[serde(default)]
    pub points: BTreeMap<Name, Vec2>,
}

/// `[[bodies]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyFile {
    /// Unique body name ("ground" is reserved).
    pub name: Name,
    /// Mass (kg).
    pub mass: Num,
    /// Moment of inertia about the centre of mass (kg·m²).
    pub inertia: Num,
    /// Named points in the body frame, whose origin is the centre of mass (m).
    #[serde(default)]
    pub points: BTreeMap<Name, Vec2>,
    /// Initial guess of the pose (and optionally of the velocity).
    pub initial: Spanned<InitialFile>,
    /// How the body is drawn (figures and animations only; no effect on the dynamics).
    #[serde(default)]
    pub shapes: Vec<Spanned<ShapeFile>>,
}

/// One drawn shape of a body, in the body frame: `{ type = "bar", from = "A", to = "B",
/// width = 0.02 }`, `{ type = "polygon", points = ["A", "B", "C"] }` or `{ type = "polygon",
/// vertices = [[x, y], …] }`, `{ type = "disc", at = "A", radius = 0.01 }` or `{ type = "disc",
/// centre = [x, y], radius = 0.01 }` (m). One flat struct; [`super::build`] checks the fields of
/// each type.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShapeFile {
    /// "bar" | "polygon" | "disc".
    #[serde(rename = "type")]
    pub kind: Name,
    /// Bar: the point at one end.
    pub from: Option<Name>,
    /// Bar: the point at the other end.
    pub to: Option<Name>,
    /// Bar: width (m).
    pub width: Option<Num>,
    /// Polygon: corners given by point names, in order.
    pub points: Option<Vec<Name>>,
    /// Polygon: corners given as body-frame coordinates (m), in order.
    pub vertices: Option<Spanned<Vec<Vec2>>>,
    /// Disc: centred on this point.
    pub at: Option<Name>,
    /// Disc: centre in body-frame coordinates (m).
    pub centre: Option<Vec2>,
    /// Disc: radius (m).
    pub radius: Option<Num>,
}

/// `initial = { x, y, phi, vx, vy, omega }` of a body.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialFile {
    /// Centre-of-mass x (m).
    pub x: Num,
    /// Centre-of-mass y (m).
    pub y: Num,
    /// Orientation of the body x-axis (rad).
    pub phi: Num,
    /// Velocity guess (m/s), default 0.
    pub vx: Option<Num>,
    /// Velocity guess (m/s), default 0.
    pub vy: Option<Num>,
    /// Angular velocity guess (rad/s), default 0.
    pub omega: Option<Num>,
}

/// `[[joints]]`: one flat struct for every joint type; [`super::build`] checks that only the
/// fields of the named type are present.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointFile {
    /// Unique joint name.
    pub name: Name,
    /// "revolute" | "prismatic" | "clearance".
    #[serde(rename = "type")]
    pub kind: Name,
    /// First body (revolute, prismatic).
    pub body_a: Option<Name>,
    /// Point on the first body.
    pub point_a: Option<Name>,
    /// Second body.
    pub body_b: Option<Name>,
    /// Point on the second body.
    pub point_b: Option<Name>,
    /// Prismatic: sliding direction in the first body's frame (default `[1, 0]`).
    pub axis: Option<Vec2>,
    /// Prismatic: fixed relative angle φ_b − φ_a (rad, default 0).
    pub angle: Option<Num>,
    /// Clearance: body carrying the bearing (hole).
    pub bearing: Option<Name>,
    /// Clearance: bearing centre on the bearing body.
    pub bearing_point: Option<Name>,
    /// Clearance: body carrying the journal (pin).
    pub journal: Option<Name>,
    /// Clearance: journal centre on the journal body.
    pub journal_point: Option<Name>,
    /// Clearance: radial clearance c = R_B − R_J (m).
    pub clearance: Option<Num>,
    /// Clearance: journal radius R_J (m).
    pub journal_radius: Option<Num>,
    /// Clearance: Young's modulus shared by journal and bearing (Pa).
    pub youngs_modulus: Option<Num>,
    /// Clearance: Poisson ratio shared by journal and bearing.
    pub poisson_ratio: Option<Num>,
    /// Clearance: bearing material, overriding the shared one.
    pub bearing_material: Option<Spanned<MaterialFile>>,
    /// Clearance: journal material, overriding the shared one.
    pub journal_material: Option<Spanned<MaterialFile>>,
    /// Clearance: generalised stiffness K (N/m^n), overriding the value from the materials.
    pub stiffness: Option<Num>,
    /// Clearance: initial eccentricity e = journal centre − bearing centre (m, global), default 0.
    pub initial_eccentricity: Option<Vec2>,
    /// Clearance: `[joints.contact]`.
    pub contact: Option<Spanned<ContactFile>>,
    /// Clearance: `[joints.friction]`.
    pub friction: Option<Spanned<FrictionFile>>,
}

/// Material of one side of a clearance joint.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialFile {
    /// Young's modulus (Pa).
    pub youngs_modulus: Num,
    /// Poisson ratio.
    pub poisson_ratio: Num,
}

/// `[joints.contact]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactFile {
    /// "lankarani-nikravesh" (default) | "hunt-crossley" | "flores" | "hertz".
    pub law: Option<Name>,
    /// Coefficient of restitution c_r (default 0.9).
    pub restitution: Option<Num>,
    /// Exponent n (default 1.5).
    pub exponent: Option<Num>,
}

/// `[joints.friction]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrictionFile {
    /// "ambrosio" (default) | "none".
    pub law: Option<Name>,
    /// Friction coefficient c_f (default 0.1).
    pub coefficient: Option<Num>,
    /// Tangential velocity below which friction is off (m/s, default 1e-4).
    pub v0: Option<Num>,
    /// Tangential velocity above which friction is fully on (m/s, default 1e-3).
    pub v1: Option<Num>,
}

/// `[[drivers]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DriverFile {
    /// Unique driver name.
    pub name: Name,
    /// "constant-speed".
    #[serde(rename = "type")]
    pub kind: Name,
    /// The revolute joint it drives.
    pub joint: Name,
    /// Speed in revolutions per minute (give this or `speed`).
    pub speed_rpm: Option<Num>,
    /// Speed in rad/s (give this or `speed_rpm`).
    pub speed: Option<Num>,
    /// Relative angle φ_b − φ_a of the joint at t = 0 (rad, default 0).
    pub initial_angle: Option<Num>,
}

/// `[[forces]]`: one flat struct; [`super::build`] checks the fields of each type.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForceFile {
    /// Unique force name.
    pub name: Name,
    /// "spring-damper" | "torque" | "force".
    #[serde(rename = "type")]
    pub kind: Name,
    /// Spring-damper: first body.
    pub body_a: Option<Name>,
    /// Spring-damper: point on the first body.
    pub point_a: Option<Name>,
    /// Spring-damper: second body.
    pub body_b: Option<Name>,
    /// Spring-damper: point on the second body.
    pub point_b: Option<Name>,
    /// Spring stiffness (N/m).
    pub stiffness: Option<Num>,
    /// Damping coefficient (N·s/m).
    pub damping: Option<Num>,
    /// Spring free length (m).
    pub free_length: Option<Num>,
    /// Torque / force: the body it acts on.
    pub body: Option<Name>,
    /// Force: point of application on the body.
    pub point: Option<Name>,
    /// Constant torque (N·m, counter-clockwise positive).
    pub torque: Option<Num>,
    /// Constant force in the global frame (N).
    pub force: Option<Vec2>,
}

/// Parses model text into the raw structs; syntax, type and unknown-field errors are located.
pub fn parse(text: &str, file: &str) -> Result<ModelFile, super::ModelError> {
    toml::from_str(text).map_err(|e| {
        let span = e.span().unwrap_or(0..0);
        super::locate::Locator::new(text, file).error(span, e.message().trim().to_string())
    })
}
