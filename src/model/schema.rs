//! A JSON Schema of the model file (`linkdyn schema`), for TOML editors (Taplo, Even Better
//! TOML) to complete and check fields as one types.
//!
//! The schema is written from the tables below, one per serde struct of `file.rs`, with each
//! field's JSON type, whether it is required and a one-line description. The field names are
//! the serde structs' own: a unit test reads the names each struct's derived `Deserialize`
//! declares (the list serde hands to `deserialize_struct`) and fails if a struct has a field the
//! table lacks or the table has one the struct lacks, so the two cannot drift apart.
//!
//! JSON Schema draft 4, the newest that Taplo reads. The schema checks what serde checks
//! (names, types, unknown fields) and the names of types and laws; the rest (a field that the
//! joint's type does not take, units, references between names) is the loader's, with its
//! messages.

use serde_json::{Map, Value, json};

/// The JSON type of a field as written in TOML.
#[derive(Debug, Clone, Copy)]
enum Ty {
    /// A string (a name).
    Str,
    /// One of the given strings.
    OneOf(&'static [&'static str]),
    /// A number or an expression string of the parameters (`"L2/2"`).
    Num,
    /// `true` or `false`.
    Bool,
    /// `[x, y]`: two numbers or expressions.
    Vec2,
    /// A list of numbers or expressions (a table's abscissae or ordinates).
    Numbers,
    /// A list of names.
    Names,
    /// A list of `[x, y]`.
    Vec2s,
    /// A table: name → `[x, y]` (named points).
    Points,
    /// A table: name → number or expression (`[parameters]`).
    NumMap,
    /// A table of the given struct.
    Table(&'static str),
    /// An array of tables of the given struct.
    Tables(&'static str),
}

/// One field: its name in the file, its type, whether it must be given, and what it is.
struct Field(&'static str, Ty, bool, &'static str);

/// One struct of `file.rs`: its name (the schema's definition name), what it is, its fields.
struct Def(&'static str, &'static str, &'static [Field]);

const REQ: bool = true;
const OPT: bool = false;

const JOINT_TYPES: &[&str] = &["revolute", "prismatic", "clearance", "prismatic-clearance"];
const DRIVER_TYPES: &[&str] = &["constant-speed", "speed-ramp", "prescribed-angle", "torque"];
const FORCE_TYPES: &[&str] = &["spring-damper", "torque", "force"];
const SHAPE_TYPES: &[&str] = &["bar", "polygon", "disc"];
const RAMP_SHAPES: &[&str] = &["smooth", "linear"];
const CONTACT_LAWS: &[&str] = &[
    "lankarani-nikravesh",
    "hunt-crossley",
    "flores",
    "hertz",
    "johnson",
    "liu",
];
const DAMPINGS: &[&str] = &["lankarani-nikravesh", "hunt-crossley", "flores", "none"];
const FRICTION_LAWS: &[&str] = &["ambrosio", "ambrosio-as-printed", "none"];
const FILM_MODELS: &[&str] = &["short", "long"];

/// The root: the whole model file.
const ROOT: &str = "ModelFile";

use Ty::*;

const DEFS: &[Def] = &[
    Def(
        "ModelFile",
        "A linkdyn model file (docs/model_format.md). Units are SI unless a field's name says otherwise (speed_rpm).",
        &[
            Field("model", Table("ModelInfo"), REQ, "Name and description."),
            Field(
                "settings",
                Table("SettingsFile"),
                OPT,
                "Gravity and constraint stabilisation.",
            ),
            Field("ground", Table("GroundFile"), OPT, "Named fixed points."),
            Field("bodies", Tables("BodyFile"), OPT, "Rigid bodies."),
            Field(
                "joints",
                Tables("JointFile"),
                OPT,
                "Revolute, prismatic and clearance joints.",
            ),
            Field(
                "drivers",
                Tables("DriverFile"),
                OPT,
                "Motors on revolute joints.",
            ),
            Field(
                "forces",
                Tables("ForceFile"),
                OPT,
                "Springs, dampers, torques and forces.",
            ),
            Field(
                "parameters",
                NumMap,
                OPT,
                "Named numbers or expressions, usable in any numeric field.",
            ),
            Field(
                "tables",
                Tables("TableFile"),
                OPT,
                "y(x) with linear interpolation, called in expressions as name(x).",
            ),
            Field(
                "repeat",
                Tables("RepeatFile"),
                OPT,
                "Bodies, joints and forces generated over an index range.",
            ),
            Field(
                "outputs",
                Tables("OutputFile"),
                OPT,
                "Points on bodies reported as extra columns.",
            ),
        ],
    ),
    Def(
        "ModelInfo",
        "[model]",
        &[
            Field("name", Str, REQ, "Short name, used in result files."),
            Field("description", Str, OPT, "Free text."),
        ],
    ),
    Def(
        "SettingsFile",
        "[settings]",
        &[
            Field(
                "gravity",
                Vec2,
                OPT,
                "Gravitational acceleration [gx, gy] (m/s²), default [0, -9.81].",
            ),
            Field(
                "baumgarte",
                Table("BaumgarteFile"),
                OPT,
                "Baumgarte stabilisation of the constraints.",
            ),
        ],
    ),
    Def(
        "BaumgarteFile",
        "[settings.baumgarte]: alpha and beta (1/s), or omega (rad/s) and zeta.",
        &[
            Field("alpha", Num, OPT, "Damping factor α (1/s)."),
            Field("beta", Num, OPT, "Stiffness factor β (1/s)."),
            Field(
                "omega",
                Num,
                OPT,
                "Natural frequency ω of the constraint error (rad/s): β = ω.",
            ),
            Field(
                "zeta",
                Num,
                OPT,
                "Damping ratio ζ of the constraint error: α = ζω.",
            ),
        ],
    ),
    Def(
        "GroundFile",
        "[ground]",
        &[Field(
            "points",
            Points,
            OPT,
            "Named points in the global frame (m).",
        )],
    ),
    Def(
        "BodyFile",
        "[[bodies]]: a rigid body.",
        &[
            Field(
                "name",
                Str,
                REQ,
                "Unique body name (\"ground\" is reserved).",
            ),
            Field("mass", Num, REQ, "Mass (kg)."),
            Field(
                "inertia",
                Num,
                REQ,
                "Moment of inertia about the centre of mass (kg·m²).",
            ),
            Field(
                "points",
                Points,
                OPT,
                "Named points in the body frame, origin at the centre of mass (m).",
            ),
            Field(
                "initial",
                Table("InitialFile"),
                REQ,
                "Initial guess of the pose (and optionally of the velocity).",
            ),
            Field(
                "shapes",
                Tables("ShapeFile"),
                OPT,
                "How the body is drawn (figures and animations only).",
            ),
        ],
    ),
    Def(
        "InitialFile",
        "initial = { x, y, phi, vx, vy, omega } of a body.",
        &[
            Field("x", Num, REQ, "Centre-of-mass x (m)."),
            Field("y", Num, REQ, "Centre-of-mass y (m)."),
            Field("phi", Num, REQ, "Orientation of the body x-axis (rad)."),
            Field("vx", Num, OPT, "Velocity guess (m/s), default 0."),
            Field("vy", Num, OPT, "Velocity guess (m/s), default 0."),
            Field(
                "omega",
                Num,
                OPT,
                "Angular velocity guess (rad/s), default 0.",
            ),
        ],
    ),
    Def(
        "ShapeFile",
        "One drawn shape of a body, in the body frame (m).",
        &[
            Field("type", OneOf(SHAPE_TYPES), REQ, "bar | polygon | disc."),
            Field("from", Str, OPT, "Bar: the point at one end."),
            Field("to", Str, OPT, "Bar: the point at the other end."),
            Field("width", Num, OPT, "Bar: width (m)."),
            Field(
                "points",
                Names,
                OPT,
                "Polygon: corners given by point names, in order.",
            ),
            Field(
                "vertices",
                Vec2s,
                OPT,
                "Polygon: corners as body-frame coordinates (m), in order.",
            ),
            Field("at", Str, OPT, "Disc: centred on this point."),
            Field(
                "centre",
                Vec2,
                OPT,
                "Disc: centre in body-frame coordinates (m).",
            ),
            Field("radius", Num, OPT, "Disc: radius (m)."),
        ],
    ),
    Def(
        "JointFile",
        "[[joints]]: the fields of its type only (revolute, prismatic: body_a … point_b; clearance: bearing … ideal; prismatic-clearance: body_a … angle, clearance, slider_length, slider_width, stiffness, initial_offset, initial_tilt, guide_start, guide_end, contact, friction, ideal).",
        &[
            Field("name", Str, REQ, "Unique joint name."),
            Field(
                "type",
                OneOf(JOINT_TYPES),
                REQ,
                "revolute | prismatic | clearance | prismatic-clearance.",
            ),
            Field("body_a", Str, OPT, "First body (revolute, prismatic)."),
            Field("point_a", Str, OPT, "Point on the first body."),
            Field("body_b", Str, OPT, "Second body."),
            Field("point_b", Str, OPT, "Point on the second body."),
            Field(
                "axis",
                Vec2,
                OPT,
                "Prismatic, prismatic-clearance: sliding direction (guide centreline) in the first body's frame, default [1, 0].",
            ),
            Field(
                "angle",
                Num,
                OPT,
                "Prismatic: fixed relative angle φ_b − φ_a (rad), default 0; prismatic-clearance: the angle at which the slider lies along the guide.",
            ),
            Field(
                "bearing",
                Str,
                OPT,
                "Clearance: body carrying the bearing (hole).",
            ),
            Field(
                "bearing_point",
                Str,
                OPT,
                "Clearance: bearing centre on the bearing body.",
            ),
            Field(
                "journal",
                Str,
                OPT,
                "Clearance: body carrying the journal (pin).",
            ),
            Field(
                "journal_point",
                Str,
                OPT,
                "Clearance: journal centre on the journal body.",
            ),
            Field(
                "clearance",
                Num,
                OPT,
                "Clearance: radial clearance c = R_B − R_J (m); prismatic-clearance: gap between slider and each guide surface, centred (m).",
            ),
            Field(
                "journal_radius",
                Num,
                OPT,
                "Clearance: journal radius R_J (m).",
            ),
            Field(
                "length",
                Num,
                OPT,
                "Clearance: axial length L of the bearing (m); needed by the line-contact laws johnson and liu and by [joints.lubrication].",
            ),
            Field(
                "youngs_modulus",
                Num,
                OPT,
                "Clearance: Young's modulus of journal and bearing (Pa).",
            ),
            Field(
                "poisson_ratio",
                Num,
                OPT,
                "Clearance: Poisson ratio of journal and bearing.",
            ),
            Field(
                "bearing_material",
                Table("MaterialFile"),
                OPT,
                "Clearance: bearing material, overriding the shared one.",
            ),
            Field(
                "journal_material",
                Table("MaterialFile"),
                OPT,
                "Clearance: journal material, overriding the shared one.",
            ),
            Field(
                "stiffness",
                Num,
                OPT,
                "Clearance: generalised stiffness K (N/m^n), overriding the value from the materials; prismatic-clearance: K of each corner contact (N/m^n), required.",
            ),
            Field(
                "initial_eccentricity",
                Vec2,
                OPT,
                "Clearance: initial eccentricity, journal centre − bearing centre (m, global), default [0, 0].",
            ),
            Field(
                "contact",
                Table("ContactFile"),
                OPT,
                "Clearance, prismatic-clearance: the normal-force law (prismatic-clearance: a point-contact law).",
            ),
            Field(
                "friction",
                Table("FrictionFile"),
                OPT,
                "Clearance, prismatic-clearance: the friction law.",
            ),
            Field(
                "lubrication",
                Table("LubricationFile"),
                OPT,
                "Clearance: an oil film in the bearing (hydrodynamic journal bearing); needs the joint's length.",
            ),
            Field(
                "wear",
                Table("WearFile"),
                OPT,
                "Clearance: Archard wear of the bearing surface, accumulated by `linkdyn wear`; needs the joint's length, not with [joints.lubrication].",
            ),
            Field(
                "ideal",
                Bool,
                OPT,
                "Clearance: true runs the joint as an ideal revolute joint; prismatic-clearance: as an ideal prismatic joint.",
            ),
            Field(
                "slider_length",
                Num,
                OPT,
                "Prismatic-clearance: slider length L between its front and rear corners (m), required.",
            ),
            Field(
                "slider_width",
                Num,
                OPT,
                "Prismatic-clearance: slider width w (m), default 0; the guide is w + 2c wide.",
            ),
            Field(
                "initial_offset",
                Num,
                OPT,
                "Prismatic-clearance: initial offset of the slider centre from the guide centreline along perp(axis) (m), default 0.",
            ),
            Field(
                "initial_tilt",
                Num,
                OPT,
                "Prismatic-clearance: initial tilt of the slider from its nominal angle (rad), default 0.",
            ),
            Field(
                "guide_start",
                Num,
                OPT,
                "Prismatic-clearance: rear end stop of the guide, along axis from point_a in the guide's frame (m); default none (unbounded). The slider's rear face (corners c1, c4) stops there.",
            ),
            Field(
                "guide_end",
                Num,
                OPT,
                "Prismatic-clearance: front end stop of the guide, along axis from point_a in the guide's frame (m); default none (unbounded). The slider's front face (corners c2, c3) stops there.",
            ),
        ],
    ),
    Def(
        "MaterialFile",
        "Material of one side of a clearance joint.",
        &[
            Field("youngs_modulus", Num, REQ, "Young's modulus (Pa)."),
            Field("poisson_ratio", Num, REQ, "Poisson ratio."),
        ],
    ),
    Def(
        "ContactFile",
        "[joints.contact]",
        &[
            Field(
                "law",
                OneOf(CONTACT_LAWS),
                OPT,
                "Normal-force law, default lankarani-nikravesh (johnson and liu: line contact, need the joint's length).",
            ),
            Field(
                "damping",
                OneOf(DAMPINGS),
                OPT,
                "Line-contact laws (johnson, liu): the hysteresis damping, default lankarani-nikravesh.",
            ),
            Field(
                "restitution",
                Num,
                OPT,
                "Coefficient of restitution c_r, default 0.9 (not for hertz).",
            ),
            Field("exponent", Num, OPT, "Exponent n, default 1.5."),
        ],
    ),
    Def(
        "FrictionFile",
        "[joints.friction]",
        &[
            Field(
                "law",
                OneOf(FRICTION_LAWS),
                OPT,
                "Friction law, default ambrosio.",
            ),
            Field(
                "coefficient",
                Num,
                OPT,
                "Friction coefficient c_f, default 0.1.",
            ),
            Field(
                "v0",
                Num,
                OPT,
                "Tangential velocity below which friction is off (m/s), default 1e-4.",
            ),
            Field(
                "v1",
                Num,
                OPT,
                "Tangential velocity above which friction is fully on (m/s), default 1e-3.",
            ),
        ],
    ),
    Def(
        "LubricationFile",
        "[joints.lubrication]",
        &[
            Field(
                "model",
                OneOf(FILM_MODELS),
                REQ,
                "Film model: short (Ocvirk's infinitely short bearing) or long (Sommerfeld's infinitely long bearing), both with the π-film.",
            ),
            Field(
                "viscosity",
                Num,
                REQ,
                "Dynamic viscosity of the oil μ (Pa·s), > 0.",
            ),
            Field(
                "contact_film_thickness",
                Num,
                OPT,
                "Film thickness at which the dry contact begins (m), at most c/2, default c/100.",
            ),
        ],
    ),
    Def(
        "WearFile",
        "[joints.wear]",
        &[
            Field(
                "coefficient",
                Num,
                REQ,
                "Dimensional wear coefficient k_w = k/H (m²/N): Archard's k over the hardness H of the worn bearing, in [1e-24, 1e-6].",
            ),
            Field(
                "bins",
                Num,
                OPT,
                "Number of angular bins of the bearing profile (integer in [8, 1e5]), default 360.",
            ),
        ],
    ),
    Def(
        "DriverFile",
        "[[drivers]]: a motor on a revolute joint.",
        &[
            Field("name", Str, REQ, "Unique driver name."),
            Field(
                "type",
                OneOf(DRIVER_TYPES),
                REQ,
                "constant-speed | speed-ramp | prescribed-angle | torque.",
            ),
            Field("joint", Str, REQ, "The revolute joint it drives."),
            Field(
                "speed_rpm",
                Num,
                OPT,
                "Speed in revolutions per minute (give this or speed).",
            ),
            Field(
                "speed",
                Num,
                OPT,
                "Speed in rad/s (give this or speed_rpm).",
            ),
            Field(
                "initial_angle",
                Num,
                OPT,
                "Relative angle φ_b − φ_a of the joint at t = 0 (rad), default 0.",
            ),
            Field(
                "speed0",
                Num,
                OPT,
                "Speed ramp: speed before the ramp (rad/s).",
            ),
            Field(
                "speed1",
                Num,
                OPT,
                "Speed ramp: speed after the ramp (rad/s).",
            ),
            Field(
                "speed0_rpm",
                Num,
                OPT,
                "Speed ramp: speed before the ramp (rpm).",
            ),
            Field(
                "speed1_rpm",
                Num,
                OPT,
                "Speed ramp: speed after the ramp (rpm).",
            ),
            Field(
                "start",
                Num,
                OPT,
                "Speed ramp: time the ramp starts (s), default 0.",
            ),
            Field(
                "duration",
                Num,
                OPT,
                "Speed ramp: how long the ramp lasts (s).",
            ),
            Field(
                "shape",
                OneOf(RAMP_SHAPES),
                OPT,
                "Speed ramp: smooth (default) or linear.",
            ),
            Field(
                "angle",
                Num,
                OPT,
                "Prescribed angle: θ(t) as an expression of t (rad).",
            ),
            Field(
                "torque",
                Num,
                OPT,
                "Torque driver: motor torque (N·m) as an expression of t, theta, omega.",
            ),
        ],
    ),
    Def(
        "ForceFile",
        "[[forces]]",
        &[
            Field("name", Str, REQ, "Unique force name."),
            Field(
                "type",
                OneOf(FORCE_TYPES),
                REQ,
                "spring-damper | torque | force.",
            ),
            Field("body_a", Str, OPT, "Spring-damper: first body."),
            Field(
                "point_a",
                Str,
                OPT,
                "Spring-damper: point on the first body.",
            ),
            Field("body_b", Str, OPT, "Spring-damper: second body."),
            Field(
                "point_b",
                Str,
                OPT,
                "Spring-damper: point on the second body.",
            ),
            Field("stiffness", Num, OPT, "Spring stiffness (N/m)."),
            Field("damping", Num, OPT, "Damping coefficient (N·s/m)."),
            Field("free_length", Num, OPT, "Spring free length (m)."),
            Field("body", Str, OPT, "Torque, force: the body it acts on."),
            Field(
                "point",
                Str,
                OPT,
                "Force: point of application on the body.",
            ),
            Field(
                "torque",
                Num,
                OPT,
                "Torque (N·m, counter-clockwise positive): a number or an expression of time and state.",
            ),
            Field(
                "force",
                Vec2,
                OPT,
                "Force [fx, fy] in the global frame (N): numbers or expressions of time and state.",
            ),
        ],
    ),
    Def(
        "TableFile",
        "[[tables]]: y(x), linear between the given points.",
        &[
            Field("name", Str, REQ, "Name, called in expressions as name(x)."),
            Field("x", Numbers, REQ, "Strictly increasing abscissae."),
            Field("y", Numbers, REQ, "Ordinates, as many as x."),
        ],
    ),
    Def(
        "RepeatFile",
        "[[repeat]]: index runs from `from` to `to` (inclusive); {expr} in a name is replaced by its integer value.",
        &[
            Field("index", Str, REQ, "Name of the index, e.g. \"i\"."),
            Field(
                "from",
                Num,
                REQ,
                "First value (an integer, or an expression of parameters).",
            ),
            Field("to", Num, REQ, "Last value, inclusive."),
            Field(
                "ground",
                Table("GroundFile"),
                OPT,
                "Ground point templates.",
            ),
            Field("bodies", Tables("BodyFile"), OPT, "Body templates."),
            Field("joints", Tables("JointFile"), OPT, "Joint templates."),
            Field("forces", Tables("ForceFile"), OPT, "Force templates."),
        ],
    ),
    Def(
        "OutputFile",
        "[[outputs]]: a point whose position, velocity and acceleration become columns.",
        &[
            Field(
                "name",
                Str,
                REQ,
                "Column prefix: name.x name.y name.vx name.vy name.ax name.ay.",
            ),
            Field("body", Str, REQ, "The body."),
            Field("point", Str, OPT, "A named point of the body."),
            Field("local", Vec2, OPT, "Or coordinates in the body frame (m)."),
        ],
    ),
];

/// A number or an expression string.
fn number() -> Value {
    json!({ "type": ["number", "string"] })
}

fn vec2() -> Value {
    json!({ "type": "array", "items": number(), "minItems": 2, "maxItems": 2 })
}

fn reference(def: &str) -> Value {
    json!({ "$ref": format!("#/definitions/{def}") })
}

fn ty(t: Ty) -> Value {
    match t {
        Str => json!({ "type": "string" }),
        OneOf(names) => json!({ "type": "string", "enum": names }),
        Num => number(),
        Bool => json!({ "type": "boolean" }),
        Vec2 => vec2(),
        Numbers => json!({ "type": "array", "items": number() }),
        Names => json!({ "type": "array", "items": { "type": "string" } }),
        Vec2s => json!({ "type": "array", "items": vec2() }),
        Points => json!({ "type": "object", "additionalProperties": vec2() }),
        NumMap => json!({ "type": "object", "additionalProperties": number() }),
        Table(def) => reference(def),
        Tables(def) => json!({ "type": "array", "items": reference(def) }),
    }
}

/// The object schema of one struct (without `$schema`).
fn object(def: &Def) -> Value {
    let Def(_, description, fields) = def;
    let mut properties = Map::new();
    for Field(name, t, _, doc) in fields.iter() {
        let mut schema = ty(*t);
        if let Value::Object(o) = &mut schema {
            o.insert("description".into(), Value::from(*doc));
        }
        properties.insert((*name).to_string(), schema);
    }
    let required: Vec<&str> = fields
        .iter()
        .filter(|f| f.2)
        .map(|Field(name, ..)| *name)
        .collect();
    let mut o = Map::new();
    o.insert("type".into(), json!("object"));
    o.insert("description".into(), json!(description));
    o.insert("properties".into(), Value::Object(properties));
    // Draft 4 wants at least one name in `required` where it is given.
    if !required.is_empty() {
        o.insert("required".into(), json!(required));
    }
    // Serde refuses unknown fields (deny_unknown_fields), so the schema does too.
    o.insert("additionalProperties".into(), json!(false));
    Value::Object(o)
}

/// The JSON Schema (draft 4) of the model file.
pub fn json_schema() -> Value {
    let mut definitions = Map::new();
    let mut root = Map::new();
    for def in DEFS {
        if def.0 == ROOT {
            if let Value::Object(o) = object(def) {
                root = o;
            }
        } else {
            definitions.insert(def.0.to_string(), object(def));
        }
    }
    let mut schema = Map::new();
    schema.insert(
        "$schema".into(),
        json!("http://json-schema.org/draft-04/schema#"),
    );
    schema.insert("title".into(), json!("linkdyn model file"));
    schema.extend(root);
    schema.insert("definitions".into(), Value::Object(definitions));
    Value::Object(schema)
}

#[cfg(test)]
mod tests {
    use super::super::file;
    use super::{DEFS, Ty};
    use serde::Deserialize;
    use serde::de::{self, Visitor};
    use std::collections::BTreeSet;

    /// The error that carries what a struct's `Deserialize` asked for.
    #[derive(Debug)]
    struct Asked(Option<&'static [&'static str]>);
    impl std::fmt::Display for Asked {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            write!(f, "{:?}", self.0)
        }
    }
    impl std::error::Error for Asked {}
    impl de::Error for Asked {
        fn custom<T: std::fmt::Display>(_: T) -> Self {
            Asked(None)
        }
    }

    /// A deserialiser that answers nothing: a derived struct's `Deserialize` calls
    /// `deserialize_struct` with the names of all its fields (as written in the file), and
    /// this one stops there with them.
    struct FieldNames;
    impl<'de> de::Deserializer<'de> for FieldNames {
        type Error = Asked;
        fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Asked> {
            Err(Asked(None))
        }
        fn deserialize_struct<V: Visitor<'de>>(
            self,
            _: &'static str,
            fields: &'static [&'static str],
            _: V,
        ) -> Result<V::Value, Asked> {
            Err(Asked(Some(fields)))
        }
        serde::forward_to_deserialize_any! {
            bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes
            byte_buf option unit unit_struct newtype_struct seq tuple tuple_struct map enum
            identifier ignored_any
        }
    }

    fn fields_of<'de, T: Deserialize<'de>>() -> BTreeSet<&'static str> {
        match T::deserialize(FieldNames) {
            Err(Asked(Some(fields))) => fields.iter().copied().collect(),
            other => panic!("not a struct: {other:?}", other = other.err()),
        }
    }

    fn schema_fields(def: &str) -> BTreeSet<&'static str> {
        let Some(d) = DEFS.iter().find(|d| d.0 == def) else {
            panic!("the schema has no definition {def}")
        };
        d.2.iter().map(|f| f.0).collect()
    }

    /// Every serde struct of the model file has exactly the schema's fields: a field added to
    /// `file.rs` without its line in the schema (or the other way round) fails here.
    #[test]
    fn schema_fields_are_the_serde_structs_fields() {
        let structs: Vec<(&str, BTreeSet<&'static str>)> = vec![
            ("ModelFile", fields_of::<file::ModelFile>()),
            ("ModelInfo", fields_of::<file::ModelInfo>()),
            ("SettingsFile", fields_of::<file::SettingsFile>()),
            ("BaumgarteFile", fields_of::<file::BaumgarteFile>()),
            ("GroundFile", fields_of::<file::GroundFile>()),
            ("BodyFile", fields_of::<file::BodyFile>()),
            ("InitialFile", fields_of::<file::InitialFile>()),
            ("ShapeFile", fields_of::<file::ShapeFile>()),
            ("JointFile", fields_of::<file::JointFile>()),
            ("MaterialFile", fields_of::<file::MaterialFile>()),
            ("ContactFile", fields_of::<file::ContactFile>()),
            ("FrictionFile", fields_of::<file::FrictionFile>()),
            ("LubricationFile", fields_of::<file::LubricationFile>()),
            ("WearFile", fields_of::<file::WearFile>()),
            ("DriverFile", fields_of::<file::DriverFile>()),
            ("ForceFile", fields_of::<file::ForceFile>()),
            ("TableFile", fields_of::<file::TableFile>()),
            ("RepeatFile", fields_of::<file::RepeatFile>()),
            ("OutputFile", fields_of::<file::OutputFile>()),
        ];
        assert_eq!(
            structs.len(),
            DEFS.len(),
            "a schema definition has no serde struct"
        );
        for (def, fields) in &structs {
            let schema = schema_fields(def);
            let missing: Vec<_> = fields.difference(&schema).collect();
            let extra: Vec<_> = schema.difference(fields).collect();
            assert!(
                missing.is_empty() && extra.is_empty(),
                "{def}: fields of the serde struct missing from the schema {missing:?}, \
                 schema fields the struct does not have {extra:?}"
            );
        }
        // Every table a field refers to is defined.
        for d in DEFS {
            for f in d.2 {
                if let Ty::Table(t) | Ty::Tables(t) = f.1 {
                    schema_fields(t);
                }
            }
        }
    }

    /// The type names the schema offers are those the loader lists when it refuses an unknown
    /// type (a joint, driver, force or shape of type "zzz" in the shipped pendulum).
    #[test]
    fn type_names_are_the_loader_s() {
        let pendulum = include_str!("../../models/pendulum.toml");
        let cases: [(&str, String, &[&str]); 4] = [
            (
                "joint",
                pendulum.replace("type = \"revolute\"", "type = \"zzz\""),
                super::JOINT_TYPES,
            ),
            (
                "driver",
                format!(
                    "{pendulum}\n[[drivers]]\nname = \"m\"\ntype = \"zzz\"\njoint = \"O\"\nspeed = 1.0\n"
                ),
                super::DRIVER_TYPES,
            ),
            (
                "force",
                format!("{pendulum}\n[[forces]]\nname = \"f\"\ntype = \"zzz\"\nbody = \"rod\"\n"),
                super::FORCE_TYPES,
            ),
            (
                "shape",
                pendulum.replace(
                    "\n[[joints]]",
                    "shapes = [{ type = \"zzz\", at = \"O\", radius = 0.01 }]\n\n[[joints]]",
                ),
                super::SHAPE_TYPES,
            ),
        ];
        for (what, text, names) in cases {
            let message = match super::super::load_str(&text, "t.toml", &[]) {
                Ok(_) => panic!("{what} of type \"zzz\" was accepted"),
                Err(e) => e.to_string(),
            };
            assert!(message.contains("zzz"), "{what}: {message}");
            for name in names {
                assert!(
                    message.contains(name),
                    "{what}: the schema offers \"{name}\", the loader's message does not list it: {message}"
                );
            }
        }
    }

    /// The names the schema offers for laws are the loader's (`laws.rs`).
    #[test]
    fn law_names_are_the_loader_s() {
        use super::super::laws;
        assert_eq!(super::CONTACT_LAWS, laws::names(laws::CONTACT).as_slice());
        assert_eq!(super::DAMPINGS, laws::DAMPING);
        assert_eq!(super::FRICTION_LAWS, laws::names(laws::FRICTION).as_slice());
        assert_eq!(super::FILM_MODELS, laws::FILM_MODELS);
    }
}
