//! Force against penetration of every contact law at the reference joint of
//! `models/farahan2016.toml` (steel, R_J = 10 mm, c = 0.5 mm) with a bearing of length
//! L = 20 mm (L/D = 1; the paper gives none): the figure `docs/figures/contact_laws.svg` and the
//! table of docs/contact_laws.md.
//!
//! The elastic part F_e(δ) is drawn: the hysteresis damping multiplies it by (1 + χ δ̇/δ̇⁽⁻⁾)
//! whatever the law, so the four point-contact laws share one curve, K δ^1.5.
//!
//! Run: `cargo run --release --example contact_laws [OUT.svg]` (default
//! `docs/figures/contact_laws.svg`).

use linkdyn::contact::ClearanceJoint;
use linkdyn::model::{JointKind, Model};
use linkdyn::plot::{Axis, Dash, Figure, Series, Style, render};

/// The laws drawn, with the `--set` that selects each.
const LAWS: [(&str, &[&str]); 3] = [
    (
        "K δ^1.5 (lankarani-nikravesh, hunt-crossley, flores, hertz)",
        &[],
    ),
    (
        "johnson (L = 20 mm)",
        &["joints.B.length=0.02", "joints.B.contact.law=johnson"],
    ),
    (
        "liu (L = 20 mm)",
        &["joints.B.length=0.02", "joints.B.contact.law=liu"],
    ),
];

fn joint(sets: &[&str]) -> Result<ClearanceJoint, String> {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/models/farahan2016.toml");
    let model: Model = linkdyn::model::load(path.as_ref(), &sets).map_err(|e| e.to_string())?;
    model
        .joints
        .iter()
        .find_map(|j| match &j.kind {
            JointKind::Clearance(spec) => Some(ClearanceJoint::from_spec(spec)),
            _ => None,
        })
        .ok_or_else(|| "no clearance joint".to_string())
}

fn main() -> Result<(), String> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "docs/figures/contact_laws.svg".to_string());
    let mut figure = Figure::new(
        "Contact laws at the reference joint (steel, R_J = 10 mm, c = 0.5 mm)",
        Axis {
            label: "penetration δ (m)".into(),
            log: true,
            ..Axis::default()
        },
        Axis {
            label: "elastic normal force F_e (N)".into(),
            log: true,
            // Room above the curves for the legend.
            range: Some((0.03, 1e7)),
            ..Axis::default()
        },
    );
    // 1e-8 m to 1e-4 m, 40 points a decade: impacts of the reference run reach about 1e-5 m.
    let deltas: Vec<f64> = (0..=160)
        .map(|i| 1e-8 * 10f64.powf(i as f64 / 40.0))
        .collect();
    println!("| law | F_e(1 µm) (N) | F_e(10 µm) (N) | dF_e/dδ at 5 µm (N/m) |");
    println!("|---|---|---|---|");
    for (k, (name, sets)) in LAWS.iter().enumerate() {
        let law = joint(sets)?.law;
        let slope = law.elastic.force_and_slope(5e-6).1;
        println!(
            "| {name} | {:.4e} | {:.4e} | {slope:.4e} |",
            law.elastic_force(1e-6),
            law.elastic_force(1e-5)
        );
        figure.series.push(Series {
            name: Some(name.to_string()),
            style: Style::Line,
            colour: k,
            dash: Dash::nth(k),
            points: deltas.iter().map(|&d| (d, law.elastic_force(d))).collect(),
        });
    }
    render(&figure, out.as_ref()).map_err(|e| e.to_string())?;
    eprintln!("wrote {out}");
    Ok(())
}
