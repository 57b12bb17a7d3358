//! Claim (docs/formulations.md, "Singular positions"): the generalised-coordinate formulation goes *through* the singular
//! positions of a parallelogram four-bar and of a chain of three parallel four-bars — the flat
//! positions, where every link lies on the ground line and the constraint Jacobian loses one
//! rank per loop — and stays on the parallelogram branch after every passage, follows the exact
//! motion, and conserves energy; and so does the DAE with the models' default Baumgarte factors
//! — its multiplier solve has regularised pivots and its step ends near a singular position are
//! projected onto the joints (`src/formulation/dae.rs`, `dae/projection.rs`) — with explicit
//! (DOP853), implicit (Radau5) and, with the `ida` feature, SUNDIALS IDA, its joint reactions
//! finite and equal to the exact ones (their limit along the motion where they are not unique).
//!
//! Exact solution: every link turns by the same angle θ and every coupler translates, so the
//! linkage is the pendulum J θ̈ = −G cos θ (constants in the fixtures' headers), integrated here
//! by a classical Runge–Kutta method of our own with a fixed step of 10 µs: its error is
//! O(h⁴) ≈ 1e-13 rad over the run, which the test checks by halving the step.

mod cli_common;
mod common;
use cli_common::{linkdyn, path_arg, scratch};
use common::*;
use linkdyn::formulation::{Dae, DaeOptions, Formulation, Generalized, Outputs};
use linkdyn::model::Model;
use linkdyn::solve::{Method, Recorder, SolveError, SolverOptions, integrate};

/// Link length L (m), link and coupler masses (kg), gravity (m/s²), as in the fixtures (the
/// coupler length does not enter: couplers translate).
const L: f64 = 0.4;
const M_LINK: f64 = 1.0;
const M_COUPLER: f64 = 2.0;
const G: f64 = 9.81;
/// Initial angle and rate: hanging down, fast enough to turn over the top.
const THETA0: f64 = -std::f64::consts::FRAC_PI_2;
const OMEGA0: f64 = 12.0;
/// Run length (s): about 4.7 turns, 9 passages of a flat position.
const T_END: f64 = 3.5;
const DT: f64 = 1e-3;

/// (J, G) of a chain of `loops` parallel four-bars: J θ̈ = −G cos θ.
fn pendulum(loops: usize) -> (f64, f64) {
    let links = (loops + 1) as f64;
    let couplers = loops as f64;
    let j = links * (M_LINK * L * L / 12.0 + M_LINK * L * L / 4.0) + couplers * M_COUPLER * L * L;
    let g = G * (links * M_LINK * L / 2.0 + couplers * M_COUPLER * L);
    (j, g)
}

/// θ at the times `ts` (increasing) by RK4 with step h, θ and θ̇ summed with Kahan's
/// compensation (3.5e5 rounded additions to θ ≈ 30 would otherwise cost ~1e-9 rad): the scheme
/// of the chain tests (`common/chain.rs`).
fn reference(loops: usize, ts: &[f64], h: f64) -> Vec<f64> {
    let (j, g) = pendulum(loops);
    common::chain::pendulum_theta(j, g, THETA0, OMEGA0, ts, h)
}

fn run<F: Formulation + Outputs>(
    f: &mut F,
    method: Method,
    rtol: f64,
) -> Result<Recorder, SolveError> {
    let options = SolverOptions::default()
        .method(method)
        .rtol(rtol)
        .atol(rtol * 1e-2)
        .build()?;
    let y0 = f.initial_state();
    let mut rec = Recorder::new(f);
    integrate(f, 0.0, &y0, T_END, DT, &options, &mut rec)?;
    Ok(rec)
}

/// The samples just after each flat position θ passes (crossings of sin θ = 0).
fn flat_positions(theta: &[f64]) -> Vec<usize> {
    theta
        .windows(2)
        .enumerate()
        .filter(|(_, w)| {
            (w[0] / std::f64::consts::PI).floor() != (w[1] / std::f64::consts::PI).floor()
        })
        .map(|(i, _)| i + 1)
        .collect()
}

/// Flat positions passed by θ over the run.
fn passages(theta: &[f64]) -> usize {
    flat_positions(theta).len()
}

/// Asserts that link0's angle follows the pendulum `exact` within 300 × rtol · max|θ| (the
/// callers give the measured factors).
fn assert_follows_pendulum(case: &str, rec: &Recorder, exact: &[f64], rtol: f64) {
    let theta = col(rec, "link0.phi");
    let theta_max = exact.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let bound = 300.0 * rtol * theta_max;
    let (worst, at) = theta
        .iter()
        .zip(exact)
        .zip(&rec.t)
        .map(|((a, b), t)| ((a - b).abs(), *t))
        .fold((0.0, 0.0), |m, x| if x.0 > m.0 { x } else { m });
    assert!(
        worst < bound,
        "{case}: θ differs from the pendulum by {worst:e} rad at t = {at} s, bound {bound:e}"
    );
}

/// Asserts that T + U stays within 1000 × rtol · J θ̇₀² of its initial value (the callers give
/// the measured factors).
fn assert_energy_conserved(case: &str, model: &Model, rec: &Recorder, loops: usize, rtol: f64) {
    let energy = mechanical_energy(model, rec);
    let (j, _) = pendulum(loops);
    let scale = j * OMEGA0 * OMEGA0;
    let drift = energy
        .iter()
        .fold(0.0_f64, |m, e| m.max((e - energy[0]).abs()));
    assert!(
        drift < 1000.0 * rtol * scale,
        "{case}: energy drifts by {drift:e} J, bound {:e} J",
        1000.0 * rtol * scale
    );
}

fn check_generalized(fixture: &str, loops: usize) {
    let model = load(fixture, &[]);
    for rtol in [1e-7, 1e-10] {
        let case = format!("{fixture}, rtol {rtol:e}");
        let mut f = Generalized::new(&model, &DaeOptions::default())
            .unwrap_or_else(|e| panic!("{case}: {e}"));
        let rec = run(&mut f, Method::Dop853, rtol).unwrap_or_else(|e| panic!("{case}: {e}"));
        let theta = col(&rec, "link0.phi");
        let exact = reference(loops, &rec.t, 1e-5);
        let n = passages(&exact);
        assert!(n >= 8, "{case}: only {n} flat positions passed");
        // Global error of an rtol-controlled run over ~9 passages and 4.7 turns: measured
        // (2026-11-23) at 1.5–75 × rtol · max|θ| for both fixtures and both tolerances (the
        // larger factors at rtol 1e-10, where a stage that lands within ~1e-8 rad of a flat
        // position computes B and c to a relative accuracy ε/s only); 300 × leaves a factor 4.
        // A wrong branch or a lost passage is an O(1) error.
        assert_follows_pendulum(&case, &rec, &exact, rtol);
        // The parallelogram branch: every coupler keeps φ = 0 and every link turns as link0.
        // The crossed branch differs by O(1) rad right after a passage; 1e-9 rad is a thousand
        // times the projection's tolerance (1e-12 L on links of 0.4 m).
        for k in 1..=loops {
            for (name, reference) in [
                (format!("coupler{k}.phi"), vec![0.0; rec.len()]),
                (format!("link{k}.phi"), theta.clone()),
            ] {
                let value = col(&rec, &name);
                let off = value
                    .iter()
                    .zip(&reference)
                    .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
                assert!(
                    off < 1e-9,
                    "{case}: {name} left the parallelogram branch by {off:e} rad"
                );
            }
        }
        // Energy: T + U is conserved; the error is the integration error of the velocities
        // over the run, measured (2026-11-23) at 2–71 × rtol · J θ̇₀² (the larger at rtol
        // 1e-10, for the reason given for θ); bound 1000 ×.
        assert_energy_conserved(&case, &model, &rec, loops, rtol);
        // No drift by construction: the projection's residual at every sample and step end.
        assert!(
            rec.max_constraint_violation < 1e-11,
            "{case}: |Φ| reached {:e}",
            rec.max_constraint_violation
        );
    }
}

#[test]
fn the_reference_pendulum_is_converged() {
    // RK4 error ∝ h⁴: halving h changes θ by 15/16 of the error of the coarse run.
    let ts: Vec<f64> = (0..=35).map(|k| 0.1 * k as f64).collect();
    let a = reference(3, &ts, 1e-5);
    let b = reference(3, &ts, 5e-6);
    let diff = a
        .iter()
        .zip(&b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(diff < 1e-11, "RK4 at 10 µs vs 5 µs: {diff:e} rad");
}

#[test]
fn generalized_passes_the_flat_position_of_a_parallelogram() {
    check_generalized("tests/fixtures/parallelogram.toml", 1);
}

#[test]
fn generalized_passes_the_flat_positions_of_a_chain_of_three_parallelograms() {
    check_generalized("tests/fixtures/parallelogram_chain3.toml", 3);
}

/// Exact force (N) on the coupler at A of a single parallelogram and on link0 at O, in the
/// state (θ, θ̇) of the motion: the coupler translates with the crank tip,
/// a = L (−sin θ θ̈ − cos θ θ̇², cos θ θ̈ − sin θ θ̇²), θ̈ = −G cos θ / J, and its two identical
/// links share its load equally (the coupler's torque balance gives F_Ay = F_By, the links'
/// F_Ax = F_Bx wherever sin θ ≠ 0, and the limit at the flat position): F_A = m_c (a − g)/2,
/// F_O = m_l (a_l − g) + F_A with a_l = a/2 the link's centre.
fn parallelogram_reactions(theta: f64, omega: f64) -> ([f64; 2], [f64; 2]) {
    let (j, g) = pendulum(1);
    let alpha = -g / j * theta.cos();
    let (s, c) = theta.sin_cos();
    let a = [
        L * (-s * alpha - c * omega * omega),
        L * (c * alpha - s * omega * omega),
    ];
    let f_a = [0.5 * M_COUPLER * a[0], 0.5 * M_COUPLER * (a[1] + G)];
    let f_o = [
        M_LINK * 0.5 * a[0] + f_a[0],
        M_LINK * (0.5 * a[1] + G) + f_a[1],
    ];
    (f_a, f_o)
}

/// The DAE with the models' default Baumgarte factors (α = β = 10 s⁻¹). Near a flat position
/// the level sets Φ = const turn onto the crossed branch: a drift ε on arrival leaves a passage
/// as a deflection some 1e3 ε (measured 2026-11-25, rtol 1e-10: 4e-13 m in, 5e-10 m out), and
/// 10 s⁻¹ damps it only ~15× in the 0.28–0.45 s between passages; without the projection of
/// the step ends near singular positions (`src/formulation/dae/projection.rs`) these runs left
/// the parallelogram branch within two or three passages at every tolerance (measured
/// 2026-11-26), with it none does. SUNDIALS IDA (`--features ida`) integrates the residual
/// form (λ as unknowns, with the same regularised pivots) and projects fewer step ends of an
/// approach (`projection::Spacing`: every projection restarts it at order 1); the same
/// assertions hold, with the values measured for it quoted beside each bound.
fn check_dae(fixture: &str, loops: usize, methods: &[Method]) {
    let model = load(fixture, &[]);
    let options = DaeOptions::default();
    for &method in methods {
        for rtol in [1e-6, 1e-8, 1e-10] {
            let case = format!("{fixture}, DAE, {method}, rtol {rtol:e}");
            let mut f = Dae::new(&model, &options).unwrap_or_else(|e| panic!("{case}: {e}"));
            let rec = run(&mut f, method, rtol).unwrap_or_else(|e| panic!("{case}: {e}"));
            let theta = col(&rec, "link0.phi");
            let exact = reference(loops, &rec.t, 1e-5);
            let n = passages(&theta);
            assert!(n >= 9, "{case}: only {n} flat positions passed");
            // Measured (2026-11-26) at 0.08–59 × rtol · max|θ| (the larger at rtol 1e-10,
            // where the ~1e-9 rad that each passage costs — the motion is free along the
            // near-null direction within ~1e-5 of the flat position, see `PIVOT_REGULARISATION`
            // — adds up over the ten passages of the chain): the bound of the generalised
            // formulation, 300 ×, leaves a factor 5. IDA, measured (2026-11-26): 3.4–122 ×
            // (the chain at rtol 1e-10 the larger: BDF's global error grows relative to rtol as
            // it tightens, `tests/ida.rs`, and each projection restarts it at order 1), a factor
            // 2.5. A passage onto the crossed branch or a lost passage is an O(1) error.
            assert_follows_pendulum(&case, &rec, &exact, rtol);
            // The parallelogram branch after every passage: every coupler keeps φ = 0 and every
            // link turns as link0, on each stretch between two passages of the reference. The
            // crossed branch turns the coupler by 0.82 rad; here the offsets are the DAE's drift,
            // measured (2026-11-26) ≤ 4.4e-7 rad (rtol 1e-6; IDA ≤ 5e-8): 1e-5 rad leaves a
            // factor 23.
            let flat = flat_positions(&exact);
            for k in 1..=loops {
                let coupler = col(&rec, &format!("coupler{k}.phi"));
                let link = col(&rec, &format!("link{k}.phi"));
                for (p, &start) in flat.iter().enumerate() {
                    let end = flat.get(p + 1).copied().unwrap_or(rec.len());
                    let off = (start..end).fold(0.0_f64, |m, i| {
                        m.max(coupler[i].abs()).max((link[i] - theta[i]).abs())
                    });
                    assert!(
                        off < 1e-5,
                        "{case}: after passage {} (t = {} s), coupler{k} or link{k} left the parallelogram branch by {off:e} rad",
                        p + 1,
                        rec.t[start]
                    );
                }
            }
            // Energy: measured (2026-11-26) at 1.2–63 × rtol · J θ̇₀² (Radau5 at 1e-10 the
            // larger; IDA 5.0–65 ×); bound 1000 × as for the generalised formulation.
            assert_energy_conserved(&case, &model, &rec, loops, rtol);
            check_reactions(&case, &rec, loops);
            // The DAE reports the passages (`Dae::singular_passages`: the smallest pivot ratio
            // of its multiplier solve, seen at a stage or fitted over the step ends of the
            // approach, below 1e-6, i.e. within ~1e-3 of the flat position), once each, within
            // 20 ms of the flat position. Steps of loose tolerances stride over the approach
            // with too few points for the fit (measured 2026-11-26: DOP853 at rtol 1e-6 reports
            // 1 of 9 for the parallelogram and 0 of 10 for the chain; at rtol 1e-8, 2 of 9 and
            // 4 of 10; Radau5 at 1e-8, 6 of 9 and 10 of 10; IDA at 1e-6, 8 of 9 and 10 of 10),
            // so all are required at rtol 1e-10
            // and none too many otherwise: a lower bound, not a count to rely on.
            let reported = f.singular_passages();
            let flat_times: Vec<f64> = flat.iter().map(|&i| rec.t[i]).collect();
            assert!(
                if rtol <= 1e-10 {
                    reported.len() == flat.len()
                } else {
                    reported.len() <= flat.len()
                },
                "{case}: passages reported at {reported:?}, flat positions at {flat_times:?}"
            );
            for &tp in &reported {
                let nearest = flat_times
                    .iter()
                    .fold(f64::INFINITY, |m, tf| m.min((tp - tf).abs()));
                assert!(
                    nearest < 2e-2,
                    "{case}: passage reported at t = {tp} s, {nearest} s from the nearest flat position ({flat_times:?})"
                );
            }
        }
    }
}

/// A regular linkage reports no singular passage: the reference four-bar with its clearance
/// joint (its smallest pivot ratio over two turns, measured 2026-11-25, is 6.1e-2, against the
/// passage level 1e-6), and the generalised formulation never reports one (it keeps the branch
/// by construction).
#[test]
fn regular_runs_report_no_singular_passage() {
    use linkdyn::simulation::{Simulation, SimulationOptions};
    let model = load("models/farahan2016.toml", &[]);
    let sim = Simulation::new(&model, SimulationOptions::default().revs(2.0).dt(1e-3))
        .unwrap_or_else(|e| panic!("{e}"));
    let result = sim.run_to_memory().unwrap_or_else(|e| panic!("{e}"));
    assert!(
        result.summary.singular_passages.is_empty(),
        "farahan2016: {:?}",
        result.summary.singular_passages
    );
    let model = load("tests/fixtures/parallelogram.toml", &[]);
    let mut g = Generalized::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    run(&mut g, Method::Dop853, 1e-8).unwrap_or_else(|e| panic!("{e}"));
    assert!(g.singular_passages().is_empty());
}

/// Joint reactions through the passages. The sum of the ground reactions is unique at every
/// position (Newton's law for the whole linkage: Σ F_O = Σ m (a − g), with a the couplers'
/// acceleration and a/2 the links'), and is checked at every sample. How it splits between
/// the joints is unique too away from the flat positions — for the single parallelogram the
/// symmetric split of [`parallelogram_reactions`], checked where |sin θ| > 0.05 (3° from flat)
/// — but not at a flat position, where a self-stress (equal and opposite forces along the
/// collinear links and couplers, zero in the sum) can be added: there the DAE's split carries
/// one of the order of (constraint drift)/|sin θ|, bounded by the regularised pivots, and is
/// only checked to be finite. All at the DAE's own state (θ, θ̇), so that only the force
/// computation is tested. The peak total ground reaction is 212 N (one loop) and 559 N (three);
/// measured errors (2026-11-26) ≤ 8e-3 N for the sum and the split: bound 0.1 % of the peak.
fn check_reactions(case: &str, rec: &Recorder, loops: usize) {
    let theta = col(rec, "link0.phi");
    let omega = col(rec, "link0.omega");
    let (j, g) = pendulum(loops);
    let ground: Vec<(Vec<f64>, Vec<f64>)> = (0..=loops)
        .map(|k| (col(rec, &format!("O{k}.fx")), col(rec, &format!("O{k}.fy"))))
        .collect();
    let single = (loops == 1).then(|| {
        (
            col(rec, "A1.fx"),
            col(rec, "A1.fy"),
            col(rec, "O0.fx"),
            col(rec, "O0.fy"),
        )
    });
    let links = (loops + 1) as f64 * M_LINK;
    let couplers = loops as f64 * M_COUPLER;
    let mut peak = 0.0_f64;
    let mut worst = (0.0_f64, 0.0);
    for i in 0..rec.len() {
        let (s, c) = theta[i].sin_cos();
        let (w, alpha) = (omega[i], -g / j * theta[i].cos());
        let a = [L * (-s * alpha - c * w * w), L * (c * alpha - s * w * w)];
        let total = [
            (0.5 * links + couplers) * a[0],
            (0.5 * links + couplers) * a[1] + (links + couplers) * G,
        ];
        let sum = ground
            .iter()
            .fold([0.0, 0.0], |m, (fx, fy)| [m[0] + fx[i], m[1] + fy[i]]);
        let mut e = (sum[0] - total[0]).abs().max((sum[1] - total[1]).abs());
        peak = peak.max(total[0].hypot(total[1]));
        match &single {
            Some((ax, ay, ox, oy)) if s.abs() > 0.05 => {
                let (fa, fo) = parallelogram_reactions(theta[i], w);
                e = e
                    .max((ax[i] - fa[0]).abs())
                    .max((ay[i] - fa[1]).abs())
                    .max((ox[i] - fo[0]).abs())
                    .max((oy[i] - fo[1]).abs());
            }
            Some((ax, ay, ox, oy)) => {
                let finite = [ax[i], ay[i], ox[i], oy[i]].iter().all(|f| f.is_finite());
                assert!(
                    finite,
                    "{case}: a reaction is not finite at t = {} s",
                    rec.t[i]
                );
            }
            None => {}
        }
        let finite = ground
            .iter()
            .all(|(fx, fy)| fx[i].is_finite() && fy[i].is_finite());
        assert!(
            finite,
            "{case}: a ground reaction is not finite at t = {} s",
            rec.t[i]
        );
        if e > worst.0 {
            worst = (e, rec.t[i]);
        }
    }
    assert!(
        worst.0 < 1e-3 * peak,
        "{case}: the reactions differ from the exact ones by {:e} N at t = {} s, bound {:e} N",
        worst.0,
        worst.1,
        1e-3 * peak
    );
}

#[test]
fn dae_passes_the_flat_positions_of_a_parallelogram() {
    check_dae(
        "tests/fixtures/parallelogram.toml",
        1,
        &[Method::Dop853, Method::Radau5],
    );
}

#[test]
fn dae_passes_the_flat_positions_of_a_chain_of_three_parallelograms() {
    check_dae(
        "tests/fixtures/parallelogram_chain3.toml",
        3,
        &[Method::Dop853, Method::Radau5],
    );
}

/// IDA on the DAE's residual form through the same passages.
#[cfg(feature = "ida")]
#[test]
fn ida_passes_the_flat_positions_of_a_parallelogram() {
    check_dae("tests/fixtures/parallelogram.toml", 1, &[Method::Ida]);
}

#[cfg(feature = "ida")]
#[test]
fn ida_passes_the_flat_positions_of_a_chain_of_three_parallelograms() {
    check_dae(
        "tests/fixtures/parallelogram_chain3.toml",
        3,
        &[Method::Ida],
    );
}

/// `linkdyn run` says when the DAE passed singular positions, how many, and what that means
/// for the results (the joint reactions there are not unique).
#[test]
fn the_cli_warns_when_the_dae_passed_singular_positions() {
    let dir = scratch("notes");
    let out = dir.join("run.csv");
    let (code, _, stderr) = linkdyn(&[
        "run",
        "tests/fixtures/parallelogram.toml",
        "--t-end",
        "1.0",
        "--rtol",
        "1e-10",
        "--out",
        path_arg(&out),
    ]);
    assert_eq!(code, 0, "{stderr}");
    // Flat positions of the exact motion before t = 1 s: 3 (from `reference`).
    let ts: Vec<f64> = (0..=1000).map(|k| 1e-3 * k as f64).collect();
    let flats = passages(&reference(1, &ts, 1e-5));
    let prefix = "note: the DAE passed at least ";
    let count: usize = stderr
        .split_once(prefix)
        .and_then(|(_, rest)| rest.split_once(' '))
        .and_then(|(n, _)| n.parse().ok())
        .unwrap_or_else(|| panic!("no {prefix:?} in: {stderr}"));
    // A lower bound (see `check_dae`): this run, measured 2026-11-26, reports 1 of 3.
    assert!(
        (1..=flats).contains(&count),
        "{count} of {flats} passages reported: {stderr}"
    );
    assert!(
        stderr.contains("singular position(s) of the linkage (the first at t = "),
        "{stderr}"
    );
    assert!(
        stderr.contains("the joint reactions there are not unique"),
        "{stderr}"
    );
    // The generalised formulation needs no such warning.
    let (code, _, stderr) = linkdyn(&[
        "run",
        "tests/fixtures/parallelogram.toml",
        "--t-end",
        "1.0",
        "--rtol",
        "1e-6",
        "--formulation",
        "generalized",
        "--out",
        path_arg(&out),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(!stderr.contains("the DAE passed"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The output grid does not change the run. The right-hand sides evaluated for output samples
/// (reactions, and DOP853's dense output, which calls f) must not count towards the projection
/// near singular positions (`StepHooks::begin_step`): before that rule, sampling every 1 ms
/// instead of every 0.25 s moved the chain's state by 2e-9 rad by t = 0.5 s. Chain of three,
/// DOP853 at rtol 1e-8, 3.5 s: the same steps, the same projections and bit-identical samples
/// at the common times.
#[test]
fn the_output_grid_does_not_change_a_dae_run_through_singular_positions() {
    check_output_grid(Method::Dop853);
}

/// The same for IDA, whose residuals count as the stages (`StepHooks::residual_stages`).
#[cfg(feature = "ida")]
#[test]
fn the_output_grid_does_not_change_an_ida_run_through_singular_positions() {
    check_output_grid(Method::Ida);
}

fn check_output_grid(method: Method) {
    let model = load("tests/fixtures/parallelogram_chain3.toml", &[]);
    let options = SolverOptions::default()
        .method(method)
        .rtol(1e-8)
        .atol(1e-10)
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let mut runs = Vec::new();
    for dt in [1e-3, 0.25] {
        let mut f = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        let y0 = f.initial_state();
        let mut rec = Recorder::new(&f);
        let stats = integrate(&mut f, 0.0, &y0, T_END, dt, &options, &mut rec)
            .unwrap_or_else(|e| panic!("dt {dt}: {e}"));
        runs.push((rec, stats.steps, f.projections()));
    }
    let (fine, coarse) = (&runs[0], &runs[1]);
    assert!(fine.2 > 0, "no projection: the test does not test the rule");
    assert_eq!((fine.1, fine.2), (coarse.1, coarse.2), "steps, projections");
    let width = fine.0.names.len();
    for (k, &t) in coarse.0.t.iter().enumerate() {
        let i = fine
            .0
            .t
            .iter()
            .position(|&s| s == t)
            .unwrap_or_else(|| panic!("no fine sample at t = {t}"));
        assert_eq!(
            fine.0.values[i * width..(i + 1) * width],
            coarse.0.values[k * width..(k + 1) * width],
            "samples at t = {t} s differ"
        );
    }
}
