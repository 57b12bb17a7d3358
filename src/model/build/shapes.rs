//! The optional `shapes` of a body: how figures and animations draw it. Resolved to body-frame
//! coordinates here; they take no part in the dynamics.

use super::super::file::{Name, Num, ShapeFile};
use super::super::suggest::did_you_mean;
use super::super::types::Shape;
use super::{Builder, Res};
use toml::Spanned;

impl Builder<'_, '_> {
    /// The shapes of body `body`, whose points are `points` (body frame, m).
    pub(super) fn shapes(
        &self,
        raw: &[Spanned<ShapeFile>],
        points: &[(String, [f64; 2])],
        body: &str,
    ) -> Res<Vec<Shape>> {
        raw.iter().map(|s| self.shape(s, points, body)).collect()
    }

    fn shape(
        &self,
        raw: &Spanned<ShapeFile>,
        points: &[(String, [f64; 2])],
        body: &str,
    ) -> Res<Shape> {
        let s = raw.get_ref();
        let kind = s.kind.get_ref().trim();
        let owner = format!("a {kind} shape of body \"{body}\"");
        let point = |name: &Name| -> Res<[f64; 2]> {
            let wanted = name.get_ref().trim();
            points
                .iter()
                .find(|(n, _)| n == wanted)
                .map(|(_, p)| *p)
                .ok_or_else(|| {
                    let names: Vec<&str> = points.iter().map(|(n, _)| n.as_str()).collect();
                    let hint = match did_you_mean(wanted, names.iter().copied()) {
                        h if !h.is_empty() => h,
                        _ => format!("; body \"{body}\" has points {}", names.join(", ")),
                    };
                    self.err(
                        name.span(),
                        format!("unknown point \"{wanted}\" in {owner}{hint}"),
                    )
                })
        };
        // Fields of the other types are refused by name, so a typo in `type` is not silently
        // drawn as something else.
        let foreign = |allowed: &[&str]| -> Res<()> {
            let given = [
                ("from", s.from.is_some()),
                ("to", s.to.is_some()),
                ("width", s.width.is_some()),
                ("points", s.points.is_some()),
                ("vertices", s.vertices.is_some()),
                ("at", s.at.is_some()),
                ("centre", s.centre.is_some()),
                ("radius", s.radius.is_some()),
            ];
            match given
                .iter()
                .find(|(field, present)| *present && !allowed.contains(field))
            {
                Some((field, _)) => Err(self.err(
                    raw.span(),
                    format!(
                        "`{field}` does not belong to {owner} (it takes {})",
                        allowed.join(", ")
                    ),
                )),
                None => Ok(()),
            }
        };
        let positive = |v: &Option<Num>, field: &str, what: &str| -> Res<f64> {
            match v {
                Some(v) => self.positive(v, what),
                None => Err(self.err(raw.span(), format!("{owner} needs `{field}`"))),
            }
        };
        match kind {
            "bar" => {
                foreign(&["from", "to", "width"])?;
                let (Some(from), Some(to)) = (&s.from, &s.to) else {
                    return Err(self.err(raw.span(), format!("{owner} needs `from` and `to`")));
                };
                Ok(Shape::Bar {
                    from: point(from)?,
                    to: point(to)?,
                    width: positive(&s.width, "width", "bar width (m)")?,
                })
            }
            "polygon" => {
                foreign(&["points", "vertices"])?;
                let vertices = match (&s.points, &s.vertices) {
                    (Some(names), None) => names.iter().map(point).collect::<Res<Vec<_>>>()?,
                    (None, Some(v)) => v
                        .get_ref()
                        .iter()
                        .map(|p| self.vec2(p, "polygon vertex (m)"))
                        .collect::<Res<Vec<_>>>()?,
                    _ => {
                        return Err(self.err(
                            raw.span(),
                            format!("{owner} needs either `points` or `vertices`"),
                        ));
                    }
                };
                if vertices.len() < 3 {
                    return Err(self.err(
                        raw.span(),
                        format!(
                            "{owner} needs at least 3 corners, found {}",
                            vertices.len()
                        ),
                    ));
                }
                Ok(Shape::Polygon { vertices })
            }
            "disc" => {
                foreign(&["at", "centre", "radius"])?;
                let centre = match (&s.at, &s.centre) {
                    (Some(at), None) => point(at)?,
                    (None, Some(c)) => self.vec2(c, "disc centre (m)")?,
                    _ => {
                        return Err(self.err(
                            raw.span(),
                            format!("{owner} needs either `at` or `centre`"),
                        ));
                    }
                };
                Ok(Shape::Disc {
                    centre,
                    radius: positive(&s.radius, "radius", "disc radius (m)")?,
                })
            }
            other => Err(self.err(
                s.kind.span(),
                format!(
                    "unknown shape type \"{other}\" on body \"{body}\" (expected \"bar\", \"polygon\" or \"disc\"){}",
                    did_you_mean(other, ["bar", "polygon", "disc"])
                ),
            )),
        }
    }
}
