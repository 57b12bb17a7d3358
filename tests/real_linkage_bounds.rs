//! Model files are held to what real linkages have (`src/model/bounds.rs`): absurd values are
//! refused at load with exit 2 and a message naming the file, the line and column, the field,
//! the allowed range and why, instead of a run that crawls for minutes (a 1e300 kg crank: 106 s,
//! 88 MB), hangs (1e308 rpm: infinite in rad/s, and the SVD of the velocity projection never
//! converged) or ends with exit 0 and a result that means nothing (an initial angle of 1e12 rad,
//! where f64 angles are 1.2e-4 rad apart). Every shipped model passes (they are loaded by most
//! tests), and the values near each bound that real linkages use are accepted.

mod cli_common;

/// `linkdyn check MODEL --set …` → (exit code, stderr).
fn check(model: &str, sets: &[&str]) -> (i32, String) {
    let mut args = vec!["check", model];
    for s in sets {
        args.extend(["--set", s]);
    }
    let (code, _, stderr) = cli_common::linkdyn(&args);
    (code, stderr.trim_end().to_string())
}

#[test]
fn absurd_values_are_refused_with_the_field_the_range_and_why() {
    let cases: [(&str, &[&str], &str); 6] = [
        (
            "models/farahan2016.toml",
            &["bodies.crank.mass=1e300"],
            "error: models/farahan2016.toml:21:8: bodies.crank.mass: expected a mass (kg) in [1e-15, 1e6] (real linkages: from a 1 µm steel cube to ten times the largest excavator boom), found 1e300 (value from --set bodies.crank.mass=1e300)",
        ),
        (
            "models/farahan2016.toml",
            &["bodies.crank.mass=1e-12"],
            "error: models/farahan2016.toml:22:11: bodies.crank.inertia: expected a moment of inertia (kg·m²) of body \"crank\" of at most m·(1000·D)² = 9.353e-7, its mass m = 1.000e-12 kg at 1000 times the linkage's extent D = 9.671e-1 m (real linkages: bodies reach beyond their joints, but not by a thousand times the linkage), found 4.600e-3 (a radius of gyration √(I/m) of 6.782e4 m) (after --set overrides)",
        ),
        (
            "models/farahan2016.toml",
            &["bodies.coupler.initial.phi=1e12"],
            "error: models/farahan2016.toml:32:39: bodies.coupler.initial.phi: expected an initial phi (rad) in [-1e4, 1e4] (1600 turns; beyond it sin and cos of the angle lose the digits that place the links), found 1e12 (value from --set bodies.coupler.initial.phi=1e12)",
        ),
        (
            "models/farahan2016.toml",
            &["drivers.motor.speed_rpm=1e308"],
            "error: models/farahan2016.toml:93:13: drivers.motor.speed_rpm: expected a driver speed of at most 1e4 rad/s (95493 rpm) in magnitude (real linkages: the fastest crank trains turn at about 20 000 rpm), found speed_rpm = 1e308, inf rad/s (value from --set drivers.motor.speed_rpm=1e308)",
        ),
        (
            "models/pendulum.toml",
            &["bodies.rod.points.tip=[5e3,0]"],
            "error: models/pendulum.toml:18:35: bodies.rod.points.tip: expected the coordinates of point \"tip\" on body \"rod\" in [-1e3, 1e3] m (real linkages: ten times the largest machines), found [5e3, 0e0] (value from --set bodies.rod.points.tip=[5e3,0])",
        ),
        (
            "models/pendulum.toml",
            &[
                "bodies.rod.points.O=[-1.5e-10,0]",
                "bodies.rod.points.tip=[1.5e-10,0]",
                "bodies.rod.initial.x=1.3e-10",
                "bodies.rod.initial.y=-7.5e-11",
                "bodies.rod.inertia=1e-20",
            ],
            "error: models/pendulum.toml: the linkage spans 3.001e-10 m (the diagonal of the box around its points, body centres and ground points at the initial position); expected at least 1e-6 m (real linkages: micro-mechanisms are tens of µm across)",
        ),
    ];
    for (model, sets, expected) in cases {
        let (code, stderr) = check(model, sets);
        assert_eq!(code, 2, "{sets:?}: {stderr}");
        assert_eq!(stderr, expected, "{sets:?}");
    }
}

#[test]
fn values_real_linkages_use_near_the_bounds_are_accepted() {
    // A 1000 t crank, 95 000 rpm (just under 1e4 rad/s), an initial crank angle of 100 turns,
    // a flywheel on the crank with √(I/m) = 4.7 m = 4.9 D.
    let cases: [&[&str]; 4] = [
        &["bodies.crank.mass=1e6", "bodies.crank.inertia=1e4"],
        &["drivers.motor.speed_rpm=95000"],
        &["bodies.crank.initial.phi=628.3185307179587"],
        &["bodies.crank.inertia=11.0"],
    ];
    for sets in cases {
        let (code, stderr) = check("models/farahan2016.toml", sets);
        assert_eq!(code, 0, "{sets:?}: {stderr}");
    }
}
