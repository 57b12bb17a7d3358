//! `linkdyn stress [--quick] [--out F.csv]`: the stress table of
//! [`linkdyn::studies::stress`] — extreme cases × formulations × methods × tolerances, a
//! verdict each — printed as aligned columns and optionally written as a CSV with provenance.

use super::{Failure, csv_field};
use clap::Args;
use linkdyn::Error;
use linkdyn::output::{self, AtomicFile, Provenance, format_number};
use linkdyn::simulation::escape_line;
use linkdyn::studies::stress::{
    FOURBAR, SLIDER_CRANK, StressCell, StressOptions, StressReport, run_stress,
};
use std::path::PathBuf;

/// Arguments of `stress`.
#[derive(Debug, Args)]
pub struct StressArgs {
    /// The quick subset for CI: one case per axis, rtol 1e-6, 2-turn runs, 4 s per run.
    #[arg(long)]
    quick: bool,
    /// Directory holding farahan2016.toml, slider_crank_clearance.toml and
    /// slider_crank_prismatic_clearance.toml.
    #[arg(long, default_value = "models")]
    models: PathBuf,
    /// Wall-clock budget of each run (s); default 4 (quick) or 60 (full).
    #[arg(long, value_name = "SECONDS")]
    max_wall_per_run: Option<f64>,
    /// Step-attempt budget of each run; default 10⁶ (quick) or 2·10⁷ (full).
    #[arg(long, value_name = "STEPS")]
    max_steps_per_run: Option<u64>,
    /// Write the table as CSV here (with `#` provenance lines).
    #[arg(long)]
    out: Option<PathBuf>,
}

const HEADER: [&str; 12] = [
    "case",
    "model",
    "formulation",
    "method",
    "rtol",
    "verdict",
    "wall_s",
    "rhs_evals",
    "impacts",
    "energy_residual",
    "max_angle_difference",
    "note",
];

fn opt<T>(v: Option<T>, f: impl Fn(T) -> String) -> String {
    v.map_or("-".to_string(), f)
}

/// The fields of a cell as text, in [`HEADER`] order (numbers exact for the CSV when `exact`).
fn fields(c: &StressCell, exact: bool) -> [String; 12] {
    let num = |x: f64| {
        if exact {
            format_number(x)
        } else {
            format!("{x:.2e}")
        }
    };
    let mut note = c.note.clone();
    if let (Some(f), linkdyn::studies::stress::Verdict::Slow) = (c.fraction_reached, c.verdict) {
        note = format!("reached {:.1} %: {note}", 100.0 * f);
    }
    [
        c.case.clone(),
        c.model.trim_end_matches(".toml").to_string(),
        opt(c.formulation, |f| f.to_string()),
        opt(c.method, |m| m.to_string()),
        opt(c.rtol, |r| format!("{r:e}")),
        c.verdict.to_string(),
        if exact {
            format_number(c.wall_s)
        } else {
            format!("{:.2}", c.wall_s)
        },
        opt(c.rhs_evals, |n| n.to_string()),
        opt(c.impacts, |n| n.to_string()),
        opt(c.energy_residual, num),
        opt(c.max_angle_difference, num),
        note,
    ]
}

fn print_row(widths: &[usize], row: &[String]) {
    let mut line = String::new();
    for (k, (w, f)) in widths.iter().zip(row).enumerate() {
        if k + 1 == row.len() {
            line.push_str(f);
        } else {
            line.push_str(&format!("{f:<w$}  "));
        }
    }
    println!("{}", line.trim_end());
}

/// The provenance lines of the CSV: per model its file and hash, then the settings.
fn provenance_lines(report: &StressReport) -> Vec<String> {
    let o = &report.options;
    let mut lines = vec![format!("linkdyn {}", escape_line(&linkdyn::version()))];
    for m in &report.models {
        let p = Provenance {
            linkdyn_version: String::new(),
            model: m.clone(),
            settings: Default::default(),
        };
        lines.extend(p.lines().into_iter().skip(1));
    }
    let rtols: Vec<String> = o.rtols.iter().map(|r| format_number(*r)).collect();
    lines.push(format!("mode = {}", if o.quick { "quick" } else { "full" }));
    lines.push(format!("rtol = {}", rtols.join(" ")));
    lines.push("atol = 1e-3 rtol".to_string());
    lines.push(format!(
        "max_wall_per_run = {}",
        format_number(o.max_wall_per_run)
    ));
    lines.push(format!("max_steps_per_run = {}", o.max_steps_per_run));
    lines.push(format!(
        "samples_per_turn = {}",
        format_number(o.samples_per_turn)
    ));
    lines.push(format!(
        "bound energy_residual = {}",
        format_number(o.bounds.energy_residual)
    ));
    lines.push(format!(
        "bound max_angle_difference = {} rtol rad over the first {} turns",
        format_number(o.bounds.angle_per_rtol),
        format_number(o.bounds.compare_turns)
    ));
    lines
}

/// Runs `stress`.
pub fn run(args: &StressArgs) -> Result<(), Failure> {
    let mut options = if args.quick {
        StressOptions::quick(&args.models)
    } else {
        StressOptions::full(&args.models)
    };
    if let Some(w) = args.max_wall_per_run {
        if !(w.is_finite() && w > 0.0) {
            return Err(Error::settings(
                "max_wall_per_run",
                format!("expected a positive number of seconds, got {w}"),
            )
            .into());
        }
        options.max_wall_per_run = w;
    }
    if let Some(n) = args.max_steps_per_run {
        if n == 0 {
            return Err(Error::settings("max_steps_per_run", "expected at least 1, got 0").into());
        }
        options.max_steps_per_run = n;
    }
    if let Some(path) = &args.out {
        output::check_output_file(path, None)?;
    }
    // Every cell would be refused for want of its model: say so once, before any work.
    for file in [FOURBAR, SLIDER_CRANK] {
        if !args.models.join(file).is_file() {
            return Err(Error::settings(
                "models",
                format!(
                    "expected the folder of the shipped models, with {file}; {} has none (run from the repository root, or give the folder that holds them)",
                    args.models.display()
                ),
            )
            .into());
        }
    }
    let widths = [22, 24, 11, 7, 6, 8, 7, 9, 7, 15, 20, 0];
    print_row(&widths, &HEADER.map(String::from));
    let report = run_stress(&options, |_, cells| {
        for c in cells {
            print_row(&widths, &fields(c, false));
        }
    });
    let count = |v| report.cells.iter().filter(|c| c.verdict == v).count();
    let verdicts = linkdyn::studies::stress::Verdict::ALL.map(|v| format!("{} {v}", count(v)));
    println!("{} cells: {}", report.cells.len(), verdicts.join(", "));
    if let Some(path) = &args.out {
        let mut text = HEADER.join(",");
        text.push('\n');
        for line in provenance_lines(&report) {
            text.push_str("# ");
            text.push_str(&line);
            text.push('\n');
        }
        for c in &report.cells {
            let row: Vec<String> = fields(c, true).iter().map(|f| csv_field(f)).collect();
            text.push_str(&row.join(","));
            text.push('\n');
        }
        let mut file = AtomicFile::create(path)?;
        file.write_str(&text)?;
        file.commit()?;
    }
    Ok(())
}
