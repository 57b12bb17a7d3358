//! `[parameters]`, `[[tables]]` and the names an expression may use in each kind of field.
//!
//! Parameters are evaluated once, at load time, in dependency order (a parameter may use any
//! other, declared before or after it); a cycle is refused naming every parameter on it.
//! Numeric fields of the model see the parameters, `pi`, the tables and the index of an
//! enclosing `[[repeat]]`. Fields that are evaluated during the run (force and torque
//! expressions, prescribed angles) see time and state as well (see [`RunScope`]).

use super::expr::{self, ExprError, Meaning, Scope, Table, Variable};
use super::suggest::did_you_mean;
use super::types::{Body, BodyId, Frame};
use std::sync::Arc;

/// Names every numeric field may use: evaluated parameters, tables, a repeat index.
#[derive(Debug, Clone, Default)]
pub struct Values {
    /// Parameters (and a repeat index), evaluated.
    pub values: Vec<(String, f64)>,
    /// Tables.
    pub tables: Vec<Arc<Table>>,
}

/// Names of the run-time quantities, refused in load-time fields with this reason.
const RUN_TIME: &[&str] = &["t", "theta", "omega"];

/// Why a name is not acceptable as a parameter or repeat index, if it is not.
pub fn check_name(name: &str) -> Result<(), String> {
    let mut chars = name.chars();
    let starts_well = chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_');
    if !starts_well || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err(
            "expected a letter or '_' followed by letters, digits or '_' (a name expressions can refer to)"
                .to_string(),
        );
    }
    if expr::reserved(name) {
        return Err(format!("\"{name}\" is a built-in function or constant"));
    }
    if RUN_TIME.contains(&name) {
        return Err(format!(
            "\"{name}\" is reserved for the run-time quantity of that name in force expressions"
        ));
    }
    Ok(())
}

impl Values {
    /// The value of a parameter, if there is one of that name.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.values
            .iter()
            .rev()
            .find(|(n, _)| n == name)
            .map(|(_, x)| *x)
    }

    /// With one more name (a repeat index), shadowing nothing: the caller refuses clashes.
    pub fn with(&self, name: &str, value: f64) -> Values {
        let mut v = self.clone();
        v.values.push((name.to_string(), value));
        v
    }

    fn unknown(&self, name: &str, extra: &[&str]) -> String {
        let mut names: Vec<&str> = self.values.iter().map(|(n, _)| n.as_str()).collect();
        names.extend_from_slice(extra);
        names.push("pi");
        format!(
            "unknown name \"{name}\"{}; expected a parameter from [parameters]{}",
            did_you_mean(name, names.iter().copied()),
            if extra.is_empty() {
                String::new()
            } else {
                format!(" or one of {}", extra.join(" "))
            }
        )
    }
}

impl Scope for Values {
    fn lookup(&self, name: &str) -> Result<Meaning, String> {
        if let Some(x) = self.get(name) {
            return Ok(Meaning::Value(x));
        }
        if RUN_TIME.contains(&name) || name.contains('.') {
            return Err(format!(
                "\"{name}\" is only known during the run, but this field is evaluated once at load time; time and state may appear in force and torque expressions and prescribed angles"
            ));
        }
        Err(self.unknown(name, &[]))
    }

    fn table(&self, name: &str) -> Option<Arc<Table>> {
        self.tables.iter().find(|t| t.name == name).cloned()
    }
}

/// Names of a field evaluated during the run: the [`Values`] plus `t`, the driver angle
/// `theta` and speed `omega` (when the field has a driver to refer to), and `body.x`,
/// `body.y`, `body.phi`, `body.vx`, `body.vy`, `body.omega` of every body.
pub struct RunScope<'a> {
    /// Parameters and tables.
    pub values: &'a Values,
    /// The bodies.
    pub bodies: &'a [Body],
    /// The joint whose relative angle and speed are `theta` and `omega`, or why there is none.
    pub driver: Result<(Frame, Frame), String>,
    /// Only `t` may vary (a prescribed angle).
    pub time_only: bool,
}

const BODY_FIELDS: [&str; 6] = ["x", "y", "phi", "vx", "vy", "omega"];

impl Scope for RunScope<'_> {
    fn lookup(&self, name: &str) -> Result<Meaning, String> {
        if let Some(x) = self.values.get(name) {
            return Ok(Meaning::Value(x));
        }
        if name == "t" {
            return Ok(Meaning::Var(Variable::Time));
        }
        if self.time_only && (name == "theta" || name == "omega" || name.contains('.')) {
            return Err(format!(
                "\"{name}\" is part of the state, but a prescribed angle is a function of time `t` alone (use a `torque` driver for a motor law)"
            ));
        }
        if name == "theta" || name == "omega" {
            let (a, b) = self.driver.clone()?;
            return Ok(Meaning::Var(if name == "theta" {
                Variable::JointAngle { a, b }
            } else {
                Variable::JointSpeed { a, b }
            }));
        }
        if let Some((body, field)) = name.split_once('.') {
            let Some(id) = self.bodies.iter().position(|b| b.name == body) else {
                return Err(format!(
                    "unknown body \"{body}\" in \"{name}\"{}",
                    did_you_mean(body, self.bodies.iter().map(|b| b.name.as_str()))
                ));
            };
            let Some(k) = BODY_FIELDS.iter().position(|f| *f == field) else {
                return Err(format!(
                    "unknown body coordinate \"{field}\" in \"{name}\"{}; expected one of {}",
                    did_you_mean(field, BODY_FIELDS),
                    BODY_FIELDS.join(" ")
                ));
            };
            return Ok(Meaning::Var(Variable::Body {
                body: BodyId(id),
                field: k,
            }));
        }
        let extra: &[&str] = if self.time_only {
            &["t"]
        } else {
            &["t", "theta", "omega", "body.x", "body.phi", "…"]
        };
        Err(self.values.unknown(name, extra))
    }

    fn table(&self, name: &str) -> Option<Arc<Table>> {
        self.values.table(name)
    }
}

/// One parameter as written: its name, expression text (or number) and the error locator.
pub struct RawParameter<'p> {
    /// Name.
    pub name: &'p str,
    /// The number, or the expression to parse.
    pub value: Result<f64, &'p str>,
}

/// Where evaluating the parameters failed: the index of the parameter whose value is at
/// fault, the byte offset into its expression (None: the whole value), and the message.
pub struct ParameterError {
    /// Index into the raw parameters.
    pub index: usize,
    /// Offset into the expression, if it is one.
    pub offset: Option<usize>,
    /// What is wrong.
    pub message: String,
}

/// Evaluates every parameter, in dependency order; `tables` are not visible to parameters.
pub fn evaluate(raw: &[RawParameter<'_>]) -> Result<Vec<(String, f64)>, ParameterError> {
    let mut parsed = Vec::with_capacity(raw.len());
    for (index, p) in raw.iter().enumerate() {
        parsed.push(match p.value {
            Ok(_) => None,
            Err(text) => Some(expr::parse(text).map_err(|e| ParameterError {
                index,
                offset: Some(e.offset),
                message: e.message,
            })?),
        });
    }
    let mut values: Vec<Option<f64>> = raw.iter().map(|p| p.value.ok()).collect();
    let mut stack = Vec::new();
    for i in 0..raw.len() {
        visit(i, raw, &parsed, &mut values, &mut stack)?;
    }
    Ok(raw
        .iter()
        .zip(values)
        .map(|(p, v)| (p.name.to_string(), v.unwrap_or(f64::NAN)))
        .collect())
}

fn visit(
    i: usize,
    raw: &[RawParameter<'_>],
    parsed: &[Option<expr::Node>],
    values: &mut Vec<Option<f64>>,
    stack: &mut Vec<usize>,
) -> Result<(), ParameterError> {
    if values.get(i).copied().flatten().is_some() {
        return Ok(());
    }
    let Some(Some(node)) = parsed.get(i) else {
        return Ok(());
    };
    if let Some(at) = stack.iter().position(|&k| k == i) {
        let mut cycle: Vec<&str> = stack[at..].iter().map(|&k| raw[k].name).collect();
        cycle.push(raw[i].name);
        return Err(ParameterError {
            index: i,
            offset: None,
            message: format!(
                "parameters refer to each other in a cycle: {}",
                cycle.join(" -> ")
            ),
        });
    }
    stack.push(i);
    let mut names = Vec::new();
    node.names(&mut names);
    for (name, _) in &names {
        if let Some(k) = raw.iter().position(|p| p.name == name) {
            visit(k, raw, parsed, values, stack)?;
        }
    }
    stack.pop();
    let known = Values {
        values: raw
            .iter()
            .zip(values.iter())
            .filter_map(|(p, v)| v.map(|x| (p.name.to_string(), x)))
            .collect(),
        tables: Vec::new(),
    };
    let x = node
        .resolve(&known)
        .map_err(|e: ExprError| ParameterError {
            index: i,
            offset: Some(e.offset),
            message: e.message,
        })?
        .constant()
        .unwrap_or(f64::NAN);
    if let Some(slot) = values.get_mut(i) {
        *slot = Some(x);
    }
    Ok(())
}
