//! Joints: ideal, translational and clearance joints with their materials, contact laws and friction.

use super::*;

impl Builder<'_, '_> {
    /// The two anchors of a joint from its required body and point fields, in the order
    /// (body, point) of the first anchor then of the second, each named with its field for the
    /// "missing field" message; `what` names the joint there, `owner` in the anchor's messages.
    fn joint_anchors(
        &self,
        scope: &Scope<'_>,
        fields: [(&Option<Name>, &str); 4],
        (what, owner, at): (&str, &str, &Range<usize>),
    ) -> Res<(Anchor, Anchor)> {
        let [
            (body_a, body_a_field),
            (point_a, point_a_field),
            (body_b, body_b_field),
            (point_b, point_b_field),
        ] = fields;
        let a = self.anchor(
            scope,
            self.required(body_a, body_a_field, what, at.clone())?,
            self.required(point_a, point_a_field, what, at.clone())?,
            owner,
        )?;
        let b = self.anchor(
            scope,
            self.required(body_b, body_b_field, what, at.clone())?,
            self.required(point_b, point_b_field, what, at.clone())?,
            owner,
        )?;
        Ok((a, b))
    }

    pub(super) fn joints(
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
                ("length", sn(&j.length)),
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
                ("lubrication", j.lubrication.as_ref().map(|v| v.span())),
                ("wear", j.wear.as_ref().map(|v| v.span())),
                ("ideal", j.ideal.as_ref().map(|v| v.span())),
                ("slider_length", sn(&j.slider_length)),
                ("slider_width", sn(&j.slider_width)),
                ("initial_offset", sn(&j.initial_offset)),
                ("initial_tilt", sn(&j.initial_tilt)),
                ("guide_start", sn(&j.guide_start)),
                ("guide_end", sn(&j.guide_end)),
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
                    let (a, b) = self.joint_anchors(
                        scope,
                        [
                            (&j.body_a, "body_a"),
                            (&j.point_a, "point_a"),
                            (&j.body_b, "body_b"),
                            (&j.point_b, "point_b"),
                        ],
                        (&what, &owner, &at),
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
                        "length",
                        "youngs_modulus",
                        "poisson_ratio",
                        "bearing_material",
                        "journal_material",
                        "stiffness",
                        "initial_eccentricity",
                        "contact",
                        "friction",
                        "lubrication",
                        "wear",
                        "ideal",
                    ];
                    self.only_fields(&present, &allowed, "clearance joint")?;
                    let what = format!("clearance joint \"{name}\"");
                    let (a, b) = self.joint_anchors(
                        scope,
                        [
                            (&j.bearing, "bearing"),
                            (&j.bearing_point, "bearing_point"),
                            (&j.journal, "journal"),
                            (&j.journal_point, "journal_point"),
                        ],
                        (&what, &owner, &at),
                    )?;
                    (
                        a,
                        b,
                        JointKind::Clearance(self.clearance(j, &what, at.clone())?),
                    )
                }
                "prismatic-clearance" => {
                    let allowed = [
                        "body_a",
                        "point_a",
                        "body_b",
                        "point_b",
                        "axis",
                        "angle",
                        "clearance",
                        "slider_length",
                        "slider_width",
                        "stiffness",
                        "initial_offset",
                        "initial_tilt",
                        "guide_start",
                        "guide_end",
                        "contact",
                        "friction",
                        "ideal",
                    ];
                    self.only_fields(&present, &allowed, "prismatic-clearance joint")?;
                    let what = format!("prismatic-clearance joint \"{name}\"");
                    let (a, b) = self.joint_anchors(
                        scope,
                        [
                            (&j.body_a, "body_a"),
                            (&j.point_a, "point_a"),
                            (&j.body_b, "body_b"),
                            (&j.point_b, "point_b"),
                        ],
                        (&what, &owner, &at),
                    )?;
                    let spec = self.prismatic_clearance(j, &what, at.clone())?;
                    (a, b, JointKind::PrismaticClearance(spec))
                }
                other => {
                    return Err(self.err(
                        j.kind.span(),
                        format!(
                            "unknown joint type \"{other}\"; expected \"revolute\", \"prismatic\", \"clearance\" or \"prismatic-clearance\"{}",
                            did_you_mean(
                                other,
                                ["revolute", "prismatic", "clearance", "prismatic-clearance"]
                            )
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
                joints.push(super::super::ideal::ideal_joint(joint));
            } else {
                joints.push(joint);
            }
        }
        Ok(joints)
    }

    pub(super) fn axis(&self, axis: Option<&Vec2>) -> Res<[f64; 2]> {
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

    pub(super) fn material(&self, m: &Spanned<MaterialFile>) -> Res<Material> {
        let f = m.get_ref();
        Ok(Material {
            youngs_modulus: self.youngs_modulus(&f.youngs_modulus)?,
            poisson_ratio: self.poisson(&f.poisson_ratio)?,
        })
    }

    pub(super) fn youngs_modulus(&self, v: &Num) -> Res<f64> {
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
    pub(super) fn poisson(&self, v: &Num) -> Res<f64> {
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

    pub(super) fn clearance(
        &self,
        j: &JointFile,
        what: &str,
        at: Range<usize>,
    ) -> Res<ClearanceSpec> {
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
        let length = j
            .length
            .as_ref()
            .map(|v| {
                self.within(
                    v,
                    "bearing length (m)",
                    MIN_BEARING_LENGTH,
                    MAX_BEARING_LENGTH,
                    "from micro-mechanism pins to ship-shaft bearings",
                )
            })
            .transpose()?;
        let (law, damping, restitution, exponent) = self.contact(j.contact.as_ref())?;
        if law.is_line_contact() {
            self.line_contact_needs(j, law, length, what, at.clone())?;
        }
        let friction = self.friction(j.friction.as_ref())?;
        let lubrication = j
            .lubrication
            .as_ref()
            .map(|l| self.lubrication(l, length, clearance, what))
            .transpose()?;
        let wear = j
            .wear
            .as_ref()
            .map(|w| self.wear(w, length, lubrication.is_some(), what))
            .transpose()?;
        if let (Some(l), Some(v)) = (&lubrication, &j.initial_eccentricity) {
            let e = initial_eccentricity[0].hypot(initial_eccentricity[1]);
            let limit = clearance - l.contact_film_thickness;
            if e >= limit {
                return Err(self.err(
                    v.span(),
                    format!(
                        "initial eccentricity |e| = {e:.6e} m leaves a film thinner than contact_film_thickness = {:.6e} m; expected |e| < c − contact_film_thickness = {limit:.6e} m, since the dry contact that begins there would have no impact velocity to scale its damping",
                        l.contact_film_thickness
                    ),
                ));
            }
        }
        Ok(ClearanceSpec {
            clearance,
            journal_radius,
            bearing_material,
            journal_material,
            stiffness_override,
            law,
            damping,
            length,
            restitution,
            exponent,
            friction,
            initial_eccentricity,
            lubrication,
            wear,
        })
    }

    /// `[joints.wear]`: the dimensional wear coefficient and the number of bins; the bearing
    /// length (the joint's `length`) is required, since the wear depth is the worn volume per
    /// unit length. A lubricated joint is refused: its dry contact acts on c − h_c, and a
    /// worn profile under a film is another model (the film's thickness would change too).
    fn wear(
        &self,
        w: &Spanned<WearFile>,
        length: Option<f64>,
        lubricated: bool,
        what: &str,
    ) -> Res<WearSpec> {
        let f = w.get_ref();
        let k_field = self.required(&f.coefficient, "coefficient", "[joints.wear]", w.span())?;
        self.positive(k_field, "wear coefficient k/H (m²/N)")?;
        let coefficient = self.within(
            k_field,
            "wear coefficient k/H (m²/N)",
            MIN_WEAR_COEFFICIENT,
            MAX_WEAR_COEFFICIENT,
            "Archard's k over the hardness H, from the mildest wear to accelerated studies",
        )?;
        let bins = match &f.bins {
            None => 360,
            Some(v) => {
                let n = self.within(
                    v,
                    "number of wear bins",
                    MIN_WEAR_BINS,
                    MAX_WEAR_BINS,
                    "angular bins on the bearing surface",
                )?;
                if n.fract() != 0.0 {
                    return Err(self.err(
                        v.span(),
                        format!("expected an integer number of wear bins, found {n}"),
                    ));
                }
                // Exact: an integer in [8, 1e5].
                n as usize
            }
        };
        if length.is_none() {
            return Err(self.err(
                w.span(),
                format!(
                    "a worn joint needs the bearing's axial length, over which the worn volume is spread (wear depth = volume / (length · arc)): expected a field `length` (m, > 0) on {what}, e.g. length = 0.02"
                ),
            ));
        }
        if lubricated {
            return Err(self.err(
                w.span(),
                format!(
                    "{what} has both [joints.lubrication] and [joints.wear]; expected one of them: wear is modelled for the dry contact only"
                ),
            ));
        }
        Ok(WearSpec { coefficient, bins })
    }

    /// `[joints.lubrication]`: the film model, the viscosity and the contact threshold; the
    /// bearing length is the joint's `length`, required here.
    fn lubrication(
        &self,
        l: &Spanned<LubricationFile>,
        length: Option<f64>,
        clearance: f64,
        what: &str,
    ) -> Res<LubricationSpec> {
        let f = l.get_ref();
        let model_field = self.required(&f.model, "model", "[joints.lubrication]", l.span())?;
        let model = match model_field.get_ref().trim() {
            "short" => FilmModel::Short,
            "long" => FilmModel::Long,
            other => {
                return Err(self.err(
                    model_field.span(),
                    format!(
                        "unknown film model \"{other}\"; expected one of {}{}",
                        laws::FILM_MODELS.join(", "),
                        did_you_mean(other, laws::FILM_MODELS.iter().copied())
                    ),
                ));
            }
        };
        let mu_field =
            self.required(&f.viscosity, "viscosity", "[joints.lubrication]", l.span())?;
        self.positive(mu_field, "viscosity (Pa·s)")?;
        let viscosity = self.within(
            mu_field,
            "viscosity (Pa·s)",
            MIN_VISCOSITY,
            MAX_VISCOSITY,
            "from near-gases to the heaviest greases",
        )?;
        if length.is_none() {
            return Err(self.err(
                l.span(),
                format!(
                    "a lubricated joint needs the bearing's axial length, which sets the film's load capacity (∝ L³ for the short bearing, ∝ L for the long): expected a field `length` (m, > 0) on {what}, e.g. length = 0.02"
                ),
            ));
        }
        let contact_film_thickness = match &f.contact_film_thickness {
            None => 0.01 * clearance,
            Some(v) => {
                let h = self.positive(v, "contact film thickness (m)")?;
                // The film is blended out between h_c and h_c/2 and the dry contact acts on
                // c − h_c: beyond c/2 the "film" would be thicker than the gap it lives in.
                if h > 0.5 * clearance {
                    return Err(self.err(
                        v.span(),
                        format!(
                            "expected a contact film thickness of at most half the radial clearance ({:e} m), found {h:e} m",
                            0.5 * clearance
                        ),
                    ));
                }
                h
            }
        };
        Ok(LubricationSpec {
            model,
            viscosity,
            contact_film_thickness,
        })
    }

    /// The data of a prismatic-clearance joint: clearance, slider size, the corner contacts'
    /// stiffness (required: a corner on a flat surface has no Hertzian stiffness from the
    /// materials alone), law and friction, and the initial pose in the guide, which must leave
    /// every corner strictly inside (as the revolute joint's initial eccentricity must).
    fn prismatic_clearance(
        &self,
        j: &JointFile,
        what: &str,
        at: Range<usize>,
    ) -> Res<PrismaticClearanceSpec> {
        let c_field = self.required(&j.clearance, "clearance", what, at.clone())?;
        let clearance = self.within(
            c_field,
            "clearance (m)",
            MIN_CLEARANCE,
            f64::INFINITY,
            "the roughness of polished surfaces",
        )?;
        let l_field = self.required(&j.slider_length, "slider_length", what, at.clone())?;
        let slider_length = self.positive(l_field, "slider length (m)")?;
        let slider_width = j
            .slider_width
            .as_ref()
            .map(|v| self.non_negative(v, "slider width (m)"))
            .transpose()?
            .unwrap_or(0.0);
        let k_field = self.required(&j.stiffness, "stiffness", what, at.clone())?;
        let stiffness = self.within(
            k_field,
            "contact stiffness K (N/m^n)",
            MIN_STIFFNESS,
            MAX_STIFFNESS,
            "the range the material and size bounds give",
        )?;
        let (law, damping, restitution, exponent) = self.contact(j.contact.as_ref())?;
        if law.is_line_contact() {
            let law_at = j
                .contact
                .as_ref()
                .and_then(|c| c.get_ref().law.as_ref().map(|l| l.span()))
                .unwrap_or(at.clone());
            return Err(self.err(
                law_at,
                format!(
                    "contact law \"{}\" is a line contact of a cylinder in a cylindrical hole and has no meaning for a slider's corner on a flat guide surface; expected a point-contact law (lankarani-nikravesh, hunt-crossley, flores or hertz) on {what}",
                    law.name()
                ),
            ));
        }
        let friction = self.friction(j.friction.as_ref())?;
        let initial_offset = j
            .initial_offset
            .as_ref()
            .map(|v| self.finite(v, "initial offset (m)"))
            .transpose()?
            .unwrap_or(0.0);
        let initial_tilt = j
            .initial_tilt
            .as_ref()
            .map(|v| self.finite(v, "initial tilt (rad)"))
            .transpose()?
            .unwrap_or(0.0);
        // The deepest corner at t = 0: max over the corners (±L/2, ±w/2) of the slider turned by
        // the tilt and moved by the offset, of its distance past its surface.
        let (sin, cos) = initial_tilt.sin_cos();
        let reach = 0.5 * slider_length * sin.abs() + 0.5 * slider_width * cos - 0.5 * slider_width
            + initial_offset.abs();
        if !(reach < clearance && cos > 0.0) {
            let span = j
                .initial_offset
                .as_ref()
                .or(j.initial_tilt.as_ref())
                .map(|v| v.span())
                .unwrap_or(at);
            return Err(self.err(
                span,
                format!(
                    "the initial offset {initial_offset:e} m and tilt {initial_tilt:e} rad put a slider corner {reach:.6e} m from its centred position towards a guide surface, not less than the clearance {clearance:.6e} m; expected every corner strictly inside the guide, since a contact that is under way at t = 0 has no impact velocity to scale its damping"
                ),
            ));
        }
        let (guide_start, guide_end) = self.guide_ends(j, slider_length)?;
        Ok(PrismaticClearanceSpec {
            axis: self.axis(j.axis.as_ref())?,
            angle: j
                .angle
                .as_ref()
                .map(|v| self.finite(v, "angle (rad)"))
                .transpose()?
                .unwrap_or(0.0),
            clearance,
            slider_length,
            slider_width,
            stiffness,
            law,
            damping,
            restitution,
            exponent,
            friction,
            initial_offset,
            initial_tilt,
            guide_start,
            guide_end,
        })
    }

    /// The optional end stops of a prismatic-clearance joint's guide, positions along the axis
    /// from the guide's point (m, within ±[`MAX_COORDINATE`]): refuses an end at or before the
    /// start, and a guide between them not longer than the slider (it could not hold it). That
    /// the slider starts between them is checked at the assembled position, by the formulation.
    fn guide_ends(&self, j: &JointFile, slider_length: f64) -> Res<(Option<f64>, Option<f64>)> {
        let read = |v: &Option<Num>, what: &str| {
            v.as_ref()
                .map(|v| {
                    self.within(
                        v,
                        what,
                        -MAX_COORDINATE,
                        MAX_COORDINATE,
                        "the coordinate bound of the model",
                    )
                })
                .transpose()
        };
        let start = read(&j.guide_start, "guide start (m)")?;
        let end = read(&j.guide_end, "guide end (m)")?;
        if let (Some(s0), Some(s1), Some(end_field)) = (start, end, j.guide_end.as_ref()) {
            if s1 <= s0 {
                return Err(self.err(
                    end_field.span(),
                    format!(
                        "the guide end {s1:e} m is not after the guide start {s0:e} m; expected guide_end > guide_start (positions along the axis from the guide's point)"
                    ),
                ));
            }
            if s1 - s0 <= slider_length {
                return Err(self.err(
                    end_field.span(),
                    format!(
                        "the guide between guide_start = {s0:e} m and guide_end = {s1:e} m is {:.6e} m long, not longer than the slider ({slider_length:.6e} m); expected guide_end − guide_start > slider_length",
                        s1 - s0
                    ),
                ));
            }
        }
        Ok((start, end))
    }

    /// A line-contact law needs the bearing's length and takes its stiffness from the materials
    /// and the length: refuses a missing `length` (at the law, which asks for it) and a
    /// `stiffness` (K of the power laws, which these laws do not have).
    fn line_contact_needs(
        &self,
        j: &JointFile,
        law: ContactLawKind,
        length: Option<f64>,
        what: &str,
        at: Range<usize>,
    ) -> Res<()> {
        let law_at = j
            .contact
            .as_ref()
            .and_then(|c| c.get_ref().law.as_ref().map(|l| l.span()))
            .unwrap_or(at);
        if length.is_none() {
            return Err(self.err(
                law_at,
                format!(
                    "contact law \"{}\" is a line contact and needs the bearing's axial length: expected a field `length` (m, > 0) on {what}, e.g. length = 0.02",
                    law.name()
                ),
            ));
        }
        if let Some(v) = &j.stiffness {
            return Err(self.err(
                v.span(),
                format!(
                    "field `stiffness` does not belong to contact law \"{}\": it sets K of the power laws K δⁿ, while a line-contact law's stiffness follows from the materials, the clearance and `length`; remove it, or choose lankarani-nikravesh, hunt-crossley, flores or hertz",
                    law.name()
                ),
            ));
        }
        Ok(())
    }

    /// The hysteresis factor named by `damping` (line-contact laws only).
    fn damping(&self, d: &Name) -> Res<DampingKind> {
        Ok(match d.get_ref().trim() {
            "lankarani-nikravesh" => DampingKind::LankaraniNikravesh,
            "hunt-crossley" => DampingKind::HuntCrossley,
            "flores" => DampingKind::Flores,
            "none" => DampingKind::None,
            other => {
                return Err(self.err(
                    d.span(),
                    format!(
                        "unknown damping \"{other}\"; expected one of {}{}",
                        laws::DAMPING.join(", "),
                        did_you_mean(other, laws::DAMPING.iter().copied())
                    ),
                ));
            }
        })
    }

    pub(super) fn contact(
        &self,
        c: Option<&Spanned<ContactFile>>,
    ) -> Res<(ContactLawKind, DampingKind, f64, f64)> {
        let Some(c) = c else {
            return Ok((
                ContactLawKind::LankaraniNikravesh,
                DampingKind::LankaraniNikravesh,
                0.9,
                1.5,
            ));
        };
        let f = c.get_ref();
        let law = match &f.law {
            None => ContactLawKind::LankaraniNikravesh,
            Some(l) => match l.get_ref().trim() {
                "lankarani-nikravesh" => ContactLawKind::LankaraniNikravesh,
                "hunt-crossley" => ContactLawKind::HuntCrossley,
                "flores" => ContactLawKind::Flores,
                "hertz" => ContactLawKind::Hertz,
                "johnson" => ContactLawKind::Johnson,
                "liu" => ContactLawKind::Liu,
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
        let damping = match law {
            ContactLawKind::LankaraniNikravesh => DampingKind::LankaraniNikravesh,
            ContactLawKind::HuntCrossley => DampingKind::HuntCrossley,
            ContactLawKind::Flores => DampingKind::Flores,
            ContactLawKind::Hertz => DampingKind::None,
            ContactLawKind::Johnson | ContactLawKind::Liu => match &f.damping {
                None => DampingKind::LankaraniNikravesh,
                Some(d) => self.damping(d)?,
            },
        };
        if let Some(d) = &f.damping
            && !law.is_line_contact()
        {
            return Err(self.err(
                d.span(),
                format!(
                    "field `damping` does not belong to contact law \"{}\", whose name fixes its damping; choose the law by its damping instead (lankarani-nikravesh, hunt-crossley, flores, or hertz for none), or a line-contact law (johnson, liu) to combine with a damping",
                    law.name()
                ),
            ));
        }
        if let Some(v) = &f.exponent
            && law.is_line_contact()
        {
            return Err(self.err(
                v.span(),
                format!(
                    "field `exponent` does not belong to contact law \"{}\", whose force–penetration relation is fixed by its source; remove it",
                    law.name()
                ),
            ));
        }
        if let Some(v) = &f.restitution {
            match (law, damping) {
                // c_r = 1 states what Hertz is (purely elastic), so it contradicts nothing; any
                // other value would be silently ignored.
                (ContactLawKind::Hertz, _) if restitution != 1.0 => {
                    return Err(self.err(
                        v.span(),
                        format!(
                            "field `restitution` does not belong to the hertz law, which is purely elastic (c_r = 1), found c_r = {restitution}; remove it, or choose lankarani-nikravesh, hunt-crossley or flores for a dissipative contact"
                        ),
                    ));
                }
                (_, DampingKind::None) if restitution != 1.0 => {
                    return Err(self.err(
                        v.span(),
                        format!(
                            "field `restitution` does not apply with damping \"none\", which is purely elastic (c_r = 1), found c_r = {restitution}; remove it, or choose damping lankarani-nikravesh, hunt-crossley or flores"
                        ),
                    ));
                }
                (_, DampingKind::Flores) if restitution < MIN_FLORES_RESTITUTION => {
                    let whose = if law.is_line_contact() {
                        "damping"
                    } else {
                        "law"
                    };
                    return Err(self.err(
                        v.span(),
                        format!(
                            "expected a coefficient of restitution of at least {MIN_FLORES_RESTITUTION} for the flores {whose}, found {restitution}: its damping factor 8(1 − c_r)/(5 c_r) grows as 1/c_r (c_r = 1e-4 costs 56× the work of 0.9, 1e-5 475×), and c_r < 0.01 is a plastic impact that no continuous contact law describes"
                        ),
                    ));
                }
                _ => {}
            }
        }
        // Hertz (and damping "none") has no damping: record c_r = 1, which is what it simulates.
        let restitution = if damping == DampingKind::None {
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
        Ok((law, damping, restitution, exponent))
    }

    pub(super) fn friction(&self, f: Option<&Spanned<FrictionFile>>) -> Res<FrictionSpec> {
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
}
