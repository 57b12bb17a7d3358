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

use super::poincare::{ModelArgs, bad, provenance_lines};
use super::{EXIT_FAILED_POINTS, EXIT_INTERRUPTED, EXIT_OUTPUT, Failure, csv_field, interrupt};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use linkdyn::analysis::{self, ParameterGrid, PeriodVerdict, Shard, SweepPoint};
use linkdyn::output::{AtomicFile, OutputLock, check_output_file, format_number};
use linkdyn::simulation::analyses::{ModelSection, SectionSpec, Sweep};
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
    /// Output CSV file `index,<param>,turn,<col>`; the verdicts go to `F.verdicts.csv`.
    #[arg(long)]
    out: PathBuf,
}

fn parse_shard(s: &str) -> Result<Shard, String> {
    s.parse()
        .map_err(|e: analysis::AnalysisError| e.to_string())
}

/// `F.csv` → `F.verdicts.csv`.
pub fn verdicts_path(out: &Path) -> PathBuf {
    out.with_extension("verdicts.csv")
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
    let base = Simulation::new(&base_model, options.clone())
        .map_err(|e| super::in_model(&args.model.model, e))?;
    let sweep = Sweep {
        model_path: &args.model.model,
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

    let head = provenance_lines(
        base.provenance(),
        &[
            ("parameter", args.param.clone()),
            ("from", format_number(args.from)),
            ("to", format_number(args.to)),
            ("steps", args.steps.to_string()),
            ("revs", turns.to_string()),
            ("transient_revs", args.transient.to_string()),
            ("phase_rad", format_number(args.phase)),
            ("observe", args.observe.clone()),
        ],
    );
    // Header row first, then the provenance (as every result CSV); the whole head is a prefix
    // that `--resume` matches and skips.
    let data_head = format!("index,{},turn,{}\n{head}", args.param, args.observe);
    let verdict_head = format!("index,{},verdict,k,message\n{head}", args.param);
    let out = &args.out;
    let verdicts = verdicts_path(out);
    check_output_file(out, Some(&args.model.model))?;
    check_output_file(&verdicts, Some(&args.model.model))?;
    let _lock = OutputLock::acquire(out)?;

    // What is finished: a verdict other than `failed` and all R − M rows. Failed points and
    // partial rows are dropped, so that they run again.
    let per_point = turns - args.transient;
    let mut finished = BTreeSet::new();
    let mut kept = (data_head.clone(), verdict_head.clone());
    if args.resume {
        let data = read_matching(out, &data_head)?;
        let verdict = read_matching(&verdicts, &verdict_head)?;
        if let (Some(data), Some(verdict)) = (&data, &verdict) {
            let rows = rows_by_index(data, data_head.len());
            let marks = rows_by_index(verdict, verdict_head.len());
            finished = marks
                .iter()
                .filter(|(i, m)| {
                    m.len() == 1
                        && !m.iter().any(|line| is_failed(line))
                        && rows.get(i).map_or(0, Vec::len) == per_point
                })
                .map(|(i, _)| *i)
                .collect();
            kept = (
                joined(&data_head, &rows, &finished),
                joined(&verdict_head, &marks, &finished),
            );
        }
    }
    let done: Vec<usize> = finished.iter().copied().collect();
    let todo = analysis::remaining(&grid, args.shard.as_ref(), &done)?;
    let total = done.len() + todo.len();
    eprintln!(
        "{total} points{}: {} finished, {} to run ({} turns each, {} recorded)",
        args.shard
            .map(|s| format!(" in shard {s}"))
            .unwrap_or_default(),
        done.len(),
        todo.len(),
        turns,
        per_point
    );

    let mut appender = Appender {
        data: Pending::new(out, kept.0),
        verdicts: Pending::new(&verdicts, kept.1),
        turns: args.transient..turns,
        bar: progress_bar(todo.len()),
    };
    interrupt::install();
    // A signal only raises the flag: points stop starting, those in flight are written.
    interrupt::defer_to_caller();
    let results = pool.install(|| {
        analysis::run_points_until(
            &grid,
            &todo,
            |_, p| sweep.point(p).map_err(Failure::from),
            |p| appender.append(p),
            interrupt::requested,
        )
    });
    appender.finish();
    let results = results?;
    if results.len() < todo.len() {
        // Only a signal leaves points out of a successful return.
        let kept = done.len() + results.len();
        return Err(Failure {
            code: EXIT_INTERRUPTED,
            message: format!(
                "interrupted: {kept} of {total} points are finished in {} and {}; run the same command with --resume to compute the {} left",
                out.display(),
                verdicts.display(),
                total - kept
            ),
        });
    }

    // Every point of the shard has its verdict: index order, whatever the threads did. (With
    // nothing to run, the kept points are written now.)
    appender.data.open()?;
    appender.verdicts.open()?;
    let mut all: BTreeSet<usize> = finished;
    all.extend(results.iter().map(|p| p.index));
    for (path, head) in [(out, &data_head), (&verdicts, &verdict_head)] {
        let text = std::fs::read_to_string(path).map_err(|e| output_failure(path, &e))?;
        rewrite(path, head, &rows_by_index(&text, head.len()), &all)?;
    }

    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let mut failures = Vec::new();
    for p in &results {
        match &p.result {
            Ok(s) => *counts.entry(s.period.verdict.to_string()).or_default() += 1,
            Err(e) => failures.push(format!(
                "point {} ({} = {}) failed: {}",
                p.index,
                args.param,
                format_number(p.parameter),
                e.message
            )),
        }
    }
    let summary: Vec<String> = counts.iter().map(|(v, n)| format!("{v}: {n}")).collect();
    println!(
        "{} points run to {} and {}; verdicts: {}",
        results.len(),
        out.display(),
        verdicts.display(),
        if summary.is_empty() {
            "none".into()
        } else {
            summary.join(", ")
        }
    );
    if failures.is_empty() {
        return Ok(());
    }
    let n_failed = failures.len();
    let more = n_failed.saturating_sub(FAILURES_LISTED);
    failures.truncate(FAILURES_LISTED);
    if more > 0 {
        failures.push(format!("{more} more failed"));
    }
    Err(Failure {
        code: EXIT_FAILED_POINTS,
        message: format!(
            "{} of {total} points; {}. The failed {} recorded as \"{FAILED}\" with {} in {}; run the same command with --resume to retry only {}",
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
            verdicts.display(),
            if n_failed == 1 { "it" } else { "them" },
        ),
    })
}

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
/// the point finished), flushed to disk, and draws progress on a terminal. A failed point gets
/// `NaN` rows and the verdict `failed` with its message.
struct Appender<'a> {
    data: Pending<'a>,
    verdicts: Pending<'a>,
    /// The recorded turns M..R.
    turns: std::ops::Range<usize>,
    bar: Option<ProgressBar>,
}

impl Appender<'_> {
    fn append(&mut self, p: &SweepPoint<Result<ModelSection, Failure>>) -> Result<(), Failure> {
        let index = p.index.to_string();
        let value = format_number(p.parameter);
        let mut rows = String::new();
        let mark = match &p.result {
            Ok(s) => {
                for (turn, point) in s.turns.iter().zip(&s.section.points) {
                    for v in point {
                        rows.push_str(&format!("{index},{value},{turn},{}\n", format_number(*v)));
                    }
                }
                let (name, k) = verdict_fields(&s.period.verdict);
                format!("{index},{value},{name},{k},\n")
            }
            Err(e) => {
                for turn in self.turns.clone() {
                    rows.push_str(&format!("{index},{value},{turn},NaN\n"));
                }
                let message = csv_field(&escape_line(&e.message));
                format!("{index},{value},{FAILED},0,{message}\n")
            }
        };
        self.data.append(&rows)?;
        self.verdicts.append(&mark)?;
        if let Some(bar) = &self.bar {
            bar.inc(1);
        }
        Ok(())
    }

    fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}

impl From<analysis::AnalysisError> for Failure {
    fn from(e: analysis::AnalysisError) -> Self {
        Failure::from(linkdyn::Error::from(e))
    }
}
