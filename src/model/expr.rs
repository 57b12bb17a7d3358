//! Arithmetic expressions in model files: `"rho*L2*w"`, `"L2/2"`, `"T0*(1 - omega/omega0)"`.
//!
//! Grammar (usual precedence, `^` binds tighter than unary minus and is right-associative, so
//! `-2^2 = -4` and `2^3^2 = 2^9`):
//!
//! ```text
//! expr  := term (('+' | '-') term)*
//! term  := unary (('*' | '/') unary)*
//! unary := ('-' | '+') unary | power
//! power := atom ('^' unary)?
//! atom  := number | name | name '(' expr (',' expr)* ')' | '(' expr ')'
//! ```
//!
//! A name is letters, digits, `_` and `.` (so `crank.phi` is one name), starting with a letter
//! or `_`. Functions: `sin cos tan asin acos atan sqrt abs exp ln floor` (one argument) and
//! `atan2(y, x) min max mod` (two; `mod(a, b) = a − b ⌊a/b⌋`, the sign of b, as Python's `%`).
//! Constant: `pi`. A table declared in `[[tables]]` is called like a function of one argument.
//!
//! Parsing gives a [`Node`] tree with byte offsets into the text, for located errors;
//! [`Node::resolve`] turns it into an [`Expr`] whose names are parameters (folded to numbers),
//! tables, or [`Variable`]s of the state, read at run time.

use super::types::{BodyId, Frame};
use serde::Serialize;
use std::sync::Arc;

/// An error in an expression: the byte offset of the offending token in the expression text
/// and the message (what was found, what was expected).
#[derive(Debug, Clone, PartialEq)]
pub struct ExprError {
    /// Byte offset into the expression text.
    pub offset: usize,
    /// What is wrong and what was expected.
    pub message: String,
}

fn fail<T>(offset: usize, message: impl Into<String>) -> Result<T, ExprError> {
    Err(ExprError {
        offset,
        message: message.into(),
    })
}

/// A binary operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum BinOp {
    /// +
    Add,
    /// −
    Sub,
    /// ×
    Mul,
    /// ÷
    Div,
    /// ^
    Pow,
}

/// A built-in function.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Func {
    /// sin (rad).
    Sin,
    /// cos (rad).
    Cos,
    /// tan (rad).
    Tan,
    /// asin (rad).
    Asin,
    /// acos (rad).
    Acos,
    /// atan (rad).
    Atan,
    /// atan2(y, x) (rad).
    Atan2,
    /// Square root.
    Sqrt,
    /// |x|.
    Abs,
    /// eˣ.
    Exp,
    /// Natural logarithm.
    Ln,
    /// ⌊x⌋.
    Floor,
    /// Smaller of two.
    Min,
    /// Larger of two.
    Max,
    /// mod(a, b) = a − b ⌊a/b⌋.
    Mod,
}

const FUNCS: &[(&str, Func, usize)] = &[
    ("sin", Func::Sin, 1),
    ("cos", Func::Cos, 1),
    ("tan", Func::Tan, 1),
    ("asin", Func::Asin, 1),
    ("acos", Func::Acos, 1),
    ("atan", Func::Atan, 1),
    ("atan2", Func::Atan2, 2),
    ("sqrt", Func::Sqrt, 1),
    ("abs", Func::Abs, 1),
    ("exp", Func::Exp, 1),
    ("ln", Func::Ln, 1),
    ("floor", Func::Floor, 1),
    ("min", Func::Min, 2),
    ("max", Func::Max, 2),
    ("mod", Func::Mod, 2),
];

/// Names of the built-in functions and constants, which no parameter may take.
pub fn reserved(name: &str) -> bool {
    name == "pi" || FUNCS.iter().any(|(n, _, _)| *n == name)
}

/// A quantity of the state an expression may read at run time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Variable {
    /// Time t (s).
    Time,
    /// Coordinate `field` (0 x, 1 y, 2 φ, 3 ẋ, 4 ẏ, 5 φ̇; m, rad, m/s, rad/s) of a body.
    Body {
        /// The body.
        body: BodyId,
        /// 0..6 as above.
        field: usize,
    },
    /// Relative angle φ_b − φ_a of a revolute joint (rad), e.g. the driver angle θ.
    JointAngle {
        /// Frame of the joint's first body.
        a: Frame,
        /// Frame of the joint's second body.
        b: Frame,
    },
    /// Relative angular speed φ̇_b − φ̇_a of a revolute joint (rad/s).
    JointSpeed {
        /// Frame of the joint's first body.
        a: Frame,
        /// Frame of the joint's second body.
        b: Frame,
    },
}

/// A table y(x) with linear interpolation, constant beyond its ends.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Table {
    /// Name in `[[tables]]`.
    pub name: String,
    /// Strictly increasing abscissae.
    pub x: Vec<f64>,
    /// Ordinates, as many as `x`.
    pub y: Vec<f64>,
}

impl Table {
    /// y(x) and dy/dx by linear interpolation; beyond the ends, the end value and slope 0.
    pub fn eval(&self, x: f64) -> (f64, f64) {
        let n = self.x.len().min(self.y.len());
        let (Some(&x0), Some(&xn)) = (self.x.first(), self.x.get(n.wrapping_sub(1))) else {
            return (0.0, 0.0);
        };
        if x <= x0 {
            return (self.y[0], 0.0);
        }
        if x >= xn {
            return (self.y[n - 1], 0.0);
        }
        // First abscissa above x: 1 ≤ k ≤ n − 1 by the two tests above.
        let k = self.x[..n].partition_point(|&xi| xi <= x).clamp(1, n - 1);
        let (xa, xb, ya, yb) = (self.x[k - 1], self.x[k], self.y[k - 1], self.y[k]);
        let slope = (yb - ya) / (xb - xa);
        (ya + slope * (x - xa), slope)
    }
}

/// A resolved expression: numbers, variables, operators, functions, tables.
#[derive(Debug, Clone, PartialEq)]
pub enum Expr {
    /// A number (parameters are folded into numbers).
    Num(f64),
    /// A run-time quantity.
    Var(Variable),
    /// −x.
    Neg(Box<Expr>),
    /// a ∘ b.
    Bin(BinOp, Box<Expr>, Box<Expr>),
    /// f(args).
    Call(Func, Vec<Expr>),
    /// table(x).
    Table(Arc<Table>, Box<Expr>),
}

impl Expr {
    /// The number, if the expression is one.
    pub fn constant(&self) -> Option<f64> {
        match self {
            Expr::Num(x) => Some(*x),
            _ => None,
        }
    }

    /// True if some variable other than time appears.
    pub fn reads_state(&self) -> bool {
        match self {
            Expr::Num(_) => false,
            Expr::Var(v) => *v != Variable::Time,
            Expr::Neg(a) | Expr::Table(_, a) => a.reads_state(),
            Expr::Bin(_, a, b) => a.reads_state() || b.reads_state(),
            Expr::Call(_, args) => args.iter().any(Expr::reads_state),
        }
    }

    /// Calls `f` with every variable that appears (repeats included), in order.
    pub fn for_each_variable(&self, f: &mut impl FnMut(Variable)) {
        match self {
            Expr::Num(_) => {}
            Expr::Var(v) => f(*v),
            Expr::Neg(a) | Expr::Table(_, a) => a.for_each_variable(f),
            Expr::Bin(_, a, b) => {
                a.for_each_variable(f);
                b.for_each_variable(f);
            }
            Expr::Call(_, args) => args.iter().for_each(|a| a.for_each_variable(f)),
        }
    }

    /// Value with the variables read from `var`.
    pub fn eval(&self, var: &impl Fn(Variable) -> f64) -> f64 {
        match self {
            Expr::Num(x) => *x,
            Expr::Var(v) => var(*v),
            Expr::Neg(a) => -a.eval(var),
            Expr::Bin(op, a, b) => binary(*op, a.eval(var), b.eval(var)),
            Expr::Call(f, args) => {
                let a = args.first().map_or(f64::NAN, |a| a.eval(var));
                let b = args.get(1).map_or(f64::NAN, |b| b.eval(var));
                call(*f, a, b)
            }
            Expr::Table(t, a) => t.eval(a.eval(var)).0,
        }
    }

    /// Value, first and second time derivative of an expression of t alone (other variables
    /// read as 0), by forward-mode differentiation with second-order jets.
    pub fn eval_jet(&self, t: f64) -> Jet {
        match self {
            Expr::Num(x) => Jet::constant(*x),
            Expr::Var(Variable::Time) => Jet([t, 1.0, 0.0]),
            Expr::Var(_) => Jet::constant(0.0),
            Expr::Neg(a) => a.eval_jet(t).scale(-1.0),
            Expr::Bin(op, a, b) => {
                let (a, b) = (a.eval_jet(t), b.eval_jet(t));
                match op {
                    BinOp::Add => Jet([a.0[0] + b.0[0], a.0[1] + b.0[1], a.0[2] + b.0[2]]),
                    BinOp::Sub => Jet([a.0[0] - b.0[0], a.0[1] - b.0[1], a.0[2] - b.0[2]]),
                    BinOp::Mul => a.mul(b),
                    BinOp::Div => a.mul(b.recip()),
                    BinOp::Pow => {
                        if b.0[1] == 0.0 && b.0[2] == 0.0 {
                            // Constant exponent: d(aᵇ) = b aᵇ⁻¹ da works for a ≤ 0 too.
                            let p = b.0[0];
                            let v = a.0[0];
                            a.chain([
                                v.powf(p),
                                p * v.powf(p - 1.0),
                                p * (p - 1.0) * v.powf(p - 2.0),
                            ])
                        } else {
                            // aᵇ = exp(b ln a).
                            let ln_a =
                                a.chain([a.0[0].ln(), 1.0 / a.0[0], -1.0 / (a.0[0] * a.0[0])]);
                            let e = b.mul(ln_a);
                            let v = e.0[0].exp();
                            e.chain([v, v, v])
                        }
                    }
                }
            }
            Expr::Call(f, args) => {
                let a = args
                    .first()
                    .map_or(Jet::constant(f64::NAN), |a| a.eval_jet(t));
                let x = a.0[0];
                match f {
                    Func::Sin => a.chain([x.sin(), x.cos(), -x.sin()]),
                    Func::Cos => a.chain([x.cos(), -x.sin(), -x.cos()]),
                    Func::Tan => {
                        let s = 1.0 / (x.cos() * x.cos());
                        a.chain([x.tan(), s, 2.0 * x.tan() * s])
                    }
                    Func::Asin => {
                        let r = 1.0 / (1.0 - x * x).sqrt();
                        a.chain([x.asin(), r, x * r * r * r])
                    }
                    Func::Acos => {
                        let r = 1.0 / (1.0 - x * x).sqrt();
                        a.chain([x.acos(), -r, -x * r * r * r])
                    }
                    Func::Atan => {
                        let r = 1.0 / (1.0 + x * x);
                        a.chain([x.atan(), r, -2.0 * x * r * r])
                    }
                    Func::Sqrt => {
                        let s = x.sqrt();
                        a.chain([s, 0.5 / s, -0.25 / (s * x)])
                    }
                    Func::Abs => {
                        let s = if x < 0.0 { -1.0 } else { 1.0 };
                        a.chain([x.abs(), s, 0.0])
                    }
                    Func::Exp => a.chain([x.exp(), x.exp(), x.exp()]),
                    Func::Ln => a.chain([x.ln(), 1.0 / x, -1.0 / (x * x)]),
                    Func::Floor => Jet::constant(x.floor()),
                    Func::Atan2 | Func::Min | Func::Max | Func::Mod => {
                        let b = args
                            .get(1)
                            .map_or(Jet::constant(f64::NAN), |b| b.eval_jet(t));
                        match f {
                            Func::Min => {
                                if a.0[0] <= b.0[0] {
                                    a
                                } else {
                                    b
                                }
                            }
                            Func::Max => {
                                if a.0[0] >= b.0[0] {
                                    a
                                } else {
                                    b
                                }
                            }
                            Func::Mod => {
                                let k = (a.0[0] / b.0[0]).floor();
                                Jet([
                                    a.0[0] - k * b.0[0],
                                    a.0[1] - k * b.0[1],
                                    a.0[2] - k * b.0[2],
                                ])
                            }
                            // atan(y/x) up to a constant, with the quotient's jet.
                            _ => {
                                let q = a.mul(b.recip());
                                let r = 1.0 / (1.0 + q.0[0] * q.0[0]);
                                let j = q.chain([0.0, r, -2.0 * q.0[0] * r * r]);
                                Jet([a.0[0].atan2(b.0[0]), j.0[1], j.0[2]])
                            }
                        }
                    }
                }
            }
            Expr::Table(tab, a) => {
                let a = a.eval_jet(t);
                let (y, slope) = tab.eval(a.0[0]);
                a.chain([y, slope, 0.0])
            }
        }
    }
}

/// A value and its first two derivatives with respect to t.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jet(pub [f64; 3]);

impl Jet {
    fn constant(x: f64) -> Self {
        Jet([x, 0.0, 0.0])
    }
    fn scale(self, k: f64) -> Self {
        Jet([k * self.0[0], k * self.0[1], k * self.0[2]])
    }
    fn mul(self, b: Jet) -> Jet {
        let [a0, a1, a2] = self.0;
        let [b0, b1, b2] = b.0;
        Jet([
            a0 * b0,
            a1 * b0 + a0 * b1,
            a2 * b0 + 2.0 * a1 * b1 + a0 * b2,
        ])
    }
    fn recip(self) -> Jet {
        let x = self.0[0];
        self.chain([1.0 / x, -1.0 / (x * x), 2.0 / (x * x * x)])
    }
    /// f(self) given f, f′, f″ at self's value: (f, f′ u′, f″ u′² + f′ u″).
    fn chain(self, [f, f1, f2]: [f64; 3]) -> Jet {
        let [_, u1, u2] = self.0;
        Jet([f, f1 * u1, f2 * u1 * u1 + f1 * u2])
    }
}

fn binary(op: BinOp, a: f64, b: f64) -> f64 {
    match op {
        BinOp::Add => a + b,
        BinOp::Sub => a - b,
        BinOp::Mul => a * b,
        BinOp::Div => a / b,
        BinOp::Pow => a.powf(b),
    }
}

fn call(f: Func, a: f64, b: f64) -> f64 {
    match f {
        Func::Sin => a.sin(),
        Func::Cos => a.cos(),
        Func::Tan => a.tan(),
        Func::Asin => a.asin(),
        Func::Acos => a.acos(),
        Func::Atan => a.atan(),
        Func::Atan2 => a.atan2(b),
        Func::Sqrt => a.sqrt(),
        Func::Abs => a.abs(),
        Func::Exp => a.exp(),
        Func::Ln => a.ln(),
        Func::Floor => a.floor(),
        Func::Min => a.min(b),
        Func::Max => a.max(b),
        Func::Mod => a - b * (a / b).floor(),
    }
}

/// A parsed expression, names unresolved, with the byte offset of each node in the text.
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    /// Byte offset of the node's first character.
    pub offset: usize,
    /// What the node is.
    pub kind: NodeKind,
}

/// Kinds of [`Node`].
#[derive(Debug, Clone, PartialEq)]
pub enum NodeKind {
    /// A number literal.
    Num(f64),
    /// A name (parameter, constant, variable).
    Name(String),
    /// −x.
    Neg(Box<Node>),
    /// a ∘ b.
    Bin(BinOp, Box<Node>, Box<Node>),
    /// name(args): a function or a table.
    Call(String, Vec<Node>),
}

/// What a name means, as the caller of [`Node::resolve`] knows it.
pub enum Meaning {
    /// A number (a parameter or the loop index).
    Value(f64),
    /// A run-time quantity.
    Var(Variable),
}

/// The names an expression may use; `lookup` gives `Err(message)` for an unknown name, with a
/// did-you-mean and what is allowed there.
pub trait Scope {
    /// The meaning of `name`, or why it has none here.
    fn lookup(&self, name: &str) -> Result<Meaning, String>;
    /// A table by name, if declared.
    fn table(&self, name: &str) -> Option<Arc<Table>>;
}

impl Node {
    /// Resolves names and folds constant sub-expressions.
    pub fn resolve(&self, scope: &dyn Scope) -> Result<Expr, ExprError> {
        let e = match &self.kind {
            NodeKind::Num(x) => Expr::Num(*x),
            NodeKind::Name(n) if n == "pi" => Expr::Num(std::f64::consts::PI),
            NodeKind::Name(n) => match scope.lookup(n) {
                Ok(Meaning::Value(x)) => Expr::Num(x),
                Ok(Meaning::Var(v)) => Expr::Var(v),
                Err(message) => return fail(self.offset, message),
            },
            NodeKind::Neg(a) => match a.resolve(scope)? {
                Expr::Num(x) => Expr::Num(-x),
                e => Expr::Neg(Box::new(e)),
            },
            NodeKind::Bin(op, a, b) => match (a.resolve(scope)?, b.resolve(scope)?) {
                (Expr::Num(x), Expr::Num(y)) => Expr::Num(binary(*op, x, y)),
                (x, y) => Expr::Bin(*op, Box::new(x), Box::new(y)),
            },
            NodeKind::Call(name, args) => {
                let resolved = args
                    .iter()
                    .map(|a| a.resolve(scope))
                    .collect::<Result<Vec<_>, _>>()?;
                if let Some((_, f, arity)) = FUNCS.iter().find(|(n, _, _)| n == name) {
                    if resolved.len() != *arity {
                        return fail(
                            self.offset,
                            format!(
                                "{name}() takes {arity} argument{}, found {}",
                                if *arity == 1 { "" } else { "s" },
                                resolved.len()
                            ),
                        );
                    }
                    match resolved.as_slice() {
                        [Expr::Num(a)] => Expr::Num(call(*f, *a, f64::NAN)),
                        [Expr::Num(a), Expr::Num(b)] => Expr::Num(call(*f, *a, *b)),
                        _ => Expr::Call(*f, resolved),
                    }
                } else if let Some(table) = scope.table(name) {
                    let [arg] = <[Expr; 1]>::try_from(resolved).map_err(|r| ExprError {
                        offset: self.offset,
                        message: format!("table {name}() takes 1 argument, found {}", r.len()),
                    })?;
                    match arg {
                        Expr::Num(x) => Expr::Num(table.eval(x).0),
                        arg => Expr::Table(table, Box::new(arg)),
                    }
                } else {
                    let names = FUNCS.iter().map(|(n, _, _)| *n);
                    return fail(
                        self.offset,
                        format!(
                            "unknown function \"{name}\"{}; expected one of {} or a table from [[tables]]",
                            super::suggest::did_you_mean(name, names.clone()),
                            names.collect::<Vec<_>>().join(" ")
                        ),
                    );
                }
            }
        };
        Ok(e)
    }

    /// Names used (not functions), each with its offset, in order of appearance.
    pub fn names(&self, out: &mut Vec<(String, usize)>) {
        match &self.kind {
            NodeKind::Num(_) => {}
            NodeKind::Name(n) => out.push((n.clone(), self.offset)),
            NodeKind::Neg(a) => a.names(out),
            NodeKind::Bin(_, a, b) => {
                a.names(out);
                b.names(out);
            }
            NodeKind::Call(_, args) => args.iter().for_each(|a| a.names(out)),
        }
    }
}

/// Parses an expression.
pub fn parse(text: &str) -> Result<Node, ExprError> {
    let mut p = Parser {
        tokens: tokenize(text)?,
        pos: 0,
        end: text.len(),
        depth: 0,
    };
    let node = p.expr()?;
    match p.peek() {
        None => Ok(node),
        Some(t) => fail(
            t.offset,
            format!(
                "unexpected {} after a complete expression; expected an operator (+ - * / ^) or the end",
                t.describe()
            ),
        ),
    }
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Num(f64),
    Name(String),
    Op(char),
}

#[derive(Debug, Clone)]
struct Token {
    tok: Tok,
    offset: usize,
}

impl Token {
    fn describe(&self) -> String {
        match &self.tok {
            Tok::Num(x) => format!("number {x}"),
            Tok::Name(n) => format!("name \"{n}\""),
            Tok::Op(c) => format!("'{c}'"),
        }
    }
}

/// Most tokens (numbers, names, operators, parentheses, commas) in one expression. The tree of a
/// long sum or product is as deep as it has terms, and resolving, evaluating, differentiating
/// and dropping it recurse that deep: 1000 tokens keep that recursion far inside the smallest
/// stack it runs on (2 MiB, a worker thread of a sweep), where 15 000 terms overflowed the main
/// thread's 8 MiB. A hand-written expression has a few dozen.
pub const MAX_TOKENS: usize = 1000;

fn tokenize(text: &str) -> Result<Vec<Token>, ExprError> {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        if out.len() == MAX_TOKENS && !c.is_ascii_whitespace() {
            return fail(
                i,
                format!(
                    "expression longer than {MAX_TOKENS} tokens (numbers, names, operators, parentheses); expected at most {MAX_TOKENS}: move parts of it into [parameters]"
                ),
            );
        }
        if c.is_ascii_whitespace() {
            i += 1;
        } else if c.is_ascii_digit()
            || (c == b'.' && bytes.get(i + 1).is_some_and(u8::is_ascii_digit))
        {
            let start = i;
            while i < bytes.len() && (bytes[i].is_ascii_digit() || bytes[i] == b'.') {
                i += 1;
            }
            // An exponent only if digits follow: "2e" alone is an error below.
            if i < bytes.len() && (bytes[i] == b'e' || bytes[i] == b'E') {
                let mut j = i + 1;
                if j < bytes.len() && (bytes[j] == b'+' || bytes[j] == b'-') {
                    j += 1;
                }
                if j < bytes.len() && bytes[j].is_ascii_digit() {
                    while j < bytes.len() && bytes[j].is_ascii_digit() {
                        j += 1;
                    }
                    i = j;
                }
            }
            let literal = text.get(start..i).unwrap_or("");
            let x = literal.parse::<f64>().map_err(|_| ExprError {
                offset: start,
                message: format!("malformed number \"{literal}\""),
            })?;
            out.push(Token {
                tok: Tok::Num(x),
                offset: start,
            });
        } else if c.is_ascii_alphabetic() || c == b'_' {
            let start = i;
            while i < bytes.len()
                && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_' || bytes[i] == b'.')
            {
                i += 1;
            }
            out.push(Token {
                tok: Tok::Name(text.get(start..i).unwrap_or("").to_string()),
                offset: start,
            });
        } else if b"+-*/^(),".contains(&c) {
            out.push(Token {
                tok: Tok::Op(c as char),
                offset: i,
            });
            i += 1;
        } else {
            let ch = text.get(i..).and_then(|s| s.chars().next()).unwrap_or('?');
            return fail(
                i,
                format!(
                    "unexpected character {ch:?}; expected a number, a name, an operator (+ - * / ^), '(', ')' or ','"
                ),
            );
        }
    }
    Ok(out)
}

struct Parser {
    tokens: Vec<Token>,
    pos: usize,
    end: usize,
    /// Nesting depth of parentheses, calls and unary signs, bounded so that a hostile string
    /// cannot overflow the stack of the recursive descent (or of evaluation, which follows the
    /// same tree).
    depth: usize,
}

/// Deepest nesting accepted: far beyond any hand-written expression.
const MAX_DEPTH: usize = 100;

const OPERAND: &str = "expected a number, a name, '(' or '-'";

impl Parser {
    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.pos)
    }

    fn peek_op(&self) -> Option<char> {
        match self.peek() {
            Some(Token {
                tok: Tok::Op(c), ..
            }) => Some(*c),
            _ => None,
        }
    }

    /// Enters one level of nesting, refusing more than [`MAX_DEPTH`].
    fn deeper(&mut self) -> Result<(), ExprError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            let offset = self.peek().map_or(self.end, |t| t.offset);
            return fail(
                offset,
                format!("expression nested more than {MAX_DEPTH} levels deep"),
            );
        }
        Ok(())
    }

    fn expr(&mut self) -> Result<Node, ExprError> {
        self.deeper()?;
        let node = self.sum();
        self.depth -= 1;
        node
    }

    fn sum(&mut self) -> Result<Node, ExprError> {
        let mut left = self.term()?;
        while let Some(c @ ('+' | '-')) = self.peek_op() {
            let offset = self.tokens[self.pos].offset;
            self.pos += 1;
            let right = self.term()?;
            let op = if c == '+' { BinOp::Add } else { BinOp::Sub };
            left = Node {
                offset,
                kind: NodeKind::Bin(op, Box::new(left), Box::new(right)),
            };
        }
        Ok(left)
    }

    fn term(&mut self) -> Result<Node, ExprError> {
        let mut left = self.unary()?;
        while let Some(c @ ('*' | '/')) = self.peek_op() {
            let offset = self.tokens[self.pos].offset;
            self.pos += 1;
            let right = self.unary()?;
            let op = if c == '*' { BinOp::Mul } else { BinOp::Div };
            left = Node {
                offset,
                kind: NodeKind::Bin(op, Box::new(left), Box::new(right)),
            };
        }
        Ok(left)
    }

    fn unary(&mut self) -> Result<Node, ExprError> {
        self.deeper()?;
        let node = self.signed();
        self.depth -= 1;
        node
    }

    fn signed(&mut self) -> Result<Node, ExprError> {
        match self.peek_op() {
            Some('-') => {
                let offset = self.tokens[self.pos].offset;
                self.pos += 1;
                let inner = self.unary()?;
                Ok(Node {
                    offset,
                    kind: NodeKind::Neg(Box::new(inner)),
                })
            }
            Some('+') => {
                self.pos += 1;
                self.unary()
            }
            _ => self.power(),
        }
    }

    fn power(&mut self) -> Result<Node, ExprError> {
        let base = self.atom()?;
        if self.peek_op() == Some('^') {
            let offset = self.tokens[self.pos].offset;
            self.pos += 1;
            let exponent = self.unary()?;
            return Ok(Node {
                offset,
                kind: NodeKind::Bin(BinOp::Pow, Box::new(base), Box::new(exponent)),
            });
        }
        Ok(base)
    }

    fn atom(&mut self) -> Result<Node, ExprError> {
        let Some(token) = self.peek().cloned() else {
            return fail(
                self.end,
                format!("unexpected end of the expression; {OPERAND}"),
            );
        };
        self.pos += 1;
        match token.tok {
            Tok::Num(x) => Ok(Node {
                offset: token.offset,
                kind: NodeKind::Num(x),
            }),
            Tok::Name(name) => {
                if self.peek_op() != Some('(') {
                    return Ok(Node {
                        offset: token.offset,
                        kind: NodeKind::Name(name),
                    });
                }
                self.pos += 1;
                let mut args = vec![self.expr()?];
                loop {
                    match self.peek_op() {
                        Some(',') => {
                            self.pos += 1;
                            args.push(self.expr()?);
                        }
                        Some(')') => {
                            self.pos += 1;
                            break;
                        }
                        _ => return self.expected(&format!("',' or ')' to close {name}(")),
                    }
                }
                Ok(Node {
                    offset: token.offset,
                    kind: NodeKind::Call(name, args),
                })
            }
            Tok::Op('(') => {
                let inner = self.expr()?;
                if self.peek_op() == Some(')') {
                    self.pos += 1;
                    Ok(inner)
                } else {
                    self.expected("')' to close the '('")
                }
            }
            Tok::Op(_) => fail(
                token.offset,
                format!("unexpected {}; {OPERAND}", token.describe()),
            ),
        }
    }

    fn expected<T>(&self, what: &str) -> Result<T, ExprError> {
        match self.peek() {
            Some(t) => fail(
                t.offset,
                format!("unexpected {}; expected {what}", t.describe()),
            ),
            None => fail(
                self.end,
                format!("unexpected end of the expression; expected {what}"),
            ),
        }
    }
}

#[cfg(test)]
#[path = "expr_tests.rs"]
mod tests;
