//! Double pendulum: energy conservation over 10 s, and constraint drift bounded with Baumgarte
//! stabilisation but growing without it.

mod common;
use common::*;
use linkdyn::solve::Method;

#[test]
fn energy_is_conserved_over_ten_seconds() {
    let model = load("models/double_pendulum.toml", &[]);
    let (rec, _) = run_dae(&model, 10.0, 1e-2, Method::Dop853, 1e-12, 1e-14);
    let e = mechanical_energy(&model, &rec);
    // Relative to |E0| = 1.04 J (released from rest: all potential).
    let drift = e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max) / e[0].abs();
    assert!(
        drift < 1e-8,
        "energy drift {drift:e} relative over 10 s (E0 = {} J)",
        e[0]
    );
}

/// Largest |Φ| over the samples in [t_from, t_to).
fn max_violation(rec: &linkdyn::solve::Recorder, t_from: f64, t_to: f64) -> f64 {
    rec.t
        .iter()
        .zip(&rec.violation)
        .filter(|(t, _)| **t >= t_from && **t < t_to)
        .map(|(_, v)| *v)
        .fold(0.0, f64::max)
}

#[test]
fn baumgarte_bounds_the_drift_that_grows_without_it() {
    // A loose tolerance makes the truncation error, and so the drift, visible.
    let (rtol, atol) = (1e-5, 1e-7);
    let free = load(
        "models/double_pendulum.toml",
        &["settings.baumgarte.alpha=0", "settings.baumgarte.beta=0"],
    );
    let (rec_free, _) = run_dae(&free, 20.0, 1e-2, Method::Dopri5, rtol, atol);
    let early = max_violation(&rec_free, 0.0, 2.0);
    let late = max_violation(&rec_free, 18.0, 20.001);
    // Without stabilisation the error integrates up: at least 10× more at 18–20 s than at 0–2 s.
    assert!(
        late > 10.0 * early,
        "unstabilised drift did not grow: {early:e} early, {late:e} late"
    );

    let stabilised = load("models/double_pendulum.toml", &[]);
    let (rec_bg, _) = run_dae(&stabilised, 20.0, 1e-2, Method::Dopri5, rtol, atol);
    let early_bg = max_violation(&rec_bg, 0.0, 2.0);
    let late_bg = max_violation(&rec_bg, 18.0, 20.001);
    // With Baumgarte the error stays at the level of the local truncation error: bounded, not
    // growing (within a factor 10 of its early level) and far below the unstabilised drift.
    assert!(
        late_bg < 10.0 * early_bg.max(1e-12),
        "stabilised drift grew: {early_bg:e} early, {late_bg:e} late"
    );
    assert!(
        late_bg < late / 10.0,
        "stabilised {late_bg:e} vs unstabilised {late:e} at 18–20 s"
    );
}
