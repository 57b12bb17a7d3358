//! Claim: the line-contact laws of the revolute clearance joint (`johnson`, `liu`), each with
//! each hysteresis damping, are first-class: one `--set` switches to them, a missing bearing
//! `length` and the fields they do not take are refused with the reason, and the reference
//! four-bar (`models/farahan2016.toml`) runs with them in every formulation and method, with
//! impacts whose first peak follows the stiffness of the law.
//!
//! The force–penetration curves themselves are checked against their formulas in
//! `src/contact/laws/` (Johnson's implicit relation against a bisection, Liu's at hand-computed
//! points, the rate and slopes against central differences); the Jacobians with these laws in
//! `src/formulation/dae/jacobian/tests.rs` and `src/formulation/reduced_lagrangian/tests.rs`.

mod common;

use linkdyn::model::{ContactLawKind, DampingKind, JointKind, Model};
use linkdyn::simulation::{
    ClearanceSummary, Discard, FormulationKind, Simulation, SimulationOptions,
};
use linkdyn::solve::{Method, SolverOptions};

const MODEL: &str = "models/farahan2016.toml";

fn load_with(sets: &[&str]) -> Result<Model, String> {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    linkdyn::model::load(
        std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/",
            "models/farahan2016.toml"
        )),
        &sets,
    )
    .map_err(|e| e.to_string())
}

fn file_error(sets: &[&str]) -> String {
    match load_with(sets) {
        Ok(_) => panic!("{sets:?} was accepted"),
        Err(e) => e,
    }
}

const FILE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/models/farahan2016.toml");

/// The refusals, each with its exact message (file, line:column, field, what was expected).
#[test]
fn bad_line_contact_settings_are_refused_with_the_reason() {
    let cases: &[(&[&str], String)] = &[
        (
            &["joints.B.contact.law=johnson"],
            format!(
                "{FILE}:71:7: joints.B.contact.law: contact law \"johnson\" is a line contact and needs the bearing's axial length: expected a field `length` (m, > 0) on clearance joint \"B\", e.g. length = 0.02 (value from --set joints.B.contact.law=johnson)"
            ),
        ),
        (
            &["joints.B.length=1e-7", "joints.B.contact.law=liu"],
            format!(
                "{FILE}: joints.B.length: expected a bearing length (m) in [1e-6, 1e1] (from micro-mechanism pins to ship-shaft bearings), found 1e-7 (value from --set joints.B.length=1e-7)"
            ),
        ),
        (
            &[
                "joints.B.length=0.02",
                "joints.B.stiffness=1e10",
                "joints.B.contact.law=johnson",
            ],
            format!(
                "{FILE}: joints.B.stiffness: field `stiffness` does not belong to contact law \"johnson\": it sets K of the power laws K δⁿ, while a line-contact law's stiffness follows from the materials, the clearance and `length`; remove it, or choose lankarani-nikravesh, hunt-crossley, flores or hertz (value from --set joints.B.stiffness=1e10)"
            ),
        ),
        (
            &["joints.B.contact.damping=flores"],
            format!(
                "{FILE}: joints.B.contact.damping: field `damping` does not belong to contact law \"lankarani-nikravesh\", whose name fixes its damping; choose the law by its damping instead (lankarani-nikravesh, hunt-crossley, flores, or hertz for none), or a line-contact law (johnson, liu) to combine with a damping (value from --set joints.B.contact.damping=flores)"
            ),
        ),
        (
            &[
                "joints.B.length=0.02",
                "joints.B.contact.law=johnson",
                "joints.B.contact.damping=hunt-crosley",
            ],
            format!(
                "{FILE}: joints.B.contact.damping: unknown damping \"hunt-crosley\"; expected one of lankarani-nikravesh, hunt-crossley, flores, none: did you mean \"hunt-crossley\"? (value from --set joints.B.contact.damping=hunt-crosley)"
            ),
        ),
        (
            &[
                "joints.B.length=0.02",
                "joints.B.contact.law=johnson",
                "joints.B.contact.exponent=1.2",
            ],
            format!(
                "{FILE}:73:12: joints.B.contact.exponent: field `exponent` does not belong to contact law \"johnson\", whose force–penetration relation is fixed by its source; remove it (value from --set joints.B.contact.exponent=1.2)"
            ),
        ),
        (
            &[
                "joints.B.length=0.02",
                "joints.B.contact.law=liu",
                "joints.B.contact.damping=flores",
                "joints.B.contact.restitution=0.001",
            ],
            format!(
                "{FILE}:72:15: joints.B.contact.restitution: expected a coefficient of restitution of at least 0.01 for the flores damping, found 0.001: its damping factor 8(1 − c_r)/(5 c_r) grows as 1/c_r (c_r = 1e-4 costs 56× the work of 0.9, 1e-5 475×), and c_r < 0.01 is a plastic impact that no continuous contact law describes (value from --set joints.B.contact.restitution=0.001)"
            ),
        ),
    ];
    for (sets, expected) in cases {
        assert_eq!(&file_error(sets), expected, "{sets:?}");
    }
}

fn clearance(model: &Model) -> &linkdyn::model::ClearanceSpec {
    model
        .joints
        .iter()
        .find_map(|j| match &j.kind {
            JointKind::Clearance(spec) => Some(spec),
            _ => None,
        })
        .unwrap_or_else(|| panic!("no clearance joint"))
}

/// One `--set` switches the law (the power law's exponent is dropped with a note); a second
/// picks the damping; damping "none" drops the restitution as switching to hertz does.
#[test]
fn one_set_switches_to_a_line_law_and_its_damping() {
    let model = load_with(&["joints.B.length=0.02", "joints.B.contact.law=johnson"])
        .unwrap_or_else(|e| panic!("{e}"));
    let spec = clearance(&model);
    assert_eq!(spec.law, ContactLawKind::Johnson);
    assert_eq!(spec.damping, DampingKind::LankaraniNikravesh, "the default");
    assert_eq!(spec.length, Some(0.02));
    assert_eq!(spec.restitution, 0.9);
    assert_eq!(
        model.notes,
        [
            "--set joints.B.contact.law=johnson: dropped exponent = 1.5 from joints.B.contact, which contact law \"johnson\" does not take"
        ]
    );
    let model = load_with(&[
        "joints.B.length=0.02",
        "joints.B.contact.law=liu",
        "joints.B.contact.damping=none",
    ])
    .unwrap_or_else(|e| panic!("{e}"));
    let spec = clearance(&model);
    assert_eq!(
        (spec.law, spec.damping),
        (ContactLawKind::Liu, DampingKind::None)
    );
    assert_eq!(spec.restitution, 1.0, "no damping records c_r = 1");
    assert_eq!(
        model.notes[1],
        "--set joints.B.contact.damping=none: dropped restitution = 0.9 from joints.B.contact, which damping \"none\" does not take"
    );
    // Back to a point-contact law: the line law's damping goes, the length stays (geometry).
    let model = load_with(&[
        "joints.B.length=0.02",
        "joints.B.contact.law=johnson",
        "joints.B.contact.damping=flores",
        "joints.B.contact.law=hunt-crossley",
    ])
    .unwrap_or_else(|e| panic!("{e}"));
    let spec = clearance(&model);
    assert_eq!(
        (spec.law, spec.damping),
        (ContactLawKind::HuntCrossley, DampingKind::HuntCrossley)
    );
}

fn run(sets: &[&str], formulation: FormulationKind, method: Method) -> ClearanceSummary {
    let model = common::load(MODEL, sets);
    let options = SimulationOptions::default()
        .formulation(formulation)
        .revs(1.0)
        .solver(SolverOptions::default().method(method));
    let sim = Simulation::new(&model, options).unwrap_or_else(|e| panic!("{sets:?}: {e}"));
    let summary = sim
        .run(&mut Discard)
        .unwrap_or_else(|e| panic!("{sets:?} {formulation:?} {method:?}: {e}"));
    summary
        .clearance_joints
        .into_iter()
        .next()
        .unwrap_or_else(|| panic!("no clearance joint"))
}

/// Every line law with every damping, in the three formulations (DOP853) and, for one damping,
/// with Radau5 (which uses the analytic Jacobians): one crank turn finishes with impacts, the
/// formulations agree on the first impact (time to 1e-7 s, the bound of tests/dae_vs_reduced.rs;
/// peak force to 1e-4, the force being located on each run's dense output), and the peaks are
/// plausible: between 1 kN and 100 kN (the Lankarani–Nikravesh reference peaks at 7.4 kN over
/// two turns).
#[test]
fn farahan2016_runs_with_every_line_law_in_every_formulation() {
    let formulations = [
        FormulationKind::Reduced,
        FormulationKind::Dae,
        FormulationKind::Generalized,
    ];
    for law in ["johnson", "liu"] {
        for damping in ["lankarani-nikravesh", "hunt-crossley", "flores", "none"] {
            let law_set = format!("joints.B.contact.law={law}");
            let damping_set = format!("joints.B.contact.damping={damping}");
            let sets = ["joints.B.length=0.02", &law_set, &damping_set];
            let mut methods = vec![Method::Dop853];
            if damping == "hunt-crossley" {
                methods.push(Method::Radau5);
            }
            for method in methods {
                let runs: Vec<ClearanceSummary> = formulations
                    .iter()
                    .map(|&f| run(&sets, f, method))
                    .collect();
                let first = &runs[0];
                let case = format!("{law}/{damping} {method:?}");
                assert!(
                    first.impact_count >= 1 && !first.impacts.is_empty(),
                    "{case}: no impact"
                );
                for (f, r) in formulations.iter().zip(&runs) {
                    assert!(
                        (1e3..1e5).contains(&r.peak_normal_force),
                        "{case} {f:?}: peak {} N",
                        r.peak_normal_force
                    );
                    let (a, b) = (&first.impacts[0], &r.impacts[0]);
                    assert!(
                        (a.t - b.t).abs() <= 1e-7,
                        "{case} {f:?}: first impact at {} vs {} s",
                        b.t,
                        a.t
                    );
                    assert!(
                        (a.peak_normal_force - b.peak_normal_force).abs()
                            <= 1e-4 * a.peak_normal_force,
                        "{case} {f:?}: first peak {} vs {} N",
                        b.peak_normal_force,
                        a.peak_normal_force
                    );
                }
            }
        }
    }
}

/// Until the first impact the laws play no part, so every law meets the wall at the same time
/// with the same impact velocity; with no damping the peak of that first impact then orders as
/// the stiffness of the laws at the reference joint (docs/contact_laws.md): Hertz-type K δ^1.5
/// below Liu below Johnson (L = 20 mm).
#[test]
fn the_first_peak_follows_the_stiffness_of_the_law() {
    let runs: Vec<(&str, ClearanceSummary)> = [
        ("hertz", vec!["joints.B.contact.law=hertz"]),
        (
            "liu",
            vec![
                "joints.B.length=0.02",
                "joints.B.contact.law=liu",
                "joints.B.contact.damping=none",
            ],
        ),
        (
            "johnson",
            vec![
                "joints.B.length=0.02",
                "joints.B.contact.law=johnson",
                "joints.B.contact.damping=none",
            ],
        ),
    ]
    .into_iter()
    .map(|(name, sets)| (name, run(&sets, FormulationKind::Reduced, Method::Dop853)))
    .collect();
    let first = |i: usize| &runs[i].1.impacts[0];
    for i in 1..runs.len() {
        // Same free flight: the same event, located to ~1e-12 relative on each dense output.
        assert!(
            (first(i).t - first(0).t).abs() <= 1e-9 && {
                let (a, b) = (first(i).impact_velocity, first(0).impact_velocity);
                (a - b).abs() <= 1e-6 * b
            },
            "{}: first impact at {} s, {} m/s; hertz at {} s, {} m/s",
            runs[i].0,
            first(i).t,
            first(i).impact_velocity,
            first(0).t,
            first(0).impact_velocity
        );
        assert!(
            first(i).peak_normal_force > first(i - 1).peak_normal_force,
            "{} peak {} N not above {} peak {} N",
            runs[i].0,
            first(i).peak_normal_force,
            runs[i - 1].0,
            first(i - 1).peak_normal_force
        );
        assert!(
            first(i).peak_penetration < first(i - 1).peak_penetration,
            "{} penetration {} m not below {}'s {} m",
            runs[i].0,
            first(i).peak_penetration,
            runs[i - 1].0,
            first(i - 1).peak_penetration
        );
    }
}

/// The energy bookkeeping closes with every line law (DAE, 2 turns, DOP853 at rtol 1e-8): the
/// elastic energy of each law (Johnson's in closed form from its explicit δ(F), Liu's by
/// quadrature) is what its force stores, so the work–energy residual stays at the level the
/// point-contact laws reach. Same bound as tests/work_energy_balance.rs (1e-6 of the driver
/// work); the reference law measured 4.0e-10, johnson 2.7e-10 and liu 4.9e-10.
#[test]
fn the_energy_balance_closes_with_every_line_law() {
    for law in ["johnson", "liu"] {
        for damping in ["lankarani-nikravesh", "none"] {
            let law_set = format!("joints.B.contact.law={law}");
            let damping_set = format!("joints.B.contact.damping={damping}");
            let model = common::load(MODEL, &["joints.B.length=0.02", &law_set, &damping_set]);
            let options = SimulationOptions::default().energy(true);
            let summary = Simulation::new(&model, options)
                .and_then(|s| s.run(&mut Discard))
                .unwrap_or_else(|e| panic!("{law}/{damping}: {e}"));
            let balance = summary
                .energy_balance
                .unwrap_or_else(|| panic!("{law}/{damping}: energy balance asked for"));
            assert!(
                balance.relative_residual < 1e-6,
                "{law}/{damping}: energy residual {:e} of the driver work",
                balance.relative_residual
            );
            assert!(
                balance.dissipated > 0.0,
                "{law}/{damping}: dissipated {} J",
                balance.dissipated
            );
        }
    }
}

/// The impact log's peaks with the line laws come from their analytic rate dF_N/dt: sampled
/// every 1 µs (about a hundredth of a contact), the normal force never exceeds the logged peak
/// of its contact, and comes within 1e-3 of it (the sampling error of a smooth maximum,
/// (Δt/T)² with T ~ 0.1 ms, is ~1e-4).
#[test]
fn the_impact_log_peaks_are_the_true_peaks_with_the_line_laws() {
    for law in ["johnson", "liu"] {
        let law_set = format!("joints.B.contact.law={law}");
        let model = common::load(MODEL, &["joints.B.length=0.02", &law_set]);
        let options = SimulationOptions::default()
            .formulation(FormulationKind::Reduced)
            .revs(0.2)
            .dt(1e-6);
        let run = Simulation::new(&model, options)
            .and_then(|s| s.run_to_memory())
            .unwrap_or_else(|e| panic!("{law}: {e}"));
        let force = run
            .column("B.fn")
            .unwrap_or_else(|| panic!("{law}: no B.fn column"));
        let joint = &run.summary.clearance_joints[0];
        let mut checked = 0;
        for impact in &joint.impacts {
            let Some(duration) = impact.duration else {
                continue;
            };
            let sampled = run
                .t
                .iter()
                .zip(force)
                .filter(|(t, _)| **t >= impact.t && **t <= impact.t + duration)
                .map(|(_, f)| *f)
                .fold(0.0_f64, f64::max);
            let peak = impact.peak_normal_force;
            assert!(
                sampled <= peak * (1.0 + 1e-12) && sampled >= peak * (1.0 - 1e-3),
                "{law} impact {} at {} s: logged peak {peak} N, sampled max {sampled} N",
                impact.index,
                impact.t
            );
            checked += 1;
        }
        assert!(checked >= 3, "{law}: only {checked} finished contacts");
    }
}
