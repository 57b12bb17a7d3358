//! The DAE's analytic Jacobian against central differences of the whole right-hand side, out of
//! contact and in contact (sliding, in the friction ramp, stuck), with and without a stored
//! impact velocity, on the clearance four-bar (revolute joints, a driver) and on the gas-loaded
//! slider-crank (a prismatic joint, expression forces, a clearance joint).

use super::super::{Dae, DaeOptions};
use crate::formulation::{Formulation, FormulationError};
use crate::mechanics::planar::{dot, perp};
use crate::model::Frame;

fn dae(path: &str, energy: bool) -> Dae {
    dae_with(path, &[], energy)
}

/// The DAE of the model at `path` with the `--set` overrides `sets`.
fn dae_with(path: &str, sets: &[&str], energy: bool) -> Dae {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let model = match crate::model::load(path.as_ref(), &sets) {
        Ok(m) => m,
        Err(e) => panic!("{path}: {e}"),
    };
    match Dae::new(
        &model,
        &DaeOptions {
            baumgarte: None,
            energy,
        },
    ) {
        Ok(d) => d,
        Err(e) => panic!("{path}: {e}"),
    }
}

/// A contact state of joint 0: the journal's body moved so that δ = `delta` along the unit
/// direction at angle `angle`, its velocity changed so that δ̇ = `delta_dot` and the slip
/// velocity is `slip`, and `stored` as the stored impact velocity.
fn contact_state(
    d: &Dae,
    delta: f64,
    angle: f64,
    delta_dot: f64,
    slip: f64,
    stored: f64,
) -> Vec<f64> {
    let mut y = d.initial_state();
    let n = d.n_coordinates();
    let site = &d.contacts().sites()[0];
    let Frame::Body(id) = site.journal.frame else {
        panic!("journal on the ground")
    };
    let b = 3 * id.0;
    let s = d.contact_state(0, &y);
    let c = site.contact.clearance;
    let dir = [angle.cos(), angle.sin()];
    for i in 0..2 {
        y[b + i] += (c + delta) * dir[i] - s.kinematics.e[i];
    }
    let s = d.contact_state(0, &y);
    let k = &s.kinematics;
    let tan = perp(k.normal);
    let spin = k.tangential_velocity - dot(k.e_dot, tan);
    let target = [delta_dot, slip - spin];
    let now = [dot(k.e_dot, k.normal), dot(k.e_dot, tan)];
    for i in 0..2 {
        y[n + b + i] += (target[0] - now[0]) * k.normal[i] + (target[1] - now[1]) * tan[i];
    }
    y[2 * n] = stored;
    let s = d.contact_state(0, &y);
    assert!(
        (s.kinematics.delta - delta).abs() < 1e-12
            && (s.kinematics.delta_dot - delta_dot).abs() < 1e-9
            && (s.kinematics.tangential_velocity - slip).abs() < 1e-9,
        "constructed state: δ {} δ̇ {} v_t {}",
        s.kinematics.delta,
        s.kinematics.delta_dot,
        s.kinematics.tangential_velocity
    );
    y
}

/// Largest mismatch between the analytic Jacobian and central differences of f, per entry
/// relative to |fd| + 1e-6 of the largest entry of its row + 1e-6.
fn check(d: &Dae, y: &[f64], case: &str) -> Result<(), FormulationError> {
    let ny = d.n_states();
    let mut jac = vec![0.0; ny * ny];
    let mut f_y = vec![0.0; ny];
    d.rhs(0.01, y, &mut f_y)?;
    let mut work = vec![0.0; 2 * ny];
    let calls = d.jacobian(0.01, y, &f_y, &mut jac, &mut work)?;
    assert_eq!(calls, 0, "{case}: an analytic Jacobian calls no RHS");
    let (mut fp, mut fm) = (vec![0.0; ny], vec![0.0; ny]);
    let mut fd = vec![0.0; ny * ny];
    let mut steps = vec![0.0; ny];
    for j in 0..ny {
        let mut yp = y.to_vec();
        let mut ym = y.to_vec();
        let h = 1e-7 * y[j].abs().max(0.1);
        steps[j] = h;
        yp[j] += h;
        ym[j] -= h;
        d.rhs(0.01, &yp, &mut fp)?;
        d.rhs(0.01, &ym, &mut fm)?;
        for i in 0..ny {
            fd[i * ny + j] = (fp[i] - fm[i]) / (2.0 * h);
        }
    }
    let n = d.n_coordinates();
    let n_energy = if d.n_states() > 2 * d.n_coordinates() + d.n_clearance_joints() {
        3
    } else {
        0
    };
    // Rounding scales with the largest intermediate (λ, contact forces), of the order of the
    // largest acceleration rather than of the row's own.
    let f_max = f_y.iter().fold(0.0_f64, |m, f| m.max(f.abs()));
    for i in 0..ny - n_energy {
        let row_max = (0..ny).fold(0.0_f64, |m, j| m.max(fd[i * ny + j].abs()));
        for j in 0..ny {
            if j >= 2 * n && y[j] == 0.0 {
                // No stored impact velocity: the law then uses δ̇ instead, so f jumps as the
                // stored value leaves 0 and central differences there see the jump, not a slope.
                continue;
            }
            let (a, b) = (jac[i * ny + j], fd[i * ny + j]);
            // Central differences with h = 1e-7·max(|y_j|, 0.1): truncation (h/δ)² ≈ 1e-5
            // relative for the δ^1.5 law at δ = 2 µm, and rounding u·|f_i|/h (u = 1.1e-16,
            // times 100 for the cancellation inside the constraint solve); 1e-4 of the entry,
            // 1e-6 of the row's largest and that rounding bound leave a margin of ~10.
            let rounding = 1e-14 * (f_max + 1.0) / steps[j];
            let bound = 1e-4 * b.abs() + 1e-6 * row_max + rounding;
            assert!(
                (a - b).abs() <= bound,
                "{case}: J[{i}][{j}] analytic {a:e} vs central differences {b:e} (bound {bound:e})"
            );
        }
    }
    Ok(())
}

#[test]
fn fourbar_out_of_contact() -> Result<(), FormulationError> {
    let d = dae("models/farahan2016.toml", false);
    let mut y = d.initial_state();
    // Move off the assembled state a little (Φ ≠ 0: Baumgarte terms; the journal stays free)
    // and change the rates.
    let n = d.n_coordinates();
    y[2] += 1e-4;
    y[5] -= 1e-5;
    y[n + 5] += 0.5;
    check(&d, &y, "free, journal centred")
}

#[test]
fn fourbar_sliding_contact() -> Result<(), FormulationError> {
    let d = dae("models/farahan2016.toml", false);
    let y = contact_state(&d, 2e-6, 0.7, 0.05, 0.3, 0.0);
    check(&d, &y, "sliding, no stored impact velocity")?;
    let y = contact_state(&d, 2e-6, 2.5, -0.03, -0.4, 0.2);
    check(&d, &y, "sliding backwards, stored 0.2 m/s")
}

/// The line-contact laws with each damping: their closed-form slopes of F_N (Johnson's by the
/// implicit function theorem) inside the analytic Jacobian, sliding and receding, with and
/// without a stored impact velocity.
#[test]
fn fourbar_line_contact_laws() -> Result<(), FormulationError> {
    for law in ["johnson", "liu"] {
        for damping in ["lankarani-nikravesh", "hunt-crossley", "flores"] {
            let sets = [
                "joints.B.length=0.02".to_string(),
                format!("joints.B.contact.law={law}"),
                format!("joints.B.contact.damping={damping}"),
            ];
            let sets: Vec<&str> = sets.iter().map(String::as_str).collect();
            let d = dae_with("models/farahan2016.toml", &sets, false);
            let case = format!("{law}/{damping}");
            let y = contact_state(&d, 2e-6, 0.7, 0.05, 0.3, 0.0);
            check(
                &d,
                &y,
                &format!("{case}: sliding, no stored impact velocity"),
            )?;
            let y = contact_state(&d, 5e-6, 2.5, -0.03, -0.4, 0.2);
            check(&d, &y, &format!("{case}: receding, stored 0.2 m/s"))?;
        }
    }
    Ok(())
}

/// A lubricated joint (short and long film): the film's slopes by central differences inside
/// the Jacobian, with the film alone (ε ≈ 0.79, squeezing and sliding), in the hand-over layer
/// (the film weighted, the dry law starting) and below it (dry contact only). `delta` is the
/// penetration past the contact clearance c − h_c. h_c = 50 µm = c/10 rather than the default
/// c/100: this test's reference differences (steps of 1e-8 m) have a truncation error of
/// (h/gap)² relative, 1e-4 at the default layer's 4 µm film (the analytic side's own steps
/// scale with the film and stay exact there); at 40 µm it is 1e-6.
#[test]
fn fourbar_lubricated() -> Result<(), FormulationError> {
    for model in ["short", "long"] {
        let film = format!("joints.B.lubrication.model={model}");
        let sets = [
            "joints.B.length=0.02",
            film.as_str(),
            "joints.B.lubrication.viscosity=0.1",
            "joints.B.lubrication.contact_film_thickness=5e-5",
        ];
        let d = dae_with("models/farahan2016.toml", &sets, false);
        let y = contact_state(&d, -1e-4, 0.7, 0.05, 0.3, 0.0);
        check(&d, &y, &format!("{model}: film only"))?;
        let y = contact_state(&d, -1e-4, 2.5, -0.03, -0.4, 0.0);
        check(&d, &y, &format!("{model}: film only, separating"))?;
        let y = contact_state(&d, 1e-5, 0.7, 0.02, 0.3, 0.1);
        check(&d, &y, &format!("{model}: hand-over layer"))?;
        let y = contact_state(&d, 3e-5, 0.7, 0.02, 0.3, 0.1);
        check(&d, &y, &format!("{model}: dry contact below the layer"))?;
    }
    Ok(())
}

#[test]
fn fourbar_near_stick() -> Result<(), FormulationError> {
    let d = dae("models/farahan2016.toml", false);
    // Inside the friction ramp v0 = 0.1 mm/s … v1 = 1 mm/s.
    let y = contact_state(&d, 3e-6, -1.2, 0.01, 5e-4, 0.1);
    check(&d, &y, "in the friction ramp")?;
    // Below v0: no friction force, no friction slope.
    let y = contact_state(&d, 3e-6, -1.2, 0.01, -5e-5, 0.1);
    check(&d, &y, "stuck (|v_t| < v0)")
}

#[test]
fn fourbar_with_energy_bookkeeping() -> Result<(), FormulationError> {
    let d = dae("models/farahan2016.toml", true);
    let y = contact_state(&d, 2e-6, 0.7, 0.05, 0.3, 0.0);
    check(&d, &y, "sliding, energy states")
}

#[test]
fn slider_crank_with_gas_load_and_clearance() -> Result<(), FormulationError> {
    let d = dae("models/slider_crank_gas.toml", false);
    check(&d, &d.initial_state(), "slider-crank, initial state")?;
    let y = contact_state(&d, 2e-6, 0.3, 0.02, 0.2, 0.1);
    check(&d, &y, "slider-crank, sliding contact")
}

/// The Jacobian keeps its buffers between calls: a call after others at different states (in
/// contact with a stored velocity, free, in contact again, with other RHS calls between) gives
/// exactly what a fresh formulation gives at the same state, so nothing of an earlier call
/// leaks into a later one.
#[test]
fn kept_buffers_carry_nothing_between_calls() -> Result<(), FormulationError> {
    let jacobian_of = |d: &Dae, y: &[f64]| -> Result<Vec<f64>, FormulationError> {
        let ny = d.n_states();
        let (mut jac, mut f_y, mut work) = (vec![0.0; ny * ny], vec![0.0; ny], vec![0.0; 2 * ny]);
        d.rhs(0.01, y, &mut f_y)?;
        d.jacobian(0.01, y, &f_y, &mut jac, &mut work)?;
        Ok(jac)
    };
    let shared = dae("models/farahan2016.toml", false);
    let contact = contact_state(&shared, 2e-6, 2.5, -0.03, -0.4, 0.2);
    let mut free = shared.initial_state();
    free[2] += 1e-4;
    let sliding = contact_state(&shared, 3e-6, 0.7, 0.05, 0.3, 0.0);
    let mut previous = Vec::new();
    for (y, case) in [
        (&contact, "in contact, stored 0.2 m/s"),
        (&free, "free after a contact"),
        (&sliding, "sliding after a free state"),
        (&contact, "the first state again"),
    ] {
        let fresh = jacobian_of(&dae("models/farahan2016.toml", false), y)?;
        let reused = jacobian_of(&shared, y)?;
        assert!(
            fresh
                .iter()
                .zip(&reused)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "{case}: the Jacobian after earlier calls differs from a fresh formulation's"
        );
        assert_ne!(
            fresh, previous,
            "{case}: the states give different Jacobians"
        );
        previous = fresh;
    }
    Ok(())
}

// ---- The sparse augmented form (`dae/sparse_jacobian.rs`) -------------------------------------

/// The augmented Jacobian 𝒥 at (t, y) writes nothing outside its pattern, and its Schur
/// complement 𝒥_yy − 𝒥_yz 𝒥_zz⁻¹ 𝒥_zy is the dense analytic Jacobian.
fn check_augmented(d: &Dae, t: f64, y: &[f64], case: &str) -> Result<(), FormulationError> {
    use crate::formulation::sparse_jacobian::SparseJacobian;
    use nalgebra::DMatrix;
    let ny = d.n_states();
    let mut dense = vec![0.0; ny * ny];
    d.analytic_jacobian(t, y, &mut dense)?;
    let layout = d.sparse_layout();
    let pattern = d.jacobian_pattern();
    let dim = pattern.dim();
    assert_eq!(dim, ny + d.n_algebraic(), "{case}: dimension of 𝒥");
    for i in 0..dim {
        assert!(pattern.position(i, i).is_some(), "{case}: diagonal {i}");
    }
    let mut values = vec![f64::NAN; pattern.nnz()];
    let missed = d.augmented_jacobian(t, y, layout, &mut values)?;
    assert_eq!(missed, 0, "{case}: entries written outside the pattern");
    let mut full = DMatrix::<f64>::zeros(dim, dim);
    for j in 0..dim {
        let start = pattern.col_ptr()[j];
        for (k, &i) in pattern.rows_of(j).iter().enumerate() {
            full[(i, j)] = values[start + k];
        }
    }
    let nz = dim - ny;
    let a = full.view((0, 0), (ny, ny));
    let b = full.view((0, ny), (ny, nz));
    let c = full.view((ny, 0), (nz, ny)).clone_owned();
    let dz = full.view((ny, ny), (nz, nz)).clone_owned();
    let Some(dz_inv_c) = dz.lu().solve(&c) else {
        panic!("{case}: ∂k/∂z singular");
    };
    let schur = a - b * dz_inv_c;
    let scale = dense.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    for i in 0..ny {
        let row_max = (0..ny).fold(0.0_f64, |m, j| m.max(dense[i * ny + j].abs()));
        for j in 0..ny {
            let (s, e) = (schur[(i, j)], dense[i * ny + j]);
            // Two orders of the same arithmetic through the constraint solve (condition number
            // ~1e3 away from singular positions) and, for force elements, differences of one
            // element's force instead of the whole Q (rounding u·|Q|/h ≈ 2e-11 |Q| with
            // h = 6e-6): 1e-9 of the row's largest entry, or of the largest, leaves a margin.
            let bound = 1e-9 * row_max + 1e-12 * scale;
            assert!(
                (s - e).abs() <= bound,
                "{case}: J[{i}][{j}] from 𝒥 {s:e} vs dense {e:e} (bound {bound:e})"
            );
        }
    }
    Ok(())
}

/// `count` random states near y0: coordinates moved by up to `dq` (m, rad), speeds set to
/// random values up to `speed` (m/s, rad/s), from a fixed seed.
fn random_states(y0: &[f64], n: usize, dq: f64, speed: f64, count: usize) -> Vec<Vec<f64>> {
    let mut rng = crate::formulation::test_rng::Lcg(0x5eed_2024);
    (0..count)
        .map(|_| {
            let mut y = y0.to_vec();
            for c in 0..n {
                y[c] += rng.range(-dq, dq);
                y[n + c] = rng.range(-speed, speed);
            }
            y
        })
        .collect()
}

#[test]
fn augmented_form_of_the_fourbar_in_and_out_of_contact() -> Result<(), FormulationError> {
    let d = dae("models/farahan2016.toml", false);
    let n = d.n_coordinates();
    for (k, y) in random_states(&d.initial_state(), n, 1e-4, 2.0, 5)
        .iter()
        .enumerate()
    {
        check_augmented(&d, 0.01, y, &format!("four-bar, random state {k}"))?;
    }
    check_augmented(
        &d,
        0.01,
        &contact_state(&d, 2e-6, 0.7, 0.05, 0.3, 0.0),
        "four-bar sliding",
    )?;
    check_augmented(
        &d,
        0.01,
        &contact_state(&d, 3e-6, -1.2, 0.01, 5e-4, 0.1),
        "four-bar in the friction ramp, stored 0.1 m/s",
    )?;
    let d = dae("models/farahan2016.toml", true);
    check_augmented(
        &d,
        0.01,
        &contact_state(&d, 2e-6, 2.5, -0.03, -0.4, 0.2),
        "four-bar sliding, energy states",
    )
}

#[test]
fn augmented_form_of_the_gas_slider_crank() -> Result<(), FormulationError> {
    let d = dae("models/slider_crank_gas.toml", false);
    check_augmented(&d, 0.0, &d.initial_state(), "slider-crank, initial state")?;
    let y = contact_state(&d, 2e-6, 0.3, 0.02, 0.2, 0.1);
    check_augmented(&d, 0.003, &y, "slider-crank, sliding contact")
}

#[test]
fn augmented_form_of_a_chain_with_force_elements() -> Result<(), FormulationError> {
    // Three loops of the N-four-bar chain with a spring-damper across two loops and a torque
    // law that reads a third body's speed and a fourth's angle: element couplings beyond the
    // joints'.
    let text = std::fs::read_to_string("models/nfourbar_chain.toml")
        .unwrap_or_else(|e| panic!("models/nfourbar_chain.toml: {e}"));
    let text = format!(
        "{text}\n{}",
        r#"
[[forces]]
name = "spring"
type = "spring-damper"
body_a = "link0"
point_a = "T"
body_b = "coupler3"
point_b = "B"
stiffness = 50.0
damping = 2.0
free_length = 1.5

[[forces]]
name = "brake"
type = "torque"
body = "link3"
torque = "-0.5*coupler1.vx - 2*(link1.phi - 1)"
"#
    );
    let model = crate::model::load_str(&text, "chain.toml", &["parameters.N=3".into()])
        .unwrap_or_else(|e| panic!("chain: {e}"));
    let d = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("chain: {e}"));
    let n = d.n_coordinates();
    for (k, y) in random_states(&d.initial_state(), n, 1e-3, 1.5, 5)
        .iter()
        .enumerate()
    {
        check_augmented(
            &d,
            0.2,
            y,
            &format!("chain of 3 with forces, random state {k}"),
        )?;
    }
    Ok(())
}
