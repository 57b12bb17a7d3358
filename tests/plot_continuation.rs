//! `linkdyn plot continuation` (docs/periodic_orbits.md, "Continuation"): a branch from
//! `linkdyn continue` drawn over a `linkdyn bifurcation` diagram of the same parameter comes
//! out as a PNG of the requested size and as an SVG whose elements match the branch file: one
//! solid polyline per stretch of stable points, one chain of dashes per stretch with an
//! unstable point (one each more for the legend), one marker per special point in the shape and colour of its kind, one dot
//! per diagram point (each kind once more in the legend). Bad requests exit 2 with the exact
//! message. No pixel comparisons: only the structure of the SVG.

mod cli_common;

use cli_common::{linkdyn, linkdyn_stderr, scratch};
use std::path::{Path, PathBuf};

fn s(p: &Path) -> String {
    p.display().to_string()
}

/// SVG colours (plotters writes `#RRGGBB`) of the figure's parts: the branch (both
/// stabilities), the diagram's dots and the markers of fold, PD, NS and grazing
/// (src/plot/continuation.rs, the Okabe–Ito palette of src/plot/render.rs).
const BRANCH: &str = "#0072B2";
const DIAGRAM: &str = "#7F7F7F";
const FOLD: &str = "#009E73";
const PD: &str = "#D55E00";
const NS: &str = "#CC79A7";
const GRAZING: &str = "#E69F00";

/// The SVG elements `<tag …>` whose `attr` is `value`, as their attribute text.
fn elements<'a>(svg: &'a str, tag: &str, attr: &str, value: &str) -> Vec<&'a str> {
    let needle = format!("{attr}=\"{value}\"");
    svg.split(&format!("<{tag} "))
        .skip(1)
        .filter_map(|e| e.split_once('>').map(|(a, _)| a))
        .filter(|a| a.contains(&needle))
        .collect()
}

/// The points of a `<polyline>`'s `points` attribute.
fn polyline_points(element: &str) -> Vec<(f64, f64)> {
    let Some((_, rest)) = element.split_once("points=\"") else {
        return Vec::new();
    };
    rest.split('"')
        .next()
        .unwrap_or("")
        .split_whitespace()
        .filter_map(|p| {
            let (x, y) = p.split_once(',')?;
            Some((x.parse().ok()?, y.parse().ok()?))
        })
        .collect()
}

/// Dash length (px) of a dashed line (src/plot/render.rs: 12 on, 8 off), with a pixel of
/// rounding at each end.
const DASH_PX: f64 = 14.0;
/// Gap (px) between two dashes of one dashed line, with rounding.
const GAP_PX: f64 = 12.0;

/// The solid lines and the dashed lines among the polylines of colour `colour`: plotters
/// writes a solid line as one `<polyline>` and a dashed one as one short `<polyline>` per dash
/// (at most [`DASH_PX`] long), each starting within [`GAP_PX`] of the end of the one before.
/// So a polyline longer than a dash is a solid line (the figures here keep the points of a
/// solid stretch more than a dash apart), and a dash starting further than a gap from the
/// previous dash's end starts a new dashed line.
fn solid_and_dashed(svg: &str, colour: &str) -> (usize, usize) {
    let (mut solid, mut dashed) = (0, 0);
    let mut last_end: Option<(f64, f64)> = None;
    for element in elements(svg, "polyline", "stroke", colour) {
        let pts = polyline_points(element);
        let length: f64 = pts
            .windows(2)
            .map(|w| (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1))
            .sum();
        if length > DASH_PX {
            solid += 1;
            last_end = None;
            continue;
        }
        let (Some(first), Some(last)) = (pts.first(), pts.last()) else {
            continue;
        };
        if !last_end.is_some_and(|(x, y)| (first.0 - x).hypot(first.1 - y) <= GAP_PX) {
            dashed += 1;
        }
        last_end = Some(*last);
    }
    (solid, dashed)
}

/// The branch file's `stable` column and `special` words, in row order.
fn branch_rows(csv: &str) -> (Vec<bool>, Vec<String>) {
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
    };
    let (stable, special) = (col("stable"), col("special"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[stable] == "1", f.get(special).unwrap_or(&"").to_string())
        })
        .unzip()
}

/// The stretches drawn solid and dashed, counted the way the figure is specified
/// (docs/periodic_orbits.md): a segment is solid when both its points are stable.
fn stretches(stable: &[bool]) -> (usize, usize) {
    let segments: Vec<bool> = stable.windows(2).map(|w| w[0] && w[1]).collect();
    let mut counts = (0, 0);
    for (k, solid) in segments.iter().enumerate() {
        if k == 0 || segments[k - 1] != *solid {
            if *solid {
                counts.0 += 1;
            } else {
                counts.1 += 1;
            }
        }
    }
    counts
}

fn png_size(bytes: &[u8]) -> Option<(u32, u32)> {
    const SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
    if bytes.len() < 24 || bytes[..8] != SIGNATURE || &bytes[12..16] != b"IHDR" {
        return None;
    }
    let be = |o: usize| u32::from_be_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]);
    Some((be(16), be(20)))
}

/// `linkdyn plot continuation ARGS --out DIR/NAME.svg` and `.png`; the SVG's text.
fn draw(dir: &Path, name: &str, args: &[&str]) -> String {
    let svg = dir.join(format!("{name}.svg"));
    let png = dir.join(format!("{name}.png"));
    for out in [&png, &svg] {
        let mut a = vec!["plot", "continuation"];
        a.extend(args);
        let out = s(out);
        a.extend(["--out", &out]);
        let (code, err) = linkdyn_stderr(&a);
        assert_eq!(code, 0, "{a:?}: {err}");
    }
    let bytes = std::fs::read(&png).unwrap_or_default();
    assert_eq!(png_size(&bytes), Some((1200, 800)), "{name}.png");
    let text = std::fs::read_to_string(&svg).unwrap_or_default();
    assert!(
        text.trim_start().starts_with("<svg") && text.trim_end().ends_with("</svg>"),
        "{name}.svg is not one <svg> element"
    );
    text
}

/// A branch of the reference four-bar at 3500 rpm through its first period doubling
/// (c = 0.4150 mm, docs/periodic_orbits.md) and a brute-force diagram over the same range.
fn fourbar_files(dir: &Path) -> (PathBuf, PathBuf) {
    let branch = dir.join("branch.csv");
    let diagram = dir.join("diagram.csv");
    let (code, out, err) = linkdyn(&[
        "continue",
        "models/farahan2016.toml",
        "--set",
        "drivers.motor.speed_rpm=3500",
        "--param",
        "joints.B.clearance",
        "--from",
        "0.0004155",
        "--to",
        "0.000414",
        "--step",
        "0.0000005",
        "--rtol",
        "1e-10",
        "--atol",
        "1e-12",
        "--out",
        &s(&branch),
    ]);
    assert_eq!(code, 0, "continue: {out}{err}");
    let (code, out, err) = linkdyn(&[
        "bifurcation",
        "models/farahan2016.toml",
        "--set",
        "drivers.motor.speed_rpm=3500",
        "--param",
        "joints.B.clearance",
        "--from",
        "0.000414",
        "--to",
        "0.0004155",
        "--steps",
        "2",
        "--transient",
        "10",
        "--revs",
        "14",
        "--observe",
        "rocker.phi",
        "--threads",
        "1",
        "--out",
        &s(&diagram),
    ]);
    assert_eq!(code, 0, "bifurcation: {out}{err}");
    (branch, diagram)
}

#[test]
fn a_branch_over_its_brute_force_diagram_has_an_element_per_stretch_point_and_dot() {
    let dir = scratch("fourbar");
    let (branch, diagram) = fourbar_files(&dir);
    let csv = std::fs::read_to_string(&branch).unwrap_or_default();
    let (stable, special) = branch_rows(&csv);
    let (solid, dashed) = stretches(&stable);
    let pds = special.iter().filter(|k| *k == "PD").count();
    // The stretch holds the period doubling at 0.41498 mm: stable before it, unstable after.
    assert!(
        pds >= 1 && solid >= 1 && dashed >= 1,
        "expected a PD between stable and unstable points: {stable:?} {special:?}"
    );
    assert!(
        special.iter().all(|k| k.is_empty() || k == "PD"),
        "{special:?}"
    );
    let dots = std::fs::read_to_string(&diagram)
        .unwrap_or_default()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .filter(|l| l.rsplit(',').next().is_some_and(|v| v != "NaN"))
        .count();
    assert!(dots >= 3, "diagram points: {dots}");

    // The coordinate comes from the diagram (rocker.phi), the clearance is shown in mm.
    let svg = draw(&dir, "over", &[&s(&branch), "--over", &s(&diagram)]);
    for text in [
        "joints.B.clearance (mm)",
        "rocker.phi (rad)",
        ">\nstable\n<",
        ">\nunstable\n<",
        ">\nperiod doubling (PD)\n<",
        ">\nbrute force (linkdyn bifurcation)\n<",
    ] {
        assert!(svg.contains(text), "SVG lacks `{text}`");
    }
    // The legend's samples are one more solid line (a 30 px dash) and one more dashed line.
    assert_eq!(
        solid_and_dashed(&svg, BRANCH),
        (solid + 1, dashed + 1),
        "solid and dashed lines"
    );
    assert_eq!(
        elements(&svg, "polygon", "fill", PD).len(),
        pds + 1,
        "PD markers"
    );
    assert_eq!(
        elements(&svg, "circle", "fill", DIAGRAM).len(),
        dots + 1,
        "diagram dots"
    );

    // Without the diagram, the same branch in a coordinate given by name.
    let alone = draw(&dir, "alone", &[&s(&branch), "--coordinate", "coupler.phi"]);
    assert!(alone.contains("coupler.phi (rad)"), "y label");
    assert!(elements(&alone, "circle", "fill", DIAGRAM).is_empty());
    assert_eq!(solid_and_dashed(&alone, BRANCH), (solid + 1, dashed + 1));
}

/// A branch file in the format of `linkdyn continue`, `rows` as (parameter, rocker.phi,
/// stable, special).
fn branch_file(dir: &Path, name: &str, rows: &[(f64, f64, u8, &str)]) -> PathBuf {
    let mut text = "joints.B.clearance,rocker.phi,coupler.phi,period_s,max_abs_mu,stable,impacts_per_period,min_gap_m,residual,special\n# model models/farahan2016.toml sha256 0\n".to_string();
    for (p, phi, stable, special) in rows {
        text += &format!("{p},{phi},0.6,0.017,0.5,{stable},1,-1e-4,1,{special}\n");
    }
    let path = dir.join(name);
    assert!(std::fs::write(&path, text).is_ok());
    path
}

#[test]
fn every_kind_of_special_point_has_its_marker_and_every_stretch_its_line() {
    let dir = scratch("kinds");
    // stable, fold, unstable, NS, stable, PD, PD, unstable, grazing (unstable), stable, stable
    let rows = [
        (4.0e-4, 1.0, 1, ""),
        (4.1e-4, 1.1, 1, "fold"),
        (4.2e-4, 1.2, 0, ""),
        (4.3e-4, 1.3, 1, "NS"),
        (4.4e-4, 1.4, 1, ""),
        (4.5e-4, 1.5, 1, "PD"),
        (4.6e-4, 1.4, 0, "PD"),
        (4.7e-4, 1.3, 0, ""),
        (4.8e-4, 1.2, 0, "grazing"),
        (4.9e-4, 1.1, 1, ""),
        (5.0e-4, 1.0, 1, ""),
    ];
    let branch = branch_file(&dir, "branch.csv", &rows);
    let svg = draw(&dir, "kinds", &[&s(&branch), "--coordinate", "rocker.phi"]);
    let stable: Vec<bool> = rows.iter().map(|r| r.2 == 1).collect();
    // Solid: rows 0–1, 3–5, 9–10; dashed: 1–3, 5–9.
    assert_eq!(stretches(&stable), (3, 2));
    assert_eq!(solid_and_dashed(&svg, BRANCH), (3 + 1, 2 + 1));
    // One marker per point and one in the legend; the cross is two strokes.
    assert_eq!(elements(&svg, "polygon", "fill", FOLD).len(), 1 + 1);
    assert_eq!(elements(&svg, "polygon", "fill", NS).len(), 1 + 1);
    assert_eq!(elements(&svg, "polygon", "fill", PD).len(), 2 + 1);
    assert_eq!(
        elements(&svg, "polyline", "stroke", GRAZING).len(),
        2 * (1 + 1)
    );
    // Square (4 corners), triangle (3), diamond (4), each a different colour.
    let corners = |colour: &str| {
        elements(&svg, "polygon", "fill", colour)
            .first()
            .and_then(|p| p.split_once("points=\""))
            .map_or(0, |(_, r)| {
                r.split('"').next().unwrap_or("").split_whitespace().count()
            })
    };
    assert_eq!((corners(FOLD), corners(PD), corners(NS)), (4, 3, 4));
    for text in [
        "fold",
        "period doubling (PD)",
        "Neimark–Sacker (NS)",
        "grazing",
    ] {
        assert!(
            svg.contains(&format!(">\n{text}\n<")),
            "legend lacks {text}"
        );
    }
    // An all-stable branch: one solid line, no dashes, no marker.
    let plain = branch_file(
        &dir,
        "plain.csv",
        &[
            (4.0e-4, 1.0, 1, ""),
            (4.1e-4, 1.1, 1, ""),
            (4.2e-4, 1.2, 1, ""),
        ],
    );
    let svg = draw(&dir, "plain", &[&s(&plain), "--coordinate", "rocker.phi"]);
    // The line and the legend's sample; no dashes.
    assert_eq!(solid_and_dashed(&svg, BRANCH), (1 + 1, 0));
    assert!(!svg.contains(">\nunstable\n<") && !svg.contains("fold"));
}

#[test]
fn each_branch_and_turn_of_its_period_is_its_own_line() {
    let dir = scratch("branches");
    // A period-1 branch (branch 0) and a period-2 branch (branch 1) whose points have a row
    // per turn, interleaved as `linkdyn continue --follow-doublings` writes them.
    let mut text = "joints.B.clearance,rocker.phi,coupler.phi,period_s,max_abs_mu,stable,impacts_per_period,min_gap_m,residual,special,branch,turn\n# model models/farahan2016.toml sha256 0\n".to_string();
    for (k, p) in [4.0e-4, 4.1e-4, 4.2e-4].iter().enumerate() {
        text += &format!(
            "{p},{},0.6,0.017,0.5,1,1,-1e-4,1,,0,0\n",
            1.0 + 0.1 * k as f64
        );
    }
    for (k, p) in [4.3e-4, 4.4e-4, 4.5e-4].iter().enumerate() {
        let d = 0.05 * (k + 1) as f64;
        for (turn, phi) in [1.3 + d, 1.3 - d].iter().enumerate() {
            text += &format!("{p},{phi},0.6,0.034,0.5,1,2,-1e-4,1,,1,{turn}\n");
        }
    }
    let branch = dir.join("branches.csv");
    assert!(std::fs::write(&branch, text).is_ok());
    let svg = draw(
        &dir,
        "branches",
        &[&s(&branch), "--coordinate", "rocker.phi"],
    );
    // Three lines (the period-1 branch and the period-2 branch's two section points), not one
    // zigzag through the interleaved rows; one more for the legend.
    assert_eq!(solid_and_dashed(&svg, BRANCH), (3 + 1, 0));
}

/// `linkdyn plot continuation ARGS --out DIR/bad.svg`: exit code and stderr; no file.
fn refused(dir: &Path, args: &[&str]) -> (i32, String) {
    let out = dir.join("bad.svg");
    let mut a = vec!["plot", "continuation"];
    a.extend(args);
    let out_s = s(&out);
    a.extend(["--out", &out_s]);
    let got = linkdyn_stderr(&a);
    assert!(!out.exists(), "{args:?} wrote a figure");
    (got.0, got.1.trim_end().to_string())
}

#[test]
fn bad_requests_exit_2_with_their_message() {
    let dir = scratch("bad");
    let branch = branch_file(
        &dir,
        "branch.csv",
        &[(4.0e-4, 1.0, 1, ""), (4.1e-4, 1.1, 0, "PD")],
    );
    let b = s(&branch);
    let diagram = |name: &str, head: &str| {
        let path = dir.join(name);
        let body = format!("{head}\n0,4e-4,0,1.0\n1,4.1e-4,0,1.1\n");
        assert!(std::fs::write(&path, body).is_ok());
        s(&path)
    };
    let speed = diagram("speed.csv", "index,drivers.motor.speed_rpm,turn,rocker.phi");
    let crank = diagram("crank.csv", "index,joints.B.clearance,turn,crank.phi");
    let phi = diagram("phi.csv", "index,joints.B.clearance,turn,rocker.phi");
    let cases: Vec<(Vec<&str>, String)> = vec![
        (
            vec![&b, "--over", &speed],
            "error: --over: speed.csv sweeps `drivers.motor.speed_rpm`, but the branch in branch.csv is continued in `joints.B.clearance`: draw the branch over a diagram of the same parameter".into(),
        ),
        (
            vec![&b, "--over", &crank],
            "error: --over: `crank.phi` is not a state column of branch.csv (its state columns: rocker.phi,coupler.phi)".into(),
        ),
        (
            vec![&b, "--over", &phi, "--coordinate", "coupler.phi"],
            "error: --coordinate: `coupler.phi` differs from the column `rocker.phi` of the diagram phi.csv: the branch is drawn in the diagram's coordinate (leave --coordinate out)".into(),
        ),
        (
            vec![&b],
            "error: --coordinate: which state column of branch.csv to draw? expected one of rocker.phi,coupler.phi (or --over a bifurcation diagram, whose column is taken)".into(),
        ),
        (
            vec![&b, "--coordinate", "rocker.omega"],
            "error: --coordinate: `rocker.omega` is not a state column of branch.csv (its state columns: rocker.phi,coupler.phi)".into(),
        ),
        (
            vec![&b, "--coordinate", "rocker.phi", "--label", "mine"],
            "error: --label: not available for `plot continuation` (its legend names stability and special points)".into(),
        ),
    ];
    for (args, message) in cases {
        assert_eq!(refused(&dir, &args), (2, message), "{args:?}");
    }
    // An unknown special point, named with its line; a file that is not a branch.
    let odd = branch_file(
        &dir,
        "odd.csv",
        &[(4.0e-4, 1.0, 1, ""), (4.1e-4, 1.1, 0, "BP")],
    );
    assert_eq!(
        refused(&dir, &[&s(&odd), "--coordinate", "rocker.phi"]),
        (
            2,
            format!(
                "error: {}:4: column `special`: `BP` is not a special point (expected fold, PD, NS, grazing or nothing)",
                s(&odd)
            )
        )
    );
    let (code, err) = refused(&dir, &[&phi, "--coordinate", "rocker.phi"]);
    assert_eq!(
        (code, err),
        (
            2,
            format!(
                "error: {phi}: no column `special` (columns: index,joints.B.clearance,turn,rocker.phi)"
            )
        )
    );
}
