//! `linkdyn bifurcation MODEL --param PATH --from A --to B --steps N --revs R --transient M
//! --observe COL --out F.csv [--resume] [--shard i/n] [--threads K]`: a bifurcation diagram.
//!
//! Each of the N + 1 parameter values loads the model with the extra override `PATH=value`,
//! integrates R driver turns and records the observed column once per turn after M transient
//! turns (its Poincaré points), with the point's period verdict. Points run in parallel; each
//! finished point is appended to `F.csv` (`index,<param>,turn,<col>`, R − M rows) and then to
//! `F.verdicts.csv` (`index,<param>,verdict,k`), both flushed to disk. The verdict row marks a
//! point as finished: `--resume` keeps the points that have their verdict and all their rows,
//! drops any partial rows, and runs only the rest. When every point of the shard is done, both
//! files are rewritten in index order, so the result does not depend on the threads, and shard
//! files merged with `linkdyn merge` equal an unsharded run byte for byte.
//!
//! **Ctrl-C** (SIGINT, SIGTERM, SIGHUP): no new point starts, the points in flight finish and
//! are appended, and the command exits with code 130 saying how many points are on disk and
//! that `--resume` continues; a second signal stops at once (the finished points are on disk,
//! a cut-off row is dropped by `--resume`). The files then hold the finished points in order
//! of completion; `--resume` puts them in index order.

use super::poincare::{ModelArgs, bad, provenance_lines};
use super::{EXIT_INTERRUPTED, EXIT_OUTPUT, Failure, interrupt};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use linkdyn::analysis::{self, ParameterGrid, PeriodVerdict, Shard, SweepPoint};
use linkdyn::output::{AtomicFile, OutputLock, check_output_file, format_number};
use linkdyn::simulation::analyses::{ModelSection, SectionSpec, Sweep};
use linkdyn::simulation::{EndTime, Simulation, SimulationOptions};
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

/// Runs `bifurcation`.
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
    let first = sweep
        .simulation(args.from)
        .map_err(|e| prefixed(e, &format!("--param {}", args.param)))?;
    if !first.column_names().iter().any(|c| c == &args.observe) {
        return Err(bad(
            "observe",
            format!(
                "no output column \"{}\"; the columns are {}",
                args.observe,
                first.column_names().join(", ")
            ),
        ));
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
    let verdict_head = format!("index,{},verdict,k\n{head}", args.param);
    let out = &args.out;
    let verdicts = verdicts_path(out);
    check_output_file(out, Some(&args.model.model))?;
    check_output_file(&verdicts, Some(&args.model.model))?;
    let _lock = OutputLock::acquire(out)?;

    // What is finished: a verdict row and all R − M rows.
    let per_point = turns - args.transient;
    let mut finished = BTreeSet::new();
    if args.resume {
        let data = read_matching(out, &data_head)?;
        let verdict = read_matching(&verdicts, &verdict_head)?;
        if let (Some(data), Some(verdict)) = (&data, &verdict) {
            let rows = rows_by_index(data, data_head.len());
            let marks = rows_by_index(verdict, verdict_head.len());
            finished = marks
                .iter()
                .filter(|(i, m)| m.len() == 1 && rows.get(i).map_or(0, Vec::len) == per_point)
                .map(|(i, _)| *i)
                .collect();
            rewrite(out, &data_head, &rows, &finished)?;
            rewrite(&verdicts, &verdict_head, &marks, &finished)?;
        }
    }
    if finished.is_empty() {
        let empty = BTreeMap::new();
        rewrite(out, &data_head, &empty, &finished)?;
        rewrite(&verdicts, &verdict_head, &empty, &finished)?;
    }
    let done: Vec<usize> = finished.iter().copied().collect();
    let todo = analysis::remaining(&grid, args.shard.as_ref(), &done)?;
    eprintln!(
        "{} points{}: {} finished, {} to run ({} turns each, {} recorded)",
        args.shard.map_or(grid.len(), |s| s.select(&grid).len()),
        args.shard
            .map(|s| format!(" in shard {s}"))
            .unwrap_or_default(),
        done.len(),
        todo.len(),
        turns,
        per_point
    );

    let mut appender = Appender::open(out, &verdicts, &args.param, todo.len())?;
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
        let total = done.len() + todo.len();
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

    // Every point of the shard is done: index order, whatever the threads did.
    let all: BTreeSet<usize> = (0..grid.len()).collect();
    let data = std::fs::read_to_string(out).map_err(|e| output_failure(out, &e))?;
    rewrite(
        out,
        &data_head,
        &rows_by_index(&data, data_head.len()),
        &all,
    )?;
    let verdict = std::fs::read_to_string(&verdicts).map_err(|e| output_failure(&verdicts, &e))?;
    rewrite(
        &verdicts,
        &verdict_head,
        &rows_by_index(&verdict, verdict_head.len()),
        &all,
    )?;

    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    for p in &results {
        if let Ok(s) = &p.result {
            *counts.entry(s.period.verdict.to_string()).or_default() += 1;
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
    Ok(())
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

/// Appends each finished point to the two files (data rows first, then the verdict that marks
/// the point finished), flushed to disk, and draws progress on a terminal.
struct Appender<'a> {
    data: (File, &'a Path),
    verdicts: (File, &'a Path),
    param: &'a str,
    bar: Option<ProgressBar>,
}

impl<'a> Appender<'a> {
    fn open(out: &'a Path, verdicts: &'a Path, param: &'a str, n: usize) -> Result<Self, Failure> {
        let open = |p: &Path| {
            OpenOptions::new()
                .append(true)
                .open(p)
                .map_err(|e| output_failure(p, &e))
        };
        let bar = std::io::stderr().is_terminal().then(|| {
            let bar = ProgressBar::with_draw_target(Some(n as u64), ProgressDrawTarget::stderr());
            let style = ProgressStyle::with_template("{wide_bar} {pos}/{len} points, {eta} left")
                .unwrap_or_else(|_| ProgressStyle::default_bar());
            bar.set_style(style);
            bar
        });
        Ok(Appender {
            data: (open(out)?, out),
            verdicts: (open(verdicts)?, verdicts),
            param,
            bar,
        })
    }

    fn append(&mut self, p: &SweepPoint<Result<ModelSection, Failure>>) -> Result<(), Failure> {
        let s = match &p.result {
            Ok(s) => s,
            Err(e) => {
                return Err(Failure {
                    code: e.code,
                    message: format!(
                        "point {} ({} = {}): {}",
                        p.index,
                        self.param,
                        format_number(p.parameter),
                        e.message
                    ),
                });
            }
        };
        let index = p.index.to_string();
        let value = format_number(p.parameter);
        let mut rows = String::new();
        for (turn, point) in s.turns.iter().zip(&s.section.points) {
            for v in point {
                rows.push_str(&format!("{index},{value},{turn},{}\n", format_number(*v)));
            }
        }
        let (name, k) = verdict_fields(&s.period.verdict);
        let mark = format!("{index},{value},{name},{k}\n");
        for ((file, path), text) in [(&mut self.data, rows), (&mut self.verdicts, mark)] {
            file.write_all(text.as_bytes())
                .and_then(|()| file.sync_data())
                .map_err(|e| output_failure(path, &e))?;
        }
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
