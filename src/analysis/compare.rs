//! Differences between two runs of the same model (e.g. two formulations) sampled on the same
//! grid: largest difference per common column, and the pairing of their impacts. Runs are
//! anything [`Sampled`]: a [`Recorder`] of the stepping driver, a simulation's `Trajectory`.
//! (`studies::compare_formulations` runs the DAE and the reduced formulation and compares them.)

use crate::formulation::Crossing;
use crate::solve::{EventRecord, Recorder};
use serde::Serialize;

/// Largest difference of one column between two runs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ColumnDifference {
    /// Column name.
    pub column: String,
    /// max |a − b| over the common samples.
    pub max_abs_difference: f64,
    /// Time of that largest difference (s).
    pub at_t: f64,
    /// max |a| over the samples: the scale to judge the difference by.
    pub max_abs_value: f64,
}

/// Everything [`compare`] finds.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Comparison {
    /// Number of common samples compared.
    pub samples: usize,
    /// Per common column, in the first run's column order.
    pub columns: Vec<ColumnDifference>,
    /// Impacts (Rising events) of each event index in run a.
    pub impacts_a: Vec<usize>,
    /// Impacts of each event index in run b.
    pub impacts_b: Vec<usize>,
    /// max |t_a − t_b| over impacts paired in order, per event index (s); `None` where the
    /// counts differ or there are none.
    pub max_impact_time_difference: Vec<Option<f64>>,
}

impl Comparison {
    /// The difference of a column by name.
    pub fn column(&self, name: &str) -> Option<&ColumnDifference> {
        self.columns.iter().find(|c| c.column == name)
    }
}

/// A sampled run that [`compare()`] can read: a [`Recorder`] or a
/// [`Trajectory`](crate::simulation::Trajectory).
pub trait Sampled {
    /// Column names.
    fn names(&self) -> &[String];
    /// Number of samples.
    fn samples(&self) -> usize;
    /// Time of sample i (s); i < `samples()`.
    fn time(&self, i: usize) -> f64;
    /// Value of column k at sample i; i < `samples()`, k < `names().len()`.
    fn value(&self, i: usize, k: usize) -> f64;
    /// Located events.
    fn events(&self) -> &[EventRecord];
}

impl Sampled for Recorder {
    fn names(&self) -> &[String] {
        &self.names
    }
    fn samples(&self) -> usize {
        self.len()
    }
    fn time(&self, i: usize) -> f64 {
        self.t[i]
    }
    fn value(&self, i: usize, k: usize) -> f64 {
        self.row(i)[k]
    }
    fn events(&self) -> &[EventRecord] {
        &self.events
    }
}

fn impact_times(run: &impl Sampled, index: usize) -> Vec<f64> {
    run.events()
        .iter()
        .filter(|e| e.index == index && e.crossing == Crossing::Rising)
        .map(|e| e.t)
        .collect()
}

/// Compares runs `a` and `b` sample by sample (they must share the output grid: the first
/// min(len) samples are compared) and their impacts for `n_events` event indices.
pub fn compare(a: &impl Sampled, b: &impl Sampled, n_events: usize) -> Comparison {
    let samples = a.samples().min(b.samples());
    let mut columns = Vec::new();
    for (ka, name) in a.names().iter().enumerate() {
        let Some(kb) = b.names().iter().position(|n| n == name) else {
            continue;
        };
        let mut diff = ColumnDifference {
            column: name.clone(),
            max_abs_difference: 0.0,
            at_t: 0.0,
            max_abs_value: 0.0,
        };
        for i in 0..samples {
            let (va, vb) = (a.value(i, ka), b.value(i, kb));
            let d = (va - vb).abs();
            if d > diff.max_abs_difference || d.is_nan() {
                diff.max_abs_difference = d;
                diff.at_t = a.time(i);
            }
            diff.max_abs_value = diff.max_abs_value.max(va.abs());
        }
        columns.push(diff);
    }
    let impacts: Vec<(Vec<f64>, Vec<f64>)> = (0..n_events)
        .map(|k| (impact_times(a, k), impact_times(b, k)))
        .collect();
    Comparison {
        samples,
        columns,
        impacts_a: impacts.iter().map(|(x, _)| x.len()).collect(),
        impacts_b: impacts.iter().map(|(_, y)| y.len()).collect(),
        max_impact_time_difference: impacts
            .iter()
            .map(|(x, y)| {
                (x.len() == y.len() && !x.is_empty()).then(|| {
                    x.iter()
                        .zip(y)
                        .map(|(p, q)| (p - q).abs())
                        .fold(0.0, f64::max)
                })
            })
            .collect(),
    }
}
