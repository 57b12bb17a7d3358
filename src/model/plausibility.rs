//! Values that are valid but more likely a unit slip than meant: an angle field of more than a
//! turn (degrees typed into a radian field), a driver speed that moves the driven body faster
//! than any linkage of its size runs (rpm typed into `speed`, which is rad/s). Warnings, never
//! refusals: a model may mean them. The command line prints them before any work.

use super::types::{DriverMotion, Frame, JointKind, Model};
use crate::numbers::format_for_people as short;
use std::f64::consts::{PI, TAU};

/// Fastest plausible speed of a driven body's points (m/s). The paper's four-bar at 5000 rpm
/// moves its crank pin at 131 m/s, which is already extreme for a linkage; a typed-in speed
/// past 200 m/s is more likely rpm written as rad/s (3500 "rad/s" moves that crank pin at
/// 875 m/s) than meant.
pub const MAX_PLAUSIBLE_POINT_SPEED: f64 = 200.0;

/// One sentence per suspicious value of `model` (module documentation), in model order.
pub fn warnings(model: &Model) -> Vec<String> {
    let mut out = Vec::new();
    let turn = |field: String, value: f64, out: &mut Vec<String>| {
        if value.abs() > TAU {
            out.push(format!(
                "{field} = {} rad is more than a turn (2π = 6.2832 rad); angles are in radians ({} degrees would be {:.4} rad)",
                short(value),
                short(value),
                value * PI / 180.0
            ));
        }
    };
    for body in &model.bodies {
        turn(
            format!("bodies.{}.initial.phi", body.name),
            body.initial.phi,
            &mut out,
        );
    }
    for joint in &model.joints {
        if let JointKind::Prismatic { angle, .. } = joint.kind {
            turn(format!("joints.{}.angle", joint.name), angle, &mut out);
        }
    }
    for driver in &model.drivers {
        if !matches!(driver.motion, DriverMotion::PrescribedAngle { .. }) {
            turn(
                format!("drivers.{}.initial_angle", driver.name),
                driver.initial_angle,
                &mut out,
            );
        }
        let radius = driven_radius(model, driver.joint.0);
        let speed = driver.speed.abs() * radius;
        if speed > MAX_PLAUSIBLE_POINT_SPEED {
            out.push(format!(
                "drivers.{}: {} rad/s ({} rpm) moves points {} m from the driven joint at {} m/s, faster than linkages of this size run (over {MAX_PLAUSIBLE_POINT_SPEED} m/s); `speed` is in rad/s: for revolutions per minute write speed_rpm",
                driver.name,
                short(driver.speed),
                short(driver.speed * 30.0 / PI),
                short(radius),
                short(speed)
            ));
        }
    }
    out
}

/// Largest distance (m) from the driven joint to a point or the centre of mass of the bodies
/// it connects: how far from the axis the driver's speed acts.
fn driven_radius(model: &Model, joint: usize) -> f64 {
    let Some(joint) = model.joints.get(joint) else {
        return 0.0;
    };
    let mut radius = 0.0_f64;
    for anchor in [&joint.a, &joint.b] {
        let Frame::Body(id) = anchor.frame else {
            continue;
        };
        let Some(body) = model.bodies.get(id.0) else {
            continue;
        };
        let centre = [0.0, 0.0];
        for p in std::iter::once(&centre).chain(body.points.iter().map(|(_, p)| p)) {
            radius = radius.max((p[0] - anchor.local[0]).hypot(p[1] - anchor.local[1]));
        }
    }
    radius
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::load;

    fn warnings_with(overrides: &[&str]) -> Vec<String> {
        let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
        let model =
            load("models/farahan2016.toml".as_ref(), &overrides).unwrap_or_else(|e| panic!("{e}"));
        warnings(&model)
    }

    /// The reference model with its driver's `speed_rpm = 250.0` line replaced.
    fn warnings_with_speed(line: &str) -> Vec<String> {
        let text = std::fs::read_to_string("models/farahan2016.toml")
            .unwrap_or_else(|e| panic!("{e}"))
            .replace("speed_rpm = 250.0", line);
        let model = crate::model::load_str(&text, "farahan2016.toml", &[])
            .unwrap_or_else(|e| panic!("{e}"));
        warnings(&model)
    }

    #[test]
    fn the_reference_model_draws_no_warning_at_its_speeds() {
        for rpm in ["250", "3500", "5000", "-5000"] {
            assert_eq!(
                warnings_with(&[&format!("drivers.motor.speed_rpm={rpm}")]),
                Vec::<String>::new(),
                "{rpm} rpm"
            );
        }
    }

    #[test]
    fn rpm_typed_as_rad_per_second_and_degrees_as_radians_are_named() {
        assert_eq!(
            warnings_with_speed("speed = 3500.0"),
            [
                "drivers.motor: 3500 rad/s (33423 rpm) moves points 0.25 m from the driven joint at 875 m/s, faster than linkages of this size run (over 200 m/s); `speed` is in rad/s: for revolutions per minute write speed_rpm"
            ]
        );
        // The same speed as rpm is the paper's.
        assert_eq!(
            warnings_with_speed("speed_rpm = 3500.0"),
            Vec::<String>::new()
        );
        let w = warnings_with(&["drivers.motor.initial_angle=90"]);
        assert_eq!(
            w,
            [
                "drivers.motor.initial_angle = 90 rad is more than a turn (2π = 6.2832 rad); angles are in radians (90 degrees would be 1.5708 rad)"
            ]
        );
    }
}
