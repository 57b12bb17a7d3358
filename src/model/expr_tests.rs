use super::*;
use std::collections::HashMap;

struct Names(HashMap<&'static str, f64>);

impl Scope for Names {
    fn lookup(&self, name: &str) -> Result<Meaning, String> {
        if name == "t" {
            return Ok(Meaning::Var(Variable::Time));
        }
        self.0
            .get(name)
            .map(|x| Meaning::Value(*x))
            .ok_or_else(|| format!("unknown name \"{name}\""))
    }
    fn table(&self, name: &str) -> Option<Arc<Table>> {
        (name == "gas").then(|| {
            Arc::new(Table {
                name: "gas".into(),
                x: vec![0.0, 1.0, 3.0],
                y: vec![10.0, 20.0, 0.0],
            })
        })
    }
}

fn value(text: &str) -> f64 {
    let names = Names(HashMap::from([("L2", 0.8), ("rho", 7800.0), ("w", 0.02)]));
    match parse(text).and_then(|n| n.resolve(&names)) {
        Ok(e) => e.eval(&|_| 2.0),
        Err(e) => panic!("{text}: {e:?}"),
    }
}

fn error(text: &str) -> (usize, String) {
    let names = Names(HashMap::from([("L2", 0.8)]));
    match parse(text).and_then(|n| n.resolve(&names)) {
        Ok(e) => panic!("{text} parsed as {e:?}"),
        Err(e) => (e.offset, e.message),
    }
}

/// Exact in binary floating point or to one rounding: the tolerance 1e-15 relative is a few ulp.
fn close(text: &str, expected: f64) {
    let got = value(text);
    assert!(
        (got - expected).abs() <= 1e-15 * expected.abs().max(1.0),
        "{text}: got {got}, expected {expected}"
    );
}

#[test]
fn precedence_and_associativity() {
    close("1 + 2 * 3", 7.0);
    close("(1 + 2) * 3", 9.0);
    close("2 ^ 3 ^ 2", 512.0);
    close("-2 ^ 2", -4.0);
    close("2 ^ -1", 0.5);
    close("8 / 4 / 2", 1.0);
    close("1 - 2 - 3", -4.0);
    close("--3", 3.0);
    close("+3 * -2", -6.0);
    close("1.5e3 + .5 + 2E-1", 1500.7);
}

#[test]
fn names_functions_and_constants() {
    close("rho*L2*w", 7800.0 * 0.8 * 0.02);
    close("L2/2", 0.4);
    close("sin(pi/6)", (std::f64::consts::PI / 6.0).sin());
    close("atan2(1, -1)", 0.75 * std::f64::consts::PI);
    close("min(3, L2) + max(3, L2)", 3.8);
    close("sqrt(16) + abs(-2) + exp(0) + ln(1)", 7.0);
    close("mod(-1, 3)", 2.0);
    close("mod(7.5, 2*pi)", 7.5 - 2.0 * std::f64::consts::PI);
    close("acos(0) - asin(1) + atan(0) + tan(0) + cos(0)", 1.0);
    close("floor(-0.5)", -1.0);
}

#[test]
fn tables_interpolate_linearly_and_hold_their_ends() {
    close("gas(0.5)", 15.0);
    close("gas(2)", 10.0);
    close("gas(-1)", 10.0);
    close("gas(9)", 0.0);
}

#[test]
fn time_expressions_fold_nothing_and_evaluate_per_call() {
    let names = Names(HashMap::new());
    let e = parse("3*t^2").and_then(|n| n.resolve(&names));
    assert!(matches!(e, Ok(Expr::Bin(..))), "{e:?}");
    let Ok(e) = e else { return };
    assert_eq!(e.eval(&|_| 2.0), 12.0);
}

#[test]
fn jets_give_exact_derivatives() {
    let names = Names(HashMap::new());
    let jet = |text: &str, t: f64| match parse(text).and_then(|n| n.resolve(&names)) {
        Ok(e) => e.eval_jet(t).0,
        Err(e) => panic!("{text}: {e:?}"),
    };
    // θ = t² → θ̇ = 2t, θ̈ = 2.
    assert_eq!(jet("t^2", 3.0), [9.0, 6.0, 2.0]);
    // θ = sin(2t) → 2 cos 2t, −4 sin 2t.
    let [v, d1, d2] = jet("sin(2*t)", 0.3);
    let want = [0.6_f64.sin(), 2.0 * 0.6_f64.cos(), -4.0 * 0.6_f64.sin()];
    for (k, (g, w)) in [v, d1, d2].iter().zip(want).enumerate() {
        assert!((g - w).abs() < 1e-15, "sin(2t) derivative {k}: {g} vs {w}");
    }
    // θ = exp(t)/t at t = 1: e, 0, e (quotient rule twice).
    let [v, d1, d2] = jet("exp(t)/t", 1.0);
    let e = std::f64::consts::E;
    assert!(
        (v - e).abs() < 1e-15 && d1.abs() < 1e-15 && (d2 - e).abs() < 1e-14,
        "{v} {d1} {d2}"
    );
    // t^t = exp(t ln t): derivative t^t (ln t + 1) = 1 at t = 1, second 2 at t = 1.
    let [_, d1, d2] = jet("t^t", 1.0);
    assert!(
        (d1 - 1.0).abs() < 1e-15 && (d2 - 2.0).abs() < 1e-14,
        "{d1} {d2}"
    );
}

#[test]
fn errors_name_the_token_and_what_was_expected() {
    assert_eq!(
        error("L2*)"),
        (
            3,
            "unexpected ')'; expected a number, a name, '(' or '-'".to_string()
        )
    );
    assert_eq!(
        error("(L2 + 1"),
        (
            7,
            "unexpected end of the expression; expected ')' to close the '('".to_string()
        )
    );
    assert_eq!(
        error("L2 L2"),
        (
            3,
            "unexpected name \"L2\" after a complete expression; expected an operator (+ - * / ^) or the end"
                .to_string()
        )
    );
    assert_eq!(
        error("2 # 3"),
        (
            2,
            "unexpected character '#'; expected a number, a name, an operator (+ - * / ^), '(', ')' or ','"
                .to_string()
        )
    );
    assert_eq!(error("L3 + 1"), (0, "unknown name \"L3\"".to_string()));
    assert_eq!(
        error("sinn(1)"),
        (
            0,
            "unknown function \"sinn\": did you mean \"sin\"?; expected one of sin cos tan asin acos atan atan2 sqrt abs exp ln floor min max mod or a table from [[tables]]"
                .to_string()
        )
    );
    assert_eq!(
        error("atan2(1)"),
        (0, "atan2() takes 2 arguments, found 1".to_string())
    );
    assert_eq!(error("1..2"), (0, "malformed number \"1..2\"".to_string()));
    assert_eq!(
        error(""),
        (
            0,
            "unexpected end of the expression; expected a number, a name, '(' or '-'".to_string()
        )
    );
}

#[test]
fn hostile_nesting_is_refused_not_a_stack_overflow() {
    let deep = format!("{}1{}", "(".repeat(150), ")".repeat(150));
    assert_eq!(
        error(&deep).1,
        "expression nested more than 100 levels deep"
    );
    assert_eq!(
        error(&"-".repeat(500)).1,
        "expression nested more than 100 levels deep"
    );
    // Longer still, the token limit comes first.
    let deeper = format!("{}1{}", "(".repeat(100_000), ")".repeat(100_000));
    assert_eq!(
        error(&deeper),
        (
            1000,
            "expression longer than 1000 tokens (numbers, names, operators, parentheses); expected at most 1000: move parts of it into [parameters]".to_string()
        )
    );
    close(&format!("{}1{}", "(".repeat(40), ")".repeat(40)), 1.0);
}

#[test]
fn a_long_sum_is_refused_past_the_token_limit_and_works_below_it() {
    // 15 000 terms overflowed the stack when resolved; now the 1001st token is refused.
    let long = vec!["1"; 15_000].join("+");
    assert_eq!(
        error(&long),
        (
            1000,
            "expression longer than 1000 tokens (numbers, names, operators, parentheses); expected at most 1000: move parts of it into [parameters]".to_string()
        )
    );
    // The deepest tree 1000 tokens make: a sum of 500 terms that cannot be folded (t varies),
    // 499 levels deep. Resolved, evaluated, differentiated, cloned and dropped on a thread
    // with half the stack of a sweep's worker (1 MiB of 2 MiB), in any build profile.
    let sum = vec!["t"; 500].join("+");
    let worker = std::thread::Builder::new()
        .stack_size(1 << 20)
        .spawn(move || {
            let names = Names(HashMap::new());
            let e = parse(&sum)
                .and_then(|n| n.resolve(&names))
                .map_err(|e| e.message)?;
            let copy = e.clone();
            let v = copy.eval(&|_| 2.0);
            let jet = e.eval_jet(2.0);
            Ok::<_, String>((v, jet.0[1], e.reads_state()))
        })
        .map(|h| h.join());
    match worker {
        Ok(Ok(r)) => assert_eq!(r, Ok((1000.0, 500.0, false))),
        _ => panic!("the 500-term sum did not finish on a 1 MiB stack"),
    }
}
