//! Parameters, tables, `[[repeat]]` blocks, extra output points, settings and the Baumgarte factors.

use super::*;

impl Builder<'_, '_> {
    /// `[parameters]`, evaluated.
    pub(super) fn parameters(
        &self,
        raw: &std::collections::BTreeMap<Name, Num>,
    ) -> Res<Vec<(String, f64)>> {
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
    pub(super) fn tables(&self, raw: &[TableFile]) -> Res<Vec<Arc<Table>>> {
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
    pub(super) fn repeat(&self, r: &RepeatFile) -> Res<Vec<Builder<'_, '_>>> {
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
    pub(super) fn outputs(&self, raw: &[OutputFile], scope: &Scope<'_>) -> Res<Vec<OutputPoint>> {
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

    pub(super) fn settings(&self, s: &SettingsFile) -> Res<Settings> {
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

    pub(super) fn baumgarte(&self, bf: &Spanned<BaumgarteFile>) -> Res<Baumgarte> {
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
}
