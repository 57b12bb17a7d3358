//! Analyses of finished runs; each returns plain data (no files, no printing).

pub mod compare;

pub use compare::{
    ColumnDifference, Comparison, FormulationComparison, Sampled, compare, compare_formulations,
};
