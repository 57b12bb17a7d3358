//! `linkdyn reproduce`: the analogues of Figs. 3–7 of Farahan, Ghazavi & Rahmanian (2016) for
//! each friction variant, with the numbers behind each figure and a verdict on each of the
//! paper's claims ([`report`]). The figures are drawn with [`crate::plot`]'s builders; the
//! numbers come from [`crate::simulation`] and [`crate::simulation::analyses`].
//!
//! | figure | what | model changes |
//! |---|---|---|
//! | 3 | rocker acceleration, crank torque against the ideal joint; journal orbit | c = 0.2 mm |
//! | 4 | coupler acceleration against the ideal joint; journal orbit | 250 and 3500 rpm |
//! | 5 | Poincaré section of the journal, amplitude spectrum, period verdict, Lyapunov exponent | 250 rpm |
//! | 6 | bifurcation of the journal's x eccentricity against c; section and spectrum at c = 0.44 mm | 3500 rpm |
//! | 7 | phase portraits of the journal's x eccentricity | 250 and 3500 rpm |
//!
//! Friction variants ([`Variant`]): Ambrósio's law as intended, no friction, and eq. 11 as printed
//! (`contact::friction::ambrosio_as_printed`). The clearance runs use the reduced formulation (the
//! paper's model); the ideal reference is the same file with `--ideal B`, in the DAE (the reduced
//! formulation needs a clearance joint).
//!
//! **Solvers.** Every computation first tries DOP853 at rtol 1e-8, atol 1e-10. Where it stops
//! (the frictionless joint at 3500 rpm has long stiff contact phases; the as-printed law sticks
//! at v_t = 0, a Filippov sliding motion whose sign switches no adaptive step can pass), it is
//! retried with Radau5 at the same tolerances, then with DOP853 at a fixed step of
//! [`FIXED_STEP`] (no error control; stick phases then chatter from step to step, as a literal
//! fixed-step implementation of the printed law would). The report names the solver behind
//! every number.
//!
//! Fig. 6a keeps this order although Radau5 computes its intended-friction sweep in about
//! 30 % less CPU time with section points within 3e-7 m of DOP853's: at c ≈ 0.41 mm, where a
//! period-2 oscillation decays over the whole run (a nearby period doubling), the period
//! verdict of one point is borderline and flips with the method (docs/reproduce.md).
//!
//! # References
//! 1. S. B. Farahan, M. R. Ghazavi, S. Rahmanian, Nonlinear dynamic analysis of a four-bar
//!    mechanism having revolute joint with clearance, *Journal of Theoretical and Applied Vibration
//!    and Acoustics* (2016), <https://tava.isav.ir/article_19881.html>.

mod experiments;
mod figures;
pub mod report;

pub use experiments::{Findings, VariantFindings, reproduce};

use crate::solve::{Method, SolverOptions};
use serde::Serialize;
use std::path::PathBuf;

/// Step of the last-resort fixed-step solver (s): 1e-5 s resolves the contact oscillation
/// (period ≈ 4e-4 s at the reference stiffness) with ~40 steps and keeps DOP853 stable.
pub const FIXED_STEP: f64 = 1e-5;

/// A friction law of the clearance joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Variant {
    /// Ambrósio's law as intended (`"ambrosio"`).
    Intended,
    /// No friction (`"none"`).
    Frictionless,
    /// Eq. 11 as printed (`"ambrosio-as-printed"`).
    AsPrinted,
}

impl Variant {
    /// The three variants, in report order.
    pub const ALL: [Variant; 3] = [Variant::Intended, Variant::Frictionless, Variant::AsPrinted];

    /// The friction law's name in a model file.
    pub fn law(self) -> &'static str {
        match self {
            Variant::Intended => "ambrosio",
            Variant::Frictionless => "none",
            Variant::AsPrinted => "ambrosio-as-printed",
        }
    }

    /// A short label for tables and file names.
    pub fn label(self) -> &'static str {
        match self {
            Variant::Intended => "intended",
            Variant::Frictionless => "frictionless",
            Variant::AsPrinted => "as-printed",
        }
    }
}

/// A solver attempt: its description and options.
#[derive(Debug, Clone)]
pub struct Attempt {
    /// E.g. "DOP853, rtol 1e-8".
    pub name: String,
    /// The options.
    pub solver: SolverOptions,
}

/// The solvers tried in order (module docs).
pub fn attempts() -> Vec<Attempt> {
    let adaptive = |m: Method| SolverOptions::default().method(m).rtol(1e-8).atol(1e-10);
    vec![
        Attempt {
            name: "DOP853, rtol 1e-8".into(),
            solver: adaptive(Method::Dop853),
        },
        Attempt {
            name: "Radau5, rtol 1e-8".into(),
            solver: adaptive(Method::Radau5),
        },
        Attempt {
            name: format!("DOP853, fixed step {FIXED_STEP:e} s"),
            solver: SolverOptions::default()
                .method(Method::Dop853)
                .fixed_step(FIXED_STEP),
        },
    ]
}

/// What to reproduce and how long.
#[derive(Debug, Clone)]
pub struct ReproduceOptions {
    /// The paper's model (`models/farahan2016.toml`).
    pub model: PathBuf,
    /// Short runs (CI): fewer turns and sweep points; the verdicts still have enough points.
    pub quick: bool,
}

/// Turn counts of one reproduction ([`Plan::quick`] or [`Plan::full`]).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Plan {
    /// Driver turns of the time histories (Figs. 3, 4).
    pub history_turns: f64,
    /// Section turns and transient at 250 rpm.
    pub section_250: (usize, usize),
    /// Section turns and transient at 3500 rpm.
    pub section_3500: (usize, usize),
    /// Turns and transient (turns) of the spectra and phase portraits at 250 rpm.
    pub signal_250: (f64, f64),
    /// The same at 3500 rpm.
    pub signal_3500: (f64, f64),
    /// Lyapunov turns and transient at 250 rpm.
    pub lyapunov_250: (f64, f64),
    /// Bifurcation points (intended friction), turns and transient.
    pub bifurcation: (usize, usize, usize),
    /// Bifurcation points of the other variants: the as-printed law needs the fixed-step
    /// fallback at 3500 rpm, some 50 times the cost of a point with the intended law.
    pub bifurcation_others: usize,
    /// Turns of the twin runs (1e-12 m apart).
    pub twin_turns: f64,
}

impl Plan {
    /// `--quick`: under two minutes; 26 section points (enough for "no period up to 8").
    pub fn quick() -> Self {
        Plan {
            history_turns: 2.0,
            section_250: (32, 6),
            section_3500: (40, 14),
            signal_250: (10.0, 2.0),
            signal_3500: (30.0, 10.0),
            lyapunov_250: (12.0, 2.0),
            bifurcation: (6, 30, 20),
            bifurcation_others: 6,
            twin_turns: 4.0,
        }
    }

    /// The full run: the paper's Fig. 6a sweep (200 clearances, 150 turns, 100 transient).
    pub fn full() -> Self {
        Plan {
            history_turns: 2.0,
            section_250: (150, 50),
            section_3500: (150, 100),
            signal_250: (60.0, 10.0),
            signal_3500: (150.0, 100.0),
            lyapunov_250: (60.0, 10.0),
            bifurcation: (200, 150, 100),
            bifurcation_others: 40,
            twin_turns: 4.0,
        }
    }
}
