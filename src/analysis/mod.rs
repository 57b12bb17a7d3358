//! Analyses of finished runs and of formulations; each returns plain data (no files, no
//! printing).
//!
//! | file | job |
//! |---|---|
//! | [`compare`](mod@compare) | differences between two runs of the same model |
//! | [`spectrum`] | one-sided amplitude spectrum (FFT) and its dominant peaks |
//! | [`poincare`] | stroboscopic Poincaré section of a driven formulation |
//! | [`period`] | period-k verdict on a sequence of Poincaré points |
//! | [`lyapunov`] | largest Lyapunov exponent (two trajectories, renormalisation) |
//! | [`phase`] | phase-portrait data (value against rate) |
//! | [`stress`] | stress table: extreme cases × formulations × methods, a verdict each |
//! | [`sweep`] | parameter-sweep bookkeeping: grid, shards, resume, merge, parallel map |
//! | [`workprecision`] | error against cost for every formulation × method × tolerance |
//! | [`error`] | [`AnalysisError`] |

pub mod compare;
pub mod error;
pub mod lyapunov;
pub mod period;
pub mod phase;
pub mod poincare;
pub mod spectrum;
pub mod stress;
pub mod sweep;
pub mod workprecision;

pub use compare::{
    ColumnDifference, Comparison, FormulationComparison, Sampled, compare, compare_formulations,
};
pub use error::AnalysisError;
pub use lyapunov::{LyapunovEstimate, LyapunovOptions, largest_lyapunov};
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
