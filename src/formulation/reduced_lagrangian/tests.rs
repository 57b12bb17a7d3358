use super::*;
use crate::model::load_str;

/// Geometry and options of a test four-bar: the paper's Table 1 with the clearance joint at B,
/// optionally with rotated body frames, shifted centres of mass, swapped bearing, a reversed
/// driver joint and extra loads.
#[derive(Clone)]
struct Variant {
    /// Per body (crank, coupler, rocker): rotation ψ of the body frame (rad) and shift o of the
    /// centre of mass in the original body frame (m).
    frames: [(f64, [f64; 2]); 3],
    bearing_on_coupler: bool,
    friction: &'static str,
    reversed_driver: bool,
    extra: &'static str,
    /// Joint fields and `[joints.contact]` lines of joint B ("" = the default law).
    contact: &'static str,
}

impl Default for Variant {
    fn default() -> Self {
        Variant {
            frames: [(0.0, [0.0, 0.0]); 3],
            bearing_on_coupler: true,
            friction: "law = \"ambrosio\"\ncoefficient = 0.1\nv0 = 1e-4\nv1 = 1e-3",
            reversed_driver: false,
            extra: "",
            contact: "",
        }
    }
}

fn rot(phi: f64, s: [f64; 2]) -> [f64; 2] {
    rotate(phi.sin_cos(), s)
}

fn model_text(v: &Variant) -> String {
    // Reference bodies: name, mass, inertia, points, initial (x, y, phi).
    type Ref = (
        &'static str,
        f64,
        f64,
        [(&'static str, [f64; 2]); 2],
        [f64; 3],
    );
    let refs: [Ref; 3] = [
        (
            "crank",
            0.494,
            0.0046,
            [("O2", [-0.125, 0.0]), ("A", [0.125, 0.0])],
            [0.125, 0.0, 0.0],
        ),
        (
            "coupler",
            1.003,
            0.0545,
            [("A", [-0.375, 0.0]), ("B", [0.375, 0.0])],
            [0.55, 0.22, 0.64],
        ),
        (
            "rocker",
            0.74,
            0.0189,
            [("O4", [-0.225, 0.0]), ("B", [0.225, 0.0])],
            [0.83, 0.22, 1.45],
        ),
    ];
    let mut text = String::from(
        "[model]\nname = \"test\"\n[settings]\ngravity = [0.0, -9.81]\n[ground]\npoints = { O2 = [0.0, 0.0], O4 = [0.8, 0.0] }\n",
    );
    for ((name, mass, inertia, points, init), (psi, o)) in refs.iter().zip(v.frames) {
        // New body frame: origin at the shifted centre o, rotated by ψ: s' = R(−ψ)(s − o).
        let p: Vec<String> = points
            .iter()
            .map(|(n, s)| {
                let q = rot(-psi, [s[0] - o[0], s[1] - o[1]]);
                format!("{n} = [{:.17e}, {:.17e}]", q[0], q[1])
            })
            .collect();
        let shift = rot(init[2], o);
        text += &format!(
            "[[bodies]]\nname = \"{name}\"\nmass = {mass}\ninertia = {inertia}\npoints = {{ {} }}\ninitial = {{ x = {:.17e}, y = {:.17e}, phi = {:.17e} }}\n",
            p.join(", "),
            init[0] + shift[0],
            init[1] + shift[1],
            init[2] + psi
        );
    }
    let (a, b) = if v.reversed_driver {
        ("crank", "ground")
    } else {
        ("ground", "crank")
    };
    text += &format!(
        "[[joints]]\nname = \"O2\"\ntype = \"revolute\"\nbody_a = \"{a}\"\npoint_a = \"O2\"\nbody_b = \"{b}\"\npoint_b = \"O2\"\n"
    );
    text += "[[joints]]\nname = \"A\"\ntype = \"revolute\"\nbody_a = \"crank\"\npoint_a = \"A\"\nbody_b = \"coupler\"\npoint_b = \"A\"\n";
    let (bearing, journal) = if v.bearing_on_coupler {
        ("coupler", "rocker")
    } else {
        ("rocker", "coupler")
    };
    text += &format!(
        "[[joints]]\nname = \"B\"\ntype = \"clearance\"\nbearing = \"{bearing}\"\nbearing_point = \"B\"\njournal = \"{journal}\"\njournal_point = \"B\"\nclearance = 0.5e-3\njournal_radius = 0.01\n{}[joints.friction]\n{}\n",
        v.contact, v.friction
    );
    text += "[[joints]]\nname = \"O4\"\ntype = \"revolute\"\nbody_a = \"ground\"\npoint_a = \"O4\"\nbody_b = \"rocker\"\npoint_b = \"O4\"\n";
    // The driver prescribes the crank's body angle φ; θ2 = 0 at t = 0 needs φ = ψ_crank.
    let (speed, angle) = if v.reversed_driver {
        (-250.0, -v.frames[0].0)
    } else {
        (250.0, v.frames[0].0)
    };
    text += &format!(
        "[[drivers]]\nname = \"motor\"\ntype = \"constant-speed\"\njoint = \"O2\"\nspeed_rpm = {speed}\ninitial_angle = {angle:.17e}\n"
    );
    text += v.extra;
    text
}

fn model(v: &Variant) -> Model {
    match load_str(&model_text(v), "test.toml", &[]) {
        Ok(m) => m,
        Err(e) => panic!("test model does not load: {e}\n{}", model_text(v)),
    }
}

fn reduced(v: &Variant) -> ReducedLagrangian {
    match ReducedLagrangian::new(&model(v)) {
        Ok(r) => r,
        Err(e) => panic!("reduced formulation refused the test model: {e}"),
    }
}

fn outputs(r: &ReducedLagrangian, t: f64, y: &[f64]) -> ReducedOutputs {
    match r.outputs(t, y) {
        Ok(o) => o,
        Err(e) => panic!("outputs at t = {t}, y = {y:?}: {e}"),
    }
}

use crate::formulation::test_rng::Lcg;

/// A random state at a random time: the loop closed at eccentricity |e| = c + `delta` in a
/// random direction, with random angular velocities (±40 rad/s, i.e. up to ~1.5× the
/// crank speed of 26 rad/s), and no stored impact velocity.
fn random_state(r: &ReducedLagrangian, rng: &mut Lcg, delta: f64) -> (f64, [f64; 5]) {
    let t = rng.range(0.0, 0.24);
    let angle = rng.range(0.0, std::f64::consts::TAU);
    let radius = r.joint.clearance + delta;
    let e0 = [radius * angle.cos(), radius * angle.sin()];
    let guess = [r.y0[0], r.y0[1]];
    // Walk the crank from θ2(0) to θ2(t) in small increments so Newton stays on the branch.
    let mut th = guess;
    for k in 1..=20 {
        let tk = t * f64::from(k) / 20.0;
        match r.assemble(tk, e0, [0.0, 0.0], th) {
            Ok(y) => th = [y[0], y[1]],
            Err(e) => panic!("cannot assemble at t = {tk}: {e}"),
        }
    }
    (
        t,
        [
            th[0],
            th[1],
            rng.range(-40.0, 40.0),
            rng.range(-40.0, 40.0),
            0.0,
        ],
    )
}

/// Masses and inertias by body order of the outputs (crank, coupler, rocker).
fn mass_props(r: &ReducedLagrangian) -> [(f64, f64); 3] {
    [
        (r.crank.mass, r.crank.inertia),
        (r.coupler.mass, r.coupler.inertia),
        (r.rocker.mass, r.rocker.inertia),
    ]
}

/// dE/dt of T + U (gravity) from the body states, and the sum of the magnitudes of its terms
/// (the scale for a relative tolerance).
fn energy_rate(r: &ReducedLagrangian, o: &ReducedOutputs) -> (f64, f64) {
    let g = r.gravity;
    let mut rate = 0.0;
    let mut scale = 0.0;
    for ((m, i), b) in mass_props(r)
        .into_iter()
        .zip([o.crank, o.coupler, o.rocker])
    {
        let terms = [
            m * (b.vx * b.ax + b.vy * b.ay),
            i * b.omega * b.alpha,
            -m * (g[0] * b.vx + g[1] * b.vy),
        ];
        rate += terms.iter().sum::<f64>();
        scale += terms.iter().map(|x| x.abs()).sum::<f64>();
    }
    (rate, scale)
}

/// parameters.md check values: open assembly at θ2 = 0 with the journal centred,
/// θ3 = 36.5795°, θ4 = 83.3294°, θ̇3 = θ̇4 = −11.899972 rad/s at 250 rpm. Tolerances: half a
/// unit of the last quoted digit.
#[test]
fn initial_state_matches_reference_values() {
    let r = reduced(&Variant::default());
    let y = r.initial_state();
    assert!(
        (y[0].to_degrees() - 36.5795).abs() < 5e-5,
        "θ3 = {}°",
        y[0].to_degrees()
    );
    assert!(
        (y[1].to_degrees() - 83.3294).abs() < 5e-5,
        "θ4 = {}°",
        y[1].to_degrees()
    );
    assert!((y[2] + 11.899972).abs() < 5e-7, "θ̇3 = {}", y[2]);
    assert!((y[3] + 11.899972).abs() < 5e-7, "θ̇4 = {}", y[3]);
    assert_eq!(y[4], 0.0, "no impact recorded at t = 0");
    let o = outputs(&r, 0.0, &y);
    // θ3 = coupler.phi and θ4 = rocker.phi for the reference frames; e = 0, so free.
    assert_eq!(o.coupler.phi, y[0]);
    assert_eq!(o.rocker.phi, y[1]);
    assert!(
        o.eccentricity[0].hypot(o.eccentricity[1]) < 1e-12,
        "e = {:?}",
        o.eccentricity
    );
    assert!((o.delta + 0.5e-3).abs() < 1e-12, "δ = {}", o.delta);
    assert_eq!(r.link_lengths(), [0.8, 0.25, 0.75, 0.45]);
    assert!(!r.contact_memory().in_contact);
}

/// A prescribed initial eccentricity is honoured: r_J − r_B = e0 at t = 0 and ė = 0.
#[test]
fn initial_eccentricity_is_assembled() {
    let text = model_text(&Variant::default()).replace(
        "journal_radius = 0.01\n",
        "journal_radius = 0.01\ninitial_eccentricity = [3e-4, -2e-4]\n",
    );
    let m = load_str(&text, "e0.toml", &[]).map_err(|e| e.to_string());
    let r = ReducedLagrangian::new(&m.unwrap_or_else(|e| panic!("{e}")))
        .unwrap_or_else(|e| panic!("{e}"));
    let o = outputs(&r, 0.0, &r.initial_state());
    assert!(
        (o.eccentricity[0] - 3e-4).abs() < 1e-12 && (o.eccentricity[1] + 2e-4).abs() < 1e-12,
        "e = {:?}",
        o.eccentricity
    );
    assert!(
        o.eccentricity_rate[0].hypot(o.eccentricity_rate[1]) < 1e-12,
        "ė = {:?}",
        o.eccentricity_rate
    );
}

/// (a) Free journal (δ < 0): the power balance dE/dt = M2 θ̇2 at random states, with E = T + U
/// from the body states. Tolerance 1e-9 of the sum of the magnitudes of the energy-rate terms
/// (rounding in sums of ~10 products).
#[test]
fn free_flight_energy_rate_equals_crank_power() {
    for variant in [
        Variant::default(),
        Variant {
            frames: [
                (0.3, [0.01, -0.02]),
                (-1.1, [0.05, 0.03]),
                (2.0, [-0.04, 0.01]),
            ],
            ..Variant::default()
        },
    ] {
        let r = reduced(&variant);
        let mut rng = Lcg(7);
        for _ in 0..20 {
            let delta = -rng.range(1e-5, 4.9e-4);
            let (t, y) = random_state(&r, &mut rng, delta);
            let o = outputs(&r, t, &y);
            assert!(
                o.delta < 0.0 && o.normal_force == 0.0,
                "free state: δ = {}",
                o.delta
            );
            let (rate, scale) = energy_rate(&r, &o);
            let power = o.crank_torque * o.theta2_dot;
            assert!(
                (rate - power).abs() <= 1e-9 * scale,
                "t = {t}, y = {y:?}: dE/dt = {rate}, M2 ω = {power} (scale {scale})"
            );
        }
    }
}

/// (b) In contact: dE/dt = M2 θ̇2 + power of the contact forces (−F_N δ̇ + F_T v_t), at random
/// contact states, with and without friction, for the bearing on either body, with shifted
/// centres of mass. Same tolerance as (a), the contact power added to the scale.
#[test]
fn contact_energy_rate_equals_crank_and_contact_power() {
    let shifted = [
        (0.3, [0.01, -0.02]),
        (-1.1, [0.05, 0.03]),
        (2.0, [-0.04, 0.01]),
    ];
    let variants = [
        Variant::default(),
        Variant {
            friction: "law = \"none\"",
            ..Variant::default()
        },
        Variant {
            bearing_on_coupler: false,
            frames: shifted,
            ..Variant::default()
        },
    ];
    for variant in variants {
        let r = reduced(&variant);
        let mut rng = Lcg(11);
        let mut contacts = 0;
        for k in 0..30 {
            let delta = rng.range(1e-7, 2e-5);
            let (t, mut y) = random_state(&r, &mut rng, delta);
            // Alternate: a recorded impact, and a stage past an unlocated impact.
            if k % 2 == 0 {
                y[4] = rng.range(0.01, 1.0);
            }
            let o = outputs(&r, t, &y);
            assert!(o.delta > 0.0, "contact state: δ = {}", o.delta);
            if o.normal_force > 0.0 {
                contacts += 1;
            }
            let (rate, scale) = energy_rate(&r, &o);
            let power = o.crank_torque * o.theta2_dot + o.contact_power;
            let scale = scale + o.contact_power.abs() + (o.crank_torque * o.theta2_dot).abs();
            assert!(
                (rate - power).abs() <= 1e-9 * scale,
                "t = {t}, y = {y:?}: dE/dt = {rate}, M2 ω + P_c = {power} (F_N {}, scale {scale})",
                o.normal_force
            );
        }
        assert!(contacts > 10, "enough states with a force: {contacts}");
    }
}

/// Loads: constant torques and point forces add their power: dE/dt = M2 θ̇2 + Σ τ ω + Σ F·v_P.
#[test]
fn loads_add_their_power() {
    let extra = "[[forces]]\nname = \"t3\"\ntype = \"torque\"\nbody = \"coupler\"\ntorque = 1.5\n\
                 [[forces]]\nname = \"t2\"\ntype = \"torque\"\nbody = \"crank\"\ntorque = -0.7\n\
                 [[forces]]\nname = \"p4\"\ntype = \"force\"\nbody = \"rocker\"\npoint = \"B\"\nforce = [3.0, -4.0]\n\
                 [[forces]]\nname = \"p3\"\ntype = \"force\"\nbody = \"coupler\"\npoint = \"A\"\nforce = [-2.0, 1.0]\n\
                 [[forces]]\nname = \"p2\"\ntype = \"force\"\nbody = \"crank\"\npoint = \"A\"\nforce = [0.5, 6.0]\n";
    let variant = Variant {
        frames: [
            (0.3, [0.01, -0.02]),
            (-1.1, [0.05, 0.03]),
            (2.0, [-0.04, 0.01]),
        ],
        extra,
        ..Variant::default()
    };
    let r = reduced(&variant);
    let m = r.model().clone();
    let mut rng = Lcg(3);
    for _ in 0..10 {
        let (t, y) = random_state(&r, &mut rng, -2e-4);
        let o = outputs(&r, t, &y);
        let (rate, scale) = energy_rate(&r, &o);
        let state_of = |name: &str| match name {
            "crank" => o.crank,
            "coupler" => o.coupler,
            _ => o.rocker,
        };
        let mut load_power = 0.0;
        for f in &m.forces {
            match f {
                ForceElement::Torque { body, torque, .. } => {
                    load_power += torque * state_of(&m.body(*body).name).omega
                }
                ForceElement::PointForce { at, force, .. } => {
                    let Frame::Body(id) = at.frame else { continue };
                    let b = state_of(&m.body(id).name);
                    let arm = rot(b.phi, at.local);
                    let v = [b.vx - b.omega * arm[1], b.vy + b.omega * arm[0]];
                    load_power += dot(*force, v);
                }
                _ => {}
            }
        }
        let power = o.crank_torque * o.theta2_dot + load_power;
        assert!(
            (rate - power).abs() <= 1e-9 * (scale + load_power.abs()),
            "t = {t}: dE/dt = {rate}, M2 ω + loads = {power}"
        );
    }
}

/// (c) The printed equations 23–25, implemented as printed with the corrections (ψ = α + φ
/// with tan φ = −c_f c_d sign(X), X = ω_B R_B − ω_J R_J − r α̇ from the corrected eq. 6;
/// α from eq. 15 read as atan2; r, ṙ, α̇ from eqs. 14–16) give the same θ̈3, θ̈4 and M2 as the
/// vector form at random contact states of the reference geometry. Tolerance 1e-9 of the
/// largest term of each equation: the two forms compute δ = |e| − c from coordinates of
/// ~0.5 m rounded differently (~1e-16 m); with δ ≥ 1e-6 m that is ≤ 3e-10 relative in F_N.
/// In the c_d ramp the slip-velocity rounding is added (see the comment in the loop).
#[test]
fn printed_equations_agree_with_derivation() {
    let (l1, l2, l3, l4) = (0.8, 0.25, 0.75, 0.45);
    let (m2, m3, m4) = (0.494, 1.003, 0.74);
    let (i3, i4) = (0.0545, 0.0189);
    let g = 9.81;
    let (c, rj) = (0.5e-3, 0.01);
    let rb = rj + c;
    let (cf, v0, v1) = (0.1, 1e-4, 1e-3);
    let r = reduced(&Variant::default());
    let linkdyn_law = r.joint.law.elastic;
    let crate::contact::laws::Elastic::Power { stiffness: k, .. } = linkdyn_law else {
        panic!("the reference joint has a power law");
    };
    let chi = 0.75 * (1.0 - 0.81);
    let mut rng = Lcg(5);
    let mut regions = [0usize; 3];
    for n in 0..40 {
        let delta = rng.range(1e-6, 2e-5);
        let (t, mut y) = random_state(&r, &mut rng, delta);
        // Every fourth state: slip velocity near zero, to reach the c_d ramp and the dead
        // zone. v_t is affine in θ̇4: solve for the θ̇4 that gives the target.
        if n % 4 == 0 {
            let target = rng.range(-2e-3, 2e-3);
            let v_a = outputs(&r, t, &y).tangential_velocity;
            let mut y1 = y;
            y1[3] += 1.0;
            let slope = outputs(&r, t, &y1).tangential_velocity - v_a;
            y[3] += (target - v_a) / slope;
        }
        let impact = rng.range(0.05, 1.0);
        y[4] = impact;
        let o = outputs(&r, t, &y);
        let (t2, t3, t4) = (o.theta2, y[0], y[1]);
        let (w, w3, w4) = (o.theta2_dot, y[2], y[3]);
        // Eqs. 14–16.
        let x = l1 - l2 * t2.cos() - l3 * t3.cos() + l4 * t4.cos();
        let yy = l4 * t4.sin() - l2 * t2.sin() - l3 * t3.sin();
        let rr = x.hypot(yy);
        let alpha = yy.atan2(x);
        let xd = l2 * w * t2.sin() + l3 * w3 * t3.sin() - l4 * w4 * t4.sin();
        let yd = l4 * w4 * t4.cos() - l2 * w * t2.cos() - l3 * w3 * t3.cos();
        let rdot = alpha.cos() * xd + alpha.sin() * yd;
        let alpha_dot = (-alpha.sin() * xd + alpha.cos() * yd) / rr;
        // Eq. 7 (clamped) and eqs. 10–13.
        let delta = rr - c;
        let f_n = (k * delta.powf(1.5) * (1.0 + chi * rdot / impact)).max(0.0);
        let slip = w3 * rb - w4 * rj - rr * alpha_dot;
        let cd = if slip.abs() < v0 {
            0.0
        } else if slip.abs() > v1 {
            1.0
        } else {
            (slip.abs() - v0) / (v1 - v0)
        };
        regions[if cd == 0.0 {
            0
        } else if cd == 1.0 {
            2
        } else {
            1
        }] += 1;
        let phi = (-cf * cd * slip.signum()).atan();
        let qc = f_n * (1.0 + cf * cf * cd * cd).sqrt();
        let psi = alpha + phi;
        // Eqs. 24, 25, 23.
        let terms3 = [
            l3 * qc * (psi - t3).sin(),
            rb * qc * (psi - alpha).sin(),
            0.5 * m3 * l2 * l3 * w * w * (t2 - t3).sin(),
            -0.5 * m3 * g * l3 * t3.cos(),
        ];
        let th3dd = terms3.iter().sum::<f64>() / (i3 + 0.25 * m3 * l3 * l3);
        let terms4 = [
            l4 * qc * (t4 - psi).sin(),
            rj * qc * (alpha - psi).sin(),
            -0.5 * m4 * g * l4 * t4.cos(),
        ];
        let th4dd = terms4.iter().sum::<f64>() / (i4 + 0.25 * m4 * l4 * l4);
        let terms2 = [
            0.5 * m3 * l2 * l3 * th3dd * (t2 - t3).cos(),
            0.5 * m3 * l2 * l3 * w3 * w3 * (t2 - t3).sin(),
            0.5 * m2 * g * l2 * t2.cos(),
            m3 * g * l2 * t2.cos(),
            l2 * qc * (t2 - psi).sin(),
        ];
        let m2_printed: f64 = terms2.iter().sum();
        let scale = |terms: &[f64]| terms.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        // In the c_d ramp F_T depends on v_t with slope c_f F_N/(v1 − v0), and v_t carries a
        // rounding error |ė| · ~1e-15 m / |e|: the direction n of e, a difference of
        // coordinates of ~0.5 m, is known to ~1e-16 m/|e|, and v_t contains ė·t.
        let e_rate = o.eccentricity_rate[0].hypot(o.eccentricity_rate[1]);
        let slip_error = if cd > 0.0 && cd < 1.0 {
            cf * f_n * e_rate * 1e-15 / (rr * (v1 - v0))
        } else {
            0.0
        };
        let (p3, p4) = (i3 + 0.25 * m3 * l3 * l3, i4 + 0.25 * m4 * l4 * l4);
        let tol3 = 1e-9 * scale(&terms3) / p3 + (l3 + rb) * slip_error / p3;
        let tol4 = 1e-9 * scale(&terms4) / p4 + (l4 + rj) * slip_error / p4;
        let tol2 = 1e-9 * scale(&terms2) + l2 * slip_error + 0.5 * m3 * l2 * l3 * tol3;
        assert!(
            (o.normal_force - f_n).abs() <= 1e-9 * f_n.max(1.0),
            "F_N {} vs {f_n}",
            o.normal_force
        );
        assert!(
            (o.theta3_ddot - th3dd).abs() <= tol3,
            "state {n}: θ̈3 = {}, printed {th3dd}",
            o.theta3_ddot
        );
        assert!(
            (o.theta4_ddot - th4dd).abs() <= tol4,
            "state {n}: θ̈4 = {}, printed {th4dd}",
            o.theta4_ddot
        );
        assert!(
            (o.crank_torque - m2_printed).abs() <= tol2,
            "state {n}: M2 = {}, printed {m2_printed}",
            o.crank_torque
        );
    }
    assert!(
        regions.iter().all(|&n| n > 0),
        "all three c_d regions visited: {regions:?}"
    );
}

/// Body states are consistent with the model's body-frame points: the ideal joints hold
/// (positions and velocities), and journal − bearing point = e. Rotated frames and shifted
/// centres of mass; bearing on either body. Tolerances: 1e-12 m, 1e-10 m/s (rounding).
#[test]
fn body_states_respect_the_joints() {
    let frames = [
        (0.3, [0.01, -0.02]),
        (-1.1, [0.05, 0.03]),
        (2.0, [-0.04, 0.01]),
    ];
    for bearing_on_coupler in [true, false] {
        let r = reduced(&Variant {
            frames,
            bearing_on_coupler,
            ..Variant::default()
        });
        let m = r.model().clone();
        let mut rng = Lcg(17);
        for _ in 0..10 {
            let delta = rng.range(-4e-4, 1e-5);
            let (t, y) = random_state(&r, &mut rng, delta);
            let o = outputs(&r, t, &y);
            let point = |body: &str, p: &str| {
                let b = match body {
                    "crank" => o.crank,
                    "coupler" => o.coupler,
                    _ => o.rocker,
                };
                let id = m.body_id(body).unwrap_or_else(|| panic!("{body}"));
                let s = m
                    .body(id)
                    .points
                    .iter()
                    .find(|(n, _)| n == p)
                    .map(|(_, s)| *s)
                    .unwrap_or_else(|| panic!("{p}"));
                let arm = rot(b.phi, s);
                (
                    [b.x + arm[0], b.y + arm[1]],
                    [b.vx - b.omega * arm[1], b.vy + b.omega * arm[0]],
                )
            };
            let close = |a: [f64; 2], b: [f64; 2], tol: f64, what: &str| {
                assert!(
                    (a[0] - b[0]).abs() < tol && (a[1] - b[1]).abs() < tol,
                    "{what}: {a:?} vs {b:?}"
                );
            };
            close(point("crank", "O2").0, [0.0, 0.0], 1e-12, "O2");
            close(point("crank", "O2").1, [0.0, 0.0], 1e-10, "O2 velocity");
            close(point("rocker", "O4").0, [0.8, 0.0], 1e-12, "O4");
            close(point("rocker", "O4").1, [0.0, 0.0], 1e-10, "O4 velocity");
            close(point("crank", "A").0, point("coupler", "A").0, 1e-12, "A");
            close(
                point("crank", "A").1,
                point("coupler", "A").1,
                1e-10,
                "A velocity",
            );
            let (journal, bearing) = if bearing_on_coupler {
                ("rocker", "coupler")
            } else {
                ("coupler", "rocker")
            };
            let (pj, vj) = point(journal, "B");
            let (pb, vb) = point(bearing, "B");
            close([pj[0] - pb[0], pj[1] - pb[1]], o.eccentricity, 1e-12, "e");
            close(
                [vj[0] - vb[0], vj[1] - vb[1]],
                o.eccentricity_rate,
                1e-10,
                "ė",
            );
        }
    }
}

/// Body accelerations against central differences of the body velocities along the flow
/// y ± h f(y) (d/dt v = ∂v/∂t + ∂v/∂y · f). Tolerance 1e-6 relative + 1e-6 absolute: O(h²)
/// with h = 1e-6 s and rounding ~1e-16/1e-6.
#[test]
fn body_accelerations_match_finite_differences() {
    let r = reduced(&Variant {
        frames: [
            (0.3, [0.01, -0.02]),
            (-1.1, [0.05, 0.03]),
            (2.0, [-0.04, 0.01]),
        ],
        ..Variant::default()
    });
    let mut rng = Lcg(23);
    let h = 1e-6;
    for _ in 0..10 {
        let (t, y) = random_state(&r, &mut rng, -1e-4);
        let o = outputs(&r, t, &y);
        let f = [
            o.theta3_dot,
            o.theta4_dot,
            o.theta3_ddot,
            o.theta4_ddot,
            0.0,
        ];
        let yp: Vec<f64> = y.iter().zip(f).map(|(a, b)| a + h * b).collect();
        let ym: Vec<f64> = y.iter().zip(f).map(|(a, b)| a - h * b).collect();
        let (op, om) = (outputs(&r, t + h, &yp), outputs(&r, t - h, &ym));
        for (name, b, bp, bm) in [
            ("crank", o.crank, op.crank, om.crank),
            ("coupler", o.coupler, op.coupler, om.coupler),
            ("rocker", o.rocker, op.rocker, om.rocker),
        ] {
            for (a, fd) in [
                (b.ax, (bp.vx - bm.vx) / (2.0 * h)),
                (b.ay, (bp.vy - bm.vy) / (2.0 * h)),
                (b.alpha, (bp.omega - bm.omega) / (2.0 * h)),
                (b.vx, (bp.x - bm.x) / (2.0 * h)),
                (b.vy, (bp.y - bm.y) / (2.0 * h)),
                (b.omega, (bp.phi - bm.phi) / (2.0 * h)),
            ] {
                assert!(
                    (a - fd).abs() < 1e-6 * a.abs() + 1e-6,
                    "{name}: {a} vs finite difference {fd}"
                );
            }
        }
        let ed = o.eccentricity_acceleration;
        let fd = [
            (op.eccentricity_rate[0] - om.eccentricity_rate[0]) / (2.0 * h),
            (op.eccentricity_rate[1] - om.eccentricity_rate[1]) / (2.0 * h),
        ];
        assert!(
            (ed[0] - fd[0]).abs() < 1e-6 * ed[0].abs() + 1e-6
                && (ed[1] - fd[1]).abs() < 1e-6 * ed[1].abs() + 1e-6,
            "ë {ed:?} vs {fd:?}"
        );
    }
}

/// Body frames are a matter of description: rotating every body frame (centres of mass kept)
/// changes φ by the rotation but nothing in θ̈3, θ̈4, M2, F_N. Reversing the driver joint
/// (ground as its second body, negative speed) changes nothing either. Without friction, the
/// side that carries the bearing does not matter (the normal force passes through both
/// centres). Tolerance 1e-9 relative: the rotated point coordinates round differently, which
/// moves the centres by ~1e-16 m; δ = |e| − c cancels down to 1e-6 m in these states, so F_N
/// (∝ δ^1.5) carries up to ~1.5 · 2e-16/1e-6 = 3e-10 relative rounding.
#[test]
fn invariant_to_frames_driver_orientation_and_frictionless_bearing_side() {
    let base = Variant {
        friction: "law = \"none\"",
        ..Variant::default()
    };
    let r0 = reduced(&base);
    let others = [
        Variant {
            frames: [(0.7, [0.0, 0.0]), (-2.5, [0.0, 0.0]), (1.2, [0.0, 0.0])],
            ..base.clone()
        },
        Variant {
            reversed_driver: true,
            ..base.clone()
        },
        Variant {
            bearing_on_coupler: false,
            ..base.clone()
        },
    ];
    let mut rng = Lcg(29);
    let states: Vec<(f64, [f64; 5])> = (0..10)
        .map(|k| {
            let delta = if k % 2 == 0 {
                rng.range(1e-6, 1e-5)
            } else {
                -1e-4
            };
            let (t, mut y) = random_state(&r0, &mut rng, delta);
            y[4] = rng.range(0.05, 1.0);
            (t, y)
        })
        .collect();
    for variant in others {
        let r = reduced(&variant);
        for (t, y) in &states {
            let (a, b) = (outputs(&r0, *t, y), outputs(&r, *t, y));
            for (x, z, what) in [
                (a.theta3_ddot, b.theta3_ddot, "θ̈3"),
                (a.theta4_ddot, b.theta4_ddot, "θ̈4"),
                (a.crank_torque, b.crank_torque, "M2"),
                (a.normal_force, b.normal_force, "F_N"),
                (a.delta, b.delta, "δ"),
            ] {
                assert!(
                    (x - z).abs() <= 1e-9 * x.abs().max(1.0),
                    "{what}: {x} vs {z}, variant: bearing on coupler {}, reversed driver {}, frames {:?}",
                    variant.bearing_on_coupler,
                    variant.reversed_driver,
                    variant.frames
                );
            }
        }
    }
}

/// The analytic Jacobian against central differences of the whole right-hand side, free and
/// in contact, with and without a stored impact velocity, on the paper's four-bar, with the
/// bearing on the rocker, and with shifted centres of mass and point loads.
#[test]
fn analytic_jacobian_matches_central_differences() {
    let extra = "[[forces]]\nname = \"p4\"\ntype = \"force\"\nbody = \"rocker\"\npoint = \"B\"\nforce = [3.0, -4.0]\n\
                 [[forces]]\nname = \"p3\"\ntype = \"force\"\nbody = \"coupler\"\npoint = \"A\"\nforce = [-2.0, 1.0]\n";
    let variants = [
        Variant::default(),
        Variant {
            bearing_on_coupler: false,
            ..Variant::default()
        },
        Variant {
            frames: [
                (0.3, [0.01, -0.02]),
                (-1.1, [0.05, 0.03]),
                (2.0, [-0.04, 0.01]),
            ],
            extra,
            ..Variant::default()
        },
        // The line-contact laws: closed-form slopes of F_N (Johnson's by the implicit function
        // theorem) instead of central differences of the law.
        Variant {
            contact: "length = 0.02\n[joints.contact]\nlaw = \"johnson\"\ndamping = \"hunt-crossley\"\n",
            ..Variant::default()
        },
        Variant {
            contact: "length = 0.02\n[joints.contact]\nlaw = \"liu\"\ndamping = \"flores\"\n",
            ..Variant::default()
        },
    ];
    let mut rng = Lcg(41);
    for (v, variant) in variants.iter().enumerate() {
        let r = reduced(variant);
        for (delta, stored) in [(-2e-4, 0.0), (1e-5, 0.0), (1e-5, 0.3), (3e-5, 0.05)] {
            let (t, mut y) = random_state(&r, &mut rng, delta);
            y[4] = stored;
            let mut exact = [0.0; 25];
            let calls = r.jacobian(t, &y, &[0.0; 5], &mut exact, &mut [0.0; 10]);
            assert_eq!(calls.ok(), Some(0), "variant {v}: analytic, no RHS call");
            // Central differences with h_j = 1e-7·max(|y_j|, 1): the truncation error is
            // (h/δ)²·O(1) of an entry; in contact an angle step of 1e-7 rad moves e by
            // ≤ 1e-7 × L (0.5 m) = 5e-8 m against δ ≥ 1e-5 m, i.e. ≤ 2.5e-5 for the δ^1.5
            // law, and rounding u·|f|/h ≈ 1e-16·1e5/1e-7 = 1e-4 rad/s² against entries of
            // 1e2 (free) to 1e9 (contact). Hence 1e-3 of the row's largest entry (a margin
            // of 40 on the truncation) plus 1e-2 absolute (20× the rounding).
            let mut row_scale = [0.0_f64; 5];
            let mut numeric = [0.0; 25];
            for j in 0..5 {
                let h = 1e-7 * y[j].abs().max(1.0);
                let (mut up, mut down) = (y, y);
                up[j] += h;
                down[j] -= h;
                let (mut fu, mut fd) = ([0.0; 5], [0.0; 5]);
                let ok = r.rhs(t, &up, &mut fu).and(r.rhs(t, &down, &mut fd));
                assert!(ok.is_ok(), "variant {v}: rhs {ok:?}");
                for i in 0..5 {
                    numeric[i * 5 + j] = (fu[i] - fd[i]) / (2.0 * h);
                    row_scale[i] = row_scale[i].max(numeric[i * 5 + j].abs());
                }
            }
            for k in 0..25 {
                // At δ̇⁽⁻⁾ = 0 (none stored) the law switches to the current δ̇ and any
                // perturbation stores one: no derivative to compare in that column.
                if stored == 0.0 && k % 5 == 4 {
                    continue;
                }
                let (a, b) = (exact[k], numeric[k]);
                let bound = 1e-3 * row_scale[k / 5] + 1e-2;
                assert!(
                    (a - b).abs() <= bound,
                    "variant {v}, δ = {delta:e}, stored {stored}: J[{}][{}] analytic {a:e} vs central difference {b:e} (bound {bound:e})",
                    k / 5,
                    k % 5
                );
            }
        }
    }
}

/// With Ambrósio friction, events 1–4 are v_t ∓ v0, v_t ∓ v1 while a contact with a stored
/// δ̇⁽⁻⁾ is open and constant (no crossing) otherwise; they change nothing in the state.
/// Without friction, or switched off, δ is the only event function.
#[test]
fn friction_kinks_are_events_in_contact() {
    let r = reduced(&Variant::default());
    assert_eq!(r.n_events(), 5);
    assert_eq!(r.clone().friction_kink_events(false).n_events(), 1);
    let frictionless = Variant {
        friction: "law = \"none\"",
        ..Variant::default()
    };
    assert_eq!(reduced(&frictionless).n_events(), 1);
    let mut rng = Lcg(17);
    let (t, mut y) = random_state(&r, &mut rng, 1e-6);
    let v_t = outputs(&r, t, &y).tangential_velocity;
    let mut g = [0.0; 5];
    r.events(t, &y, &mut g);
    assert_eq!(g[1..], [1.0; 4], "no stored δ̇⁽⁻⁾: kinks inactive");
    y[4] = 0.05;
    r.events(t, &y, &mut g);
    assert!(g[0] > 0.0, "in contact: δ = {}", g[0]);
    assert_eq!(g[1..], [v_t - 1e-4, v_t + 1e-4, v_t - 1e-3, v_t + 1e-3]);
    let mut m = r.clone();
    for index in 1..5 {
        let mut yy = y;
        for crossing in [Crossing::Rising, Crossing::Falling] {
            assert_eq!(
                m.apply_event(t, &mut yy, index, crossing),
                EventResponse::Continue
            );
            assert_eq!(yy, y, "event {index} changes nothing");
        }
    }
    assert!(m.contact_memory().impacts.is_empty());
}

/// Events: g = δ; a Rising crossing stores δ̇⁽⁻⁾ = max(δ̇, 0) in y and restarts; a Falling one
/// clears it. The grazing guard limits the step while free and not in contact.
#[test]
fn events_and_grazing_guard() {
    let mut r = reduced(&Variant::default());
    let mut rng = Lcg(31);
    let (t, y) = random_state(&r, &mut rng, 0.0);
    let mut g = [1.0];
    r.events(t, &y, &mut g);
    assert!(g[0].abs() < 1e-12, "δ at the assembled contact: {}", g[0]);
    let mut yy = y;
    let o = outputs(&r, t, &y);
    assert_eq!(
        r.apply_event(t, &mut yy, 0, Crossing::Rising),
        EventResponse::Restart
    );
    assert_eq!(yy[4], o.delta_dot.max(0.0), "stored δ̇⁽⁻⁾");
    assert_eq!(yy[..4], y[..4], "only δ̇⁽⁻⁾ changes");
    assert_eq!(outputs(&r, t, &yy).impact_velocity, yy[4]);
    assert_eq!(r.contact_memory().impact_velocity, yy[4]);
    assert_eq!(r.contact_memory().impacts, vec![t]);
    assert!(r.contact_memory().in_contact);
    assert_eq!(
        r.apply_event(t, &mut yy, 0, Crossing::Falling),
        EventResponse::Restart
    );
    assert_eq!(yy[4], 0.0, "cleared at separation");
    assert!(!r.contact_memory().in_contact);
    assert_eq!(
        r.apply_event(t, &mut yy, 3, Crossing::Falling),
        EventResponse::Continue
    );
    r.reset_contact_memory();
    assert!(r.contact_memory().impacts.is_empty());

    let (t, y) = random_state(&r, &mut rng, -1e-4);
    let h = r.max_step(t, &y);
    let o = outputs(&r, t, &y);
    let v = o.eccentricity_rate[0].hypot(o.eccentricity_rate[1]);
    assert!(h.is_finite() && h > 0.0, "free: h = {h}");
    assert!(
        v * h <= 0.5e-4 * (1.0 + 1e-12) || h <= 2.0 * 1e-3 * 0.5e-3 / v,
        "h = {h}, |ė| = {v}"
    );
    let (t, y) = random_state(&r, &mut rng, 1e-6);
    assert_eq!(r.max_step(t, &y), f64::INFINITY, "in contact");
}

/// rhs writes [θ̇3, θ̇4, θ̈3, θ̈4, 0]; a non-finite state is an error, not a panic.
#[test]
fn rhs_layout_and_bad_state() {
    let r = reduced(&Variant::default());
    let y = r.initial_state();
    let mut dy = [1.0; 5];
    r.rhs(0.0, &y, &mut dy).unwrap_or_else(|e| panic!("{e}"));
    let o = outputs(&r, 0.0, &y);
    assert_eq!(
        dy,
        [
            o.theta3_dot,
            o.theta4_dot,
            o.theta3_ddot,
            o.theta4_ddot,
            0.0
        ]
    );
    let names = r.output_names();
    let mut out = Vec::new();
    r.outputs_into(0.0, &y, &mut out)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(names.len(), out.len());
    assert_eq!(
        names[9..12],
        [
            "coupler.x".to_string(),
            "coupler.y".into(),
            "coupler.phi".into()
        ]
    );
    assert_eq!(
        names[27..],
        [
            "motor.torque".to_string(),
            "B.ex".into(),
            "B.ey".into(),
            "B.delta".into(),
            "B.fn".into(),
            "B.ft".into()
        ]
    );
    let nan = [f64::NAN, 0.0, 0.0, 0.0, 0.0];
    let err = r.rhs(0.0, &nan, &mut dy).map_err(|e| e.to_string());
    assert_eq!(
        err,
        Err("non-finite acceleration of body \"coupler\" at t = 0.000000000 s".to_string())
    );
}

fn error_text(text: &str) -> String {
    let m =
        load_str(text, "bad.toml", &[]).unwrap_or_else(|e| panic!("test model does not load: {e}"));
    match ReducedLagrangian::new(&m) {
        Ok(_) => panic!("accepted an unsupported model"),
        Err(e) => e.to_string(),
    }
}

/// (d) Unsupported models are refused with a message naming what is missing or different.
#[test]
fn unsupported_models_are_refused_with_reasons() {
    let good = model_text(&Variant::default());
    let ideal = good.replace(
        "type = \"clearance\"\nbearing = \"coupler\"\nbearing_point = \"B\"\njournal = \"rocker\"\njournal_point = \"B\"\nclearance = 0.5e-3\njournal_radius = 0.01\n[joints.friction]\nlaw = \"ambrosio\"\ncoefficient = 0.1\nv0 = 1e-4\nv1 = 1e-3\n",
        "type = \"revolute\"\nbody_a = \"coupler\"\npoint_a = \"B\"\nbody_b = \"rocker\"\npoint_b = \"B\"\n",
    );
    assert_ne!(ideal, good, "replacement applied");
    assert_eq!(
        error_text(&ideal),
        "reduced formulation: needs exactly one clearance joint, between the coupler and the rocker; the model has 0"
    );
    let pendulum = "[model]\nname = \"p\"\n[ground]\npoints = { O = [0.0, 0.0] }\n[[bodies]]\nname = \"rod\"\nmass = 1.0\ninertia = 0.1\npoints = { O = [-0.5, 0.0] }\ninitial = { x = 0.5, y = 0.0, phi = 0.0 }\n[[joints]]\nname = \"O\"\ntype = \"revolute\"\nbody_a = \"ground\"\npoint_a = \"O\"\nbody_b = \"rod\"\npoint_b = \"O\"\n";
    assert_eq!(
        error_text(pendulum),
        "reduced formulation: needs exactly 3 moving bodies (crank, coupler, rocker); the model has 1"
    );
    let no_driver = good
        .split("[[drivers]]")
        .next()
        .unwrap_or_default()
        .to_string();
    assert_eq!(
        error_text(&no_driver),
        "reduced formulation: needs exactly one driver, on the revolute joint between ground and the crank; the model has 0"
    );
    let driver_on_a = good.replace("joint = \"O2\"", "joint = \"A\"");
    assert_eq!(
        error_text(&driver_on_a),
        "reduced formulation: driver \"motor\" drives joint \"A\" between \"crank\" and \"coupler\"; it must drive the joint between ground and the crank"
    );
    // Clearance at A (crank–coupler) and an ideal B.
    let clearance_at_a = ideal
        .replace(
            "name = \"A\"\ntype = \"revolute\"\nbody_a = \"crank\"\npoint_a = \"A\"\nbody_b = \"coupler\"\npoint_b = \"A\"\n",
            "name = \"A\"\ntype = \"clearance\"\nbearing = \"crank\"\nbearing_point = \"A\"\njournal = \"coupler\"\njournal_point = \"A\"\nclearance = 0.5e-3\njournal_radius = 0.01\n",
        );
    assert_eq!(
        error_text(&clearance_at_a),
        "reduced formulation: needs an ideal revolute joint between the crank \"crank\" and the coupler; found none (the clearance joint must be the coupler–rocker joint)"
    );
    // Clearance at O4 (rocker–ground) and an ideal B.
    let clearance_at_o4 = ideal.replace(
        "name = \"O4\"\ntype = \"revolute\"\nbody_a = \"ground\"\npoint_a = \"O4\"\nbody_b = \"rocker\"\npoint_b = \"O4\"\n",
        "name = \"O4\"\ntype = \"clearance\"\nbearing = \"ground\"\nbearing_point = \"O4\"\njournal = \"rocker\"\njournal_point = \"O4\"\nclearance = 0.5e-3\njournal_radius = 0.01\n",
    );
    assert_eq!(
        error_text(&clearance_at_o4),
        "reduced formulation: clearance joint \"O4\" connects \"ground\" and \"rocker\"; it must connect the coupler \"coupler\" and the rocker \"rocker\""
    );
    let extra_joint = format!(
        "{good}[[joints]]\nname = \"extra\"\ntype = \"revolute\"\nbody_a = \"ground\"\npoint_a = \"O2\"\nbody_b = \"coupler\"\npoint_b = \"A\"\n"
    );
    assert_eq!(
        error_text(&extra_joint),
        "reduced formulation: joint \"extra\" (revolute between \"ground\" and \"coupler\") is not part of the four-bar ground–crank–coupler–rocker–ground; no other joints are allowed"
    );
    let no_o4 = good.replace(
        "[[joints]]\nname = \"O4\"\ntype = \"revolute\"\nbody_a = \"ground\"\npoint_a = \"O4\"\nbody_b = \"rocker\"\npoint_b = \"O4\"\n",
        "",
    );
    assert_eq!(
        error_text(&no_o4),
        "reduced formulation: needs an ideal revolute joint between the rocker \"rocker\" and ground; found none"
    );
    let spring = format!(
        "{good}[[forces]]\nname = \"s\"\ntype = \"spring-damper\"\nbody_a = \"ground\"\npoint_a = \"O4\"\nbody_b = \"coupler\"\npoint_b = \"A\"\nstiffness = 10.0\nfree_length = 0.5\n"
    );
    assert_eq!(
        error_text(&spring),
        "reduced formulation: force \"s\" is a spring-damper; only gravity, constant torques and constant point forces are supported"
    );
    let degenerate: String = good
        .lines()
        .map(|l| {
            if l.starts_with("points = { O4 =") {
                "points = { O4 = [0.0, 0.0], B = [0.0, 0.0] }"
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    assert_eq!(
        error_text(&degenerate),
        "reduced formulation: body \"rocker\": its joint points \"O4\" and \"B\" coincide, so its link angle is undefined"
    );
    // Link lengths that cannot close the loop: the assembly error names the clearance joint
    // (matched on the variant; its wording belongs to `FormulationError`).
    let unclosable = good.replace("O4 = [0.8, 0.0]", "O4 = [3.0, 0.0]");
    let m = load_str(&unclosable, "bad.toml", &[]).unwrap_or_else(|e| panic!("{e}"));
    match ReducedLagrangian::new(&m) {
        Err(FormulationError::Unassemblable {
            joint, residual, ..
        }) => {
            assert_eq!(joint, "B");
            assert!(
                residual > 1.0,
                "O4 moved 2.2 m out of reach: residual {residual}"
            );
        }
        Err(e) => panic!("expected Unassemblable, got {e}"),
        Ok(_) => panic!("assembled an unclosable loop"),
    }
}
