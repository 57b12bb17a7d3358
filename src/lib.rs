//! # linkdyn
//!
//! Dynamics of planar linkages whose revolute joints may have clearance.
//!
//! One straight path through the crate: model file → [`model::Model`] ([`model::load`]) →
//! [`simulation::Simulation`] (formulation, end time, sampling and solver settings, all checked
//! before any work) → samples streamed to a [`simulation::SampleSink`] (a CSV file:
//! [`output::CsvSink`]) or kept as a [`simulation::Trajectory`] → [`analysis`] and result files
//! ([`output`]); studies of many runs (work against precision, the stress table, the two
//! formulations compared) in [`studies`]. Every run returns a [`simulation::RunSummary`]: provenance, solver statistics,
//! constraint violation, per clearance joint the impacts and contact maxima, and with the
//! energy bookkeeping the work–energy balance.
//!
//! Underneath: formulations ([`formulation::Dae`] for any model,
//! [`formulation::ReducedLagrangian`] for the reference four-bar with a clearance joint), the
//! integrator ([`solve::integrate()`], DOPRI5 or DOP853 with event location), contact and
//! friction laws ([`contact`]). Figures: [`plot`]; the mechanism drawn at an instant and
//! animated (HTML player, animated SVG, GIF): [`animate`].
//!
//! ```
//! use linkdyn::simulation::{Simulation, SimulationOptions};
//!
//! // Two crank turns (0.48 s at 250 rpm) of the reference four-bar with ideal joints,
//! // sampled every millisecond.
//! let model = linkdyn::model::load("models/fourbar_ideal.toml".as_ref(), &[])?;
//! let sim = Simulation::new(&model, SimulationOptions::default().revs(2.0).dt(1e-3))?;
//! let run = sim.run_to_memory()?;
//! let torque = run.column("motor.torque").unwrap_or_default();
//! assert_eq!(torque.len(), 481);
//! println!(
//!     "{} steps; crank torque at t = 0: {:.4} N·m; max |Phi| = {:.1e}",
//!     run.stats().steps,
//!     torque[0],
//!     run.summary.max_constraint_violation
//! );
//! # Ok::<(), linkdyn::Error>(())
//! ```
#![warn(missing_docs)]
// Index loops over the x, y, φ components mirror the equations they implement.
#![allow(clippy::needless_range_loop)]

pub mod analysis;
pub mod animate;
pub mod contact;
pub mod error;
pub mod formulation;
pub mod linalg;
pub mod mechanics;
pub mod model;
pub mod numbers;
pub mod output;
pub mod plot;
pub mod reproduce;
pub mod simulation;
pub mod solve;
pub mod studies;
pub(crate) mod trig;

pub use error::{Error, Result};

/// Version of this build: crate version and git commit (from `build.rs`).
pub fn version() -> String {
    format!(
        "{} ({})",
        env!("CARGO_PKG_VERSION"),
        env!("LINKDYN_GIT_COMMIT")
    )
}
