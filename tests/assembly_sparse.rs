//! Building a model with hundreds of bodies: above 16 constraint rows, assembly finds the rank,
//! the redundant rows, the Newton steps and the velocities with the sparse row-order Cholesky of
//! Φ_q Φ_qᵀ (`formulation::assembly::RowBasis`) instead of dense SVD and Gram–Schmidt. On chains
//! of 101 and 121 bodies it gives what the dense path gives: the same redundant rows, the same
//! rank, positions and velocities that satisfy the constraints to the assembly's tolerances, the
//! same point of the solution curve; and the model it builds moves as it must.

mod common;
use common::*;
use linkdyn::formulation::assembly::{
    Assembly, RankSolver, assemble_with, redundant_rows_checked_with,
};
use linkdyn::formulation::{Dae, DaeOptions, Formulation};
use linkdyn::mechanics::constraints::ConstraintEval;
use linkdyn::mechanics::{ConstraintSet, RowSource};
use linkdyn::model::Model;

/// |Φ| (m or rad) at which assembly stops: `POSITION_TOLERANCE` of the assembly.
const POSITION_TOLERANCE: f64 = 1e-12;

/// `models/parallel_fourbar_chain.toml` with a third crank in every loop, from a ground pivot
/// midway between the loop's two to the middle of its coupler: the classic over-constrained
/// parallelogram, one redundant row per loop (N loops: 3N + 1 bodies, 10N + 2 rows).
fn third_crank_chain(loops: usize) -> Model {
    let base = std::fs::read_to_string("models/parallel_fourbar_chain.toml")
        .unwrap_or_else(|e| panic!("{e}"));
    let text = base.replace(
        "points = { A = [\"-a/2\", 0], B = [\"a/2\", 0] }",
        "points = { A = [\"-a/2\", 0], B = [\"a/2\", 0], M = [0, 0] }",
    ) + r#"
[[repeat]]
index = "k"
from = 1
to = "N"

[repeat.ground]
points = { "H{k}" = ["(k - 1/2)*a", 0] }

[[repeat.bodies]]
name = "mid{k}"
mass = "m_link"
inertia = "m_link*L^2/12"
points = { P = ["-L/2", 0], T = ["L/2", 0] }
initial = { x = "(k - 1/2)*a + L/2*cos(phi0)", y = "L/2*sin(phi0)", phi = "phi0" }

[[repeat.joints]]
name = "hang{k}"
type = "revolute"
body_a = "ground"
point_a = "H{k}"
body_b = "mid{k}"
point_b = "P"

[[repeat.joints]]
name = "tip{k}"
type = "revolute"
body_a = "mid{k}"
point_a = "T"
body_b = "coupler{k}"
point_b = "M"
"#;
    assert!(
        text.contains("M = [0, 0]"),
        "the coupler's points line changed"
    );
    linkdyn::model::load_str(
        &text,
        "third_crank_chain.toml",
        &[format!("parameters.N={loops}")],
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

/// Moves every body's initial guess off the assembled chain by up to 1 cm and 0.05 rad (a fixed,
/// irregular pattern) and gives every body ω = 1 rad/s to be projected.
fn disturb(model: &mut Model) {
    for (i, body) in model.bodies.iter_mut().enumerate() {
        let wobble = |k: usize| ((i * 3 + k) as f64 * 0.618_033_988_75).fract() - 0.5;
        body.initial.x += 0.02 * wobble(0);
        body.initial.y += 0.02 * wobble(1);
        body.initial.phi += 0.1 * wobble(2);
        body.initial.omega = 1.0;
    }
}

fn assemble(model: &Model, solver: RankSolver) -> Assembly {
    let set = ConstraintSet::from_model(model, true);
    let dynamic = ConstraintSet::from_model(model, false);
    assemble_with(model, &set, &dynamic, 0.0, solver).unwrap_or_else(|e| panic!("{solver:?}: {e}"))
}

fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
}

/// Largest |Φ| and |Φ̇| = |Φ_q q̇ + Φ_t| of the model's dynamic rows at the assembled (q, q̇).
fn constraint_residuals(model: &Model, a: &Assembly) -> (f64, f64) {
    let set = ConstraintSet::from_model(model, false);
    let mut eval = ConstraintEval::with_rows(set.n_rows());
    let sin_cos: Vec<(f64, f64)> = a.q.chunks_exact(3).map(|b| b[2].sin_cos()).collect();
    set.evaluate_into(0.0, &a.q, &a.v, &sin_cos, &mut eval);
    let max_abs = |v: &[f64]| v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    (max_abs(&eval.phi), max_abs(&eval.phi_dot))
}

#[test]
fn a_101_body_chain_assembles_from_a_disturbed_guess_as_on_the_dense_path() {
    let mut model = load("models/parallel_fourbar_chain.toml", &["parameters.N=50"]);
    assert_eq!(model.bodies.len(), 101);
    let guess: Vec<f64> = {
        disturb(&mut model);
        model
            .bodies
            .iter()
            .flat_map(|b| [b.initial.x, b.initial.y, b.initial.phi])
            .collect()
    };
    let sparse = assemble(&model, RankSolver::Sparse);
    let dense = assemble(&model, RankSolver::Dense);
    for (name, a) in [("sparse", &sparse), ("dense", &dense)] {
        assert!(
            a.residual <= POSITION_TOLERANCE,
            "{name}: |Φ| = {:e} after {} iterations",
            a.residual,
            a.iterations
        );
        let (phi, phi_dot) = constraint_residuals(&model, a);
        assert!(
            phi <= POSITION_TOLERANCE,
            "{name}: |Φ| = {phi:e} re-evaluated"
        );
        // The velocity tolerance of the assembly (1e-10 relative to 1 + max |Φ_t|, Φ_t = 0).
        assert!(phi_dot <= 1e-10, "{name}: |Φ_q q̇| = {phi_dot:e}");
        assert_eq!(
            (a.rank, a.dof),
            (302, 1),
            "{name}: rank and degrees of freedom"
        );
        assert!(
            a.redundant_rows.is_empty(),
            "{name}: {:?}",
            a.redundant_rows
        );
    }
    // Both take the least-squares minimum-norm steps −Φ_q⁺ Φ; the dense path above 16 rows
    // through shifted normal equations (relative shift 1e-10) whose steps are off by
    // shift |Φ_q|² / σ_min² relative, which the free direction of the chain (one degree of
    // freedom: nothing pulls the two back to one point) keeps: 2e-3 of the distance travelled.
    let travel = max_difference(&dense.q, &guess);
    let dq = max_difference(&sparse.q, &dense.q);
    assert!(
        travel > 1e-3,
        "the guess was disturbed: travelled {travel:e}"
    );
    assert!(
        dq <= 2e-3 * travel,
        "positions differ by {dq:e} after travelling {travel:e}"
    );
    // Velocities at positions dq apart: a few dq with |q̇| ~ 1 rad/s and 0.2–0.3 m links.
    let dv = max_difference(&sparse.v, &dense.v);
    assert!(dv <= 100.0 * dq + 1e-10, "velocities differ by {dv:e}");
}

#[test]
fn a_121_body_chain_with_a_redundant_row_per_loop_keeps_one_degree_of_freedom() {
    let model = third_crank_chain(40);
    assert_eq!(model.bodies.len(), 121);
    let dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let a = dae.assembly();
    assert!(a.residual <= POSITION_TOLERANCE, "|Φ| = {:e}", a.residual);
    assert_eq!(a.dof, 1, "the chain moves");
    // In row order each loop's third crank closes the loop: the second row of its tip pin
    // repeats the others, for the assembly and the dynamics alike, on both paths.
    let names: Vec<String> = dae
        .redundant_rows()
        .iter()
        .map(|&k| dae.constraints().row_name(&model, k))
        .collect();
    let expected: Vec<String> = (1..=40).map(|k| format!("tip{k}.y")).collect();
    assert_eq!(names, expected);
    let dense = redundant_rows_checked_with(
        &model,
        dae.constraints(),
        &a.q,
        &a.v,
        0.0,
        RankSolver::Dense,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(dense, dae.redundant_rows(), "dense against sparse");
    assert!(
        dae.constraints()
            .sources()
            .iter()
            .all(|s| !matches!(s, RowSource::Driver(_)))
    );
    // Released at rest 0.6 rad from hanging, every link and third crank turns alike and every
    // coupler stays level: the chain is one compound pendulum. Its angular acceleration is
    // −(g / ℓ) sin(0.6) for some ℓ > 0, the same on every crank to round-off of the
    // 400-row Schur solve (1e-9 relative).
    let y = dae.initial_state();
    let mut dy = vec![0.0; y.len()];
    dae.rhs(0.0, &y, &mut dy).unwrap_or_else(|e| panic!("{e}"));
    let n = dae.n_coordinates();
    let alpha = |name: &str| {
        let i = model
            .bodies
            .iter()
            .position(|b| b.name == name)
            .unwrap_or_else(|| panic!("no body {name}"));
        dy[n + 3 * i + 2]
    };
    let reference = alpha("link0");
    assert!(
        reference < 0.0,
        "the chain swings back towards hanging: {reference}"
    );
    for k in 0..=40 {
        let link = alpha(&format!("link{k}"));
        assert!(
            (link - reference).abs() <= 1e-9 * reference.abs(),
            "link{k}: φ̈ = {link} against {reference}"
        );
    }
    for k in 1..=40 {
        let mid = alpha(&format!("mid{k}"));
        let coupler = alpha(&format!("coupler{k}"));
        assert!(
            (mid - reference).abs() <= 1e-9 * reference.abs(),
            "mid{k}: φ̈ = {mid} against {reference}"
        );
        assert!(
            coupler.abs() <= 1e-9 * reference.abs(),
            "coupler{k} turns: φ̈ = {coupler}"
        );
    }
}
