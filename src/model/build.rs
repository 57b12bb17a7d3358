//! Validation and conversion of a parsed [`ModelFile`] into a [`Model`] (SI units, typed ids).
//!
//! Every refusal names the field and its place in the file; physically impossible values
//! (negative mass, zero inertia, a joint on a missing point) are refused here, before any
//! numerics. Whether the linkage can be assembled is checked by the formulation.

use super::bounds::*;
use super::error::{ModelError, abbreviate};
use super::expr::{self, Expr, ExprError, Table};
use super::file::*;
use super::laws;
use super::locate::Locator;
use super::names;
use super::params::{self, RunScope, Values};
use super::suggest::did_you_mean;
use super::types::*;
use std::collections::HashSet;
use std::ops::Range;
use std::sync::Arc;
use toml::Spanned;

mod bodies;
mod drivers;
mod forces;
mod joints;
mod parameters;
mod shapes;
mod values;

/// Builds the model, refusing the first problem found.
pub fn build(raw: ModelFile, source: ModelSource, loc: &Locator<'_>) -> Result<Model, ModelError> {
    let plain = Builder {
        loc,
        values: Values::default(),
        repeat: None,
    };
    let parameters = plain.parameters(&raw.parameters)?;
    let mut values = Values {
        values: parameters.clone(),
        tables: Vec::new(),
    };
    values.tables = Builder {
        loc,
        values: values.clone(),
        repeat: None,
    }
    .tables(&raw.tables)?;
    let b = Builder {
        loc,
        values,
        repeat: None,
    };
    let name = b.name_on(&raw.model.name, "model", "")?;
    let settings = b.settings(&raw.settings)?;
    // Each [[repeat]] expands into one builder per index value, whose names substitute `{…}`.
    let mut repeats = Vec::with_capacity(raw.repeat.len());
    for r in &raw.repeat {
        for rb in b.repeat(r)? {
            repeats.push((rb, r));
        }
    }
    let mut ground_points = b.points(&raw.ground.points, "ground")?;
    for (rb, r) in &repeats {
        ground_points.extend(rb.points(&r.ground.points, "ground")?);
    }
    let mut seen = HashSet::new();
    for (name, _) in &ground_points {
        if !seen.insert(name.as_str()) {
            return Err(loc.whole(format!(
                "ground point \"{name}\" is defined twice (in [ground] or a [repeat.ground]); expected unique names"
            )));
        }
    }
    let mut seen = HashSet::new();
    let mut bodies = b.bodies(&raw.bodies, &mut seen)?;
    for (rb, r) in &repeats {
        bodies.extend(rb.bodies(&r.bodies, &mut seen)?);
    }
    if bodies.is_empty() {
        return Err(loc.whole("expected at least one [[bodies]] entry"));
    }
    // The linkage's size bounds its smallest scale and every body's inertia (see `bounds`).
    // A model whose points all coincide has no size to compare with: nothing to check.
    let extent = extent(&ground_points, &bodies);
    if extent > 0.0 && extent < MIN_EXTENT {
        return Err(loc.whole(format!(
            "the linkage spans {extent:.3e} m (the diagonal of the box around its points, body centres and ground points at the initial position); expected at least {MIN_EXTENT:e} m (real linkages: micro-mechanisms are tens of µm across)"
        )));
    }
    if extent > 0.0 {
        let mut built = bodies.iter();
        for raw_body in &raw.bodies {
            b.inertia_fits(raw_body, built.next(), extent)?;
        }
        for (rb, r) in &repeats {
            for raw_body in &r.bodies {
                rb.inertia_fits(raw_body, built.next(), extent)?;
            }
        }
    }
    let scope = Scope {
        ground_points: &ground_points,
        bodies: &bodies,
    };
    let mut seen = HashSet::new();
    let mut joints = b.joints(&raw.joints, &scope, &mut seen)?;
    for (rb, r) in &repeats {
        joints.extend(rb.joints(&r.joints, &scope, &mut seen)?);
    }
    let (drivers, motors) = b.drivers(&raw.drivers, &joints, &bodies)?;
    let theta = single_driver(&drivers, &motors, &joints);
    let mut seen: HashSet<String> = motors.iter().map(|m| m.name().to_string()).collect();
    let mut forces = b.forces(&raw.forces, &scope, &theta, &mut seen)?;
    for (rb, r) in &repeats {
        forces.extend(rb.forces(&r.forces, &scope, &theta, &mut seen)?);
    }
    forces.extend(motors);
    let outputs = b.outputs(&raw.outputs, &scope)?;
    Ok(Model {
        name,
        description: raw.model.description,
        settings,
        ground_points,
        bodies,
        joints,
        drivers,
        forces,
        outputs,
        parameters,
        source,
        notes: Vec::new(),
        warnings: Vec::new(),
    })
}

/// The extent D of a linkage (m): the diagonal of the box around its ground points, body
/// centres of mass and body points at the initial position. Within a factor √2 of the largest
/// distance between two of them, which is all its uses (bounds with margins of ten) need.
fn extent(ground: &[(String, [f64; 2])], bodies: &[Body]) -> f64 {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    let mut add = |p: [f64; 2]| {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    };
    for (_, p) in ground {
        add(*p);
    }
    for b in bodies {
        let s = &b.initial;
        let (sin, cos) = s.phi.sin_cos();
        add([s.x, s.y]);
        for (_, p) in &b.points {
            add([s.x + cos * p[0] - sin * p[1], s.y + sin * p[0] + cos * p[1]]);
        }
    }
    (hi[0] - lo[0]).hypot(hi[1] - lo[1])
}

/// The joint whose angle and speed `theta` and `omega` name in force expressions: that of the
/// model's single driver (kinematic or torque), or why there is none.
fn single_driver(
    drivers: &[Driver],
    motors: &[ForceElement],
    joints: &[Joint],
) -> Result<(Frame, Frame), String> {
    let mut driven: Vec<JointId> = drivers.iter().map(|d| d.joint).collect();
    driven.extend(motors.iter().filter_map(|m| match m {
        ForceElement::Motor { joint, .. } => Some(*joint),
        _ => None,
    }));
    match driven.as_slice() {
        [j] => joints
            .get(j.0)
            .map(|j| (j.a.frame, j.b.frame))
            .ok_or_else(|| "the driver's joint is missing".to_string()),
        other => Err(format!(
            "`theta` and `omega` are the angle and speed of the model's single driver, but it has {}; write a body's angle instead, e.g. crank.phi",
            other.len()
        )),
    }
}

/// Names a model may refer to.
struct Scope<'m> {
    ground_points: &'m [(String, [f64; 2])],
    bodies: &'m [Body],
}

struct Builder<'l, 'a> {
    loc: &'l Locator<'a>,
    /// Parameters, tables and the repeat index.
    values: Values,
    /// Inside a `[[repeat]]`: its index name and value.
    repeat: Option<(String, i64)>,
}

type Res<T> = Result<T, ModelError>;

/// Why coordinates are bounded ([`MAX_COORDINATE`]).
const COORDINATE_WHY: &str = "real linkages: ten times the largest machines";
/// Why angles are bounded ([`MAX_ANGLE`]).
const ANGLE_WHY: &str =
    "1600 turns; beyond it sin and cos of the angle lose the digits that place the links";
/// Why speeds are bounded ([`MAX_SPEED`]).
const SPEED_WHY: &str = "real linkages: the fastest crank trains turn at about 20 000 rpm";
