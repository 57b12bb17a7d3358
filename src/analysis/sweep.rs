//! Bookkeeping of a parameter sweep (a bifurcation diagram) without running any model: the
//! parameter grid, shards (`--shard i/n`), what is left to do on `--resume`, merging of shard
//! results, and a parallel map over the points (rayon).
//!
//! # Conventions
//! * **Grid.** `steps` intervals from `from` to `to`, both ends included: n = steps + 1 points
//!   p_i = from + (to − from)·i/steps, i = 0..=steps, with p_steps = `to` exactly. Points are
//!   named by their 0-based index i everywhere (results, error messages).
//! * **Shards.** Shard `i/n` has a **1-based** i (1 ≤ i ≤ n, as typed on a command line) and
//!   takes every n-th point starting at index i − 1: {j : j mod n = i − 1}. The n shards
//!   partition the grid, and each shard spreads over the whole parameter range (so shards cost
//!   about the same even when the cost depends on the parameter).
//! * **Resume.** Given the indices already finished (read back from a partial result file), the
//!   points left are the shard's points not among them, ascending. A finished index outside the
//!   shard, or one given twice, is an error (a file of another shard or sweep, or a corrupted
//!   one).
//! * **Merge.** The results of all shards together must hold each grid point exactly once, with
//!   the grid's parameter value (to 1e-9 of max(|from|, |to|), so values written with 10
//!   significant digits pass); otherwise the error names the points out of range, doubled,
//!   disagreeing or missing, checked in that order.
//! * **Parallel map.** [`run_points`] calls the user's closure on every chosen point in the
//!   current rayon thread pool (wrap the call in `ThreadPool::install` to choose the threads),
//!   calls `on_done` for each point as it finishes (in order of completion, one at a time, so it
//!   may append to a file), and returns the results in grid order. [`run_points_until`] also
//!   takes a cancellation check: once it answers true, no further point starts, the points in
//!   flight finish and are reported, and the finished points are returned.
//! * **Continuation.** [`continuation_chunks`] splits the grid into `n` contiguous chunks of
//!   nearly equal length (the first `len mod n` one point longer), each in the sweep's
//!   direction: up (ascending index) or down (descending). [`run_chunks_until`] runs the chunks
//!   in parallel, the points of each in order, handing each point what the one before it in
//!   its chunk left (a warm start); the first point of a chunk starts with nothing. The chunks
//!   are fixed by `n`, not by the threads, so the results do not depend on the threads.

use std::collections::BTreeSet;
use std::fmt;
use std::str::FromStr;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;
use serde::Serialize;

use super::error::AnalysisError;

/// Relative agreement required between a result's parameter and the grid's (see the module
/// documentation).
const PARAMETER_TOL: f64 = 1e-9;

/// Most points a grid may have. Each point is a whole integration (about a second for the
/// Fig. 6a settings of Farahan et al. 2016), so a million points are already weeks of CPU
/// time; a larger count is a typo, and `steps + 1` must not wrap or size an allocation of
/// gigabytes before the first point runs.
pub const MAX_POINTS: usize = 1_000_000;

/// The parameter values of a sweep: `steps` intervals from `from` to `to`, ends included.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ParameterGrid {
    from: f64,
    to: f64,
    steps: usize,
}

impl ParameterGrid {
    /// The grid p_i = from + (to − from)·i/steps, i = 0..=steps. `steps = 0` is one point and
    /// needs from = to. Errors: non-finite ends, steps = 0 with from ≠ to, or more than
    /// [`MAX_POINTS`] points.
    pub fn new(from: f64, to: f64, steps: usize) -> Result<Self, AnalysisError> {
        if steps >= MAX_POINTS {
            return Err(AnalysisError::invalid(
                "parameter grid",
                format!(
                    "expected at most {} steps ({MAX_POINTS} points, each a whole integration), got {steps}",
                    MAX_POINTS - 1
                ),
            ));
        }
        if !(from.is_finite() && to.is_finite()) {
            return Err(AnalysisError::invalid(
                "parameter grid",
                format!("expected finite ends, got from = {from}, to = {to}"),
            ));
        }
        if steps == 0 && from != to {
            return Err(AnalysisError::invalid(
                "parameter grid",
                format!("0 steps give one point, but from = {from} and to = {to} differ"),
            ));
        }
        Ok(Self { from, to, steps })
    }

    /// Number of points, steps + 1.
    #[must_use]
    pub fn len(&self) -> usize {
        self.steps + 1
    }

    /// Always false: a grid has at least one point.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        false
    }

    /// p_i, or `None` if i ≥ [`ParameterGrid::len`].
    #[must_use]
    pub fn value(&self, i: usize) -> Option<f64> {
        if i > self.steps {
            None
        } else if i == self.steps {
            Some(self.to)
        } else {
            Some(self.from + (self.to - self.from) * (i as f64 / self.steps as f64))
        }
    }

    /// All p_i in order.
    #[must_use]
    pub fn values(&self) -> Vec<f64> {
        (0..self.len()).filter_map(|i| self.value(i)).collect()
    }

    /// Largest accepted |p − p_i| for a result's parameter p.
    fn tolerance(&self) -> f64 {
        PARAMETER_TOL * self.from.abs().max(self.to.abs())
    }
}

/// Shard i of n (1-based i); see the module documentation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Shard {
    index: usize,
    count: usize,
}

impl Shard {
    /// Shard `index`/`count` with 1 ≤ index ≤ count.
    pub fn new(index: usize, count: usize) -> Result<Self, AnalysisError> {
        if count == 0 || index == 0 || index > count {
            return Err(AnalysisError::invalid(
                "--shard",
                format!("expected i/n with 1 ≤ i ≤ n (i is 1-based), got {index}/{count}"),
            ));
        }
        Ok(Self { index, count })
    }

    /// The 1-based shard number i.
    #[must_use]
    pub fn index(&self) -> usize {
        self.index
    }

    /// The number of shards n.
    #[must_use]
    pub fn count(&self) -> usize {
        self.count
    }

    /// Whether grid point j (0-based) belongs to this shard: j mod n = i − 1.
    #[must_use]
    pub fn contains(&self, j: usize) -> bool {
        j % self.count == self.index - 1
    }

    /// The shard's point indices in `grid`, ascending.
    #[must_use]
    pub fn select(&self, grid: &ParameterGrid) -> Vec<usize> {
        (self.index - 1..grid.len()).step_by(self.count).collect()
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for Shard {
    type Err = AnalysisError;

    /// Parses `"i/n"` (spaces around the numbers allowed).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let parsed = s
            .split_once('/')
            .and_then(|(i, n)| Some((i.trim().parse().ok()?, n.trim().parse().ok()?)));
        match parsed {
            Some((i, n)) => Self::new(i, n),
            None => Err(AnalysisError::invalid(
                "--shard",
                format!("expected i/n with whole numbers 1 ≤ i ≤ n (e.g. 2/4), got \"{s}\""),
            )),
        }
    }
}

/// The result of one sweep point.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepPoint<T> {
    /// 0-based grid index.
    pub index: usize,
    /// Parameter value p_index.
    pub parameter: f64,
    /// What the user's closure returned.
    pub result: T,
}

/// The points of `shard` (all points if `None`) not in `finished`, ascending (see the module
/// documentation).
///
/// Errors: a finished index outside the grid or the shard, or one listed twice.
pub fn remaining(
    grid: &ParameterGrid,
    shard: Option<&Shard>,
    finished: &[usize],
) -> Result<Vec<usize>, AnalysisError> {
    let mut done = BTreeSet::new();
    let mut doubled = BTreeSet::new();
    for &j in finished {
        if j >= grid.len() {
            return Err(AnalysisError::PointOutOfRange {
                what: "resume",
                index: j,
                n_points: grid.len(),
            });
        }
        if let Some(s) = shard
            && !s.contains(j)
        {
            return Err(AnalysisError::NotInShard {
                index: j,
                shard: s.to_string(),
            });
        }
        if !done.insert(j) {
            doubled.insert(j);
        }
    }
    if !doubled.is_empty() {
        return Err(AnalysisError::DoubledPoints {
            what: "resume",
            indices: doubled.into_iter().collect(),
        });
    }
    let all = shard.map_or_else(|| (0..grid.len()).collect(), |s| s.select(grid));
    Ok(all.into_iter().filter(|j| !done.contains(j)).collect())
}

/// Merges the results of all shards (in any order) into one list in grid order, checking that
/// every grid point is there exactly once with the grid's parameter value (see the module
/// documentation).
pub fn merge<T>(
    grid: &ParameterGrid,
    parts: Vec<Vec<SweepPoint<T>>>,
) -> Result<Vec<SweepPoint<T>>, AnalysisError> {
    const WHAT: &str = "merge";
    let mut all: Vec<SweepPoint<T>> = parts.into_iter().flatten().collect();
    if let Some(p) = all.iter().find(|p| p.index >= grid.len()) {
        return Err(AnalysisError::PointOutOfRange {
            what: WHAT,
            index: p.index,
            n_points: grid.len(),
        });
    }
    all.sort_by_key(|p| p.index);
    let doubled: Vec<usize> = all
        .windows(2)
        .filter(|w| w[0].index == w[1].index)
        .map(|w| w[0].index)
        .collect::<BTreeSet<_>>()
        .into_iter()
        .collect();
    if !doubled.is_empty() {
        return Err(AnalysisError::DoubledPoints {
            what: WHAT,
            indices: doubled,
        });
    }
    let tol = grid.tolerance();
    for p in &all {
        let expected = grid.value(p.index).unwrap_or(f64::NAN);
        if p.parameter.is_nan() || (p.parameter - expected).abs() > tol {
            return Err(AnalysisError::ParameterMismatch {
                what: WHAT,
                index: p.index,
                value: p.parameter,
                expected,
            });
        }
    }
    if all.len() < grid.len() {
        let present: BTreeSet<usize> = all.iter().map(|p| p.index).collect();
        return Err(AnalysisError::MissingPoints {
            what: WHAT,
            indices: (0..grid.len()).filter(|j| !present.contains(j)).collect(),
        });
    }
    Ok(all)
}

/// Computes `compute(index, parameter)` for every point of `indices` in parallel (rayon's
/// current pool), calls `on_done` with each result as it finishes (in order of completion, never
/// two at once), and returns the results in grid order.
///
/// If `on_done` fails (e.g. the partial file cannot be written), points not yet started are
/// skipped, points in flight finish without being reported, and the first error is returned:
/// what `on_done` accepted is exactly what is done, so [`remaining`] loses and doubles nothing.
///
/// Errors: an index outside the grid or given twice ([`AnalysisError`], converted into `E`),
/// or the first error of `on_done`.
pub fn run_points<T, E, C, D>(
    grid: &ParameterGrid,
    indices: &[usize],
    compute: C,
    on_done: D,
) -> Result<Vec<SweepPoint<T>>, E>
where
    T: Send,
    E: Send + From<AnalysisError>,
    C: Fn(usize, f64) -> T + Sync,
    D: FnMut(&SweepPoint<T>) -> Result<(), E> + Send,
{
    run_points_until(grid, indices, compute, on_done, || false)
}

/// [`run_points`] that starts no further point once `cancelled()` answers true (a signal, a
/// deadline): the points in flight finish and are reported to `on_done`, and the points
/// reported are returned, in grid order — fewer than `indices` exactly when cancelled. What
/// `on_done` accepted is what is done, so [`remaining`] continues the sweep.
///
/// Errors: as [`run_points`].
pub fn run_points_until<T, E, C, D, S>(
    grid: &ParameterGrid,
    indices: &[usize],
    compute: C,
    on_done: D,
    cancelled: S,
) -> Result<Vec<SweepPoint<T>>, E>
where
    T: Send,
    E: Send + From<AnalysisError>,
    C: Fn(usize, f64) -> T + Sync,
    D: FnMut(&SweepPoint<T>) -> Result<(), E> + Send,
    S: Fn() -> bool + Sync,
{
    let mut seen = BTreeSet::new();
    let mut points = Vec::with_capacity(indices.len());
    for &j in indices {
        let Some(parameter) = grid.value(j) else {
            return Err(AnalysisError::PointOutOfRange {
                what: "sweep",
                index: j,
                n_points: grid.len(),
            }
            .into());
        };
        if !seen.insert(j) {
            return Err(AnalysisError::DoubledPoints {
                what: "sweep",
                indices: vec![j],
            }
            .into());
        }
        points.push((j, parameter));
    }
    let stop = AtomicBool::new(false);
    let reporter = Mutex::new((on_done, None::<E>));
    let finished: Vec<Option<SweepPoint<T>>> = points
        .par_iter()
        .map(|&(index, parameter)| {
            if stop.load(Ordering::Relaxed) || cancelled() {
                return None;
            }
            let point = SweepPoint {
                index,
                parameter,
                result: compute(index, parameter),
            };
            // A poisoned lock means another point's callback panicked; its state is still
            // usable for reporting this point's result.
            let mut guard = reporter
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            if stop.load(Ordering::Relaxed) {
                return None;
            }
            let (on_done, first_error) = &mut *guard;
            match on_done(&point) {
                Ok(()) => Some(point),
                Err(e) => {
                    stop.store(true, Ordering::Relaxed);
                    *first_error = Some(e);
                    None
                }
            }
        })
        .collect();
    let (_, first_error) = reporter
        .into_inner()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some(e) = first_error {
        return Err(e);
    }
    let mut results: Vec<SweepPoint<T>> = finished.into_iter().flatten().collect();
    results.sort_by_key(|p| p.index);
    Ok(results)
}

/// Direction of a continuation sweep through the grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    /// Ascending index (parameter from `from` to `to`).
    Up,
    /// Descending index.
    Down,
}

impl fmt::Display for Direction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Direction::Up => "up",
            Direction::Down => "down",
        })
    }
}

/// A contiguous run of grid points swept in one direction, each point starting from the one
/// before it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Chunk {
    /// The direction.
    pub direction: Direction,
    /// Grid indices in the order they run.
    pub indices: Vec<usize>,
}

/// The grid split into `n_chunks` contiguous chunks in `direction` (module documentation).
///
/// Errors: `n_chunks` zero or above the number of points.
pub fn continuation_chunks(
    grid: &ParameterGrid,
    n_chunks: usize,
    direction: Direction,
) -> Result<Vec<Chunk>, AnalysisError> {
    let n = grid.len();
    if n_chunks == 0 || n_chunks > n {
        return Err(AnalysisError::invalid(
            "--chunks",
            format!("expected 1 to {n} chunks (one grid point at least in each), got {n_chunks}"),
        ));
    }
    let (base, extra) = (n / n_chunks, n % n_chunks);
    let mut start = 0;
    let mut chunks = Vec::with_capacity(n_chunks);
    for c in 0..n_chunks {
        let len = base + usize::from(c < extra);
        let mut indices: Vec<usize> = (start..start + len).collect();
        if direction == Direction::Down {
            indices.reverse();
        }
        chunks.push(Chunk { direction, indices });
        start += len;
    }
    if direction == Direction::Down {
        chunks.reverse();
    }
    Ok(chunks)
}

/// The points of a continuation sweep with their directions, as [`run_chunks_until`] returns
/// them.
pub type ChunkPoints<T> = Vec<(Direction, SweepPoint<T>)>;

/// Runs `chunks` in parallel (rayon's current pool), the points of each in order:
/// `compute(direction, index, parameter, previous)` gets what the point before it in its
/// chunk returned as its second value (`None` for a chunk's first point), and returns its
/// result and what the next point starts from. `on_done` gets each point as it finishes
/// (never two at once), and the points are returned sorted by direction, then index.
///
/// `starts` (one per chunk, or empty for none) is what each chunk's first point starts from:
/// a resumed chunk carries on from its last finished point.
///
/// As [`run_points_until`]: once `cancelled()` answers true or `on_done` fails, no further
/// point starts, and what `on_done` accepted is exactly what is returned.
///
/// Errors: an index outside the grid or given twice in one direction, or the first error of
/// `on_done`.
pub fn run_chunks_until<T, W, E, C, D, S>(
    grid: &ParameterGrid,
    chunks: &[Chunk],
    starts: Vec<Option<W>>,
    compute: C,
    on_done: D,
    cancelled: S,
) -> Result<ChunkPoints<T>, E>
where
    T: Send,
    W: Send,
    E: Send + From<AnalysisError>,
    C: Fn(Direction, usize, f64, Option<&W>) -> (T, Option<W>) + Sync,
    D: FnMut(Direction, &SweepPoint<T>) -> Result<(), E> + Send,
    S: Fn() -> bool + Sync,
{
    let mut seen = BTreeSet::new();
    for chunk in chunks {
        for &j in &chunk.indices {
            if j >= grid.len() {
                return Err(AnalysisError::PointOutOfRange {
                    what: "sweep",
                    index: j,
                    n_points: grid.len(),
                }
                .into());
            }
            if !seen.insert((chunk.direction, j)) {
                return Err(AnalysisError::DoubledPoints {
                    what: "sweep",
                    indices: vec![j],
                }
                .into());
            }
        }
    }
    let mut starts = starts;
    starts.resize_with(chunks.len(), || None);
    let stop = AtomicBool::new(false);
    let reporter = Mutex::new((on_done, None::<E>));
    let finished: Vec<ChunkPoints<T>> = chunks
        .par_iter()
        .zip(starts)
        .map(|(chunk, start)| {
            let mut done = Vec::with_capacity(chunk.indices.len());
            let mut previous: Option<W> = start;
            for &index in &chunk.indices {
                if stop.load(Ordering::Relaxed) || cancelled() {
                    break;
                }
                let parameter = grid.value(index).unwrap_or(f64::NAN);
                let (result, next) = compute(chunk.direction, index, parameter, previous.as_ref());
                previous = next;
                let point = SweepPoint {
                    index,
                    parameter,
                    result,
                };
                // A poisoned lock means another point's callback panicked; its state is still
                // usable for reporting this point's result.
                let mut guard = reporter
                    .lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner);
                if stop.load(Ordering::Relaxed) {
                    break;
                }
                let (on_done, first_error) = &mut *guard;
                match on_done(chunk.direction, &point) {
                    Ok(()) => done.push((chunk.direction, point)),
                    Err(e) => {
                        stop.store(true, Ordering::Relaxed);
                        *first_error = Some(e);
                        break;
                    }
                }
            }
            done
        })
        .collect();
    let (_, first_error) = reporter
        .into_inner()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some(e) = first_error {
        return Err(e);
    }
    let mut results: ChunkPoints<T> = finished.into_iter().flatten().collect();
    results.sort_by_key(|(d, p)| (*d, p.index));
    Ok(results)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_are_contiguous_and_cover_the_grid_once() {
        let grid = ParameterGrid::new(0.0, 1.0, 9);
        let Ok(grid) = grid else {
            panic!("{grid:?}");
        };
        let up = continuation_chunks(&grid, 3, Direction::Up)
            .map(|c| c.into_iter().map(|c| c.indices).collect::<Vec<_>>());
        assert_eq!(
            up.ok(),
            Some(vec![vec![0, 1, 2, 3], vec![4, 5, 6], vec![7, 8, 9]])
        );
        let down = continuation_chunks(&grid, 3, Direction::Down)
            .map(|c| c.into_iter().map(|c| c.indices).collect::<Vec<_>>());
        assert_eq!(
            down.ok(),
            Some(vec![vec![9, 8, 7], vec![6, 5, 4], vec![3, 2, 1, 0]])
        );
        for bad in [0, 11] {
            let e = continuation_chunks(&grid, bad, Direction::Up)
                .err()
                .map(|e| e.to_string());
            assert_eq!(
                e,
                Some(format!(
                    "invalid --chunks: expected 1 to 10 chunks (one grid point at least in each), got {bad}"
                ))
            );
        }
    }

    #[test]
    fn chunk_points_start_from_their_predecessor_whatever_the_threads() {
        // Each point returns the index of the point it started from: the one before it in its
        // chunk, or none for the chunk's first.
        let grid = ParameterGrid::new(0.0, 1.0, 9);
        let Ok(grid) = grid else {
            panic!("{grid:?}");
        };
        let mut chunks = continuation_chunks(&grid, 3, Direction::Up).unwrap_or_default();
        chunks.extend(continuation_chunks(&grid, 3, Direction::Down).unwrap_or_default());
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build();
            let Ok(pool) = pool else {
                panic!("no thread pool");
            };
            let got: Result<ChunkPoints<Option<usize>>, AnalysisError> = pool.install(|| {
                run_chunks_until(
                    &grid,
                    &chunks,
                    Vec::new(),
                    |_, i, _, previous: Option<&usize>| (previous.copied(), Some(i)),
                    |_, _| Ok(()),
                    || false,
                )
            });
            got.unwrap_or_default()
                .into_iter()
                .map(|(d, p)| (d, p.index, p.result))
                .collect::<Vec<_>>()
        };
        let one = run(1);
        assert_eq!(one.len(), 20, "every point of both directions: {one:?}");
        let from = |d: Direction, i: usize| {
            one.iter()
                .find(|(dd, ii, _)| *dd == d && *ii == i)
                .and_then(|p| p.2)
        };
        assert_eq!(from(Direction::Up, 0), None);
        assert_eq!(from(Direction::Up, 3), Some(2));
        assert_eq!(
            from(Direction::Up, 4),
            None,
            "a chunk's first point starts cold"
        );
        assert_eq!(from(Direction::Down, 9), None);
        assert_eq!(from(Direction::Down, 0), Some(1));
        assert_eq!(from(Direction::Down, 3), None);
        assert_eq!(run(3), one, "results do not depend on the threads");
    }

    #[test]
    fn grid_ends_are_exact() {
        let g = ParameterGrid::new(0.1, 0.7, 6);
        let Ok(g) = g else {
            panic!("{g:?}");
        };
        assert_eq!(g.len(), 7);
        assert_eq!(g.value(0), Some(0.1));
        assert_eq!(g.value(6), Some(0.7));
        assert_eq!(g.value(7), None);
        let v = g.values();
        for (i, p) in v.iter().enumerate() {
            assert!((p - (0.1 + 0.1 * i as f64)).abs() < 1e-15, "p_{i} = {p}");
        }
        let one = ParameterGrid::new(2.0, 2.0, 0).map(|g| g.values());
        assert_eq!(one.ok(), Some(vec![2.0]));
        let e = ParameterGrid::new(1.0, 2.0, 0).err().map(|e| e.to_string());
        assert_eq!(
            e.as_deref(),
            Some("invalid parameter grid: 0 steps give one point, but from = 1 and to = 2 differ")
        );
        // The largest grid, and one more point: refused before anything is sized by it.
        assert_eq!(
            ParameterGrid::new(0.0, 1.0, MAX_POINTS - 1)
                .ok()
                .map(|g| g.len()),
            Some(MAX_POINTS)
        );
        for steps in [MAX_POINTS, usize::MAX] {
            let e = ParameterGrid::new(0.0, 1.0, steps)
                .err()
                .map(|e| e.to_string());
            assert_eq!(
                e,
                Some(format!(
                    "invalid parameter grid: expected at most 999999 steps (1000000 points, each a whole integration), got {steps}"
                ))
            );
        }
    }

    #[test]
    fn shards_parse_one_based() {
        let s: Result<Shard, _> = "2/4".parse();
        assert_eq!(
            s.as_ref().ok().map(ToString::to_string).as_deref(),
            Some("2/4")
        );
        assert_eq!(s.ok().map(|s| (s.index(), s.count())), Some((2, 4)));
        for bad in ["0/4", "5/4", "1/0"] {
            let e = bad.parse::<Shard>().err().map(|e| e.to_string());
            let (i, n) = bad.split_once('/').unwrap_or_default();
            assert_eq!(
                e,
                Some(format!(
                    "invalid --shard: expected i/n with 1 ≤ i ≤ n (i is 1-based), got {i}/{n}"
                )),
                "{bad}"
            );
        }
        let e = "two/4".parse::<Shard>().err().map(|e| e.to_string());
        assert_eq!(
            e.as_deref(),
            Some(
                "invalid --shard: expected i/n with whole numbers 1 ≤ i ≤ n (e.g. 2/4), got \"two/4\""
            )
        );
    }

    #[test]
    fn cancelled_sweeps_report_exactly_what_they_return() {
        // Cancelled once three points are reported: with two threads a fourth point may be in
        // flight; it finishes and is reported too, and nothing else starts.
        let grid = ParameterGrid::new(0.0, 1.0, 9);
        let Ok(grid) = grid else {
            panic!("{grid:?}");
        };
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build();
        let Ok(pool) = pool else {
            panic!("no thread pool");
        };
        let cancel = AtomicBool::new(false);
        let mut reported = Vec::new();
        let all: Vec<usize> = (0..grid.len()).collect();
        let got: Result<Vec<SweepPoint<f64>>, AnalysisError> = pool.install(|| {
            run_points_until(
                &grid,
                &all,
                |_, p| 2.0 * p,
                |p| {
                    reported.push(p.index);
                    if reported.len() >= 3 {
                        cancel.store(true, Ordering::SeqCst);
                    }
                    Ok(())
                },
                || cancel.load(Ordering::SeqCst),
            )
        });
        let Ok(got) = got else {
            panic!("{got:?}");
        };
        let returned: Vec<usize> = got.iter().map(|p| p.index).collect();
        reported.sort_unstable();
        assert_eq!(returned, reported, "returned vs reported points");
        assert!(
            (3..=4).contains(&returned.len()),
            "3 reported before the cancellation and at most one in flight, got {returned:?}"
        );
        assert!(
            got.iter().all(|p| p.result == 2.0 * p.parameter),
            "results kept with their points: {got:?}"
        );
        let left = remaining(&grid, None, &returned);
        assert_eq!(
            left.map(|l| l.len()).ok(),
            Some(grid.len() - returned.len()),
            "resume runs the rest"
        );
    }
}
