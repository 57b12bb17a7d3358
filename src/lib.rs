//! # linkdyn
//!
//! Dynamics of planar linkages whose revolute joints may have clearance.
//!
//! One straight path through the crate: model file → [`model::Model`] ([`model::load`]) →
//! formulation ([`formulation::Dae`] for any model, [`formulation::ReducedLagrangian`] for the
//! reference four-bar with a clearance joint) → integrator ([`solve::integrate()`], DOPRI5 or
//! DOP853 with event location) → sampled trajectory ([`solve::Recorder`]) → [`analysis`] and
//! result files ([`output`]). Clearance-joint contact and friction laws are in [`contact`].
//!
//! ```
//! use linkdyn::formulation::{Dae, DaeOptions, Formulation};
//! use linkdyn::solve::Recorder;
//! use linkdyn::solve::{integrate, SolverOptions};
//!
//! // Two crank turns (0.48 s at 250 rpm) of the reference four-bar with ideal joints.
//! let model = linkdyn::model::load("models/fourbar_ideal.toml".as_ref(), &[])?;
//! let mut dae = Dae::new(&model, &DaeOptions::default())?;
//! let y0 = dae.initial_state();
//! let mut samples = Recorder::new(&dae);
//! let stats = integrate(&mut dae, 0.0, &y0, 0.48, 1e-3, &SolverOptions::default(), &mut samples)?;
//! let torque = samples.column("motor.torque").unwrap_or_default();
//! assert_eq!(torque.len(), 481);
//! println!("{} steps; crank torque at t = 0: {:.4} N·m", stats.steps, torque[0]);
//! # Ok::<(), linkdyn::Error>(())
//! ```
#![warn(missing_docs)]
// Index loops over the x, y, φ components mirror the equations they implement.
#![allow(clippy::needless_range_loop)]

pub mod analysis;
pub mod cli;
pub mod contact;
pub mod error;
pub mod formulation;
pub mod mechanics;
pub mod model;
pub mod output;
pub mod solve;

pub use error::{Error, Result};

/// Version of this build: crate version and git commit (from `build.rs`).
pub fn version() -> String {
    format!(
        "{} ({})",
        env!("CARGO_PKG_VERSION"),
        env!("LINKDYN_GIT_COMMIT")
    )
}
