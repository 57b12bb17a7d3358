//! Records the git commit of the build for the provenance lines of result files:
//! `LINKDYN_GIT_COMMIT` is the 12-digit commit, with `-dirty` when the sources that are compiled
//! into the crate (`src/`, `Cargo.toml`, `Cargo.lock`, `build.rs`) differ from it, or `unknown`
//! outside a git checkout of this crate.
//!
//! Cargo reruns this script only when one of the paths it prints with `rerun-if-changed` changes,
//! so the watched set is chosen to match what the commit string depends on, and nothing more:
//! - `HEAD` of this worktree and the file of the branch it points to (or `packed-refs`): a commit
//!   or a checkout changes the commit;
//! - the compiled sources themselves (cargo scans directories): an edit, a revert or a new file
//!   changes `-dirty`, which is computed for exactly these paths.
//!
//! Not watched on purpose: the index (`git status` rewrites it to refresh its stat cache, which
//! made every build after a `git status` recompile the crate), and any path that does not exist
//! (cargo treats a missing watched file as changed, which recompiled every build outside a
//! checkout and in a `git worktree`, where `.git` is a file).

use std::path::{Path, PathBuf};
use std::process::Command;

/// The paths compiled into the crate, relative to the manifest directory.
const SOURCES: &[&str] = &["src", "Cargo.toml", "Cargo.lock", "build.rs"];

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let commit = match describe() {
        Some((commit, watched)) => {
            for path in watched {
                println!("cargo:rerun-if-changed={}", path.display());
            }
            commit
        }
        None => "unknown".to_string(),
    };
    println!("cargo:rustc-env=LINKDYN_GIT_COMMIT={commit}");
}

/// Runs git in `dir` and returns its trimmed stdout if it succeeded.
fn git(dir: &Path, args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .args(args)
        .current_dir(dir)
        .output()
        .ok()
        .filter(|o| o.status.success())?;
    String::from_utf8(out.stdout)
        .ok()
        .map(|s| s.trim().to_string())
}

/// The commit string and the paths whose change must rerun this script; `None` when the crate
/// is not the top of a git worktree (a tarball, or a copy vendored inside another repository,
/// whose commit says nothing about these sources).
fn describe() -> Option<(String, Vec<PathBuf>)> {
    let manifest_dir = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR")?);
    let top = git(&manifest_dir, &["rev-parse", "--show-toplevel"])?;
    let same = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if !same(Path::new(&top), &manifest_dir) {
        return None;
    }
    let commit =
        git(&manifest_dir, &["rev-parse", "--short=12", "HEAD"]).filter(|s| !s.is_empty())?;
    let mut status = vec!["status", "--porcelain", "--"];
    status.extend(SOURCES);
    let dirty = git(&manifest_dir, &status).is_some_and(|s| !s.is_empty());

    let git_dir = PathBuf::from(git(&manifest_dir, &["rev-parse", "--absolute-git-dir"])?);
    let common_dir = git(
        &manifest_dir,
        &["rev-parse", "--path-format=absolute", "--git-common-dir"],
    )
    .map_or_else(|| git_dir.clone(), PathBuf::from);
    let mut watched = vec![git_dir.join("HEAD")];
    if let Some(branch) = git(&manifest_dir, &["symbolic-ref", "-q", "HEAD"]) {
        watched.push(common_dir.join(branch));
    }
    watched.push(common_dir.join("packed-refs"));
    watched.extend(SOURCES.iter().map(|s| manifest_dir.join(s)));
    watched.retain(|p| p.exists());
    let suffix = if dirty { "-dirty" } else { "" };
    Some((format!("{commit}{suffix}"), watched))
}
