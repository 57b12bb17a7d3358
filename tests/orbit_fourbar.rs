//! Periodic orbits of the reference four-bar (Farahan et al. 2016, Table 1, `models/
//! farahan2016.toml`) at 3500 rpm with a radial clearance of 0.44 mm, by shooting
//! (docs/periodic_orbits.md):
//!
//! * the period-1 orbit equals the long-run Poincaré fixed point — the section once per crank
//!   turn after 150 turns of transient (`linkdyn poincare … --revs 300 --transient 250` gives
//!   rocker.phi = 1.4529894458 rad at rtol 1e-10) — to 1e-8 rad, and it is stable;
//! * its monodromy matrix (variational equations with saltation matrices) equals central
//!   differences of the period map at two tolerances, over a period with an impact and a
//!   separation, and over a stretch of free flight;
//! * Newton's method that runs out of iterations fails with the exact message and its
//!   residual history.
//!
//! Reference: S. B. Farahan, M. R. Ghazavi, S. Rahmanian, "Nonlinear dynamic analysis of a
//! four-bar mechanism having revolute joint with clearance", *Journal of Theoretical and
//! Applied Vibration and Acoustics* 2 (2016) 91–106 (Table 1; period-1 motion at small
//! clearances, Fig. 6a).

use linkdyn::analysis::AnalysisError;
use linkdyn::analysis::orbit::{OrbitOptions, periodic_orbit, shoot};
use linkdyn::formulation::{Crossing, Formulation, ReducedLagrangian};
use linkdyn::simulation::analyses::{self, SectionSpec};
use linkdyn::simulation::{Discard, FormulationKind, Simulation, SimulationOptions};
use linkdyn::solve::{Method, SolverOptions, Stepper, Stop};
use linkdyn::studies::orbit::{OrbitPeriod, OrbitRequest, orbit};

const SETS: [&str; 2] = ["drivers.motor.speed_rpm=3500", "joints.B.clearance=0.44e-3"];
const PERIOD: f64 = 60.0 / 3500.0;

fn model() -> linkdyn::model::Model {
    let sets: Vec<String> = SETS.iter().map(|s| s.to_string()).collect();
    linkdyn::model::load("models/farahan2016.toml".as_ref(), &sets)
        .unwrap_or_else(|e| panic!("{e}"))
}

fn solver(rtol: f64) -> SolverOptions {
    SolverOptions::default()
        .method(Method::Dop853)
        .rtol(rtol)
        .atol(rtol * 1e-2)
}

fn reduced() -> ReducedLagrangian {
    ReducedLagrangian::new(&model()).unwrap_or_else(|e| panic!("{e}"))
}

/// The state after `turns` crank turns from the model's initial state.
fn after(f: &mut ReducedLagrangian, turns: f64, rtol: f64) -> Vec<f64> {
    let (t0, y0) = (f.t0(), f.initial_state());
    let t1 = t0 + turns * PERIOD;
    let mut y = y0.clone();
    let mut s = Stepper::new(f, t0, &y0, t1, &solver(rtol)).unwrap_or_else(|e| panic!("{e}"));
    while s.step().unwrap_or_else(|e| panic!("{e}")) != Stop::EndReached {}
    s.interpolate(t1, &mut y).unwrap_or_else(|e| panic!("{e}"));
    y
}

#[test]
fn the_period_one_orbit_is_the_long_run_poincare_fixed_point_and_is_stable() {
    let options = SimulationOptions::default()
        .formulation(FormulationKind::Reduced)
        .solver(solver(1e-10));
    let request = OrbitRequest {
        options: options.clone(),
        period: OrbitPeriod::Turns(1),
        guess_from_turn: 3,
        dt: 1e-4,
    };
    let found = orbit(&model(), &request).unwrap_or_else(|e| panic!("{e}"));
    let rocker = found.state["rocker.phi"];

    // The long run: 150 turns of transient, then 20 section points at the same phase.
    let sim =
        Simulation::new(&model(), options.clone().revs(170.0)).unwrap_or_else(|e| panic!("{e}"));
    let spec = SectionSpec {
        turns: 170,
        transient: 150,
        phase: 0.0,
        observe: vec!["rocker.phi".into()],
    };
    let section = analyses::poincare(&sim, &spec).unwrap_or_else(|e| panic!("{e}"));
    let points: Vec<f64> = section.section.points.iter().map(|p| p[0]).collect();
    // The settled points repeat to ~1e-11 rad (16 ε at rtol 1e-10; module docs of
    // simulation::analyses): the orbit must sit among them to 1e-8 rad, the bound asked for.
    for p in &points {
        assert!(
            (rocker - p).abs() < 1e-8,
            "orbit rocker.phi = {rocker}, Poincaré point {p}"
        );
    }
    assert!(
        (rocker - 1.4529894458).abs() < 1e-8,
        "rocker.phi = {rocker}, reference run 1.4529894458"
    );
    assert!(found.stable, "{:?}", found.floquet_multipliers);
    assert!(found.spectral_radius < 1.0 && found.spectral_radius > 0.0);
    // One impact per turn (the impact log of the long run has one per turn too), the joint
    // in contact at the section: its stored velocity is an unknown, and its separation
    // within the period makes one multiplier a structural zero, removed as trivial.
    assert_eq!(found.impacts_per_period, 1);
    assert_eq!(found.trivial_multipliers, 1);
    assert_eq!(found.floquet_multipliers.len(), 4);
    // The smallest gap is the deepest penetration of the period, located inside its step: the
    // true peak penetration of the settled attractor's impacts in the long run's impact log
    // (measured: equal to 9e-13 m of 1.06e-4 m; sampled every 1e-4 s, 1.055e-4 m).
    let gap = found.min_gap_m.unwrap_or(f64::NAN);
    let sim = Simulation::new(&model(), options.revs(170.0)).unwrap_or_else(|e| panic!("{e}"));
    let summary = sim.run(&mut Discard).unwrap_or_else(|e| panic!("{e}"));
    // The deepest of the last ten impacts (the very last is cut short by the end of the run).
    let impacts = &summary.clearance_joints[0].impacts;
    let settled = impacts[impacts.len().saturating_sub(10)..]
        .iter()
        .max_by(|a, b| a.peak_penetration.total_cmp(&b.peak_penetration))
        .unwrap_or_else(|| panic!("the long run has impacts"));
    assert!(
        (gap + settled.peak_penetration).abs() <= 1e-7 * settled.peak_penetration,
        "smallest gap {gap}, the settled impacts' peak penetration {}",
        settled.peak_penetration
    );
    assert!(
        found.closing_error <= 1e3,
        "closing {}",
        found.closing_error
    );
    // One period sampled every 1e-4 s, from the section to its end.
    let (first, last) = (found.samples[0].0, found.samples[found.samples.len() - 1].0);
    assert_eq!(first, found.t_section_s);
    assert!(
        last <= first + PERIOD + 1e-12 && last > first + PERIOD - 1e-4,
        "{first} {last}"
    );
}

/// Largest |M_ij − D_ij| over the largest |D_ij|, D the central differences of the period map
/// over the controlled states and the stored impact velocity, entries scaled by the states'
/// scales (angles 1 rad, rates |ω|, stored velocity 0.01 m/s) so that they compare in one unit.
fn monodromy_error(t0: f64, y0: &[f64], t1: f64, rtol: f64, want_events: usize) -> f64 {
    let f = reduced();
    let time_scale = PERIOD / std::f64::consts::TAU;
    let shot =
        shoot(&f, t0, y0, t1, time_scale, &solver(rtol), "test").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(shot.events.len(), want_events, "{:?}", shot.events);
    let n = y0.len();
    let mut worst: f64 = 0.0;
    let mut largest: f64 = 0.0;
    for j in 0..n {
        // Steps: 1e-7 of the state's scale for the angles (1 rad) and rates (|ω| rad/s), 1e-5
        // m/s for the stored impact velocity (about 0.017 m/s). The contact is stiff
        // (∂θ̈/∂θ ≈ 8e8 1/s²): measured over a stretch of contact, steps of 1e-5 rad change the
        // differences by 30 % and 1e-6 rad by 1e-3, so the steps must be this small, and then
        // the integration's noise (rtol·|y|/step) allows tolerances of 1e-10 and below only.
        let h = if j == 4 {
            1e-5
        } else {
            1e-7 * [1.0, 1.0, 366.5, 366.5][j]
        };
        let end = |sign: f64| {
            let mut y = y0.to_vec();
            y[j] += sign * h;
            shoot(&f, t0, &y, t1, time_scale, &solver(rtol), "test")
                .unwrap_or_else(|e| panic!("{e}"))
                .y_end
        };
        let (up, down) = (end(1.0), end(-1.0));
        for i in 0..n {
            let d = (up[i] - down[i]) / (2.0 * h);
            // Rows scaled like the columns, so that all entries compare in one unit.
            let scale = [1.0, 1.0, 366.5, 366.5, 0.01];
            let (m, d) = (
                shot.monodromy[i * n + j] / scale[i] * scale[j],
                d / scale[i] * scale[j],
            );
            worst = worst.max((m - d).abs());
            largest = largest.max(d.abs());
        }
    }
    worst / largest
}

#[test]
fn the_monodromy_matrix_matches_finite_differences_with_and_without_contact() {
    let mut f = reduced();
    // On the settled motion: 20 turns in, the joint is in contact at the section.
    let y0 = after(&mut f, 20.0, 1e-10);
    let t0 = f.t0() + 20.0 * PERIOD;
    // One period: the separation and one impact (2 events; the friction kinks change nothing
    // and are not counted).
    let with_contact = [1e-10, 1e-12].map(|rtol| monodromy_error(t0, &y0, t0 + PERIOD, rtol, 2));
    // Find the free flight of that period: from just after the separation to just before
    // the impact.
    let shot = shoot(
        &f,
        t0,
        &y0,
        t0 + PERIOD,
        PERIOD / std::f64::consts::TAU,
        &solver(1e-10),
        "test",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let sep = shot
        .events
        .iter()
        .find(|e| e.2 == Crossing::Falling)
        .map(|e| e.0);
    let imp = shot
        .events
        .iter()
        .find(|e| e.2 == Crossing::Rising)
        .map(|e| e.0);
    let (Some(sep), Some(imp)) = (sep, imp) else {
        panic!(
            "a separation and an impact in the period: {:?}",
            shot.events
        );
    };
    assert!(sep < imp, "free flight between them: {sep} {imp}");
    let (a, b) = (sep + 0.1 * (imp - sep), imp - 0.1 * (imp - sep));
    let mut g = reduced();
    let ya = {
        let (t_start, y_start) = (g.t0(), g.initial_state());
        let mut y = y_start.clone();
        let mut s = Stepper::new(&mut g, t_start, &y_start, a, &solver(1e-10))
            .unwrap_or_else(|e| panic!("{e}"));
        while s.step().unwrap_or_else(|e| panic!("{e}")) != Stop::EndReached {}
        s.interpolate(a, &mut y).unwrap_or_else(|e| panic!("{e}"));
        y
    };
    let free = [1e-10, 1e-12].map(|rtol| monodromy_error(a, &ya, b, rtol, 0));
    // Free flight: the differences carry the integration's noise over the step (rtol/1e-7 of
    // the scale) plus the monodromy's own error; measured 1.7e-7 at both tolerances, bound
    // 1e-5. Over the contact the saltation's differences take steps of 1e-8, so their noise is
    // about rtol/1e-8 of the scale: 1e-2 at rtol 1e-10 and 1e-4 at 1e-12. Measured 1.3e-3 and
    // 1.6e-4 with the C library's sine, 7.2e-3 and 7.6e-5 with linkdyn's own (the last bits of
    // every evaluation moved), the largest in the stored-velocity row (before the saltation's
    // differences took steps of 1e-8 instead of 1e-5: 1.0e-2 and 1.1e-2, not shrinking with
    // the tolerance). Bounds 4 × that noise, 4e-2 and 4e-4, one per tolerance: the second
    // catches that step and an error that stops shrinking with the tolerance, both a wrong
    // saltation matrix (order 1 in its row).
    let bounds = [
        (with_contact, "impact and separation", [4e-2, 4e-4]),
        (free, "free flight", [1e-5, 1e-5]),
    ];
    eprintln!("relative error, rtol 1e-10 and 1e-12: contact {with_contact:?}, free {free:?}");
    for (errors, case, bound) in bounds {
        assert!(errors[0] < bound[0], "{case}, rtol 1e-10: {errors:?}");
        assert!(errors[1] < bound[1], "{case}, rtol 1e-12: {errors:?}");
    }
}

#[test]
fn newton_out_of_iterations_fails_with_its_residual_history() {
    let mut f = reduced();
    let listed = |h: &[f64]| {
        let l: Vec<String> = h.iter().map(|r| format!("{r:.3e}")).collect();
        l.join(", ")
    };
    // From 3 turns in, one iteration only: not enough.
    let guess = after(&mut f, 3.0, 1e-8);
    let options = OrbitOptions {
        max_iterations: 1,
        ..OrbitOptions::new(PERIOD)
    };
    let e = periodic_orbit(&f, f.t0() + 3.0 * PERIOD, &guess, &options, &solver(1e-8)).err();
    let Some(AnalysisError::NoConvergence { history, .. }) = &e else {
        panic!("expected no convergence, got {e:?}");
    };
    assert_eq!(history.len(), 2, "the guess and one iterate: {history:?}");
    assert!(history[1] < history[0], "Newton improves: {history:?}");
    assert_eq!(
        e.as_ref().map(ToString::to_string).unwrap_or_default(),
        format!(
            "periodic orbit: no periodic orbit found: Newton's method did not converge in 1 iteration; residual max|P(x) - x| by iteration, in units of the integration tolerance: {}",
            listed(history)
        )
    );
    // From the initial state (the journal centred, the transient ahead): the period map is
    // so far from linear there that no halving of the first Newton step lowers the residual.
    let e = periodic_orbit(
        &f,
        f.t0(),
        &f.initial_state(),
        &OrbitOptions::new(PERIOD),
        &solver(1e-8),
    )
    .err();
    let Some(AnalysisError::NoConvergence { history, .. }) = &e else {
        panic!("expected no convergence, got {e:?}");
    };
    assert_eq!(
        e.as_ref().map(ToString::to_string).unwrap_or_default(),
        format!(
            "periodic orbit: no periodic orbit found: a Newton step halved 8 times still raises the residual; residual max|P(x) - x| by iteration, in units of the integration tolerance: {}",
            listed(history)
        )
    );
}
