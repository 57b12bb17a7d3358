//! Validation and conversion of a parsed [`ModelFile`] into a [`Model`] (SI units, typed ids).
//!
//! Every refusal names the field and its place in the file; physically impossible values
//! (negative mass, zero inertia, a joint on a missing point) are refused here, before any
//! numerics. Whether the linkage can be assembled is checked by the formulation.

use super::bounds::*;
use super::error::ModelError;
use super::file::*;
use super::laws;
use super::locate::Locator;
use super::names;
use super::suggest::did_you_mean;
use super::types::*;
use std::collections::HashSet;
use std::ops::Range;
use toml::Spanned;

mod shapes;

/// Builds the model, refusing the first problem found.
pub fn build(raw: ModelFile, source: ModelSource, loc: &Locator<'_>) -> Result<Model, ModelError> {
    let b = Builder { loc };
    let name = b.name_on(&raw.model.name, "model", "")?;
    let settings = b.settings(&raw.settings)?;
    let ground_points = b.points(&raw.ground.points, "ground")?;
    let bodies = b.bodies(&raw.bodies)?;
    if bodies.is_empty() {
        return Err(loc.whole("expected at least one [[bodies]] entry"));
    }
    let scope = Scope {
        ground_points: &ground_points,
        bodies: &bodies,
    };
    let joints = b.joints(&raw.joints, &scope)?;
    let drivers = b.drivers(&raw.drivers, &joints)?;
    let forces = b.forces(&raw.forces, &scope)?;
    Ok(Model {
        name,
        description: raw.model.description,
        settings,
        ground_points,
        bodies,
        joints,
        drivers,
        forces,
        source,
        notes: Vec::new(),
    })
}

/// Names a model may refer to.
struct Scope<'m> {
    ground_points: &'m [(String, [f64; 2])],
    bodies: &'m [Body],
}

struct Builder<'l, 'a> {
    loc: &'l Locator<'a>,
}

type Res<T> = Result<T, ModelError>;

impl Builder<'_, '_> {
    fn err(&self, span: Range<usize>, message: impl Into<String>) -> ModelError {
        self.loc.error(span, message)
    }

    fn finite(&self, v: &Num, what: &str) -> Res<f64> {
        let x = *v.get_ref();
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
        if (min..=max).contains(&x) {
            Ok(x)
        } else if max == f64::INFINITY {
            Err(self.err(
                v.span(),
                format!("expected a {what} of at least {min:e} ({why}), found {x:e}"),
            ))
        } else {
            Err(self.err(
                v.span(),
                format!("expected a {what} in [{min:e}, {max:e}] ({why}), found {x:e}"),
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
        let n = name.get_ref();
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
            out.push((n, self.vec2(p, "point (m)")?));
        }
        Ok(out)
    }

    fn bodies(&self, raw: &[BodyFile]) -> Res<Vec<Body>> {
        let mut seen = HashSet::new();
        let mut bodies = Vec::with_capacity(raw.len());
        for b in raw {
            let name = self.unique(&mut seen, &b.name, "body")?;
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
                f64::INFINITY,
                "a 1 µm steel cube",
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
            let opt = |v: &Option<Num>, what| {
                v.as_ref()
                    .map(|v| self.finite(v, what))
                    .transpose()
                    .map(|x| x.unwrap_or(0.0))
            };
            let initial = BodyState {
                x: self.finite(&i.x, "initial x (m)")?,
                y: self.finite(&i.y, "initial y (m)")?,
                phi: self.finite(&i.phi, "initial phi (rad)")?,
                vx: opt(&i.vx, "initial vx (m/s)")?,
                vy: opt(&i.vy, "initial vy (m/s)")?,
                omega: opt(&i.omega, "initial omega (rad/s)")?,
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

    /// Resolves `body` and `point` names to an anchor; `owner` is e.g. `joint "A"`.
    fn anchor(&self, scope: &Scope<'_>, body: &Name, point: &Name, owner: &str) -> Res<Anchor> {
        let body_name = body.get_ref().trim();
        let point_name = point.get_ref().trim();
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

    fn joints(&self, raw: &[JointFile], scope: &Scope<'_>) -> Res<Vec<Joint>> {
        let mut seen = HashSet::new();
        let mut joints = Vec::with_capacity(raw.len());
        for j in raw {
            let name = self.unique(&mut seen, &j.name, "joint")?;
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
            joints.push(Joint { name, a, b, kind });
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
            None | Some(("ambrosio", _)) => {
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
                Ok(FrictionSpec::Ambrosio {
                    coefficient,
                    v0,
                    v1,
                })
            }
            Some((other, span)) => Err(self.err(
                span,
                format!(
                    "unknown friction law \"{other}\"; expected \"ambrosio\" or \"none\"{}",
                    did_you_mean(other, ["ambrosio", "none"])
                ),
            )),
        }
    }

    fn drivers(&self, raw: &[DriverFile], joints: &[Joint]) -> Res<Vec<Driver>> {
        let mut seen = HashSet::new();
        let mut driven = HashSet::new();
        let mut drivers = Vec::with_capacity(raw.len());
        for d in raw {
            let name = self.unique(&mut seen, &d.name, "driver")?;
            let kind = d.kind.get_ref().trim();
            if kind != "constant-speed" {
                return Err(self.err(
                    d.kind.span(),
                    format!("unknown driver type \"{kind}\"; expected \"constant-speed\""),
                ));
            }
            let joint_name = d.joint.get_ref().trim();
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
                        "driver \"{name}\" drives joint \"{joint_name}\", which is {}; a constant-speed driver needs a revolute joint",
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
            let speed = match (&d.speed_rpm, &d.speed) {
                (Some(rpm), None) => self.finite(rpm, "speed_rpm")? * std::f64::consts::PI / 30.0,
                (None, Some(w)) => self.finite(w, "speed (rad/s)")?,
                (Some(_), Some(w)) => {
                    return Err(self.err(
                        w.span(),
                        "give either `speed_rpm` or `speed` (rad/s), not both",
                    ));
                }
                (None, None) => {
                    return Err(self.err(
                        d.name.span(),
                        format!(
                            "missing field `speed_rpm` or `speed` (rad/s) of driver \"{name}\""
                        ),
                    ));
                }
            };
            let initial_angle = d
                .initial_angle
                .as_ref()
                .map(|v| self.finite(v, "initial angle (rad)"))
                .transpose()?
                .unwrap_or(0.0);
            drivers.push(Driver {
                name,
                joint: JointId(id),
                speed,
                initial_angle,
            });
        }
        Ok(drivers)
    }

    fn forces(&self, raw: &[ForceFile], scope: &Scope<'_>) -> Res<Vec<ForceElement>> {
        let mut seen = HashSet::new();
        let mut forces = Vec::with_capacity(raw.len());
        for f in raw {
            let name = self.unique(&mut seen, &f.name, "force")?;
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
                    ForceElement::Torque {
                        name,
                        body,
                        torque: self.finite(
                            self.required(&f.torque, "torque", &what, at.clone())?,
                            "torque (N·m)",
                        )?,
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
                    ForceElement::PointForce {
                        name,
                        at: at_anchor,
                        force: self.vec2(
                            self.required(&f.force, "force", &what, at.clone())?,
                            "force (N)",
                        )?,
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

    fn body_of(&self, scope: &Scope<'_>, body: &Name, owner: &str) -> Res<BodyId> {
        let n = body.get_ref().trim();
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
