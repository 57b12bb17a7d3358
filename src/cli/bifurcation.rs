//! `linkdyn bifurcation MODEL --param PATH --from A --to B --steps N --revs R --transient M
//! --observe COL --out F.csv [--resume] [--shard i/n] [--threads K]`: a bifurcation diagram.
//!
//! Each of the N + 1 parameter values loads the model with the extra override `PATH=value`,
//! integrates R driver turns and records the observed column once per turn after M transient
//! turns (its Poincaré points), with the point's period verdict. Points run in parallel; each
//! finished point is appended to `F.csv` (`index,<param>,turn,<col>`, R − M rows) and then to
//! `F.verdicts.csv` (`index,<param>,verdict,k,message`), both flushed to disk. The verdict row
//! marks a point as finished: `--resume` keeps the points that have their verdict and all
//! their rows, drops any partial rows, and runs only the rest. When every point of the shard
//! is done, both files are rewritten in index order, so the result does not depend on the
//! threads, and shard files merged with `linkdyn merge` equal an unsharded run byte for byte.
//!
//! **Checks first.** Every option, both ends of the grid (each loaded and built as a point
//! would be) and the output paths are checked before any file is touched, and an earlier
//! result is replaced only when the first point of this run is finished: bad input leaves it
//! as it was.
//!
//! **Failed points.** A point whose model, simulation or integration fails does not end the
//! sweep: its R − M rows hold `NaN`, its verdict is `failed` with the message (one line,
//! quoted as RFC 4180 says), and the other points run. The command then exits with
//! [`EXIT_FAILED_POINTS`] and a summary (`199 of 200 points; point 198 (…) failed: …`);
//! `--resume` keeps the finished points and runs only the failed ones again.
//!
//! **Ctrl-C** (SIGINT, SIGTERM, SIGHUP): no new point starts, the points in flight finish and
//! are appended, and the command exits with code 130 saying how many points are on disk and
//! that `--resume` continues; a second signal stops at once (the finished points are on disk,
//! a cut-off row is dropped by `--resume`). The files then hold the finished points in order
//! of completion; `--resume` puts them in index order.
//!
//! **Transient detection** (`--settle`): each point's transient ends once its section has
//! settled (`linkdyn::simulation::analyses::poincare_from`), and the verdicts say after how
//! many turns (`transient_turns`). **Warm starts** (`--warm-start`, reduced formulation): the
//! grid is split into `--chunks` contiguous chunks, fixed whatever the threads, each walked in
//! `--direction` (`both`: `F.up.csv` and `F.down.csv`), every point but a chunk's first
//! starting from the state the one before it ended in; that state is in the verdicts
//! (`end_state`), so `--resume` carries a chunk on exactly. `--shard` is refused with it.

use super::poincare::{ModelArgs, bad, provenance_lines};
use super::{EXIT_FAILED_POINTS, EXIT_INTERRUPTED, EXIT_OUTPUT, Failure, csv_field, interrupt};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use linkdyn::analysis::{self, Direction, ParameterGrid, PeriodVerdict, Shard, SweepPoint};
use linkdyn::output::{AtomicFile, OutputLock, check_output_file, format_number};
use linkdyn::simulation::analyses::{
    ModelSection, SectionSpec, Sweep, SweepMode, SweepModeRequest,
};
use linkdyn::simulation::{EndTime, Simulation, SimulationOptions, escape_line};
use std::collections::{BTreeMap, BTreeSet};
use std::fs::{File, OpenOptions};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};

/// Arguments of `bifurcation`.
#[derive(Debug, Args)]
pub struct BifurcationArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// The swept model field, as a `--set` path (e.g. `joints.B.clearance`).
    #[arg(long)]
    param: String,
    /// First parameter value (the field's unit in the model file).
    #[arg(long, allow_negative_numbers = true)]
    from: f64,
    /// Last parameter value.
    #[arg(long, allow_negative_numbers = true)]
    to: f64,
    /// Number of intervals: steps + 1 points, both ends included.
    #[arg(long)]
    steps: usize,
    /// Transient driver turns dropped at each point.
    #[arg(long, default_value_t = 100)]
    transient: usize,
    /// Section phase within a driver turn (rad, in [0, 2π)).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    phase: f64,
    /// The output column recorded once per turn (e.g. `coupler.phi`).
    #[arg(long)]
    observe: String,
    /// Keep the finished points of an earlier, interrupted run of the same sweep and run the
    /// rest.
    #[arg(long)]
    resume: bool,
    /// Run only shard i of n (1-based): points i − 1, i − 1 + n, …
    #[arg(long, value_parser = parse_shard)]
    shard: Option<Shard>,
    /// Worker threads (default: one per core).
    #[arg(long)]
    threads: Option<usize>,
    /// Start each point from the state the point before it ended in (on its attractor)
    /// instead of the model's initial state: the grid is split into --chunks contiguous
    /// chunks run in parallel, each swept in --direction from a cold first point. Reduced
    /// formulation only; not with --shard.
    #[arg(long)]
    warm_start: bool,
    /// Chunks of a warm-started sweep (default: one per 25 points, at most 8; fixed, so that
    /// the result does not depend on --threads). 1 follows one branch over the whole range.
    #[arg(long)]
    chunks: Option<usize>,
    /// Direction of a warm-started sweep: up (from --from to --to), down, or both (two
    /// branches, written to F.up.csv and F.down.csv, which show coexisting attractors and
    /// hysteresis).
    #[arg(long, value_parser = parse_direction)]
    direction: Option<Directions>,
    /// End each point's transient once its Poincaré points have settled (the last 4 repeat
    /// with a period k ≤ 8 within 10 times the integration tolerance), after at least
    /// --transient-min turns and at most --transient; the turns used go to the verdicts.
    #[arg(long)]
    settle: bool,
    /// Fewest transient turns with --settle (default 5).
    #[arg(long)]
    transient_min: Option<usize>,
    /// Output CSV file `index,<param>,turn,<col>`; the verdicts go to `F.verdicts.csv`.
    #[arg(long)]
    out: PathBuf,
}

/// The branches of a warm-started sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Directions {
    /// One branch.
    One(Direction),
    /// Up and down.
    Both,
}

fn parse_direction(s: &str) -> Result<Directions, String> {
    match s {
        "up" => Ok(Directions::One(Direction::Up)),
        "down" => Ok(Directions::One(Direction::Down)),
        "both" => Ok(Directions::Both),
        _ => Err(format!("expected up, down or both, got \"{s}\"")),
    }
}

fn parse_shard(s: &str) -> Result<Shard, String> {
    s.parse()
        .map_err(|e: analysis::AnalysisError| e.to_string())
}

/// `F.csv` → `F.verdicts.csv`.
pub fn verdicts_path(out: &Path) -> PathBuf {
    out.with_extension("verdicts.csv")
}

/// `F.csv` → `F.up.csv` or `F.down.csv`: the branches of `--direction both`.
pub fn branch_path(out: &Path, direction: Direction) -> PathBuf {
    out.with_extension(format!("{direction}.csv"))
}

/// Verdict name and period for the verdicts file (`period`/k, `no_period`/0, `not_settled`/0).
fn verdict_fields(v: &PeriodVerdict) -> (&'static str, usize) {
    match v {
        PeriodVerdict::Period { k, .. } => ("period", *k),
        PeriodVerdict::NoPeriod { .. } => ("no_period", 0),
        PeriodVerdict::NotSettled { .. } => ("not_settled", 0),
    }
}

/// Rows of a result file after its head, grouped by their index (first field). Lines without
/// a final newline (cut off) or with an unreadable index are left out.
fn rows_by_index(text: &str, head_len: usize) -> BTreeMap<usize, Vec<&str>> {
    let mut rows: BTreeMap<usize, Vec<&str>> = BTreeMap::new();
    let body = text.get(head_len..).unwrap_or("");
    for line in body.split_inclusive('\n') {
        if !line.ends_with('\n') {
            continue;
        }
        if let Some(Ok(i)) = line.split(',').next().map(str::parse::<usize>) {
            rows.entry(i).or_default().push(line);
        }
    }
    rows
}

/// Rewrites `path` (atomically) as `head` and the rows of the indices in `keep`, in index order.
fn rewrite(
    path: &Path,
    head: &str,
    rows: &BTreeMap<usize, Vec<&str>>,
    keep: &BTreeSet<usize>,
) -> Result<(), Failure> {
    let mut file = AtomicFile::create(path)?;
    file.write_str(head)?;
    for (i, lines) in rows {
        if keep.contains(i) {
            for line in lines {
                file.write_str(line)?;
            }
        }
    }
    file.commit()?;
    Ok(())
}

/// Reads `path` if it exists and starts with `head`; `None` if it does not exist.
fn read_matching(path: &Path, head: &str) -> Result<Option<String>, Failure> {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => {
            return Err(bad(
                "resume",
                format!("cannot read {}: {e}", path.display()),
            ));
        }
    };
    if !text.starts_with(head) {
        let ours = head.lines();
        let first = text
            .lines()
            .zip(ours)
            .find(|(a, b)| a != b)
            .map(|(a, b)| format!(": it has \"{a}\" where this sweep has \"{b}\""))
            .unwrap_or_default();
        return Err(bad(
            "resume",
            format!(
                "{} was written by a different sweep or with other settings{first}",
                path.display()
            ),
        ));
    }
    Ok(Some(text))
}

/// The verdict of a point whose model, simulation or integration failed (its `k` is 0, its
/// `message` the error, its rows `NaN`).
const FAILED: &str = "failed";
/// Failed points named one by one in the closing message; the rest are counted.
const FAILURES_LISTED: usize = 5;

/// One result file pair: `F.csv` and `F.verdicts.csv` (per direction with `--direction both`).
struct Branch {
    direction: Option<Direction>,
    out: PathBuf,
    verdicts: PathBuf,
    data_head: String,
    verdict_head: String,
}

/// A point's section, whether it started warm, and the state it ended in (warm starts).
struct Outcome {
    section: ModelSection,
    warm: bool,
    end: Option<[f64; 5]>,
}

/// What `--resume` keeps of one branch: the finished points, the files' text with them, and
/// their end states (warm starts).
struct Kept {
    finished: BTreeSet<usize>,
    data: String,
    verdicts: String,
    ends: BTreeMap<usize, Vec<f64>>,
}

/// The `end_state` field of a warm-started point's verdict row (the 7th): its numbers, or
/// `None` if missing or unreadable.
fn end_state(line: &str) -> Option<Vec<f64>> {
    let field = line.split(',').nth(6)?;
    let y: Option<Vec<f64>> = field.split(' ').map(|v| v.parse().ok()).collect();
    y.filter(|y| y.len() == 5 && y.iter().all(|v: &f64| v.is_finite()))
}

/// Runs `bifurcation`. Every check comes before any file is touched: an earlier result is
/// replaced only once the first point of this run is finished.
pub fn run(args: &BifurcationArgs) -> Result<(), Failure> {
    let turns = args.model.whole_turns(150)?;
    if turns <= args.transient {
        return Err(bad(
            "revs",
            format!(
                "expected more turns than the {} transient turns, got {turns}",
                args.transient
            ),
        ));
    }
    let grid = ParameterGrid::new(args.from, args.to, args.steps)?;
    let pool = {
        let builder = rayon::ThreadPoolBuilder::new();
        let builder = match args.threads {
            Some(0) => return Err(bad("threads", "expected at least 1 thread, got 0")),
            Some(k) => builder.num_threads(k),
            None => builder,
        };
        builder
            .build()
            .map_err(|e| bad("threads", format!("cannot start the threads: {e}")))?
    };
    // The base model and settings, checked once before any point (bad input exits 2 now).
    let base_model = super::load_model(
        &args.model.model,
        &args.model.solve.set,
        &args.model.solve.ideal,
    )?;
    let options = SimulationOptions {
        end: EndTime::DriverTurns(turns as f64),
        ..args.model.options()?
    };
    let mode = SweepMode::new(
        &SweepModeRequest {
            settle: args.settle,
            transient_min: args.transient_min,
            transient: args.transient,
            warm_start: args.warm_start,
            chunks: args.chunks,
            directions: args.direction.map(|d| match d {
                Directions::One(d) => vec![d],
                Directions::Both => vec![Direction::Up, Direction::Down],
            }),
            sharded: args.shard.is_some(),
            n_points: grid.len(),
        },
        options.formulation,
    )?;
    let chunks = mode.chunks(&grid)?;
    let base = Simulation::new(&base_model, options.clone())
        .map_err(|e| super::in_model(&args.model.model, e))?;
    let sweep = Sweep {
        model_path: &args.model.model,
        model_text: None,
        // `--set` then `--ideal` as overrides, so every point reloads the same model.
        overrides: &base_model.source.overrides,
        parameter: &args.param,
        grid,
        options,
        section: SectionSpec {
            turns,
            transient: args.transient,
            phase: args.phase,
            observe: vec![args.observe.clone()],
        },
    };
    // Both ends of the grid load and build (a bad --from or --to is bad input, not a failed
    // point), and the section's settings hold on the first.
    let ends = [Some(args.from), (grid.len() > 1).then_some(args.to)];
    for value in ends.into_iter().flatten() {
        let sim = sweep
            .simulation(value)
            .map_err(|e| prefixed(e, &format!("--param {}", args.param)))?;
        sweep.section.check(&sim)?;
    }

    let mut extra = vec![
        ("parameter", args.param.clone()),
        ("from", format_number(args.from)),
        ("to", format_number(args.to)),
        ("steps", args.steps.to_string()),
        ("revs", turns.to_string()),
        ("transient_revs", args.transient.to_string()),
        ("phase_rad", format_number(args.phase)),
        ("observe", args.observe.clone()),
    ];
    // Only the new modes add lines, so that the files of independent starts stay as they were
    // (and `--resume` still matches them).
    if let Some(s) = mode.settle {
        extra.push(("settle_min_revs", s.min_transient.to_string()));
    }
    if let Some((n, _)) = &mode.warm {
        extra.push(("warm_start_chunks", n.to_string()));
    }
    let branches: Vec<Branch> = match &mode.warm {
        None => vec![None],
        Some((_, directions)) => directions.iter().copied().map(Some).collect(),
    }
    .into_iter()
    .map(|direction| {
        let mut extra = extra.clone();
        let out = match direction {
            Some(d) => {
                extra.push(("direction", d.to_string()));
                if matches!(args.direction, Some(Directions::Both)) {
                    branch_path(&args.out, d)
                } else {
                    args.out.clone()
                }
            }
            None => args.out.clone(),
        };
        let head = provenance_lines(base.provenance(), &extra);
        // Header row first, then the provenance (as every result CSV); the whole head is a
        // prefix that `--resume` matches and skips.
        let verdict_columns = if mode.warm.is_some() {
            "verdict,k,transient_turns,start,end_state,message"
        } else if mode.extended() {
            "verdict,k,transient_turns,start,message"
        } else {
            "verdict,k,message"
        };
        Branch {
            direction,
            verdicts: verdicts_path(&out),
            data_head: format!("index,{},turn,{}\n{head}", args.param, args.observe),
            verdict_head: format!("index,{},{verdict_columns}\n{head}", args.param),
            out,
        }
    })
    .collect();
    let mut locks = Vec::new();
    for b in &branches {
        check_output_file(&b.out, Some(&args.model.model))?;
        check_output_file(&b.verdicts, Some(&args.model.model))?;
        locks.push(OutputLock::acquire(&b.out)?);
    }

    // What is finished: a verdict other than `failed` and all R − M rows. Failed points and
    // partial rows are dropped, so that they run again. (A warm-started sweep has one branch
    // per direction and no --resume.)
    let per_point = turns - args.transient;
    let warm_mode = mode.warm.is_some();
    // Per branch: the finished points and the files' text to keep. A warm-started point also
    // needs its end state (the next point starts from it).
    let mut kept: Vec<Kept> = Vec::with_capacity(branches.len());
    for b in &branches {
        let mut k = Kept {
            finished: BTreeSet::new(),
            data: b.data_head.clone(),
            verdicts: b.verdict_head.clone(),
            ends: BTreeMap::new(),
        };
        if args.resume {
            let data = read_matching(&b.out, &b.data_head)?;
            let verdict = read_matching(&b.verdicts, &b.verdict_head)?;
            if let (Some(data), Some(verdict)) = (&data, &verdict) {
                let rows = rows_by_index(data, b.data_head.len());
                let marks = rows_by_index(verdict, b.verdict_head.len());
                for (i, m) in &marks {
                    let [line] = m.as_slice() else {
                        continue;
                    };
                    if is_failed(line) || rows.get(i).map_or(0, Vec::len) != per_point {
                        continue;
                    }
                    if warm_mode {
                        match end_state(line) {
                            Some(y) => {
                                k.ends.insert(*i, y);
                            }
                            None => continue,
                        }
                    }
                    k.finished.insert(*i);
                }
                if let Some(chunks) = &chunks {
                    // A chunk carries on after its finished points that run in a row from its
                    // start; a finished point after a gap (a failed point) runs again.
                    let mut prefix = BTreeSet::new();
                    for c in chunks.iter().filter(|c| Some(c.direction) == b.direction) {
                        prefix.extend(c.indices.iter().take_while(|i| k.finished.contains(i)));
                    }
                    k.finished = prefix;
                }
                k.data = joined(&b.data_head, &rows, &k.finished);
                k.verdicts = joined(&b.verdict_head, &marks, &k.finished);
            }
        }
        kept.push(k);
    }
    let done: usize = kept.iter().map(|k| k.finished.len()).sum();
    // Independent points: those of the shard not finished. Warm-started: each chunk's points
    // after its finished ones, from the last finished one's end state.
    let mut todo = Vec::new();
    let mut starts = Vec::new();
    let mut runs: Vec<analysis::Chunk> = Vec::new();
    match &chunks {
        None => {
            let done: Vec<usize> = kept[0].finished.iter().copied().collect();
            todo = analysis::remaining(&grid, args.shard.as_ref(), &done)?;
        }
        Some(chunks) => {
            for c in chunks {
                let k = &kept[branches
                    .iter()
                    .position(|b| b.direction == Some(c.direction))
                    .unwrap_or(0)];
                let n_done = c
                    .indices
                    .iter()
                    .take_while(|i| k.finished.contains(i))
                    .count();
                let start = match n_done.checked_sub(1).map(|j| c.indices[j]) {
                    Some(last) => {
                        let y = k.ends.get(&last).map_or(&[][..], Vec::as_slice);
                        let value = grid.value(last).unwrap_or(f64::NAN);
                        Some(sweep.warm_state(value, y)?)
                    }
                    None => None,
                };
                let rest = c.indices[n_done..].to_vec();
                if !rest.is_empty() {
                    todo.extend(&rest);
                    starts.push(start);
                    runs.push(analysis::Chunk {
                        direction: c.direction,
                        indices: rest,
                    });
                }
            }
        }
    }
    let to_run = todo.len();
    let total = done + to_run;
    eprintln!(
        "{total} points{}{}: {done} finished, {to_run} to run ({}{turns} turns each{}, {per_point} recorded)",
        args.shard
            .map(|s| format!(" in shard {s}"))
            .unwrap_or_default(),
        match &mode.warm {
            Some((n, d)) => format!(
                ", warm-started in {n} chunks {}",
                d.iter()
                    .map(ToString::to_string)
                    .collect::<Vec<_>>()
                    .join(" and ")
            ),
            None => String::new(),
        },
        if mode.settle.is_some() {
            "at most "
        } else {
            ""
        },
        if mode.settle.is_some() {
            ", the transient ended once settled"
        } else {
            ""
        },
    );

    let mut appenders: Vec<Appender> = branches
        .iter()
        .zip(&kept)
        .map(|(b, k)| Appender {
            data: Pending::new(&b.out, k.data.clone()),
            verdicts: Pending::new(&b.verdicts, k.verdicts.clone()),
            turns: args.transient..turns,
            extended: mode.extended(),
            warm: warm_mode,
        })
        .collect();
    let bar = progress_bar(to_run);
    let branch_of =
        |d: Option<Direction>| branches.iter().position(|b| b.direction == d).unwrap_or(0);
    interrupt::install();
    // A signal only raises the flag: points stop starting, those in flight are written.
    interrupt::defer_to_caller();
    let settle = mode.settle;
    let results: Result<Vec<BranchPoint>, Failure> = pool.install(|| match &chunks {
        None => analysis::run_points_until(
            &grid,
            &todo,
            |_, p| {
                sweep
                    .point_from(p, settle, None)
                    .map(|r| Outcome {
                        section: r.section,
                        warm: r.warm,
                        end: None,
                    })
                    .map_err(Failure::from)
            },
            |p| {
                appenders[0].append(p)?;
                if let Some(bar) = &bar {
                    bar.inc(1);
                }
                Ok(())
            },
            interrupt::requested,
        )
        .map(|r| r.into_iter().map(|p| (None, p)).collect()),
        Some(_) => analysis::run_chunks_until(
            &grid,
            &runs,
            starts,
            |_, _, p, previous| match sweep.point_from(p, settle, previous) {
                Ok(r) => (
                    Ok(Outcome {
                        section: r.section,
                        warm: r.warm,
                        end: r.end.as_ref().map(|w| w.y),
                    }),
                    r.end,
                ),
                Err(e) => (Err(Failure::from(e)), None),
            },
            |d, p| {
                appenders[branch_of(Some(d))].append(p)?;
                if let Some(bar) = &bar {
                    bar.inc(1);
                }
                Ok(())
            },
            interrupt::requested,
        )
        .map(|r| r.into_iter().map(|(d, p)| (Some(d), p)).collect()),
    });
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    let results = results?;
    let files = branches
        .iter()
        .map(|b| format!("{} and {}", b.out.display(), b.verdicts.display()))
        .collect::<Vec<_>>()
        .join(", ");
    if results.len() < to_run {
        // Only a signal leaves points out of a successful return.
        let kept = done + results.len();
        return Err(Failure {
            code: EXIT_INTERRUPTED,
            message: format!(
                "interrupted: {kept} of {total} points are finished in {files}; run the same command with --resume to compute the {} left",
                total - kept
            ),
        });
    }

    // Every point of the shard has its verdict: index order, whatever the threads did. (With
    // nothing to run, the kept points are written now.)
    for (k, b) in branches.iter().enumerate() {
        appenders[k].data.open()?;
        appenders[k].verdicts.open()?;
        let mut all: BTreeSet<usize> = kept[k].finished.clone();
        all.extend(
            results
                .iter()
                .filter(|(d, _)| *d == b.direction)
                .map(|(_, p)| p.index),
        );
        for (path, head) in [(&b.out, &b.data_head), (&b.verdicts, &b.verdict_head)] {
            let text = std::fs::read_to_string(path).map_err(|e| output_failure(path, &e))?;
            rewrite(path, head, &rows_by_index(&text, head.len()), &all)?;
        }
    }
    drop(locks);

    let mut failures = Vec::new();
    for b in &branches {
        let mut counts: BTreeMap<String, usize> = BTreeMap::new();
        let mut n = 0;
        for (_, p) in results.iter().filter(|(d, _)| *d == b.direction) {
            n += 1;
            match &p.result {
                Ok(s) => {
                    *counts
                        .entry(s.section.period.verdict.to_string())
                        .or_default() += 1
                }
                Err(e) => failures.push(format!(
                    "point {}{} ({} = {}) failed: {}",
                    p.index,
                    b.direction.map(|d| format!(" {d}")).unwrap_or_default(),
                    args.param,
                    format_number(p.parameter),
                    e.message
                )),
            }
        }
        let summary: Vec<String> = counts.iter().map(|(v, n)| format!("{v}: {n}")).collect();
        println!(
            "{n} points run to {} and {}; verdicts: {}",
            b.out.display(),
            b.verdicts.display(),
            if summary.is_empty() {
                "none".into()
            } else {
                summary.join(", ")
            }
        );
    }
    if failures.is_empty() {
        return Ok(());
    }
    let n_failed = failures.len();
    let more = n_failed.saturating_sub(FAILURES_LISTED);
    failures.truncate(FAILURES_LISTED);
    if more > 0 {
        failures.push(format!("{more} more failed"));
    }
    let retry = if mode.warm.is_some() {
        // The next point of a failed one's chunk started cold (`start` = cold): it runs again
        // too, from the retried point's end.
        format!(
            "run the same command with --resume to retry {} and the rest of {}",
            if n_failed == 1 { "it" } else { "them" },
            if n_failed == 1 {
                "its chunk"
            } else {
                "their chunks"
            }
        )
    } else {
        format!(
            "run the same command with --resume to retry only {}",
            if n_failed == 1 { "it" } else { "them" }
        )
    };
    Err(Failure {
        code: EXIT_FAILED_POINTS,
        message: format!(
            "{} of {total} points; {}. The failed {} recorded as \"{FAILED}\" with {} in {}; {retry}",
            total - n_failed,
            failures.join("; "),
            if n_failed == 1 {
                "point is"
            } else {
                "points are"
            },
            if n_failed == 1 {
                "its message"
            } else {
                "their messages"
            },
            branches
                .iter()
                .map(|b| b.verdicts.display().to_string())
                .collect::<Vec<_>>()
                .join(" and "),
        ),
    })
}

/// A point's outcome: its section, or why it failed.
type PointResult = Result<Outcome, Failure>;
/// A finished point with its branch (`None`: independent starts).
type BranchPoint = (Option<Direction>, SweepPoint<PointResult>);

/// Whether a verdict row is that of a failed point.
fn is_failed(line: &str) -> bool {
    line.split(',').nth(2) == Some(FAILED)
}

/// `head` and the rows of the indices in `keep`, in index order.
fn joined(head: &str, rows: &BTreeMap<usize, Vec<&str>>, keep: &BTreeSet<usize>) -> String {
    let mut text = head.to_string();
    for (i, lines) in rows {
        if keep.contains(i) {
            text.extend(lines.iter().copied());
        }
    }
    text
}

/// A failure of a library call, with `what` in front of its message.
fn prefixed(e: linkdyn::Error, what: &str) -> Failure {
    let mut f = Failure::from(e);
    f.message = format!("{what}: {}", f.message);
    f
}

fn output_failure(path: &Path, e: &std::io::Error) -> Failure {
    Failure {
        code: EXIT_OUTPUT,
        message: format!("cannot write {}: {e}", path.display()),
    }
}

/// A progress bar of `n` points on a terminal; none otherwise.
fn progress_bar(n: usize) -> Option<ProgressBar> {
    std::io::stderr().is_terminal().then(|| {
        let bar = ProgressBar::with_draw_target(Some(n as u64), ProgressDrawTarget::stderr());
        let style = ProgressStyle::with_template("{wide_bar} {pos}/{len} points, {eta} left")
            .unwrap_or_else(|_| ProgressStyle::default_bar());
        bar.set_style(style);
        bar
    })
}

/// A result file that is written only when the first point is appended: until then an
/// earlier file of the same name stays as it was. Opening replaces it (atomically) with the
/// head and the points kept by `--resume`, then appends.
struct Pending<'a> {
    path: &'a Path,
    initial: String,
    file: Option<File>,
}

impl<'a> Pending<'a> {
    fn new(path: &'a Path, initial: String) -> Self {
        Pending {
            path,
            initial,
            file: None,
        }
    }

    /// The file, written with its initial text on first use.
    fn open(&mut self) -> Result<&mut File, Failure> {
        if self.file.is_none() {
            let mut whole = AtomicFile::create(self.path)?;
            whole.write_str(&self.initial)?;
            whole.commit()?;
            let file = OpenOptions::new()
                .append(true)
                .open(self.path)
                .map_err(|e| output_failure(self.path, &e))?;
            self.file = Some(file);
        }
        self.file
            .as_mut()
            .ok_or_else(|| output_failure(self.path, &std::io::Error::other("not open")))
    }

    /// Appends `text` and flushes it to disk.
    fn append(&mut self, text: &str) -> Result<(), Failure> {
        let path = self.path;
        self.open()?
            .write_all(text.as_bytes())
            .and_then(|()| self.file.as_mut().map_or(Ok(()), |f| f.sync_data()))
            .map_err(|e| output_failure(path, &e))
    }
}

/// Appends each finished point to the two files (data rows first, then the verdict that marks
/// the point finished), flushed to disk. A failed point gets `NaN` rows and the verdict
/// `failed` with its message.
struct Appender<'a> {
    data: Pending<'a>,
    verdicts: Pending<'a>,
    /// The recorded turns M..R (of a failed point).
    turns: std::ops::Range<usize>,
    /// Verdict rows with `transient_turns,start`.
    extended: bool,
    /// Verdict rows with `end_state` too.
    warm: bool,
}

impl Appender<'_> {
    fn append(&mut self, p: &SweepPoint<PointResult>) -> Result<(), Failure> {
        let index = p.index.to_string();
        let value = format_number(p.parameter);
        let mut rows = String::new();
        let mark = match &p.result {
            Ok(Outcome {
                section: s,
                warm,
                end,
            }) => {
                for (turn, point) in s.turns.iter().zip(&s.section.points) {
                    for v in point {
                        rows.push_str(&format!("{index},{value},{turn},{}\n", format_number(*v)));
                    }
                }
                let (name, k) = verdict_fields(&s.period.verdict);
                if self.extended {
                    let transient = s.turns.first().copied().unwrap_or(self.turns.start);
                    let start = if *warm { "warm" } else { "cold" };
                    let end = if self.warm {
                        let y: Vec<String> =
                            end.iter().flatten().map(|v| format_number(*v)).collect();
                        format!("{},", y.join(" "))
                    } else {
                        String::new()
                    };
                    format!("{index},{value},{name},{k},{transient},{start},{end}\n")
                } else {
                    format!("{index},{value},{name},{k},\n")
                }
            }
            Err(e) => {
                for turn in self.turns.clone() {
                    rows.push_str(&format!("{index},{value},{turn},NaN\n"));
                }
                let message = csv_field(&escape_line(&e.message));
                if self.warm {
                    format!("{index},{value},{FAILED},0,,,,{message}\n")
                } else if self.extended {
                    format!("{index},{value},{FAILED},0,,,{message}\n")
                } else {
                    format!("{index},{value},{FAILED},0,{message}\n")
                }
            }
        };
        self.data.append(&rows)?;
        self.verdicts.append(&mark)
    }
}

impl From<analysis::AnalysisError> for Failure {
    fn from(e: analysis::AnalysisError) -> Self {
        Failure::from(linkdyn::Error::from(e))
    }
}
