//! The computations behind each figure, per friction variant, and the figures they draw.

use super::figures::{self, FigureFile};
use super::{Attempt, Plan, ReproduceOptions, Variant, attempts};
use crate::analysis::{self, ParameterGrid, PeriodVerdict, SweepPoint};
use crate::error::{Error, Result};
use crate::model::{Model, idealise, load};
use crate::simulation::analyses::{self, LyapunovSpec, SectionSpec, Sweep};
use crate::simulation::{FormulationKind, Simulation, SimulationOptions, Trajectory};
use crate::solve::SolverOptions;
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// Radial clearance of the paper's runs (m).
pub const CLEARANCE: f64 = 0.5e-3;
/// Clearance of the validation case, Fig. 3 (m).
pub const CLEARANCE_VALIDATION: f64 = 0.2e-3;
/// Clearance of the period-one claim at 3500 rpm, Fig. 6 (m).
pub const CLEARANCE_3500: f64 = 0.44e-3;
/// Clearance range of the bifurcation diagram, Fig. 6a (m).
pub const SWEEP: (f64, f64) = (0.05e-3, 0.5e-3);
/// Separation of the twin runs (m): the journal's initial x eccentricity.
pub const TWIN_SEPARATION: f64 = 1e-12;
/// The observed column of the sections, sweeps and phase portraits: the journal's x eccentricity.
pub const JOURNAL_X: &str = "B.ex";

/// A computation's result, the solver that produced it, and the failed attempts before it.
#[derive(Debug, Clone, Serialize)]
pub struct Outcome<T> {
    /// The result, or the last attempt's error.
    pub value: std::result::Result<T, String>,
    /// The solver of the result ("" on failure).
    pub solver: String,
    /// "solver: error" of every failed attempt.
    pub failures: Vec<String>,
}

impl<T> Outcome<T> {
    /// The value, if any.
    pub fn ok(&self) -> Option<&T> {
        self.value.as_ref().ok()
    }
}

/// `e` with every cause it wraps, once each.
pub fn chain(e: &Error) -> String {
    let mut text = e.to_string();
    let mut cause = std::error::Error::source(e);
    while let Some(c) = cause {
        let more = c.to_string();
        if !text.contains(&more) {
            text.push_str(": ");
            text.push_str(&more);
        }
        cause = c.source();
    }
    text
}

/// Tries [`attempts`] in order until one succeeds.
fn with_fallback<T>(f: impl Fn(&Attempt) -> Result<T>) -> Outcome<T> {
    let mut failures = Vec::new();
    for attempt in attempts() {
        match f(&attempt) {
            Ok(v) => {
                return Outcome {
                    value: Ok(v),
                    solver: attempt.name,
                    failures,
                };
            }
            Err(e) => failures.push(format!("{}: {}", attempt.name, chain(&e))),
        }
    }
    Outcome {
        value: Err(failures.last().cloned().unwrap_or_default()),
        solver: String::new(),
        failures,
    }
}

/// Impacts and contact of one time history.
#[derive(Debug, Clone, Serialize)]
pub struct History {
    /// Driver speed (rpm).
    pub rpm: f64,
    /// Radial clearance (m).
    pub clearance: f64,
    /// Impacts in the run.
    pub impacts: usize,
    /// Impacts within the first 25 ms.
    pub impacts_25ms: usize,
    /// Start of permanent contact (s) and its impact number, if any.
    pub permanent: Option<(f64, usize)>,
    /// Largest normal force (N).
    pub peak_force: f64,
    /// Driver turns simulated.
    pub turns: f64,
}

/// A section's verdict.
#[derive(Debug, Clone, Serialize)]
pub struct SectionFindings {
    /// "period-1", "no period found up to k_max = 8", …
    pub verdict: String,
    /// k of a period-k verdict.
    pub period: Option<usize>,
    /// Points judged.
    pub points: usize,
    /// Turn from which the points repeat (period-k only).
    pub settled_at_turn: Option<usize>,
    /// Period tolerance per observed column (their units).
    pub tolerance: Vec<f64>,
}

/// The dominant peaks of a spectrum.
#[derive(Debug, Clone, Serialize)]
pub struct SpectrumFindings {
    /// Driving frequency (Hz).
    pub driving_hz: f64,
    /// (frequency in Hz, multiple of the driving frequency, amplitude), largest first.
    pub peaks: Vec<(f64, Option<f64>, f64)>,
}

/// A Lyapunov estimate.
#[derive(Debug, Clone, Serialize)]
pub struct LyapunovFindings {
    /// λ₁ (1/s).
    pub exponent: f64,
    /// Its batch-means uncertainty (1/s).
    pub uncertainty: f64,
}

/// Twin runs 1e-12 m apart.
#[derive(Debug, Clone, Serialize)]
pub struct TwinFindings {
    /// Turns run.
    pub turns: f64,
    /// Largest |Δθ3|, |Δθ4| (coupler.phi, rocker.phi) over the run (rad).
    pub max_gap: f64,
    /// First time |Δθ3| or |Δθ4| ≥ 1e-3 rad (s), if ever.
    pub reached_1e3_at: Option<f64>,
}

/// The bifurcation sweep's summary.
#[derive(Debug, Clone, Serialize)]
pub struct SweepFindings {
    /// Points computed (of the grid).
    pub points: usize,
    /// Points that failed with every solver.
    pub failed: usize,
    /// Points with a period-1 verdict.
    pub period_1: usize,
    /// Points with a period-k verdict, k > 1.
    pub period_k: usize,
    /// Points with no period up to 8.
    pub no_period: usize,
    /// Wall time of the sweep (s).
    pub wall_s: f64,
    /// The solver tried first at every point (the others are fallbacks).
    pub solver: String,
    /// Points that needed a fallback solver.
    pub fallbacks: usize,
    /// Worker threads.
    pub threads: usize,
}

/// Everything measured for one friction variant.
#[derive(Debug, Clone, Serialize)]
pub struct VariantFindings {
    /// The variant.
    pub variant: Variant,
    /// Fig. 3: c = 0.2 mm, 250 rpm.
    pub validation: Outcome<History>,
    /// Fig. 4a/b: 250 rpm.
    pub history_250: Outcome<History>,
    /// Fig. 4c/d: 3500 rpm.
    pub history_3500: Outcome<History>,
    /// Fig. 5b/c: the section at 250 rpm.
    pub section_250: Outcome<SectionFindings>,
    /// Fig. 5a: the spectrum at 250 rpm.
    pub spectrum_250: Outcome<SpectrumFindings>,
    /// λ₁ at 250 rpm.
    pub lyapunov_250: Outcome<LyapunovFindings>,
    /// Twin runs at 250 rpm.
    pub twin_250: Outcome<TwinFindings>,
    /// Fig. 6a: the sweep at 3500 rpm.
    pub sweep_3500: Option<SweepFindings>,
    /// Fig. 6c/d: the section at 3500 rpm, c = 0.44 mm.
    pub section_3500: Outcome<SectionFindings>,
    /// Fig. 6b: the spectrum at 3500 rpm, c = 0.44 mm.
    pub spectrum_3500: Outcome<SpectrumFindings>,
    /// Figures drawn (or why not).
    pub figures: Vec<FigureFile>,
}

/// The whole reproduction.
#[derive(Debug, Clone, Serialize)]
pub struct Findings {
    /// `--quick` or not.
    pub quick: bool,
    /// The turn counts used.
    pub plan: Plan,
    /// The model file.
    pub model: String,
    /// Per variant, in [`Variant::ALL`] order.
    pub variants: Vec<VariantFindings>,
    /// Figures of the ideal reference alone (none so far; the ideal lines are in the others).
    pub wall_s: f64,
}

/// The model with the variant's friction law and `extra` overrides.
fn model(opts: &ReproduceOptions, variant: Variant, extra: &[String]) -> Result<Model> {
    let mut set = vec![format!("joints.B.friction.law={}", variant.law())];
    set.extend_from_slice(extra);
    Ok(load(&opts.model, &set)?)
}

fn rpm_set(rpm: f64) -> String {
    format!("drivers.motor.speed_rpm={rpm}")
}

fn clearance_set(c: f64) -> String {
    format!("joints.B.clearance={c}")
}

fn options(turns: f64, dt: f64, solver: &SolverOptions) -> SimulationOptions {
    SimulationOptions::default()
        .formulation(FormulationKind::Reduced)
        .revs(turns)
        .dt(dt)
        .solver(solver.clone())
}

/// Output interval of a run at `rpm`: about 600 samples per turn, at most 1e-4 s.
fn dt_for(rpm: f64) -> f64 {
    (60.0 / rpm / 600.0).min(1e-4)
}

/// The ideal reference (`--ideal B`, DAE) at `rpm`.
fn ideal_run(opts: &ReproduceOptions, rpm: f64, turns: f64) -> Result<Trajectory> {
    let m = idealise(load(&opts.model, &[rpm_set(rpm)])?, &["B".to_string()])?;
    let o = SimulationOptions::default()
        .formulation(FormulationKind::Dae)
        .revs(turns)
        .dt(dt_for(rpm));
    Simulation::new(&m, o)?.run_to_memory()
}

fn history(
    opts: &ReproduceOptions,
    variant: Variant,
    rpm: f64,
    clearance: f64,
    turns: f64,
) -> (Outcome<History>, Option<Trajectory>) {
    let extra = [rpm_set(rpm), clearance_set(clearance)];
    let out = with_fallback(|a| {
        let m = model(opts, variant, &extra)?;
        Simulation::new(&m, options(turns, dt_for(rpm), &a.solver))?.run_to_memory()
    });
    let traj = out.value.as_ref().ok().cloned();
    let value = out.value.map(|t| {
        let j = t.summary.clearance_joints.first();
        History {
            rpm,
            clearance,
            impacts: j.map_or(0, |j| j.impact_count),
            impacts_25ms: j.map_or(0, |j| j.impacts.iter().filter(|i| i.t <= 0.025).count()),
            permanent: j
                .and_then(|j| j.permanent_contact.as_ref())
                .map(|p| (p.since, p.impact_index)),
            peak_force: j.map_or(0.0, |j| j.peak_normal_force),
            turns,
        }
    });
    (
        Outcome {
            value,
            solver: out.solver,
            failures: out.failures,
        },
        traj,
    )
}

fn section_findings(s: &analyses::ModelSection) -> SectionFindings {
    SectionFindings {
        verdict: s.period.verdict.to_string(),
        period: match s.period.verdict {
            PeriodVerdict::Period { k, .. } => Some(k),
            _ => None,
        },
        points: s.section.points.len(),
        settled_at_turn: s.settled_at_turn,
        tolerance: s.tolerance.clone(),
    }
}

fn section(
    opts: &ReproduceOptions,
    variant: Variant,
    extra: &[String],
    (turns, transient): (usize, usize),
) -> Outcome<analyses::ModelSection> {
    with_fallback(|a| {
        let m = model(opts, variant, extra)?;
        let sim = Simulation::new(&m, options(turns as f64, 1e-3, &a.solver))?;
        analyses::poincare(
            &sim,
            &SectionSpec {
                turns,
                transient,
                phase: 0.0,
                observe: vec!["B.ex".into(), "B.ey".into()],
            },
        )
    })
}

fn map<T, U>(o: &Outcome<T>, f: impl FnOnce(&T) -> U) -> Outcome<U> {
    Outcome {
        value: match &o.value {
            Ok(v) => Ok(f(v)),
            Err(e) => Err(e.clone()),
        },
        solver: o.solver.clone(),
        failures: o.failures.clone(),
    }
}

fn spectrum_findings(s: &analysis::Spectrum, f_drive: f64) -> SpectrumFindings {
    SpectrumFindings {
        driving_hz: f_drive,
        peaks: s
            .peaks
            .iter()
            .take(6)
            .map(|p| (p.frequency, p.multiple, p.amplitude))
            .collect(),
    }
}

/// Runs the whole reproduction into directory `dir` (figures as PNG), calling `log` with one
/// line per step. Per-computation failures are recorded in the findings, not returned; the
/// error is for a model that cannot be loaded at all.
pub fn reproduce(
    opts: &ReproduceOptions,
    dir: &Path,
    log: &mut dyn FnMut(&str),
) -> Result<Findings> {
    let start = Instant::now();
    let plan = if opts.quick {
        Plan::quick()
    } else {
        Plan::full()
    };
    // Refuse a model that does not load before any work.
    model(opts, Variant::Intended, &[])?;
    log("ideal references (--ideal B, DAE)");
    let ideal_250 = ideal_run(opts, 250.0, plan.history_turns)?;
    let ideal_3500 = ideal_run(opts, 3500.0, plan.history_turns)?;
    let mut variants = Vec::new();
    for variant in Variant::ALL {
        let v = variant.label();
        let mut figs = Vec::new();
        log(&format!("{v}: Fig. 3 (c = 0.2 mm)"));
        let (validation, traj) = history(
            opts,
            variant,
            250.0,
            CLEARANCE_VALIDATION,
            plan.history_turns,
        );
        if let Some(t) = &traj {
            figs.push(figures::series(
                dir,
                "fig3",
                v,
                "a",
                t,
                &ideal_250,
                "rocker.alpha",
                "Fig. 3a/b: rocker (follower) angular acceleration, c = 0.2 mm, 250 rpm",
            ));
            figs.push(figures::series(
                dir,
                "fig3",
                v,
                "b",
                t,
                &ideal_250,
                "motor.torque",
                "Fig. 3c/d: crank torque, c = 0.2 mm, 250 rpm",
            ));
            figs.push(figures::orbit(
                dir,
                "fig3",
                v,
                "c",
                t,
                CLEARANCE_VALIDATION,
                "Fig. 3e/f: journal orbit, c = 0.2 mm, 250 rpm",
            ));
        }
        log(&format!("{v}: Fig. 4 (250 and 3500 rpm)"));
        let (history_250, traj) = history(opts, variant, 250.0, CLEARANCE, plan.history_turns);
        if let Some(t) = &traj {
            figs.push(figures::series(
                dir,
                "fig4",
                v,
                "a",
                t,
                &ideal_250,
                "coupler.alpha",
                "Fig. 4a: coupler angular acceleration, 250 rpm, c = 0.5 mm",
            ));
            figs.push(figures::orbit(
                dir,
                "fig4",
                v,
                "b",
                t,
                CLEARANCE,
                "Fig. 4b: journal orbit, 250 rpm, c = 0.5 mm",
            ));
        }
        let (history_3500, traj) = history(opts, variant, 3500.0, CLEARANCE, plan.history_turns);
        if let Some(t) = &traj {
            figs.push(figures::series(
                dir,
                "fig4",
                v,
                "c",
                t,
                &ideal_3500,
                "coupler.alpha",
                "Fig. 4c: coupler angular acceleration, 3500 rpm, c = 0.5 mm",
            ));
            figs.push(figures::orbit(
                dir,
                "fig4",
                v,
                "d",
                t,
                CLEARANCE,
                "Fig. 4d: journal orbit, 3500 rpm, c = 0.5 mm",
            ));
        }

        log(&format!(
            "{v}: Fig. 5 (250 rpm: section, spectrum, Lyapunov, twins)"
        ));
        let base_250 = [rpm_set(250.0), clearance_set(CLEARANCE)];
        let s250 = section(opts, variant, &base_250, plan.section_250);
        if let Some(s) = s250.ok() {
            figs.push(figures::poincare(
                dir,
                "fig5",
                v,
                "bc",
                s,
                CLEARANCE,
                "Fig. 5b/c: Poincaré section, journal centre, 250 rpm",
            ));
        }
        let section_250 = map(&s250, section_findings);
        let sp250 = signal(opts, variant, &base_250, plan.signal_250, 250.0);
        if let Some((s, f)) = sp250.ok() {
            figs.push(figures::spectrum(
                dir,
                "fig5",
                v,
                "a",
                s,
                *f,
                "Fig. 5a: spectrum of coupler.alpha, 250 rpm",
            ));
        }
        let spectrum_250 = map(&sp250, |(s, f)| spectrum_findings(s, *f));
        let ly = with_fallback(|a| {
            let m = model(opts, variant, &base_250)?;
            let sim = Simulation::new(&m, options(plan.lyapunov_250.0, 1e-3, &a.solver))?;
            analyses::lyapunov(
                &sim,
                &LyapunovSpec {
                    turns: plan.lyapunov_250.0,
                    transient: plan.lyapunov_250.1,
                    d0: 1e-7,
                    renormalise_every: 1.0,
                },
            )
        });
        if let Some(e) = ly.ok() {
            figs.push(figures::lyapunov(
                dir,
                "fig5",
                v,
                "d",
                e,
                "Largest Lyapunov exponent, running estimate, 250 rpm",
            ));
        }
        let lyapunov_250 = map(&ly, |e| LyapunovFindings {
            exponent: e.exponent,
            uncertainty: e.uncertainty,
        });
        let twin_250 = twins(opts, variant, &base_250, plan.twin_turns);

        log(&format!(
            "{v}: Fig. 6 (3500 rpm: bifurcation, section, spectrum)"
        ));
        let sweep_3500 = sweep(opts, variant, plan, dir, &mut figs);
        let base_3500 = [rpm_set(3500.0), clearance_set(CLEARANCE_3500)];
        let s3500 = section(opts, variant, &base_3500, plan.section_3500);
        if let Some(s) = s3500.ok() {
            figs.push(figures::poincare(
                dir,
                "fig6",
                v,
                "cd",
                s,
                CLEARANCE_3500,
                "Fig. 6c/d: Poincaré section, journal centre, 3500 rpm, c = 0.44 mm",
            ));
        }
        let section_3500 = map(&s3500, section_findings);
        let sp3500 = signal(opts, variant, &base_3500, plan.signal_3500, 3500.0);
        if let Some((s, f)) = sp3500.ok() {
            figs.push(figures::spectrum(
                dir,
                "fig6",
                v,
                "b",
                s,
                *f,
                "Fig. 6b: spectrum of coupler.alpha, 3500 rpm, c = 0.44 mm",
            ));
        }
        let spectrum_3500 = map(&sp3500, |(s, f)| spectrum_findings(s, *f));

        log(&format!("{v}: Fig. 7 (phase portraits)"));
        for (rpm, base, turns, panel) in [
            (250.0, &base_250, plan.signal_250, "a"),
            (3500.0, &base_3500, plan.signal_3500, "b"),
        ] {
            let p = with_fallback(|a| {
                let m = model(opts, variant, base)?;
                let sim = Simulation::new(&m, options(turns.0, dt_for(rpm), &a.solver))?;
                analyses::phase(&sim, JOURNAL_X, turns.1)
            });
            if let Some((t, p)) = p.ok() {
                let c = if rpm > 1000.0 { "0.44" } else { "0.5" };
                figs.push(figures::phase(
                    dir,
                    "fig7",
                    v,
                    panel,
                    t,
                    p,
                    &format!("Fig. 7{panel}: phase portrait of B.ex, {rpm} rpm, c = {c} mm"),
                ));
            }
        }
        variants.push(VariantFindings {
            variant,
            validation,
            history_250,
            history_3500,
            section_250,
            spectrum_250,
            lyapunov_250,
            twin_250,
            sweep_3500,
            section_3500,
            spectrum_3500,
            figures: figs,
        });
    }
    Ok(Findings {
        quick: opts.quick,
        plan,
        model: opts.model.display().to_string(),
        variants,
        wall_s: start.elapsed().as_secs_f64(),
    })
}

/// Spectrum of the coupler's angular acceleration after the transient.
fn signal(
    opts: &ReproduceOptions,
    variant: Variant,
    extra: &[String],
    (turns, transient): (f64, f64),
    rpm: f64,
) -> Outcome<(analysis::Spectrum, f64)> {
    with_fallback(|a| {
        let m = model(opts, variant, extra)?;
        let sim = Simulation::new(&m, options(turns, dt_for(rpm), &a.solver))?;
        analyses::spectrum(&sim, "coupler.alpha", transient)
    })
}

/// Twin runs: the journal centred and 1e-12 m off centre; the gap in coupler.phi.
fn twins(
    opts: &ReproduceOptions,
    variant: Variant,
    extra: &[String],
    turns: f64,
) -> Outcome<TwinFindings> {
    with_fallback(|a| {
        let run = |e: f64| -> Result<Trajectory> {
            let mut set = extra.to_vec();
            set.push(format!("joints.B.initial_eccentricity=[{e:e}, 0.0]"));
            let m = model(opts, variant, &set)?;
            Simulation::new(&m, options(turns, 1e-4, &a.solver))?.run_to_memory()
        };
        let (p, q) = (run(0.0)?, run(TWIN_SEPARATION)?);
        let mut max_gap = 0.0_f64;
        let mut reached: Option<f64> = None;
        for column in ["coupler.phi", "rocker.phi"] {
            let (Some(x), Some(y)) = (p.column(column), q.column(column)) else {
                return Err(Error::settings("observe", format!("no column {column}")));
            };
            for ((a, b), t) in x.iter().zip(y).zip(&p.t) {
                let gap = (a - b).abs();
                max_gap = max_gap.max(gap);
                if gap >= 1e-3 && reached.is_none_or(|r| *t < r) {
                    reached = Some(*t);
                }
            }
        }
        Ok(TwinFindings {
            turns,
            max_gap,
            reached_1e3_at: reached,
        })
    })
}

/// A sweep point: the index of the solver that computed it (`attempts().len()` if none) and
/// its section.
type Tried = (usize, Result<analyses::ModelSection>);

/// Fig. 6a: the bifurcation sweep against the clearance at 3500 rpm, each point with the
/// fallback solvers; draws the diagram.
fn sweep(
    opts: &ReproduceOptions,
    variant: Variant,
    plan: Plan,
    dir: &Path,
    figs: &mut Vec<FigureFile>,
) -> Option<SweepFindings> {
    let (n, turns, transient) = plan.bifurcation;
    let n = if variant == Variant::Intended {
        n
    } else {
        plan.bifurcation_others
    };
    let grid = ParameterGrid::new(SWEEP.0, SWEEP.1, n.saturating_sub(1)).ok()?;
    let overrides = vec![
        format!("joints.B.friction.law={}", variant.law()),
        rpm_set(3500.0),
    ];
    let section = SectionSpec {
        turns,
        transient,
        phase: 0.0,
        observe: vec![JOURNAL_X.into()],
    };
    let sweeps: Vec<(String, Sweep<'_>)> = attempts()
        .into_iter()
        .map(|a| {
            (
                a.name,
                Sweep {
                    model_path: &opts.model,
                    model_text: None,
                    overrides: &overrides,
                    parameter: "joints.B.clearance",
                    grid,
                    options: options(turns as f64, 1e-3, &a.solver),
                    section: section.clone(),
                },
            )
        })
        .collect();
    let indices: Vec<usize> = (0..grid.len()).collect();
    let start = Instant::now();
    let points: std::result::Result<Vec<SweepPoint<Tried>>, Error> = analysis::run_points(
        &grid,
        &indices,
        |_, p| {
            let mut last = None;
            for (k, (_, s)) in sweeps.iter().enumerate() {
                match s.point(p) {
                    Ok(v) => return (k, Ok(v)),
                    Err(e) => last = Some(e),
                }
            }
            (
                sweeps.len(),
                Err(last.unwrap_or_else(|| Error::settings("solver", "no solver"))),
            )
        },
        |_| Ok(()),
    );
    let wall_s = start.elapsed().as_secs_f64();
    let points = points.ok()?;
    let mut f = SweepFindings {
        points: points.len(),
        failed: 0,
        period_1: 0,
        period_k: 0,
        no_period: 0,
        wall_s,
        solver: sweeps
            .first()
            .map(|(name, _)| name.clone())
            .unwrap_or_default(),
        fallbacks: 0,
        threads: rayon::current_num_threads(),
    };
    let mut rows = Vec::new();
    for p in &points {
        let (k, r) = &p.result;
        if *k > 0 {
            f.fallbacks += 1;
        }
        match r {
            Ok(s) => {
                match s.period.verdict {
                    PeriodVerdict::Period { k: 1, .. } => f.period_1 += 1,
                    PeriodVerdict::Period { .. } => f.period_k += 1,
                    _ => f.no_period += 1,
                }
                for (turn, pt) in s.turns.iter().zip(&s.section.points) {
                    if let Some(v) = pt.first() {
                        rows.push([p.index as f64, p.parameter * 1e3, *turn as f64, *v]);
                    }
                }
            }
            Err(_) => f.failed += 1,
        }
    }
    figs.push(figures::bifurcation(
        dir,
        variant.label(),
        &rows,
        "Fig. 6a: bifurcation diagram against the clearance, 3500 rpm",
    ));
    Some(f)
}
