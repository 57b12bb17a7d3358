//! `linkdyn continue MODEL --param PATH --from A --to B [--step H] [--period-turns K]
//! [--guess-from-turn N] --out F.csv`: the periodic orbit continued in one model field by
//! pseudo-arclength, with its folds, period doublings, Neimark–Sacker points and grazing
//! located; `F.csv` (one row per point) and `F.json` (summary and provenance) appear together
//! or not at all.

use super::args::SolveArgs;
use super::poincare::bad;
use super::progress::SHOW_AFTER;
use super::{EXIT_INTERRUPTED, EXIT_SOLVER, Failure, in_model, interrupt};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use linkdyn::Error;
use linkdyn::analysis::orbit::BranchEnd;
use linkdyn::analysis::orbit::BranchPoint;
use linkdyn::output::{ResultPair, push_number};
use linkdyn::simulation::FormulationKind;
use linkdyn::studies::continuation::{ContinuationRequest, ContinuationRow, continuation_watched};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `continue`.
#[derive(Debug, Args)]
pub struct ContinueArgs {
    /// Model file (TOML).
    model: PathBuf,
    #[command(flatten)]
    solve: SolveArgs,
    /// Equations of motion: `reduced` (the four-bar with one clearance joint) or `dae` (any
    /// linkage, about ten times slower); not `generalized`.
    #[arg(long, default_value = "reduced", value_parser = super::run::parse_formulation)]
    formulation: FormulationKind,
    /// The continued model field, as a `--set` path (e.g. `joints.B.clearance`).
    #[arg(long)]
    param: String,
    /// First parameter value (the field's unit in the model file): the branch starts with the
    /// orbit there.
    #[arg(long, allow_negative_numbers = true)]
    from: f64,
    /// Last parameter value.
    #[arg(long, allow_negative_numbers = true)]
    to: f64,
    /// Largest step along the branch (parameter units; default |to − from|/20).
    #[arg(long, allow_negative_numbers = true)]
    step: Option<f64>,
    /// Period of the orbit in driver turns.
    #[arg(long, default_value_t = 1)]
    period_turns: usize,
    /// Periods integrated from the initial state at --from before the first shooting starts
    /// from where they end (the section).
    #[arg(long, default_value_t = 3)]
    guess_from_turn: usize,
    /// Also continue the period-2K branch from each located period doubling, and theirs, N
    /// doublings deep (rows with `branch` ≥ 1).
    #[arg(long, default_value_t = 0)]
    follow_doublings: usize,
    /// Result file (CSV, one row per point and driver turn of its period); the summary goes
    /// beside it as `.json`.
    #[arg(long)]
    out: PathBuf,
}

/// Runs `continue`.
pub fn run(args: &ContinueArgs) -> Result<(), Failure> {
    if args.solve.t_end.is_some() || args.solve.revs.is_some() {
        return Err(bad(
            "revs",
            "an orbit lasts one period: give `period_turns` instead",
        ));
    }
    if args.out.extension().and_then(|e| e.to_str()) != Some("csv") {
        return Err(bad(
            "out",
            format!(
                "expected a .csv file (the summary goes beside it as .json), got {}",
                args.out.display()
            ),
        ));
    }
    if args.from == args.to {
        return Err(bad(
            "to",
            format!(
                "expected a value other than --from {} (a branch needs a range)",
                args.from
            ),
        ));
    }
    if let Some(h) = args.step
        && !(h.is_finite() && h > 0.0)
    {
        return Err(bad("step", format!("expected a finite step > 0, got {h}")));
    }
    let model = super::load_model(&args.model, &args.solve.set, &args.solve.ideal)?;
    let text = std::fs::read_to_string(&args.model).map_err(|e| Failure {
        code: super::EXIT_BAD_INPUT,
        message: format!("cannot read {}: {e}", args.model.display()),
    })?;
    // `--set` then `--ideal` as overrides, so every point reloads the same model.
    let overrides = model.source.overrides.clone();
    // Both ends load with the parameter: an unknown path or a bad value is named now.
    for value in [args.from, args.to] {
        let mut with = overrides.clone();
        with.push(format!("{}={value}", args.param));
        linkdyn::model::load_str(&text, &args.model.display().to_string(), &with).map_err(|e| {
            let mut f = Failure::from(Error::from(e));
            f.message = format!("--param {}: {}", args.param, f.message);
            f
        })?;
    }
    let request = ContinuationRequest {
        model_path: &args.model,
        model_text: &text,
        overrides: &overrides,
        parameter: &args.param,
        from: args.from,
        to: args.to,
        step: args.step,
        period_turns: args.period_turns,
        guess_from_turn: args.guess_from_turn,
        follow_doublings: args.follow_doublings,
        options: args.solve.options()?.formulation(args.formulation),
    };
    if args.solve.rtol > 1e-9 {
        eprintln!(
            "note: at rtol {:e} the Floquet multipliers in contact are coarse (above 1e-9), and multiplier counts that jump without a crossing are reported as not located (docs/periodic_orbits.md, \"Continuation\"); rtol 1e-10 --atol 1e-12 is advised",
            args.solve.rtol
        );
    }
    // Before any work: a result is not lost to a target that cannot be written.
    let mut pair = ResultPair::begin(&args.out, Some(&args.model))?;
    for note in pair.notes() {
        eprintln!("note: {note}");
    }
    // A first Ctrl-C ends the branch after its current point (the files are written with what
    // was computed, exit 130); a second one stops at once.
    interrupt::install();
    interrupt::defer_to_caller();
    let mut progress = Progress::new(&args.param);
    let result = continuation_watched(&request, &mut |branch, point| {
        progress.show(branch, point);
        !interrupt::requested()
    })
    .map_err(|e| in_model(&args.model, e))?;
    progress.finish();

    let mut text = String::new();
    text.push_str(&args.param);
    for name in &result.names {
        text.push(',');
        text.push_str(name);
    }
    text.push_str(
        ",period_s,max_abs_mu,stable,impacts_per_period,min_gap_m,residual,special,branch,turn\n",
    );
    for line in result.provenance.lines() {
        text.push_str("# ");
        text.push_str(&line);
        text.push('\n');
    }
    for row in &result.rows {
        push_row(&mut text, row);
    }
    pair.csv().write_str(&text)?;
    pair.commit(&result)?;

    let main: Vec<&ContinuationRow> = result.rows.iter().filter(|r| r.branch == 0).collect();
    for row in main.iter().filter(|r| r.special.is_some() && r.turn == 0) {
        println!("{}", describe(&args.param, row));
    }
    for (kind, p, why) in &result.unlocated {
        println!(
            "{kind} between the point before and {} = {p}, not located: {why}",
            args.param
        );
    }
    let (first, last) = (
        main.first().map_or(f64::NAN, |r| r.parameter),
        main.last().map_or(f64::NAN, |r| r.parameter),
    );
    println!(
        "{} points from {} = {first} to {last}; largest residual {:.3e} integration tolerances",
        result.points,
        args.param,
        main.iter().map(|r| r.residual).fold(0.0, f64::max)
    );
    let mut stopped = Vec::new();
    for b in result.branches.iter().skip(1) {
        let rows: Vec<&ContinuationRow> = result
            .rows
            .iter()
            .filter(|r| r.branch == b.branch && r.turn == 0)
            .collect();
        let (parent, at) = b.switched_from.unwrap_or((0, f64::NAN));
        let last = rows.last().map_or(f64::NAN, |r| r.parameter);
        let how = match &b.end {
            BranchEnd::Reached => format!("reached --to {}", args.to),
            BranchEnd::TurnedBack => format!("left the range at --from {}", args.from),
            BranchEnd::Rejoined { parameter } => format!(
                "rejoined branch {parent} at {} = {parameter} (a period doubling of that branch)",
                args.param
            ),
            BranchEnd::Stopped => format!("stopped at {} = {last} (interrupted)", args.param),
            BranchEnd::MaxPoints => {
                stopped.push(format!(
                    "branch {} stopped after {} points",
                    b.branch, b.points
                ));
                format!(
                    "stopped after {} points at {} = {last}",
                    b.points, args.param
                )
            }
            BranchEnd::Failed { message } => {
                stopped.push(format!(
                    "branch {} stopped at {} = {last}: {message}",
                    b.branch, args.param
                ));
                format!("stopped at {} = {last}: {message}", args.param)
            }
        };
        println!(
            "branch {} (period {} turns) from the PD of branch {parent} at {} = {at}: {} points; {how}",
            b.branch, b.period_turns, args.param, b.points
        );
        for row in rows.iter().skip(1).filter(|r| r.special.is_some()) {
            if !matches!(b.end, BranchEnd::Rejoined { parameter } if parameter == row.parameter) {
                println!("  {}", describe(&args.param, row));
            }
        }
        for (kind, p, why) in &b.unlocated {
            println!(
                "  {kind} between the point before and {} = {p}, not located: {why}",
                args.param
            );
        }
    }
    for (parent, p, why) in &result.switch_failures {
        println!(
            "no period-doubled branch followed from the PD of branch {parent} at {} = {p}: {why}",
            args.param
        );
        stopped.push(format!("no branch from the PD at {} = {p}", args.param));
    }
    eprintln!(
        "{} and {} in {:.3} s",
        args.out.display(),
        args.out.with_extension("json").display(),
        result.wall_time_s
    );
    if interrupt::requested() {
        return Err(Failure {
            code: EXIT_INTERRUPTED,
            message: format!(
                "interrupted: the branches up to the last point are in {} and {}",
                args.out.display(),
                args.out.with_extension("json").display()
            ),
        });
    }
    let main_end = match &result.end {
        BranchEnd::Reached | BranchEnd::Rejoined { .. } | BranchEnd::Stopped => Ok(()),
        BranchEnd::TurnedBack => {
            println!(
                "the branch turned back (a fold) and left the range at --from before reaching --to"
            );
            Ok(())
        }
        BranchEnd::MaxPoints => Err(Failure {
            code: EXIT_SOLVER,
            message: format!(
                "the branch stopped after {} points at {} = {last}, before --to (files written)",
                result.points, args.param
            ),
        }),
        BranchEnd::Failed { message } => Err(Failure {
            code: EXIT_SOLVER,
            message: format!(
                "the branch stopped at {} = {last}, before --to (files written): {message}",
                args.param
            ),
        }),
    };
    main_end?;
    if stopped.is_empty() {
        Ok(())
    } else {
        Err(Failure {
            code: EXIT_SOLVER,
            message: format!(
                "not every period-doubled branch was followed to its end (files written): {}",
                stopped.join("; ")
            ),
        })
    }
}

fn push_row(text: &mut String, row: &ContinuationRow) {
    push_number(text, row.parameter);
    for v in &row.state {
        text.push(',');
        push_number(text, *v);
    }
    for v in [row.period_s, row.max_abs_mu] {
        text.push(',');
        push_number(text, v);
    }
    text.push_str(if row.stable { ",1," } else { ",0," });
    text.push_str(&row.impacts_per_period.to_string());
    text.push(',');
    push_number(text, row.min_gap_m.unwrap_or(f64::NAN));
    text.push(',');
    push_number(text, row.residual);
    text.push(',');
    text.push_str(row.special.map_or("", |k| k.name()));
    text.push(',');
    text.push_str(&row.branch.to_string());
    text.push(',');
    text.push_str(&row.turn.to_string());
    text.push('\n');
}

fn describe(param: &str, row: &ContinuationRow) -> String {
    let mu: Vec<String> = row
        .floquet_multipliers
        .iter()
        .take(3)
        .map(|z| format!("{:.4}{:+.4}i", z[0], z[1]))
        .collect();
    format!(
        "{} at {param} = {} (multipliers {}; {} impacts per period; smallest gap {})",
        row.special.map_or("", |k| k.name()),
        row.parameter,
        mu.join(", "),
        row.impacts_per_period,
        row.min_gap_m
            .map_or("none".into(), |g| format!("{g:.3e} m"))
    )
}

/// A spinner on stderr with the branch and the last point, for a continuation longer than
/// about 2 s with stderr on a terminal; nothing otherwise (a file, a pipe, a test).
struct Progress<'a> {
    param: &'a str,
    started: Instant,
    terminal: bool,
    points: Vec<usize>,
    bar: Option<ProgressBar>,
}

impl<'a> Progress<'a> {
    fn new(param: &'a str) -> Self {
        Progress {
            param,
            started: Instant::now(),
            terminal: std::io::stderr().is_terminal(),
            points: Vec::new(),
            bar: None,
        }
    }

    fn show(&mut self, branch: usize, point: &BranchPoint) {
        if self.points.len() <= branch {
            self.points.resize(branch + 1, 0);
        }
        self.points[branch] += 1;
        if !self.terminal || self.started.elapsed() < SHOW_AFTER {
            return;
        }
        let bar = self.bar.get_or_insert_with(|| {
            let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
            let style = ProgressStyle::with_template("{spinner} {elapsed} {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_spinner());
            bar.set_style(style);
            bar
        });
        bar.set_message(format!(
            "branch {branch}: {} points, {} = {}{}",
            self.points[branch],
            self.param,
            point.parameter,
            point.special.map(|k| format!(" ({k})")).unwrap_or_default()
        ));
        bar.tick();
    }

    fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}
