//! The periodic orbit of a damped linear oscillator under harmonic forcing, continued in the
//! forcing frequency through resonance, against its closed form at every point.
//!
//! x'' + 2ζω0 x' + ω0² x = (F0/m) sin(w t): the steady state of period T = 2π/w is
//! x(t) = A sin(w t − ϕ), A = (F0/m)/√((ω0² − w²)² + (2ζω0 w)²), tan ϕ = 2ζω0 w/(ω0² − w²);
//! its Floquet multipliers are exp(λT), λ = −ζω0 ± iω0√(1−ζ²) (L. Meirovitch, *Fundamentals of
//! Vibrations*, McGraw-Hill, 2001, §3.2 and §1.10). The multipliers stay inside the circle
//! (|μ| = exp(−ζω0T)) and the orbit has no contact: the branch has no special point. The
//! oscillator is a formulation of its own (`tests/common/ode.rs`), as in
//! `tests/orbit_forced_oscillator.rs`.

mod common;

use common::ode::ForcedOscillator;
use linkdyn::analysis::AnalysisError;
use linkdyn::analysis::orbit::{
    BranchEnd, ContinuationOptions, OrbitAt, OrbitFamily, continue_orbit,
};
use linkdyn::solve::{Method, SolverOptions};

const OMEGA0: f64 = ForcedOscillator::OMEGA0;
const ZETA: f64 = ForcedOscillator::ZETA;

/// The oscillator in its forcing frequency w (rad/s): section at t = 0, period 2π/w.
struct InFrequency;
impl OrbitFamily for InFrequency {
    type F = ForcedOscillator;
    fn at(&self, w: f64) -> Result<OrbitAt<ForcedOscillator>, AnalysisError> {
        Ok(OrbitAt {
            f: ForcedOscillator { w },
            t0: 0.0,
            period: std::f64::consts::TAU / w,
        })
    }
}

#[test]
fn every_point_of_the_branch_through_resonance_is_the_steady_state() {
    let solver = SolverOptions::default()
        .method(Method::Dop853)
        .rtol(1e-11)
        .atol(1e-13);
    // From w = 2.2 through resonance (ω0 = 3, where A grows 6-fold) to w = 4, from rest: the
    // first point's guess is far from the orbit.
    let options = ContinuationOptions::new(2.2, 4.0, 0.1);
    let branch = continue_orbit(&InFrequency, &[0.0, 0.0], &options, &solver)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(branch.end, BranchEnd::Reached);
    let last = branch.points.last().map_or(f64::NAN, |p| p.parameter);
    assert_eq!(last, 4.0, "the branch ends at --to exactly");
    // Steps of at most 0.1 over a range of 1.8: at least 18 steps.
    assert!(branch.points.len() >= 19, "{} points", branch.points.len());
    for pt in &branch.points {
        let w = pt.parameter;
        let (x0, v0) = ForcedOscillator { w }.steady_state();
        // The orbit to a few hundred integration tolerances of states of order 1.
        for (got, want, what) in [(pt.y0[0], x0, "x"), (pt.y0[1], v0, "v")] {
            assert!(
                (got - want).abs() < 1e-8 * (1.0 + want.abs()),
                "w = {w}: {what}(0) = {got}, steady state {want}"
            );
        }
        let period = std::f64::consts::TAU / w;
        assert!((pt.period - period).abs() < 1e-15 * period, "w = {w}");
        let radius = (-ZETA * OMEGA0 * period).exp();
        assert!(
            (pt.spectral_radius - radius).abs() < 1e-8,
            "w = {w}: |μ| = {}, exp(−ζω0T) = {radius}",
            pt.spectral_radius
        );
        assert!(pt.stable && pt.special.is_none(), "w = {w}: {pt:?}");
        assert!(pt.residual <= 1e3, "w = {w}: residual {} ε", pt.residual);
    }
    assert!(branch.unlocated.is_empty(), "{:?}", branch.unlocated);
}

#[test]
fn a_branch_needs_a_range() {
    let solver = SolverOptions::default();
    let e = continue_orbit(
        &InFrequency,
        &[0.0, 0.0],
        &ContinuationOptions::new(2.0, 2.0, 0.1),
        &solver,
    )
    .err()
    .map(|e| e.to_string());
    assert_eq!(
        e.as_deref(),
        Some("invalid to: expected a value other than from = 2 (a branch needs a range)")
    );
}
