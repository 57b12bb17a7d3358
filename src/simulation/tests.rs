//! The facade gives the numbers of a direct integration, refuses bad settings before any work,
//! and its incremental summary equals the summary computed from all the samples.

use super::impacts::{ContactPoint, ContactProbe};
use super::summary::SummaryBuilder;
use super::*;
use crate::contact::kinks;
use crate::formulation::Crossing;
use crate::solve::{Method, Recorder, SolveError};

fn load(path: &str, overrides: &[&str]) -> Model {
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    match crate::model::load(path.as_ref(), &overrides) {
        Ok(m) => m,
        Err(e) => panic!("{path}: {e}"),
    }
}

fn refusal(model: &Model, options: SimulationOptions) -> String {
    match Simulation::new(model, options) {
        Ok(_) => "accepted".to_string(),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bad_settings_are_refused_naming_the_option() {
    let fourbar = load("models/fourbar_ideal.toml", &[]);
    let pendulum = load("models/pendulum.toml", &[]);
    let still = load("models/fourbar_ideal.toml", &["drivers.motor.speed_rpm=0"]);
    let o = SimulationOptions::default;
    let cases = [
        (
            refusal(&pendulum, o()),
            "revs: counts turns of the single driver, but model \"pendulum\" has 0 drivers: give `t_end`",
        ),
        (
            refusal(&still, o()),
            "revs: driver \"motor\" has zero speed: give `t_end` instead",
        ),
        (
            refusal(&fourbar, o().revs(-1.0)),
            "revs: expected a positive, finite number of turns, got -1",
        ),
        (
            refusal(&fourbar, o().t_end(f64::INFINITY)),
            "t_end: expected a positive, finite end time, got inf s",
        ),
        (
            refusal(&fourbar, o().dt(0.0)),
            "dt: expected a positive time step, got 0",
        ),
        (
            refusal(
                &fourbar,
                o().formulation(FormulationKind::Reduced).energy(true),
            ),
            "energy: the energy bookkeeping is available for the DAE formulation only",
        ),
        (
            refusal(&fourbar, o().formulation(FormulationKind::Reduced)),
            "reduced formulation: needs exactly one clearance joint, between the coupler and the rocker; the model has 0",
        ),
    ];
    for (got, expected) in cases {
        assert_eq!(got, expected);
    }
    let rtol = refusal(&fourbar, o().solver(SolverOptions::default().rtol(-1.0)));
    assert!(rtol.starts_with("rtol: expected"), "{rtol}");
    // 1e5 s at 1e-4 s: 1e9 samples of the four-bar's columns, far above 1e9 values.
    let big = refusal(&fourbar, o().t_end(1e5));
    assert!(
        big.starts_with("dt: 1e-4 s over 1e5 s asks for 1.000e9 samples × ")
            && big.ends_with("at most 1e9 are allowed: raise `dt`"),
        "{big}"
    );
}

/// The samples of a direct integration, and the largest |Φ| over its accepted step ends.
fn direct_recorder(model: &Model, t_end: f64, dt: f64, energy: bool) -> (Recorder, f64) {
    let options = DaeOptions {
        energy,
        ..DaeOptions::default()
    };
    // The simulation's default solver (DOP853, rtol 1e-8) has the friction kinks as events.
    let mut dae = Dae::new(model, &options)
        .unwrap_or_else(|e| panic!("{e}"))
        .friction_kink_events(true);
    let y0 = dae.initial_state();
    let mut rec = Recorder::new(&dae);
    let opts = SolverOptions::default();
    solve::integrate(&mut dae, 0.0, &y0, t_end, dt, &opts, &mut rec)
        .unwrap_or_else(|e| panic!("{e}"));
    (rec, dae.step_constraint_violation())
}

#[test]
fn run_to_memory_gives_the_numbers_of_a_direct_integration_and_the_same_summary() {
    // The clearance four-bar for a quarter turn (0.06 s at 250 rpm): several impacts, so the
    // event counts, impact times and contact maxima are all exercised.
    let model = load("models/farahan2016.toml", &[]);
    let sim = Simulation::new(
        &model,
        SimulationOptions::default()
            .revs(0.25)
            .dt(1e-4)
            .energy(true),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let run = sim.run_to_memory().unwrap_or_else(|e| panic!("{e}"));
    let (rec, step_violation) = direct_recorder(&model, sim.t_end(), 1e-4, true);
    assert_eq!(run.names, rec.names);
    assert_eq!(run.t, rec.t, "sample times");
    assert_eq!(run.len(), sim.expected_samples());
    for (k, name) in run.names.iter().enumerate() {
        // Same formulation, same solver, same grid: bit-identical, not merely close.
        assert_eq!(
            Some(run.columns[k].clone()),
            rec.column(name),
            "column {name}"
        );
    }
    assert_eq!(run.events, rec.events);
    assert_eq!(run.constraint_violation, rec.violation);

    // The incremental summary against the batch computation over all samples.
    let s = &run.summary;
    assert_eq!(s.samples, rec.len());
    // Over the samples and the accepted step ends (a step end can exceed every sample).
    assert_eq!(
        s.max_constraint_violation,
        rec.max_constraint_violation.max(step_violation)
    );
    let b = &s.clearance_joints[0];
    // Impacts: rising δ (event 0); events 1–4 are the friction kinks.
    let impacts: Vec<f64> = rec
        .events
        .iter()
        .filter(|e| e.index == 0 && e.crossing == Crossing::Rising)
        .map(|e| e.t)
        .collect();
    assert!(
        impacts.len() > 3,
        "the quarter turn has impacts: {impacts:?}"
    );
    assert_eq!(b.impact_count, impacts.len());
    assert_eq!(b.first_impact_times, impacts[..impacts.len().min(10)]);
    let max = |c: &str| {
        rec.column(c)
            .unwrap_or_default()
            .into_iter()
            .fold(f64::NEG_INFINITY, f64::max)
    };
    // The true peaks are located between the samples: never below the sampled maxima, and
    // the largest of the impact log's peaks (the joint starts free, so every contact is logged).
    assert!(
        b.max_penetration >= max("B.delta"),
        "{} vs sampled {}",
        b.max_penetration,
        max("B.delta")
    );
    assert!(
        b.peak_normal_force >= max("B.fn"),
        "{} vs sampled {}",
        b.peak_normal_force,
        max("B.fn")
    );
    let log_max = |f: fn(&crate::simulation::Impact) -> f64| {
        b.impacts.iter().map(f).fold(f64::NEG_INFINITY, f64::max)
    };
    assert_eq!(b.peak_normal_force, log_max(|i| i.peak_normal_force));
    assert_eq!(b.max_penetration, log_max(|i| i.peak_penetration));
    let e = s
        .energy_balance
        .as_ref()
        .unwrap_or_else(|| panic!("energy balance expected with energy(true)"));
    let last = |c: &str| rec.column(c).and_then(|v| v.last().copied());
    assert_eq!(Some(e.driver_work), last("energy.driver_work"));
    assert_eq!(Some(e.dissipated), last("energy.dissipated"));
    assert_eq!(
        e.max_abs_residual,
        rec.column("energy.balance")
            .unwrap_or_default()
            .iter()
            .fold(0.0, |m: f64, x| m.max(x.abs()))
    );
    assert_eq!(run.stats().events, rec.events.len() as u64);
    assert_eq!(
        run.provenance()
            .settings
            .get("formulation")
            .map(String::as_str),
        Some("dae")
    );
}

#[test]
fn a_streamed_run_has_the_summary_of_a_run_in_memory() {
    let model = load("models/farahan2016.toml", &[]);
    let sim = Simulation::new(
        &model,
        SimulationOptions::default()
            .formulation(FormulationKind::Reduced)
            .revs(0.1),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let streamed = sim.run(&mut Discard).unwrap_or_else(|e| panic!("{e}"));
    let kept = sim.run_to_memory().unwrap_or_else(|e| panic!("{e}"));
    // Wall time is the only thing allowed to differ.
    let same = RunSummary {
        wall_time_s: kept.summary.wall_time_s,
        sink_time_s: kept.summary.sink_time_s,
        ..streamed
    };
    let json = |s: &RunSummary| serde_json::to_string(s).unwrap_or_default();
    assert_eq!(json(&same), json(&kept.summary));
    assert_eq!(
        sim.driver_turns(sim.t_end())
            .map(|r| (r - 0.1).abs() < 1e-12),
        Some(true),
        "turns at t_end"
    );
}

#[test]
fn simulations_and_trajectories_can_cross_threads() {
    // Parameter sweeps move one simulation into each thread and send the results back; the
    // Python bindings release the GIL around a run. Both need these bounds (a compile-time
    // check). A simulation is Send, not Sync: the DAE keeps scratch space in a RefCell, so
    // threads each take a clone.
    fn send<T: Send>() {}
    fn send_sync<T: Send + Sync>() {}
    send::<Simulation>();
    send_sync::<Trajectory>();
    send_sync::<RunSummary>();
}

/// The friction kinks are events with Radau5 (which ends its steps at them) and with the
/// explicit pairs at rtol ≤ [`EXPLICIT_CUT_MAX_RTOL`] (where they cut their steps at events),
/// in every formulation; not with DOP853 at a looser rtol, whose cut is then off. The impacts
/// (event 0, the one clearance joint) and the summary's impact log do not depend on it.
#[test]
fn friction_kink_events_where_steps_are_cut_at_them() {
    let model = load("models/farahan2016.toml", &[]);
    let run = |kind: FormulationKind, method: crate::solve::Method, rtol: f64| {
        let solver = SolverOptions::default()
            .method(method)
            .rtol(rtol)
            .atol(rtol * 1e-3);
        let options = SimulationOptions::default()
            .formulation(kind)
            .revs(0.25)
            .dt(1e-3)
            .solver(solver);
        let sim = Simulation::new(&model, options).unwrap_or_else(|e| panic!("{e}"));
        let cut = sim.options().solver.explicit_rk.cut_at_events;
        (sim.run_to_memory().unwrap_or_else(|e| panic!("{e}")), cut)
    };
    // Events 1–4 are the one joint's kinks (the generalised formulation's repartition event
    // comes after them).
    let kinks = |t: &Trajectory| {
        t.events
            .iter()
            .filter(|e| (1..=kinks::N_KINK_EVENTS).contains(&e.index))
            .count()
    };
    let impacts = |t: &Trajectory| t.summary.clearance_joints[0].impacts.len();
    for kind in FormulationKind::ALL {
        let (radau, _) = run(kind, crate::solve::Method::Radau5, 1e-8);
        let (dop, dop_cut) = run(kind, crate::solve::Method::Dop853, 1e-8);
        let (loose, loose_cut) = run(kind, crate::solve::Method::Dop853, 1e-4);
        assert!(kinks(&radau) > 0, "{kind:?} Radau5: no kink events");
        assert!(
            kinks(&dop) > 0 && dop_cut,
            "{kind:?} DOP853 rtol 1e-8: no kink events"
        );
        assert!(
            kinks(&loose) == 0 && !loose_cut,
            "{kind:?} DOP853 rtol 1e-4: kink events or cuts"
        );
        assert_eq!(impacts(&radau), impacts(&dop), "{kind:?}");
        assert_eq!(
            impacts(&radau),
            radau
                .events
                .iter()
                .filter(|e| e.index == 0 && e.crossing == Crossing::Rising)
                .count(),
            "{kind:?}"
        );
    }
}

/// A sink that hands everything to the simulation's own ([`Observed`]) and, for every step in
/// contact, also scans the step's dense output densely for the largest F_N and δ: the check of
/// the peak search's assumption that the rates at the step ends reveal every interior maximum.
struct DenseScan<'s, S: SampleSink + ?Sized> {
    inner: Observed<'s, S>,
    /// Per joint: the scan of every step in contact.
    steps: Vec<Vec<ScannedStep>>,
}

/// (step start, step end, largest F_N, largest δ) of one step.
type ScannedStep = (f64, f64, f64, f64);

/// Probes per step of the scan (then golden-section search around the best probe).
const SCAN_PROBES: usize = 64;

impl<F: Formulation + Outputs + ContactProbe, S: SampleSink + ?Sized> solve::Sink<F>
    for DenseScan<'_, S>
{
    fn sample(&mut self, f: &F, t: f64, y: &[f64]) -> std::result::Result<(), SolveError> {
        self.inner.sample(f, t, y)
    }

    fn event(
        &mut self,
        f: &F,
        event: &solve::EventRecord,
        before: &[f64],
        after: &[f64],
    ) -> std::result::Result<(), SolveError> {
        self.inner.event(f, event, before, after)
    }

    fn on_step(
        &mut self,
        step: &mut solve::DenseStep<'_, F>,
    ) -> std::result::Result<(), SolveError> {
        let (a, b) = step.range();
        let f = step.formulation();
        let mut y = vec![0.0; step.n_states()];
        for k in 0..self.steps.len() {
            if !self.inner.summary.in_contact_during(k, b) {
                continue;
            }
            let mut at = |t: f64| -> std::result::Result<ContactPoint, SolveError> {
                step.interpolate(t, &mut y)?;
                f.contact_probe(k, t, &y)
                    .map_err(|source| SolveError::Formulation { t, source })
            };
            let times: Vec<f64> = (0..=SCAN_PROBES)
                .map(|j| {
                    if j == SCAN_PROBES {
                        b
                    } else {
                        a + (b - a) * j as f64 / SCAN_PROBES as f64
                    }
                })
                .collect();
            let mut points = Vec::with_capacity(times.len());
            for &t in &times {
                points.push(at(t)?);
            }
            let mut peak =
                |value: fn(&ContactPoint) -> f64| -> std::result::Result<f64, SolveError> {
                    let (mut i, mut best) = (0, f64::NEG_INFINITY);
                    for (j, p) in points.iter().enumerate() {
                        if value(p) > best {
                            (i, best) = (j, value(p));
                        }
                    }
                    let lo = times[i.saturating_sub(1)];
                    let hi = times[(i + 1).min(SCAN_PROBES)];
                    let (_, refined) = crate::solve::maximise::maximise(
                        |t| at(t).map(|p| value(&p)),
                        lo,
                        hi,
                        1e-6 * (b - a),
                    )?;
                    Ok(best.max(refined))
                };
            let force = peak(|p| p.normal_force)?;
            let delta = peak(|p| p.delta)?;
            self.steps[k].push((a, b, force, delta));
        }
        self.inner.on_step(step)
    }
}

/// Runs `sim` with the dense scan beside its own peak search; returns its summary and the
/// scan's steps.
fn run_with_scan(sim: &Simulation) -> (RunSummary, Vec<Vec<ScannedStep>>) {
    let mut consumer = Discard;
    let mut summary = SummaryBuilder::new(&sim.names, &sim.clearance_joints);
    if let [d] = sim.model.drivers.as_slice() {
        summary = summary.driver(d.initial_angle, d.speed);
    }
    let mut scan = DenseScan {
        inner: Observed::new(
            summary,
            &mut consumer,
            sim.names.len(),
            sim.options.solver.controlled_tolerances(),
        ),
        steps: vec![Vec::new(); sim.clearance_joints.len()],
    };
    fn go<F: Formulation + Outputs + ContactProbe, S: SampleSink + ?Sized>(
        sim: &Simulation,
        f: &mut F,
        scan: &mut DenseScan<'_, S>,
    ) -> solve::SolverStats {
        let y0 = f.initial_state();
        let t0 = f.t0();
        solve::integrate(
            f,
            t0,
            &y0,
            sim.t_end,
            sim.options.dt,
            &sim.options.solver,
            scan,
        )
        .unwrap_or_else(|e| panic!("{e}"))
    }
    let stats = match &sim.formulation {
        Built::Dae(f) => go(sim, &mut (**f).clone(), &mut scan),
        Built::Reduced(f) => go(sim, &mut (**f).clone(), &mut scan),
        Built::Generalized(f) => go(sim, &mut (**f).clone(), &mut scan),
    };
    let summary = scan.inner.summary.finish(
        sim.provenance(),
        sim.options.solver.clone(),
        stats,
        0.0,
        0.0,
    );
    (summary, scan.steps)
}

/// The impact log's peaks (found from the step ends' rates and a search only where a maximum
/// lies inside a step) equal those of a dense scan of every step in contact (65 probes and a
/// golden-section search to 1e-6 of the step), for every impact of the reference four-bar at
/// 250 and 3500 rpm, with DOP853 and Radau5 on the reduced and the DAE formulation. Bound
/// 1e-6 relative: both locate the maximum of the same dense output, the log to 1e-4 of the step
/// in time, which costs ½|F''|(1e-4 h)² ≈ 5e-8 F (module docs of `impacts.rs`); measured ≤ 1e-10.
#[test]
fn impact_peaks_equal_a_dense_scan_of_every_step() {
    for rpm in ["250", "3500"] {
        let model = load(
            "models/farahan2016.toml",
            &[&format!("drivers.motor.speed_rpm={rpm}")],
        );
        for formulation in [FormulationKind::Reduced, FormulationKind::Dae] {
            for method in [Method::Dop853, Method::Radau5] {
                let options = SimulationOptions::default()
                    .revs(2.0)
                    .dt(1e-3)
                    .formulation(formulation)
                    .solver(SolverOptions::default().method(method));
                let sim = Simulation::new(&model, options).unwrap_or_else(|e| panic!("{e}"));
                let (summary, steps) = run_with_scan(&sim);
                let joint = &summary.clearance_joints[0];
                assert!(
                    joint.impact_count >= 5,
                    "{rpm} rpm: {} impacts",
                    joint.impact_count
                );
                for impact in &joint.impacts {
                    let (mut force, mut delta) = (0.0_f64, 0.0_f64);
                    for &(a, _, fk, dk) in &steps[0] {
                        if impact.covers(a) {
                            force = force.max(fk);
                            delta = delta.max(dk);
                        }
                    }
                    let case = format!(
                        "{rpm} rpm, {formulation}, {method}, impact {} at {} s",
                        impact.index, impact.t
                    );
                    assert!(
                        (impact.peak_normal_force - force).abs() <= 1e-6 * force,
                        "{case}: peak F_N {} vs scan {force}",
                        impact.peak_normal_force
                    );
                    assert!(
                        (impact.peak_penetration - delta).abs() <= 1e-6 * delta,
                        "{case}: peak δ {} vs scan {delta}",
                        impact.peak_penetration
                    );
                }
            }
        }
    }
}
