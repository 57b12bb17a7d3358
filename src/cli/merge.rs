//! `linkdyn merge F1.csv F2.csv … --out F.csv`: joins the shard files of one bifurcation sweep
//! (and their `.verdicts.csv` files) into one, in index order, after checking that they come
//! from the same sweep (identical `#` lines and header), hold every grid point exactly once
//! ([`linkdyn::analysis::merge`]) and every point whole: `revs − transient_revs` rows (one per
//! recorded turn) in the data, one in the verdicts. The result equals the file of an unsharded
//! run byte for byte. `--out` may not name one of the files it reads (their verdicts included),
//! however spelled: it is written only after all are read, but a failed merge must leave the
//! inputs as they were.

use super::Failure;
use super::bifurcation::verdicts_path;
use super::poincare::{bad, write_whole};
use clap::Args;
use linkdyn::analysis::{self, ParameterGrid, SweepPoint};
use linkdyn::output::same_file;
use std::path::{Path, PathBuf};

/// Arguments of `merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Shard result files of one sweep (`bifurcation --shard i/n --out Fi.csv`).
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Merged CSV; the verdicts go to `F.verdicts.csv`.
    #[arg(long)]
    out: PathBuf,
}

/// A result file split into its head (`#` lines and the header row) and its rows.
struct Parsed {
    head: String,
    rows: Vec<String>,
}

fn parse(path: &Path) -> Result<Parsed, Failure> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| bad("files", format!("cannot read {}: {e}", path.display())))?;
    // The head: the header row and the `#` lines around it (header first as written now;
    // `#` lines first in files of earlier versions).
    let mut head = String::new();
    let mut lines = text.split_inclusive('\n').peekable();
    let mut header_seen = false;
    while let Some(line) = lines.peek() {
        if line.starts_with('#') {
            head.push_str(line);
        } else if !header_seen {
            head.push_str(line);
            header_seen = true;
        } else {
            break;
        }
        lines.next();
    }
    let rows: Vec<String> = lines.map(str::to_string).collect();
    if let Some(last) = rows.last()
        && !last.ends_with('\n')
    {
        return Err(bad(
            "files",
            format!(
                "{}: the last row is cut off (an interrupted shard: finish it with --resume)",
                path.display()
            ),
        ));
    }
    Ok(Parsed { head, rows })
}

/// A `# key = value` setting of the head.
fn setting<'h>(head: &'h str, key: &str) -> Option<&'h str> {
    head.lines()
        .filter_map(|l| l.strip_prefix("# "))
        .find_map(|l| l.strip_prefix(key)?.strip_prefix(" = "))
}

/// The sweep's grid from the head's `from`, `to` and `steps` settings.
fn grid(head: &str, path: &Path) -> Result<ParameterGrid, Failure> {
    let value = |key: &str| {
        setting(head, key).ok_or_else(|| {
            bad(
                "files",
                format!(
                    "{} has no \"# {key} = …\" line: not a bifurcation result file",
                    path.display()
                ),
            )
        })
    };
    let number = |key: &str| -> Result<f64, Failure> {
        value(key)?
            .parse()
            .map_err(|_| bad("files", format!("{}: unreadable {key}", path.display())))
    };
    let steps: usize = value("steps")?
        .parse()
        .map_err(|_| bad("files", format!("{}: unreadable steps", path.display())))?;
    Ok(ParameterGrid::new(number("from")?, number("to")?, steps)?)
}

/// Rows of one sweep point in a data file: one per recorded turn, `revs − transient_revs`.
fn rows_per_point(head: &str, path: &Path) -> Result<usize, Failure> {
    let count = |key: &str| -> Result<usize, Failure> {
        setting(head, key)
            .and_then(|v| v.parse().ok())
            .ok_or_else(|| {
                bad(
                    "files",
                    format!(
                        "{} has no readable \"# {key} = …\" line: not a bifurcation result file",
                        path.display()
                    ),
                )
            })
    };
    let (revs, transient) = (count("revs")?, count("transient_revs")?);
    revs.checked_sub(transient)
        .filter(|&n| n > 0)
        .ok_or_else(|| {
            bad(
                "files",
                format!(
                    "{}: revs = {revs} is not above transient_revs = {transient}",
                    path.display()
                ),
            )
        })
}

/// What a file of a sweep holds per point.
#[derive(Clone, Copy)]
enum Kind {
    /// The data: one row per recorded turn.
    Data,
    /// The verdicts: one row per point.
    Verdicts,
}

/// Merges `files` (all with the same head) into one text, checking every point once and
/// whole (its expected number of rows, by `kind`).
fn merge_files(files: &[PathBuf], kind: Kind) -> Result<String, Failure> {
    let mut parsed = Vec::with_capacity(files.len());
    for f in files {
        parsed.push((f, parse(f)?));
    }
    let Some((first_path, first)) = parsed.first() else {
        return Err(bad("files", "expected at least one file"));
    };
    let grid = grid(&first.head, first_path)?;
    let per_point = match kind {
        Kind::Data => rows_per_point(&first.head, first_path)?,
        Kind::Verdicts => 1,
    };
    let mut parts = Vec::with_capacity(parsed.len());
    for (path, p) in &parsed {
        if p.head != first.head {
            let differs = p
                .head
                .lines()
                .zip(first.head.lines())
                .find(|(a, b)| a != b)
                .map(|(a, b)| format!(": \"{a}\" where {} has \"{b}\"", first_path.display()))
                .unwrap_or_default();
            return Err(bad(
                "files",
                format!(
                    "{} is not from the same sweep as {}{differs}",
                    path.display(),
                    first_path.display()
                ),
            ));
        }
        // One sweep point per index: its consecutive rows.
        let mut points: Vec<SweepPoint<Vec<&str>>> = Vec::new();
        for row in &p.rows {
            let mut fields = row.split(',');
            let index = fields.next().and_then(|s| s.parse::<usize>().ok());
            let parameter = fields.next().and_then(|s| s.trim().parse::<f64>().ok());
            let (Some(index), Some(parameter)) = (index, parameter) else {
                return Err(bad(
                    "files",
                    format!("{}: unreadable row \"{}\"", path.display(), row.trim_end()),
                ));
            };
            match points.last_mut() {
                Some(last) if last.index == index => last.result.push(row),
                _ => points.push(SweepPoint {
                    index,
                    parameter,
                    result: vec![row],
                }),
            }
        }
        // A point with rows lost (a truncated or edited shard) or added is not whole.
        if let Some(p) = points.iter().find(|p| p.result.len() != per_point) {
            let what = match kind {
                Kind::Data => "one per recorded turn, revs − transient_revs",
                Kind::Verdicts => "one verdict per point",
            };
            return Err(bad(
                "files",
                format!(
                    "{}: point {} has {} row{}, expected {per_point} ({what}): the file lost or gained rows",
                    path.display(),
                    p.index,
                    p.result.len(),
                    if p.result.len() == 1 { "" } else { "s" }
                ),
            ));
        }
        parts.push(points);
    }
    let merged = analysis::merge(&grid, parts)?;
    let mut text = first.head.clone();
    for p in merged {
        for row in p.result {
            text.push_str(row);
        }
    }
    Ok(text)
}

/// Runs `merge`.
pub fn run(args: &MergeArgs) -> Result<(), Failure> {
    let verdict_files: Vec<PathBuf> = args.files.iter().map(|f| verdicts_path(f)).collect();
    let outputs = [args.out.clone(), verdicts_path(&args.out)];
    for input in args.files.iter().chain(&verdict_files) {
        if let Some(out) = outputs.iter().find(|o| *o == input || same_file(o, input)) {
            return Err(bad(
                "out",
                format!(
                    "{} would overwrite {}, one of the files to merge; choose another name",
                    out.display(),
                    input.display()
                ),
            ));
        }
    }
    let have_verdicts = verdict_files.iter().all(|f| f.exists());
    // The verdicts mark finished points: check them first, so that an unfinished shard is
    // reported as missing points.
    let verdicts = if have_verdicts {
        Some(merge_files(&verdict_files, Kind::Verdicts)?)
    } else {
        None
    };
    let data = merge_files(&args.files, Kind::Data)?;
    let model = Path::new("");
    write_whole(&args.out, model, &data)?;
    if let Some(v) = verdicts {
        write_whole(&verdicts_path(&args.out), model, &v)?;
    }
    eprintln!(
        "{} files merged to {}{}",
        args.files.len(),
        args.out.display(),
        if have_verdicts {
            format!(" and {}", verdicts_path(&args.out).display())
        } else {
            String::new()
        }
    );
    Ok(())
}
