//! `linkdyn stress --quick` (docs/usage.md): every cell of the stress table gets one of the four
//! verdicts; the reference case (250 rpm, c = 0.5 mm) is ok on every formulation × method;
//! cases the model validation refuses carry its message; a run over its budget is "slow" with
//! the fraction of t_end it reached; the CSV has the provenance and one row per cell.

use linkdyn::solve::Method;
use linkdyn::studies::stress::{FOURBAR, cases};

mod cli_common;
use cli_common::{linkdyn, scratch};

/// The fields of one CSV line (RFC 4180 quoting).
fn split_csv(line: &str) -> Vec<String> {
    let mut fields = vec![String::new()];
    let (mut quoted, mut chars) = (false, line.chars().peekable());
    while let Some(c) = chars.next() {
        let last = fields.len() - 1;
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                chars.next();
                fields[last].push('"');
            }
            ('"', _) => quoted = !quoted,
            (',', false) => fields.push(String::new()),
            (c, _) => fields[last].push(c),
        }
    }
    fields
}

/// Header row, provenance lines (without `# `), and data rows as name → value maps.
struct Table {
    header: Vec<String>,
    provenance: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    fn read(path: &std::path::Path) -> Table {
        let text = std::fs::read_to_string(path)
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
        let mut lines = text.lines();
        let header = split_csv(lines.next().unwrap_or(""));
        let (mut provenance, mut rows) = (Vec::new(), Vec::new());
        for line in lines {
            match line.strip_prefix("# ") {
                Some(p) => provenance.push(p.to_string()),
                None => rows.push(split_csv(line)),
            }
        }
        Table {
            header,
            provenance,
            rows,
        }
    }

    fn get<'a>(&self, row: &'a [String], column: &str) -> &'a str {
        let k = self
            .header
            .iter()
            .position(|h| h == column)
            .unwrap_or_else(|| panic!("no column {column} in {:?}", self.header));
        row.get(k).map_or("", String::as_str)
    }
}

/// The two cases the model validation must refuse, and a piece of each message.
const REFUSED: [(&str, &str); 2] = [
    (
        "E*1000",
        "joints.B.youngs_modulus: expected a Young's modulus (Pa) in [1e6, 1.2e12]",
    ),
    (
        "e0=c (on the wall)",
        "joints.B.initial_eccentricity: initial eccentricity |e| = 5.000000e-4 m is not smaller than the clearance",
    ),
];

/// Rows expected in quick mode: one per refused case, else formulations × methods (rtol 1e-6).
fn expected_rows() -> usize {
    cases(true)
        .iter()
        .map(|c| {
            if REFUSED.iter().any(|(name, _)| *name == c.name) {
                1
            } else if c.model == FOURBAR {
                2 * Method::ALL.len()
            } else {
                Method::ALL.len()
            }
        })
        .sum()
}

#[test]
fn quick_table_has_a_verdict_per_cell_and_the_reference_is_ok() {
    let dir = scratch("quick");
    let out = dir.join("stress.csv");
    let (code, stdout, stderr) = linkdyn(&[
        "stress",
        "--quick",
        "--out",
        out.to_str().unwrap_or_default(),
    ]);
    assert_eq!(code, 0, "stress --quick exit code; stderr: {stderr}");
    let table = Table::read(&out);
    assert_eq!(
        table.rows.len(),
        expected_rows(),
        "one CSV row per cell (quick cases × formulations × methods, refused cases once)"
    );
    // The terminal table has the same cells.
    let summary = format!("{} cells:", expected_rows());
    assert!(
        stdout.contains(&summary),
        "missing {summary:?} in\n{stdout}"
    );
    // Provenance: version, both models with their hashes, the mode and the bounds.
    let prov = table.provenance.join("\n");
    for needle in [
        "linkdyn ",
        "model models/farahan2016.toml sha256 ",
        "model models/slider_crank_clearance.toml sha256 ",
        "mode = quick",
        "rtol = 1e-6",
        "bound energy_residual = ",
        "bound max_angle_difference = ",
    ] {
        assert!(
            prov.contains(needle),
            "provenance lacks {needle:?}:\n{prov}"
        );
    }
    for row in &table.rows {
        let verdict = table.get(row, "verdict");
        assert!(
            ["ok", "slow", "failed", "refused"].contains(&verdict),
            "case {} has verdict {verdict:?}",
            table.get(row, "case")
        );
    }
    // The reference four-bar is ok on every formulation × method: energy residual and angle
    // agreement within the stated bounds.
    let reference: Vec<&Vec<String>> = table
        .rows
        .iter()
        .filter(|r| table.get(r, "case") == "reference" && table.get(r, "model") == "farahan2016")
        .collect();
    assert_eq!(reference.len(), 2 * Method::ALL.len(), "reference cells");
    for r in &reference {
        assert_eq!(
            table.get(r, "verdict"),
            "ok",
            "reference case on {} {}: note {}",
            table.get(r, "formulation"),
            table.get(r, "method"),
            table.get(r, "note")
        );
    }
    // Refused cases carry the validation message.
    for (name, message) in REFUSED {
        let rows: Vec<&Vec<String>> = table
            .rows
            .iter()
            .filter(|r| table.get(r, "case") == name)
            .collect();
        assert_eq!(rows.len(), 1, "refused case {name} has one row");
        assert_eq!(table.get(rows[0], "verdict"), "refused", "case {name}");
        let note = table.get(rows[0], "note");
        assert!(
            note.contains(message),
            "case {name}: note {note:?} lacks {message:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_run_over_its_wall_budget_is_slow_with_the_fraction_reached() {
    // 1 µs cannot cover one 2-turn run (the quickest takes ~10 ms): every run that starts
    // must stop on its first check of the clock, before t_end.
    let dir = scratch("budget");
    let out = dir.join("stress.csv");
    let (code, _, stderr) = linkdyn(&[
        "stress",
        "--quick",
        "--max-wall-per-run",
        "1e-6",
        "--out",
        out.to_str().unwrap_or_default(),
    ]);
    assert_eq!(code, 0, "exit code; stderr: {stderr}");
    let table = Table::read(&out);
    for row in &table.rows {
        let (case, verdict) = (table.get(row, "case"), table.get(row, "verdict"));
        if REFUSED.iter().any(|(name, _)| *name == case) {
            assert_eq!(verdict, "refused", "case {case}");
            continue;
        }
        assert_eq!(verdict, "slow", "case {case} with a 1 µs budget");
        let note = table.get(row, "note");
        let reached = note
            .strip_prefix("reached ")
            .and_then(|s| s.split(" %").next())
            .and_then(|s| s.parse::<f64>().ok())
            .unwrap_or_else(|| panic!("case {case}: no fraction reached in {note:?}"));
        assert!(
            (0.0..100.0).contains(&reached),
            "case {case}: reached {reached} % of t_end with a 1 µs budget"
        );
        assert!(
            note.contains("wall-clock budget") && note.contains("max_wall = 0.000001 s"),
            "case {case}: note {note:?} names neither the budget nor the limit"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_bad_budget_is_refused_before_any_run() {
    let (code, stdout, stderr) = linkdyn(&["stress", "--quick", "--max-wall-per-run", "0"]);
    assert_eq!(code, 2, "exit code; stdout: {stdout}");
    assert!(
        stderr.contains("--max-wall-per-run: expected a positive number of seconds, got 0"),
        "{stderr}"
    );
}

/// Without its models (run from another folder, or a wrong `--models`), `stress` refuses
/// before any work, naming the folder, instead of reporting every cell as refused with exit 0.
#[test]
fn stress_without_its_models_is_refused() {
    let dir = scratch("no-models");
    let empty = dir.display().to_string();
    let (code, stdout, stderr) = linkdyn(&["stress", "--quick", "--models", &empty]);
    assert_eq!(code, 2, "{stdout}{stderr}");
    assert!(stdout.is_empty(), "no table: {stdout}");
    assert_eq!(
        stderr,
        format!(
            "error: --models: expected the folder of the shipped models, with farahan2016.toml; {empty} has none (run from the repository root, or give the folder that holds them)\n"
        )
    );
}
