//! Names of the scratch files a writer keeps beside its targets, and their removal once the
//! writer is gone.
//!
//! A temporary file of a target `F` is `.F.linkdyn-<pid>-<nonce>.tmp` in F's directory, and
//! the backup of the earlier `F` kept during a commit is `.F.linkdyn-<pid>-<nonce>.old`:
//! hidden, created exclusively (`O_EXCL`: never an existing file, never through a planted
//! link), and named after the process that writes them. A process that is killed outright
//! (SIGKILL, an out-of-memory kill, a power cut) cannot remove them; the next process that
//! takes the target's lock ([`super::OutputLock`]) removes those of its target's files whose
//! writer has died ([`remove_stale`]). The pid is what tells: a writer still alive keeps its
//! files, and so does a new process that happens to have been given the same pid (a file left
//! for longer, never one removed while in use); the random nonce keeps two files of one pid
//! apart.

use std::collections::hash_map::RandomState;
use std::hash::{BuildHasher, Hasher};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// What a scratch file is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    /// New content, renamed over the target at the commit.
    Temp,
    /// The earlier target, kept (hard link) until the commit is through.
    Backup,
}

impl Kind {
    fn suffix(self) -> &'static str {
        match self {
            Kind::Temp => "tmp",
            Kind::Backup => "old",
        }
    }
}

/// Marks the writer in a scratch file's name.
const TAG: &str = ".linkdyn-";

/// A fresh name for a scratch file of `target`: `.F.linkdyn-<pid>-<nonce>.tmp` (or `.old`)
/// beside it. Create it with `create_new` and ask again if it exists.
pub(crate) fn scratch_path(target: &Path, kind: Kind) -> PathBuf {
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let file = format!(
        ".{name}{TAG}{}-{:016x}.{}",
        std::process::id(),
        nonce(),
        kind.suffix()
    );
    match target.parent() {
        Some(dir) => dir.join(file),
        None => PathBuf::from(file),
    }
}

/// A random 64-bit number, different at every call (the standard library's per-process random
/// hash keys, mixed with a counter).
fn nonce() -> u64 {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let mut h = RandomState::new().build_hasher();
    h.write_u64(COUNTER.fetch_add(1, Ordering::Relaxed));
    h.finish()
}

/// A scratch file's name taken apart: the target's file name, the writer's pid and the kind.
/// `None` for any other name.
pub(crate) fn parse(name: &str) -> Option<(&str, u32, Kind)> {
    let rest = name.strip_prefix('.')?;
    let (rest, kind) = if let Some(r) = rest.strip_suffix(".tmp") {
        (r, Kind::Temp)
    } else {
        (rest.strip_suffix(".old")?, Kind::Backup)
    };
    let (target, id) = rest.rsplit_once(TAG)?;
    let (pid, nonce) = id.split_once('-')?;
    let hex = nonce.len() == 16 && nonce.bytes().all(|b| b.is_ascii_hexdigit());
    let pid = pid.parse().ok().filter(|_| hex && !target.is_empty())?;
    Some((target, pid, kind))
}

/// Whether a process `pid` exists (a signal 0 reaches it, or is refused for lack of
/// permission). A number that cannot be a pid (0, or beyond `i32`) is no process: `kill` would
/// read it as a process group.
#[cfg(unix)]
pub(crate) fn pid_alive(pid: u32) -> bool {
    let Ok(pid) = libc::pid_t::try_from(pid) else {
        return false;
    };
    if pid <= 0 {
        return false;
    }
    // SAFETY: kill with signal 0 sends nothing; it only checks that the process exists.
    let r = unsafe { libc::kill(pid, 0) };
    r == 0 || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
}

/// Without a way to ask, every writer counts as alive: nothing is removed.
#[cfg(not(unix))]
pub(crate) fn pid_alive(_pid: u32) -> bool {
    true
}

/// The directory of `target` ("." for a bare file name).
pub(crate) fn dir_of(target: &Path) -> &Path {
    match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// Whether `name` is the file name of `target` or of a file beside it that shares its stem
/// (`r.csv` → `r.json`, `r.impacts.csv`, `r.verdicts.csv`, `r.csv.commit`).
pub(crate) fn related(target: &Path, name: &str) -> bool {
    let own = target.file_name().map(|n| n.to_string_lossy());
    let stem = target
        .file_stem()
        .map(|s| format!("{}.", s.to_string_lossy()));
    own.is_some_and(|o| o == name) || stem.is_some_and(|s| name.starts_with(&s))
}

/// Removes the scratch files of `target` and of the files beside it that share its stem
/// ([`related`]) whose writer has died; returns their names. Call it holding the target's lock.
pub(crate) fn remove_stale(target: &Path) -> Vec<String> {
    let own = std::process::id();
    let Ok(entries) = std::fs::read_dir(dir_of(target)) else {
        return Vec::new();
    };
    let mut removed = Vec::new();
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let Some((of, pid, _)) = parse(&name) else {
            continue;
        };
        if pid != own
            && related(target, of)
            && !pid_alive(pid)
            && std::fs::remove_file(entry.path()).is_ok()
        {
            removed.push(name);
        }
    }
    removed.sort();
    removed
}

/// Flushes the directory of `target` to disk, so that renames and removals in it survive a
/// power cut. Best effort: some file systems refuse to sync a directory, and by the time this
/// runs the renames have happened, so a failure here is no reason to report the write failed.
pub(crate) fn sync_dir(target: &Path) {
    #[cfg(unix)]
    if let Ok(d) = std::fs::File::open(dir_of(target)) {
        let _ = d.sync_all();
    }
    #[cfg(not(unix))]
    let _ = target;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scratch_names_parse_back_and_other_names_do_not() {
        let p = scratch_path(Path::new("out/r.csv"), Kind::Temp);
        let name = p
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        assert_eq!(p.parent(), Some(Path::new("out")));
        assert_eq!(
            parse(&name),
            Some(("r.csv", std::process::id(), Kind::Temp))
        );
        assert_ne!(
            p,
            scratch_path(Path::new("out/r.csv"), Kind::Temp),
            "two names differ"
        );
        assert_eq!(
            parse(".r.json.linkdyn-12-00000000000000ab.old"),
            Some(("r.json", 12, Kind::Backup))
        );
        for other in [
            "r.csv",
            "r.csv.12.tmp",
            ".r.csv.linkdyn-12-ab.tmp",
            ".r.csv.linkdyn-x-00000000000000ab.tmp",
            "..linkdyn-12-00000000000000ab.tmp",
        ] {
            assert_eq!(parse(other), None, "{other}");
        }
    }

    #[test]
    fn only_files_of_dead_writers_sharing_the_stem_are_removed() {
        let dir = std::env::temp_dir().join(format!("linkdyn-scratch-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let _ = std::fs::create_dir_all(&dir);
        // 4194305 = 2^22 + 1 is above the largest pid Linux can give (pid_max ≤ 2^22).
        let dead = ".r.csv.linkdyn-4194305-00000000000000ab.tmp";
        let dead_json = ".r.json.linkdyn-4194305-00000000000000cd.old";
        let alive = format!(".r.csv.linkdyn-{}-00000000000000ef.tmp", std::process::id());
        let other_target = ".s.csv.linkdyn-4194305-00000000000000ab.tmp";
        for f in [dead, dead_json, alive.as_str(), other_target, "r.csv"] {
            let _ = std::fs::write(dir.join(f), "x");
        }
        assert!(!pid_alive(4_194_305) && !pid_alive(0) && !pid_alive(u32::MAX));
        assert!(pid_alive(std::process::id()));
        let removed = remove_stale(&dir.join("r.csv"));
        assert_eq!(removed, [dead, dead_json]);
        let mut left: Vec<String> = std::fs::read_dir(&dir)
            .map(|r| {
                r.flatten()
                    .map(|e| e.file_name().to_string_lossy().into_owned())
                    .collect()
            })
            .unwrap_or_default();
        left.sort();
        assert_eq!(left, [alive.as_str(), other_target, "r.csv"]);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
