//! Recognising the paper's four-bar in a model: crank, coupler and rocker, their joints, the
//! driver and the coupler–rocker clearance joint, or what the model lacks for the reduced
//! formulation.

use super::unsupported;
use crate::formulation::FormulationError;
use crate::model::{Anchor, BodyId, ClearanceSpec, Driver, Frame, Joint, JointKind, Model};

/// The parts of a four-bar with a coupler–rocker clearance joint, as found in a model.
pub(super) struct FourBar<'m> {
    pub(super) driver: &'m Driver,
    /// +1 if ground is the driven joint's first body, −1 if its second.
    pub(super) sign: f64,
    /// Crank ground pivot O2 (m).
    pub(super) o2: [f64; 2],
    /// Rocker ground pivot O4 (m).
    pub(super) o4: [f64; 2],
    pub(super) clearance_joint: &'m Joint,
    pub(super) spec: &'m ClearanceSpec,
    pub(super) bearing_on_coupler: bool,
    /// (body, first joint point, second joint point) of crank, coupler and rocker.
    pub(super) links: [(BodyId, &'m Anchor, &'m Anchor); 3],
}

/// Finds crank, coupler and rocker and their joints, or says what the model lacks.
pub(super) fn find_four_bar(model: &Model) -> Result<FourBar<'_>, FormulationError> {
    // First, so that a slider-crank hears why rather than a body count.
    if let Some(j) = model
        .joints
        .iter()
        .find(|j| matches!(j.kind, JointKind::PrismaticClearance(_)))
    {
        return Err(unsupported(format!(
            "joint \"{}\" is a prismatic-clearance joint; the reduced formulation is the four-bar model of Farahan et al. (2016) with one revolute clearance joint and has no translational contacts (use the DAE or generalized formulation)",
            j.name
        )));
    }
    let n_bodies = model.bodies.len();
    if n_bodies != 3 {
        return Err(unsupported(format!(
            "needs exactly 3 moving bodies (crank, coupler, rocker); the model has {n_bodies}"
        )));
    }
    let [driver] = model.drivers.as_slice() else {
        return Err(unsupported(format!(
            "needs exactly one driver, on the revolute joint between ground and the crank; the model has {}",
            model.drivers.len()
        )));
    };
    let driver_joint = model.joints.get(driver.joint.0).ok_or_else(|| {
        unsupported(format!(
            "driver \"{}\" refers to a joint the model does not have",
            driver.name
        ))
    })?;
    let (crank_id, crank_pivot, o2, sign) = match (driver_joint.a.frame, driver_joint.b.frame) {
        (Frame::Ground, Frame::Body(c)) => (c, &driver_joint.b, driver_joint.a.local, 1.0),
        (Frame::Body(c), Frame::Ground) => (c, &driver_joint.a, driver_joint.b.local, -1.0),
        (a, b) => {
            return Err(unsupported(format!(
                "driver \"{}\" drives joint \"{}\" between \"{}\" and \"{}\"; it must drive the joint between ground and the crank",
                driver.name,
                driver_joint.name,
                model.frame_name(a),
                model.frame_name(b)
            )));
        }
    };
    let clearance: Vec<(usize, &Joint, &ClearanceSpec)> = model
        .joints
        .iter()
        .enumerate()
        .filter_map(|(i, j)| match &j.kind {
            JointKind::Clearance(spec) => Some((i, j, spec)),
            _ => None,
        })
        .collect();
    let [(clearance_index, clearance_joint, spec)] = clearance.as_slice() else {
        return Err(unsupported(format!(
            "needs exactly one clearance joint, between the coupler and the rocker; the model has {}",
            clearance.len()
        )));
    };
    if spec.lubrication.is_some() {
        return Err(unsupported(format!(
            "the clearance joint \"{}\" is lubricated, and this formulation's contact forces, analytic Jacobian and outputs are those of the dry contact alone; run it with the DAE or the generalised formulation",
            clearance_joint.name
        )));
    }
    let crank_name = &model.body(crank_id).name;
    // Crank–coupler: an ideal revolute joint from the crank to another body.
    let Some((crank_coupler_index, crank_coupler)) =
        model.joints.iter().enumerate().find(|(i, j)| {
            *i != driver.joint.0
                && matches!(j.kind, JointKind::Revolute)
                && matches!(
                    (j.a.frame, j.b.frame),
                    (Frame::Body(a), Frame::Body(b)) if (a == crank_id) != (b == crank_id)
                )
        })
    else {
        return Err(unsupported(format!(
            "needs an ideal revolute joint between the crank \"{crank_name}\" and the coupler; found none (the clearance joint must be the coupler–rocker joint)"
        )));
    };
    let (crank_a, coupler_a) = if crank_coupler.a.frame == Frame::Body(crank_id) {
        (&crank_coupler.a, &crank_coupler.b)
    } else {
        (&crank_coupler.b, &crank_coupler.a)
    };
    let Frame::Body(coupler_id) = coupler_a.frame else {
        return Err(unsupported(format!(
            "joint \"{}\" must connect the crank \"{crank_name}\" to the coupler",
            crank_coupler.name
        )));
    };
    let Some(rocker_id) = (0..3)
        .map(BodyId)
        .find(|&b| b != crank_id && b != coupler_id)
    else {
        return Err(unsupported(
            "cannot tell the rocker from the crank and the coupler".to_string(),
        ));
    };
    let (coupler_name, rocker_name) = (&model.body(coupler_id).name, &model.body(rocker_id).name);
    // Clearance joint between coupler and rocker, either way round.
    let bearing_on_coupler = match (clearance_joint.a.frame, clearance_joint.b.frame) {
        (Frame::Body(a), Frame::Body(b)) if a == coupler_id && b == rocker_id => true,
        (Frame::Body(a), Frame::Body(b)) if a == rocker_id && b == coupler_id => false,
        (a, b) => {
            return Err(unsupported(format!(
                "clearance joint \"{}\" connects \"{}\" and \"{}\"; it must connect the coupler \"{coupler_name}\" and the rocker \"{rocker_name}\"",
                clearance_joint.name,
                model.frame_name(a),
                model.frame_name(b)
            )));
        }
    };
    let (coupler_b, rocker_b) = if bearing_on_coupler {
        (&clearance_joint.a, &clearance_joint.b)
    } else {
        (&clearance_joint.b, &clearance_joint.a)
    };
    // Rocker–ground: an ideal revolute joint.
    let rocker_ground = model.joints.iter().enumerate().find(|(_, j)| {
        matches!(j.kind, JointKind::Revolute)
            && matches!(
                (j.a.frame, j.b.frame),
                (Frame::Ground, Frame::Body(b)) | (Frame::Body(b), Frame::Ground) if b == rocker_id
            )
    });
    let Some((rocker_ground_index, rocker_ground)) = rocker_ground else {
        return Err(unsupported(format!(
            "needs an ideal revolute joint between the rocker \"{rocker_name}\" and ground; found none"
        )));
    };
    let (rocker_pivot, o4) = if rocker_ground.a.frame == Frame::Ground {
        (&rocker_ground.b, rocker_ground.a.local)
    } else {
        (&rocker_ground.a, rocker_ground.b.local)
    };
    let used = [
        driver.joint.0,
        crank_coupler_index,
        *clearance_index,
        rocker_ground_index,
    ];
    if let Some(extra) = model
        .joints
        .iter()
        .enumerate()
        .find(|(i, _)| !used.contains(i))
        .map(|(_, j)| j)
    {
        return Err(unsupported(format!(
            "joint \"{}\" ({} between \"{}\" and \"{}\") is not part of the four-bar ground–crank–coupler–rocker–ground; no other joints are allowed",
            extra.name,
            extra.kind.type_name(),
            model.frame_name(extra.a.frame),
            model.frame_name(extra.b.frame)
        )));
    }

    Ok(FourBar {
        driver,
        sign,
        o2,
        o4,
        clearance_joint,
        spec,
        bearing_on_coupler,
        links: [
            (crank_id, crank_pivot, crank_a),
            (coupler_id, coupler_a, coupler_b),
            (rocker_id, rocker_pivot, rocker_b),
        ],
    })
}
