//! Shared by the animation tests: a short run of the Farahan four-bar in memory, the
//! trajectory's own values at any time (interpolated here, independently of
//! `linkdyn::animate`), and pixel look-ups.
#![allow(dead_code)]

use linkdyn::animate::{Colour, View};
use linkdyn::model::Model;
use linkdyn::plot::Table;
use linkdyn::simulation::{Simulation, SimulationOptions};

/// The bars the animation tests give the Farahan four-bar (after each body's `initial` line):
/// 30 mm wide, between the body's two points.
pub const BARS: [(&str, &str); 3] = [
    (
        "crank",
        r#"shapes = [{ type = "bar", from = "O2", to = "A", width = 0.03 }]"#,
    ),
    (
        "coupler",
        r#"shapes = [{ type = "bar", from = "A", to = "B", width = 0.03 }]"#,
    ),
    (
        "rocker",
        r#"shapes = [{ type = "bar", from = "O4", to = "B", width = 0.03 }]"#,
    ),
];

/// The text of models/farahan2016.toml with `lines[k]` inserted after the `initial` line of
/// body k (crank, coupler, rocker): line 25 is the crank's.
pub fn farahan_text_with(lines: [&str; 3]) -> String {
    let text = match std::fs::read_to_string("models/farahan2016.toml") {
        Ok(t) => t,
        Err(e) => panic!("models/farahan2016.toml: {e}"),
    };
    let mut out = String::new();
    let mut k = 0;
    for line in text.lines() {
        out.push_str(line);
        out.push('\n');
        if line.starts_with("initial = ") {
            if let Some(extra) = lines.get(k) {
                out.push_str(extra);
                out.push('\n');
            }
            k += 1;
        }
    }
    assert_eq!(
        k, 3,
        "models/farahan2016.toml: {k} `initial` lines, expected 3"
    );
    out
}

/// models/farahan2016.toml with [`BARS`], run for `revs` crank turns (250 rpm: 0.24 s a turn),
/// sampled every millisecond, as the table `linkdyn run` would write (with `t` first).
pub fn farahan(revs: f64) -> (Model, Table) {
    let text = farahan_text_with(BARS.map(|(_, line)| line));
    let model = match linkdyn::model::load_str(&text, "farahan2016_bars.toml", &[]) {
        Ok(m) => m,
        Err(e) => panic!("{e}"),
    };
    let table = run_table(
        &model,
        "models/farahan2016.toml",
        SimulationOptions::default().revs(revs).dt(1e-3),
    );
    (model, table)
}

/// `model` run with `options`, as the table `linkdyn run` would write for the file `path`
/// (with `t` first).
pub fn run_table(model: &Model, path: &str, options: SimulationOptions) -> Table {
    let sim = match Simulation::new(model, options) {
        Ok(s) => s,
        Err(e) => panic!("{e}"),
    };
    let run = match sim.run_to_memory() {
        Ok(r) => r,
        Err(e) => panic!("{e}"),
    };
    let mut names = vec!["t".to_string()];
    names.extend(run.names.iter().cloned());
    let mut columns = vec![run.t];
    columns.extend(run.columns);
    Table {
        path: path.into(),
        comments: Vec::new(),
        names,
        columns,
    }
}

/// Column `name` of `run` at time `t` (s), linear between the samples around it.
pub fn value_at(run: &Table, name: &str, t: f64) -> f64 {
    let (Ok(ts), Ok(col)) = (run.column("t"), run.column(name)) else {
        panic!("no column {name}");
    };
    let i = ts.iter().rposition(|&s| s <= t).unwrap_or(0);
    let j = (i + 1).min(ts.len() - 1);
    if j == i || ts[j] == ts[i] {
        return col[i];
    }
    let w = (t - ts[i]) / (ts[j] - ts[i]);
    col[i] + w * (col[j] - col[i])
}

/// The global position (m) of body point `local` (body frame) of `body` at time `t`, from the
/// trajectory's x, y, φ: r = (x, y) + R(φ) s.
pub fn point_at(run: &Table, body: &str, local: [f64; 2], t: f64) -> [f64; 2] {
    let x = value_at(run, &format!("{body}.x"), t);
    let y = value_at(run, &format!("{body}.y"), t);
    let phi = value_at(run, &format!("{body}.phi"), t);
    [
        x + phi.cos() * local[0] - phi.sin() * local[1],
        y + phi.sin() * local[0] + phi.cos() * local[1],
    ]
}

/// Pixel (column, row) of world point `p` through `view`, written out here from its
/// definition p_px = origin + scale·(x, −y), rounded to the nearest pixel.
pub fn pixel_of(view: &View, p: [f64; 2]) -> (usize, usize) {
    let x = view.origin[0] + view.scale * p[0];
    let y = view.origin[1] - view.scale * p[1];
    (x.round() as usize, y.round() as usize)
}

/// RGB at (x, y) of an RGB buffer `width` pixels wide.
pub fn rgb_at(rgb: &[u8], width: usize, (x, y): (usize, usize)) -> [u8; 3] {
    let i = 3 * (y * width + x);
    match rgb.get(i..i + 3) {
        Some(p) => [p[0], p[1], p[2]],
        None => panic!("pixel ({x}, {y}) outside the picture"),
    }
}

/// True if `c` is within `tol` of `want` in every channel.
pub fn near(c: [u8; 3], want: Colour, tol: u8) -> bool {
    c[0].abs_diff(want.0) <= tol && c[1].abs_diff(want.1) <= tol && c[2].abs_diff(want.2) <= tol
}

/// The centre of mass of each body of the four-bar: the middle of its bar (the body frames of
/// models/farahan2016.toml have their origin at mid-length), drawn in the body's colour.
pub const BODIES: [&str; 3] = ["crank", "coupler", "rocker"];
