//! `linkdyn workprecision MODEL [--revs N] [--formulations …] [--methods …] [--rtols …]
//! [--repeats K] --out DIR`: the work–precision table of
//! [`linkdyn::studies::workprecision`] — every formulation × method × tolerance, its error
//! against a confirmed reference and its cost — printed as it runs and written as
//! `DIR/workprecision.csv`, `.md`, `.png` and `.svg`.

use super::Failure;
use clap::Args;
use linkdyn::Error;
use linkdyn::output::{self, AtomicFile};
use linkdyn::simulation::{EndTime, FormulationKind};
use linkdyn::solve::{Method, SolveError};
use linkdyn::studies::workprecision::{
    Progress, WorkPrecisionOptions, csv_text, markdown_text, run_workprecision,
};
use std::path::{Path, PathBuf};

/// Arguments of `workprecision`.
#[derive(Debug, Args)]
pub struct WorkPrecisionArgs {
    /// Model file (TOML).
    model: PathBuf,
    /// Turns of the (single) driver per run; default 2.
    #[arg(long, conflicts_with = "t_end", allow_negative_numbers = true)]
    revs: Option<f64>,
    /// End time of every run (s), instead of --revs.
    #[arg(long, allow_negative_numbers = true)]
    t_end: Option<f64>,
    /// Formulations, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "dae,reduced")]
    formulations: Vec<String>,
    /// Methods, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "dopri5,dop853,radau5")]
    methods: Vec<String>,
    /// Relative tolerances, comma-separated (atol = --atol-per-rtol × rtol).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10",
        allow_negative_numbers = true
    )]
    rtols: Vec<f64>,
    /// atol = this × rtol.
    #[arg(long, default_value_t = 1e-3, allow_negative_numbers = true)]
    atol_per_rtol: f64,
    /// Timed runs per cell (the median is reported).
    #[arg(long, default_value_t = 3)]
    repeats: usize,
    /// Samples of the common output grid over a run.
    #[arg(long, default_value_t = 4000)]
    samples: usize,
    /// Wall-clock budget of each run (s); a run over it is a failed cell.
    #[arg(
        long,
        value_name = "SECONDS",
        default_value_t = 60.0,
        allow_negative_numbers = true
    )]
    max_wall_per_run: f64,
    /// Reference method (the most accurate).
    #[arg(long, default_value = "dop853")]
    reference_method: String,
    /// Method that confirms the reference.
    #[arg(long, default_value = "dopri5")]
    confirm_method: String,
    /// Reference tolerance; default 1/100 of the tightest --rtols, not below 1e-13.
    #[arg(long, allow_negative_numbers = true)]
    reference_rtol: Option<f64>,
    /// Override a model field (repeatable), e.g. `--set drivers.motor.speed_rpm=3500`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Run this clearance joint as its ideal joint, revolute or prismatic (repeatable).
    #[arg(long, value_name = "JOINT")]
    ideal: Vec<String>,
    /// Output directory (created if missing) for workprecision.csv, .md, .png and .svg.
    #[arg(long)]
    out: PathBuf,
}

fn method(option: &'static str, name: &str) -> Result<Method, Failure> {
    name.parse().map_err(|e| {
        let reason = match e {
            SolveError::InvalidOption { reason, .. } => reason,
            other => other.to_string(),
        };
        Failure::from(Error::Settings { option, reason })
    })
}

fn options(args: &WorkPrecisionArgs) -> Result<WorkPrecisionOptions, Failure> {
    let formulations = args
        .formulations
        .iter()
        .map(|s| s.parse::<FormulationKind>())
        .collect::<Result<Vec<_>, _>>()?;
    let methods = args
        .methods
        .iter()
        .map(|s| method("methods", s))
        .collect::<Result<Vec<_>, _>>()?;
    let end = match (args.t_end, args.revs) {
        (Some(t), _) => EndTime::Seconds(t),
        (None, r) => EndTime::DriverTurns(r.unwrap_or(2.0)),
    };
    Ok(WorkPrecisionOptions {
        formulations,
        methods,
        rtols: args.rtols.clone(),
        atol_per_rtol: args.atol_per_rtol,
        end,
        samples: args.samples,
        repeats: args.repeats,
        max_wall_per_run: args.max_wall_per_run,
        reference_method: method("reference_method", &args.reference_method)?,
        confirm_method: method("confirm_method", &args.confirm_method)?,
        reference_rtol: args.reference_rtol,
    })
}

/// The four result files in `dir`.
fn targets(dir: &Path) -> [PathBuf; 4] {
    ["csv", "md", "png", "svg"].map(|ext| dir.join(format!("workprecision.{ext}")))
}

fn short(v: Option<f64>) -> String {
    v.map_or("-".to_string(), |x| format!("{x:.2e}"))
}

/// Runs `workprecision`.
pub fn run(args: &WorkPrecisionArgs) -> Result<(), Failure> {
    let model = super::load_model(&args.model, &args.set, &args.ideal)?;
    let options = options(args)?;
    options.validate()?;
    if args.out.exists() && !args.out.is_dir() {
        return Err(Error::from(linkdyn::output::OutputError::Target {
            path: args.out.display().to_string(),
            reason: "is not a directory".into(),
        })
        .into());
    }
    std::fs::create_dir_all(&args.out).map_err(|e| {
        Failure::from(Error::from(linkdyn::output::OutputError::Io {
            path: args.out.display().to_string(),
            reason: e.to_string(),
        }))
    })?;
    let files = targets(&args.out);
    for f in &files {
        output::check_output_file(f, Some(&args.model))?;
    }
    println!(
        "{:<8} {:<7} {:>7}  {:>9} {:>9} {:>10} {:>10} {:>8}  note",
        "form.", "method", "rtol", "wall_ms", "rhs", "angle_rad", "orbit_m", "impacts"
    );
    let report = run_workprecision(&model, &options, |p| match p {
        Progress::Reference(r) => println!(
            "reference {}: {} rtol {:e}, confirmed by {}: own angle error {} rad{}",
            r.formulation,
            r.method,
            r.rtol,
            r.confirm_method,
            short(r.own_error.as_ref().map(|e| e.angle)),
            r.failure
                .as_ref()
                .map_or(String::new(), |f| format!(" (failed: {f})"))
        ),
        Progress::Cell(c) => {
            let cost = c.cost.as_ref();
            let e = c.errors.as_ref();
            println!(
                "{:<8} {:<7} {:>7.0e}  {:>9} {:>9} {:>10} {:>10} {:>8}  {}",
                c.formulation.to_string(),
                c.method.to_string(),
                c.rtol,
                cost.map_or("-".into(), |k| format!("{:.2}", 1e3 * k.wall_s)),
                cost.map_or("-".into(), |k| k.stats.rhs_evals.to_string()),
                short(e.map(|e| e.angle)),
                short(e.and_then(|e| e.orbit)),
                e.map_or("-".into(), |e| e.impacts.to_string()),
                c.failure.as_deref().unwrap_or(&c.note)
            );
        }
    })
    .map_err(|e| super::in_model(&args.model, e))?;
    let [csv, md, png, svg] = &files;
    for (path, text) in [(csv, csv_text(&report)), (md, markdown_text(&report))] {
        let mut file = AtomicFile::create(path)?;
        file.write_str(&text)?;
        file.commit()?;
    }
    match linkdyn::plot::workprecision::workprecision(&report) {
        Ok(fig) => {
            linkdyn::plot::render(&fig, png)?;
            linkdyn::plot::render(&fig, svg)?;
        }
        // No finished cell with an error: the tables say why; there is nothing to draw.
        Err(e) => eprintln!("note: no figure drawn: {e}"),
    }
    let failed = report.cells.iter().filter(|c| c.failure.is_some()).count();
    println!(
        "{} cells ({failed} failed) to {}",
        report.cells.len(),
        args.out.display()
    );
    Ok(())
}
