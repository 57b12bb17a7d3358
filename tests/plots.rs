//! `linkdyn plot`: every kind of figure comes out as a PNG of the requested size and
//! as an SVG that is well-formed and carries the expected title and axis labels (with units);
//! the orbit's clearance is read from the model named in the run's provenance; bad requests
//! (a missing column, an unknown kind or format) exit 2 with a message naming the file and the
//! column; figures are written atomically (no temporary file left, an earlier figure kept when
//! a request fails). The common options act on what is drawn: --xlim/--ylim bound the tick
//! labels, --fmax the spectrum's bins, a converged Poincaré point and an orbit keep axes as wide
//! as the clearance, legends name the runs by model and overrides or --label; bad values exit
//! 2 naming the option and what was expected. No pixel comparisons: fonts and anti-aliasing may
//! change between plotters versions, the structure may not.

mod cli_common;

use cli_common::{linkdyn_stderr, scratch};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

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
            let (code, err) = linkdyn_stderr(&[
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
        let (code, err) = linkdyn_stderr(&a);
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
            // Legends and title from the provenance's models, not the file names.
            "motor.torque: farahan2016 vs fourbar_ideal",
            ">\nfarahan2016\n<",
            ">\nfourbar_ideal\n<",
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
    let (code, err) = linkdyn_stderr(&[
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
    let (code, err) = linkdyn_stderr(&["plot", "lyapunov", &s(&i.lyapunov), "--out", &s(&out)]);
    assert_eq!(code, 0, "{err}");
    let before = std::fs::read(&out).unwrap_or_default();

    let header = std::fs::read_to_string(&i.run)
        .unwrap_or_default()
        .lines()
        .find(|l| !l.starts_with('#'))
        .unwrap_or_default()
        .to_string();
    let (code, err) = linkdyn_stderr(&[
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
    let (code, err) = linkdyn_stderr(&["plot", "spectrum", &s(&i.lyapunov), "--out", &s(&out)]);
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
    let (code, err) = linkdyn_stderr(&["plot", "histogram", &s(&i.run), "--out", "x.png"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("unrecognized subcommand 'histogram'"), "{err}");

    let out = dir.join("fig.pdf");
    let (code, err) = linkdyn_stderr(&["plot", "lyapunov", &s(&i.lyapunov), "--out", &s(&out)]);
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
    let (code, err) = linkdyn_stderr(&["plot", "lyapunov", &s(&i.lyapunov), "--out", &s(&out)]);
    assert_eq!(code, 4, "{err}");
    assert!(
        err.starts_with(&format!("error: cannot write {}: ", s(&out))),
        "{err}"
    );
}

/// The numbers among the SVG's texts (tick labels), in document order.
fn numeric_texts(svg: &str) -> Vec<f64> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let body = t.split_once('>')?.1.split_once("</text>")?.0;
            body.trim().parse().ok()
        })
        .collect()
}

/// The largest number of points in one `<polyline>` of the SVG (the data line of a spectrum:
/// grid lines are `<line>`s, the harmonic marks two-point polylines).
fn longest_polyline(svg: &str) -> usize {
    svg.split("<polyline")
        .skip(1)
        .filter_map(|p| p.split_once("points=\"")?.1.split_once('"'))
        .map(|(points, _)| points.split_whitespace().count())
        .max()
        .unwrap_or(0)
}

/// `linkdyn plot ARGS --out DIR/NAME.svg`; the SVG's text, or the exit code and stderr.
fn svg_of(dir: &Path, name: &str, args: &[&str]) -> Result<String, (i32, String)> {
    let out = dir.join(format!("{name}.svg"));
    let mut a = vec!["plot"];
    a.extend(args);
    let out_s = s(&out);
    a.extend(["--out", &out_s]);
    match linkdyn_stderr(&a) {
        (0, _) => Ok(std::fs::read_to_string(&out).unwrap_or_default()),
        failed => Err(failed),
    }
}

#[test]
fn limits_bound_the_tick_labels_and_the_fitted_axis_follows_the_window() {
    let i = inputs();
    let dir = scratch("limits");
    // lyapunov.csv: t from 0.1 to 5 s, lambda from 3.02 to 4.
    let whole = svg_of(&dir, "whole", &["lyapunov", &s(&i.lyapunov)]);
    let whole = whole.unwrap_or_else(|e| panic!("lyapunov: {e:?}"));
    assert!(
        numeric_texts(&whole).iter().any(|&v| v >= 4.0),
        "without limits the ticks reach t = 4 s"
    );
    let svg = svg_of(
        &dir,
        "window",
        &[
            "lyapunov",
            &s(&i.lyapunov),
            "--xlim",
            "1,2",
            "--ylim",
            "3.2,3.4",
        ],
    );
    let svg = svg.unwrap_or_else(|e| panic!("lyapunov --xlim 1,2 --ylim 3.2,3.4: {e:?}"));
    let ticks = numeric_texts(&svg);
    assert!(ticks.len() >= 4, "too few tick labels: {ticks:?}");
    for v in &ticks {
        assert!(
            (1.0..=2.0).contains(v) || (3.2..=3.4).contains(v),
            "tick label {v} outside --xlim 1,2 and --ylim 3.2,3.4 (all: {ticks:?})"
        );
    }
    // Negative limits are values, not options.
    let svg = svg_of(
        &dir,
        "negative",
        &["lyapunov", &s(&i.lyapunov), "--xlim", "-1,1"],
    );
    assert!(
        svg.is_ok_and(|t| numeric_texts(&t).contains(&-1.0)),
        "--xlim -1,1: a tick at -1"
    );
}

#[test]
fn fmax_limits_the_spectrums_bins_and_ticks() {
    let i = inputs();
    let dir = scratch("fmax");
    // spectrum.csv: 50 bins 0, 0.5, …, 24.5 Hz.
    let all = svg_of(&dir, "all", &["spectrum", &s(&i.spectrum)]);
    assert_eq!(all.map(|t| longest_polyline(&t)), Ok(50), "every bin");
    let svg = svg_of(&dir, "ten", &["spectrum", &s(&i.spectrum), "--fmax", "10"]);
    let svg = svg.unwrap_or_else(|e| panic!("--fmax 10: {e:?}"));
    assert_eq!(longest_polyline(&svg), 21, "bins 0 to 10 Hz");
    let top = numeric_texts(&svg).into_iter().fold(f64::MIN, f64::max);
    assert!(top <= 10.0, "a tick label at {top} beyond --fmax 10");
    // Without --fmax a driving frequency in the provenance limits it to 25 multiples, and the
    // amplitude axis names the observed column with its unit.
    let text = std::fs::read_to_string(&i.spectrum).unwrap_or_default();
    let with = dir.join("driven.csv");
    let head = "# observe = B.fn\n# driving_frequency_hz = 0.2\n";
    assert!(std::fs::write(&with, format!("{head}{text}")).is_ok());
    let svg = svg_of(&dir, "driven", &["spectrum", &s(&with)]);
    let svg = svg.unwrap_or_else(|e| panic!("driven: {e:?}"));
    assert_eq!(longest_polyline(&svg), 11, "bins 0 to 25 × 0.2 Hz");
    assert!(svg.contains("amplitude of B.fn (N)"), "amplitude label");
    // 25 multiples in range: every second is marked (at most 20 labels), none beyond 25×.
    assert!(
        svg.contains(">\n24×\n<") && !svg.contains("26×") && !svg.contains(">\n3×\n<"),
        "marks 1×, 2×, 4×, … 24×"
    );
}

#[test]
fn bad_limits_labels_and_font_sizes_exit_2_naming_the_option() {
    let i = inputs();
    let dir = scratch("bad_options");
    let cases: [(&[&str], String); 6] = [
        (
            &["--xlim", "3,1"],
            "error: --xlim: expected two numbers LOW,HIGH with LOW < HIGH (e.g. --xlim 0,100), \
             got `3,1`: LOW is not below HIGH"
                .into(),
        ),
        (
            &["--ylim", "a,b"],
            "error: --ylim: expected two numbers LOW,HIGH with LOW < HIGH (e.g. --ylim 0,100), \
             got `a,b`"
                .into(),
        ),
        (
            &["--xlim", "5"],
            "error: --xlim: expected two numbers LOW,HIGH with LOW < HIGH (e.g. --xlim 0,100), \
             got `5`"
                .into(),
        ),
        (
            &["--font-size", "2"],
            "error: --font-size: expected 6 to 72 pt, got 2".into(),
        ),
        (
            &["--label", "a", "--label", "b"],
            format!(
                "error: --label: expected one label per file, 1 ({}), got 2",
                i.lyapunov
                    .file_name()
                    .map(|f| f.to_string_lossy().into_owned())
                    .unwrap_or_default()
            ),
        ),
        (
            &["--fmax", "0"],
            "error: unexpected argument '--fmax' found".into(),
        ),
    ];
    for (extra, expected) in cases {
        let mut args = vec!["lyapunov", i.lyapunov.to_str().unwrap_or_default()];
        args.extend(extra);
        let got = svg_of(&dir, "bad", &args);
        let Err((code, err)) = got else {
            panic!("{extra:?} was accepted");
        };
        assert_eq!(code, 2, "{extra:?}: {err}");
        let first = err.lines().next().unwrap_or_default();
        assert_eq!(first, expected, "{extra:?}");
    }
    assert!(!dir.join("bad.svg").exists(), "nothing written");
    // Series: one label per file, FILE then --compare.
    let got = svg_of(
        &dir,
        "bad",
        &[
            "series",
            &s(&i.run),
            "--y",
            "motor.torque",
            "--compare",
            &s(&i.ideal),
            "--label",
            "only one",
        ],
    );
    assert_eq!(
        got.map_err(|(code, err)| (code, err.trim_end().to_string())),
        Err((
            2,
            "error: --label: expected one label per file, 2 (run.csv, ideal.csv), got 1"
                .to_string()
        ))
    );
    let got = svg_of(&dir, "bad", &["spectrum", &s(&i.spectrum), "--fmax", "-5"]);
    assert_eq!(
        got.map_err(|(code, err)| (code, err.trim_end().to_string())),
        Err((
            2,
            "error: --fmax: expected a positive frequency in Hz, got -5".to_string()
        ))
    );
}

#[test]
fn labels_name_the_runs_and_font_size_scales_the_text() {
    let i = inputs();
    let dir = scratch("labels");
    let args = [
        "series",
        &s(&i.run),
        "--y",
        "motor.torque",
        "--compare",
        &s(&i.ideal),
        "--label",
        "with clearance",
        "--label",
        "ideal",
    ];
    let svg = svg_of(&dir, "labelled", &args).unwrap_or_else(|e| panic!("{e:?}"));
    assert!(svg.contains(">\nwith clearance\n<") && svg.contains(">\nideal\n<"));
    // Each run its own colour (Okabe–Ito blue, vermillion).
    assert!(
        svg.contains("#0072B2") && svg.contains("#D55E00"),
        "colours"
    );
    let size_of = |svg: &str, text: &str| -> f64 {
        svg.split("<text")
            .find(|t| t.contains(text))
            .and_then(|t| t.split_once("font-size=\"")?.1.split_once('"'))
            .and_then(|(v, _)| v.parse().ok())
            .unwrap_or(0.0)
    };
    let mut big = args.to_vec();
    big.extend(["--font-size", "30"]);
    let big = svg_of(&dir, "big", &big).unwrap_or_else(|e| panic!("{e:?}"));
    let ratio = size_of(&big, "t (s)") / size_of(&svg, "t (s)");
    // 30 pt against the default 20: the axis label grows 1.5 times (to a pixel).
    assert!((ratio - 1.5).abs() < 0.05, "axis label grew {ratio} times");
}

#[test]
fn a_converged_section_and_a_still_orbit_keep_the_clearance_in_view() {
    let dir = scratch("spans");
    let model = format!("{}/models/farahan2016.toml", env!("CARGO_MANIFEST_DIR"));
    // A converged period-1 section: 20 crossings within 20 nm of (0.241735, -0.412) mm, and a
    // run whose journal stays within 10 nm of the centre; farahan2016 has c = 0.5 mm.
    let mut section = format!("# model {model} sha256 00\nturn,t,B.ex,B.ey\n");
    let mut still = format!("# model {model} sha256 00\nt,B.ex,B.ey\n");
    for k in 0..20 {
        let wobble = 1e-11 * f64::from(k % 3);
        section += &format!(
            "{k},{},{},{}\n",
            0.24 * f64::from(k),
            2.41735e-4 + wobble,
            -4.12e-4 + wobble
        );
        still += &format!("{},{wobble},{wobble}\n", 0.01 * f64::from(k));
    }
    let (p, o) = (dir.join("section.csv"), dir.join("still.csv"));
    assert!(std::fs::write(&p, section).is_ok() && std::fs::write(&o, still).is_ok());
    let svg = svg_of(
        &dir,
        "section",
        &["poincare", &s(&p), "--x", "B.ex", "--y", "B.ey"],
    );
    let svg = svg.unwrap_or_else(|e| panic!("poincare: {e:?}"));
    assert!(
        svg.contains("(axes span ≥ 0.5 mm, the clearance)"),
        "span stated"
    );
    let ticks = numeric_texts(&svg);
    let xs: Vec<f64> = ticks.iter().copied().filter(|v| *v >= 0.0).collect();
    let spread =
        xs.iter().fold(f64::MIN, |m, v| m.max(*v)) - xs.iter().fold(f64::MAX, |m, v| m.min(*v));
    assert!(
        spread >= 0.4,
        "x ticks span {spread} mm, not the clearance: {ticks:?}"
    );
    assert!(
        !ticks.contains(&0.241735),
        "a tick label at the point itself: nanometre autoscaling"
    );
    let svg = svg_of(&dir, "orbit", &["orbit", &s(&o), "--joint", "B"]);
    let ticks = numeric_texts(&svg.unwrap_or_else(|e| panic!("orbit: {e:?}")));
    let (lo, hi) = ticks
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
    assert!(
        lo <= -0.5 && hi >= 0.5,
        "orbit ticks {lo} to {hi} mm exclude the clearance 0.5 mm"
    );
}

#[test]
fn a_swept_clearance_axis_says_mm() {
    let dir = scratch("sweep_units");
    let mut text = "index,joints.B.clearance,turn,coupler.phi\n".to_string();
    for k in 0..10 {
        text += &format!(
            "{k},{},0,{}\n",
            5e-5 * f64::from(k + 1),
            1.0 + 0.01 * f64::from(k)
        );
    }
    let p = dir.join("sweep.csv");
    assert!(std::fs::write(&p, text).is_ok());
    let svg = svg_of(&dir, "sweep", &["bifurcation", &s(&p)]);
    let svg = svg.unwrap_or_else(|e| panic!("bifurcation: {e:?}"));
    assert!(
        svg.contains("joints.B.clearance (mm)"),
        "x axis label with mm"
    );
    assert!(svg.contains("coupler.phi (rad)"), "y axis label with rad");
}
