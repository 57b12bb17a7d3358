//! `linkdyn reproduce --out DIR [--quick] [--model M]`: the analogues of Figs. 3–7 of Farahan et
//! al. (2016) for each friction variant, with `DIR/report.md` judging the paper's claims
//! ([`linkdyn::reproduce`]). The directory appears whole: everything is written into a
//! temporary sibling, which is renamed to DIR at the end.

use super::Failure;
use clap::Args;
use linkdyn::Error;
use linkdyn::output::{AtomicFile, OutputError};
use linkdyn::reproduce::{ReproduceOptions, report};
use std::path::{Path, PathBuf};

/// Arguments of `reproduce`.
#[derive(Debug, Args)]
pub struct ReproduceArgs {
    /// Output directory (created; a previous reproduction there, one with a report.md, is
    /// replaced; any other existing path is refused).
    #[arg(long)]
    out: PathBuf,
    /// Short runs (under two minutes; CI): fewer turns and 6 sweep points instead of 200.
    #[arg(long)]
    quick: bool,
    /// The paper's model file. By default models/farahan2016.toml of the current directory,
    /// else of the source tree linkdyn was built from.
    #[arg(long, default_value = DEFAULT_MODEL)]
    model: PathBuf,
}

/// The paper's model, relative to the repository root.
const DEFAULT_MODEL: &str = "models/farahan2016.toml";

/// The model to reproduce with: the one given, or the default found from any directory (in
/// the current one, else in the source tree the binary was built from, where `cargo install
/// --path .` leaves it); checked before any directory is made.
fn model_path(given: &Path) -> Result<PathBuf, Failure> {
    if given != Path::new(DEFAULT_MODEL) || given.is_file() {
        return Ok(given.to_path_buf());
    }
    let built = Path::new(env!("CARGO_MANIFEST_DIR")).join(DEFAULT_MODEL);
    if built.is_file() {
        eprintln!("reproduce: model {}", built.display());
        return Ok(built);
    }
    Err(Failure {
        code: super::EXIT_BAD_INPUT,
        message: format!(
            "the paper's model {DEFAULT_MODEL} is neither in the current directory nor in the source tree linkdyn was built from ({}); run from the repository root or give --model PATH",
            built.display()
        ),
    })
}

fn io(path: &Path, e: std::io::Error) -> Failure {
    Failure::from(OutputError::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    })
}

/// Runs `reproduce`.
pub fn run(args: &ReproduceArgs) -> Result<(), Failure> {
    let model = model_path(&args.model)?;
    let out = &args.out;
    if out.exists() && !out.join("report.md").is_file() {
        return Err(Failure::from(OutputError::Target {
            path: out.display().to_string(),
            reason:
                "exists and is not a previous reproduction (no report.md); choose a new directory"
                    .into(),
        }));
    }
    let mut temp = out.as_os_str().to_owned();
    temp.push(format!(".{}.tmp", std::process::id()));
    let temp = PathBuf::from(temp);
    std::fs::create_dir_all(&temp).map_err(|e| io(&temp, e))?;
    let result = build(args, &model, &temp);
    if let Err(e) = result {
        let _ = std::fs::remove_dir_all(&temp);
        return Err(e);
    }
    // Swap in the new directory; the old one (if any) is removed only after the rename.
    let mut old = out.as_os_str().to_owned();
    old.push(format!(".{}.old", std::process::id()));
    let old = PathBuf::from(old);
    if out.exists() {
        std::fs::rename(out, &old).map_err(|e| io(out, e))?;
    }
    std::fs::rename(&temp, out).map_err(|e| io(out, e))?;
    if old.exists() {
        let _ = std::fs::remove_dir_all(&old);
    }
    println!("report: {}", out.join("report.md").display());
    Ok(())
}

fn build(args: &ReproduceArgs, model: &Path, dir: &Path) -> Result<(), Failure> {
    let opts = ReproduceOptions {
        model: model.to_path_buf(),
        quick: args.quick,
    };
    let mut log = |line: &str| eprintln!("reproduce: {line}");
    let findings = linkdyn::reproduce::reproduce(&opts, dir, &mut log)
        .map_err(|e| super::in_model(model, e))?;
    let mut md = AtomicFile::create(&dir.join("report.md"))?;
    md.write_str(&report::markdown(&findings))?;
    md.commit()?;
    let json = serde_json::to_string_pretty(&findings).map_err(|e| {
        Failure::from(Error::from(OutputError::Io {
            path: dir.join("findings.json").display().to_string(),
            reason: e.to_string(),
        }))
    })?;
    let mut js = AtomicFile::create(&dir.join("findings.json"))?;
    js.write_str(&json)?;
    js.commit()?;
    eprintln!("reproduce: done in {:.1} s", findings.wall_s);
    Ok(())
}
