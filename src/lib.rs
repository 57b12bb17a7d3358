//! # linkdyn
//!
//! Dynamics of planar linkages whose revolute joints may have clearance.
//!
//! One straight path through the crate: model file → [`model::Model`] → formulation
//! ([`formulation::Dae`]) → integrator ([`solve::integrate`]) → samples → [`output`].
//!
//! ```no_run
//! use linkdyn::formulation::{Dae, DaeOptions};
//! use linkdyn::solve::{integrate, SolverOptions, Samples};
//!
//! let model = linkdyn::model::load("models/fourbar_ideal.toml".as_ref(), &[])?;
//! let mut dae = Dae::new(&model, &DaeOptions::default())?;
//! let y0 = linkdyn::formulation::Formulation::initial_state(&dae);
//! let mut samples = Samples::default();
//! let stats = integrate(&mut dae, 0.0, &y0, 0.48, 1e-3, &SolverOptions::default(), &mut samples)?;
//! println!("{} steps, {} samples", stats.steps, samples.t.len());
//! # Ok::<(), linkdyn::Error>(())
//! ```
#![warn(missing_docs)]

pub mod error;
pub mod formulation;
pub mod mechanics;
pub mod model;
pub mod output;
pub mod solve;

pub use error::{Error, Result};

/// Version of this build: crate version and git commit (from `build.rs`).
pub fn version() -> String {
    format!("{} ({})", env!("CARGO_PKG_VERSION"), env!("LINKDYN_GIT_COMMIT"))
}
