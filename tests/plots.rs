//! `linkdyn plot`: every kind of figure comes out as a PNG of the requested size and
//! as an SVG that is well-formed and carries the expected title and axis labels (with units);
//! the orbit's clearance is read from the model named in the run's provenance; bad requests
//! (a missing column, an unknown kind or format) exit 2 with a message naming the file and the
//! column; figures are written atomically (no temporary file left, an earlier figure kept when
//! a request fails). No pixel comparisons: fonts and anti-aliasing may change between plotters
//! versions, the structure may not.

mod cli_common;

use cli_common::scratch;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

const BIN: &str = env!("CARGO_BIN_EXE_linkdyn");

fn linkdyn(args: &[&str]) -> (i32, String) {
    let out = Command::new(BIN)
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap_or_else(|e| panic!("cannot run linkdyn: {e}"));
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn s(p: &Path) -> String {
    p.display().to_string()
}

/// Input files shared by the tests: half a crank turn of the reference four-bar with its
/// clearance joint and of the ideal four-bar (real `linkdyn run` output), and small files in
/// the analysis formats made from the clearance run.
struct Inputs {
    run: PathBuf,
    ideal: PathBuf,
    poincare: PathBuf,
    bifurcation: PathBuf,
    spectrum: PathBuf,
    phase: PathBuf,
    lyapunov: PathBuf,
}

fn inputs() -> &'static Inputs {
    static INPUTS: OnceLock<Inputs> = OnceLock::new();
    INPUTS.get_or_init(|| {
        let dir = scratch("inputs");
        let run = dir.join("run.csv");
        let ideal = dir.join("ideal.csv");
        for (model, out) in [
            ("models/farahan2016.toml", &run),
            ("models/fourbar_ideal.toml", &ideal),
        ] {
            let (code, err) = linkdyn(&[
                "run",
                model,
                "--revs",
                "0.5",
                "--dt",
                "1e-3",
                "--out",
                &s(out),
            ]);
            assert_eq!(code, 0, "run {model}: {err}");
        }
        let text = std::fs::read_to_string(&run).unwrap_or_default();
        let mut lines = text.lines().filter(|l| !l.starts_with('#'));
        let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
        let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
        let col = |name: &str| header.iter().position(|h| *h == name).unwrap_or(0);
        let (t, ex, ey, omega, alpha) = (
            col("t"),
            col("B.ex"),
            col("B.ey"),
            col("coupler.omega"),
            col("coupler.alpha"),
        );
        let write = |name: &str, body: String| {
            let p = dir.join(name);
            assert!(std::fs::write(&p, body).is_ok(), "cannot write {name}");
            p
        };
        let mut poincare = "# every 10th sample\nturn,t,B.ex,B.ey\n".to_string();
        let mut phase = "t,value,rate\n".to_string();
        for (k, r) in rows.iter().enumerate() {
            if k % 10 == 0 {
                poincare += &format!("{},{},{},{}\n", k / 10, r[t], r[ex], r[ey]);
            }
            phase += &format!("{},{},{}\n", r[t], r[omega], r[alpha]);
        }
        let mut bifurcation = "index,drivers.motor.speed_rpm,turn,B.ey\n".to_string();
        let mut spectrum = "frequency_hz,amplitude\n".to_string();
        let mut lyapunov = "t,lambda\n".to_string();
        for i in 0..50 {
            let x = f64::from(i);
            bifurcation += &format!(
                "{},{},{},{}\n",
                i / 5,
                100.0 + 10.0 * f64::from(i / 5),
                i % 5,
                4e-4 + 1e-6 * x
            );
            spectrum += &format!("{},{}\n", 0.5 * x, 1.0 / (1.0 + x));
            lyapunov += &format!("{},{}\n", 0.1 * (x + 1.0), 3.0 + 1.0 / (x + 1.0));
        }
        Inputs {
            poincare: write("poincare.csv", poincare),
            phase: write("phase.csv", phase),
            bifurcation: write("bifurcation.csv", bifurcation),
            spectrum: write("spectrum.csv", spectrum),
            lyapunov: write("lyapunov.csv", lyapunov),
            run,
            ideal,
        }
    })
}

/// Width and height from a PNG's signature and IHDR chunk, or why the bytes are not a PNG.
fn png_size(bytes: &[u8]) -> Result<(u32, u32), String> {
    const SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
    if bytes.len() < 24 || bytes[..8] != SIGNATURE || &bytes[12..16] != b"IHDR" {
        return Err(format!("not a PNG ({} bytes)", bytes.len()));
    }
    let be = |o: usize| u32::from_be_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]);
    Ok((be(16), be(20)))
}

/// Checks that `svg` is one `<svg>` element whose tags are balanced; returns the first
/// problem.
fn check_svg(svg: &str) -> Result<(), String> {
    if !svg.trim_start().starts_with("<svg") {
        return Err("does not start with <svg".into());
    }
    let mut stack: Vec<String> = Vec::new();
    let mut rest = svg;
    while let Some(open) = rest.find('<') {
        let Some(close) = rest[open..].find('>') else {
            return Err("unterminated tag".into());
        };
        let tag = &rest[open + 1..open + close];
        rest = &rest[open + close + 1..];
        if tag.starts_with('?') || tag.starts_with('!') || tag.ends_with('/') {
            continue;
        }
        if let Some(name) = tag.strip_prefix('/') {
            match stack.pop() {
                Some(top) if top == name.trim() => {}
                top => return Err(format!("</{name}> closes {top:?}")),
            }
        } else {
            stack.push(tag.split_whitespace().next().unwrap_or("").to_string());
        }
        if stack.is_empty() && !rest.trim().is_empty() {
            return Err("content after </svg>".into());
        }
    }
    if stack.is_empty() {
        Ok(())
    } else {
        Err(format!("unclosed {stack:?}"))
    }
}

/// Draws `args` into `name.png` and `name.svg` in `dir`; checks the PNG's size and that the
/// SVG is well-formed and contains every text of `texts`. Returns the SVG text.
fn both_formats(dir: &Path, name: &str, args: &[&str], texts: &[&str]) -> String {
    let png = dir.join(format!("{name}.png"));
    let svg = dir.join(format!("{name}.svg"));
    for out in [&png, &svg] {
        let mut a: Vec<String> = vec!["plot".into()];
        a.extend(args.iter().map(|s| s.to_string()));
        a.extend(["--out".into(), s(out)]);
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        let (code, err) = linkdyn(&a);
        assert_eq!(code, 0, "{name} → {}: {err}", out.display());
    }
    let bytes = std::fs::read(&png).unwrap_or_default();
    assert_eq!(png_size(&bytes), Ok((1200, 800)), "{name}: PNG header");
    let text = std::fs::read_to_string(&svg).unwrap_or_default();
    assert_eq!(check_svg(&text), Ok(()), "{name}: SVG structure");
    for t in texts {
        assert!(text.contains(t), "{name}: SVG lacks the text `{t}`");
    }
    text
}

#[test]
fn every_kind_gives_a_png_and_a_well_formed_labelled_svg() {
    let i = inputs();
    let dir = scratch("kinds");
    both_formats(
        &dir,
        "series",
        &[
            "series",
            &s(&i.run),
            "--y",
            "motor.torque",
            "--compare",
            &s(&i.ideal),
        ],
        &[
            "t (s)",
            "motor.torque (N·m)",
            "motor.torque (run.csv)",
            "motor.torque (ideal.csv)",
        ],
    );
    // Eccentricities of the order of the clearance are drawn in mm.
    both_formats(
        &dir,
        "series_lengths",
        &["series", &s(&i.run), "--y", "B.ex,B.ey"],
        &["B.ex, B.ey (mm)"],
    );
    both_formats(
        &dir,
        "orbit",
        &["orbit", &s(&i.run), "--joint", "B"],
        &["B.ex (mm)", "B.ey (mm)", "clearance circle"],
    );
    both_formats(
        &dir,
        "poincare",
        &["poincare", &s(&i.poincare), "--x", "B.ex", "--y", "B.ey"],
        &["Poincaré section", "B.ex (mm)", "B.ey (mm)"],
    );
    both_formats(
        &dir,
        "bifurcation",
        &["bifurcation", &s(&i.bifurcation)],
        &["drivers.motor.speed_rpm", "B.ey (mm)"],
    );
    both_formats(
        &dir,
        "spectrum",
        &["spectrum", &s(&i.spectrum), "--log", "--driving-hz", "5"],
        &["frequency (Hz)", "amplitude", "1×"],
    );
    both_formats(
        &dir,
        "phase",
        &["phase", &s(&i.phase), "--value-name", "coupler.omega"],
        &["coupler.omega (rad/s)", "d(coupler.omega)/dt (rad/s²)"],
    );
    // The mechanism at one instant, with the model from the run's provenance.
    both_formats(
        &dir,
        "mechanism",
        &["mechanism", &s(&i.run), "--time", "0.05"],
        &["t = 0.0500 s", "crank", "coupler", "rocker", "paths × 100"],
    );
    both_formats(
        &dir,
        "lyapunov",
        &["lyapunov", &s(&i.lyapunov)],
        &["t (s)", "λ (1/s)"],
    );
}

#[test]
fn orbit_clearance_comes_from_the_model_unless_given() {
    let i = inputs();
    let dir = scratch("clearance");
    // models/farahan2016.toml: joints.B.clearance = 0.0005 m.
    let svg = both_formats(
        &dir,
        "from_model",
        &["orbit", &s(&i.run), "--joint", "B"],
        &[],
    );
    assert!(
        svg.contains("(c = 0.5 mm)"),
        "title should give c = 0.5 mm from the model"
    );
    let svg = both_formats(
        &dir,
        "given",
        &["orbit", &s(&i.run), "--joint", "B", "--clearance", "0.001"],
        &[],
    );
    assert!(
        svg.contains("(c = 1 mm)"),
        "title should give the --clearance 1 mm"
    );
}

#[test]
fn png_size_follows_the_size_option() {
    let i = inputs();
    let out = scratch("size").join("small.png");
    let (code, err) = linkdyn(&[
        "plot",
        "lyapunov",
        &s(&i.lyapunov),
        "--size",
        "640x480",
        "--out",
        &s(&out),
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        png_size(&std::fs::read(&out).unwrap_or_default()),
        Ok((640, 480))
    );
}

#[test]
fn a_missing_column_exits_2_naming_file_and_column_and_keeps_the_old_figure() {
    let i = inputs();
    let dir = scratch("missing");
    let out = dir.join("fig.png");
    let (code, err) = linkdyn(&["plot", "lyapunov", &s(&i.lyapunov), "--out", &s(&out)]);
    assert_eq!(code, 0, "{err}");
    let before = std::fs::read(&out).unwrap_or_default();

    let header = std::fs::read_to_string(&i.run)
        .unwrap_or_default()
        .lines()
        .find(|l| !l.starts_with('#'))
        .unwrap_or_default()
        .to_string();
    let (code, err) = linkdyn(&[
        "plot",
        "series",
        &s(&i.run),
        "--y",
        "B.zz",
        "--out",
        &s(&out),
    ]);
    assert_eq!(code, 2, "missing column: {err}");
    assert_eq!(
        err.trim_end(),
        format!("error: {}: no column `B.zz` (columns: {header})", s(&i.run))
    );
    // The analysis formats need their own columns.
    let (code, err) = linkdyn(&["plot", "spectrum", &s(&i.lyapunov), "--out", &s(&out)]);
    assert_eq!(code, 2, "spectrum of a Lyapunov file: {err}");
    assert_eq!(
        err.trim_end(),
        format!(
            "error: {}: no column `frequency_hz` (columns: t,lambda)",
            s(&i.lyapunov)
        )
    );
    assert_eq!(
        std::fs::read(&out).unwrap_or_default(),
        before,
        "old figure changed"
    );
    let names: Vec<String> = std::fs::read_dir(&dir)
        .map(|d| {
            d.filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    assert_eq!(
        names,
        vec!["fig.png".to_string()],
        "only the figure, no temporary file"
    );
}

#[test]
fn unknown_kind_and_format_exit_2() {
    let i = inputs();
    let dir = scratch("unknown");
    let (code, err) = linkdyn(&["plot", "histogram", &s(&i.run), "--out", "x.png"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("unrecognized subcommand 'histogram'"), "{err}");

    let out = dir.join("fig.pdf");
    let (code, err) = linkdyn(&["plot", "lyapunov", &s(&i.lyapunov), "--out", &s(&out)]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(
        err.trim_end(),
        format!(
            "error: --out {}: unknown figure format (use a .png or .svg file name)",
            s(&out)
        )
    );
    assert!(!out.exists(), "nothing written for an unknown format");
}

#[test]
fn an_unwritable_target_exits_4_and_leaves_nothing() {
    let i = inputs();
    let dir = scratch("unwritable");
    let out = dir.join("no-such-dir").join("fig.svg");
    let (code, err) = linkdyn(&["plot", "lyapunov", &s(&i.lyapunov), "--out", &s(&out)]);
    assert_eq!(code, 4, "{err}");
    assert!(
        err.starts_with(&format!("error: cannot write {}: ", s(&out))),
        "{err}"
    );
}
