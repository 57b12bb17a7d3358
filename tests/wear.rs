//! Archard wear of a revolute clearance joint's bearing (`linkdyn::studies::wear`,
//! docs/wear.md) against closed forms, on two rigs where a bushing (the bearing) turns at
//! 600 rpm about a fixed centre and a non-turning pin (the journal) is pressed into it:
//!
//! * the shipped `models/wear_pin.toml`: a constant 200 N load fixed in the ground frame, so
//!   the contact sweeps the bore uniformly: every bin wears to h = k_w F N / L after N turns;
//! * a rig built here whose load turns with the bushing, so the contact stays at one angle of
//!   the bore: the bore wears there at Archard's rate k_w p0 v under the Hertz peak pressure
//!   p0, and after a profile update the pin sits deeper by the wear depth.
//!
//! Both contacts are frictionless, so the pin never turns and the sliding speed is set by the
//! bushing: R_B ω (first rig) or R_J ω (second: the pin's centre orbits with the load).

use linkdyn::model::load_str;
use linkdyn::simulation::{Simulation, SimulationOptions};
use linkdyn::studies::{WearRequest, WearResult, wear};
use std::f64::consts::{PI, TAU};

const OMEGA: f64 = 600.0 * TAU / 60.0; // rad/s
const C: f64 = 5e-4; // clearance (m)
const R_J: f64 = 0.01; // journal radius (m)
const LENGTH: f64 = 0.02; // bearing length (m)

fn run(text: &str, overrides: &[&str], turns: usize, update_every: usize) -> WearResult {
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let model = load_str(text, "wear_rig.toml", &overrides).expect("model loads");
    let sim = Simulation::new(&model, SimulationOptions::default().revs(turns as f64))
        .expect("simulation builds");
    wear(
        &sim,
        WearRequest {
            turns,
            update_every,
        },
    )
    .expect("wear study runs")
}

fn wear_pin() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/models/wear_pin.toml"))
        .expect("models/wear_pin.toml")
}

/// Mean of `v`.
fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// A load fixed in the ground frame on a turning bushing (models/wear_pin.toml): after N = 4
/// turns the mean depth is Archard's closed form h = k_w p̄ v t = k_w (F/(2π R_B L)) (R_B ω)
/// (2π N/ω) = k_w F N/L, and the wear is uniform around the bore (a load that is symmetric
/// under every rotation of the bushing wears it symmetrically).
///
/// Tolerances: the mean to 1e-5, since the worn volume is k_w ∫F_N v dt exactly and ∫F_N dt
/// differs from F t only by the pin's momentum change (it starts at rest and ends in residual
/// contact oscillations: m Δv/(F t) ≈ 0.2 kg · 1e-3 m/s / 80 N·s ≈ 2.5e-6). Uniformity over 10°
/// sectors to 1e-3 and over single 1° bins to 1e-2: the wear is deposited at three instants
/// per solver step, each spread over the Hertz width (2b ≈ 1.7° here), and a step turns the
/// bushing by up to ~0.4°, so single bins ripple by the sampling of the semi-ellipse's steep
/// edges, a ripple that averages out over a sector swept in ~30 steps. The transients after the
/// start and after each update (the pin drops onto the newly worn bore and bounces) all happen
/// with the contact near 270°: the single-bin bound leaves out 260–280°, the sector bound
/// holds there too.
#[test]
fn uniform_load_wears_the_bore_uniformly_to_archards_depth() {
    let turns = 4;
    let r = run(&wear_pin(), &[], turns, 2);
    let (k_w, f) = (1e-11, 200.0);
    let closed = k_w * f * turns as f64 / LENGTH;
    let last = &r.updates.last().expect("updates").depth;
    assert_eq!(last.len(), 360);
    let m = mean(last);
    assert!(
        (m - closed).abs() < 1e-5 * closed,
        "mean depth {m:e} m, Archard k_w F N / L = {closed:e} m"
    );
    assert!(
        (r.summary.mean_depth - closed).abs() < 1e-5 * closed,
        "summary mean depth {:e}",
        r.summary.mean_depth
    );
    for (i, h) in last.iter().enumerate() {
        // The transients happen with the contact within a few degrees of 270°.
        if (i as f64 + 0.5 - 270.0).abs() < 10.0 {
            continue;
        }
        assert!(
            (h - m).abs() < 1e-2 * m,
            "bin {i} ({}°): {h:e} m against the mean {m:e} m",
            i as f64 + 0.5
        );
    }
    for s in 0..36 {
        let sector = mean(&last[10 * s..10 * s + 10]);
        assert!(
            (sector - m).abs() < 1e-3 * m,
            "sector {}–{}°: {sector:e} m against the mean {m:e} m",
            10 * s,
            10 * s + 10
        );
    }
    // Half the wear in each half of the run: the updates do not change the wear rate of a
    // uniform profile.
    let half = mean(&r.updates[1].depth);
    assert!(
        (half - 0.5 * closed).abs() < 1e-5 * closed,
        "after 2 turns {half:e} m, expected {:e} m",
        0.5 * closed
    );
}

/// The rig whose 100 N load turns with the bushing at the centre of bin 0 (0.5° in the bore's
/// frame, of 3600 bins): the contact stays there. The pin starts at rest, so at first it lags
/// the turning load and swings about it (±2.5°, at sqrt(F/(m c)) = 1414 rad/s, undamped on a
/// frictionless wall); a damper (200 N·s/m) from the pin to a bushing point 5 cm away at right
/// angles to the load damps the swing (damping ratio 0.7) and, once the pin turns with the
/// bushing, its length stays constant and it exerts no force.
fn turning_load_rig(k_w: f64) -> String {
    let a0 = 0.5 * TAU / 3600.0;
    let e0 = C - 1e-7;
    format!(
        r#"
[model]
name = "turning_load_rig"

[settings]
gravity = [0.0, 0.0]

[ground]
points = {{ O = [0.0, 0.0] }}

[[bodies]]
name = "bushing"
mass = 0.5
inertia = 1e-4
points = {{ C = [0.0, 0.0], D = [{dx}, {dy}] }}
initial = {{ x = 0.0, y = 0.0, phi = 0.0 }}

[[bodies]]
name = "pin"
mass = 0.1
inertia = 1e-5
points = {{ P = [0.0, 0.0] }}
initial = {{ x = {x}, y = {y}, phi = 0.0 }}

[[joints]]
name = "O"
type = "revolute"
body_a = "ground"
point_a = "O"
body_b = "bushing"
point_b = "C"

[[joints]]
name = "J"
type = "clearance"
bearing = "bushing"
bearing_point = "C"
journal = "pin"
journal_point = "P"
clearance = {C}
journal_radius = {R_J}
length = {LENGTH}
initial_eccentricity = [{x}, {y}]

[joints.friction]
law = "none"

[joints.wear]
coefficient = {k_w}
bins = 3600

[[forces]]
name = "load"
type = "force"
body = "pin"
point = "P"
force = ["100*cos(bushing.phi + {a0})", "100*sin(bushing.phi + {a0})"]

[[forces]]
name = "swing_damper"
type = "spring-damper"
body_a = "bushing"
point_a = "D"
body_b = "pin"
point_b = "P"
stiffness = 0.0
damping = 200.0
free_length = {free}

[[drivers]]
name = "motor"
type = "constant-speed"
joint = "O"
speed_rpm = 600.0
"#,
        x = e0 * a0.cos(),
        y = e0 * a0.sin(),
        dx = -0.05 * a0.sin(),
        dy = 0.05 * a0.cos(),
        free = (e0 * e0 + 0.05 * 0.05_f64).sqrt(),
    )
}

/// Hertz data of the rig: steel on steel (207 GPa, 0.3), R* = R_J R_B / c.
fn hertz_half_width(normal_force: f64) -> f64 {
    let e_star = 207e9 / (2.0 * (1.0 - 0.09));
    let r_b = R_J + C;
    let r_star = R_J * r_b / C;
    (4.0 * normal_force * r_star / (PI * LENGTH * e_star)).sqrt()
}

/// Constant load at a fixed angle of the bore, constant sliding speed: over the second turn
/// (T = 0.1 s, after the start's swing has died out), the bin under the contact wears by
/// Archard's h = k_w p0 v T, with the Hertz peak pressure p0 = 2F_N/(π L b) and
/// v = (R_J − δ) ω ≈ R_J ω; F_N = F + m |e| ω² (the load plus the pin's centripetal force,
/// |e| ≈ c); the worn area grows by k_w F_N v T / L; nothing wears outside the contact width,
/// and the wear is mirror-symmetric about the load.
///
/// Tolerances: 3e-3 on the centre bin, from the bin average of the semi-ellipse
/// ((Δs/b)²/24 = 1.2e-3, Δs = R_B·0.1° = 1.8e-5 m, b = 1.1e-4 m) and v = (R_J − δ)ω with
/// δ ≈ 1e-6 m (1e-4); 1e-3 on the worn area (δ/R_J and the pin's radial settling after the
/// update, when it drops by the 0.2 µm worn in the first turn).
#[test]
fn fixed_contact_wears_at_the_hertz_peak_rate() {
    let k_w = 1e-13;
    let r = run(&turning_load_rig(k_w), &[], 2, 1);
    let depth: Vec<f64> = r.updates[2]
        .depth
        .iter()
        .zip(&r.updates[1].depth)
        .map(|(a, b)| a - b)
        .collect();
    let f_n = 100.0 + 0.1 * C * OMEGA * OMEGA;
    let b = hertz_half_width(f_n);
    let v = R_J * OMEGA;
    let t = TAU / OMEGA;
    let p0 = 2.0 * f_n / (PI * LENGTH * b);
    let h = k_w * p0 * v * t;
    assert!(
        (depth[0] - h).abs() < 3e-3 * h,
        "centre bin {:e} m, Archard k_w p0 v T = {h:e} m",
        depth[0]
    );
    let bin_arc = (R_J + C) * TAU / 3600.0;
    let area: f64 = depth.iter().sum::<f64>() * bin_arc;
    let closed = k_w * f_n * v * t / LENGTH;
    assert!(
        (area - closed).abs() < 1e-3 * closed,
        "worn area {area:e} m², k_w F_N v T / L = {closed:e} m²"
    );
    // Outside ±(b + two bins) of the contact nothing wears; b spans about 6 bins.
    let reach = (b / bin_arc).ceil() as usize + 2;
    for (i, d) in depth.iter().enumerate() {
        let from = i.min(3600 - i);
        if from > reach {
            assert!(
                d.abs() < 1e-9 * h,
                "bin {i} ({from} bins from the contact) wore {d:e} m"
            );
        }
    }
    // Mirror symmetric about the contact (bin 0's centre): bins k and −k (mod 3600), to 1e-3
    // of the centre depth (the semi-ellipse's steep edges sampled by a contact that settles
    // within a small fraction of a bin).
    for k in 1..reach {
        let (a, c) = (depth[k], depth[3600 - k]);
        assert!(
            (a - c).abs() < 1e-3 * depth[0],
            "bins ±{k}: {a:e} m and {c:e} m"
        );
    }
}

/// After an update the contact sees the grown clearance: the pin, pressed by the same load,
/// settles deeper by the wear depth under it. The eccentricity at the end of turn 2 minus that
/// at the end of turn 1 equals the depth of bin 0 after the first update (the contact sits at
/// its centre), to 2e-3 of it: the residual oscillation of the pin on the contact stiffness
/// after it dropped onto the worn bore, of order the static deflection 1e-6 m times the decay
/// of the hysteresis damping, against a depth of 2e-5 m.
#[test]
fn after_an_update_the_journal_sits_deeper_by_the_wear() {
    let r = run(&turning_load_rig(1e-11), &[], 2, 1);
    let h1 = r.updates[1].depth[0];
    assert!(h1 > 1e-5, "the first turn wears {h1:e} m");
    let sank = r.updates[2].eccentricity - r.updates[1].eccentricity;
    assert!(
        (sank - h1).abs() < 2e-3 * h1,
        "the pin sank {sank:e} m, the bore wore {h1:e} m"
    );
    // And before any wear it sat at the unworn wall: |e| − c is the static penetration
    // (F_N/K)^(2/3) with K = 6.9494e10 N/m^1.5 (steel, c = 0.5 mm, R_J = 10 mm), to 5 % (the
    // residual oscillation on the contact).
    let static_delta = r.updates[1].eccentricity - C;
    let expected = ((100.0 + 0.1 * C * OMEGA * OMEGA) / 6.9494e10_f64).powf(1.0 / 1.5);
    assert!(
        (static_delta - expected).abs() < 0.05 * expected,
        "unworn penetration {static_delta:e} m, static {expected:e} m"
    );
}

/// Bad input is refused with the file, the line and what was expected.
#[test]
fn bad_wear_fields_are_refused_with_the_reason() {
    let text = wear_pin();
    let cases: [(&str, &str); 4] = [
        (
            "joints.J.wear.coefficient=-1",
            "expected a positive wear coefficient k/H (m²/N), found -1",
        ),
        (
            "joints.J.wear.bins=360.5",
            "expected an integer number of wear bins, found 360.5",
        ),
        (
            "joints.J.wear.bins=4",
            "expected a number of wear bins in [8e0, 1e5] (angular bins on the bearing surface), found 4e0",
        ),
        ("joints.J.wear.hardness=1e9", "hardness"),
    ];
    for (set, expected) in cases {
        let err = load_str(&text, "wear_pin.toml", &[set.to_string()])
            .expect_err(set)
            .to_string();
        assert!(
            err.contains(expected) && err.contains("wear_pin.toml"),
            "--set {set}: {err}"
        );
    }
    // The length is required, and the lubricated joint refuses wear.
    let no_length = text.replace("length = 0.02", "");
    let err = load_str(&no_length, "wear_pin.toml", &[])
        .expect_err("no length")
        .to_string();
    assert!(
        err.contains("a worn joint needs the bearing's axial length")
            && err.contains("expected a field `length` (m, > 0) on clearance joint \"J\""),
        "{err}"
    );
    let err = load_str(
        &text,
        "wear_pin.toml",
        &[
            "joints.J.lubrication.model=short".into(),
            "joints.J.lubrication.viscosity=0.01".into(),
        ],
    )
    .expect_err("lubricated")
    .to_string();
    assert!(
        err.contains("has both [joints.lubrication] and [joints.wear]"),
        "{err}"
    );
}

/// The study refuses the formulations it cannot change, and a model without a worn joint.
#[test]
fn wear_study_refusals() {
    let model = load_str(&wear_pin(), "wear_pin.toml", &[]).expect("loads");
    let options = SimulationOptions::default()
        .revs(1.0)
        .formulation(linkdyn::simulation::FormulationKind::Generalized);
    let sim = Simulation::new(&model, options).expect("builds");
    let err = wear(
        &sim,
        WearRequest {
            turns: 1,
            update_every: 1,
        },
    )
    .expect_err("generalized")
    .to_string();
    assert!(
        err.contains("the wear study runs on the DAE formulation only"),
        "{err}"
    );
    let text = wear_pin();
    let (start, end) = (
        text.find("[joints.wear]").expect("wear table"),
        text.find("[[forces]]").expect("forces"),
    );
    let unworn = format!("{}{}", &text[..start], &text[end..]);
    let model = load_str(&unworn, "wear_pin.toml", &[]).expect("loads without wear");
    let sim = Simulation::new(&model, SimulationOptions::default().revs(1.0)).expect("builds");
    let err = wear(
        &sim,
        WearRequest {
            turns: 1,
            update_every: 1,
        },
    )
    .expect_err("no worn joint")
    .to_string();
    assert!(
        err.contains("no clearance joint of the model has a [joints.wear] table"),
        "{err}"
    );
}
