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
/// A spanned number, or an expression string such as `"L2/2"` (see `expr`).
pub type Num = Spanned<Scalar>;

/// A number as written: a TOML integer or float, or an expression string.
#[derive(Debug, Clone, PartialEq)]
pub enum Scalar {
    /// A TOML integer or float.
    Number(f64),
    /// An expression to evaluate with the parameters.
    Expr(String),
}

impl<'de> Deserialize<'de> for Scalar {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = Scalar;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a number or an expression string such as \"L2/2\"")
            }
            fn visit_f64<E>(self, v: f64) -> Result<Scalar, E> {
                Ok(Scalar::Number(v))
            }
            fn visit_i64<E>(self, v: i64) -> Result<Scalar, E> {
                // The float nearest the integer, as serde reads an integer into f64.
                Ok(Scalar::Number(v as f64))
            }
            fn visit_u64<E>(self, v: u64) -> Result<Scalar, E> {
                Ok(Scalar::Number(v as f64))
            }
            fn visit_str<E>(self, v: &str) -> Result<Scalar, E> {
                Ok(Scalar::Expr(v.to_string()))
            }
        }
        d.deserialize_any(Visitor)
    }
}
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
    /// `[parameters]`: named numbers or expressions, usable in any numeric field.
    #[serde(default)]
    pub parameters: BTreeMap<Name, Num>,
    /// `[[tables]]`: y(x) with linear interpolation, called in expressions as `name(x)`.
    #[serde(default)]
    pub tables: Vec<TableFile>,
    /// `[[repeat]]`: bodies, joints and forces generated over an index range.
    #[serde(default)]
    pub repeat: Vec<RepeatFile>,
    /// `[[outputs]]`: points on bodies reported as extra columns.
    #[serde(default)]
    pub outputs: Vec<OutputFile>,
}

/// `[[tables]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TableFile {
    /// Name, called in expressions as `name(x)`.
    pub name: Name,
    /// Strictly increasing abscissae (numbers or expressions).
    pub x: Vec2,
    /// Ordinates, as many as `x`.
    pub y: Vec2,
}

/// `[[repeat]]`: `index` runs from `from` to `to` (integers, inclusive); in every entry of
/// `bodies`, `joints` and `forces`, `{expr}` in a name is replaced by the integer value of
/// `expr`, and the index is a parameter of every expression.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RepeatFile {
    /// Name of the index, e.g. "i".
    pub index: Name,
    /// First value (integer, or an expression of parameters).
    pub from: Num,
    /// Last value, inclusive.
    pub to: Num,
    /// Ground point templates (`[repeat.ground] points = { "G{i}" = ["i*a", 0] }`).
    #[serde(default)]
    pub ground: GroundFile,
    /// Body templates.
    #[serde(default)]
    pub bodies: Vec<BodyFile>,
    /// Joint templates.
    #[serde(default)]
    pub joints: Vec<JointFile>,
    /// Force templates.
    #[serde(default)]
    pub forces: Vec<ForceFile>,
}

/// `[[outputs]]`: a point on a body whose position, velocity and acceleration become columns.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputFile {
    /// Column prefix: `name.x name.y name.vx name.vy name.ax name.ay`.
    pub name: Name,
    /// The body.
    pub body: Name,
    /// A named point of the body.
    pub point: Option<Name>,
    /// Or coordinates in the body frame (m).
    pub local: Option<Vec2>,
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
    /// "revolute" | "prismatic" | "clearance" | "prismatic-clearance".
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
    /// Clearance: axial length L of the bearing (m); required by the line-contact laws.
    pub length: Option<Num>,
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
    /// Clearance: `[joints.lubrication]`, an oil film in the bearing.
    pub lubrication: Option<Spanned<LubricationFile>>,
    /// Clearance: `[joints.wear]`, Archard wear of the bearing surface (`linkdyn wear`).
    pub wear: Option<Spanned<WearFile>>,
    /// Clearance: `true` runs the joint as an ideal revolute joint (see `model::ideal`).
    pub ideal: Option<Spanned<bool>>,
    /// Prismatic clearance: slider length L (m).
    pub slider_length: Option<Num>,
    /// Prismatic clearance: slider width w (m), default 0.
    pub slider_width: Option<Num>,
    /// Prismatic clearance: initial offset of the slider centre from the guide centreline
    /// along perp(axis) (m), default 0.
    pub initial_offset: Option<Num>,
    /// Prismatic clearance: initial tilt of the slider from its nominal angle (rad), default 0.
    pub initial_tilt: Option<Num>,
    /// Prismatic clearance: position of the guide's rear end stop along `axis` from `point_a`
    /// (m, guide frame), default none (unbounded).
    pub guide_start: Option<Num>,
    /// Prismatic clearance: position of the guide's front end stop along `axis` from `point_a`
    /// (m, guide frame), default none (unbounded).
    pub guide_end: Option<Num>,
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
    /// "lankarani-nikravesh" (default) | "hunt-crossley" | "flores" | "hertz" | "johnson" | "liu".
    pub law: Option<Name>,
    /// Line-contact laws: the hysteresis factor, "lankarani-nikravesh" (default) |
    /// "hunt-crossley" | "flores" | "none".
    pub damping: Option<Name>,
    /// Coefficient of restitution c_r (default 0.9).
    pub restitution: Option<Num>,
    /// Exponent n (default 1.5).
    pub exponent: Option<Num>,
}

/// `[joints.lubrication]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LubricationFile {
    /// "short" | "long" (required).
    pub model: Option<Name>,
    /// Dynamic viscosity μ (Pa·s, required, > 0).
    pub viscosity: Option<Num>,
    /// Film thickness at which the dry contact begins (m, default c/100).
    pub contact_film_thickness: Option<Num>,
}

/// `[joints.wear]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WearFile {
    /// Dimensional wear coefficient k_w = k/H (m²/N, required, > 0).
    pub coefficient: Option<Num>,
    /// Number of angular bins on the bearing surface (default 360).
    pub bins: Option<Num>,
}

/// `[joints.friction]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrictionFile {
    /// "ambrosio" (default) | "none" | "ambrosio-as-printed" (the paper's eq. 11 as printed).
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
    /// "constant-speed" | "speed-ramp" | "prescribed-angle" | "torque".
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
    /// Speed ramp: speed before the ramp (rad/s).
    pub speed0: Option<Num>,
    /// Speed ramp: speed after the ramp (rad/s).
    pub speed1: Option<Num>,
    /// Speed ramp: speed before the ramp (rpm).
    pub speed0_rpm: Option<Num>,
    /// Speed ramp: speed after the ramp (rpm).
    pub speed1_rpm: Option<Num>,
    /// Speed ramp: time the ramp starts (s, default 0).
    pub start: Option<Num>,
    /// Speed ramp: how long the ramp lasts (s).
    pub duration: Option<Num>,
    /// Speed ramp: "smooth" (default) or "linear".
    pub shape: Option<Name>,
    /// Prescribed angle: θ(t) as an expression of `t` (rad).
    pub angle: Option<Num>,
    /// Torque driver: motor torque (N·m) as an expression of `t`, `theta`, `omega`.
    pub torque: Option<Num>,
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
    /// Torque (N·m, counter-clockwise positive): a number or an expression of time and state.
    pub torque: Option<Num>,
    /// Force in the global frame (N): numbers or expressions of time and state.
    pub force: Option<Vec2>,
}

/// Parses model text into the raw structs; syntax, type and unknown-field errors are located.
pub fn parse(text: &str, file: &str) -> Result<ModelFile, super::ModelError> {
    toml::from_str(text).map_err(|e| {
        let span = e.span().unwrap_or(0..0);
        super::locate::Locator::new(text, file).error(span, for_people(e.message().trim()))
    })
}

/// The deserialiser's message in the model file's words: an unknown field gets the nearest
/// known one ("did you mean"), and serde's type names become TOML's ("a table", "an array",
/// never a Rust struct name such as `FrictionFile`).
fn for_people(message: &str) -> String {
    if let Some(rest) = message.strip_prefix("unknown field `")
        && let Some((field, expected)) = rest.split_once("`, expected ")
    {
        let known: Vec<&str> = expected.split('`').skip(1).step_by(2).collect();
        let hint = super::suggest::did_you_mean(field, known.iter().copied());
        return format!("unknown field `{field}`{hint}; expected {expected}");
    }
    let mut text = message.to_string();
    for (serde, toml) in [
        ("invalid type: map", "invalid type: a table"),
        ("invalid type: sequence", "invalid type: an array"),
        ("expected a map", "expected a table"),
        ("expected a sequence", "expected an array"),
    ] {
        text = text.replace(serde, toml);
    }
    // "expected struct FrictionFile" and the like: a table, whatever the Rust type is called.
    while let Some(at) = text.find("expected struct ") {
        let name_end = text[at + 16..]
            .find(|c: char| !c.is_alphanumeric() && c != '_')
            .map_or(text.len(), |k| at + 16 + k);
        text.replace_range(at..name_end, "expected a table");
    }
    text
}

#[cfg(test)]
mod tests {
    use super::for_people;

    #[test]
    fn parse_messages_speak_toml_and_suggest_the_nearest_field() {
        assert_eq!(
            for_people(
                "unknown field `coefficent`, expected one of `law`, `coefficient`, `v0`, `v1`"
            ),
            "unknown field `coefficent`: did you mean \"coefficient\"?; expected one of `law`, `coefficient`, `v0`, `v1`"
        );
        // Nothing near enough: no guess.
        assert_eq!(
            for_people("unknown field `zzz`, expected one of `law`, `coefficient`"),
            "unknown field `zzz`; expected one of `law`, `coefficient`"
        );
        assert_eq!(
            for_people("invalid type: map, expected a sequence"),
            "invalid type: a table, expected an array"
        );
        assert_eq!(
            for_people("invalid type: integer `3`, expected struct FrictionFile"),
            "invalid type: integer `3`, expected a table"
        );
        assert_eq!(
            for_people("invalid type: integer `5`, expected a map"),
            "invalid type: integer `5`, expected a table"
        );
    }
}
