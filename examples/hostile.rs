//! The seeded hostile-input run (results that never lie): `cargo run --release --example hostile -- --count
//! 2000 --seed S` builds `count` mutants of the shipped models and settings (seeds S, S+1, …),
//! runs each with the release `linkdyn` binary (build it first: `cargo build --release`) and
//! prints every broken promise (panic, hang, exit 0 with bad results, files left after a
//! failure) with its seed, then a tally by exit code. Exit 1 if anything broke.

#[path = "../tests/hostile/mod.rs"]
mod hostile;

use std::collections::BTreeMap;

fn main() -> std::process::ExitCode {
    let args: Vec<String> = std::env::args().collect();
    let value = |flag: &str, default: u64| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1))
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    let (count, seed) = (value("--count", 100), value("--seed", 1));
    let binary = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/release/linkdyn");
    let scratch = std::env::temp_dir().join(format!("linkdyn-hostile-ex-{}", std::process::id()));
    let mut tally: BTreeMap<String, usize> = BTreeMap::new();
    let mut broken = 0;
    for s in seed..seed + count {
        let m = hostile::mutant(s);
        match hostile::check(&binary, &scratch, &m) {
            Ok(code) => *tally.entry(format!("exit {code}")).or_default() += 1,
            Err(why) => {
                broken += 1;
                println!(
                    "seed {s} ({} with {:?}, {:?}): {why}",
                    m.base, m.mutations, m.args
                );
            }
        }
    }
    let _ = std::fs::remove_dir_all(&scratch);
    println!("{count} mutants from seed {seed}: {tally:?}, {broken} broken");
    if broken == 0 {
        std::process::ExitCode::SUCCESS
    } else {
        std::process::ExitCode::FAILURE
    }
}
