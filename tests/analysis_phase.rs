//! The phase portrait of a sine is an ellipse (`linkdyn::analysis::phase`).

use std::f64::consts::PI;

use linkdyn::analysis::phase::{RateSource, phase_portrait};

const A: f64 = 0.3;
const OMEGA: f64 = 2.0 * PI * 1.5;

/// Samples of x = A sin(ωt) and ẋ = Aω cos(ωt), `per_period` samples per period over 3 periods.
fn sine(per_period: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let h = 2.0 * PI / OMEGA / per_period as f64;
    let t: Vec<f64> = (0..=3 * per_period).map(|i| i as f64 * h).collect();
    let x = t.iter().map(|t| A * (OMEGA * t).sin()).collect();
    let v = t.iter().map(|t| A * OMEGA * (OMEGA * t).cos()).collect();
    (t, x, v)
}

/// max |(x/A)² + (ẋ/(Aω))² − 1| over the points.
fn off_ellipse(x: &[f64], v: &[f64]) -> f64 {
    x.iter()
        .zip(v)
        .map(|(x, v)| ((x / A).powi(2) + (v / (A * OMEGA)).powi(2) - 1.0).abs())
        .fold(0.0, f64::max)
}

#[test]
fn rate_column_gives_the_exact_ellipse() {
    let (t, x, v) = sine(50);
    let p = phase_portrait(&t, &x, Some(&v)).map_err(|e| e.to_string());
    let Ok(p) = p else {
        panic!("{p:?}");
    };
    assert_eq!(p.source, RateSource::Column);
    let off = off_ellipse(&p.value, &p.rate);
    assert!(off < 1e-14, "rate column: off the ellipse by {off}");
}

#[test]
fn central_differences_give_the_ellipse_to_second_order() {
    // Relative rate error ≤ (ωh)²/3 (one-sided ends), so the ellipse residual
    // (x/A)² + (ẋ/(Aω))² − 1 is ≤ 2·(ωh)²/3 + its square. Halving h must divide it by ≈ 4.
    let mut previous = f64::NAN;
    for per_period in [40, 80, 160] {
        let (t, x, _) = sine(per_period);
        let p = phase_portrait(&t, &x, None).map_err(|e| e.to_string());
        let Ok(p) = p else {
            panic!("{per_period} per period: {p:?}");
        };
        assert_eq!(p.source, RateSource::CentralDifference);
        let wh = 2.0 * PI / per_period as f64;
        let bound = 2.0 * wh * wh / 3.0 + (wh * wh / 3.0).powi(2);
        let off = off_ellipse(&p.value, &p.rate);
        assert!(
            off <= bound,
            "{per_period} samples per period: off the ellipse by {off} (bound {bound})"
        );
        if previous.is_finite() {
            let ratio = previous / off;
            assert!(
                (3.5..4.5).contains(&ratio),
                "{per_period} samples per period: error ratio {ratio} for h/2, expected ≈ 4 (second order)"
            );
        }
        previous = off;
    }
}

#[test]
fn finite_differences_need_a_uniform_grid_and_three_samples() {
    let e = phase_portrait(&[0.0, 1.0], &[0.0, 1.0], None)
        .err()
        .map(|e| e.to_string());
    assert_eq!(
        e.as_deref(),
        Some("phase portrait (rate by finite differences): 2 samples, at least 3 needed")
    );
    let e = phase_portrait(&[0.0, 1.0, 1.5, 3.0], &[0.0; 4], None)
        .err()
        .map(|e| e.to_string());
    assert_eq!(
        e.as_deref(),
        Some(
            "invalid t: finite-difference rates need a uniform grid, but t[2] = 1.5 s is off the grid t0 + i·h (h = 1 s) by -5.000e-1 s; pass the rate column instead"
        )
    );
    // With the rate column a non-uniform grid is fine.
    assert!(phase_portrait(&[0.0, 1.0, 1.5], &[0.0; 3], Some(&[1.0; 3])).is_ok());
    let e = phase_portrait(&[0.0, 1.0], &[0.0, 1.0], Some(&[1.0]))
        .err()
        .map(|e| e.to_string());
    assert_eq!(
        e.as_deref(),
        Some("invalid rate: t has 2 samples but the rate has 1")
    );
}
