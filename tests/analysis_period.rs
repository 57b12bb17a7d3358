//! Period verdicts on Poincaré sequences built to have a known period
//! (`linkdyn::analysis::period`).

use std::f64::consts::PI;

use linkdyn::analysis::AnalysisError;
use linkdyn::analysis::period::{PeriodOptions, PeriodVerdict, period_verdict};

/// A fixed absolute tolerance (tol_rel = 0) so that the noise amplitudes below are exact
/// fractions of it.
const TOL: f64 = 1e-6;

fn opts(k_max: usize, m: usize) -> PeriodOptions {
    PeriodOptions {
        k_max,
        m,
        tol_rel: 0.0,
        tol_abs: TOL,
    }
}

/// Points cycling through `cycle` (2-D), plus deterministic noise `noise(i)` on both
/// components.
fn cycle_points(cycle: &[[f64; 2]], n: usize, noise: impl Fn(usize) -> f64) -> Vec<Vec<f64>> {
    (0..n)
        .map(|i| {
            let c = cycle[i % cycle.len()];
            vec![c[0] + noise(i), c[1] - noise(i)]
        })
        .collect()
}

const PERIOD_3: [[f64; 2]; 3] = [[0.1, -2.0], [0.7, 1.0], [-0.4, 0.3]];

fn verdict(points: &[Vec<f64>], o: &PeriodOptions) -> PeriodVerdict {
    match period_verdict(points, o) {
        Ok(a) => a.verdict,
        Err(e) => panic!("{e}"),
    }
}

#[test]
fn period_3_with_noise_below_the_tolerance() {
    // |noise| ≤ 0.45·TOL, so differences between points three periods apart are ≤ 0.9·TOL.
    let points = cycle_points(&PERIOD_3, 100, |i| 0.45 * TOL * (2.3 * i as f64).sin());
    let v = verdict(&points, &opts(10, 30));
    assert!(
        matches!(v, PeriodVerdict::Period { k: 3, mismatch } if mismatch <= 0.9),
        "period-3 with noise 0.45 tol: {v:?}"
    );
    assert_eq!(v.to_string(), "period-3");
}

#[test]
fn period_3_with_noise_above_the_tolerance_is_not_period_3() {
    // Alternating ±0.6·TOL: points three periods apart differ by 1.2·TOL. The noise has period
    // 2, so the sequence is exactly period-6; with k_max = 5 no period is found, and the closest
    // is k = 3 at mismatch 1.2.
    let points = cycle_points(&PERIOD_3, 100, |i| {
        0.6 * TOL * if i % 2 == 0 { 1.0 } else { -1.0 }
    });
    let v = verdict(&points, &opts(5, 30));
    assert!(
        matches!(v, PeriodVerdict::NoPeriod { k_max: 5, closest_k: 3, mismatch } if (mismatch - 1.2).abs() < 1e-6),
        "period-3 with noise 0.6 tol, k_max 5: {v:?}"
    );
    assert_eq!(v.to_string(), "no period found up to k_max = 5");
    let v = verdict(&points, &opts(8, 30));
    assert!(
        matches!(v, PeriodVerdict::Period { k: 6, .. }),
        "period-3 with period-2 noise, k_max 8: {v:?}"
    );
}

#[test]
fn fixed_point_is_period_1() {
    let points = cycle_points(&[[0.25, 3.0]], 50, |i| 0.4 * TOL * (i as f64).cos());
    let v = verdict(&points, &opts(10, 20));
    assert!(matches!(v, PeriodVerdict::Period { k: 1, .. }), "{v:?}");
}

#[test]
fn irrational_rotation_has_no_period() {
    // Rotation by the golden ratio's fractional part α: the closest return within k ≤ 20 is
    // k = 13 (|13α − 8| ≈ 0.034 turns, a chord of ≈ 0.21 on the unit circle), far above any
    // tolerance, and the relative tolerance (1e-4 of the spread 2) is 2e-4.
    let alpha = (5f64.sqrt() - 1.0) / 2.0;
    let points: Vec<Vec<f64>> = (0..200)
        .map(|i| {
            let a = 2.0 * PI * alpha * i as f64;
            vec![a.cos(), a.sin()]
        })
        .collect();
    let o = PeriodOptions {
        k_max: 20,
        m: 50,
        tol_rel: 1e-4,
        tol_abs: 1e-9,
    };
    let v = verdict(&points, &o);
    assert!(
        matches!(v, PeriodVerdict::NoPeriod { k_max: 20, closest_k: 13, mismatch } if mismatch > 100.0),
        "quasi-periodic rotation: {v:?}"
    );
}

#[test]
fn tolerance_follows_the_spread_of_the_data() {
    // The same period-3 orbit in other units (×1e6) with noise scaled alike: the relative
    // tolerance scales with it, so the verdict is unchanged.
    for scale in [1.0, 1e6] {
        let points: Vec<Vec<f64>> = cycle_points(&PERIOD_3, 60, |i| 1e-5 * (i as f64).sin())
            .into_iter()
            .map(|p| p.into_iter().map(|v| v * scale).collect())
            .collect();
        let o = PeriodOptions {
            k_max: 6,
            m: 20,
            tol_rel: 1e-4,
            tol_abs: 1e-12,
        };
        let a = period_verdict(&points, &o).map_err(|e| e.to_string());
        let Ok(a) = a else {
            panic!("scale {scale}: {a:?}");
        };
        assert!(
            matches!(a.verdict, PeriodVerdict::Period { k: 3, .. }),
            "scale {scale}: {:?}",
            a.verdict
        );
        // Spread of component 0 is 1.1 (+ noise ≤ 2e-5): tol = 1e-12 + 1e-4·1.1·scale.
        let expected = 1e-12 + 1.1e-4 * scale;
        assert!(
            (a.tolerance[0] - expected).abs() < 3e-9 * scale,
            "scale {scale}: tol {} vs {expected}",
            a.tolerance[0]
        );
    }
}

#[test]
fn settling_needs_m_plus_k_max_points() {
    let o = opts(4, 10);
    let points = cycle_points(&PERIOD_3, 14, |_| 0.0);
    let v = verdict(&points, &o);
    assert!(
        matches!(v, PeriodVerdict::Period { k: 3, .. }),
        "exactly m + k_max = 14 points: {v:?}"
    );
    let v = verdict(&points[1..], &o);
    assert_eq!(
        v,
        PeriodVerdict::NotSettled {
            points: 13,
            needed: 14
        }
    );
    assert_eq!(v.to_string(), "not settled: 13 points, 14 needed");
    assert_eq!(
        verdict(&[], &o),
        PeriodVerdict::NotSettled {
            points: 0,
            needed: 14
        }
    );
    // Period 3 with k_max = 2: nothing found.
    let v = verdict(&points, &opts(2, 10));
    assert!(
        matches!(v, PeriodVerdict::NoPeriod { k_max: 2, .. }),
        "period-3 with k_max 2: {v:?}"
    );
}

#[test]
fn only_the_last_points_are_judged() {
    // A transient of 40 wandering points, then a fixed point: period-1 once m + k_max trailing
    // points are settled.
    let mut points: Vec<Vec<f64>> = (0..40).map(|i| vec![(i as f64).sin(), 0.0]).collect();
    points.extend(std::iter::repeat_n(vec![0.5, 0.5], 15));
    assert!(matches!(
        verdict(&points, &opts(5, 10)),
        PeriodVerdict::Period { k: 1, .. }
    ));
    // Only 9 fixed points after the transient with m = 10: the judged points include a
    // transient one, and no period is found.
    let v = verdict(&points[..49], &opts(5, 10));
    assert!(
        matches!(v, PeriodVerdict::NoPeriod { .. }),
        "transient inside the last m points: {v:?}"
    );
}

#[test]
fn bad_inputs_are_errors() {
    let pts = vec![vec![0.0, 1.0], vec![0.0]];
    let e = period_verdict(&pts, &opts(2, 2))
        .err()
        .map(|e| e.to_string());
    assert_eq!(
        e.as_deref(),
        Some("invalid points: point 1 has 1 components but point 0 has 2")
    );
    let pts = vec![vec![0.0, 1.0], vec![0.0, f64::NAN]];
    let e = period_verdict(&pts, &opts(2, 2)).err();
    assert!(
        matches!(e, Some(AnalysisError::NonFinite { index: 1, .. })),
        "{e:?}"
    );
    let e = period_verdict(&[], &opts(0, 2))
        .err()
        .map(|e| e.to_string());
    assert_eq!(
        e.as_deref(),
        Some("invalid k_max: expected a largest period ≥ 1, got 0")
    );
    let o = PeriodOptions {
        tol_rel: 0.0,
        tol_abs: 0.0,
        ..PeriodOptions::default()
    };
    assert!(period_verdict(&[], &o).is_err(), "zero tolerance accepted");
}
