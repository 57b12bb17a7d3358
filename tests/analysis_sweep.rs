//! Parameter-sweep bookkeeping (`linkdyn::analysis::sweep`): shards partition the grid, a
//! resumed run loses and doubles nothing, merge names the points that are wrong, and the
//! parallel map reports points as they finish and returns them in grid order.

use std::sync::mpsc;
use std::time::Duration;

use linkdyn::analysis::AnalysisError;
use linkdyn::analysis::sweep::{ParameterGrid, Shard, SweepPoint, merge, remaining, run_points};

fn grid(steps: usize) -> ParameterGrid {
    match ParameterGrid::new(0.1e-3, 0.5e-3, steps) {
        Ok(g) => g,
        Err(e) => panic!("{e}"),
    }
}

fn shard(i: usize, n: usize) -> Shard {
    match Shard::new(i, n) {
        Ok(s) => s,
        Err(e) => panic!("{e}"),
    }
}

/// A stand-in for a model run: a number that depends on the point.
fn compute(index: usize, p: f64) -> f64 {
    p * 1e3 + index as f64
}

#[test]
fn shards_partition_the_grid() {
    let single = ParameterGrid::new(0.2e-3, 0.2e-3, 0).map_err(|e| e.to_string());
    let Ok(single) = single else {
        panic!("{single:?}");
    };
    for g in [single, grid(1), grid(6), grid(20), grid(99)] {
        let steps = g.len() - 1;
        for n in 1..=7 {
            let mut count = vec![0; g.len()];
            for i in 1..=n {
                let s = shard(i, n);
                let sel = s.select(&g);
                assert!(
                    sel.windows(2).all(|w| w[1] == w[0] + n),
                    "{s} of {steps}: {sel:?}"
                );
                assert!(sel.iter().all(|&j| s.contains(j)), "{s}: {sel:?}");
                for j in sel {
                    count[j] += 1;
                }
            }
            assert!(
                count.iter().all(|&c| c == 1),
                "{n} shards of {} points: counts {count:?}",
                g.len()
            );
        }
    }
    // Shard 1 starts at index 0 (1-based shard, 0-based points).
    assert_eq!(shard(1, 3).select(&grid(7)), [0, 3, 6]);
    assert_eq!(shard(3, 3).select(&grid(7)), [2, 5]);
}

#[test]
fn resume_after_an_interruption_loses_and_doubles_nothing() {
    let g = grid(40);
    let mut parts = Vec::new();
    for i in 1..=3 {
        let s = shard(i, 3);
        // First run: "killed" after 4 points were written to the partial file.
        let mut partial: Vec<SweepPoint<f64>> = Vec::new();
        let first = run_points(&g, &s.select(&g), compute, |p: &SweepPoint<f64>| {
            if partial.len() == 4 {
                return Err(AnalysisError::InvalidInput {
                    what: "test",
                    reason: "interrupted".into(),
                });
            }
            partial.push(p.clone());
            Ok(())
        });
        assert!(
            matches!(&first, Err(AnalysisError::InvalidInput { reason, .. }) if reason == "interrupted"),
            "shard {s}: {first:?}"
        );
        assert_eq!(partial.len(), 4, "shard {s}: points in the partial file");

        // Resume: the finished indices come back from the partial file.
        let finished: Vec<usize> = partial.iter().map(|p| p.index).collect();
        let left = match remaining(&g, Some(&s), &finished) {
            Ok(l) => l,
            Err(e) => panic!("shard {s}: {e}"),
        };
        assert_eq!(
            left.len() + finished.len(),
            s.select(&g).len(),
            "shard {s}: left {left:?}, finished {finished:?}"
        );
        let mut appended = partial.clone();
        let second = run_points(&g, &left, compute, |p: &SweepPoint<f64>| {
            appended.push(p.clone());
            Ok::<(), AnalysisError>(())
        });
        let Ok(second) = second else {
            panic!("shard {s}: {second:?}");
        };
        assert_eq!(second.len(), left.len());
        assert_eq!(
            appended.len(),
            s.select(&g).len(),
            "shard {s}: points after resume"
        );
        // Nothing left to do.
        let done: Vec<usize> = appended.iter().map(|p| p.index).collect();
        assert_eq!(
            remaining(&g, Some(&s), &done).ok(),
            Some(vec![]),
            "shard {s}"
        );
        parts.push(appended);
    }
    let merged = match merge(&g, parts) {
        Ok(m) => m,
        Err(e) => panic!("merge: {e}"),
    };
    assert_eq!(merged.len(), g.len());
    for (j, p) in merged.iter().enumerate() {
        assert_eq!(p.index, j);
        assert_eq!(Some(p.parameter), g.value(j));
        assert_eq!(p.result, compute(j, p.parameter), "point {j}");
    }
}

#[test]
fn resume_rejects_foreign_and_doubled_points() {
    let g = grid(10);
    let s = shard(2, 3);
    let e = remaining(&g, Some(&s), &[1, 3])
        .err()
        .map(|e| e.to_string());
    assert_eq!(
        e.as_deref(),
        Some(
            "resume: point 3 is not in shard 2/3 (the partial results belong to another shard or sweep)"
        )
    );
    let e = remaining(&g, Some(&s), &[1, 4, 1])
        .err()
        .map(|e| e.to_string());
    assert_eq!(
        e.as_deref(),
        Some("resume: 1 point given more than once: 1")
    );
    let e = remaining(&g, None, &[11]).err().map(|e| e.to_string());
    assert_eq!(
        e.as_deref(),
        Some("resume: point index 11 is outside the grid of 11 points (0..=10)")
    );
    assert_eq!(
        remaining(&g, None, &[0, 5, 10]).ok(),
        Some(vec![1, 2, 3, 4, 6, 7, 8, 9])
    );
}

fn points(g: &ParameterGrid, indices: &[usize]) -> Vec<SweepPoint<f64>> {
    indices
        .iter()
        .map(|&j| {
            let parameter = g.value(j).unwrap_or(f64::NAN);
            SweepPoint {
                index: j,
                parameter,
                result: compute(j, parameter),
            }
        })
        .collect()
}

#[test]
fn merge_names_missing_doubled_and_foreign_points() {
    let g = grid(8);
    let msg = |parts: Vec<Vec<SweepPoint<f64>>>| merge(&g, parts).err().map(|e| e.to_string());
    assert_eq!(
        msg(vec![points(&g, &[0, 2, 4, 6, 8]), points(&g, &[1, 5])]).as_deref(),
        Some("merge: 2 points missing: 3, 7")
    );
    assert_eq!(
        msg(vec![
            points(&g, &[0, 2, 4, 6, 8]),
            points(&g, &[1, 3, 5, 7, 2, 8])
        ])
        .as_deref(),
        Some("merge: 2 points given more than once: 2, 8")
    );
    let mut wrong = points(&g, &[1, 3, 5, 7]);
    wrong[2].parameter = 0.31e-3;
    assert_eq!(
        msg(vec![points(&g, &[0, 2, 4, 6, 8]), wrong]).as_deref(),
        Some(
            "merge: point 5 has parameter 3.1e-4 but the grid has 3.5e-4 there (results of a different sweep?)"
        )
    );
    assert_eq!(
        msg(vec![
            points(&g, &[0, 1, 2, 3, 4, 5, 6, 7, 8]),
            points(&grid(9), &[9])
        ])
        .as_deref(),
        Some("merge: point index 9 is outside the grid of 9 points (0..=8)")
    );
    // A parameter written with 10 significant digits still matches.
    let mut rounded = points(&g, &[1, 3, 5, 7]);
    rounded[0].parameter = 1.500000000e-4;
    assert!(merge(&g, vec![points(&g, &[0, 2, 4, 6, 8]), rounded]).is_ok());
}

#[test]
fn run_points_reports_in_completion_order_and_returns_grid_order() {
    // Point 0 waits until point 1 has been reported, so point 1 must complete (and be reported)
    // first; the results still come back in grid order. Two threads, so that the two points
    // run at once (a 10 s timeout turns a stuck run into a failure, not a hang).
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build();
    let Ok(pool) = pool else {
        panic!("thread pool: {pool:?}");
    };
    let g = grid(1);
    let (tx, rx) = mpsc::channel::<()>();
    let rx = std::sync::Mutex::new(rx);
    let mut order = Vec::new();
    let result = pool.install(|| {
        run_points(
            &g,
            &[1, 0],
            |j, p| {
                if j == 0 {
                    let got = rx
                        .lock()
                        .map(|rx| rx.recv_timeout(Duration::from_secs(10)).is_ok());
                    assert_eq!(
                        got.ok(),
                        Some(true),
                        "point 1 was not reported while point 0 ran"
                    );
                }
                compute(j, p)
            },
            |p: &SweepPoint<f64>| {
                order.push(p.index);
                if p.index == 1 {
                    let _ = tx.send(());
                }
                Ok::<(), AnalysisError>(())
            },
        )
    });
    let Ok(result) = result else {
        panic!("{result:?}");
    };
    assert_eq!(order, [1, 0], "order of completion");
    assert_eq!(result.iter().map(|p| p.index).collect::<Vec<_>>(), [0, 1]);
}

#[test]
fn run_points_rejects_bad_indices() {
    let g = grid(4);
    let never = |_: &SweepPoint<f64>| Ok::<(), AnalysisError>(());
    let e = run_points(&g, &[0, 5], compute, never)
        .err()
        .map(|e| e.to_string());
    assert_eq!(
        e.as_deref(),
        Some("sweep: point index 5 is outside the grid of 5 points (0..=4)")
    );
    let e = run_points(&g, &[2, 2], compute, never)
        .err()
        .map(|e| e.to_string());
    assert_eq!(e.as_deref(), Some("sweep: 1 point given more than once: 2"));
}
