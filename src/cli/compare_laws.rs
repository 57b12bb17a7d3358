//! `linkdyn compare-laws MODEL --joint B --laws a,b,c [--out F.csv]`: the same scene once per
//! contact law of one clearance joint ([`linkdyn::studies::contact_laws`]), printed as a table
//! and optionally written whole as a CSV with provenance.

use super::args::SolveArgs;
use super::{Failure, csv_field};
use clap::Args;
use linkdyn::output::{self, AtomicFile, format_number};
use linkdyn::simulation::FormulationKind;
use linkdyn::studies::contact_laws::{LawRun, compare_contact_laws};
use std::path::PathBuf;

/// Arguments of `compare-laws`.
#[derive(Debug, Args)]
pub struct CompareLawsArgs {
    /// Model file (TOML) with one driver and the clearance joint.
    model: PathBuf,
    /// The clearance joint whose contact law changes.
    #[arg(long)]
    joint: String,
    /// Contact laws, comma-separated, as in the model file; a line-contact law may name its
    /// damping after a colon: `lankarani-nikravesh,johnson,johnson:flores,liu`. The first is the
    /// reference of the torque difference. A line law needs the joint's `length` (e.g.
    /// `--set joints.B.length=0.02`).
    #[arg(long, value_delimiter = ',', required = true)]
    laws: Vec<String>,
    /// Equations of motion: `dae`, `reduced` or `generalized`.
    #[arg(long, value_parser = super::run::parse_formulation, default_value = "dae")]
    formulation: FormulationKind,
    #[command(flatten)]
    solve: SolveArgs,
    /// Write the table as CSV here (whole, after every run has finished).
    #[arg(long)]
    out: Option<PathBuf>,
}

const HEADER: [&str; 8] = [
    "law",
    "impacts",
    "peak_normal_force_N",
    "max_penetration_m",
    "torque_rms_difference_Nm",
    "torque_rms_Nm",
    "rhs_evals",
    "wall_s",
];

fn fields(r: &LawRun, exact: bool) -> [String; 8] {
    let num = |x: f64| {
        if exact {
            format_number(x)
        } else {
            format!("{x:.4e}")
        }
    };
    [
        r.law.clone(),
        r.impacts.to_string(),
        num(r.peak_normal_force),
        num(r.max_penetration),
        num(r.torque_rms_difference),
        num(r.torque_rms),
        r.rhs_evals.to_string(),
        if exact {
            format_number(r.wall_time_s)
        } else {
            format!("{:.3}", r.wall_time_s)
        },
    ]
}

/// Runs `compare-laws`.
pub fn run(args: &CompareLawsArgs) -> Result<(), Failure> {
    let options = args.solve.options()?.formulation(args.formulation);
    if let Some(path) = &args.out {
        output::check_output_file(path, Some(&args.model))?;
    }
    if !args.solve.ideal.is_empty() {
        return Err(linkdyn::Error::settings(
            "ideal",
            "compare-laws changes the law of a clearance joint; --ideal does not apply",
        )
        .into());
    }
    let result = compare_contact_laws(
        &args.model,
        &args.solve.set,
        &args.joint,
        &args.laws,
        &options,
    )
    .map_err(|e| super::in_model(&args.model, e))?;
    println!(
        "{}: joint {}, {} law(s), torque of driver {} against the first law's",
        args.model.display(),
        result.joint,
        result.runs.len(),
        result.driver
    );
    let widths = [28, 8, 20, 18, 25, 14, 10, 0];
    let print = |row: &[String]| {
        let mut line = String::new();
        for (w, f) in widths.iter().zip(row) {
            line.push_str(&format!("{f:<w$}  "));
        }
        println!("{}", line.trim_end());
    };
    print(&HEADER.map(String::from));
    for r in &result.runs {
        print(&fields(r, false));
    }
    if let Some(path) = &args.out {
        let mut text = HEADER.join(",");
        text.push('\n');
        for line in result.provenance.lines() {
            text.push_str("# ");
            text.push_str(&line);
            text.push('\n');
        }
        text.push_str(&format!(
            "# joint = {}\n# laws = {}\n",
            result.joint,
            args.laws.join(" ")
        ));
        for r in &result.runs {
            let row: Vec<String> = fields(r, true).iter().map(|f| csv_field(f)).collect();
            text.push_str(&row.join(","));
            text.push('\n');
        }
        let mut file = AtomicFile::create(path)?;
        file.write_str(&text)?;
        file.commit()?;
    }
    Ok(())
}
