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

mod shapes;

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

impl Builder<'_, '_> {
    fn err(&self, span: Range<usize>, message: impl Into<String>) -> ModelError {
        match &self.repeat {
            None => self.loc.error(span, message),
            Some((index, i)) => self.loc.error(
                span,
                format!("{} (in [[repeat]] with {index} = {i})", message.into()),
            ),
        }
    }

    /// An error in the expression `text` written at `span`, at the offending token.
    fn expr_err(&self, span: Range<usize>, text: &str, e: ExprError) -> ModelError {
        let start = span.start + self.loc.string_body_offset(span.start) + e.offset;
        self.err(
            start..start + 1,
            format!("in expression \"{}\": {}", abbreviate(text), e.message),
        )
    }

    /// The value of a number or of an expression of parameters.
    fn number(&self, v: &Num) -> Res<f64> {
        match v.get_ref() {
            Scalar::Number(x) => Ok(*x),
            Scalar::Expr(text) => self.static_expr(text, v.span()),
        }
    }

    fn static_expr(&self, text: &str, span: Range<usize>) -> Res<f64> {
        expr::parse(text)
            .and_then(|n| n.resolve(&self.values))
            .map(|e| e.constant().unwrap_or(f64::NAN))
            .map_err(|e| self.expr_err(span, text, e))
    }

    /// A run-time expression (force, torque, prescribed angle): numbers stay numbers.
    fn run_expr(&self, v: &Num, scope: &RunScope<'_>, what: &str) -> Res<Expression> {
        let (text, tree) = match v.get_ref() {
            Scalar::Number(x) => (format!("{x}"), Expr::Num(*x)),
            Scalar::Expr(text) => (
                text.clone(),
                expr::parse(text)
                    .and_then(|n| n.resolve(scope))
                    .map_err(|e| self.expr_err(v.span(), text, e))?,
            ),
        };
        if let Some(x) = tree.constant()
            && !x.is_finite()
        {
            return Err(self.err(v.span(), format!("expected a finite {what}, found {x}")));
        }
        Ok(Expression { text, tree })
    }

    /// The text of a name; inside a `[[repeat]]`, every `{expr}` replaced by the integer value
    /// of `expr` (the index and parameters).
    fn text(&self, name: &Name) -> Res<String> {
        let raw = name.get_ref();
        if self.repeat.is_none() || !raw.contains('{') {
            return Ok(raw.clone());
        }
        let mut out = String::with_capacity(raw.len());
        let mut rest = raw.as_str();
        let mut at = 0;
        while let Some(open) = rest.find('{') {
            out.push_str(&rest[..open]);
            let Some(close) = rest[open..].find('}') else {
                return Err(self.err(
                    name.span(),
                    format!("unclosed '{{' in name template \"{raw}\"; expected {{expression}}"),
                ));
            };
            let inner = &rest[open + 1..open + close];
            let inner_at = at + open + 1;
            let x = expr::parse(inner)
                .and_then(|n| n.resolve(&self.values))
                .map(|e| e.constant().unwrap_or(f64::NAN))
                .map_err(|mut e| {
                    e.offset += inner_at;
                    self.expr_err(name.span(), raw, e)
                })?;
            if !(x.is_finite() && (x - x.round()).abs() < 1e-9) {
                return Err(self.err(
                    name.span(),
                    format!("{{{inner}}} in name template \"{raw}\" is {x}; expected an integer"),
                ));
            }
            out.push_str(&format!("{}", x.round() as i64));
            at += open + close + 1;
            rest = &rest[open + close + 1..];
        }
        out.push_str(rest);
        Ok(out)
    }

    /// `[parameters]`, evaluated.
    fn parameters(&self, raw: &std::collections::BTreeMap<Name, Num>) -> Res<Vec<(String, f64)>> {
        let entries: Vec<(&Name, &Num)> = raw.iter().collect();
        for (name, _) in &entries {
            params::check_name(name.get_ref()).map_err(|reason| {
                self.err(
                    name.span(),
                    format!("invalid parameter name \"{}\": {reason}", name.get_ref()),
                )
            })?;
        }
        let list: Vec<params::RawParameter<'_>> = entries
            .iter()
            .map(|(n, v)| params::RawParameter {
                name: n.get_ref(),
                value: match v.get_ref() {
                    Scalar::Number(x) => Ok(*x),
                    Scalar::Expr(t) => Err(t.as_str()),
                },
            })
            .collect();
        let values = params::evaluate(&list).map_err(|e| {
            let (name, v) = entries[e.index];
            match (e.offset, v.get_ref()) {
                (Some(offset), Scalar::Expr(text)) => self.expr_err(
                    v.span(),
                    text,
                    ExprError {
                        offset,
                        message: e.message,
                    },
                ),
                _ => self.err(name.span(), e.message),
            }
        })?;
        for ((_, v), (name, x)) in entries.iter().zip(&values) {
            if !x.is_finite() {
                return Err(self.err(
                    v.span(),
                    format!("parameter {name} evaluates to {x}; expected a finite number"),
                ));
            }
        }
        Ok(values)
    }

    /// `[[tables]]`.
    fn tables(&self, raw: &[TableFile]) -> Res<Vec<Arc<Table>>> {
        let mut seen = HashSet::new();
        let mut out = Vec::with_capacity(raw.len());
        for t in raw {
            let name = self.unique(&mut seen, &t.name, "table")?;
            params::check_name(&name).map_err(|reason| {
                self.err(
                    t.name.span(),
                    format!("invalid table name \"{name}\": {reason}"),
                )
            })?;
            let list = |v: &Vec2, axis: &str| -> Res<Vec<f64>> {
                v.get_ref()
                    .iter()
                    .map(|c| self.component(c, axis, &format!("table \"{name}\""))
                        .and_then(|x| if x.is_finite() { Ok(x) } else {
                            Err(self.err(c.span(), format!("expected a finite {axis} value in table \"{name}\", found {x}")))
                        }))
                    .collect()
            };
            let x = list(&t.x, "x")?;
            let y = list(&t.y, "y")?;
            if x.len() != y.len() || x.len() < 2 {
                return Err(self.err(
                    t.y.span(),
                    format!(
                        "table \"{name}\" has {} x and {} y values; expected as many of each, at least 2",
                        x.len(),
                        y.len()
                    ),
                ));
            }
            if let Some(k) = (1..x.len()).find(|&k| x[k] <= x[k - 1]) {
                return Err(self.err(
                    t.x.get_ref()[k].span(),
                    format!(
                        "table \"{name}\": x[{k}] = {} is not above x[{}] = {}; expected strictly increasing x",
                        x[k],
                        k - 1,
                        x[k - 1]
                    ),
                ));
            }
            out.push(Arc::new(Table { name, x, y }));
        }
        Ok(out)
    }

    /// One builder per value of the index of a `[[repeat]]`.
    fn repeat(&self, r: &RepeatFile) -> Res<Vec<Builder<'_, '_>>> {
        let index = r.index.get_ref();
        params::check_name(index).map_err(|reason| {
            self.err(
                r.index.span(),
                format!("invalid repeat index \"{index}\": {reason}"),
            )
        })?;
        if self.values.get(index).is_some() {
            return Err(self.err(
                r.index.span(),
                format!("repeat index \"{index}\" is also a parameter; expected a name of its own"),
            ));
        }
        let bound = |v: &Num, what: &str| -> Res<i64> {
            let x = self.number(v)?;
            if x.is_finite() && (x - x.round()).abs() < 1e-9 && x.abs() < 1e6 {
                Ok(x.round() as i64)
            } else {
                Err(self.err(
                    v.span(),
                    format!("expected an integer `{what}` of at most 1e6 in magnitude, found {x}"),
                ))
            }
        };
        let (from, to) = (bound(&r.from, "from")?, bound(&r.to, "to")?);
        if to < from {
            return Err(self.err(
                r.to.span(),
                format!("repeat runs {index} from {from} to {to}; expected to ≥ from"),
            ));
        }
        if to - from >= 100_000 {
            return Err(self.err(
                r.to.span(),
                format!(
                    "repeat runs {index} over {} values; expected at most 100000",
                    to - from + 1
                ),
            ));
        }
        Ok((from..=to)
            .map(|i| Builder {
                loc: self.loc,
                values: self.values.with(index, i as f64),
                repeat: Some((index.clone(), i)),
            })
            .collect())
    }

    /// `[[outputs]]`.
    fn outputs(&self, raw: &[OutputFile], scope: &Scope<'_>) -> Res<Vec<OutputPoint>> {
        let mut seen = HashSet::new();
        let mut out = Vec::with_capacity(raw.len());
        for o in raw {
            let name = self.unique(&mut seen, &o.name, "output")?;
            if let Some(b) = scope.bodies.iter().find(|b| b.name == name) {
                return Err(self.err(
                    o.name.span(),
                    format!("output name \"{name}\" is also a body's name (columns {}.x … would clash); expected a name of its own", b.name),
                ));
            }
            let owner = format!("output \"{name}\"");
            let body = self.body_of(scope, &o.body, &owner)?;
            let at = match (&o.point, &o.local) {
                (Some(p), None) => self.anchor(scope, &o.body, p, &owner)?,
                (None, Some(local)) => Anchor {
                    frame: Frame::Body(body),
                    point: name.clone(),
                    local: self.vec2(local, "local point (m)")?,
                },
                (Some(_), Some(l)) => {
                    return Err(self.err(l.span(), "give either `point` (a named point of the body) or `local` ([x, y] in the body frame), not both"));
                }
                (None, None) => {
                    return Err(self.err(
                        o.name.span(),
                        format!("missing field `point` or `local` of {owner}"),
                    ));
                }
            };
            out.push(OutputPoint { name, at });
        }
        Ok(out)
    }

    fn finite(&self, v: &Num, what: &str) -> Res<f64> {
        let x = self.number(v)?;
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.err(v.span(), format!("expected a finite {what}, found {x}")))
        }
    }

    fn positive(&self, v: &Num, what: &str) -> Res<f64> {
        let x = self.finite(v, what)?;
        if x > 0.0 {
            Ok(x)
        } else {
            Err(self.err(v.span(), format!("expected a positive {what}, found {x}")))
        }
    }

    /// A finite value in `[min, max]`; `why` says where the bounds come from.
    fn within(&self, v: &Num, what: &str, min: f64, max: f64, why: &str) -> Res<f64> {
        let x = self.finite(v, what)?;
        let a = if what.starts_with(['a', 'e', 'i', 'o', 'u']) {
            "an"
        } else {
            "a"
        };
        if (min..=max).contains(&x) {
            Ok(x)
        } else if max == f64::INFINITY {
            Err(self.err(
                v.span(),
                format!("expected {a} {what} of at least {min:e} ({why}), found {x:e}"),
            ))
        } else {
            Err(self.err(
                v.span(),
                format!("expected {a} {what} in [{min:e}, {max:e}] ({why}), found {x:e}"),
            ))
        }
    }

    fn non_negative(&self, v: &Num, what: &str) -> Res<f64> {
        let x = self.finite(v, what)?;
        if x >= 0.0 {
            Ok(x)
        } else {
            Err(self.err(
                v.span(),
                format!("expected a non-negative {what}, found {x}"),
            ))
        }
    }

    fn vec2(&self, v: &Vec2, what: &str) -> Res<[f64; 2]> {
        let items = v.get_ref();
        let [x, y] = match items.as_slice() {
            [x, y] => [self.component(x, "x", what)?, self.component(y, "y", what)?],
            _ => {
                return Err(self.err(
                    v.span(),
                    format!(
                        "expected 2 components [x, y] for the {what}, found {} component{}",
                        items.len(),
                        if items.len() == 1 { "" } else { "s" }
                    ),
                ));
            }
        };
        if x.is_finite() && y.is_finite() {
            Ok([x, y])
        } else {
            Err(self.err(
                v.span(),
                format!("expected a finite {what}, found [{x}, {y}]"),
            ))
        }
    }

    /// One component of a vector: a TOML integer or float.
    fn component(&self, v: &Spanned<toml::Value>, axis: &str, what: &str) -> Res<f64> {
        match v.get_ref() {
            toml::Value::Float(x) => Ok(*x),
            // An integer is read as the float nearest it, as serde does for f64 fields.
            toml::Value::Integer(i) => Ok(*i as f64),
            toml::Value::String(text) => self.static_expr(text, v.span()),
            other => Err(self.err(
                v.span(),
                format!(
                    "expected a number for the {axis} component of the {what}, found a {} {other}",
                    other.type_str()
                ),
            )),
        }
    }

    /// A name that follows [`names::check`]: it heads CSV columns and provenance lines.
    /// `owner` is empty or e.g. ` on body "crank"`.
    fn name_on(&self, name: &Name, what: &str, owner: &str) -> Res<String> {
        let n = &self.text(name)?;
        names::check(n).map_err(|reason| {
            self.err(
                name.span(),
                format!(
                    "invalid {what} name {n:?}{owner}: {reason}; expected {}",
                    names::RULE
                ),
            )
        })?;
        Ok(n.clone())
    }

    fn unique(&self, seen: &mut HashSet<String>, name: &Name, what: &str) -> Res<String> {
        let n = self.name_on(name, what, "")?;
        if !seen.insert(n.clone()) {
            return Err(self.err(name.span(), format!("duplicate {what} name \"{n}\"")));
        }
        Ok(n)
    }

    fn settings(&self, s: &SettingsFile) -> Res<Settings> {
        let gravity = match &s.gravity {
            Some(g) => self.vec2(g, "gravity vector (m/s²)")?,
            None => [0.0, -9.81],
        };
        let baumgarte = match &s.baumgarte {
            None => Baumgarte::default(),
            Some(bf) => self.baumgarte(bf)?,
        };
        Ok(Settings { gravity, baumgarte })
    }

    fn baumgarte(&self, bf: &Spanned<BaumgarteFile>) -> Res<Baumgarte> {
        let f = bf.get_ref();
        let nn = |v: &Option<Num>, what| v.as_ref().map(|v| self.non_negative(v, what)).transpose();
        let (alpha, beta, omega, zeta) = (
            nn(&f.alpha, "alpha (1/s)")?,
            nn(&f.beta, "beta (1/s)")?,
            nn(&f.omega, "omega (rad/s)")?,
            nn(&f.zeta, "zeta")?,
        );
        let physical = omega.is_some() || zeta.is_some();
        let direct = alpha.is_some() || beta.is_some();
        if physical && direct {
            return Err(self.err(
                bf.span(),
                "give either alpha and beta, or omega and zeta, not both",
            ));
        }
        let default = Baumgarte::default();
        if physical {
            let omega = omega.unwrap_or(default.beta);
            let zeta = zeta.unwrap_or(1.0);
            Ok(Baumgarte {
                alpha: zeta * omega,
                beta: omega,
            })
        } else {
            Ok(Baumgarte {
                alpha: alpha.unwrap_or(default.alpha),
                beta: beta.unwrap_or(default.beta),
            })
        }
    }

    fn points(
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

    fn bodies(&self, raw: &[BodyFile], seen: &mut HashSet<String>) -> Res<Vec<Body>> {
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
    fn inertia_fits(&self, raw: &BodyFile, body: Option<&Body>, extent: f64) -> Res<()> {
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
    fn anchor(&self, scope: &Scope<'_>, body: &Name, point: &Name, owner: &str) -> Res<Anchor> {
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

    /// Refuses fields that do not belong to the entry's type.
    fn only_fields(
        &self,
        present: &[(&str, Option<Range<usize>>)],
        allowed: &[&str],
        what: &str,
    ) -> Res<()> {
        for (field, span) in present {
            if let Some(span) = span
                && !allowed.contains(field)
            {
                return Err(self.err(
                    span.clone(),
                    format!(
                        "field `{field}` does not belong to a {what}; expected only {}",
                        allowed.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }

    fn required<'n, T>(
        &self,
        v: &'n Option<T>,
        field: &str,
        what: &str,
        at: Range<usize>,
    ) -> Res<&'n T> {
        v.as_ref()
            .ok_or_else(|| self.err(at, format!("missing field `{field}` of {what}")))
    }

    fn joints(
        &self,
        raw: &[JointFile],
        scope: &Scope<'_>,
        seen: &mut HashSet<String>,
    ) -> Res<Vec<Joint>> {
        let mut joints = Vec::with_capacity(raw.len());
        for j in raw {
            let name = self.unique(seen, &j.name, "joint")?;
            let owner = format!("joint \"{name}\"");
            let sp = |o: &Option<Name>| o.as_ref().map(|v| v.span());
            let sn = |o: &Option<Num>| o.as_ref().map(|v| v.span());
            let present = [
                ("body_a", sp(&j.body_a)),
                ("point_a", sp(&j.point_a)),
                ("body_b", sp(&j.body_b)),
                ("point_b", sp(&j.point_b)),
                ("axis", j.axis.as_ref().map(|v| v.span())),
                ("angle", sn(&j.angle)),
                ("bearing", sp(&j.bearing)),
                ("bearing_point", sp(&j.bearing_point)),
                ("journal", sp(&j.journal)),
                ("journal_point", sp(&j.journal_point)),
                ("clearance", sn(&j.clearance)),
                ("journal_radius", sn(&j.journal_radius)),
                ("youngs_modulus", sn(&j.youngs_modulus)),
                ("poisson_ratio", sn(&j.poisson_ratio)),
                (
                    "bearing_material",
                    j.bearing_material.as_ref().map(|v| v.span()),
                ),
                (
                    "journal_material",
                    j.journal_material.as_ref().map(|v| v.span()),
                ),
                ("stiffness", sn(&j.stiffness)),
                (
                    "initial_eccentricity",
                    j.initial_eccentricity.as_ref().map(|v| v.span()),
                ),
                ("contact", j.contact.as_ref().map(|v| v.span())),
                ("friction", j.friction.as_ref().map(|v| v.span())),
                ("ideal", j.ideal.as_ref().map(|v| v.span())),
            ];
            let at = j.name.span();
            let kind_name = j.kind.get_ref().trim();
            let (a, b, kind) = match kind_name {
                "revolute" | "prismatic" => {
                    let mut allowed = vec!["body_a", "point_a", "body_b", "point_b"];
                    if kind_name == "prismatic" {
                        allowed.extend(["axis", "angle"]);
                    }
                    self.only_fields(&present, &allowed, &format!("{kind_name} joint"))?;
                    let what = format!("{kind_name} joint \"{name}\"");
                    let a = self.anchor(
                        scope,
                        self.required(&j.body_a, "body_a", &what, at.clone())?,
                        self.required(&j.point_a, "point_a", &what, at.clone())?,
                        &owner,
                    )?;
                    let b = self.anchor(
                        scope,
                        self.required(&j.body_b, "body_b", &what, at.clone())?,
                        self.required(&j.point_b, "point_b", &what, at.clone())?,
                        &owner,
                    )?;
                    let kind = if kind_name == "revolute" {
                        JointKind::Revolute
                    } else {
                        JointKind::Prismatic {
                            axis: self.axis(j.axis.as_ref())?,
                            angle: j
                                .angle
                                .as_ref()
                                .map(|v| self.finite(v, "angle (rad)"))
                                .transpose()?
                                .unwrap_or(0.0),
                        }
                    };
                    (a, b, kind)
                }
                "clearance" => {
                    let allowed = [
                        "bearing",
                        "bearing_point",
                        "journal",
                        "journal_point",
                        "clearance",
                        "journal_radius",
                        "youngs_modulus",
                        "poisson_ratio",
                        "bearing_material",
                        "journal_material",
                        "stiffness",
                        "initial_eccentricity",
                        "contact",
                        "friction",
                        "ideal",
                    ];
                    self.only_fields(&present, &allowed, "clearance joint")?;
                    let what = format!("clearance joint \"{name}\"");
                    let a = self.anchor(
                        scope,
                        self.required(&j.bearing, "bearing", &what, at.clone())?,
                        self.required(&j.bearing_point, "bearing_point", &what, at.clone())?,
                        &owner,
                    )?;
                    let b = self.anchor(
                        scope,
                        self.required(&j.journal, "journal", &what, at.clone())?,
                        self.required(&j.journal_point, "journal_point", &what, at.clone())?,
                        &owner,
                    )?;
                    (
                        a,
                        b,
                        JointKind::Clearance(self.clearance(j, &what, at.clone())?),
                    )
                }
                other => {
                    return Err(self.err(
                        j.kind.span(),
                        format!(
                            "unknown joint type \"{other}\"; expected \"revolute\", \"prismatic\" or \"clearance\"{}",
                            did_you_mean(other, ["revolute", "prismatic", "clearance"])
                        ),
                    ));
                }
            };
            if a.frame == b.frame {
                return Err(self.err(
                    at,
                    format!(
                        "joint \"{name}\" connects \"{}\" to itself; expected two different bodies",
                        match a.frame {
                            Frame::Ground => "ground",
                            Frame::Body(id) => &scope.bodies[id.0].name,
                        }
                    ),
                ));
            }
            let joint = Joint { name, a, b, kind };
            // `ideal = true`: the clearance data above are validated, then set aside.
            if j.ideal.as_ref().is_some_and(|v| *v.get_ref()) {
                joints.push(super::ideal::ideal_joint(joint));
            } else {
                joints.push(joint);
            }
        }
        Ok(joints)
    }

    fn axis(&self, axis: Option<&Vec2>) -> Res<[f64; 2]> {
        let Some(v) = axis else {
            return Ok([1.0, 0.0]);
        };
        let [x, y] = self.vec2(v, "axis")?;
        let n = x.hypot(y);
        if n < 1e-12 {
            return Err(self.err(v.span(), "expected a non-zero sliding axis, found [0, 0]"));
        }
        Ok([x / n, y / n])
    }

    fn material(&self, m: &Spanned<MaterialFile>) -> Res<Material> {
        let f = m.get_ref();
        Ok(Material {
            youngs_modulus: self.youngs_modulus(&f.youngs_modulus)?,
            poisson_ratio: self.poisson(&f.poisson_ratio)?,
        })
    }

    fn youngs_modulus(&self, v: &Num) -> Res<f64> {
        self.within(
            v,
            "Young's modulus (Pa)",
            MIN_YOUNGS_MODULUS,
            MAX_YOUNGS_MODULUS,
            "from soft rubber to diamond",
        )
    }

    /// ν ∈ (−1, 0.5): the bounds of a stable isotropic solid, both open; at ν = −1 both
    /// compliances σ = (1 − ν²)/E vanish and K = 4/(3(σ_J + σ_B)) divides by zero.
    fn poisson(&self, v: &Num) -> Res<f64> {
        let nu = self.finite(v, "Poisson ratio")?;
        if nu > -1.0 && nu < 0.5 {
            Ok(nu)
        } else {
            Err(self.err(
                v.span(),
                format!("expected a Poisson ratio in (-1, 0.5), found {nu}"),
            ))
        }
    }

    fn clearance(&self, j: &JointFile, what: &str, at: Range<usize>) -> Res<ClearanceSpec> {
        let c_field = self.required(&j.clearance, "clearance", what, at.clone())?;
        self.positive(c_field, "radial clearance (m)")?;
        let r_field = self.required(&j.journal_radius, "journal_radius", what, at.clone())?;
        self.positive(r_field, "journal radius (m)")?;
        let journal_radius = self.within(
            r_field,
            "journal radius (m)",
            MIN_JOURNAL_RADIUS,
            MAX_JOURNAL_RADIUS,
            "from micro-mechanism pins to ship shafts",
        )?;
        let clearance = self.within(
            c_field,
            "radial clearance (m)",
            MIN_CLEARANCE,
            f64::INFINITY,
            "the roughness of polished surfaces",
        )?;
        // c ≥ R_J makes the bearing at least twice the journal's size: no longer a joint with
        // clearance, and the contact geometry (nearly conforming cylinders) no longer holds.
        if clearance >= journal_radius {
            return Err(self.err(
                c_field.span(),
                format!(
                    "radial clearance c = {clearance:e} m is not smaller than the journal radius R_J = {journal_radius:e} m; expected c < R_J (a bearing of more than twice the journal's radius is not a clearance joint)"
                ),
            ));
        }
        // Shared material first; a per-side table overrides it. Steel (207 GPa, 0.3) by default,
        // as in Flores et al. 2007 for this mechanism.
        let shared = Material {
            youngs_modulus: j
                .youngs_modulus
                .as_ref()
                .map(|v| self.youngs_modulus(v))
                .transpose()?
                .unwrap_or(207e9),
            poisson_ratio: j
                .poisson_ratio
                .as_ref()
                .map(|v| self.poisson(v))
                .transpose()?
                .unwrap_or(0.3),
        };
        let bearing_material = j
            .bearing_material
            .as_ref()
            .map(|m| self.material(m))
            .transpose()?
            .unwrap_or(shared);
        let journal_material = j
            .journal_material
            .as_ref()
            .map(|m| self.material(m))
            .transpose()?
            .unwrap_or(shared);
        let stiffness_override = j
            .stiffness
            .as_ref()
            .map(|v| {
                self.within(
                    v,
                    "contact stiffness K (N/m^n)",
                    MIN_STIFFNESS,
                    MAX_STIFFNESS,
                    "the range the material and size bounds give",
                )
            })
            .transpose()?;
        let initial_eccentricity = match &j.initial_eccentricity {
            None => [0.0, 0.0],
            Some(v) => {
                let e = self.vec2(v, "initial eccentricity (m)")?;
                // On the wall (|e| = c) the contact would begin without an impact event, so the
                // impact velocity δ̇⁽⁻⁾ that scales the damping would be unknown; such a run
                // made no impact and did not finish in 1e7 steps (models/farahan2016.toml).
                if e[0].hypot(e[1]) >= clearance {
                    return Err(self.err(
                        v.span(),
                        format!(
                            "initial eccentricity |e| = {:.6e} m is not smaller than the clearance {clearance:.6e} m; expected the journal strictly inside the bearing, since a contact that is under way at t = 0 has no impact velocity to scale its damping",
                            e[0].hypot(e[1])
                        ),
                    ));
                }
                e
            }
        };
        let (law, restitution, exponent) = self.contact(j.contact.as_ref())?;
        let friction = self.friction(j.friction.as_ref())?;
        Ok(ClearanceSpec {
            clearance,
            journal_radius,
            bearing_material,
            journal_material,
            stiffness_override,
            law,
            restitution,
            exponent,
            friction,
            initial_eccentricity,
        })
    }

    fn contact(&self, c: Option<&Spanned<ContactFile>>) -> Res<(ContactLawKind, f64, f64)> {
        let Some(c) = c else {
            return Ok((ContactLawKind::LankaraniNikravesh, 0.9, 1.5));
        };
        let f = c.get_ref();
        let law = match &f.law {
            None => ContactLawKind::LankaraniNikravesh,
            Some(l) => match l.get_ref().trim() {
                "lankarani-nikravesh" => ContactLawKind::LankaraniNikravesh,
                "hunt-crossley" => ContactLawKind::HuntCrossley,
                "flores" => ContactLawKind::Flores,
                "hertz" => ContactLawKind::Hertz,
                other => {
                    let laws = laws::names(laws::CONTACT);
                    return Err(self.err(
                        l.span(),
                        format!(
                            "unknown contact law \"{other}\"; expected one of {}{}",
                            laws.join(", "),
                            did_you_mean(other, laws.iter().copied())
                        ),
                    ));
                }
            },
        };
        let restitution = match &f.restitution {
            None => 0.9,
            Some(v) => {
                let cr = self.finite(v, "coefficient of restitution")?;
                if !(cr > 0.0 && cr <= 1.0) {
                    return Err(self.err(
                        v.span(),
                        format!("expected a coefficient of restitution in (0, 1], found {cr}"),
                    ));
                }
                cr
            }
        };
        if let Some(v) = &f.restitution {
            match law {
                // c_r = 1 states what Hertz is (purely elastic), so it contradicts nothing; any
                // other value would be silently ignored.
                ContactLawKind::Hertz if restitution != 1.0 => {
                    return Err(self.err(
                        v.span(),
                        format!(
                            "field `restitution` does not belong to the hertz law, which is purely elastic (c_r = 1), found c_r = {restitution}; remove it, or choose lankarani-nikravesh, hunt-crossley or flores for a dissipative contact"
                        ),
                    ));
                }
                ContactLawKind::Flores if restitution < MIN_FLORES_RESTITUTION => {
                    return Err(self.err(
                        v.span(),
                        format!(
                            "expected a coefficient of restitution of at least {MIN_FLORES_RESTITUTION} for the flores law, found {restitution}: its damping factor 8(1 − c_r)/(5 c_r) grows as 1/c_r (c_r = 1e-4 costs 56× the work of 0.9, 1e-5 475×), and c_r < 0.01 is a plastic impact that no continuous contact law describes"
                        ),
                    ));
                }
                _ => {}
            }
        }
        // Hertz has no damping: record c_r = 1, which is what it simulates.
        let restitution = if law == ContactLawKind::Hertz {
            1.0
        } else {
            restitution
        };
        let exponent = match &f.exponent {
            None => 1.5,
            Some(v) => {
                let n = self.finite(v, "exponent")?;
                if !(1.0..=3.0).contains(&n) {
                    return Err(self.err(
                        v.span(),
                        format!("expected a contact exponent in [1, 3], found {n}"),
                    ));
                }
                n
            }
        };
        Ok((law, restitution, exponent))
    }

    fn friction(&self, f: Option<&Spanned<FrictionFile>>) -> Res<FrictionSpec> {
        let default = FrictionSpec::Ambrosio {
            coefficient: 0.1,
            v0: 1e-4,
            v1: 1e-3,
        };
        let Some(fr) = f else {
            return Ok(default);
        };
        let t = fr.get_ref();
        match t.law.as_ref().map(|l| (l.get_ref().trim(), l.span())) {
            Some(("none", _)) => {
                let extra = [
                    ("coefficient", &t.coefficient),
                    ("v0", &t.v0),
                    ("v1", &t.v1),
                ];
                if let Some((field, Some(v))) = extra.iter().find(|(_, v)| v.is_some()) {
                    return Err(self.err(
                        v.span(),
                        format!("field `{field}` does not belong to friction law \"none\""),
                    ));
                }
                Ok(FrictionSpec::None)
            }
            None | Some(("ambrosio" | "ambrosio-as-printed", _)) => {
                let as_printed = t
                    .law
                    .as_ref()
                    .is_some_and(|l| l.get_ref().trim() == "ambrosio-as-printed");
                let coefficient = t
                    .coefficient
                    .as_ref()
                    .map(|v| self.non_negative(v, "friction coefficient"))
                    .transpose()?
                    .unwrap_or(0.1);
                let v0 =
                    t.v0.as_ref()
                        .map(|v| self.non_negative(v, "v0 (m/s)"))
                        .transpose()?
                        .unwrap_or(1e-4);
                let v1 =
                    t.v1.as_ref()
                        .map(|v| self.positive(v, "v1 (m/s)"))
                        .transpose()?
                        .unwrap_or(1e-3);
                if v1 <= v0 {
                    let span = t.v1.as_ref().map_or_else(|| fr.span(), |v| v.span());
                    return Err(self.err(
                        span,
                        format!("expected v1 > v0, found v0 = {v0}, v1 = {v1}"),
                    ));
                }
                Ok(if as_printed {
                    FrictionSpec::AmbrosioAsPrinted {
                        coefficient,
                        v0,
                        v1,
                    }
                } else {
                    FrictionSpec::Ambrosio {
                        coefficient,
                        v0,
                        v1,
                    }
                })
            }
            Some((other, span)) => Err(self.err(
                span,
                format!(
                    "unknown friction law \"{other}\"; expected \"ambrosio\", \"none\" or \"ambrosio-as-printed\"{}",
                    did_you_mean(other, ["ambrosio", "none", "ambrosio-as-printed"])
                ),
            )),
        }
    }

    /// Kinematic drivers, and torque drivers as [`ForceElement::Motor`].
    fn drivers(
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
    fn speed(
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

    fn forces(
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

    /// A vector whose components may be run-time expressions.
    fn run_vec2(&self, v: &Vec2, run: &RunScope<'_>, what: &str) -> Res<[Expression; 2]> {
        let items = v.get_ref();
        let [x, y] = items.as_slice() else {
            return Err(self.err(
                v.span(),
                format!(
                    "expected 2 components [x, y] for the {what}, found {} component{}",
                    items.len(),
                    if items.len() == 1 { "" } else { "s" }
                ),
            ));
        };
        let one = |c: &Spanned<toml::Value>, axis: &str| -> Res<Expression> {
            match c.get_ref() {
                toml::Value::String(text) => {
                    let num: Num = Spanned::new(c.span(), Scalar::Expr(text.clone()));
                    self.run_expr(&num, run, what)
                }
                _ => {
                    let x = self.component(c, axis, what)?;
                    let num: Num = Spanned::new(c.span(), Scalar::Number(x));
                    self.run_expr(&num, run, what)
                }
            }
        };
        Ok([one(x, "x")?, one(y, "y")?])
    }

    fn body_of(&self, scope: &Scope<'_>, body: &Name, owner: &str) -> Res<BodyId> {
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
