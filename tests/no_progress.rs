//! Claims: a run that makes no progress stops within a window of 1000 step attempts
//! with a message giving the time, the step size and the cause — "stiff, use an implicit
//! method" when the method's stiffness test fired, "the step size collapsed" otherwise; a run
//! that outlives `max_wall` stops with the time reached and the rate; and the rule never comes
//! near healthy contact-rich runs (the reference four-bar at 250 and 3500 rpm). And a
//! stall at a singular position ends the message with the constraint rows that lose their
//! independence there (`src/formulation/diagnosis.rs`).

use linkdyn::formulation::{
    Dae, DaeOptions, Formulation, FormulationError, Generalized, NoStepHooks, ReducedLagrangian,
};
use linkdyn::solve::{Method, SolveError, SolverOptions, Stepper, Stop};

/// Runs a stepper to the end and returns the error it stopped with.
fn failure<F: Formulation>(f: &mut F, t_end: f64, opts: &SolverOptions) -> SolveError {
    let y0 = f.initial_state();
    let result = Stepper::new(f, 0.0, &y0, t_end, opts).and_then(|mut s| {
        while s.step()? != Stop::EndReached {}
        Ok(s.stats().clone())
    });
    match result {
        Ok(stats) => panic!("expected a failure, the run finished: {stats:?}"),
        Err(e) => e,
    }
}

/// y' = 1 with a formulation that allows steps of 1e-11 s only (a step guard gone wrong).
struct Crawling;

impl NoStepHooks for Crawling {}

impl Formulation for Crawling {
    fn n_states(&self) -> usize {
        1
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![0.0]
    }
    fn rhs(&self, _t: f64, _y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        dy[0] = 1.0;
        Ok(())
    }
    fn max_step(&self, _t: f64, _y: &[f64]) -> f64 {
        1e-11
    }
}

#[test]
fn a_collapsed_step_size_stops_the_run_within_the_window() {
    for method in Method::ALL {
        let err = failure(&mut Crawling, 1.0, &SolverOptions::default().method(method));
        // 1000 attempts of 1e-11 s: t = 1e-8 s; 1000·(1 − 1e-8)/1e-8 ≈ 1e11 attempts to go,
        // more than 100 × the 1e7 left of max_steps.
        assert_eq!(
            err.to_string(),
            "no progress at t = 0.000000010 s: the last 1000 step attempts advanced t by 1.000e-8 s (mean step 1.000e-11 s); reaching t_end at this pace needs about 1.0e11 more attempts, max_steps allows 1.0e7. The step size collapsed: the solution is (nearly) discontinuous here (a singular position of the linkage such as a toggle, a discontinuous force) or events pile up (chattering, a Zeno sequence of impacts); check the model",
            "{method}"
        );
    }
}

/// y' = 1 with steps of at most 1e-6 s: a steady pace, 1e6 attempts per simulated second.
struct Steady;

impl NoStepHooks for Steady {}

impl Formulation for Steady {
    fn n_states(&self) -> usize {
        1
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![0.0]
    }
    fn rhs(&self, _t: f64, _y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        dy[0] = 1.0;
        Ok(())
    }
    fn max_step(&self, _t: f64, _y: &[f64]) -> f64 {
        1e-6
    }
}

/// The sustained-pace stop of `Steady` over `t_end` with `max_steps`: (t reached, projected
/// attempts, budget left), after checking the message's cause.
fn steady_stop(method: Method, t_end: f64, max_steps: u64) -> (f64, f64, f64) {
    let opts = SolverOptions::default().method(method).max_steps(max_steps);
    let err = failure(&mut Steady, t_end, &opts);
    let SolveError::NoProgress {
        t,
        attempts,
        projected,
        budget,
        ..
    } = err
    else {
        panic!("{method}: expected NoProgress, got {err}");
    };
    assert_eq!(attempts, 10_000, "{method}");
    let message = err.to_string();
    assert!(
        message.ends_with("The step size has stayed this small for 10000 attempts: something keeps it there (a long contact phase, a stiff element, a step guard); raise --max-steps if the run must go on"),
        "{method}: {message}"
    );
    (t, projected, budget)
}

#[test]
fn a_steady_pace_beyond_the_budget_stops_at_a_tenth_of_it() {
    // 5e8 attempts for 500 s: fifty times the 1e7 of max_steps, under the hundred times of the
    // collapse rule, which let it run until the budget left fell under 5e6 (5e6 attempts, all
    // to end in an error). Now it stops once a tenth of the budget is spent: at attempt 1e6,
    // t ≈ 1 s.
    for method in Method::ALL {
        let (t, projected, budget) = steady_stop(method, 500.0, 10_000_000);
        // The first steps may be shorter than 1e-6 s (the initial step heuristic, then growth
        // by at most 8× a step for Radau5): t within ten steps of 1 s.
        assert!((t - 1.0).abs() <= 1e-5, "{method}: t = {t}");
        assert!(
            projected > budget && projected < 100.0 * budget,
            "{method}: projected {projected:e}, budget {budget:e}"
        );
    }
    // 5e4 attempts for 50 ms against max_steps = 20 000: 2.5 times the budget. A tenth of it
    // (2000 attempts) is spent before the window of 10 000 is full, so the run stops as soon
    // as the window is full, at attempt 10 001, t ≈ 1e-2 s; before, it ran into TooManySteps at
    // attempt 20 000.
    for method in Method::ALL {
        let (t, projected, budget) = steady_stop(method, 0.05, 20_000);
        assert!((t - 1e-2).abs() <= 1e-5, "{method}: t = {t}");
        assert!(
            projected > budget && projected < 100.0 * budget,
            "{method}: projected {projected:e}, budget {budget:e}"
        );
    }
}

/// y' = −λ (y − cos t), λ = 1e9 s⁻¹: y follows cos t, but an explicit method must keep
/// hλ inside its stability region (h ≲ 6e-9 s): some 1e10 steps for 100 s.
struct Stiff;

impl NoStepHooks for Stiff {}

impl Formulation for Stiff {
    fn n_states(&self) -> usize {
        1
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![1.0]
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        dy[0] = -1e9 * (y[0] - t.cos());
        Ok(())
    }
}

#[test]
fn a_stiff_problem_is_called_stiff_and_an_implicit_method_is_suggested() {
    // The explicit methods: the implicit Radau5 solves this problem (in about 11 steps).
    for method in Method::ALL.into_iter().filter(|m| !m.is_implicit()) {
        let err = failure(&mut Stiff, 100.0, &SolverOptions::default().method(method));
        let SolveError::NoProgress {
            t,
            h,
            advance,
            attempts,
            projected,
            budget,
            stiff,
            ref implicit,
            ref diagnosis,
        } = err
        else {
            panic!("{method}: expected NoProgress, got {err}");
        };
        assert!(stiff, "{method}: the stiffness test did not fire ({err})");
        // A formulation without constraints has nothing to add.
        assert_eq!(diagnosis, &None, "{method}");
        assert_eq!(attempts, 1000, "{method}");
        // The step sits at the stability limit, hλ of the order of the boundary of the
        // stability region (3.3 for DOPRI5, 6.1 for DOP853), far below what accuracy asks for
        // y ≈ cos t at rtol 1e-8 (~1e-2 s).
        assert!(
            (1.0..10.0).contains(&(h * 1e9)),
            "{method}: mean step {h:.3e} s, hλ = {}",
            h * 1e9
        );
        let advice = if implicit.is_empty() {
            "an implicit method (none is built into this version)".to_string()
        } else {
            format!("an implicit method (--method {implicit})")
        };
        assert_eq!(
            err.to_string(),
            format!(
                "no progress at t = {t:.9} s: the last 1000 step attempts advanced t by {advance:.3e} s (mean step {h:.3e} s); reaching t_end at this pace needs about {projected:.1e} more attempts, max_steps allows {budget:.1e}. The step size is limited by stability, not accuracy: the problem is stiff here (e.g. a long contact phase). Use {advice}; loosening rtol/atol will not help"
            ),
            "{method}"
        );
    }
}

/// y' = 1, each RHS call sleeping 200 µs: a slow formulation.
struct Slow;

impl NoStepHooks for Slow {}

impl Formulation for Slow {
    fn n_states(&self) -> usize {
        1
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![0.0]
    }
    fn rhs(&self, _t: f64, _y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        std::thread::sleep(std::time::Duration::from_micros(200));
        dy[0] = 1.0;
        Ok(())
    }
}

#[test]
fn max_wall_bounds_the_run_and_says_how_far_it_got() {
    // Steps of at most 1e-3 s over 1000 s: far more than 20 ms of work.
    let opts = SolverOptions::default().h_max(1e-3).max_wall(0.02);
    let err = failure(&mut Slow, 1000.0, &opts);
    let SolveError::WallTimeExceeded {
        t,
        t_end,
        wall_s,
        limit_s,
        rate,
    } = err
    else {
        panic!("expected WallTimeExceeded, got {err}");
    };
    assert_eq!((t_end, limit_s), (1000.0, 0.02));
    assert!(wall_s > limit_s && t > 0.0, "t = {t}, wall {wall_s} s");
    // The rate is the simulated time per wall-clock second, by definition.
    assert_eq!(rate, t / wall_s);
    assert_eq!(
        err.to_string(),
        format!(
            "stopped after {wall_s:.3} s of wall-clock time (limit max_wall = 0.02 s) at t = {t:.9} s of t_end = 1000 s, simulating {rate:.3e} s per wall-clock second"
        )
    );
}

/// The factor of the rule in `src/solve/progress.rs`.
const STALL_FACTOR: f64 = 100.0;

/// The rules' quantities for a run, reconstructed from the stepper: the largest
/// projected/(100·budget) over all windows of 1000 attempts, and the largest projected/budget
/// over all windows of 10 000 attempts (1 would stop the run).
fn worst_stall_ratio<F: Formulation>(f: &mut F, t_end: f64, opts: &SolverOptions) -> (f64, f64) {
    let y0 = f.initial_state();
    let mut s = Stepper::new(f, 0.0, &y0, t_end, opts).unwrap_or_else(|e| panic!("{e}"));
    // Start time of every attempt: all attempts of one `step` call start at the same t.
    let mut starts: Vec<f64> = Vec::new();
    loop {
        let (t, before) = (s.t(), s.stats().steps + s.stats().rejected);
        let stop = s.step().unwrap_or_else(|e| panic!("{e}"));
        let after = s.stats().steps + s.stats().rejected;
        starts.extend(std::iter::repeat_n(t, (after - before) as usize));
        if stop == Stop::EndReached {
            break;
        }
    }
    let max_steps = opts.max_steps as f64;
    let worst = |w: usize, factor: f64| {
        (w..starts.len())
            .map(|a| {
                let advance = starts[a] - starts[a - w];
                let projected = w as f64 * (t_end - starts[a]) / advance;
                projected / (factor * (max_steps - a as f64))
            })
            .fold(0.0, f64::max)
    };
    (worst(1000, STALL_FACTOR), worst(10_000, 1.0))
}

#[test]
fn healthy_contact_runs_stay_far_from_the_threshold() {
    let mut worst: f64 = 0.0;
    let mut worst_sustained: f64 = 0.0;
    for rpm in [250.0, 3500.0] {
        let model = linkdyn::model::load(
            "models/farahan2016.toml".as_ref(),
            &[format!("drivers.motor.speed_rpm={rpm}")],
        )
        .unwrap_or_else(|e| panic!("{e}"));
        let t_end = 2.0 * 60.0 / rpm;
        for method in Method::ALL {
            for (rtol, atol) in [(1e-6, 1e-9), (1e-9, 1e-12)] {
                let opts = SolverOptions::default()
                    .method(method)
                    .rtol(rtol)
                    .atol(atol);
                let mut dae =
                    Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
                let mut reduced = ReducedLagrangian::new(&model).unwrap_or_else(|e| panic!("{e}"));
                for (name, (ratio, sustained)) in [
                    ("dae", worst_stall_ratio(&mut dae, t_end, &opts)),
                    ("reduced", worst_stall_ratio(&mut reduced, t_end, &opts)),
                ] {
                    println!(
                        "{rpm} rpm, {name}, {method}, rtol {rtol:.0e}: {ratio:.3e}, sustained {sustained:.3e}"
                    );
                    // 1 stops the run; 0.01 leaves a factor 100 for harder cases of the model
                    // (measured worst: 1.1e-3).
                    assert!(
                        ratio < 0.01,
                        "{rpm} rpm, {name}, {method}, rtol {rtol:.0e}: ratio {ratio:.3e}"
                    );
                    // The sustained-pace rule: windows of 10 000 attempts against the budget
                    // itself (factor 1, not 100); 0.1 leaves a factor 10 for harder cases
                    // (measured worst: 2.8e-3, reduced DOPRI5 rtol 1e-9 at 250 rpm).
                    assert!(
                        sustained < 0.1,
                        "{rpm} rpm, {name}, {method}, rtol {rtol:.0e}: sustained {sustained:.3e}"
                    );
                    worst = worst.max(ratio);
                    worst_sustained = worst_sustained.max(sustained);
                }
            }
        }
    }
    println!(
        "worst projected/(100·budget) over the reference runs: {worst:.3e}, sustained projected/budget: {worst_sustained:.3e}"
    );
}

/// The reference four-bar with a crank of 0.4 m: at θ2 = π all four links lie on the ground
/// line (0.4 + 0.8 = 0.75 + 0.45, a change point), where the constraint Jacobian loses rank and
/// two assembly branches cross.
fn toggle() -> linkdyn::model::Model {
    linkdyn::model::load(
        "models/fourbar_ideal.toml".as_ref(),
        &[
            "bodies.crank.points.A=[0.2,0.0]".to_string(),
            "bodies.crank.points.O2=[-0.2,0.0]".to_string(),
            "bodies.crank.initial.x=0.2".to_string(),
        ],
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

/// The reference four-bar with a crank of 0.45 m: the loop closes only while the crank tip A is
/// within reach of the stretched coupler and rocker, |O4 A| ≤ 0.75 + 0.45 = 1.2 m, i.e.
/// 0.8425 − 0.72 cos θ2 ≤ 1.44, θ2 ≤ 2.550 rad (t = 0.0974 s at 250 rpm). There the driver
/// would carry the crank on, where no position of the coupler and rocker closes the loop: a
/// true lock, which no solve of the multipliers can pass.
fn lock() -> linkdyn::model::Model {
    linkdyn::model::load(
        "models/fourbar_ideal.toml".as_ref(),
        &[
            "bodies.crank.points.A=[0.225,0.0]".to_string(),
            "bodies.crank.points.O2=[-0.225,0.0]".to_string(),
            "bodies.crank.initial.x=0.225".to_string(),
        ],
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

/// The diagnosis of a stall, split at its one number: σ_min/σ_max.
fn split_ratio(message: &str) -> (&str, f64, &str) {
    let key = "(σ_min/σ_max = ";
    let Some(at) = message.find(key) else {
        panic!("no singular-value ratio in: {message}");
    };
    let (head, rest) = message.split_at(at + key.len());
    let end = rest.find(' ').unwrap_or(rest.len());
    let ratio = rest[..end]
        .parse()
        .unwrap_or_else(|e| panic!("{e}: {message}"));
    (head, ratio, &rest[end..])
}

/// The two positions of the rocker of the 0.4 m-crank four-bar at crank angle θ2 (rad): B where
/// the circles (A, 0.75 m) and (O4, 0.45 m) meet, on either side of the line A → O4.
fn rocker_roots(theta2: f64) -> [f64; 2] {
    let (l1, l2, l3, l4) = (0.8, 0.4, 0.75, 0.45);
    let a = [l2 * theta2.cos(), l2 * theta2.sin()];
    let d = [l1 - a[0], -a[1]];
    let dist = d[0].hypot(d[1]);
    let along = (l3 * l3 - l4 * l4 + dist * dist) / (2.0 * dist);
    let h = (l3 * l3 - along * along).max(0.0).sqrt();
    let u = [d[0] / dist, d[1] / dist];
    [1.0, -1.0].map(|side| {
        let b = [
            a[0] + along * u[0] - side * h * u[1],
            a[1] + along * u[1] + side * h * u[0],
        ];
        b[1].atan2(b[0] - l1)
    })
}

/// The DAE goes through the change point of the 0.4 m crank (its regularised multiplier solve
/// and the projection near singular positions, `src/formulation/dae.rs`): no stall, and the
/// passage reported at θ2 = π, t = π/ω = 0.12 s. Two branches cross there, with different
/// rocker rates (24.7 and −7.2 rad/s); the motion continues on the one its rate leads to (the
/// rocker turns on at 24.7 rad/s), moving from one root of the loop closure to the other. A switch onto the other branch would show as a jump
/// of the rocker's rate. The generalised formulation follows the same branch. Only a true lock
/// (below) stalls the DAE.
#[test]
fn the_dae_and_generalized_pass_the_change_point_of_a_toggle() {
    use linkdyn::formulation::Outputs;
    use linkdyn::solve::{Recorder, integrate};
    let model = toggle();
    let mut dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let y0 = dae.initial_state();
    let mut rec = Recorder::new(&dae);
    let stats = integrate(
        &mut dae,
        0.0,
        &y0,
        0.24,
        1e-4,
        &SolverOptions::default(),
        &mut rec,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let passages = dae.singular_passages();
    assert_eq!(passages.len(), 1, "{passages:?} ({stats:?})");
    assert!(
        (passages[0] - 0.12).abs() < 1e-3,
        "passage at t = {} s, change point at 0.12 s",
        passages[0]
    );
    // The violation bound at the default tolerances (rtol 1e-6, atol 1e-9, L ≈ 0.8 m) is
    // 8e-5 m; the run stays within 1e-6 m (measured 2026-11-26: 2.9e-9 m).
    let violation = dae.step_constraint_violation();
    assert!(violation < 1e-6, "|Φ| reached {violation:e}");
    let column = |name: &str| {
        rec.column(name)
            .unwrap_or_else(|| panic!("no column {name}"))
    };
    let (crank, rocker, rate) = (
        column("crank.phi"),
        column("rocker.phi"),
        column("rocker.omega"),
    );
    let wrap = |x: f64| {
        (x + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
    };
    let mut roots_used = [false; 2];
    for i in 0..rec.len() {
        // On the configuration set at every sample: one of the two roots.
        let off = rocker_roots(crank[i]).map(|r| wrap(rocker[i] - r).abs());
        let nearest = usize::from(off[1] < off[0]);
        assert!(
            off[nearest] < 1e-6,
            "t = {} s: rocker {} rad is off both roots by {off:?}",
            rec.t[i],
            rocker[i]
        );
        if (rec.t[i] - 0.12).abs() > 1e-3 {
            roots_used[nearest] = true;
        }
        // The rate is continuous: the rocker's angular acceleration stays below 2 600 rad/s²
        // (measured 2026-11-26), so 0.1 ms apart the rate moves by < 0.26 rad/s; the other
        // branch's rate at the change point differs by 32 rad/s.
        if i > 0 {
            let jump = (rate[i] - rate[i - 1]).abs();
            assert!(
                jump < 0.5,
                "t = {} s: rocker rate jumps by {jump} rad/s",
                rec.t[i]
            );
        }
    }
    assert_eq!(
        roots_used,
        [true, true],
        "the motion went from one root to the other"
    );
    // The generalised formulation (no independent coordinate in this fully driven linkage: all
    // its states are bookkeeping, so all are error-controlled) goes through too, on the same
    // branch. Samples within 1 ms of the change point are not compared.
    let mut g = Generalized::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let y0 = g.initial_state();
    let mut grec = Recorder::new(&g);
    integrate(
        &mut g,
        0.0,
        &y0,
        0.24,
        1e-4,
        &SolverOptions::default(),
        &mut grec,
    )
    .unwrap_or_else(|e| panic!("generalized: {e}"));
    let g_rocker = grec
        .column("rocker.phi")
        .unwrap_or_else(|| panic!("no rocker.phi"));
    let worst = (0..rec.len())
        .filter(|&i| (rec.t[i] - 0.12).abs() > 1e-3)
        .fold(0.0_f64, |m, i| m.max(wrap(rocker[i] - g_rocker[i]).abs()));
    // Measured 2026-11-26: 9.3e-9 rad at the default tolerances (rtol 1e-6); the other branch
    // is O(1) rad away.
    assert!(
        worst < 1e-6,
        "generalized and DAE rocker differ by {worst:e} rad"
    );
}

/// A true lock, where no motion can go on, stops the DAE at the lock, although its multiplier
/// solve is regularised (`src/formulation/dae.rs`; it goes through the flat positions of a
/// parallelogram, `tests/singular_parallelogram.rs`, and of long chains of them,
/// `tests/nfourbar_chain.rs`): the driver cannot be followed any more, its row is violated
/// beyond the bound at the lock, and the error names the rows that lost independence there.
#[test]
fn a_stop_at_a_lock_names_the_constraints_that_lose_independence() {
    let model = lock();
    let mut dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let err = failure(&mut dae, 0.24, &SolverOptions::default());
    let SolveError::Formulation { t, source } = err else {
        panic!("expected the driver's constraint violation, got {err:?}");
    };
    let message = source.to_string();
    let (head, ratio, tail) = split_ratio(&message);
    // At the lock coupler and rocker are stretched along n = (O4 − A)/|O4 − A| =
    // (0.979, −0.207): the loop closure along n, Σ_joints (n_x x-row + n_y y-row), no longer
    // constrains anything the other rows do not, with shares |n_x|/2 = 0.49 and
    // |n_y|/2 = 0.10 of the dependence. Below 1e-5 σ_min/σ_max says the rows are dependent to
    // the digits the message shows.
    let prefix = "constraint \"motor\" is violated by |Φ| = ";
    assert!(head.starts_with(prefix), "{message}");
    assert!(
        head.contains(&format!(
            "the motion no longer satisfies the joints; tighten rtol/atol, raise the Baumgarte factors, or check that the linkage can move as driven. At t = {t:.9} s: the constraint rows "
        )),
        "{message}"
    );
    // The four x rows share the dependence equally: their order among themselves is rounding.
    for row in ["O2.x", "A.x", "B.x", "O4.x"] {
        assert!(head.contains(&format!("\"{row}\" (0.49)")), "{message}");
    }
    assert!(
        head.ends_with(" and 3 more are nearly dependent: the linkage is at or near a singular position (σ_min/σ_max = "),
        "{message}"
    );
    // Measured 2026-11-27: 6.6e-5 where the violation stops the run, 1 µs before the lock.
    assert!(ratio < 1e-4, "σ_min/σ_max = {ratio:e} at the lock");
    assert_eq!(
        tail,
        " of the scaled constraint Jacobian; in parentheses each row's share |u_i| of the dependence)"
    );
    // The lock: |O4 A|² = 0.8425 − 0.72 cos θ2 reaches 1.2² at θ2 = 2.551 rad, t = 0.09739 s
    // at 250 rpm.
    let omega = 250.0 * std::f64::consts::TAU / 60.0;
    let t_lock = ((0.8425_f64 - 1.44) / 0.72).acos() / omega;
    assert!(
        (t - t_lock).abs() < 1e-6,
        "stopped at t = {t} s, lock at {t_lock} s"
    );
}

#[test]
fn the_generalized_diagnosis_names_the_ill_conditioned_partition_near_a_toggle() {
    // Integrated to just before the toggle, where the one dependent block left (the driver
    // makes the linkage rigid: no independent coordinate) loses rank with Φ_q itself.
    let model = toggle();
    let mut generalized = linkdyn::formulation::Generalized::new(&model, &DaeOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    let y0 = generalized.initial_state();
    let t_end = 0.12 - 1.5e-6;
    let y = {
        let mut s = Stepper::new(&mut generalized, 0.0, &y0, t_end, &SolverOptions::default())
            .unwrap_or_else(|e| panic!("{e}"));
        while s.step().unwrap_or_else(|e| panic!("{e}")) != Stop::EndReached {}
        s.y().to_vec()
    };
    let message = generalized
        .diagnose(t_end, &y)
        .unwrap_or_else(|| panic!("no diagnosis 1.5e-6 s before the toggle"));
    // The pivot ratio (≈ 1/cond of the dependent block) is of the order of σ_min/σ_max, far
    // below the 1e-3 that makes a block "ill-conditioned".
    let (head, _, tail) = split_ratio(&message);
    assert!(
        head.starts_with(
            "the coordinate partition is ill-conditioned (independent coordinates none: the drivers fix every coordinate; pivot ratio of the dependent block "
        ),
        "{message}"
    );
    assert!(
        head.ends_with("; the constraint rows \"O2.x\" (0.50), \"A.x\" (0.50), \"B.x\" (0.50), \"O4.x\" (0.50) are nearly dependent: the linkage is at or near a singular position (σ_min/σ_max = "),
        "{message}"
    );
    assert_eq!(
        tail,
        " of the scaled constraint Jacobian; in parentheses each row's share |u_i| of the dependence)"
    );
}
