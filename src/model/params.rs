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
use std::collections::HashMap;
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

/// Longest chain of parameters each naming the next that is evaluated. Hand-written files
/// have chains of a few; a longer one is generated, and refusing it up front keeps load time
/// and the error message small.
pub const MAX_CHAIN: usize = 1000;

/// The error for parameter `i` at the end of a chain longer than [`MAX_CHAIN`].
fn too_long(raw: &[RawParameter<'_>], i: usize) -> ParameterError {
    ParameterError {
        index: i,
        offset: None,
        message: format!(
            "parameter {} depends on a chain of more than {MAX_CHAIN} parameters each naming the next; expected at most {MAX_CHAIN}",
            raw.get(i).map_or("?", |p| p.name)
        ),
    }
}

/// The parameters evaluated so far, by name: the scope of a parameter's expression.
struct Evaluated<'a, 'p> {
    raw: &'a [RawParameter<'p>],
    index: &'a HashMap<&'p str, usize>,
    values: &'a [Option<f64>],
}

impl Scope for Evaluated<'_, '_> {
    fn lookup(&self, name: &str) -> Result<Meaning, String> {
        if let Some(x) = self
            .index
            .get(name)
            .and_then(|&k| self.values.get(k).copied().flatten())
        {
            return Ok(Meaning::Value(x));
        }
        // The message (with its did-you-mean over the evaluated names) as for any field.
        Values {
            values: self
                .raw
                .iter()
                .zip(self.values)
                .filter_map(|(p, v)| v.map(|x| (p.name.to_string(), x)))
                .collect(),
            tables: Vec::new(),
        }
        .lookup(name)
    }

    fn table(&self, _name: &str) -> Option<Arc<Table>> {
        None
    }
}

/// Evaluates every parameter, in dependency order; `tables` are not visible to parameters.
///
/// A depth-first walk with its own stack (not recursion: a long chain cannot overflow the
/// thread's stack) and names looked up in a hash map, so the time is linear in the size of the
/// parameters. Errors: a cycle (every parameter on it named), a chain longer than
/// [`MAX_CHAIN`], or an expression that does not parse or names an unknown parameter.
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
    let mut index: HashMap<&str, usize> = HashMap::with_capacity(raw.len());
    for (k, p) in raw.iter().enumerate() {
        index.entry(p.name).or_insert(k);
    }
    // The parameters each one names, in order of appearance.
    let deps: Vec<Vec<usize>> = parsed
        .iter()
        .map(|node| {
            let mut names = Vec::new();
            if let Some(node) = node {
                node.names(&mut names);
            }
            names
                .iter()
                .filter_map(|(n, _)| index.get(n.as_str()).copied())
                .collect()
        })
        .collect();
    let mut values: Vec<Option<f64>> = raw.iter().map(|p| p.value.ok()).collect();
    let mut on_stack = vec![false; raw.len()];
    // Longest chain of expression parameters ending at each (0: a number), whatever the order
    // of declaration.
    let mut depth = vec![0usize; raw.len()];
    for root in 0..raw.len() {
        if values[root].is_some() {
            continue;
        }
        // (parameter, how many of its names are done)
        let mut stack: Vec<(usize, usize)> = vec![(root, 0)];
        on_stack[root] = true;
        while let Some(top) = stack.last_mut() {
            let (i, next) = *top;
            if let Some(&j) = deps[i].get(next) {
                top.1 += 1;
                if values[j].is_some() || parsed[j].is_none() {
                    continue;
                }
                if on_stack[j] {
                    let at = stack.iter().position(|&(k, _)| k == j).unwrap_or(0);
                    let mut cycle: Vec<&str> =
                        stack[at..].iter().map(|&(k, _)| raw[k].name).collect();
                    cycle.push(raw[j].name);
                    return Err(ParameterError {
                        index: j,
                        offset: None,
                        message: format!(
                            "parameters refer to each other in a cycle: {}",
                            cycle.join(" -> ")
                        ),
                    });
                }
                // The stack is a chain of parameters each naming the next.
                if stack.len() >= MAX_CHAIN {
                    return Err(too_long(raw, root));
                }
                on_stack[j] = true;
                stack.push((j, 0));
                continue;
            }
            let scope = Evaluated {
                raw,
                index: &index,
                values: &values,
            };
            let d = 1 + deps[i].iter().map(|&j| depth[j]).max().unwrap_or(0);
            if d > MAX_CHAIN {
                return Err(too_long(raw, i));
            }
            depth[i] = d;
            let x = match &parsed[i] {
                Some(node) => node
                    .resolve(&scope)
                    .map_err(|e: ExprError| ParameterError {
                        index: i,
                        offset: Some(e.offset),
                        message: e.message,
                    })?
                    .constant()
                    .unwrap_or(f64::NAN),
                None => f64::NAN,
            };
            values[i] = Some(x);
            on_stack[i] = false;
            stack.pop();
        }
    }
    Ok(raw
        .iter()
        .zip(values)
        .map(|(p, v)| (p.name.to_string(), v.unwrap_or(f64::NAN)))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Parameters `p0 = 1`, then `p_k = "p_{k-1} + 1"` for k = 1..=n, declared in order or
    /// reversed.
    fn chain(n: usize, reversed: bool) -> (Vec<String>, Vec<String>) {
        let names: Vec<String> = (0..=n).map(|k| format!("p{k}")).collect();
        let mut texts: Vec<String> = (0..=n)
            .map(|k| {
                if k == 0 {
                    String::new()
                } else {
                    format!("p{} + 1", k - 1)
                }
            })
            .collect();
        let mut names = names;
        if reversed {
            names.reverse();
            texts.reverse();
        }
        (names, texts)
    }

    fn run(names: &[String], texts: &[String]) -> Result<Vec<(String, f64)>, String> {
        let raw: Vec<RawParameter<'_>> = names
            .iter()
            .zip(texts)
            .map(|(n, t)| RawParameter {
                name: n,
                value: if t.is_empty() { Ok(1.0) } else { Err(t) },
            })
            .collect();
        evaluate(&raw).map_err(|e| format!("{}: {}", raw[e.index].name, e.message))
    }

    #[test]
    fn a_chain_of_the_limit_evaluates_in_either_order_and_one_more_is_refused() {
        for reversed in [false, true] {
            let (names, texts) = chain(MAX_CHAIN, reversed);
            let values = run(&names, &texts).unwrap_or_else(|e| panic!("{e}"));
            let last = values.iter().find(|(n, _)| n == "p1000").map(|v| v.1);
            assert_eq!(last, Some(1001.0), "reversed: {reversed}");
            let (names, texts) = chain(MAX_CHAIN + 1, reversed);
            // Either way the parameter at the end of the chain is named.
            assert_eq!(
                run(&names, &texts).err().as_deref(),
                Some(
                    "p1001: parameter p1001 depends on a chain of more than 1000 parameters each naming the next; expected at most 1000"
                ),
                "reversed: {reversed}"
            );
        }
    }

    #[test]
    fn a_cycle_is_named_in_full() {
        let names = ["a", "b", "c"].map(String::from);
        let texts = ["b", "c", "a + 1"].map(String::from);
        assert_eq!(
            run(&names, &texts).err().as_deref(),
            Some("a: parameters refer to each other in a cycle: a -> b -> c -> a")
        );
    }
}
