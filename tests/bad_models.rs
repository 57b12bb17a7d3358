//! Every file in tests/bad_models/ is refused by `linkdyn check` with exit code 2 and exactly the
//! one-line message below (file, line:column, field, what was expected), never a panic.

mod cli_common;
use cli_common::{linkdyn, scratch};

const CASES: &[(&str, &str)] = &[
    (
        "axis_one_component",
        "tests/bad_models/axis_one_component.toml:22:8: joints.pivot.axis: expected 2 components [x, y] for the axis, found 1 component",
    ),
    (
        "body_name_comma",
        "tests/bad_models/body_name_comma.toml:9:8: bodies[0].name: invalid body name \"link,1\": ',' (it splits a CSV field) is not allowed; expected 1 to 64 ASCII letters, digits, '_' or '-', starting with a letter or digit",
    ),
    (
        "clearance_1e308",
        "tests/bad_models/clearance_1e308.toml:22:13: joints.C.clearance: radial clearance c = 1e308 m is not smaller than the journal radius R_J = 1e-2 m; expected c < R_J (a bearing of more than twice the journal's radius is not a clearance joint)",
    ),
    (
        "clearance_below_floor",
        "tests/bad_models/clearance_below_floor.toml:22:13: joints.C.clearance: expected a radial clearance (m) of at least 1e-9 (the roughness of polished surfaces), found 1e-12",
    ),
    (
        "clearance_equal_to_journal_radius",
        "tests/bad_models/clearance_equal_to_journal_radius.toml:22:13: joints.C.clearance: radial clearance c = 1e-2 m is not smaller than the journal radius R_J = 1e-2 m; expected c < R_J (a bearing of more than twice the journal's radius is not a clearance joint)",
    ),
    (
        "clearance_field_on_revolute",
        "tests/bad_models/clearance_field_on_revolute.toml:37:13: joints.A.clearance: field `clearance` does not belong to a revolute joint; expected only body_a, point_a, body_b, point_b",
    ),
    (
        "clearance_too_large_eccentricity",
        "tests/bad_models/clearance_too_large_eccentricity.toml:24:24: joints.C.initial_eccentricity: initial eccentricity |e| = 1.000000e-3 m is not smaller than the clearance 5.000000e-4 m; expected the journal strictly inside the bearing, since a contact that is under way at t = 0 has no impact velocity to scale its damping",
    ),
    (
        "driver_field_of_other_type",
        "tests/bad_models/driver_field_of_other_type.toml:32:9: drivers.motor.speed: field `speed` does not belong to a prescribed-angle driver; expected only angle",
    ),
    (
        "driver_name_quote",
        "tests/bad_models/driver_name_quote.toml:24:8: drivers[0].name: invalid driver name \"mo\\\"tor\": '\"' (it quotes a CSV field) is not allowed; expected 1 to 64 ASCII letters, digits, '_' or '-', starting with a letter or digit",
    ),
    (
        "driver_on_locked_body",
        "tests/bad_models/driver_on_locked_body.toml: conflicting constraints at t = 0: \"motor\" depends on \"O.x\", \"T.x\", and a driver must prescribe a motion the other constraints leave free, but at the assembled position this one is a combination of them (its angle is already fixed by them: two drivers on one loop, or a link of zero length); remove one of them or fix the geometry",
    ),
    (
        "driver_on_prismatic",
        "tests/bad_models/driver_on_prismatic.toml:41:9: drivers.motor.joint: driver \"motor\" drives joint \"A\", which is prismatic; a constant-speed driver needs a revolute joint",
    ),
    (
        "driver_prescribed_angle_of_state",
        "tests/bad_models/driver_prescribed_angle_of_state.toml:31:18: drivers.motor.angle: in expression \"0.1*t + crank.phi\": \"crank.phi\" is part of the state, but a prescribed angle is a function of time `t` alone (use a `torque` driver for a motor law)",
    ),
    (
        "driver_ramp_unknown_shape",
        "tests/bad_models/driver_ramp_unknown_shape.toml:34:9: drivers.motor.shape: unknown ramp shape \"cubic\"; expected \"smooth\" or \"linear\"",
    ),
    (
        "driver_ramp_without_duration",
        "tests/bad_models/driver_ramp_without_duration.toml:28:8: drivers.motor.name: missing field `duration` of speed-ramp driver \"motor\"",
    ),
    (
        "driver_two_speeds",
        "tests/bad_models/driver_two_speeds.toml:43:9: drivers.motor.speed: give either `speed_rpm` or `speed` (rad/s), not both",
    ),
    (
        "driver_unknown_joint",
        "tests/bad_models/driver_unknown_joint.toml:41:9: drivers.motor.joint: unknown joint \"O2\" in driver \"motor\": did you mean \"O\"?",
    ),
    (
        "eccentricity_on_the_wall",
        "tests/bad_models/eccentricity_on_the_wall.toml:24:24: joints.C.initial_eccentricity: initial eccentricity |e| = 5.000000e-4 m is not smaller than the clearance 5.000000e-4 m; expected the journal strictly inside the bearing, since a contact that is under way at t = 0 has no impact velocity to scale its damping",
    ),
    (
        "eccentricity_one_component",
        "tests/bad_models/eccentricity_one_component.toml:24:24: joints.C.initial_eccentricity: expected 2 components [x, y] for the initial eccentricity (m), found 1 component",
    ),
    (
        "expr_syntax",
        "tests/bad_models/expr_syntax.toml:14:15: bodies.crank.mass: in expression \"(m + L\": unexpected end of the expression; expected ')' to close the '('",
    ),
    (
        "expr_time_at_load",
        "tests/bad_models/expr_time_at_load.toml:14:16: bodies.crank.mass: in expression \"m*(1 + t)\": \"t\" is only known during the run, but this field is evaluated once at load time; time and state may appear in force and torque expressions and prescribed angles",
    ),
    (
        "expr_unknown_function",
        "tests/bad_models/expr_unknown_function.toml:17:38: bodies.crank.initial.phi: in expression \"sinn(0.1)\": unknown function \"sinn\": did you mean \"sin\"?; expected one of sin cos tan asin acos atan atan2 sqrt abs exp ln floor min max mod or a table from [[tables]]",
    ),
    (
        "expr_unknown_parameter",
        "tests/bad_models/expr_unknown_parameter.toml:15:14: bodies.crank.inertia: in expression \"m*Ll^2/12\": unknown name \"Ll\": did you mean \"L\"?; expected a parameter from [parameters]",
    ),
    (
        "flores_restitution_below_floor",
        "tests/bad_models/flores_restitution_below_floor.toml:27:15: joints.C.contact.restitution: expected a coefficient of restitution of at least 0.01 for the flores law, found 0.001: its damping factor 8(1 − c_r)/(5 c_r) grows as 1/c_r (c_r = 1e-4 costs 56× the work of 0.9, 1e-5 475×), and c_r < 0.01 is a plastic impact that no continuous contact law describes",
    ),
    (
        "force_name_hash",
        "tests/bad_models/force_name_hash.toml:30:8: forces[0].name: invalid force name \"#push\": '#' (it starts a comment line) is not allowed; expected 1 to 64 ASCII letters, digits, '_' or '-', starting with a letter or digit",
    ),
    (
        "force_theta_without_driver",
        "tests/bad_models/force_theta_without_driver.toml:31:15: forces.spring.torque: in expression \"-10*theta\": `theta` and `omega` are the angle and speed of the model's single driver, but it has 0; write a body's angle instead, e.g. crank.phi",
    ),
    (
        "force_unknown_coordinate",
        "tests/bad_models/force_unknown_coordinate.toml:37:15: forces.spring.torque: in expression \"-10*crank.ph\": unknown body coordinate \"ph\" in \"crank.ph\": did you mean \"phi\"?; expected one of x y phi vx vy omega",
    ),
    (
        "force_vector_three_components",
        "tests/bad_models/force_vector_three_components.toml:38:9: forces.push.force: expected 2 components [x, y] for the force (N), found 3 components",
    ),
    (
        "gravity_component_not_a_number",
        "tests/bad_models/gravity_component_not_a_number.toml:6:16: settings.gravity[1]: in expression \"down\": unknown name \"down\"; expected a parameter from [parameters]",
    ),
    (
        "gravity_junk_component",
        "tests/bad_models/gravity_junk_component.toml:6:11: settings.gravity: expected 2 components [x, y] for the gravity vector (m/s²), found 4 components",
    ),
    (
        "gravity_not_finite",
        "tests/bad_models/gravity_not_finite.toml:6:11: settings.gravity: expected a finite gravity vector (m/s²), found [NaN, -9.81]",
    ),
    (
        "gravity_three_components",
        "tests/bad_models/gravity_three_components.toml:6:11: settings.gravity: expected 2 components [x, y] for the gravity vector (m/s²), found 3 components",
    ),
    (
        "hertz_with_restitution",
        "tests/bad_models/hertz_with_restitution.toml:27:15: joints.C.contact.restitution: field `restitution` does not belong to the hertz law, which is purely elastic (c_r = 1), found c_r = 0.5; remove it, or choose lankarani-nikravesh, hunt-crossley or flores for a dissipative contact",
    ),
    (
        "inertia_below_floor",
        "tests/bad_models/inertia_below_floor.toml:11:11: bodies.link.inertia: expected a moment of inertia (kg·m²) of at least 1e-30 (a 1 µm steel cube), found 1e-300",
    ),
    (
        "joint_name_newline",
        "tests/bad_models/joint_name_newline.toml:16:8: joints[0].name: invalid joint name \"piv\\not\": a newline is not allowed; expected 1 to 64 ASCII letters, digits, '_' or '-', starting with a letter or digit",
    ),
    (
        "joint_to_itself",
        "tests/bad_models/joint_to_itself.toml:31:8: joints.A.name: joint \"A\" connects \"crank\" to itself; expected two different bodies",
    ),
    (
        "journal_radius_1e6",
        "tests/bad_models/journal_radius_1e6.toml:23:18: joints.C.journal_radius: expected a journal radius (m) in [1e-6, 1e1] (from micro-mechanism pins to ship shafts), found 1e6",
    ),
    (
        "journal_radius_not_finite",
        "tests/bad_models/journal_radius_not_finite.toml:23:18: joints.C.journal_radius: expected a finite journal radius (m), found inf",
    ),
    (
        "mass_below_floor",
        "tests/bad_models/mass_below_floor.toml:10:8: bodies.link.mass: expected a mass (kg) in [1e-15, 1e6] (real linkages: from a 1 µm steel cube to ten times the largest excavator boom), found 1e-300",
    ),
    (
        "missing_model_name",
        "tests/bad_models/missing_model_name.toml:2:1: model: missing field `name`",
    ),
    (
        "model_name_control_character",
        "tests/bad_models/model_name_control_character.toml:3:8: model.name: invalid model name \"bad\\u{7}\": the control character U+0007 is not allowed; expected 1 to 64 ASCII letters, digits, '_' or '-', starting with a letter or digit",
    ),
    (
        "model_name_empty",
        "tests/bad_models/model_name_empty.toml:3:8: model.name: invalid model name \"\": it is empty; expected 1 to 64 ASCII letters, digits, '_' or '-', starting with a letter or digit",
    ),
    (
        "negative_mass",
        "tests/bad_models/negative_mass.toml:10:8: bodies.crank.mass: expected a positive mass (kg), found -0.5",
    ),
    (
        "no_bodies",
        "tests/bad_models/no_bodies.toml: expected at least one [[bodies]] entry",
    ),
    (
        "non_finite_mass",
        "tests/bad_models/non_finite_mass.toml:10:8: bodies.crank.mass: expected a finite mass (kg), found NaN",
    ),
    (
        "output_name_space",
        "tests/bad_models/output_name_space.toml:28:8: outputs[0].name: invalid output name \"coupler tip\": a space is not allowed; expected 1 to 64 ASCII letters, digits, '_' or '-', starting with a letter or digit",
    ),
    (
        "output_unknown_point",
        "tests/bad_models/output_unknown_point.toml:30:9: outputs.tip.point: unknown point \"B\" on body \"crank\" in output \"tip\"; body \"crank\" has points A, O",
    ),
    (
        "parameter_cycle",
        "tests/bad_models/parameter_cycle.toml:6:1: parameters.L: parameters refer to each other in a cycle: L -> m -> L",
    ),
    (
        "parameter_reserved_name",
        "tests/bad_models/parameter_reserved_name.toml:7:1: parameters.theta: invalid parameter name \"theta\": \"theta\" is reserved for the run-time quantity of that name in force expressions",
    ),
    (
        "point_name_space",
        "tests/bad_models/point_name_space.toml:12:12: bodies.link.points.\"P 1\": invalid point name \"P 1\" on body \"link\": a space is not allowed; expected 1 to 64 ASCII letters, digits, '_' or '-', starting with a letter or digit",
    ),
    (
        "point_three_components",
        "tests/bad_models/point_three_components.toml:12:16: bodies.link.points.P: expected 2 components [x, y] for the point (m), found 3 components",
    ),
    (
        "poisson_ratio_minus_one",
        "tests/bad_models/poisson_ratio_minus_one.toml:24:17: joints.C.poisson_ratio: expected a Poisson ratio in (-1, 0.5), found -1",
    ),
    (
        "prismatic_clearance_corner_on_the_wall",
        "tests/bad_models/prismatic_clearance_corner_on_the_wall.toml:67:16: joints.rail.initial_tilt: the initial offset 0e0 m and tilt 1.3e-2 rad put a slider corner 5.178729e-4 m from its centred position towards a guide surface, not less than the clearance 5.000000e-4 m; expected every corner strictly inside the guide, since a contact that is under way at t = 0 has no impact velocity to scale its damping",
    ),
    (
        "prismatic_clearance_guide_end_before_start",
        "tests/bad_models/prismatic_clearance_guide_end_before_start.toml:68:13: joints.rail.guide_end: the guide end 1e-1 m is not after the guide start 5e-1 m; expected guide_end > guide_start (positions along the axis from the guide's point)",
    ),
    (
        "prismatic_clearance_guide_shorter_than_slider",
        "tests/bad_models/prismatic_clearance_guide_shorter_than_slider.toml:68:13: joints.rail.guide_end: the guide between guide_start = 3.6e-1 m and guide_end = 4.3e-1 m is 7.000000e-2 m long, not longer than the slider (8.000000e-2 m); expected guide_end − guide_start > slider_length",
    ),
    (
        "prismatic_clearance_line_law",
        "tests/bad_models/prismatic_clearance_line_law.toml:72:7: joints.rail.contact.law: contact law \"liu\" is a line contact of a cylinder in a cylindrical hole and has no meaning for a slider's corner on a flat guide surface; expected a point-contact law (lankarani-nikravesh, hunt-crossley, flores or hertz) on prismatic-clearance joint \"rail\"",
    ),
    (
        "prismatic_clearance_slider_past_guide_end",
        "tests/bad_models/prismatic_clearance_slider_past_guide_end.toml: prismatic-clearance joint \"rail\": at the assembled position (t = 0) the slider's corner c2 is 2.000000e-2 m past `guide_end` (4.2e-1 m along the axis); expected the slider strictly between the guide's end stops, since a contact that is under way at t = 0 has no impact velocity to scale its damping: move `guide_end` or the slider",
    ),
    (
        "prismatic_clearance_without_slider_length",
        "tests/bad_models/prismatic_clearance_without_slider_length.toml:59:8: joints.rail.name: missing field `slider_length` of prismatic-clearance joint \"rail\"",
    ),
    (
        "prismatic_clearance_without_stiffness",
        "tests/bad_models/prismatic_clearance_without_stiffness.toml:59:8: joints.rail.name: missing field `stiffness` of prismatic-clearance joint \"rail\"",
    ),
    (
        "repeat_name_not_integer",
        "tests/bad_models/repeat_name_not_integer.toml:33:8: repeat[0].bodies[0].name: {i/2} in name template \"b{i/2}\" is 0.5; expected an integer (in [[repeat]] with i = 1)",
    ),
    (
        "repeat_non_integer_bound",
        "tests/bad_models/repeat_non_integer_bound.toml:30:6: repeat[0].to: expected an integer `to` of at most 1e6 in magnitude, found 2.1",
    ),
    (
        "repeat_unknown_point",
        "tests/bad_models/repeat_unknown_point.toml:45:11: repeat[0].joints[0].point_b: unknown point \"Q\" on body \"b1\" in joint \"j1\"; body \"b1\" has points P (in [[repeat]] with i = 1)",
    ),
    (
        "stiffness_absurd",
        "tests/bad_models/stiffness_absurd.toml:24:13: joints.C.stiffness: expected a contact stiffness K (N/m^n) in [1e2, 1e18] (the range the material and size bounds give), found 1e30",
    ),
    (
        "syntax_error",
        "tests/bad_models/syntax_error.toml:6:26: (TOML syntax): missing comma between array elements, expected `,`",
    ),
    (
        "table_lengths_differ",
        "tests/bad_models/table_lengths_differ.toml:30:5: tables.gas.y: table \"gas\" has 3 x and 2 y values; expected as many of each, at least 2",
    ),
    (
        "table_not_increasing",
        "tests/bad_models/table_not_increasing.toml:29:12: tables.gas.x[2]: table \"gas\": x[2] = 1 is not above x[1] = 2; expected strictly increasing x",
    ),
    (
        "two_drivers_one_loop",
        "tests/bad_models/two_drivers_one_loop.toml: conflicting constraints at t = 0: \"motor2\" depends on \"O2.x\", \"O2.y\", \"A.x\", \"A.y\", \"B.x\", \"B.y\", \"O4.x\", \"O4.y\", \"motor\", and a driver must prescribe a motion the other constraints leave free, but at the assembled position this one is a combination of them (its angle is already fixed by them: two drivers on one loop, or a link of zero length); remove one of them or fix the geometry",
    ),
    (
        "unassemblable",
        "tests/bad_models/unassemblable.toml: the linkage cannot be assembled: the constraint of joint \"B\" is still off by 2.000e-1 (m or rad) after 1 Newton iterations; check the link lengths and the bodies' initial guesses",
    ),
    (
        "unknown_body",
        "tests/bad_models/unknown_body.toml:35:10: joints.A.body_b: unknown body \"rood\" in joint \"A\": did you mean \"rod\"?",
    ),
    (
        "unknown_field",
        "tests/bad_models/unknown_field.toml:12:1: bodies.crank.colour: unknown field `colour`; expected one of `name`, `mass`, `inertia`, `points`, `initial`, `shapes`",
    ),
    (
        "unknown_joint_type",
        "tests/bad_models/unknown_joint_type.toml:32:8: joints.A.type: unknown joint type \"revolut\"; expected \"revolute\", \"prismatic\", \"clearance\" or \"prismatic-clearance\": did you mean \"revolute\"?",
    ),
    (
        "unknown_point",
        "tests/bad_models/unknown_point.toml:36:11: joints.A.point_b: unknown point \"Z\" on body \"rod\" in joint \"A\"; body \"rod\" has points A, B",
    ),
    (
        "wrong_type",
        "tests/bad_models/wrong_type.toml:10:8: bodies.crank.mass: invalid type: boolean `true`, expected a number or an expression string such as \"L2/2\"",
    ),
    (
        "youngs_modulus_absurd",
        "tests/bad_models/youngs_modulus_absurd.toml:24:18: joints.C.youngs_modulus: expected a Young's modulus (Pa) in [1e6, 1.2e12] (from soft rubber to diamond), found 1e20",
    ),
    (
        "zero_inertia",
        "tests/bad_models/zero_inertia.toml:11:11: bodies.crank.inertia: expected a positive moment of inertia (kg·m²), found 0",
    ),
];

#[test]
fn each_bad_model_is_refused_with_its_exact_message_and_exit_code_2() {
    for (name, expected) in CASES {
        let path = format!("tests/bad_models/{name}.toml");
        let (code, stdout, stderr) = linkdyn(&["check", &path]);
        assert_eq!(code, 2, "{name}: exit code {code}, stderr {stderr}");
        assert_eq!(stderr.trim_end(), format!("error: {expected}"), "{name}");
        assert!(stdout.is_empty(), "{name}: nothing on stdout, got {stdout}");
    }
}

#[test]
fn every_file_in_the_corpus_has_a_case() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_models");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{e}"))
        .filter_map(|e| e.ok())
        .filter_map(|e| {
            e.path()
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
        })
        .collect();
    files.sort();
    let cases: Vec<String> = CASES.iter().map(|(n, _)| n.to_string()).collect();
    assert_eq!(
        files, cases,
        "tests/bad_models/ and CASES must list the same files"
    );
    assert!(cases.len() >= 12);
}

#[test]
fn bad_set_overrides_are_refused_with_exit_code_2() {
    let (code, _, stderr) = linkdyn(&[
        "check",
        "models/fourbar_ideal.toml",
        "--set",
        "drivers.motr.speed_rpm=3500",
    ]);
    assert_eq!(code, 2);
    assert_eq!(
        stderr.trim_end(),
        "error: --set drivers.motr.speed_rpm=3500: no entry named \"motr\" in drivers: did you mean \"motor\"?"
    );
    let (code, _, stderr) = linkdyn(&[
        "check",
        "models/fourbar_ideal.toml",
        "--set",
        "bodies.crank.mass=-1",
    ]);
    assert_eq!(code, 2);
    // Located in the file where the overridden field stands, and naming the override.
    assert_eq!(
        stderr.trim_end(),
        "error: models/fourbar_ideal.toml:17:8: bodies.crank.mass: expected a positive mass (kg), found -1 (value from --set bodies.crank.mass=-1)"
    );
    let (code, _, stderr) = linkdyn(&[
        "check",
        "models/fourbar_ideal.toml",
        "--set",
        "bodies.crank.colour=red",
    ]);
    assert_eq!(code, 2);
    assert_eq!(
        stderr.trim_end(),
        "error: models/fourbar_ideal.toml: bodies.crank.colour: unknown field `colour`; expected one of `name`, `mass`, `inertia`, `points`, `initial`, `shapes` (value from --set bodies.crank.colour=red)"
    );
    // A misspelt field gets the nearest known one.
    let (code, _, stderr) = linkdyn(&[
        "check",
        "models/fourbar_ideal.toml",
        "--set",
        "bodies.crank.inertai=0.1",
    ]);
    assert_eq!(code, 2);
    assert_eq!(
        stderr.trim_end(),
        "error: models/fourbar_ideal.toml: bodies.crank.inertai: unknown field `inertai`: did you mean \"inertia\"?; expected one of `name`, `mass`, `inertia`, `points`, `initial`, `shapes` (value from --set bodies.crank.inertai=0.1)"
    );
}

#[test]
fn a_failed_run_writes_no_result_file() {
    let dir = scratch("bad-run");
    let out = dir.join("r.csv");
    let out_s = out.display().to_string();
    // An rtol of zero is refused before anything runs.
    let (code, _, stderr) = linkdyn(&[
        "run",
        "models/fourbar_ideal.toml",
        "--rtol",
        "0",
        "--out",
        &out_s,
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        !out.exists() && !dir.join("r.json").exists(),
        "no partial result files"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn same_model_and_settings_give_identical_numbers() {
    let dir = scratch("repro");
    let mut bodies = Vec::new();
    for k in 0..2 {
        let out = dir.join(format!("r{k}.csv"));
        let (code, _, stderr) = linkdyn(&[
            "run",
            "models/fourbar_ideal.toml",
            "--revs",
            "0.5",
            "--dt",
            "1e-3",
            "--out",
            &out.display().to_string(),
        ]);
        assert_eq!(code, 0, "{stderr}");
        let text = std::fs::read_to_string(&out).unwrap_or_default();
        let provenance: Vec<&str> = text.lines().filter(|l| l.starts_with('#')).collect();
        assert!(
            provenance.iter().any(|l| l.starts_with("# linkdyn ")),
            "version recorded"
        );
        assert!(
            provenance.iter().any(|l| l.contains("sha256")),
            "model hash recorded"
        );
        assert!(
            provenance.iter().any(|l| l.starts_with("# rtol = ")),
            "settings recorded"
        );
        bodies.push(text);
    }
    assert_eq!(
        bodies[0], bodies[1],
        "two identical runs must write identical files"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_solver_failure_says_when_and_exits_with_code_3_leaving_no_files() {
    // A crank of 0.45 m in the reference four-bar cannot turn fully: coupler and rocker are
    // stretched into a line (0.75 + 0.45 = 1.2 m) when the crank tip is 1.2 m from O4, at
    // θ2 = 2.550 rad (t = 0.0974 s at 250 rpm), and no motion can go on. The solver must stop
    // there with a message, not hang or write half a file. (The 0.4 m crank reaches a change
    // point instead (crank + ground = coupler + rocker), which the DAE passes: tests/no_progress.rs.)
    let dir = scratch("lock");
    let out = dir.join("lock.csv");
    let (code, _, stderr) = linkdyn(&[
        "run",
        "models/fourbar_ideal.toml",
        "--set",
        "bodies.crank.points.A=[0.225,0.0]",
        "--set",
        "bodies.crank.points.O2=[-0.225,0.0]",
        "--set",
        "bodies.crank.initial.x=0.225",
        "--revs",
        "1",
        "--out",
        &out.display().to_string(),
    ]);
    assert_eq!(code, 3, "{stderr}");
    // At the lock the driver cannot be followed: its row is violated beyond the bound, and the
    // message names the rows that lost independence there.
    assert!(
        stderr.starts_with("error: the equations of motion could not be evaluated at t = 0.0973"),
        "{stderr}"
    );
    assert!(
        stderr.contains("constraint \"motor\" is violated by |Φ| = "),
        "{stderr}"
    );
    assert!(
        stderr.contains("are nearly dependent: the linkage is at or near a singular position"),
        "{stderr}"
    );
    assert!(
        !out.exists() && !dir.join("lock.json").exists(),
        "no partial result files"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_linkage_driven_through_its_clearance_joint_stops_with_the_reason() {
    // Moving the crank's pivot point 1 m off its axis makes the reference four-bar unable to
    // turn: the driver pushes the journal through the bearing. Trial stages of too-large steps
    // that overshoot are retried smaller; only a real penetration beyond 0.1 R_J stops the run.
    let dir = scratch("deep");
    let out = dir.join("deep.csv");
    let (code, _, stderr) = linkdyn(&[
        "run",
        "models/farahan2016.toml",
        "--set",
        "bodies.crank.points.O2=[-0.125,-1.0]",
        "--revs",
        "0.05",
        "--out",
        &out.display().to_string(),
    ]);
    assert_eq!(code, 3, "{stderr}");
    assert!(
        stderr.contains("penetration of clearance joint \"B\" reached")
            && stderr.contains("the linkage is being driven through the joint"),
        "{stderr}"
    );
    assert!(!out.exists(), "no partial result file");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The clearance joint "B" of the loaded model.
fn clearance_spec(model: &linkdyn::model::Model) -> &linkdyn::model::ClearanceSpec {
    model
        .joints
        .iter()
        .find_map(|j| match &j.kind {
            linkdyn::model::JointKind::Clearance(spec) if j.name == "B" => Some(spec),
            _ => None,
        })
        .unwrap_or_else(|| panic!("no clearance joint B"))
}

fn load_with(sets: &[&str]) -> Result<linkdyn::model::Model, String> {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    linkdyn::model::load(
        std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/models/farahan2016.toml"
        )),
        &sets,
    )
    .map_err(|e| e.to_string())
}

#[test]
fn switching_the_friction_law_with_one_set_drops_the_old_fields_with_a_note() {
    let model = load_with(&["joints.B.friction.law=none"]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        clearance_spec(&model).friction,
        linkdyn::model::FrictionSpec::None
    );
    assert_eq!(
        model.notes,
        [
            "--set joints.B.friction.law=none: dropped coefficient = 0.1, v0 = 0.0001, v1 = 0.001 from joints.B.friction, which friction law \"none\" does not take"
        ]
    );
    // The CLI accepts it too (exit 0); printing the notes is the CLI's job.
    let (code, _, stderr) = linkdyn(&[
        "check",
        "models/farahan2016.toml",
        "--set",
        "joints.B.friction.law=none",
    ]);
    assert_eq!(code, 0, "{stderr}");
    // A field of the old law set again afterwards is the user's explicit choice: an error, as in
    // a file.
    let err = load_with(&[
        "joints.B.friction.law=none",
        "joints.B.friction.coefficient=0.2",
    ])
    .err();
    assert_eq!(
        err.as_deref(),
        Some(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/models/farahan2016.toml:77:15: joints.B.friction.coefficient: field `coefficient` does not belong to friction law \"none\" (value from --set joints.B.friction.coefficient=0.2)"
        ))
    );
}

#[test]
fn switching_the_contact_law_with_one_set_drops_the_old_fields_with_a_note() {
    use linkdyn::model::ContactLawKind;
    // To the purely elastic Hertz law: the restitution of the old law goes, with a note.
    let model = load_with(&["joints.B.contact.law=hertz"]).unwrap_or_else(|e| panic!("{e}"));
    let spec = clearance_spec(&model);
    assert_eq!(spec.law, ContactLawKind::Hertz);
    assert_eq!(spec.restitution, 1.0, "Hertz records c_r = 1");
    assert_eq!(
        spec.exponent, 1.5,
        "the exponent belongs to every law and stays"
    );
    assert_eq!(
        model.notes,
        [
            "--set joints.B.contact.law=hertz: dropped restitution = 0.9 from joints.B.contact, which contact law \"hertz\" does not take"
        ]
    );
    // To another dissipative law: everything applies, nothing is dropped, no note.
    let model = load_with(&["joints.B.contact.law=flores"]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(clearance_spec(&model).law, ContactLawKind::Flores);
    assert_eq!(clearance_spec(&model).restitution, 0.9);
    assert!(model.notes.is_empty(), "{:?}", model.notes);
    // An unknown law drops nothing and is named by validation.
    let err = load_with(&["joints.B.contact.law=hertzian"]).err();
    assert_eq!(
        err.as_deref(),
        Some(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/models/farahan2016.toml:71:7: joints.B.contact.law: unknown contact law \"hertzian\"; expected one of lankarani-nikravesh, hunt-crossley, flores, hertz, johnson, liu (value from --set joints.B.contact.law=hertzian)"
        ))
    );
}
