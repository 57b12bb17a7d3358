//! Period of a sequence of Poincaré points: the verdict "period-k", "no period found up to
//! k_max" or "not settled" that bifurcation diagrams of clearance joints are read by \[1\].
//!
//! # Method
//! Let p_0 … p_{N−1} be the points (vectors of d components, one per driving period, e.g. from
//! [`poincare`](super::poincare)). Only the last W = m + k_max points are judged (the earlier
//! ones are taken as transient). Per component j, the tolerance is
//!
//!   tol_j = tol_abs + tol_rel·s_j,   s_j = max_i p_{i,j} − min_i p_{i,j} over those W points,
//!
//! relative to the spread of the data (so that the verdict does not depend on units) plus an
//! absolute floor (a fixed point has s_j ≈ 0). The caller derives tol_abs and tol_rel from the
//! integration tolerances and prints them; the numbers used are returned. The mismatch of
//! period k is
//!
//!   μ_k = max_{N−m ≤ i < N} max_j |p_{i,j} − p_{i−k,j}| / tol_j,
//!
//! and the verdict is period-k for the smallest k ∈ 1..=k_max with μ_k ≤ 1 (a period-3 orbit
//! also repeats after 6, so the smallest is its period); otherwise "no period found up to
//! k_max" (quasi-periodic, chaotic, a longer period, or not yet settled — the points cannot tell
//! these apart). With fewer than W points the verdict is "not settled".
//!
//! # References
//! 1. S. Rahmanian, M. R. Ghazavi, "Bifurcation in planar slider-crank mechanism with revolute
//!    clearance joint", *Mechanism and Machine Theory* 91, 86–101, 2015.
//! 2. T. S. Parker, L. O. Chua, *Practical Numerical Algorithms for Chaotic Systems*,
//!    Springer, 1989 (Ch. 6, Poincaré maps and the period of a limit set).

use std::fmt;

use serde::Serialize;

use super::error::{AnalysisError, check_finite};

/// Options of [`period_verdict`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PeriodOptions {
    /// Largest period tried (≥ 1).
    pub k_max: usize,
    /// Number of trailing points that must repeat (≥ 1).
    pub m: usize,
    /// Tolerance relative to each component's spread (dimensionless, ≥ 0).
    pub tol_rel: f64,
    /// Absolute tolerance floor (units of the components, ≥ 0; tol_rel + tol_abs > 0).
    pub tol_abs: f64,
}

impl Default for PeriodOptions {
    /// k_max = 16, m = 32, tol_rel = 1e-4, tol_abs = 1e-8. The caller should set the
    /// tolerances from its integration tolerances.
    fn default() -> Self {
        Self {
            k_max: 16,
            m: 32,
            tol_rel: 1e-4,
            tol_abs: 1e-8,
        }
    }
}

/// What the points say about the period.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "verdict")]
pub enum PeriodVerdict {
    /// The last m points repeat with period k (the smallest such k).
    Period {
        /// The period, in driving periods.
        k: usize,
        /// μ_k ≤ 1: the largest difference in units of the tolerance.
        mismatch: f64,
    },
    /// No k ≤ k_max makes the last m points repeat.
    NoPeriod {
        /// Largest period tried.
        k_max: usize,
        /// The k with the smallest mismatch.
        closest_k: usize,
        /// Its mismatch μ_k > 1.
        mismatch: f64,
    },
    /// Too few points to judge.
    NotSettled {
        /// Points given.
        points: usize,
        /// Points needed (m + k_max).
        needed: usize,
    },
}

impl fmt::Display for PeriodVerdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PeriodVerdict::Period { k, .. } => write!(f, "period-{k}"),
            PeriodVerdict::NoPeriod { k_max, .. } => {
                write!(f, "no period found up to k_max = {k_max}")
            }
            PeriodVerdict::NotSettled { points, needed } => {
                write!(f, "not settled: {points} points, {needed} needed")
            }
        }
    }
}

/// The verdict and the tolerances it was reached with.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PeriodAnalysis {
    /// The verdict.
    pub verdict: PeriodVerdict,
    /// tol_j per component (units of the components); empty when not settled.
    pub tolerance: Vec<f64>,
}

/// Judges the period of `points` (see the module documentation).
///
/// Errors: k_max or m zero, negative or non-finite tolerances (or both zero), points of
/// different lengths, or a non-finite component.
///
/// ```
/// use linkdyn::analysis::period::{period_verdict, PeriodOptions, PeriodVerdict};
/// let points: Vec<Vec<f64>> = (0..60).map(|i| vec![[1.0, 2.0, 5.0][i % 3]]).collect();
/// let a = period_verdict(&points, &PeriodOptions::default())?;
/// assert!(matches!(a.verdict, PeriodVerdict::Period { k: 3, .. }));
/// # Ok::<(), linkdyn::analysis::AnalysisError>(())
/// ```
pub fn period_verdict(
    points: &[Vec<f64>],
    opts: &PeriodOptions,
) -> Result<PeriodAnalysis, AnalysisError> {
    validate(points, opts)?;
    let needed = opts.m + opts.k_max;
    if points.len() < needed {
        return Ok(PeriodAnalysis {
            verdict: PeriodVerdict::NotSettled {
                points: points.len(),
                needed,
            },
            tolerance: Vec::new(),
        });
    }
    let window = &points[points.len() - needed..];
    let d = window[0].len();
    let tolerance: Vec<f64> = (0..d)
        .map(|j| {
            let (lo, hi) = window
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(p[j]), hi.max(p[j]))
                });
            opts.tol_abs + opts.tol_rel * (hi - lo)
        })
        .collect();
    let mut closest = (1, f64::INFINITY);
    for k in 1..=opts.k_max {
        let mismatch = (needed - opts.m..needed)
            .flat_map(|i| {
                let (a, b) = (&window[i], &window[i - k]);
                (0..d).map(|j| (a[j] - b[j]).abs() / tolerance[j])
            })
            .fold(0.0_f64, f64::max);
        if mismatch <= 1.0 {
            return Ok(PeriodAnalysis {
                verdict: PeriodVerdict::Period { k, mismatch },
                tolerance,
            });
        }
        if mismatch < closest.1 {
            closest = (k, mismatch);
        }
    }
    Ok(PeriodAnalysis {
        verdict: PeriodVerdict::NoPeriod {
            k_max: opts.k_max,
            closest_k: closest.0,
            mismatch: closest.1,
        },
        tolerance,
    })
}

fn validate(points: &[Vec<f64>], opts: &PeriodOptions) -> Result<(), AnalysisError> {
    if opts.k_max == 0 {
        return Err(AnalysisError::invalid(
            "k_max",
            "expected a largest period ≥ 1, got 0",
        ));
    }
    if opts.m == 0 {
        return Err(AnalysisError::invalid(
            "m",
            "expected at least 1 trailing point to compare, got 0",
        ));
    }
    let ok = |v: f64| v.is_finite() && v >= 0.0;
    if !(ok(opts.tol_rel) && ok(opts.tol_abs) && opts.tol_rel + opts.tol_abs > 0.0) {
        return Err(AnalysisError::invalid(
            "tolerance",
            format!(
                "expected tol_rel ≥ 0 and tol_abs ≥ 0, not both zero, got tol_rel = {}, tol_abs = {}",
                opts.tol_rel, opts.tol_abs
            ),
        ));
    }
    let Some(first) = points.first() else {
        return Ok(());
    };
    if first.is_empty() {
        return Err(AnalysisError::invalid(
            "points",
            "points have no components",
        ));
    }
    for (i, p) in points.iter().enumerate() {
        if p.len() != first.len() {
            return Err(AnalysisError::invalid(
                "points",
                format!(
                    "point {i} has {} components but point 0 has {}",
                    p.len(),
                    first.len()
                ),
            ));
        }
        check_finite(&format!("point {i}"), p)?;
    }
    Ok(())
}
