//! Which names a model may give its bodies, points, joints, drivers, forces and itself.
//!
//! Names head CSV columns (`coupler.phi`, `B.fn`, `motor.torque`), sit on `# ` provenance lines,
//! are addressed by `--set` paths (`bodies.crank.mass`) and appear in error messages. So a name
//! is 1 to [`MAX_LEN`] ASCII letters, digits, `_` or `-`, starting with a letter or a digit:
//! - no `,` or `"` (they split or quote a CSV field), no whitespace, newline or control
//!   character (they break a header or a provenance line), no `.` (it separates the parts of a
//!   column name and of a `--set` path), no `=` (it ends the path of a `--set`);
//! - no `#` (a line starting with it is a comment to CSV readers) and no leading `-` (it reads
//!   as a command-line option);
//! - ASCII only, so every CSV reader and terminal shows the same name.

/// Longest name accepted (characters): long enough for any descriptive name, short enough that
/// a column header stays readable.
pub const MAX_LEN: usize = 64;

/// The rule, as error messages state it.
pub const RULE: &str = "1 to 64 ASCII letters, digits, '_' or '-', starting with a letter or digit";

/// `Ok` if `name` follows the rule; otherwise why not (the first offending character, named).
pub fn check(name: &str) -> Result<(), String> {
    let Some(first) = name.chars().next() else {
        return Err("it is empty".to_string());
    };
    if name.chars().count() > MAX_LEN {
        return Err(format!(
            "it has {} characters, more than {MAX_LEN}",
            name.chars().count()
        ));
    }
    if let Some(bad) = name
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || *c == '_' || *c == '-'))
    {
        return Err(format!("{} is not allowed", describe(bad)));
    }
    if !first.is_ascii_alphanumeric() {
        return Err(format!("it starts with {}", describe(first)));
    }
    Ok(())
}

/// `true` if `name` follows the rule.
pub fn is_valid(name: &str) -> bool {
    check(name).is_ok()
}

/// A character named so that the message stays on one line and shows what it is.
fn describe(c: char) -> String {
    match c {
        ' ' => "a space".to_string(),
        '\t' => "a tab".to_string(),
        '\n' => "a newline".to_string(),
        '\r' => "a carriage return".to_string(),
        ',' => "',' (it splits a CSV field)".to_string(),
        '"' => "'\"' (it quotes a CSV field)".to_string(),
        '.' => "'.' (it separates the parts of a column name and of a --set path)".to_string(),
        '#' => "'#' (it starts a comment line)".to_string(),
        '-' => "'-' (it reads as a command-line option)".to_string(),
        '_' => "'_'".to_string(),
        c if c.is_control() => format!("the control character U+{:04X}", c as u32),
        c if !c.is_ascii() => format!("the non-ASCII character '{c}' (U+{:04X})", c as u32),
        c => format!("'{c}'"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shipped_names_are_valid() {
        for n in [
            "crank",
            "O2",
            "B",
            "motor",
            "farahan2016",
            "slider_crank",
            "a-1",
        ] {
            assert_eq!(check(n), Ok(()), "{n}");
        }
    }

    #[test]
    fn each_hostile_name_is_refused_with_its_reason() {
        let cases = [
            ("", "it is empty"),
            ("a,b", "',' (it splits a CSV field) is not allowed"),
            ("a\"b", "'\"' (it quotes a CSV field) is not allowed"),
            ("my crank", "a space is not allowed"),
            ("a\nb", "a newline is not allowed"),
            ("a\u{7}", "the control character U+0007 is not allowed"),
            ("#x", "'#' (it starts a comment line) is not allowed"),
            (
                "-x",
                "it starts with '-' (it reads as a command-line option)",
            ),
            ("_x", "it starts with '_'"),
            (
                "a.b",
                "'.' (it separates the parts of a column name and of a --set path) is not allowed",
            ),
            ("é", "the non-ASCII character 'é' (U+00E9) is not allowed"),
        ];
        for (name, reason) in cases {
            assert_eq!(check(name), Err(reason.to_string()), "{name:?}");
        }
        let long = "a".repeat(MAX_LEN + 1);
        assert_eq!(
            check(&long),
            Err(format!("it has {} characters, more than 64", MAX_LEN + 1))
        );
        assert_eq!(check(&"a".repeat(MAX_LEN)), Ok(()));
    }
}
