//! The README and the usage guide say what the binary does: every `linkdyn` command line in
//! their code blocks (and every inline `` `linkdyn <command> …` `` span) names a command that
//! `linkdyn --help` lists, and only options that the command's own `--help` lists. The synopses
//! drifted from the code before (a `run` synopsis that knew two methods and two formulations);
//! this test makes the next drift fail with the file, the line and the unknown option.
//!
//! Also: the README stays a front door, at most `README_MAX_LINES` lines; the detail lives in
//! `docs/`.
//!
//! What counts as a command line: in a fenced code block, a line that starts with `linkdyn `,
//! `target/release/linkdyn ` or `cargo run --release -- ` (after an optional `$ `), joined with
//! the lines after it that a shell would join (a trailing `\`) or that continue a synopsis (more
//! indented, starting with `[` or `--`); shell comments (` #…`) are dropped. Outside code blocks,
//! an inline code span that starts with `linkdyn ` and a lower-case word. Alternatives written
//! `a|b` are each checked (`linkdyn plot series|orbit …` checks both kinds). Placeholders in
//! capitals (`linkdyn COMMAND --help`) are not commands and are skipped.

mod cli_common;

use cli_common::linkdyn;
use std::collections::{BTreeMap, BTreeSet};

/// The documents whose command lines are checked, relative to the crate root.
const FILES: &[&str] = &["README.md", "docs/usage.md", "docs/python.md"];

/// The README's length limit: a front door (what it is, the two commands, one example, where
/// each topic lives) fits in about 200 lines; 220 leaves room for a line or two of news.
const README_MAX_LINES: usize = 220;

/// One command line found in a document: where it starts, and its words after the program
/// name, each with the line it is on (a synopsis spans several).
#[derive(Debug)]
struct CommandLine {
    file: String,
    line: usize,
    words: Vec<String>,
    word_lines: Vec<usize>,
}

impl CommandLine {
    fn new(file: &str, parts: &[(usize, &str)]) -> CommandLine {
        let (mut words, mut word_lines) = (Vec::new(), Vec::new());
        for (line, text) in parts {
            for w in text.split_whitespace() {
                words.push(w.to_string());
                word_lines.push(*line);
            }
        }
        CommandLine {
            file: file.to_string(),
            line: parts.first().map_or(0, |p| p.0),
            words,
            word_lines,
        }
    }
}

const PREFIXES: &[&str] = &[
    "linkdyn ",
    "target/release/linkdyn ",
    "cargo run --release -- ",
];

/// Drops a shell comment: from the first `#` that starts a word.
fn strip_comment(s: &str) -> &str {
    let bytes = s.as_bytes();
    for (i, &b) in bytes.iter().enumerate() {
        if b == b'#' && (i == 0 || bytes[i - 1].is_ascii_whitespace()) {
            return &s[..i];
        }
    }
    s
}

fn indentation(s: &str) -> usize {
    s.len() - s.trim_start().len()
}

/// The command lines of one document.
fn command_lines(file: &str, text: &str) -> Vec<CommandLine> {
    let lines: Vec<&str> = text.lines().collect();
    let mut found = Vec::new();
    let mut in_code = false;
    let mut i = 0;
    while i < lines.len() {
        let raw = lines[i];
        let trimmed = raw.trim_start();
        if trimmed.starts_with("```") {
            in_code = !in_code;
            i += 1;
            continue;
        }
        if !in_code {
            for span in inline_code_spans(raw) {
                if let Some(rest) = span.strip_prefix("linkdyn ")
                    && rest.starts_with(|c: char| c.is_ascii_lowercase())
                {
                    found.push(CommandLine::new(file, &[(i + 1, rest)]));
                }
            }
            i += 1;
            continue;
        }
        let body = trimmed.strip_prefix("$ ").unwrap_or(trimmed);
        let Some(rest) = PREFIXES.iter().find_map(|p| body.strip_prefix(p)) else {
            i += 1;
            continue;
        };
        let mut parts: Vec<(usize, &str)> = vec![(i + 1, strip_comment(rest).trim_end())];
        // A trailing backslash joins the next line, as in a shell.
        while i + 1 < lines.len() {
            let Some(last) = parts.last_mut() else { break };
            let Some(text) = last.1.strip_suffix('\\') else {
                break;
            };
            last.1 = text;
            i += 1;
            parts.push((i + 1, strip_comment(lines[i].trim()).trim_end()));
        }
        // A synopsis continues on more indented lines that start with an option.
        while i + 1 < lines.len() {
            let next = lines[i + 1];
            let next_trimmed = next.trim_start();
            if indentation(next) > indentation(raw)
                && (next_trimmed.starts_with('[') || next_trimmed.starts_with("--"))
            {
                i += 1;
                parts.push((i + 1, strip_comment(next_trimmed).trim_end()));
            } else {
                break;
            }
        }
        found.push(CommandLine::new(file, &parts));
        i += 1;
    }
    found
}

/// The text between single backticks on one line.
fn inline_code_spans(line: &str) -> Vec<&str> {
    line.split('`').skip(1).step_by(2).collect()
}

/// The `--options` a command line uses, each with its line: every word, or `|`-separated piece
/// of a word, that starts with `--`, without brackets, `=value` or `...`.
fn options_used(words: &[String], word_lines: &[usize]) -> Vec<(usize, String)> {
    let mut options = Vec::new();
    for (word, line) in words.iter().zip(word_lines) {
        for piece in word.split('|') {
            let piece = piece.trim_start_matches('[');
            let Some(name) = piece.strip_prefix("--") else {
                continue;
            };
            let name: String = name
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '-')
                .collect();
            if !name.is_empty() {
                options.push((*line, format!("--{name}")));
            }
        }
    }
    options
}

/// The options a `--help` text lists: the first `--name` on each option line (indented by at
/// most six spaces and starting with `-`, as clap writes them), not options that a description
/// mentions.
fn options_listed(help: &str) -> BTreeSet<String> {
    help.lines()
        .filter(|l| indentation(l) <= 6 && l.trim_start().starts_with('-'))
        .filter_map(|l| {
            let at = l.find("--")?;
            let name: String = l[at + 2..]
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '-')
                .collect();
            Some(format!("--{name}"))
        })
        .collect()
}

/// The subcommands a `--help` text lists under `Commands:`.
fn commands_listed(help: &str) -> BTreeSet<String> {
    help.lines()
        .skip_while(|l| l.trim() != "Commands:")
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .collect()
}

/// `linkdyn ARGS… --help`, remembered.
fn help(cache: &mut BTreeMap<Vec<String>, String>, args: &[&str]) -> String {
    let key: Vec<String> = args.iter().map(|s| s.to_string()).collect();
    cache
        .entry(key)
        .or_insert_with(|| {
            let mut with_help: Vec<&str> = args.to_vec();
            with_help.push("--help");
            let (code, stdout, stderr) = linkdyn(&with_help);
            assert_eq!(
                code,
                0,
                "linkdyn {} exited {code}: {stderr}",
                with_help.join(" ")
            );
            stdout
        })
        .clone()
}

/// Every problem with one document's command lines, as `file:line: …` messages.
fn problems(lines: &[CommandLine], cache: &mut BTreeMap<Vec<String>, String>) -> Vec<String> {
    let commands = commands_listed(&help(cache, &[]));
    assert!(
        commands.contains("run"),
        "`linkdyn --help` lists no `run` under Commands: the parser above is out of date"
    );
    let mut problems = Vec::new();
    for cl in lines {
        let Some(first) = cl.words.first() else {
            continue;
        };
        if first.starts_with(|c: char| c.is_ascii_uppercase()) || first.starts_with('-') {
            continue; // a placeholder (`linkdyn COMMAND --help`) or `linkdyn --version`
        }
        for command in first.split('|') {
            if !commands.contains(command) {
                problems.push(format!(
                    "{}:{}: `linkdyn {command}` is not a command (linkdyn --help lists: {})",
                    cl.file,
                    cl.line,
                    commands.iter().cloned().collect::<Vec<_>>().join(", ")
                ));
                continue;
            }
            // `plot` has kinds of its own, each with its options; a placeholder kind
            // (`linkdyn plot KIND …`) may use the options of any kind, and `linkdyn plot` alone
            // names the command.
            let mut targets: Vec<(String, BTreeSet<String>)> = Vec::new();
            let mut from = 1;
            if command == "plot" {
                let plot_kinds = commands_listed(&help(cache, &["plot"]));
                let kinds = cl.words.get(1).map_or("", String::as_str);
                from = 2.min(cl.words.len());
                if kinds.starts_with(|c: char| c.is_ascii_uppercase()) {
                    let mut any = BTreeSet::new();
                    for kind in plot_kinds.iter().filter(|k| *k != "help") {
                        any.extend(options_listed(&help(cache, &["plot", kind])));
                    }
                    targets.push(("plot KIND".to_string(), any));
                }
                for kind in kinds
                    .split('|')
                    .filter(|k| !k.is_empty() && !k.starts_with(|c: char| c.is_ascii_uppercase()))
                {
                    if plot_kinds.contains(kind) {
                        targets.push((
                            format!("plot {kind}"),
                            options_listed(&help(cache, &["plot", kind])),
                        ));
                    } else {
                        problems.push(format!(
                            "{}:{}: `linkdyn plot {kind}` is not a plot kind (linkdyn plot --help lists: {})",
                            cl.file,
                            cl.line,
                            plot_kinds.iter().cloned().collect::<Vec<_>>().join(", ")
                        ));
                    }
                }
            } else {
                targets.push((
                    command.to_string(),
                    options_listed(&help(cache, &[command])),
                ));
            }
            for (label, listed) in targets {
                for (line, option) in options_used(&cl.words[from..], &cl.word_lines[from..]) {
                    if !listed.contains(&option) {
                        problems.push(format!(
                            "{}:{line}: `linkdyn {label}` has no option `{option}` (its --help lists: {})",
                            cl.file,
                            listed.iter().cloned().collect::<Vec<_>>().join(" ")
                        ));
                    }
                }
            }
        }
    }
    problems
}

fn read(file: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn every_documented_command_line_matches_the_binary() {
    let mut cache = BTreeMap::new();
    let mut all = Vec::new();
    for file in FILES {
        let lines = command_lines(file, &read(file));
        // Each file holds command lines; none found means the parser no longer sees them.
        assert!(
            !lines.is_empty() || *file == "docs/python.md",
            "{file}: no `linkdyn` command line found"
        );
        all.extend(problems(&lines, &mut cache));
    }
    assert!(
        all.is_empty(),
        "{} command line(s) in the docs disagree with the binary:\n{}",
        all.len(),
        all.join("\n")
    );
}

#[test]
fn the_usage_guide_has_a_synopsis_for_every_command() {
    let mut cache = BTreeMap::new();
    let commands = commands_listed(&help(&mut cache, &[]));
    let lines = command_lines("docs/usage.md", &read("docs/usage.md"));
    let documented: BTreeSet<&str> = lines
        .iter()
        .filter_map(|cl| cl.words.first())
        .flat_map(|w| w.split('|'))
        .collect();
    let missing: Vec<&String> = commands
        .iter()
        .filter(|c| *c != "help" && !documented.contains(c.as_str()))
        .collect();
    assert!(
        missing.is_empty(),
        "docs/usage.md has no command line for: {missing:?}"
    );
}

#[test]
fn the_readme_stays_short() {
    let n = read("README.md").lines().count();
    assert!(
        n <= README_MAX_LINES,
        "README.md has {n} lines, more than {README_MAX_LINES}: move the detail into docs/ and link it"
    );
}

/// The checker itself: a misspelt option, an unknown command and an unknown plot kind are
/// each reported with the file and line; a correct synopsis over several lines is not.
#[test]
fn the_checker_finds_wrong_options_and_commands() {
    let doc = "intro\n\
               ```text\n\
               linkdyn run MODEL [--rtol X]\n\
               \x20                 [--methd radau5] --out F.csv\n\
               linkdyn runn MODEL\n\
               linkdyn plot orbit|orbits F.csv --joint B --out o.png\n\
               ```\n\
               ```sh\n\
               linkdyn check models/pendulum.toml \\\n\
               \x20   --set bodies.rod.mass=2   # a comment --not-an-option\n\
               ```\n\
               and inline `linkdyn compare m.toml --formulation dae` too\n";
    let lines = command_lines("t.md", doc);
    assert_eq!(lines.len(), 5, "command lines found: {lines:?}");
    let mut cache = BTreeMap::new();
    let found = problems(&lines, &mut cache);
    let expected = [
        "t.md:4: `linkdyn run` has no option `--methd`",
        "t.md:5: `linkdyn runn` is not a command",
        "t.md:6: `linkdyn plot orbits` is not a plot kind",
        "t.md:12: `linkdyn compare` has no option `--formulation`",
    ];
    for e in expected {
        assert!(
            found.iter().any(|p| p.starts_with(e)),
            "expected a problem starting {e:?}; found:\n{}",
            found.join("\n")
        );
    }
    assert_eq!(
        found.len(),
        expected.len(),
        "unexpected problems:\n{}",
        found.join("\n")
    );
}
