//! `linkdyn orbit MODEL [--period-turns K | --period S] [--guess-from-turn N] --out F.json`:
//! a periodic orbit by shooting, its Floquet multipliers and stability; `F.json` (the result)
//! and `F.csv` (one period of the orbit, the run CSV's columns) appear together or not at all.

use super::args::SolveArgs;
use super::poincare::bad;
use super::{Failure, in_model};
use clap::Args;
use linkdyn::output::{ResultPair, csv_header, push_number};
use linkdyn::simulation::FormulationKind;
use linkdyn::studies::orbit::{OrbitPeriod, OrbitRequest, orbit};
use std::path::PathBuf;

/// Arguments of `orbit`.
#[derive(Debug, Args)]
pub struct OrbitArgs {
    /// Model file (TOML).
    model: PathBuf,
    #[command(flatten)]
    solve: SolveArgs,
    /// Equations of motion: `reduced` (the four-bar with one clearance joint) or `dae` (any
    /// linkage); not `generalized`.
    #[arg(long, default_value = "reduced", value_parser = super::run::parse_formulation)]
    formulation: FormulationKind,
    /// Period in turns of the model's single driver (default 1).
    #[arg(long, conflicts_with = "period", allow_negative_numbers = true)]
    period_turns: Option<usize>,
    /// Period in seconds (for a model without a single driver).
    #[arg(long, allow_negative_numbers = true)]
    period: Option<f64>,
    /// Periods integrated from the initial state before the shooting starts from where they
    /// end (the section).
    #[arg(long, default_value_t = 3)]
    guess_from_turn: usize,
    /// Result file (JSON); one period of the orbit goes beside it as `.csv`.
    #[arg(long)]
    out: PathBuf,
}

/// Runs `orbit`.
pub fn run(args: &OrbitArgs) -> Result<(), Failure> {
    if args.solve.t_end.is_some() || args.solve.revs.is_some() {
        return Err(bad(
            "revs",
            "an orbit lasts one period: give `period_turns` or `period` instead",
        ));
    }
    if args.out.extension().and_then(|e| e.to_str()) != Some("json") {
        return Err(bad(
            "out",
            format!(
                "expected a .json file (the orbit's CSV goes beside it), got {}",
                args.out.display()
            ),
        ));
    }
    let csv = args.out.with_extension("csv");
    let period = match (args.period_turns, args.period) {
        (_, Some(s)) => OrbitPeriod::Seconds(s),
        (Some(k), None) => OrbitPeriod::Turns(k),
        (None, None) => OrbitPeriod::Turns(1),
    };
    let model = super::load_model(&args.model, &args.solve.set, &args.solve.ideal)?;
    let request = OrbitRequest {
        options: args.solve.options()?.formulation(args.formulation),
        period,
        guess_from_turn: args.guess_from_turn,
        dt: args.solve.dt,
    };
    // Before any work: a result is not lost to a target that cannot be written.
    let mut pair = ResultPair::begin(&csv, Some(&args.model))?;
    for note in pair.notes() {
        eprintln!("note: {note}");
    }
    let result = orbit(&model, &request).map_err(|e| in_model(&args.model, e))?;
    let mut text = csv_header(&result.provenance, &result.names);
    for (t, row) in &result.samples {
        push_number(&mut text, *t);
        for v in row {
            text.push(',');
            push_number(&mut text, *v);
        }
        text.push('\n');
    }
    pair.csv().write_str(&text)?;
    pair.commit(&result)?;

    let history: Vec<String> = result
        .residual_history
        .iter()
        .map(|r| format!("{r:.2e}"))
        .collect();
    println!(
        "periodic orbit of period {:.9} s{} found in {} Newton iterations (residual in units of the integration tolerance: {})",
        result.period_s,
        result
            .period_turns
            .map_or(String::new(), |k| format!(" ({k} driver turns)")),
        result.newton_iterations,
        history.join(", ")
    );
    println!(
        "closing error of the re-integrated orbit: {:.3e} integration tolerances",
        result.closing_error
    );
    for (name, value) in &result.state {
        if name.ends_with(".phi") || name.ends_with(".ex") || name.ends_with(".ey") {
            println!("  {name} = {value:.12}");
        }
    }
    let mu: Vec<String> = result
        .floquet_multipliers
        .iter()
        .map(|z| format!("{:.6}{:+.6}i (|mu| {:.6})", z[0], z[1], z[0].hypot(z[1])))
        .collect();
    println!(
        "Floquet multipliers: {} ({} trivial removed): {}",
        mu.join(", "),
        result.trivial_multipliers,
        if result.stable { "stable" } else { "unstable" }
    );
    println!(
        "impacts per period: {}; smallest gap: {}",
        result.impacts_per_period,
        result
            .min_gap_m
            .map_or("no clearance joint".into(), |g| format!("{g:.3e} m"))
    );
    eprintln!(
        "{} and {} in {:.3} s",
        args.out.display(),
        csv.display(),
        result.wall_time_s
    );
    Ok(())
}
