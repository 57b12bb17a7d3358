//! The DAE in residual form F(t, Y, Ẏ) = 0 (`formulation::dae::residual`), the equations IDA
//! integrates: it is the same DAE as the explicit path's (the residual vanishes at the state,
//! q̈ and λ of `Dae`), and its iteration matrix ∂F/∂Y + c ∂F/∂Ẏ matches forward differences of
//! the residual — on the ideal four-bar, the clearance four-bar in contact (with and without
//! energy bookkeeping) and the slider-crank (prismatic rows); the energy integrals are
//! quadratures outside F whose rates are the DAE's. Runs without the `ida` feature.

mod common;
use common::load;
use linkdyn::formulation::residual::{ResidualForm, finite_difference_jacobian};
use linkdyn::formulation::{Crossing, Dae, DaeOptions, Formulation};
use linkdyn::model::Model;
use linkdyn::solve::{Method, SolverOptions, Stepper, Stop};

/// The residual form of the DAE of `model`.
fn residual_of(dae: &Dae) -> Box<dyn ResidualForm> {
    dae.residual_form()
        .unwrap_or_else(|| panic!("the DAE has a residual form"))
}

/// A state of `model` at time t: the initial one, or (with `into_contact`) the state a short
/// while after the first impact of the clearance joint, integrated with DOP853.
fn state(model: &Model, energy: bool, into_contact: bool) -> (Dae, f64, Vec<f64>) {
    let mut dae = Dae::new(
        model,
        &DaeOptions {
            energy,
            ..DaeOptions::default()
        },
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let y0 = dae.initial_state();
    if !into_contact {
        return (dae, 0.0, y0);
    }
    let opts = SolverOptions::default()
        .method(Method::Dop853)
        .rtol(1e-9)
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let (t, y) = {
        let mut stepper =
            Stepper::new(&mut dae, 0.0, &y0, 0.5, &opts).unwrap_or_else(|e| panic!("{e}"));
        let mut impact = None;
        loop {
            match stepper.step().unwrap_or_else(|e| panic!("{e}")) {
                Stop::Event { t, .. }
                    if stepper.last_event().map(|e| e.crossing) == Some(Crossing::Rising) =>
                {
                    impact = Some(t);
                }
                Stop::Step if impact.is_some_and(|ti| stepper.t() > ti + 2e-5) => break,
                Stop::EndReached => panic!("no impact in 0.5 s"),
                _ => {}
            }
        }
        (stepper.t(), stepper.y().to_vec())
    };
    (dae, t, y)
}

/// Consistent (Y, Ẏ) at (t, y) from the DAE's own right-hand side.
fn consistent(dae: &Dae, form: &dyn ResidualForm, t: f64, y: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let mut dy = vec![0.0; y.len()];
    dae.rhs(t, y, &mut dy).unwrap_or_else(|e| panic!("{e}"));
    let nn = form.n_unknowns();
    let (mut yy, mut yp) = (vec![0.0; nn], vec![0.0; nn]);
    form.consistent_values(t, y, &dy, &mut yy, &mut yp)
        .unwrap_or_else(|e| panic!("{e}"));
    (yy, yp)
}

/// At (y, ẏ = f(t, y)) with λ from the first block row, every residual row vanishes to
/// round-off, and λ equals the multipliers of `Dae::evaluate`.
fn check_consistent(case: &str, model: &Model, energy: bool, into_contact: bool) {
    let (dae, t, y) = state(model, energy, into_contact);
    let form = residual_of(&dae);
    assert_eq!(form.n_states(), dae.n_states(), "{case}: n");
    let (yy, yp) = consistent(&dae, &*form, t, &y);
    let mut res = vec![0.0; form.n_unknowns()];
    form.residual(t, &yy, &yp, &mut res)
        .unwrap_or_else(|e| panic!("{e}"));
    // Scale of each equation: forces of the dynamics rows (m·|q̈| and |Φ_qᵀλ|), accelerations
    // of the constraint rows. Round-off of sums of such terms is ~1e-16 of them; 1e-9 leaves
    // room for the Cholesky solves of both sides (condition numbers up to ~1e4 here).
    let scale = yy.iter().chain(&yp).fold(1.0_f64, |m, x| m.max(x.abs()));
    let worst = res.iter().fold(0.0_f64, |m, r| m.max(r.abs()));
    assert!(
        worst <= 1e-9 * scale,
        "{case}: largest residual {worst:e} vs bound {:e}",
        1e-9 * scale
    );
    let eval = dae.evaluate(t, &y).unwrap_or_else(|e| panic!("{e}"));
    let lambda_dae: Vec<f64> = (0..eval.lambda.len())
        .filter(|k| !dae.redundant_rows().contains(k))
        .map(|k| eval.lambda[k])
        .collect();
    // λ follows the states of Y: the formulation's states less the quadratures.
    let n = dae.n_states() - form.n_quadratures();
    assert_eq!(
        form.n_unknowns(),
        n + lambda_dae.len(),
        "{case}: unknowns = states without the energy integrals + λ"
    );
    for (i, (a, b)) in yy[n..].iter().zip(&lambda_dae).enumerate() {
        assert!(
            (a - b).abs() <= 1e-9 * scale,
            "{case}: λ_{i} residual form {a} vs Dae {b}"
        );
    }
}

/// The analytic iteration matrix against forward differences of the residual, entry by entry.
fn check_jacobian(case: &str, model: &Model, energy: bool, into_contact: bool) {
    let (dae, t, y) = state(model, energy, into_contact);
    let form = residual_of(&dae);
    let (yy, yp) = consistent(&dae, &*form, t, &y);
    let nn = form.n_unknowns();
    let mut res = vec![0.0; nn];
    form.residual(t, &yy, &yp, &mut res)
        .unwrap_or_else(|e| panic!("{e}"));
    // c = α₀/h of a BDF step of 10 µs, a typical step in contact; c = 0 checks ∂F/∂Y alone
    // (the curvature terms, which the c-scaled mass terms would dwarf).
    for c in [1e5, 0.0] {
        check_jacobian_at(case, &*form, t, &yy, &yp, &res, c);
    }
}

fn check_jacobian_at(
    case: &str,
    form: &dyn ResidualForm,
    t: f64,
    yy: &[f64],
    yp: &[f64],
    res: &[f64],
    c: f64,
) {
    let nn = form.n_unknowns();
    let mut analytic = vec![0.0; nn * nn];
    form.jacobian(t, yy, yp, res, c, &mut analytic)
        .unwrap_or_else(|e| panic!("{e}"));
    let mut fd = vec![0.0; nn * nn];
    finite_difference_jacobian(form, t, yy, yp, c, &mut fd).unwrap_or_else(|e| panic!("{e}"));
    // The central differences are good to ~1e-10 of the row's terms, but the analytic matrix
    // takes Q's columns by forward differences (δ ≈ 1e-8·√|x|: error ≈ 1e-7 of the force's
    // size). The bound, 1e-5 of the largest entry of the row (rows mix N, m/s² and c-scaled
    // entries, so each row is judged on its own scale), is a hundred times that; a wrong
    // analytic term (a sign, a missing λ or ω² factor) is of the row's size and fails by
    // orders of magnitude.
    for i in 0..nn {
        let row_scale = (0..nn).fold(0.0_f64, |m, j| m.max(fd[j * nn + i].abs()));
        for j in 0..nn {
            let (a, b) = (analytic[j * nn + i], fd[j * nn + i]);
            assert!(
                (a - b).abs() <= 1e-5 * row_scale + 1e-9,
                "{case}, c = {c:e}: J[{i}][{j}] analytic {a:e} vs finite differences {b:e} (row scale {row_scale:e})"
            );
        }
    }
}

#[test]
fn residual_vanishes_at_the_dae_solution() {
    let fourbar = load("models/fourbar_ideal.toml", &[]);
    let farahan = load("models/farahan2016.toml", &[]);
    let slider = load("models/slider_crank.toml", &[]);
    check_consistent("fourbar_ideal, t = 0", &fourbar, false, false);
    check_consistent("farahan2016, t = 0, energy", &farahan, true, false);
    check_consistent("farahan2016, in contact", &farahan, false, true);
    check_consistent("slider_crank, t = 0", &slider, false, false);
}

/// On a chain of loops the consistent λ comes from the skyline Schur solve (32 rows, above the
/// dense limit of 16), as the DAE's own multipliers do: the residual vanishes and λ is the DAE's.
#[test]
fn residual_vanishes_on_a_chain_of_loops() {
    let chain = load("models/parallel_fourbar_chain.toml", &["parameters.N=5"]);
    let dae = Dae::new(&chain, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert!(dae.schur_is_skyline(), "5 loops, 32 rows: the skyline");
    check_consistent(
        "parallel_fourbar_chain, 5 loops, t = 0",
        &chain,
        false,
        false,
    );
}

#[test]
fn jacobian_matches_finite_differences() {
    let fourbar = load("models/fourbar_ideal.toml", &[]);
    let farahan = load("models/farahan2016.toml", &[]);
    let slider = load("models/slider_crank.toml", &[]);
    check_jacobian("fourbar_ideal, t = 0", &fourbar, false, false);
    check_jacobian("farahan2016, t = 0", &farahan, false, false);
    check_jacobian("farahan2016, in contact", &farahan, false, true);
    check_jacobian("farahan2016, in contact, energy", &farahan, true, true);
    check_jacobian("slider_crank, t = 0", &slider, false, false);
}

/// The sparse iteration matrix (IDA's sparse LU on large models) holds exactly the dense one:
/// every non-zero of the dense matrix lies in the sparse pattern (`sparse_jacobian` refuses
/// otherwise) with the same value, bit for bit (the same sums in the same order), and the
/// pattern has the whole diagonal. On every kind of row and force: revolute and driver rows
/// (four-bar, chain), prismatic rows (slider-crank), a clearance joint in contact with energy
/// bookkeeping, a lubricated pin, a slider in a guide with clearance, a gas force law.
#[test]
fn sparse_iteration_matrix_is_the_dense_one() {
    let cases: [(&str, &str, &[&str], bool, bool); 8] = [
        (
            "fourbar_ideal",
            "models/fourbar_ideal.toml",
            &[],
            false,
            false,
        ),
        (
            "farahan2016, in contact, energy",
            "models/farahan2016.toml",
            &[],
            true,
            true,
        ),
        (
            "slider_crank",
            "models/slider_crank.toml",
            &[],
            false,
            false,
        ),
        (
            "slider_crank_gas",
            "models/slider_crank_gas.toml",
            &[],
            false,
            false,
        ),
        (
            "slider_crank_lubricated",
            "models/slider_crank_lubricated.toml",
            &[],
            false,
            false,
        ),
        (
            "slider_crank_prismatic_clearance",
            "models/slider_crank_prismatic_clearance.toml",
            &[],
            false,
            false,
        ),
        ("watt_sixbar", "models/watt_sixbar.toml", &[], false, false),
        (
            "parallel_fourbar_chain, 5 loops",
            "models/parallel_fourbar_chain.toml",
            &["parameters.N=5"],
            false,
            false,
        ),
    ];
    let with_stops = (
        "a slider hitting the end stop of its guide, with friction",
        slider_between_stops(),
        true,
        true,
    );
    let loaded = cases
        .iter()
        .map(|(case, path, overrides, energy, into_contact)| {
            (*case, load(path, overrides), *energy, *into_contact)
        });
    for (case, model, energy, into_contact) in loaded.chain([with_stops]) {
        let (dae, t, y) = state(&model, energy, into_contact);
        let form = residual_of(&dae);
        let (yy, yp) = consistent(&dae, &*form, t, &y);
        let nn = form.n_unknowns();
        let pattern = form
            .sparse_pattern()
            .unwrap_or_else(|| panic!("{case}: the DAE's residual form has a sparse pattern"));
        assert_eq!(pattern.dim(), nn, "{case}: dimension");
        assert!(
            (0..nn).all(|i| pattern.position(i, i).is_some()),
            "{case}: the whole diagonal"
        );
        let mut res = vec![0.0; nn];
        form.residual(t, &yy, &yp, &mut res)
            .unwrap_or_else(|e| panic!("{e}"));
        for c in [2.5e4, 0.0] {
            let mut dense = vec![0.0; nn * nn];
            form.jacobian(t, &yy, &yp, &res, c, &mut dense)
                .unwrap_or_else(|e| panic!("{case}: {e}"));
            let mut values = vec![0.0; pattern.nnz()];
            form.sparse_jacobian(t, &yy, &yp, c, &mut values)
                .unwrap_or_else(|e| panic!("{case}, c = {c}: {e}"));
            let mut rebuilt = vec![0.0; nn * nn];
            for j in 0..nn {
                for &i in pattern.rows_of(j) {
                    if let Some(p) = pattern.position(i, j) {
                        rebuilt[j * nn + i] = values[p];
                    }
                }
            }
            let nonzero = dense.iter().filter(|v| **v != 0.0).count();
            assert!(nonzero > nn, "{case}: a matrix beyond its diagonal");
            for (k, (a, b)) in dense.iter().zip(&rebuilt).enumerate() {
                assert!(
                    a.to_bits() == b.to_bits() || (*a == 0.0 && *b == 0.0),
                    "{case}, c = {c}: entry ({}, {}) dense {a:e}, sparse {b:e}",
                    k % nn,
                    k / nn
                );
            }
            println!(
                "{case}: N = {nn}, {} structural non-zeros, {nonzero} non-zero now",
                pattern.nnz()
            );
        }
    }
}

/// A free slider (1 kg, 0.1 × 0.04 m) centred in a guide with 1 mm clearance and stops 10 mm
/// ahead of each face, moving at 0.5 m/s along it under gravity, with friction: its first impact
/// is on the lower guide surface, then the end stop (`tests/prismatic_guide_ends.rs`).
fn slider_between_stops() -> Model {
    common::slider::SliderInGuide {
        gravity: 9.81,
        vx: 0.5,
        tilt: 0.0,
        stop_gap: Some(0.01),
        contact: "law = \"lankarani-nikravesh\"\nrestitution = 0.9",
        friction: "law = \"ambrosio\"",
    }
    .model("slider_between_stops")
}

/// With `--energy` the three energy integrals are quadratures, not unknowns of F: the residual
/// system is the one without them (same N), and their rates g(t, Y, Ẏ) at consistent values are
/// the energy rates of the DAE's own right-hand side (driver power from λ, external power,
/// dissipation) — in free flight and in contact, where the dissipation is not zero.
#[test]
fn energy_integrals_are_quadratures_with_the_dae_rates() {
    let farahan = load("models/farahan2016.toml", &[]);
    for into_contact in [false, true] {
        let (plain, _, _) = state(&farahan, false, into_contact);
        let (dae, t, y) = state(&farahan, true, into_contact);
        let form = residual_of(&dae);
        let plain_form = residual_of(&plain);
        assert_eq!(form.n_quadratures(), 3, "energy integrals");
        assert_eq!(plain_form.n_quadratures(), 0, "no energy integrals");
        assert_eq!(
            form.n_unknowns(),
            plain_form.n_unknowns(),
            "the residual system does not grow with --energy"
        );
        let mut dy = vec![0.0; y.len()];
        dae.rhs(t, &y, &mut dy).unwrap_or_else(|e| panic!("{e}"));
        let (yy, yp) = consistent(&dae, &*form, t, &y);
        let mut rates = [0.0; 3];
        form.quadrature_rhs(t, &yy, &yp, &mut rates)
            .unwrap_or_else(|e| panic!("{e}"));
        let expected = &dy[y.len() - 3..];
        // The same sums of the same products, with λ from the same Schur complement (formed
        // from Q − M q̈ instead of Q and γ): agreement to ~1e-9 of the largest power
        // (round-off times condition numbers up to ~1e4, as for λ above).
        let scale = expected.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
        for (k, (a, b)) in rates.iter().zip(expected).enumerate() {
            assert!(
                (a - b).abs() <= 1e-9 * scale,
                "farahan2016 (contact: {into_contact}), energy rate {k}: quadrature {a:e} W vs DAE {b:e} W"
            );
        }
        if into_contact {
            assert!(
                rates[2].abs() > 0.0,
                "farahan2016 in contact: the dissipation rate is not zero ({:e} W)",
                rates[2]
            );
        }
    }
}
