//! Drivers: prescribed angles, speeds and motions, and the driver speed in rpm or rad/s.

use super::*;

impl Builder<'_, '_> {
    /// Kinematic drivers, and torque drivers as [`ForceElement::Motor`].
    pub(super) fn drivers(
        &self,
        raw: &[DriverFile],
        joints: &[Joint],
        bodies: &[Body],
    ) -> Res<(Vec<Driver>, Vec<ForceElement>)> {
        let mut seen = HashSet::new();
        let mut driven = HashSet::new();
        let mut drivers = Vec::with_capacity(raw.len());
        let mut motors = Vec::new();
        for d in raw {
            let name = self.unique(&mut seen, &d.name, "driver")?;
            let kind = d.kind.get_ref().trim();
            const KINDS: [&str; 4] = ["constant-speed", "speed-ramp", "prescribed-angle", "torque"];
            if !KINDS.contains(&kind) {
                return Err(self.err(
                    d.kind.span(),
                    format!(
                        "unknown driver type \"{kind}\"; expected one of {}{}",
                        KINDS.join(", "),
                        did_you_mean(kind, KINDS)
                    ),
                ));
            }
            let sn = |o: &Option<Num>| o.as_ref().map(|v| v.span());
            let present = [
                ("speed_rpm", sn(&d.speed_rpm)),
                ("speed", sn(&d.speed)),
                ("initial_angle", sn(&d.initial_angle)),
                ("speed0", sn(&d.speed0)),
                ("speed1", sn(&d.speed1)),
                ("speed0_rpm", sn(&d.speed0_rpm)),
                ("speed1_rpm", sn(&d.speed1_rpm)),
                ("start", sn(&d.start)),
                ("duration", sn(&d.duration)),
                ("shape", d.shape.as_ref().map(|v| v.span())),
                ("angle", sn(&d.angle)),
                ("torque", sn(&d.torque)),
            ];
            let allowed: &[&str] = match kind {
                "constant-speed" => &["speed_rpm", "speed", "initial_angle"],
                "speed-ramp" => &[
                    "speed0",
                    "speed1",
                    "speed0_rpm",
                    "speed1_rpm",
                    "start",
                    "duration",
                    "shape",
                    "initial_angle",
                ],
                "prescribed-angle" => &["angle"],
                _ => &["torque"],
            };
            self.only_fields(&present, allowed, &format!("{kind} driver"))?;
            let joint_name = self.text(&d.joint)?;
            let joint_name = joint_name.trim();
            let id = joints
                .iter()
                .position(|j| j.name == joint_name)
                .ok_or_else(|| {
                    self.err(
                        d.joint.span(),
                        format!(
                            "unknown joint \"{joint_name}\" in driver \"{name}\"{}",
                            did_you_mean(joint_name, joints.iter().map(|j| j.name.as_str()))
                        ),
                    )
                })?;
            if !matches!(joints[id].kind, JointKind::Revolute) {
                return Err(self.err(
                    d.joint.span(),
                    format!(
                        "driver \"{name}\" drives joint \"{joint_name}\", which is {}; a {kind} driver needs a revolute joint",
                        joints[id].kind.type_name()
                    ),
                ));
            }
            if !driven.insert(id) {
                return Err(self.err(
                    d.joint.span(),
                    format!(
                        "joint \"{joint_name}\" already has a driver; expected one driver per joint"
                    ),
                ));
            }
            let initial_angle = || -> Res<f64> {
                Ok(d.initial_angle
                    .as_ref()
                    .map(|v| {
                        self.within(v, "initial angle (rad)", -MAX_ANGLE, MAX_ANGLE, ANGLE_WHY)
                    })
                    .transpose()?
                    .unwrap_or(0.0))
            };
            let joint = &joints[id];
            let (speed, initial_angle, motion) = match kind {
                "constant-speed" => (
                    self.speed(&d.speed_rpm, &d.speed, "speed", &name, d.name.span())?,
                    initial_angle()?,
                    DriverMotion::ConstantSpeed,
                ),
                "speed-ramp" => {
                    let speed0 =
                        self.speed(&d.speed0_rpm, &d.speed0, "speed0", &name, d.name.span())?;
                    let speed1 =
                        self.speed(&d.speed1_rpm, &d.speed1, "speed1", &name, d.name.span())?;
                    let what = format!("speed-ramp driver \"{name}\"");
                    let duration = self.positive(
                        self.required(&d.duration, "duration", &what, d.name.span())?,
                        "ramp duration (s)",
                    )?;
                    let start = d
                        .start
                        .as_ref()
                        .map(|v| self.non_negative(v, "ramp start (s)"))
                        .transpose()?
                        .unwrap_or(0.0);
                    let smooth = match d.shape.as_ref().map(|s| (s.get_ref().trim(), s.span())) {
                        None | Some(("smooth", _)) => true,
                        Some(("linear", _)) => false,
                        Some((other, span)) => {
                            return Err(self.err(
                                span,
                                format!(
                                    "unknown ramp shape \"{other}\"; expected \"smooth\" or \"linear\"{}",
                                    did_you_mean(other, ["smooth", "linear"])
                                ),
                            ));
                        }
                    };
                    (
                        speed1,
                        initial_angle()?,
                        DriverMotion::SpeedRamp {
                            speed0,
                            speed1,
                            start,
                            duration,
                            smooth,
                        },
                    )
                }
                "prescribed-angle" => {
                    let what = format!("prescribed-angle driver \"{name}\"");
                    let angle = self.required(&d.angle, "angle", &what, d.name.span())?;
                    let scope = RunScope {
                        values: &self.values,
                        bodies,
                        driver: Err(String::new()),
                        time_only: true,
                    };
                    let e = self.run_expr(angle, &scope, "angle (rad)")?;
                    let [theta0, ..] = e.tree.eval_jet(0.0).0;
                    if !theta0.is_finite() {
                        return Err(self.err(
                            angle.span(),
                            format!(
                                "prescribed angle is {theta0} at t = 0; expected a finite angle"
                            ),
                        ));
                    }
                    if theta0.abs() > MAX_ANGLE {
                        return Err(self.err(
                            angle.span(),
                            format!(
                                "prescribed angle is {theta0:e} rad at t = 0; expected at most {MAX_ANGLE:e} rad in magnitude ({ANGLE_WHY})"
                            ),
                        ));
                    }
                    (0.0, theta0, DriverMotion::PrescribedAngle(e))
                }
                _ => {
                    let what = format!("torque driver \"{name}\"");
                    let torque = self.required(&d.torque, "torque", &what, d.name.span())?;
                    let scope = RunScope {
                        values: &self.values,
                        bodies,
                        driver: Ok((joint.a.frame, joint.b.frame)),
                        time_only: false,
                    };
                    motors.push(ForceElement::Motor {
                        name,
                        joint: JointId(id),
                        a: joint.a.frame,
                        b: joint.b.frame,
                        torque: self.run_expr(torque, &scope, "torque (N·m)")?,
                    });
                    continue;
                }
            };
            drivers.push(Driver {
                name,
                joint: JointId(id),
                speed,
                initial_angle,
                motion,
            });
        }
        Ok((drivers, motors))
    }

    /// A speed given in rpm (`{field}_rpm`) or rad/s (`{field}`), exactly one of them.
    pub(super) fn speed(
        &self,
        rpm: &Option<Num>,
        rad_s: &Option<Num>,
        field: &str,
        name: &str,
        at: Range<usize>,
    ) -> Res<f64> {
        // The bound applies to the speed in rad/s, after the conversion from rpm: a finite rpm
        // can overflow it (1e308 rpm is an infinite speed in rad/s).
        let bounded = |given: &Num, written: String, omega: f64| -> Res<f64> {
            if omega.abs() <= MAX_SPEED {
                Ok(omega)
            } else {
                Err(self.err(
                    given.span(),
                    format!(
                        "expected a driver speed of at most {MAX_SPEED:e} rad/s ({:.0} rpm) in magnitude ({SPEED_WHY}), found {written}",
                        MAX_SPEED * 30.0 / std::f64::consts::PI
                    ),
                ))
            }
        };
        match (rpm, rad_s) {
            (Some(rpm), None) => {
                let n = self.finite(rpm, &format!("{field}_rpm"))?;
                let omega = n * std::f64::consts::PI / 30.0;
                bounded(
                    rpm,
                    format!("{field}_rpm = {n:e}, {omega:.3e} rad/s"),
                    omega,
                )
            }
            (None, Some(w)) => {
                let omega = self.finite(w, &format!("{field} (rad/s)"))?;
                bounded(w, format!("{field} = {omega:e} rad/s"), omega)
            }
            (Some(_), Some(w)) => Err(self.err(
                w.span(),
                format!("give either `{field}_rpm` or `{field}` (rad/s), not both"),
            )),
            (None, None) => Err(self.err(
                at,
                format!("missing field `{field}_rpm` or `{field}` (rad/s) of driver \"{name}\""),
            )),
        }
    }
}
