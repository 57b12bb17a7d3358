//! `linkdyn workprecision` (docs/numerics.md) on a cheap case, the ideal four-bar over one crank turn:
//! the errors against the confirmed reference fall as the tolerance tightens, the reference is
//! better than every cell it judges, a formulation that does not take the model gives failed
//! cells with the reason (the table goes on), and the command writes the CSV, the markdown table
//! and both figures whole.

use linkdyn::simulation::{EndTime, FormulationKind};
use linkdyn::solve::Method;
use linkdyn::studies::workprecision::{
    CSV_HEADER, WorkPrecisionOptions, WorkPrecisionReport, run_workprecision,
};

mod cli_common;
use cli_common::{linkdyn, scratch};

const MODEL: &str = "models/fourbar_ideal.toml";
/// Why the reduced formulation refuses the ideal four-bar.
const REFUSAL: &str = "needs exactly one clearance joint";

fn table() -> WorkPrecisionReport {
    let model = linkdyn::model::load(MODEL.as_ref(), &[]).unwrap_or_else(|e| panic!("{e}"));
    let options = WorkPrecisionOptions {
        formulations: vec![FormulationKind::Dae, FormulationKind::Reduced],
        methods: Method::ALL.to_vec(),
        rtols: vec![1e-5, 1e-8],
        end: EndTime::DriverTurns(1.0),
        samples: 400,
        repeats: 1,
        ..WorkPrecisionOptions::default()
    };
    run_workprecision(&model, &options, |_| {}).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn errors_fall_with_the_tolerance_and_a_refused_formulation_is_a_failed_cell() {
    let report = table();
    assert_eq!(
        report.cells.len(),
        2 * 3 * 2,
        "formulations × methods × rtols"
    );
    let reference = report
        .reference(FormulationKind::Dae)
        .unwrap_or_else(|| panic!("no DAE reference"));
    assert_eq!(reference.rtol, 1e-10, "1/100 of the tightest rtol 1e-8");
    let own = reference
        .own_error
        .as_ref()
        .unwrap_or_else(|| panic!("DAE reference not confirmed: {:?}", reference.failure));
    for method in Method::ALL {
        let cell = |rtol: f64| {
            report
                .cells
                .iter()
                .find(|c| {
                    c.formulation == FormulationKind::Dae && c.method == method && c.rtol == rtol
                })
                .unwrap_or_else(|| panic!("no cell dae {method} {rtol:e}"))
        };
        let angle = |rtol: f64| {
            let c = cell(rtol);
            let e = c
                .errors
                .as_ref()
                .unwrap_or_else(|| panic!("dae {method} {rtol:e} has no errors: {:?}", c.failure));
            // The ideal four-bar has no clearance joint: nothing to pair, nothing to miss.
            assert!(
                e.impacts == 0 && e.impacts_match && e.orbit.is_none() && e.peak_force.is_none(),
                "dae {method} {rtol:e}: {e:?}"
            );
            e.angle
        };
        let (loose, tight) = (angle(1e-5), angle(1e-8));
        // Three decades of tolerance: a method of order p under tolerance-proportional control
        // has a global error ∝ rtol^(p/(p+1)) (≥ 500× for p ≥ 5); Radau5 works with Hairer's
        // rtol' = 0.1·rtol^(2/3), i.e. error ∝ rtol^(2/3 · 5/6) ≈ 50×. A factor 10 keeps a
        // margin of 5 below the weakest of them.
        assert!(
            tight < loose / 10.0,
            "dae {method}: angle error {tight:e} rad at rtol 1e-8 vs {loose:e} rad at 1e-5"
        );
        // A reference must be better than what it judges: its own error (DOP853 against DOPRI5
        // at 1e-10) below the tightest cell's error.
        assert!(
            own.angle < tight,
            "dae {method}: reference own error {:e} rad vs the rtol 1e-8 cell's {tight:e} rad",
            own.angle
        );
    }
    for c in report
        .cells
        .iter()
        .filter(|c| c.formulation == FormulationKind::Reduced)
    {
        let failure = c.failure.as_deref().unwrap_or("");
        assert!(
            failure.contains(REFUSAL) && c.cost.is_none() && c.errors.is_none(),
            "reduced {} {:e}: failure {failure:?}",
            c.method,
            c.rtol
        );
    }
}

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

#[test]
fn the_command_writes_csv_markdown_and_figures_whole() {
    // A folder the command creates itself.
    let dir = scratch("command").join("wp");
    let out = dir.to_string_lossy().into_owned();
    let (code, stdout, stderr) = linkdyn(&[
        "workprecision",
        MODEL,
        "--revs",
        "1",
        "--rtols",
        "1e-5,1e-7",
        "--methods",
        "dopri5,dop853",
        "--formulations",
        "dae,reduced",
        "--repeats",
        "1",
        "--samples",
        "300",
        "--out",
        &out,
    ]);
    assert_eq!(code, 0, "exit code; stdout {stdout}\nstderr {stderr}");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{out}: {e}"))
        .filter_map(|e| e.ok().map(|e| e.file_name().to_string_lossy().into_owned()))
        .collect();
    names.sort();
    // No temporary or lock file left behind: the four results and nothing else.
    assert_eq!(
        names,
        [
            "workprecision.csv",
            "workprecision.md",
            "workprecision.png",
            "workprecision.svg"
        ],
        "files in {out}"
    );
    let read = |name: &str| std::fs::read(dir.join(name)).unwrap_or_default();
    let csv = String::from_utf8(read("workprecision.csv")).unwrap_or_default();
    assert!(csv.ends_with('\n'), "CSV ends with a whole line");
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some(CSV_HEADER.join(",").as_str()),
        "header first"
    );
    let (comments, rows): (Vec<&str>, Vec<&str>) = lines.partition(|l| l.starts_with('#'));
    assert!(
        comments
            .iter()
            .any(|l| l.starts_with("# model models/fourbar_ideal.toml sha256 "))
            && comments
                .iter()
                .any(|l| l.starts_with("# reference dae: dop853 rtol 1e-9")),
        "provenance lines: {comments:?}"
    );
    assert_eq!(
        rows.len(),
        2 * 2 * 2,
        "one row per formulation × method × rtol"
    );
    for row in &rows {
        let f = split_csv(row);
        assert_eq!(f.len(), CSV_HEADER.len(), "fields of {row}");
        let ok = f[0] == "dae";
        assert_eq!(f[4], if ok { "ok" } else { "failed" }, "status of {row}");
        assert!(ok || f[17].contains(REFUSAL), "failure reason in {row}");
        assert!(
            !ok || f[10].parse::<f64>().is_ok_and(|e| e > 0.0),
            "angle error of {row}"
        );
    }
    let md = String::from_utf8(read("workprecision.md")).unwrap_or_default();
    assert!(
        md.contains("| dae | dop853 | 1e-7 | ok |")
            && md.contains("| reduced | dopri5 | 1e-5 | failed |"),
        "markdown rows:\n{md}"
    );
    assert!(
        read("workprecision.png").starts_with(b"\x89PNG\r\n\x1a\n"),
        "PNG signature"
    );
    let svg = String::from_utf8(read("workprecision.svg")).unwrap_or_default();
    assert!(
        svg.contains("<svg") && svg.trim_end().ends_with("</svg>"),
        "SVG whole"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
