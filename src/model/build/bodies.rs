//! Ground points, bodies (mass, inertia against the body's size, points) and the anchors that joints, drivers and forces name.

use super::*;

impl Builder<'_, '_> {
    pub(super) fn points(
        &self,
        points: &std::collections::BTreeMap<Name, Vec2>,
        owner: &str,
    ) -> Res<Vec<(String, [f64; 2])>> {
        let mut out = Vec::with_capacity(points.len());
        for (name, p) in points {
            let n = self.name_on(name, "point", &format!(" on {owner}"))?;
            let at = self.vec2(p, "point (m)")?;
            if at.iter().any(|x| x.abs() > MAX_COORDINATE) {
                return Err(self.err(
                    p.span(),
                    format!(
                        "expected the coordinates of point \"{n}\" on {owner} in [{:e}, {MAX_COORDINATE:e}] m ({COORDINATE_WHY}), found [{:e}, {:e}]",
                        -MAX_COORDINATE, at[0], at[1]
                    ),
                ));
            }
            out.push((n, at));
        }
        Ok(out)
    }

    pub(super) fn bodies(&self, raw: &[BodyFile], seen: &mut HashSet<String>) -> Res<Vec<Body>> {
        let mut bodies = Vec::with_capacity(raw.len());
        for b in raw {
            let name = self.unique(seen, &b.name, "body")?;
            if name == "ground" {
                return Err(self.err(
                    b.name.span(),
                    "\"ground\" is reserved for the fixed frame; put its points in [ground]",
                ));
            }
            // Positive first (the common slip), then the floor (see `bounds`).
            self.positive(&b.mass, "mass (kg)")?;
            let mass = self.within(
                &b.mass,
                "mass (kg)",
                MIN_MASS,
                MAX_MASS,
                "real linkages: from a 1 µm steel cube to ten times the largest excavator boom",
            )?;
            self.positive(&b.inertia, "moment of inertia (kg·m²)")?;
            let inertia = self.within(
                &b.inertia,
                "moment of inertia (kg·m²)",
                MIN_INERTIA,
                f64::INFINITY,
                "a 1 µm steel cube",
            )?;
            let points = self.points(&b.points, &format!("body \"{name}\""))?;
            let i = b.initial.get_ref();
            let opt = |v: &Option<Num>, what, limit: f64, why| {
                v.as_ref()
                    .map(|v| self.within(v, what, -limit, limit, why))
                    .transpose()
                    .map(|x| x.unwrap_or(0.0))
            };
            let coordinate = |v: &Num, what| {
                self.within(v, what, -MAX_COORDINATE, MAX_COORDINATE, COORDINATE_WHY)
            };
            const VELOCITY_WHY: &str =
                "real linkages: a point 1 m from its pivot at 95 500 rpm moves at 1e4 m/s";
            let initial = BodyState {
                x: coordinate(&i.x, "initial x (m)")?,
                y: coordinate(&i.y, "initial y (m)")?,
                phi: self.within(
                    &i.phi,
                    "initial phi (rad)",
                    -MAX_ANGLE,
                    MAX_ANGLE,
                    ANGLE_WHY,
                )?,
                vx: opt(&i.vx, "initial vx (m/s)", MAX_VELOCITY, VELOCITY_WHY)?,
                vy: opt(&i.vy, "initial vy (m/s)", MAX_VELOCITY, VELOCITY_WHY)?,
                omega: opt(&i.omega, "initial omega (rad/s)", MAX_SPEED, SPEED_WHY)?,
            };
            let shapes = self.shapes(&b.shapes, &points, &name)?;
            bodies.push(Body {
                name,
                mass,
                inertia,
                points,
                initial,
                shapes,
            });
        }
        Ok(bodies)
    }

    /// Refuses a moment of inertia whose radius of gyration √(I/m) exceeds
    /// [`MAX_GYRATION_PER_EXTENT`] times the linkage's `extent` (m).
    pub(super) fn inertia_fits(&self, raw: &BodyFile, body: Option<&Body>, extent: f64) -> Res<()> {
        // Bodies are built from the same list in the same order; none left is a bug, not input.
        let Some(body) = body else {
            debug_assert!(false, "one built body per raw body");
            return Ok(());
        };
        let limit = body.mass * (MAX_GYRATION_PER_EXTENT * extent).powi(2);
        if body.inertia <= limit {
            return Ok(());
        }
        Err(self.err(
            raw.inertia.span(),
            format!(
                "expected a moment of inertia (kg·m²) of body \"{}\" of at most m·({MAX_GYRATION_PER_EXTENT}·D)² = {limit:.3e}, its mass m = {:.3e} kg at {MAX_GYRATION_PER_EXTENT} times the linkage's extent D = {extent:.3e} m (real linkages: bodies reach beyond their joints, but not by a thousand times the linkage), found {:.3e} (a radius of gyration √(I/m) of {:.3e} m)",
                body.name,
                body.mass,
                body.inertia,
                (body.inertia / body.mass).sqrt()
            ),
        ))
    }

    /// Resolves `body` and `point` names to an anchor; `owner` is e.g. `joint "A"`.
    pub(super) fn anchor(
        &self,
        scope: &Scope<'_>,
        body: &Name,
        point: &Name,
        owner: &str,
    ) -> Res<Anchor> {
        let body_name = &self.text(body)?;
        let body_name = body_name.trim();
        let point_name = &self.text(point)?;
        let point_name = point_name.trim();
        let (frame, points, where_) = if body_name == "ground" {
            (Frame::Ground, scope.ground_points, "[ground]".to_string())
        } else {
            let id = scope
                .bodies
                .iter()
                .position(|b| b.name == body_name)
                .ok_or_else(|| {
                    let names = std::iter::once("ground")
                        .chain(scope.bodies.iter().map(|b| b.name.as_str()));
                    self.err(
                        body.span(),
                        format!(
                            "unknown body \"{body_name}\" in {owner}{}",
                            did_you_mean(body_name, names)
                        ),
                    )
                })?;
            (
                Frame::Body(BodyId(id)),
                scope.bodies[id].points.as_slice(),
                format!("body \"{body_name}\""),
            )
        };
        let local = points
            .iter()
            .find(|(n, _)| n == point_name)
            .map(|(_, p)| *p)
            .ok_or_else(|| {
                let names: Vec<&str> = points.iter().map(|(n, _)| n.as_str()).collect();
                let hint = match did_you_mean(point_name, names.iter().copied()) {
                    h if !h.is_empty() => h,
                    _ if names.is_empty() => format!("; {where_} has no points"),
                    _ => format!("; {where_} has points {}", names.join(", ")),
                };
                self.err(
                    point.span(),
                    format!("unknown point \"{point_name}\" on {where_} in {owner}{hint}"),
                )
            })?;
        Ok(Anchor {
            frame,
            point: point_name.to_string(),
            local,
        })
    }

    pub(super) fn body_of(&self, scope: &Scope<'_>, body: &Name, owner: &str) -> Res<BodyId> {
        let n = &self.text(body)?;
        let n = n.trim();
        scope
            .bodies
            .iter()
            .position(|b| b.name == n)
            .map(BodyId)
            .ok_or_else(|| {
                self.err(
                    body.span(),
                    format!(
                        "unknown body \"{n}\" in {owner}{}",
                        did_you_mean(n, scope.bodies.iter().map(|b| b.name.as_str()))
                    ),
                )
            })
    }
}
