//! `linkdyn poincare MODEL --revs N --transient M [--phase RAD] [--observe COLS] --out F.csv`:
//! the state or chosen output columns once per driver turn, CSV `turn,t,<cols>`, and the
//! period verdict. Also the pieces the other analysis commands share: the model and solve
//! arguments, and the atomic CSV with its header row, then `#` provenance lines.

use super::args::SolveArgs;
use super::{Failure, in_model};
use clap::Args;
use linkdyn::Error;
use linkdyn::output::{AtomicFile, OutputLock, Provenance, check_output_file, format_number};
use linkdyn::simulation::analyses::{self, SectionSpec};
use linkdyn::simulation::{EndTime, FormulationKind, Simulation, SimulationOptions};
use std::path::{Path, PathBuf};

/// The model, its overrides and the solve settings of every analysis command.
#[derive(Debug, Args)]
pub struct ModelArgs {
    /// Model file (TOML).
    pub model: PathBuf,
    #[command(flatten)]
    pub solve: SolveArgs,
    /// Equations of motion: `dae`, `reduced` (the four-bar with one clearance joint) or
    /// `generalized`.
    #[arg(long, value_parser = super::run::parse_formulation, default_value = "dae")]
    pub formulation: FormulationKind,
}

impl ModelArgs {
    /// The simulation options of these arguments (formulation included).
    pub fn options(&self) -> Result<SimulationOptions, Failure> {
        Ok(self.solve.options()?.formulation(self.formulation))
    }

    /// Loads the model with its overrides and builds the simulation, integrating `turns`
    /// driver turns.
    pub fn simulation(&self, turns: f64) -> Result<Simulation, Failure> {
        let model = super::load_model(&self.model, &self.solve.set, &self.solve.ideal)?;
        let options = SimulationOptions {
            end: EndTime::DriverTurns(turns),
            ..self.options()?
        };
        Simulation::new(&model, options).map_err(|e| in_model(&self.model, e))
    }

    /// The analyses count driver turns: `--t-end` is refused.
    pub fn no_t_end(&self) -> Result<(), Failure> {
        match self.solve.t_end {
            Some(_) => Err(bad(
                "t_end",
                "the analyses count driver turns: give `revs` instead",
            )),
            None => Ok(()),
        }
    }

    /// Driver turns: `--revs` as a whole number ≥ 1 (default `default`).
    pub fn whole_turns(&self, default: usize) -> Result<usize, Failure> {
        self.no_t_end()?;
        match self.solve.revs {
            None => Ok(default),
            Some(r) if r.is_finite() && r >= 1.0 && r.fract() == 0.0 && r < 1e9 => Ok(r as usize),
            Some(r) => Err(bad(
                "revs",
                format!("expected a whole number of turns ≥ 1, got {r}"),
            )),
        }
    }
}

/// A bad-input failure naming the option.
pub fn bad(option: &'static str, reason: impl Into<String>) -> Failure {
    Failure::from(Error::settings(option, reason))
}

/// The head of an analysis CSV: the header row `header` first (as in the run CSV, see
/// `output::csv_header`), then the `#` provenance lines with `extra` settings added, so that
/// `np.genfromtxt(f, delimiter=",", names=True, comments="#")` reads the file in one call.
pub fn csv_head(header: &str, provenance: Provenance, extra: &[(&str, String)]) -> String {
    format!("{header}\n{}", provenance_lines(provenance, extra))
}

/// `#` provenance lines of `provenance` with `extra` settings added.
pub fn provenance_lines(mut provenance: Provenance, extra: &[(&str, String)]) -> String {
    for (k, v) in extra {
        provenance.settings.insert((*k).to_string(), v.clone());
    }
    let mut head = String::new();
    for line in provenance.lines() {
        head.push_str("# ");
        head.push_str(&line);
        head.push('\n');
    }
    head
}

/// Writes `text` to `out` whole or not at all (temporary file, then rename; under the output
/// lock), refusing to overwrite the model file.
pub fn write_whole(out: &Path, model: &Path, text: &str) -> Result<(), Failure> {
    check_output_file(out, Some(model))?;
    let _lock = OutputLock::acquire(out)?;
    let mut file = AtomicFile::create(out)?;
    file.write_str(text)?;
    file.commit()?;
    Ok(())
}

/// A CSV row of numbers.
pub fn row(values: impl IntoIterator<Item = f64>) -> String {
    let mut line = String::new();
    for (k, v) in values.into_iter().enumerate() {
        if k > 0 {
            line.push(',');
        }
        line.push_str(&format_number(v));
    }
    line.push('\n');
    line
}

/// Output column names from `--observe a,b,c` (repeatable).
pub fn columns(observe: &[String]) -> Vec<String> {
    observe
        .iter()
        .flat_map(|o| o.split(','))
        .map(|c| c.trim().to_string())
        .filter(|c| !c.is_empty())
        .collect()
}

/// Arguments of `poincare`.
#[derive(Debug, Args)]
pub struct PoincareArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// Transient driver turns dropped before the first point.
    #[arg(long, default_value_t = 0)]
    transient: usize,
    /// Phase of the section within a driver turn (rad, in [0, 2π)).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    phase: f64,
    /// Output columns to record (comma-separated or repeated); default: each clearance joint's
    /// ex, ey and each body's phi, omega (angles modulo whole turns).
    #[arg(long)]
    observe: Vec<String>,
    /// Output CSV file: `turn,t,<cols>`.
    #[arg(long)]
    out: PathBuf,
}

/// Runs `poincare`.
pub fn run(args: &PoincareArgs) -> Result<(), Failure> {
    let turns = args.model.whole_turns(2)?;
    let sim = args.model.simulation(turns as f64)?;
    // Before any work: a result is not lost to a folder that does not exist.
    linkdyn::output::check_output_file(&args.out, Some(&args.model.model))?;
    let spec = SectionSpec {
        turns,
        transient: args.transient,
        phase: args.phase,
        observe: columns(&args.observe),
    };
    let s = analyses::poincare(&sim, &spec)?;
    let omega = analyses::driver_speed(sim.model(), "revs")?;
    let mut header = String::from("turn,t");
    for name in &s.section.names {
        header.push(',');
        header.push_str(name);
    }
    let mut text = csv_head(
        &header,
        sim.provenance(),
        &[
            ("transient_revs", args.transient.to_string()),
            ("phase_rad", format_number(args.phase)),
            (
                "driver_period",
                format_number(std::f64::consts::TAU / omega),
            ),
        ],
    );
    for ((k, t), p) in s.turns.iter().zip(&s.section.times).zip(&s.section.points) {
        text.push_str(&k.to_string());
        text.push(',');
        text.push_str(&row(std::iter::once(*t).chain(p.iter().copied())));
    }
    write_whole(&args.out, &args.model.model, &text)?;
    eprintln!(
        "{} points (turns {}..{}) to {}",
        s.turns.len(),
        args.transient,
        turns - 1,
        args.out.display()
    );
    print_verdict(&s);
    Ok(())
}

/// Prints the verdict, the tolerance it used and when the motion settled.
pub fn print_verdict(s: &analyses::ModelSection) {
    let tol: Vec<String> = s
        .section
        .names
        .iter()
        .zip(&s.tolerance)
        .map(|(n, t)| format!("{n} {t:.2e}"))
        .collect();
    println!("verdict: {}", s.period.verdict);
    println!(
        "period tolerance ({} x the integration tolerance carried to each column): {}",
        analyses::PERIOD_TOL_FACTOR,
        tol.join(", ")
    );
    if let Some(turn) = s.settled_at_turn {
        println!("settled: every point from turn {turn} on repeats within the tolerance");
    }
}
