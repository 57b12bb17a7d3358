//! Claim: a lubricated clearance joint (`[joints.lubrication]`, `src/contact/lubrication/`)
//! reproduces the closed forms of hydrodynamic lubrication when integrated as part of a model,
//! and its film only ever dissipates energy.
//!
//! **Steady load (short bearing).** A journal spinning at ω in a fixed bearing under a constant
//! load W settles where the film carries the load. Ocvirk's short-bearing solution with the
//! π-film (Pinkus & Sternlicht 1961, §3.6; Flores et al. 2008, ch. 6) gives, with the
//! pressure p = 3μ(L²/4 − z²)(−g)/h³ on the half turn −π < θ < 0 (g = eω sin θ), the load
//! components F_r = μωRL³ε²/(c²(1 − ε²)²) (along the line of centres) and
//! F_t = πμωRL³ε/(4c²(1 − ε²)^(3/2)) (across it), derived here independently:
//! ∫_{−π}^0 sin² θ/(1 − ε cos θ)³ dθ = (π/2)(1 − ε²)^(−3/2) and
//! ∫_{−π}^0 sin θ cos θ/(1 − ε cos θ)³ dθ = −∫_{−1}^1 u/(1 − εu)³ du = −2ε/(1 − ε²)². So
//!
//! ```text
//!     W = (μωRL³/(4c²)) ε/(1 − ε²)² √(π²(1 − ε²) + 16ε²),   tan ψ = π√(1 − ε²)/(4ε)
//! ```
//!
//! (ψ the attitude angle between the load line and the line of centres; the journal sits on
//! the side the spin carries it to). The steady ε is found from W by bisection in the test.
//!
//! **Pure squeeze (short bearing).** A journal without spin, at rest in the centre, pushed
//! along x by a constant force F0: the π-film is the half turn −π/2 < θ < π/2 facing the
//! motion and the film's force is F = (μRL³ė/c³) I(ε),
//! I(ε) = [(1 + 2ε²)(π/2 + asin ε) + 3ε√(1 − ε²)]/(1 − ε²)^(5/2)
//! (∫ cos² θ/(1 − ε cos θ)³ over that half turn, by Sommerfeld's substitution). Since
//! ė = c dε/dt, F dt = (μRL³/c²) I(ε) dε, and I = dJ/dε with
//! J(ε) = ε(π/2 + asin ε)/(1 − ε²)^(3/2) + 1/(1 − ε²) (differentiate to check), the momentum
//! balance m dv/dt = F0 − F integrates exactly, inertia included:
//!
//! ```text
//!     m v(t) = F0 t − (μRL³/c²) (J(ε(t)) − J(0)).
//! ```
//!
//! (A clearance joint starts with the journal moving with the bearing: the assembly makes the
//! initial relative velocity zero, hence the push rather than a throw.)
//!
//! **Energy.** On the shipped lubricated slider-crank, the work of the motor equals the change
//! of the mechanical energy plus what the contacts and the film dissipated, and the film's
//! power (its forces and shear torques on both bodies) is never positive.

mod common;

use common::col;
use linkdyn::formulation::{Dae, DaeOptions, Formulation};
use linkdyn::model::Model;
use linkdyn::solve::{Method, Recorder, SolverOptions, integrate};
use std::f64::consts::{FRAC_PI_2, PI};

const MU: f64 = 0.05; // Pa·s
const R: f64 = 0.01; // m
const L: f64 = 0.01; // m
const C: f64 = 5e-4; // m

/// A journal body "shaft" centred in a bearing on the ground, spinning at `omega`, under a
/// constant force `force` (N); mass `mass`, a large inertia so that the film's shear torque
/// hardly slows the spin.
fn journal_model(omega: f64, force: [f64; 2], mass: f64) -> Model {
    let text = format!(
        r#"
[model]
name = "lubricated_journal"
[settings]
gravity = [0.0, 0.0]
[ground]
points = {{ O = [0.0, 0.0] }}
[[bodies]]
name = "shaft"
mass = {mass:e}
inertia = 1.0
points = {{ C = [0.0, 0.0] }}
initial = {{ x = 0.0, y = 0.0, phi = 0.0, omega = {omega:e} }}
[[joints]]
name = "J"
type = "clearance"
bearing = "ground"
bearing_point = "O"
journal = "shaft"
journal_point = "C"
clearance = {C:e}
journal_radius = {R:e}
length = {L:e}
[joints.lubrication]
model = "short"
viscosity = {MU:e}
[[forces]]
name = "load"
type = "force"
body = "shaft"
point = "C"
force = [{fx:e}, {fy:e}]
"#,
        fx = force[0],
        fy = force[1]
    );
    linkdyn::model::load_str(&text, "lubricated_journal.toml", &[])
        .unwrap_or_else(|e| panic!("{e}"))
}

fn run(model: &Model, t_end: f64, dt: f64, rtol: f64, energy: bool) -> Recorder {
    let options = DaeOptions {
        energy,
        ..DaeOptions::default()
    };
    let mut dae = Dae::new(model, &options).unwrap_or_else(|e| panic!("{e}"));
    let solver = SolverOptions::default()
        .method(Method::Dop853)
        .rtol(rtol)
        .atol(rtol * 1e-6)
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let y0 = dae.initial_state();
    let mut rec = Recorder::new(&dae);
    integrate(&mut dae, 0.0, &y0, t_end, dt, &solver, &mut rec).unwrap_or_else(|e| panic!("{e}"));
    rec
}

/// Ocvirk's steady load W(ε) (N) at spin ω (module documentation).
fn steady_load(eps: f64, omega: f64) -> f64 {
    let m = 1.0 - eps * eps;
    MU * omega * R * L.powi(3) / (4.0 * C * C) * eps / (m * m)
        * (PI * PI * m + 16.0 * eps * eps).sqrt()
}

/// The ε that carries `load` at spin ω, by bisection (W grows monotonically with ε).
fn steady_eccentricity(load: f64, omega: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 1.0 - 1e-12);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if steady_load(mid, omega) < load {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn spinning_journal_reaches_ocvirk_eccentricity_and_attitude() {
    // W = 1 N on a 1 g journal: the mass parameter m c ω²/W = 0.02 keeps the journal far
    // from oil whirl, and the film settles it within ~1e-3 s.
    let (omega, load) = (200.0, 1.0);
    // It is settled to 1e-9 by t = 0.1 s.
    let rec = run(
        &journal_model(omega, [0.0, -load], 1e-3),
        0.3,
        1e-2,
        1e-11,
        false,
    );
    let last = rec.t.len() - 1;
    let (ex, ey) = (col(&rec, "J.ex")[last], col(&rec, "J.ey")[last]);
    // The spin at the end (the shear torque of ~2e-3 N·m slows it by 1e-4 rad/s over the run).
    let spin = col(&rec, "shaft.omega")[last];
    let eps = ex.hypot(ey) / C;
    let expected = steady_eccentricity(load, spin);
    assert!(
        (eps / expected - 1.0).abs() < 1e-6,
        "steady ε = {eps}, Ocvirk's {expected} (W = {load} N, ω = {spin} rad/s)"
    );
    // Attitude: angle between the load line (−y) and e; a counter-clockwise spin carries the
    // journal to the +x side.
    let psi = (ex / -ey).atan();
    let psi_expected = (PI * (1.0 - expected * expected).sqrt() / (4.0 * expected)).atan();
    assert!(ex > 0.0 && ey < 0.0, "journal at ({ex}, {ey})");
    assert!(
        (psi / psi_expected - 1.0).abs() < 1e-6,
        "attitude ψ = {psi} rad, closed form {psi_expected} rad (ε = {expected})"
    );
    // The film carries the whole load: J.fn is the film's normal force there, and the
    // total force balances W.
    let (f_n, f_t) = (col(&rec, "J.fn")[last], col(&rec, "J.ft")[last]);
    assert_eq!(
        f_n,
        col(&rec, "J.fn_film")[last],
        "no dry contact at ε = {eps}"
    );
    assert!(
        (f_n.hypot(f_t) / load - 1.0).abs() < 1e-6,
        "film force {} N against the load {load} N",
        f_n.hypot(f_t)
    );
}

/// J(ε) of the module documentation.
fn squeeze_primitive(eps: f64) -> f64 {
    let m = 1.0 - eps * eps;
    eps * (FRAC_PI_2 + eps.asin()) / m.powf(1.5) + 1.0 / m
}

#[test]
fn pure_squeeze_follows_the_closed_form() {
    // A 10 g journal pushed along +x by 1 N from the centre: ε reaches ~0.8 by t = 0.022 s,
    // and m v is ~1 % of the impulse F0 t, so inertia takes part.
    let (mass, push, t_end) = (0.01, 1.0, 0.022);
    let rec = run(
        &journal_model(0.0, [push, 0.0], mass),
        t_end,
        2e-4,
        1e-11,
        false,
    );
    let (ex, ey, vx) = (col(&rec, "J.ex"), col(&rec, "J.ey"), col(&rec, "shaft.vx"));
    let damping = MU * R * L.powi(3) / (C * C); // μRL³/c² (N·s)
    let mut worst: f64 = 0.0;
    for i in 0..rec.t.len() {
        assert!(ey[i].abs() < 1e-12 * C, "left the x-axis: e_y = {}", ey[i]);
        // m v = F0 t − (μRL³/c²)(J(ε) − J(0)), the momentum balance integrated exactly.
        let momentum =
            push * rec.t[i] - damping * (squeeze_primitive(ex[i] / C) - squeeze_primitive(0.0));
        worst = worst.max((mass * vx[i] - momentum).abs() / (push * t_end));
    }
    assert!(
        worst < 1e-6,
        "momentum off the closed form by {worst:e} of the impulse F0 t_end"
    );
    let eps_end = ex[ex.len() - 1] / C;
    let inertia = mass * vx[vx.len() - 1] / (push * t_end);
    assert!(
        eps_end > 0.7 && eps_end < 0.9 && inertia > 1e-3,
        "ε = {eps_end}, m v/(F0 t) = {inertia}: not the case meant"
    );
}

/// The shipped lubricated slider-crank, two crank turns with the energy books: the motor's work
/// equals the change of T + U + V_contact plus what contacts and film dissipated, and at every
/// sample the film's power on the two bodies (its pressure forces and shear torques,
/// `contact::lubrication`) is not positive; over the run the film dissipates a share of the
/// motor's work that is not negligible.
#[test]
fn shipped_slider_crank_energy_balance_and_film_dissipation() {
    let model = common::load("models/slider_crank_lubricated.toml", &[]);
    let t_end = 2.0 * 60.0 / 600.0;
    let rec = run(&model, t_end, 1e-4, 1e-10, true);
    let driver = col(&rec, "energy.driver_work");
    let balance = col(&rec, "energy.balance");
    let dissipated = col(&rec, "energy.dissipated");
    let scale = driver.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let worst = balance.iter().fold(0.0_f64, |m, x| m.max(x.abs())) / scale;
    // The books are integrated with the motion at rtol 1e-10 (measured: 1.5e-12 of the work);
    // 1e-9 leaves room for the contact phases' error control, far below the film's share
    // (3.5 % of the work, below).
    assert!(
        worst < 1e-9,
        "balance off by {worst:e} of the motor's work ({scale} J)"
    );
    assert!(
        dissipated.windows(2).all(|w| w[1] >= w[0] - 1e-12 * scale),
        "the dissipated energy decreased"
    );

    // The film's power at every sample, from the body states in the columns.
    let dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let k = model
        .joints
        .iter()
        .filter(|j| matches!(j.kind, linkdyn::model::JointKind::Clearance(_)))
        .position(|j| j.name == "A")
        .unwrap_or_else(|| panic!("no clearance joint A"));
    let columns: Vec<Vec<f64>> = model
        .bodies
        .iter()
        .flat_map(|b| {
            ["x", "y", "phi", "vx", "vy", "omega"].map(|c| col(&rec, &format!("{}.{c}", b.name)))
        })
        .collect();
    let film_column = col(&rec, "A.fn_film");
    let mut film_work = 0.0;
    let mut last_power = 0.0;
    for i in 0..rec.len() {
        let (mut q, mut v) = (Vec::new(), Vec::new());
        for b in 0..model.bodies.len() {
            q.extend((0..3).map(|c| columns[6 * b + c][i]));
            v.extend((3..6).map(|c| columns[6 * b + c][i]));
        }
        let s = dae.contacts().site_state_alone(k, &q, &v, 0.0);
        let power = s.film.power;
        assert!(
            power <= 1e-12 * scale,
            "film power {power} W > 0 at t = {}",
            rec.t[i]
        );
        assert_eq!(
            s.film.normal_force, film_column[i],
            "the film column at t = {}",
            rec.t[i]
        );
        if i > 0 {
            film_work += 0.5 * (power + last_power) * (rec.t[i] - rec.t[i - 1]);
        }
        last_power = power;
    }
    assert!(
        -film_work > 1e-2 * scale,
        "the film dissipated only {} J of {scale} J",
        -film_work
    );
}

/// The shipped lubricated slider-crank in the formulations and methods that take it, one crank
/// turn each at rtol 1e-9: they agree on joint A's first impact (where the film has thinned to
/// the contact threshold; measured within 2e-11 s) and its peak normal force (film plus
/// contact; measured within 1.4e-8), and the reduced formulation refuses a lubricated joint
/// (on the reference four-bar, the one model it takes) with the reason. Radau5 runs on the DAE's Jacobian with the film's
/// central differences (`formulation/dae/jacobian.rs`).
#[test]
fn shipped_slider_crank_in_every_formulation_and_method() {
    use linkdyn::simulation::{Discard, FormulationKind, Simulation, SimulationOptions};
    let model = common::load("models/slider_crank_lubricated.toml", &[]);
    let run = |formulation: FormulationKind, method: Method| {
        let options = SimulationOptions::default()
            .formulation(formulation)
            .revs(1.0)
            .solver(
                SolverOptions::default()
                    .method(method)
                    .rtol(1e-9)
                    .atol(1e-12),
            );
        let summary = Simulation::new(&model, options)
            .and_then(|s| s.run(&mut Discard))
            .unwrap_or_else(|e| panic!("{formulation:?} {method:?}: {e}"));
        summary
            .clearance_joints
            .into_iter()
            .find(|j| j.joint == "A")
            .unwrap_or_else(|| panic!("no joint A"))
    };
    let reference = run(FormulationKind::Dae, Method::Dop853);
    assert!(!reference.impacts.is_empty(), "no impact at A");
    for (formulation, method) in [
        (FormulationKind::Dae, Method::Radau5),
        (FormulationKind::Dae, Method::Dopri5),
        (FormulationKind::Generalized, Method::Dop853),
    ] {
        let r = run(formulation, method);
        let (a, b) = (&reference.impacts[0], &r.impacts[0]);
        assert!(
            (a.t - b.t).abs() <= 1e-9,
            "{formulation:?} {method:?}: first impact at {} s, DAE/DOP853 {} s",
            b.t,
            a.t
        );
        assert!(
            (r.peak_normal_force / reference.peak_normal_force - 1.0).abs() <= 1e-6,
            "{formulation:?} {method:?}: peak {} N, DAE/DOP853 {} N",
            r.peak_normal_force,
            reference.peak_normal_force
        );
    }
    let fourbar = common::load(
        "models/farahan2016.toml",
        &[
            "joints.B.length=0.02",
            "joints.B.lubrication.model=short",
            "joints.B.lubrication.viscosity=0.1",
        ],
    );
    let refused = SimulationOptions::default().formulation(FormulationKind::Reduced);
    let message = match Simulation::new(&fourbar, refused) {
        Ok(_) => panic!("the reduced formulation took a lubricated joint"),
        Err(e) => e.to_string(),
    };
    assert!(
        message.contains("the clearance joint \"B\" is lubricated")
            && message.contains("DAE or the generalised"),
        "{message}"
    );
}

/// Bad `[joints.lubrication]` settings are refused with the file, line and column, the field
/// and what was expected; a missing bearing `length` with the reason it is needed.
#[test]
fn bad_lubrication_settings_are_refused_with_the_reason() {
    const FILE: &str = "models/slider_crank_lubricated.toml";
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(FILE);
    let refusal = |set: &str| match linkdyn::model::load(&path, &[set.to_string()]) {
        Ok(_) => panic!("--set {set} was accepted"),
        Err(e) => e.to_string(),
    };
    let file = path.display().to_string();
    let cases = [
        (
            "joints.A.lubrication.model=medium",
            format!(
                "{file}:66:9: joints.A.lubrication.model: unknown film model \"medium\"; expected one of short, long (value from --set joints.A.lubrication.model=medium)"
            ),
        ),
        (
            "joints.A.lubrication.viscosity=0",
            format!(
                "{file}:67:13: joints.A.lubrication.viscosity: expected a positive viscosity (Pa·s), found 0 (value from --set joints.A.lubrication.viscosity=0)"
            ),
        ),
        (
            "joints.A.lubrication.viscosity=-0.1",
            format!(
                "{file}:67:13: joints.A.lubrication.viscosity: expected a positive viscosity (Pa·s), found -0.1 (value from --set joints.A.lubrication.viscosity=-0.1)"
            ),
        ),
        (
            "joints.A.lubrication.contact_film_thickness=3e-4",
            format!(
                "{file}: joints.A.lubrication.contact_film_thickness: expected a contact film thickness of at most half the radial clearance (2.5e-4 m), found 3e-4 m (value from --set joints.A.lubrication.contact_film_thickness=3e-4)"
            ),
        ),
        (
            "joints.A.initial_eccentricity=[4.96e-4,0]",
            format!(
                "{file}:63:24: joints.A.initial_eccentricity: initial eccentricity |e| = 4.960000e-4 m leaves a film thinner than contact_film_thickness = 5.000000e-6 m; expected |e| < c − contact_film_thickness = 4.950000e-4 m, since the dry contact that begins there would have no impact velocity to scale its damping (value from --set joints.A.initial_eccentricity=[4.96e-4,0])"
            ),
        ),
    ];
    for (set, expected) in cases {
        assert_eq!(refusal(set), expected, "--set {set}");
    }
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{e}"));
    let no_length = text.replacen(
        "length = 0.02                       # bearing length L (m)\n",
        "",
        1,
    );
    assert_ne!(no_length, text, "model edit failed");
    let message = match linkdyn::model::load_str(&no_length, "no_length.toml", &[]) {
        Ok(_) => panic!("a lubricated joint without length was accepted"),
        Err(e) => e.to_string(),
    };
    assert_eq!(
        message,
        "no_length.toml:64:1: joints.A.lubrication: a lubricated joint needs the bearing's axial length, which sets the film's load capacity (∝ L³ for the short bearing, ∝ L for the long): expected a field `length` (m, > 0) on clearance joint \"A\", e.g. length = 0.02"
    );
}

/// A lubricated revolute joint beside a prismatic-clearance joint: the slider-crank in its
/// guide with clearance (models/slider_crank_prismatic_clearance.toml) with its crank pin A
/// made a lubricated clearance joint as in models/slider_crank_lubricated.toml. The contact
/// sites are the revolute joint first, then the guide's four corners; the film belongs to the
/// first only (an index over all sites read past the revolute ones when the two features were
/// merged). One crank turn with the energy books: every column finite, the film's column
/// beside A's, the corners' after it, and the balance closed.
#[test]
fn a_lubricated_pin_and_a_slider_in_a_guide_with_clearance_run_together() {
    let text = std::fs::read_to_string("models/slider_crank_prismatic_clearance.toml")
        .unwrap_or_else(|e| panic!("{e}"));
    let ideal_pin = "name = \"A\"\ntype = \"revolute\"\nbody_a = \"crank\"\npoint_a = \"A\"\nbody_b = \"rod\"\npoint_b = \"A\"\n";
    assert!(
        text.contains(ideal_pin),
        "the shipped model's pin A changed"
    );
    let lubricated_pin = r#"name = "A"
type = "clearance"
bearing = "rod"
bearing_point = "A"
journal = "crank"
journal_point = "A"
clearance = 0.0005
journal_radius = 0.01
length = 0.02
youngs_modulus = 207e9
poisson_ratio = 0.3
[joints.lubrication]
model = "long"
viscosity = 0.1
[joints.contact]
law = "lankarani-nikravesh"
restitution = 0.9
exponent = 1.5
"#;
    let model = linkdyn::model::load_str(
        &text.replace(ideal_pin, lubricated_pin),
        "pin_and_guide.toml",
        &[],
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let rec = run(&model, 60.0 / 600.0, 1e-4, 1e-10, true);
    let names = &rec.names;
    let at = |c: &str| {
        names
            .iter()
            .position(|n| n == c)
            .unwrap_or_else(|| panic!("no column {c}"))
    };
    assert_eq!(at("A.fn_film"), at("A.ft") + 1);
    assert_eq!(at("rail.c1.delta"), at("A.fn_film") + 1);
    assert!(
        rec.values.iter().all(|x| x.is_finite()),
        "a column is not finite"
    );
    let driver = col(&rec, "energy.driver_work");
    let scale = driver.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let worst = col(&rec, "energy.balance")
        .iter()
        .fold(0.0_f64, |m, x| m.max(x.abs()))
        / scale;
    assert!(
        worst < 1e-8,
        "balance off by {worst:e} of the motor's work ({scale} J)"
    );
}
