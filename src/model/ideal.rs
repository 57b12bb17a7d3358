//! Clearance joints made ideal: the ideal reference of a model with clearance, from the same file.
//!
//! A clearance joint whose journal centre J (on the journal body) sits in a bearing of centre B
//! (on the bearing body) becomes the ideal revolute joint that pins J to B: the constraint
//! r_J − r_B = 0, i.e. the clearance c → 0 with the journal held at the bearing's centre. Its
//! contact law, friction and materials are ignored; the joint keeps its name, so a reaction
//! column of the ideal joint takes the place of the contact columns.
//!
//! Two spellings, one transformation ([`ideal_joint`]):
//! - in the model file, `ideal = true` on a `type = "clearance"` joint (the clearance data stay
//!   in the file and are still validated, so the flag can be switched back);
//! - on the command line, `--ideal NAME` (repeatable), applied by [`idealise`] to a loaded model.
//!   It records `joints.NAME.ideal=true` among the model's overrides, so the provenance of every
//!   result file reloads the same ideal model (`load(path, &source.overrides)`).

use super::{Joint, JointKind, Model, ModelError};

/// The `--set` spelling of making joint `name` ideal: `joints.NAME.ideal=true`.
pub fn ideal_override(name: &str) -> String {
    format!("joints.{name}.ideal=true")
}

/// The ideal joint that replaces a clearance joint, the anchors unchanged: for a revolute
/// clearance joint the revolute joint that pins the bearing centre (a) to the journal centre
/// (b); for a prismatic-clearance joint the prismatic joint that holds the slider centre (b) on
/// the guide's centreline, aligned at the nominal angle (the clearance c → 0).
pub fn ideal_joint(joint: Joint) -> Joint {
    let kind = match &joint.kind {
        JointKind::PrismaticClearance(p) => JointKind::Prismatic {
            axis: p.axis,
            angle: p.angle,
        },
        _ => JointKind::Revolute,
    };
    Joint { kind, ..joint }
}

/// `model` with the clearance joints named in `names` made ideal ([`ideal_joint`]), each recorded
/// as [`ideal_override`] in `model.source.overrides` (once, even if named twice).
///
/// Errors ([`ModelError::Ideal`]): a name that is no joint of the model, or a joint that is not a
/// clearance joint; the message names it and lists the model's clearance joints.
pub fn idealise(mut model: Model, names: &[String]) -> Result<Model, ModelError> {
    for name in names {
        let clearance: Vec<&str> = model
            .joints
            .iter()
            .filter(|j| {
                matches!(
                    j.kind,
                    JointKind::Clearance(_) | JointKind::PrismaticClearance(_)
                )
            })
            .map(|j| j.name.as_str())
            .collect();
        let listed = if clearance.is_empty() {
            "the model has no clearance joint".to_string()
        } else {
            format!("its clearance joints are {}", quoted(&clearance))
        };
        let Some(k) = model.joints.iter().position(|j| &j.name == name) else {
            return Err(ModelError::Ideal {
                file: model.source.path.clone(),
                joint: name.clone(),
                message: format!("no joint named \"{name}\" in the model; {listed}"),
            });
        };
        let joint = model.joints.remove(k);
        match joint.kind {
            JointKind::Clearance(_) | JointKind::PrismaticClearance(_) => {
                model.joints.insert(k, ideal_joint(joint));
                model.source.overrides.push(ideal_override(name));
            }
            // Named twice: the first made it ideal; the override is recorded once.
            JointKind::Revolute | JointKind::Prismatic { .. }
                if model.source.overrides.contains(&ideal_override(name)) =>
            {
                model.joints.insert(k, joint);
            }
            _ => {
                let message = format!(
                    "joint \"{name}\" is not a clearance joint (only a clearance joint can be made ideal); {listed}"
                );
                model.joints.insert(k, joint);
                return Err(ModelError::Ideal {
                    file: model.source.path.clone(),
                    joint: name.clone(),
                    message,
                });
            }
        }
    }
    Ok(model)
}

/// `"A", "B"`.
fn quoted(names: &[&str]) -> String {
    names
        .iter()
        .map(|n| format!("\"{n}\""))
        .collect::<Vec<_>>()
        .join(", ")
}
