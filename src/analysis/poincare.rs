//! Stroboscopic Poincaré section of a driven formulation: the state (or chosen output columns)
//! once per driving period, the "Poincaré portraits" of the clearance-joint literature \[1, 2\].
//!
//! # Method
//! For a system driven with period T (the crank period 2π/ω of a linkage), the section is the
//! sequence of states at the exact instants
//!
//!   t_k = t0 + φ + k·T,   k = n_transient, …, n_transient + n_points − 1,
//!
//! with φ ≥ 0 the phase offset (s) and the first n_transient periods discarded as transient.
//! The formulation is integrated once from (t0, y0) to the last t_k with
//! [`Stepper`] (so events — contacts — are located and applied as in any
//! run), and each t_k is read from the dense output of the step that contains it, never from a
//! step end: the section points carry the integrator's dense-output error (order 4 for DOPRI5, 7
//! for DOP853) and no error from the placement of the steps. Each t_k is computed as
//! t0 + φ + k·T, not accumulated, so the phase does not drift over long runs. A point exactly at
//! an event time shows the state before the event's change (as in
//! [`integrate`](fn@crate::solve::integrate)).
//!
//! A T-periodic orbit gives one point, a period-k orbit k points, quasi-periodic motion a closed
//! curve and chaotic motion a fractal set \[2\]; [`period`](super::period) turns the points into a
//! verdict.
//!
//! # References
//! 1. S. Rahmanian, M. R. Ghazavi, "Bifurcation in planar slider-crank mechanism with revolute
//!    clearance joint", *Mechanism and Machine Theory* 91, 86–101, 2015.
//! 2. T. S. Parker, L. O. Chua, *Practical Numerical Algorithms for Chaotic Systems*,
//!    Springer, 1989 (Ch. 6).

use serde::Serialize;

use super::error::AnalysisError;
use crate::formulation::{Formulation, Outputs};
use crate::solve::{SolverOptions, SolverStats, Stepper, Stop};

const WHAT: &str = "Poincaré section";

/// Where and how often to cut the trajectory (see the module documentation).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SectionOptions {
    /// Driving period T (s), > 0.
    pub period: f64,
    /// Phase offset φ of the section within the period (s), ≥ 0.
    pub phase_offset: f64,
    /// Driving periods discarded before the first point.
    pub n_transient: usize,
    /// Number of section points (≥ 1).
    pub n_points: usize,
}

/// A stroboscopic Poincaré section.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PoincareSection {
    /// Names of the point components: `y[i]` for states, the column names for outputs.
    pub names: Vec<String>,
    /// Section times t_k (s).
    pub times: Vec<f64>,
    /// One point per section time, `names.len()` components each.
    pub points: Vec<Vec<f64>>,
    /// Cost of the integration.
    pub stats: SolverStats,
}

/// Section of the state components `components` (all states if `None`) of `f` integrated from
/// (t0, y0) with `opts`.
///
/// Errors: invalid section options, a component index ≥ n_states, or a failed integration
/// ([`AnalysisError::Solve`], whose source says when).
pub fn section_states<F: Formulation>(
    f: &mut F,
    t0: f64,
    y0: &[f64],
    section: &SectionOptions,
    components: Option<&[usize]>,
    opts: &SolverOptions,
) -> Result<PoincareSection, AnalysisError> {
    let n = f.n_states();
    let chosen: Vec<usize> = components.map_or_else(|| (0..n).collect(), <[usize]>::to_vec);
    if let Some(&bad) = chosen.iter().find(|&&i| i >= n) {
        return Err(AnalysisError::invalid(
            "components",
            format!("state index {bad} is out of range: the formulation has {n} states"),
        ));
    }
    let names = chosen.iter().map(|i| format!("y[{i}]")).collect();
    run(f, t0, y0, section, opts, names, |_, _, y, out| {
        out.clear();
        out.extend(chosen.iter().map(|&i| y[i]));
        Ok(())
    })
}

/// Section of the output columns `columns` (all columns if empty) of `f` (see [`Outputs`]).
///
/// Errors: as [`section_states`], plus an unknown column name (the message lists the known
/// ones) or outputs that cannot be evaluated at a section time ([`AnalysisError::Outputs`]).
pub fn section_outputs<F: Formulation + Outputs>(
    f: &mut F,
    t0: f64,
    y0: &[f64],
    section: &SectionOptions,
    columns: &[&str],
    opts: &SolverOptions,
) -> Result<PoincareSection, AnalysisError> {
    section_outputs_settling(f, t0, y0, section, columns, opts, None).map(|s| s.section)
}

fn validate(section: &SectionOptions, t0: f64) -> Result<(), AnalysisError> {
    if !(section.period.is_finite() && section.period > 0.0) {
        return Err(AnalysisError::invalid(
            "period",
            format!(
                "expected a finite driving period > 0 s, got {}",
                section.period
            ),
        ));
    }
    if !(section.phase_offset.is_finite() && section.phase_offset >= 0.0) {
        return Err(AnalysisError::invalid(
            "phase_offset",
            format!(
                "expected a finite offset ≥ 0 s (integration runs forward from t0 = {t0} s), got {}",
                section.phase_offset
            ),
        ));
    }
    if section.n_points == 0 {
        return Err(AnalysisError::invalid(
            "n_points",
            "expected at least 1 section point, got 0",
        ));
    }
    Ok(())
}

/// Transient detection for [`section_outputs_settling`]: the transient ends at the first turn
/// τ with `min_transient` ≤ τ ≤ n_transient for which `settled` answers true on the points of
/// turns 0 … τ − 1 (the section at every turn from the start), and at n_transient if none does.
pub struct Settling<'a> {
    /// Fewest transient turns, whatever `settled` says.
    pub min_transient: usize,
    /// Whether the points so far (turn 0 first) have settled.
    pub settled: &'a mut dyn FnMut(&[Vec<f64>]) -> bool,
}

/// A section with the turns its transient took and the state at its last point.
#[derive(Debug, Clone, PartialEq)]
pub struct SettledSection {
    /// The section; its points are turns `transient`, `transient + 1`, ….
    pub section: PoincareSection,
    /// Transient turns dropped before the first point.
    pub transient: usize,
    /// Time (s) and whole state at the last point.
    pub end: (f64, Vec<f64>),
}

/// [`section_outputs`] whose transient ends as soon as `settling` says the points have settled
/// (never before its `min_transient`, never after `section.n_transient` turns), with the turns
/// it took and the state at the last point (to start a neighbouring run from).
///
/// Errors: as [`section_outputs`].
pub fn section_outputs_settling<F: Formulation + Outputs>(
    f: &mut F,
    t0: f64,
    y0: &[f64],
    section: &SectionOptions,
    columns: &[&str],
    opts: &SolverOptions,
    settling: Option<Settling<'_>>,
) -> Result<SettledSection, AnalysisError> {
    let all = f.output_names();
    let chosen: Vec<usize> = if columns.is_empty() {
        (0..all.len()).collect()
    } else {
        columns
            .iter()
            .map(|c| {
                all.iter().position(|a| a == c).ok_or_else(|| {
                    AnalysisError::invalid(
                        "columns",
                        format!(
                            "no output column \"{c}\"; the columns are {}",
                            all.join(", ")
                        ),
                    )
                })
            })
            .collect::<Result<_, _>>()?
    };
    let names = chosen.iter().map(|&i| all[i].clone()).collect();
    let mut row = Vec::new();
    run_settling(
        f,
        t0,
        y0,
        section,
        opts,
        names,
        |f, t, y, out| {
            f.outputs_into(t, y, &mut row)
                .map_err(|source| AnalysisError::Outputs {
                    analysis: WHAT,
                    t,
                    source,
                })?;
            out.clear();
            for &i in &chosen {
                // outputs_into writes output_names().len() columns; a shorter row is a
                // formulation bug, reported rather than indexed blindly.
                let v = row.get(i).copied().ok_or_else(|| {
                    AnalysisError::invalid(
                        "columns",
                        format!(
                            "the formulation wrote {} output columns at t = {t} s but names {}",
                            row.len(),
                            all.len()
                        ),
                    )
                })?;
                out.push(v);
            }
            Ok(())
        },
        settling,
    )
}

/// Integrates once and calls `observe(f, t_k, y(t_k), out)` at every section time.
fn run<F: Formulation>(
    f: &mut F,
    t0: f64,
    y0: &[f64],
    section: &SectionOptions,
    opts: &SolverOptions,
    names: Vec<String>,
    observe: impl FnMut(&F, f64, &[f64], &mut Vec<f64>) -> Result<(), AnalysisError>,
) -> Result<PoincareSection, AnalysisError> {
    run_settling(f, t0, y0, section, opts, names, observe, None).map(|s| s.section)
}

/// [`run`] with transient detection: while `settling` has not ended the transient, the point
/// of every turn is observed and handed to it.
#[allow(clippy::too_many_arguments)]
fn run_settling<F: Formulation>(
    f: &mut F,
    t0: f64,
    y0: &[f64],
    section: &SectionOptions,
    opts: &SolverOptions,
    names: Vec<String>,
    mut observe: impl FnMut(&F, f64, &[f64], &mut Vec<f64>) -> Result<(), AnalysisError>,
    mut settling: Option<Settling<'_>>,
) -> Result<SettledSection, AnalysisError> {
    validate(section, t0)?;
    let solve = |source| AnalysisError::Solve {
        analysis: WHAT,
        source,
    };
    let max_transient = section.n_transient;
    // The first recorded turn, once known: at once without detection (or with nothing to
    // detect), else when the transient points have settled.
    let mut first = if settling.is_some() && max_transient > 0 {
        None
    } else {
        Some(max_transient)
    };
    let time = |k: usize| t0 + section.phase_offset + k as f64 * section.period;
    let t_end = time(max_transient + section.n_points - 1);
    let mut stepper = Stepper::new(f, t0, y0, t_end, opts).map_err(solve)?;
    let mut y = vec![0.0; stepper.n_states()];
    let mut out = Vec::new();
    let mut times = Vec::with_capacity(section.n_points);
    let mut points = Vec::with_capacity(section.n_points);
    let mut transient_points = Vec::new();
    let mut k = first.unwrap_or(0);
    let finished =
        |first: Option<usize>, k: usize| first.is_some_and(|f0| k >= f0 + section.n_points);
    loop {
        while !finished(first, k) && time(k) <= stepper.t_reached() {
            let t = time(k);
            stepper.interpolate(t, &mut y).map_err(solve)?;
            observe(stepper.formulation(), t, &y, &mut out)?;
            if first.is_some() {
                times.push(t);
                points.push(out.clone());
            } else {
                transient_points.push(out.clone());
                let ends = k + 1 >= max_transient
                    || settling.as_mut().is_some_and(|s| {
                        k + 1 >= s.min_transient && (s.settled)(&transient_points)
                    });
                if ends {
                    first = Some(k + 1);
                }
            }
            k += 1;
        }
        if finished(first, k) {
            break;
        }
        if stepper.step().map_err(solve)? == Stop::EndReached && stepper.t_reached() < time(k) {
            // Only reachable if the last step ended short of t_end by rounding: sample the end.
            let t = stepper.t_reached();
            stepper.interpolate(t, &mut y).map_err(solve)?;
            observe(stepper.formulation(), time(k), &y, &mut out)?;
            times.push(time(k));
            points.push(out.clone());
            break;
        }
    }
    Ok(SettledSection {
        section: PoincareSection {
            names,
            times,
            points,
            stats: stepper.stats().clone(),
        },
        transient: first.unwrap_or(max_transient),
        end: (time(k.saturating_sub(1)), y),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formulation::FormulationError;
    use crate::formulation::NoStepHooks;

    /// x' = 1 (x = t), with outputs "x" and "twice".
    struct Clock;
    impl NoStepHooks for Clock {}

    impl Formulation for Clock {
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
    }
    impl Outputs for Clock {
        fn output_names(&self) -> Vec<String> {
            vec!["x".into(), "twice".into()]
        }
        fn outputs_into(
            &self,
            _t: f64,
            y: &[f64],
            out: &mut Vec<f64>,
        ) -> Result<f64, FormulationError> {
            out.clear();
            out.extend([y[0], 2.0 * y[0]]);
            Ok(0.0)
        }
    }

    #[test]
    fn section_times_are_exact_and_points_are_the_state_there() {
        let section = SectionOptions {
            period: 0.3,
            phase_offset: 0.05,
            n_transient: 2,
            n_points: 5,
        };
        let r = section_outputs(
            &mut Clock,
            1.0,
            &[1.0],
            &section,
            &["twice"],
            &SolverOptions::default(),
        );
        let Ok(s) = r else {
            panic!("{r:?}");
        };
        assert_eq!(s.names, ["twice"]);
        for (k, (t, p)) in s.times.iter().zip(&s.points).enumerate() {
            let expected_t = 1.0 + 0.05 + (k + 2) as f64 * 0.3;
            assert_eq!(*t, expected_t, "section time {k}");
            // x = t, so twice = 2t; the dense output of x' = 1 is exact to rounding.
            assert!(
                (p[0] - 2.0 * t).abs() < 1e-12,
                "point {k}: {} vs {}",
                p[0],
                2.0 * t
            );
        }
        let r = section_outputs(
            &mut Clock,
            0.0,
            &[0.0],
            &section,
            &["thrice"],
            &SolverOptions::default(),
        );
        assert_eq!(
            r.err().map(|e| e.to_string()).as_deref(),
            Some("invalid columns: no output column \"thrice\"; the columns are x, twice")
        );
    }

    #[test]
    fn a_section_point_at_t0_is_the_initial_state() {
        let section = SectionOptions {
            period: 1.0,
            phase_offset: 0.0,
            n_transient: 0,
            n_points: 3,
        };
        let r = section_states(
            &mut Clock,
            0.0,
            &[0.5],
            &section,
            None,
            &SolverOptions::default(),
        );
        let Ok(s) = r else {
            panic!("{r:?}");
        };
        assert_eq!(s.times, [0.0, 1.0, 2.0]);
        assert_eq!(s.points[0], [0.5]);
        assert!((s.points[2][0] - 2.5).abs() < 1e-12, "{:?}", s.points);
        let r = section_states(
            &mut Clock,
            0.0,
            &[0.5],
            &section,
            Some(&[1]),
            &SolverOptions::default(),
        );
        assert_eq!(
            r.err().map(|e| e.to_string()).as_deref(),
            Some("invalid components: state index 1 is out of range: the formulation has 1 states")
        );
    }
}
