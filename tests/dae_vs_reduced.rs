//! The absolute-coordinate DAE and the paper's reduced Lagrangian model are two independent
//! formulations of the same four-bar with a clearance joint: over two crank turns they must give
//! the same angles, the same impacts and the same impact times.

mod common;
use common::*;
use linkdyn::analysis::compare;
use linkdyn::formulation::{Dae, DaeOptions, Formulation, Outputs, ReducedLagrangian};
use linkdyn::solve::{Method, Recorder, SolverOptions, integrate};

fn run<F: Formulation + Outputs>(f: &mut F, t_end: f64) -> Recorder {
    let options = SolverOptions::default()
        .method(Method::Dop853)
        .rtol(1e-11)
        .atol(1e-14)
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let y0 = f.initial_state();
    let mut rec = Recorder::new(f);
    integrate(f, 0.0, &y0, t_end, 1e-4, &options, &mut rec).unwrap_or_else(|e| panic!("{e}"));
    rec
}

fn agree_over_two_turns(speed_rpm: f64) {
    let set = format!("drivers.motor.speed_rpm={speed_rpm}");
    let model = load("models/farahan2016.toml", &[&set]);
    let t_end = 2.0 * 60.0 / speed_rpm;
    let mut dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let mut reduced = ReducedLagrangian::new(&model).unwrap_or_else(|e| panic!("{e}"));
    let a = run(&mut dae, t_end);
    let b = run(&mut reduced, t_end);
    let c = compare(&a, &b, 1);
    // 1e-6 rad: the bound; at rtol 1e-11 both formulations are ~1e-9 from the truth,
    // so a difference above it means different physics, not different round-off.
    for column in ["coupler.phi", "rocker.phi"] {
        let d = c
            .column(column)
            .unwrap_or_else(|| panic!("no column {column}"));
        assert!(
            d.max_abs_difference < 1e-6,
            "{speed_rpm} rpm {column}: DAE and reduced differ by {:e} rad at t = {}",
            d.max_abs_difference,
            d.at_t
        );
    }
    assert!(c.impacts_a[0] > 0, "{speed_rpm} rpm: no impact at all");
    assert_eq!(
        c.impacts_a[0], c.impacts_b[0],
        "{speed_rpm} rpm: impact counts DAE vs reduced"
    );
    let dt = c.max_impact_time_difference[0].unwrap_or(f64::INFINITY);
    // 1e-7 s: the bound; impacts are located to 1e-12 relative on each run's dense output.
    assert!(
        dt <= 1e-7,
        "{speed_rpm} rpm: impact times differ by up to {dt:e} s"
    );
    // Journal orbit (m) agrees far inside the clearance (0.5 mm).
    for column in ["B.ex", "B.ey"] {
        let d = c
            .column(column)
            .unwrap_or_else(|| panic!("no column {column}"));
        assert!(
            d.max_abs_difference < 1e-8,
            "{speed_rpm} rpm {column}: {:e} m",
            d.max_abs_difference
        );
    }
}

#[test]
fn formulations_agree_at_250_rpm() {
    agree_over_two_turns(250.0);
}

#[test]
fn formulations_agree_at_3500_rpm() {
    agree_over_two_turns(3500.0);
}

#[test]
fn reduced_formulation_refuses_another_topology_with_a_clear_reason() {
    let model = load("models/fourbar_ideal.toml", &[]);
    let err = ReducedLagrangian::new(&model).err().map(|e| e.to_string());
    assert_eq!(
        err.as_deref(),
        Some(
            "reduced formulation: needs exactly one clearance joint, between the coupler and the rocker; the model has 0"
        )
    );
}

#[test]
fn compare_command_prints_and_writes_the_differences() {
    let dir = std::env::temp_dir().join(format!("linkdyn-compare-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let json = dir.join("cmp.json");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_linkdyn"))
        .args([
            "compare",
            "models/farahan2016.toml",
            "--revs",
            "0.25",
            "--rtol",
            "1e-10",
            "--atol",
            "1e-13",
        ])
        .arg("--out")
        .arg(&json)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap_or_else(|e| panic!("{e}"));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for column in [
        "coupler.phi",
        "rocker.phi",
        "B.ex",
        "B.ey",
        "B.fn",
        "motor.torque",
    ] {
        assert!(stdout.contains(column), "{column} missing from:\n{stdout}");
    }
    let text = std::fs::read_to_string(&json).unwrap_or_default();
    let report: serde_json::Value =
        serde_json::from_str(&text).unwrap_or_else(|e| panic!("{e}: {text}"));
    let comparison = &report["comparison"];
    let a = comparison["impacts_a"][0].as_u64().unwrap_or(0);
    assert!(
        a > 0 && Some(a) == comparison["impacts_b"][0].as_u64(),
        "impact counts: {comparison}"
    );
    let theta3 = comparison["columns"]
        .as_array()
        .and_then(|c| c.iter().find(|c| c["column"] == "coupler.phi"))
        .and_then(|c| c["max_abs_difference"].as_f64())
        .unwrap_or(f64::INFINITY);
    assert!(theta3 < 1e-6, "theta3 difference {theta3}");
    assert!(report["provenance"]["linkdyn_version"].is_string());
    let _ = std::fs::remove_dir_all(&dir);
}
