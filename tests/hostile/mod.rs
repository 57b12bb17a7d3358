//! Shared by `tests/hostile_models.rs` and `examples/hostile.rs`: seeded mutations of the
//! shipped models and settings, one run of the built `linkdyn` binary per mutant, and the
//! verdict on what it left behind.
//!
//! The contract checked ("results that never lie"): no panic (exit 101 or
//! "panicked" on stderr), no hang (killed after [`HANG_LIMIT`]), exit 0 only with both whole
//! result files and a JSON `max_constraint_violation` within the bound of
//! `linkdyn::formulation::Dae::violation_limits`, and exit 2, 3 or 4 with no result or
//! temporary file left in the output directory.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A run that has not ended after this long hangs: `--max-wall 5` bounds the integration,
/// the rest (parsing, assembly, writing) takes milliseconds.
pub const HANG_LIMIT: Duration = Duration::from_secs(60);

/// The shipped models the mutations start from.
pub const MODELS: &[&str] = &[
    "models/pendulum.toml",
    "models/double_pendulum.toml",
    "models/fourbar_ideal.toml",
    "models/slider_crank.toml",
    "models/slider_crank_clearance.toml",
    "models/farahan2016.toml",
    "models/flores2007.toml",
];

/// xorshift64*: a small deterministic generator, so that a seed names a mutant forever.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator from `seed` (any value; 0 is remapped).
    pub fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    /// Next 64 random bits.
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    /// Uniform index below `n` (n > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
    /// One element of `items`.
    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// Factors a number is scaled by: extreme, signed, zero, non-finite.
const FACTORS: &[f64] = &[
    0.0,
    -1.0,
    1e-300,
    1e-12,
    1e-3,
    0.5,
    2.0,
    1e3,
    1e12,
    1e300,
    f64::INFINITY,
    f64::NAN,
];

/// Paths to every leaf of a TOML value (keys and array indices).
fn leaves(value: &toml::Value, path: &mut Vec<Key>, out: &mut Vec<Vec<Key>>) {
    match value {
        toml::Value::Table(t) => {
            out.push(path.clone());
            for (k, v) in t {
                path.push(Key::Name(k.clone()));
                leaves(v, path, out);
                path.pop();
            }
        }
        toml::Value::Array(a) => {
            out.push(path.clone());
            for (i, v) in a.iter().enumerate() {
                path.push(Key::Index(i));
                leaves(v, path, out);
                path.pop();
            }
        }
        _ => out.push(path.clone()),
    }
}

/// One step of a path into a TOML document.
#[derive(Debug, Clone)]
enum Key {
    Name(String),
    Index(usize),
}

fn get_mut<'a>(value: &'a mut toml::Value, path: &[Key]) -> Option<&'a mut toml::Value> {
    let mut v = value;
    for k in path {
        v = match (k, v) {
            (Key::Name(n), toml::Value::Table(t)) => t.get_mut(n)?,
            (Key::Index(i), toml::Value::Array(a)) => a.get_mut(*i)?,
            _ => return None,
        };
    }
    Some(v)
}

/// Applies one random mutation to the document; returns what it did.
fn mutate_once(doc: &mut toml::Value, rng: &mut Rng) -> String {
    let mut paths = Vec::new();
    leaves(doc, &mut Vec::new(), &mut paths);
    let path = rng.pick(&paths).clone();
    let name = format!("{path:?}");
    let op = rng.below(7);
    if op == 0 && !path.is_empty() {
        // Delete the field or array element.
        let (last, parent) = path.split_last().unwrap_or_else(|| unreachable!());
        if let Some(p) = get_mut(doc, parent) {
            match (last, p) {
                (Key::Name(n), toml::Value::Table(t)) => {
                    t.remove(n);
                }
                (Key::Index(i), toml::Value::Array(a)) if *i < a.len() => {
                    a.remove(*i);
                }
                _ => {}
            }
        }
        return format!("delete {name}");
    }
    let Some(v) = get_mut(doc, &path) else {
        return "none".into();
    };
    match (op, &mut *v) {
        (1 | 2, toml::Value::Float(x)) => {
            let f = *rng.pick(FACTORS);
            *x *= f;
            format!("scale {name} by {f}")
        }
        (1 | 2, toml::Value::Integer(i)) => {
            *i = i.wrapping_mul(*rng.pick(&[-1, 0, 1000, i64::MAX]));
            format!("scale int {name}")
        }
        (3, toml::Value::Array(a)) => {
            // Lengthen a vector (or duplicate an array-of-tables entry: duplicate names).
            let extra = a.first().cloned().unwrap_or(toml::Value::Float(1.0));
            a.push(extra);
            format!("lengthen {name}")
        }
        (4, toml::Value::String(s)) => {
            let new = rng
                .pick(&["", "x", "ground", "crank", "O", "a b", "ü", "rod"])
                .to_string();
            *s = new.clone();
            format!("rename {name} to {new:?}")
        }
        (5, _) => {
            // Retype.
            let new = match v {
                toml::Value::String(_) => toml::Value::Float(1.0),
                toml::Value::Float(_) | toml::Value::Integer(_) => {
                    toml::Value::String("1.0".into())
                }
                _ => toml::Value::Float(0.0),
            };
            *v = new;
            format!("retype {name}")
        }
        (_, toml::Value::Float(x)) => {
            *x = -*x;
            format!("flip {name}")
        }
        _ => "none".into(),
    }
}

/// One mutant: the model text and the command-line settings.
#[derive(Debug, Clone)]
pub struct Mutant {
    /// Seed it came from.
    pub seed: u64,
    /// The shipped model it started from.
    pub base: &'static str,
    /// What was done, in order.
    pub mutations: Vec<String>,
    /// The mutated model file.
    pub text: String,
    /// Extra arguments of `linkdyn run` (end time, tolerances, sampling, method).
    pub args: Vec<String>,
}

/// The mutant of `seed`: 0 to 5 mutations of one shipped model, and settings inside and
/// beyond their ranges.
pub fn mutant(seed: u64) -> Mutant {
    let mut rng = Rng::new(seed);
    let base = *rng.pick(MODELS);
    let text = std::fs::read_to_string(base).unwrap_or_default();
    let mut doc: toml::Value = toml::from_str(&text).unwrap_or(toml::Value::Boolean(false));
    let mut mutations = Vec::new();
    for _ in 0..rng.below(6) {
        mutations.push(mutate_once(&mut doc, &mut rng));
    }
    let text = toml::to_string(&doc).unwrap_or_default();
    let num = |rng: &mut Rng, values: &[&str]| rng.pick(values).to_string();
    let mut args = Vec::new();
    if rng.below(2) == 0 {
        args.push("--revs".into());
        args.push(num(
            &mut rng,
            &["0.02", "0.05", "0.1", "0.3", "0", "-1", "1e-9", "nan"],
        ));
    } else {
        args.push("--t-end".into());
        args.push(num(
            &mut rng,
            &["0.02", "0.05", "0.1", "0.3", "0", "-1", "inf", "1e-300"],
        ));
    }
    for (flag, values) in [
        (
            "--rtol",
            &["1e-4", "1e-8", "1e-12", "0.1", "0.5", "0", "1e-300", "nan"][..],
        ),
        (
            "--atol",
            &["1e-4", "1e-10", "1e-14", "1", "2", "0", "-1"][..],
        ),
        (
            "--dt",
            &["1e-3", "1e-2", "1e-4", "0", "1e-12", "-1", "inf"][..],
        ),
    ] {
        if rng.below(3) == 0 {
            args.push(flag.into());
            args.push(num(&mut rng, values));
        }
    }
    if rng.below(2) == 0 {
        args.push("--method".into());
        args.push(num(&mut rng, &["dopri5", "dop853"]));
    }
    Mutant {
        seed,
        base,
        mutations,
        text,
        args,
    }
}

/// Runs `binary` on the mutant in a fresh directory under `scratch`; returns `Err` with the
/// broken promise, or `Ok(exit code)`.
pub fn check(binary: &Path, scratch: &Path, m: &Mutant) -> Result<i32, String> {
    let dir = scratch.join(format!("m{}", m.seed));
    let out_dir = dir.join("out");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&out_dir).map_err(|e| format!("scratch: {e}"))?;
    let model = dir.join("model.toml");
    std::fs::write(&model, &m.text).map_err(|e| format!("scratch: {e}"))?;
    let csv = out_dir.join("r.csv");
    let mut child = Command::new(binary)
        .arg("run")
        .arg(&model)
        .args(&m.args)
        .args(["--max-wall", "5", "--out"])
        .arg(&csv)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("spawn: {e}"))?;
    let started = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(s)) => break s,
            Ok(None) if started.elapsed() > HANG_LIMIT => {
                let _ = child.kill();
                let _ = child.wait();
                return Err(format!("hung for more than {HANG_LIMIT:?}"));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(5)),
            Err(e) => return Err(format!("wait: {e}")),
        }
    };
    let mut stderr = String::new();
    if let Some(mut s) = child.stderr.take() {
        use std::io::Read;
        let _ = s.read_to_string(&mut stderr);
    }
    let code = status.code().unwrap_or(-1);
    if code == 101 || stderr.contains("panicked") {
        return Err(format!("panic (exit {code}): {stderr}"));
    }
    let left: Vec<PathBuf> = std::fs::read_dir(&out_dir)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    let verdict = match code {
        0 => whole_results(&model, &csv, &m.args, &left),
        2..=4 => {
            if left.is_empty() {
                Ok(code)
            } else {
                Err(format!("exit {code} left {left:?}: {stderr}"))
            }
        }
        _ => Err(format!("unexpected exit {code}: {stderr}")),
    };
    let _ = std::fs::remove_dir_all(&dir);
    verdict
}

/// Exit 0: exactly the three result files (CSV, JSON summary, impact log), a CSV ending in a
/// whole line, a JSON that parses, and a constraint violation within the bound.
fn whole_results(
    model: &Path,
    csv: &Path,
    args: &[String],
    left: &[PathBuf],
) -> Result<i32, String> {
    let json = csv.with_extension("json");
    let impacts = csv.with_extension("impacts.csv");
    if left.len() != 3 || !csv.exists() || !json.exists() || !impacts.exists() {
        return Err(format!("exit 0 but the output directory holds {left:?}"));
    }
    let text = std::fs::read_to_string(csv).map_err(|e| format!("csv: {e}"))?;
    if !text.ends_with('\n') {
        return Err("exit 0 with a CSV that does not end in a whole line".into());
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).map_err(|e| format!("json: {e}"))?)
            .map_err(|e| format!("exit 0 with a JSON that does not parse: {e}"))?;
    let violation = summary["max_constraint_violation"]
        .as_f64()
        .ok_or("exit 0 without a numeric max_constraint_violation")?;
    let tol = |flag: &str, default: f64| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1))
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    // The bound is formed with the tolerances the method controls (Radau5: Hairer's transform).
    let method: linkdyn::solve::Method = args
        .iter()
        .position(|a| a == "--method")
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(linkdyn::solve::SolverOptions::default().method);
    let linkdyn::formulation::Tolerances { rtol, atol } = linkdyn::solve::SolverOptions::default()
        .method(method)
        .rtol(tol("--rtol", 1e-8))
        .atol(tol("--atol", 1e-10))
        .controlled_tolerances();
    let model = linkdyn::model::load(model, &[]).map_err(|e| format!("reload: {e}"))?;
    let dae = linkdyn::formulation::Dae::new(&model, &Default::default())
        .map_err(|e| format!("rebuild: {e}"))?;
    let (m, rad) = dae.violation_limits(rtol, atol);
    if violation.is_nan() || violation > m.max(rad) {
        return Err(format!(
            "exit 0 with max |Φ| = {violation:e} beyond the bound {:e}",
            m.max(rad)
        ));
    }
    Ok(0)
}
