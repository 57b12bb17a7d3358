//! Force elements: gravity, springs, dampers, torques and point loads.

use super::*;

impl Builder<'_, '_> {
    pub(super) fn forces(
        &self,
        raw: &[ForceFile],
        scope: &Scope<'_>,
        theta: &Result<(Frame, Frame), String>,
        seen: &mut HashSet<String>,
    ) -> Res<Vec<ForceElement>> {
        let run = RunScope {
            values: &self.values,
            bodies: scope.bodies,
            driver: theta.clone(),
            time_only: false,
        };
        let mut forces = Vec::with_capacity(raw.len());
        for f in raw {
            let name = self.unique(seen, &f.name, "force")?;
            let owner = format!("force \"{name}\"");
            let sp = |o: &Option<Name>| o.as_ref().map(|v| v.span());
            let sn = |o: &Option<Num>| o.as_ref().map(|v| v.span());
            let present = [
                ("body_a", sp(&f.body_a)),
                ("point_a", sp(&f.point_a)),
                ("body_b", sp(&f.body_b)),
                ("point_b", sp(&f.point_b)),
                ("stiffness", sn(&f.stiffness)),
                ("damping", sn(&f.damping)),
                ("free_length", sn(&f.free_length)),
                ("body", sp(&f.body)),
                ("point", sp(&f.point)),
                ("torque", sn(&f.torque)),
                ("force", f.force.as_ref().map(|v| v.span())),
            ];
            let at = f.name.span();
            let kind = f.kind.get_ref().trim();
            let what = format!("{kind} \"{name}\"");
            let element = match kind {
                "spring-damper" => {
                    self.only_fields(
                        &present,
                        &[
                            "body_a",
                            "point_a",
                            "body_b",
                            "point_b",
                            "stiffness",
                            "damping",
                            "free_length",
                        ],
                        "spring-damper",
                    )?;
                    let a = self.anchor(
                        scope,
                        self.required(&f.body_a, "body_a", &what, at.clone())?,
                        self.required(&f.point_a, "point_a", &what, at.clone())?,
                        &owner,
                    )?;
                    let b = self.anchor(
                        scope,
                        self.required(&f.body_b, "body_b", &what, at.clone())?,
                        self.required(&f.point_b, "point_b", &what, at.clone())?,
                        &owner,
                    )?;
                    let opt = |v: &Option<Num>, what| {
                        v.as_ref().map(|v| self.non_negative(v, what)).transpose()
                    };
                    ForceElement::SpringDamper {
                        name,
                        a,
                        b,
                        stiffness: opt(&f.stiffness, "stiffness (N/m)")?.unwrap_or(0.0),
                        damping: opt(&f.damping, "damping (N·s/m)")?.unwrap_or(0.0),
                        free_length: self.non_negative(
                            self.required(&f.free_length, "free_length", &what, at.clone())?,
                            "free length (m)",
                        )?,
                    }
                }
                "torque" => {
                    self.only_fields(&present, &["body", "torque"], "torque")?;
                    let body = self.required(&f.body, "body", &what, at.clone())?;
                    let body = self.body_of(scope, body, &owner)?;
                    let torque = self.run_expr(
                        self.required(&f.torque, "torque", &what, at.clone())?,
                        &run,
                        "torque (N·m)",
                    )?;
                    match torque.tree.constant() {
                        Some(torque) => ForceElement::Torque { name, body, torque },
                        None => ForceElement::TorqueLaw { name, body, torque },
                    }
                }
                "force" => {
                    self.only_fields(&present, &["body", "point", "force"], "force")?;
                    let body = self.required(&f.body, "body", &what, at.clone())?;
                    let point = self.required(&f.point, "point", &what, at.clone())?;
                    let at_anchor = self.anchor(scope, body, point, &owner)?;
                    if at_anchor.frame == Frame::Ground {
                        return Err(self.err(
                            body.span(),
                            format!("{owner} acts on the ground; expected a moving body"),
                        ));
                    }
                    let force = self.required(&f.force, "force", &what, at.clone())?;
                    let [fx, fy] = self.run_vec2(force, &run, "force (N)")?;
                    match (fx.tree.constant(), fy.tree.constant()) {
                        (Some(x), Some(y)) => ForceElement::PointForce {
                            name,
                            at: at_anchor,
                            force: [x, y],
                        },
                        _ => ForceElement::ForceLaw {
                            name,
                            at: at_anchor,
                            force: [fx, fy],
                        },
                    }
                }
                other => {
                    let kinds = ["spring-damper", "torque", "force"];
                    return Err(self.err(
                        f.kind.span(),
                        format!(
                            "unknown force type \"{other}\"; expected one of {}{}",
                            kinds.join(", "),
                            did_you_mean(other, kinds)
                        ),
                    ));
                }
            };
            forces.push(element);
        }
        Ok(forces)
    }
}
