//! Studies: many simulations of a model, run and judged together. They build
//! [`Simulation`](crate::simulation::Simulation)s, so they sit above [`crate::simulation`] (the
//! tools that a simulation itself uses are in [`crate::analysis`]).
//!
//! | file | job |
//! |---|---|
//! | [`contact_laws`] | one scene run once per contact law of a clearance joint, compared |
//! | [`continuation`](mod@continuation) | a periodic orbit continued in one model field, its special points |
//! | [`formulations`] | the DAE and the reduced formulation of one model, run and compared |
//! | [`orbit`](mod@orbit) | a periodic orbit by shooting, its Floquet multipliers and one period of it |
//! | [`stress`] | stress table: extreme cases × formulations × methods, a verdict each |
//! | [`workprecision`] | error against cost for every formulation × method × tolerance |

pub mod contact_laws;
pub mod continuation;
pub mod formulations;
pub mod orbit;
pub mod stress;
pub mod wear;
pub mod workprecision;

pub use contact_laws::{LawComparison, compare_contact_laws};
pub use formulations::{FormulationComparison, compare_formulations};
pub use orbit::{OrbitPeriod, OrbitRequest, OrbitResult, orbit};
pub use wear::{WearRequest, WearResult, wear};
