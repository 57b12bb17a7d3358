//! Tools that analyse runs and formulations; each returns plain data (no files, no printing).
//! They sit below [`crate::simulation`], which uses them (a Poincaré section, a spectrum of its
//! output); the studies that build whole simulations are in [`crate::studies`].
//!
//! | file | job |
//! |---|---|
//! | [`compare`](mod@compare) | differences between two runs of the same model |
//! | [`spectrum`] | one-sided amplitude spectrum (FFT) and its dominant peaks |
//! | [`poincare`] | stroboscopic Poincaré section of a driven formulation |
//! | [`period`] | period-k verdict on a sequence of Poincaré points |
//! | [`lyapunov`] | largest Lyapunov exponent (two trajectories, renormalisation) |
//! | [`orbit`] | periodic orbits by shooting, monodromy with saltation, Floquet multipliers |
//! | [`phase`] | phase-portrait data (value against rate) |
//! | [`sweep`] | parameter-sweep bookkeeping: grid, shards, resume, merge, parallel map |
//! | [`error`] | [`AnalysisError`] |

pub mod compare;
pub mod error;
pub mod lyapunov;
pub mod orbit;
pub mod period;
pub mod phase;
pub mod poincare;
pub mod spectrum;
pub mod sweep;

pub use compare::{ColumnDifference, Comparison, Sampled, compare};
pub use error::AnalysisError;
pub use lyapunov::{LyapunovEstimate, LyapunovOptions, largest_lyapunov};
pub use orbit::{OrbitOptions, PeriodicOrbit, periodic_orbit};
pub use period::{PeriodAnalysis, PeriodOptions, PeriodVerdict, period_verdict};
pub use phase::{PhasePortrait, RateSource, phase_portrait};
pub use poincare::{
    PoincareSection, SectionOptions, SettledSection, Settling, section_outputs,
    section_outputs_settling, section_states,
};
pub use spectrum::{Peak, Spectrum, SpectrumOptions, Window, amplitude_spectrum};
pub use sweep::{
    Chunk, ChunkPoints, Direction, MAX_POINTS, ParameterGrid, Shard, SweepPoint,
    continuation_chunks, merge, remaining, run_chunks_until, run_points, run_points_until,
};
