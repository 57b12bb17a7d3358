//! Reading values: numbers and expressions, ranges, vectors, names, and the errors that point into the file.

use super::*;

impl Builder<'_, '_> {
    pub(super) fn err(&self, span: Range<usize>, message: impl Into<String>) -> ModelError {
        match &self.repeat {
            None => self.loc.error(span, message),
            Some((index, i)) => self.loc.error(
                span,
                format!("{} (in [[repeat]] with {index} = {i})", message.into()),
            ),
        }
    }

    /// An error in the expression `text` written at `span`, at the offending token.
    pub(super) fn expr_err(&self, span: Range<usize>, text: &str, e: ExprError) -> ModelError {
        let start = span.start + self.loc.string_body_offset(span.start) + e.offset;
        self.err(
            start..start + 1,
            format!("in expression \"{}\": {}", abbreviate(text), e.message),
        )
    }

    /// The value of a number or of an expression of parameters.
    pub(super) fn number(&self, v: &Num) -> Res<f64> {
        match v.get_ref() {
            Scalar::Number(x) => Ok(*x),
            Scalar::Expr(text) => self.static_expr(text, v.span()),
        }
    }

    pub(super) fn static_expr(&self, text: &str, span: Range<usize>) -> Res<f64> {
        expr::parse(text)
            .and_then(|n| n.resolve(&self.values))
            .map(|e| e.constant().unwrap_or(f64::NAN))
            .map_err(|e| self.expr_err(span, text, e))
    }

    /// A run-time expression (force, torque, prescribed angle): numbers stay numbers.
    pub(super) fn run_expr(&self, v: &Num, scope: &RunScope<'_>, what: &str) -> Res<Expression> {
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
    pub(super) fn text(&self, name: &Name) -> Res<String> {
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

    pub(super) fn finite(&self, v: &Num, what: &str) -> Res<f64> {
        let x = self.number(v)?;
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.err(v.span(), format!("expected a finite {what}, found {x}")))
        }
    }

    pub(super) fn positive(&self, v: &Num, what: &str) -> Res<f64> {
        let x = self.finite(v, what)?;
        if x > 0.0 {
            Ok(x)
        } else {
            Err(self.err(v.span(), format!("expected a positive {what}, found {x}")))
        }
    }

    /// A finite value in `[min, max]`; `why` says where the bounds come from.
    pub(super) fn within(&self, v: &Num, what: &str, min: f64, max: f64, why: &str) -> Res<f64> {
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

    pub(super) fn non_negative(&self, v: &Num, what: &str) -> Res<f64> {
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

    pub(super) fn vec2(&self, v: &Vec2, what: &str) -> Res<[f64; 2]> {
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
    pub(super) fn component(&self, v: &Spanned<toml::Value>, axis: &str, what: &str) -> Res<f64> {
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

    /// A vector whose components may be run-time expressions.
    pub(super) fn run_vec2(
        &self,
        v: &Vec2,
        run: &RunScope<'_>,
        what: &str,
    ) -> Res<[Expression; 2]> {
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

    /// A name that follows [`names::check`]: it heads CSV columns and provenance lines.
    /// `owner` is empty or e.g. ` on body "crank"`.
    pub(super) fn name_on(&self, name: &Name, what: &str, owner: &str) -> Res<String> {
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

    pub(super) fn unique(
        &self,
        seen: &mut HashSet<String>,
        name: &Name,
        what: &str,
    ) -> Res<String> {
        let n = self.name_on(name, what, "")?;
        if !seen.insert(n.clone()) {
            return Err(self.err(name.span(), format!("duplicate {what} name \"{n}\"")));
        }
        Ok(n)
    }

    /// Refuses fields that do not belong to the entry's type.
    pub(super) fn only_fields(
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

    pub(super) fn required<'n, T>(
        &self,
        v: &'n Option<T>,
        field: &str,
        what: &str,
        at: Range<usize>,
    ) -> Res<&'n T> {
        v.as_ref()
            .ok_or_else(|| self.err(at, format!("missing field `{field}` of {what}")))
    }
}
