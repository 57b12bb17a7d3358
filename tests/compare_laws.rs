//! `linkdyn compare-laws` (docs/contact_laws.md): the same scene once per contact law; its
//! table and CSV carry each law's impacts and peak force exactly as a `run` with that law gives
//! them, the first law is the torque reference (difference 0), and a bad law refuses the whole
//! comparison before any file is written.

mod cli_common;
mod common;

use cli_common::{linkdyn, scratch};
use linkdyn::simulation::{Discard, FormulationKind, Simulation, SimulationOptions};

#[test]
fn each_row_is_the_run_of_its_law() {
    let dir = scratch("rows");
    let out = dir.join("laws.csv");
    let (code, stdout, stderr) = linkdyn(&[
        "compare-laws",
        "models/farahan2016.toml",
        "--joint",
        "B",
        "--laws",
        "lankarani-nikravesh,liu:flores",
        "--formulation",
        "reduced",
        "--revs",
        "0.5",
        "--set",
        "joints.B.length=0.02",
        "--out",
        &out.display().to_string(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("liu:flores"), "{stdout}");
    let text = std::fs::read_to_string(&out).unwrap_or_else(|e| panic!("{e}"));
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some(
            "law,impacts,peak_normal_force_N,max_penetration_m,torque_rms_difference_Nm,torque_rms_Nm,rhs_evals,wall_s"
        )
    );
    let rows: Vec<Vec<&str>> = lines
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 2, "{text}");
    for (row, sets) in rows.iter().zip([
        vec!["joints.B.length=0.02"],
        vec![
            "joints.B.length=0.02",
            "joints.B.contact.law=liu",
            "joints.B.contact.damping=flores",
        ],
    ]) {
        let model = common::load("models/farahan2016.toml", &sets);
        let options = SimulationOptions::default()
            .formulation(FormulationKind::Reduced)
            .revs(0.5);
        let summary = Simulation::new(&model, options)
            .and_then(|s| s.run(&mut Discard))
            .unwrap_or_else(|e| panic!("{e}"));
        let joint = &summary.clearance_joints[0];
        assert_eq!(
            row[1],
            joint.impact_count.to_string(),
            "{}: impacts",
            row[0]
        );
        let peak: f64 = row[2].parse().unwrap_or(f64::NAN);
        assert_eq!(peak, joint.peak_normal_force, "{}: peak force", row[0]);
        assert_eq!(
            row[6],
            summary.solver_stats.rhs_evals.to_string(),
            "{}: RHS evaluations",
            row[0]
        );
    }
    assert_eq!(rows[0][4], "0", "the first law is the torque reference");
    let difference: f64 = rows[1][4].parse().unwrap_or(f64::NAN);
    assert!(difference > 0.0, "liu changes the torque: {difference}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_line_law_without_length_refuses_the_comparison() {
    let dir = scratch("no-length");
    let out = dir.join("laws.csv");
    let (code, _, stderr) = linkdyn(&[
        "compare-laws",
        "models/farahan2016.toml",
        "--joint",
        "B",
        "--laws",
        "lankarani-nikravesh,johnson",
        "--out",
        &out.display().to_string(),
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains(
            "contact law \"johnson\" is a line contact and needs the bearing's axial length"
        ),
        "{stderr}"
    );
    assert!(!out.exists(), "no result file");
    let (code, _, stderr) = linkdyn(&[
        "compare-laws",
        "models/farahan2016.toml",
        "--joint",
        "A",
        "--laws",
        "hertz",
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("expected the name of a clearance joint of the model, found \"A\""),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
