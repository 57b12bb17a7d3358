//! The sparse rank and least-norm path ([`RowBasis`]) against the dense one on generated chains of
//! parallelogram loops: the same redundant rows, the same assembled positions, the same
//! velocities, and the same loop named when a chain cannot be assembled.

use super::*;
use crate::model::load_str;

/// A chain of `loops` parallelogram loops (the geometry of `models/parallel_fourbar_chain.toml`:
/// links of length L = 0.3 m hanging from ground pivots a = 0.2 m apart, coupler k joining the
/// tips of links k − 1 and k), written joint by joint as a model file would be.
struct Chain {
    loops: usize,
    /// A third, parallel crank in each loop, from a ground pivot midway to the coupler's middle:
    /// the classic over-constrained parallelogram, one redundant row per loop.
    third_crank: bool,
    /// Couplers this much longer than the pivot spacing (m), by loop (1-based): a loop whose
    /// coupler is longer than a + 2L = 0.8 m cannot close.
    longer_coupler: Option<(usize, f64)>,
    /// A third crank this much longer than the others (m), by loop: it cannot reach the
    /// coupler's middle, which stays within L of its pivot, beyond L.
    longer_crank: Option<(usize, f64)>,
    /// Relative disturbance of the initial guesses (positions and angles), so that Newton has
    /// work to do; the initial velocities are ω = 1 rad/s on every body, to be projected.
    disturb: f64,
}

const L: f64 = 0.3;
const A: f64 = 0.2;
const PHI0: f64 = -std::f64::consts::FRAC_PI_2 + 0.6;

impl Chain {
    fn model(&self) -> Model {
        // A fixed, irregular disturbance per body (no random generator needed).
        let mut body = 0usize;
        let mut off = |scale: f64| {
            body += 1;
            self.disturb * scale * ((body as f64 * 1.618_033_988_75).fract() - 0.5)
        };
        let mut text = String::from(
            "[model]\nname = \"chain\"\n[settings]\ngravity = [0.0, -9.81]\n[ground]\npoints = { ",
        );
        let mut ground: Vec<String> = (0..=self.loops)
            .map(|i| format!("G{i} = [{}, 0.0]", i as f64 * A))
            .collect();
        if self.third_crank {
            ground.extend(
                (1..=self.loops).map(|k| format!("H{k} = [{}, 0.0]", (k as f64 - 0.5) * A)),
            );
        }
        text += &ground.join(", ");
        text += " }\n";
        let (c, s) = (PHI0.cos(), PHI0.sin());
        let link = |name: String, x0: f64, len: f64, off: &mut dyn FnMut(f64) -> f64| {
            format!(
                "[[bodies]]\nname = \"{name}\"\nmass = 0.6\ninertia = 0.0045\npoints = {{ P = [{p}, 0.0], T = [{t}, 0.0] }}\ninitial = {{ x = {x}, y = {y}, phi = {phi}, omega = 1.0 }}\n",
                p = -len / 2.0,
                t = len / 2.0,
                x = x0 + L / 2.0 * c + off(L),
                y = L / 2.0 * s + off(L),
                phi = PHI0 + off(1.0),
            )
        };
        for i in 0..=self.loops {
            text += &link(format!("link{i}"), i as f64 * A, L, &mut off);
        }
        for k in 1..=self.loops {
            let a = A + match self.longer_coupler {
                Some((bad, extra)) if bad == k => extra,
                _ => 0.0,
            };
            text += &format!(
                "[[bodies]]\nname = \"coupler{k}\"\nmass = 0.4\ninertia = 0.0013\npoints = {{ A = [{}, 0.0], B = [{}, 0.0], M = [0.0, 0.0] }}\ninitial = {{ x = {x}, y = {y}, phi = {phi}, omega = 1.0 }}\n",
                -a / 2.0,
                a / 2.0,
                x = (k as f64 - 0.5) * A + L * c + off(A),
                y = L * s + off(A),
                phi = off(1.0),
            );
            if self.third_crank {
                let len = L + match self.longer_crank {
                    Some((bad, extra)) if bad == k => extra,
                    _ => 0.0,
                };
                text += &link(format!("mid{k}"), (k as f64 - 0.5) * A, len, &mut off);
            }
        }
        let joint = |name: String, a: String, pa: &str, b: String, pb: &str| {
            format!(
                "[[joints]]\nname = \"{name}\"\ntype = \"revolute\"\nbody_a = \"{a}\"\npoint_a = \"{pa}\"\nbody_b = \"{b}\"\npoint_b = \"{pb}\"\n"
            )
        };
        for i in 0..=self.loops {
            text += &joint(
                format!("pivot{i}"),
                "ground".into(),
                &format!("G{i}"),
                format!("link{i}"),
                "P",
            );
        }
        for k in 1..=self.loops {
            let coupler = format!("coupler{k}");
            text += &joint(
                format!("left{k}"),
                format!("link{}", k - 1),
                "T",
                coupler.clone(),
                "A",
            );
            text += &joint(
                format!("right{k}"),
                format!("link{k}"),
                "T",
                coupler.clone(),
                "B",
            );
            if self.third_crank {
                text += &joint(
                    format!("hang{k}"),
                    "ground".into(),
                    &format!("H{k}"),
                    format!("mid{k}"),
                    "P",
                );
                text += &joint(format!("tip{k}"), format!("mid{k}"), "T", coupler, "M");
            }
        }
        load_str(&text, "chain.toml", &[]).unwrap_or_else(|e| panic!("{e}"))
    }
}

fn sets(model: &Model) -> (ConstraintSet, ConstraintSet) {
    (
        ConstraintSet::from_model(model, true),
        ConstraintSet::from_model(model, false),
    )
}

fn assemble_by(model: &Model, solver: RankSolver) -> Result<Assembly, FormulationError> {
    let (set, dynamic) = sets(model);
    assemble_with(model, &set, &dynamic, 0.0, solver)
}

/// Largest |Φ| and |Φ_q q̇ + Φ_t| of `set` at the assembled state.
fn residuals(model: &Model, a: &Assembly) -> (f64, f64) {
    let (set, _) = sets(model);
    let mut eval = ConstraintEval::with_rows(set.n_rows());
    evaluate(&set, 0.0, &a.q, &a.v, &mut eval);
    (max_abs(&eval.phi), max_abs(&eval.phi_dot))
}

fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
}

#[test]
fn sparse_and_dense_find_the_same_redundant_rows_and_positions() {
    for (loops, third_crank, disturb) in [
        (1, true, 0.05),
        (2, false, 0.05),
        (3, true, 0.0),
        (3, true, 0.05),
        (12, true, 0.05),
        (12, false, 0.05),
        (40, true, 0.02),
    ] {
        let case = format!("{loops} loops, third crank {third_crank}, disturbance {disturb}");
        let model = Chain {
            loops,
            third_crank,
            longer_coupler: None,
            longer_crank: None,
            disturb,
        }
        .model();
        let dense =
            assemble_by(&model, RankSolver::Dense).unwrap_or_else(|e| panic!("{case}: {e}"));
        let sparse =
            assemble_by(&model, RankSolver::Sparse).unwrap_or_else(|e| panic!("{case}: {e}"));
        // One degree of freedom; with the third cranks one redundant row per loop.
        let expected = if third_crank { loops } else { 0 };
        assert_eq!(dense.redundant_rows.len(), expected, "{case}: dense");
        assert_eq!(sparse.redundant_rows, dense.redundant_rows, "{case}");
        assert_eq!((sparse.rank, sparse.dof), (dense.rank, 1), "{case}");
        // Both converge to |Φ| ≤ 1e-12 (the Newton tolerance) along the same least-squares
        // minimum-norm steps Δq = −Φ_q⁺ Φ. The solutions form a curve (one degree of freedom),
        // so where the steps differ the point reached on it differs by as much, not by the
        // tolerance. Against the SVD pseudo-inverse at every step (the dense path up to 16
        // rows; `pinv` here), the same steps to round-off: positions agree to 1e-7 of the
        // distance travelled. The dense path above 16 rows takes the shifted normal
        // equations instead (Levenberg–Marquardt, relative shift 1e-10), whose steps are off by
        // shift |Φ_q|² / σ_min² relative: 1e-4 at 3 loops, 5e-4 at 40 loops (σ_min falls
        // with the chain's length), so 2e-3 of the distance travelled there.
        let (phi_sparse, phi_dot_sparse) = residuals(&model, &sparse);
        let (phi_dense, _) = residuals(&model, &dense);
        assert!(
            phi_sparse <= POSITION_TOLERANCE,
            "{case}: |Φ| = {phi_sparse:e}"
        );
        assert!(
            phi_dense <= POSITION_TOLERANCE,
            "{case}: dense |Φ| = {phi_dense:e}"
        );
        let guess: Vec<f64> = model
            .bodies
            .iter()
            .flat_map(|b| [b.initial.x, b.initial.y, b.initial.phi])
            .collect();
        let travel = max_difference(&dense.q, &guess);
        let m = sets(&model).0.n_rows();
        let relative = if m <= DENSE_MAX_ROWS { 1e-7 } else { 2e-3 };
        let dq = max_difference(&sparse.q, &dense.q);
        assert!(
            dq <= relative * travel + 1e-13,
            "{case}: positions differ by {dq:e} after travelling {travel:e}"
        );
        let (set, dynamic) = sets(&model);
        let pinv = assemble_steps(
            &model,
            &set,
            &dynamic,
            0.0,
            RankSolver::Dense,
            SchurSolver::Dense,
        )
        .unwrap_or_else(|e| panic!("{case}: {e}"));
        let dp = max_difference(&sparse.q, &pinv.q);
        assert!(
            dp <= 1e-7 * travel + 1e-13,
            "{case}: positions differ from the pseudo-inverse steps' by {dp:e} after travelling {travel:e}"
        );
        // The velocities: both the least-squares correction of the same guess onto
        // Φ_q q̇ = 0, at positions dq apart; with |q̇| ~ 1 and links of 0.2–0.3 m they differ by
        // a few dq (100 dq as margin) and the round-off of the projection.
        let dv = max_difference(&sparse.v, &dense.v);
        assert!(
            phi_dot_sparse < 1e-10,
            "{case}: |Φ_q q̇| = {phi_dot_sparse:e}"
        );
        assert!(
            dv <= 100.0 * dq + 1e-10,
            "{case}: velocities differ by {dv:e} (positions by {dq:e})"
        );
        // The checked redundancy of the dynamic rows agrees too (no conflict: the redundant
        // rows are consistent, the linkage moves).
        let (_, dynamic) = sets(&model);
        let checked = |solver| {
            redundant_rows_checked_with(&model, &dynamic, &sparse.q, &sparse.v, 0.0, solver)
                .unwrap_or_else(|e| panic!("{case}: {e}"))
        };
        assert_eq!(
            checked(RankSolver::Sparse),
            checked(RankSolver::Dense),
            "{case}"
        );
    }
}

#[test]
fn the_redundant_rows_are_the_last_rows_of_each_third_crank() {
    // In row order a loop's third crank closes the loop: its tip pin's second row is the one
    // that repeats the others (the dense rule's answer, and the sparse path's).
    let model = Chain {
        loops: 30,
        third_crank: true,
        longer_coupler: None,
        longer_crank: None,
        disturb: 0.01,
    }
    .model();
    let a = assemble_by(&model, RankSolver::Sparse).unwrap_or_else(|e| panic!("{e}"));
    let (set, _) = sets(&model);
    let names: Vec<String> = a
        .redundant_rows
        .iter()
        .map(|&k| set.row_name(&model, k))
        .collect();
    let expected: Vec<String> = (1..=30).map(|k| format!("tip{k}.y")).collect();
    assert_eq!(names, expected);
}

#[test]
fn a_third_crank_that_cannot_reach_is_named_by_both_paths() {
    // The coupler's middle stays within L of the third crank's pivot (it is the midpoint of
    // two points within L of pivots symmetric about it), so a third crank longer than L cannot
    // reach it: that loop cannot close, and both paths name one of its joints (the misfit,
    // shared out by the least-squares steps, is largest there).
    for (bad, extra) in [(1, 0.01), (7, 0.1), (7, 0.3), (20, 0.1), (20, 0.3)] {
        let model = Chain {
            loops: 20,
            third_crank: true,
            longer_coupler: None,
            longer_crank: Some((bad, extra)),
            disturb: 0.0,
        }
        .model();
        let loop_joints = [
            format!("pivot{}", bad - 1),
            format!("pivot{bad}"),
            format!("left{bad}"),
            format!("right{bad}"),
            format!("hang{bad}"),
            format!("tip{bad}"),
        ];
        for solver in [RankSolver::Dense, RankSolver::Sparse] {
            let case = format!("loop {bad}, crank {extra} m too long, {solver:?}");
            match assemble_by(&model, solver) {
                Err(FormulationError::Unassemblable {
                    joint, residual, ..
                }) => {
                    assert!(
                        loop_joints.contains(&joint),
                        "{case}: named {joint} (residual {residual:e})"
                    );
                    // The crank is `extra` too long; the misfit shared out over the loop's
                    // joints leaves at least a tenth of it on the worst.
                    assert!(residual > 0.1 * extra, "{case}: residual {residual:e}");
                }
                other => panic!("{case}: expected Unassemblable, got {other:?}"),
            }
        }
    }
}

#[test]
fn row_basis_fit_reproduces_a_dependent_row() {
    // The fit of a redundant row by the independent rows before it rebuilds that row of Φ_q
    // to round-off: the coefficients the conflict check combines Φ_t and γ with.
    let model = Chain {
        loops: 10,
        third_crank: true,
        longer_coupler: None,
        longer_crank: None,
        disturb: 0.0,
    }
    .model();
    let a = assemble_by(&model, RankSolver::Sparse).unwrap_or_else(|e| panic!("{e}"));
    let (set, _) = sets(&model);
    let mut eval = ConstraintEval::with_rows(set.n_rows());
    evaluate(&set, 0.0, &a.q, &a.v, &mut eval);
    let n = a.q.len();
    let mut basis = RowBasis::new(&eval.rows, n);
    basis.factor(&eval.rows, RANK_TOLERANCE);
    assert_eq!(basis.dependent_rows(), a.redundant_rows);
    for &k in &a.redundant_rows {
        let mut c = vec![0.0; k];
        basis.combination_into(&eval.rows, k, &mut c);
        let mut rebuilt = vec![0.0; n];
        let mut target = vec![0.0; n];
        for (row, ci) in eval.rows[..k].iter().zip(&c) {
            scatter(row, *ci, &mut rebuilt);
        }
        scatter(&eval.rows[k], 1.0, &mut target);
        let err = max_difference(&rebuilt, &target);
        assert!(err < 1e-12, "row {k}: the fit is off by {err:e}");
    }
}
