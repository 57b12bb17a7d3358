//! A grazing located on a system whose grazing point is known in closed form: a damped linear
//! oscillator under harmonic forcing next to a one-sided elastic stop at x = d,
//!
//! ```text
//! x'' + 2ζω0 x' + ω0² x = F cos(w t) − K (x − d)·[x > d],
//! ```
//!
//! continued in the forcing amplitude F. While the motion stays clear of the stop it is the
//! linear steady state x(t) = A cos(w t − ϕ), A = F/√((ω0² − w²)² + (2ζω0 w)²) (L. Meirovitch,
//! *Fundamentals of Vibrations*, McGraw-Hill, 2001, §3.2), whose smallest gap to the stop over
//! a period is d − A: the orbit grazes the stop where A = d, at F_g = d·√((ω0² − w²)² +
//! (2ζω0 w)²), and beyond it strikes the stop once per period. The event function is the
//! penetration x − d (a contact event: its rising crossings are impacts).
//!
//! The branch from F = 0.3 to 0.7 (F_g = 0.5 here) must have one special point, a grazing at
//! F_g, and below it every point's smallest gap must be d − A — the gap's minimum inside a step,
//! located on the dense output, not the smallest gap at the step ends (which would be off by
//! ~(w h)²/8 of A for steps h).

mod common;

use common::branch::the_one_special_point;
use linkdyn::analysis::AnalysisError;
use linkdyn::analysis::orbit::{
    ContinuationOptions, OrbitAt, OrbitFamily, OrbitOptions, SpecialKind, continue_orbit,
    periodic_orbit,
};
use linkdyn::formulation::{Crossing, EventResponse, Formulation, FormulationError, NoStepHooks};
use linkdyn::solve::{Method, SolverOptions};

const OMEGA0: f64 = 3.0;
const ZETA: f64 = 0.1;
const W: f64 = 2.0;
const GAP: f64 = 0.1;
/// Stop stiffness (1/s²): a stiff stop, 1000 ω0².
const STOP: f64 = 9000.0;

/// |ω0² − w² + 2iζω0 w|: A = F/this.
fn impedance() -> f64 {
    (OMEGA0 * OMEGA0 - W * W).hypot(2.0 * ZETA * OMEGA0 * W)
}

#[derive(Clone)]
struct OscillatorAtAStop {
    force: f64,
}

impl NoStepHooks for OscillatorAtAStop {}
impl Formulation for OscillatorAtAStop {
    fn n_states(&self) -> usize {
        2
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![0.0, 0.0]
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        let stop = if y[0] > GAP { STOP * (y[0] - GAP) } else { 0.0 };
        dy[0] = y[1];
        dy[1] = -OMEGA0 * OMEGA0 * y[0] - 2.0 * ZETA * OMEGA0 * y[1] + self.force * (W * t).cos()
            - stop;
        Ok(())
    }
    fn jacobian(
        &self,
        _t: f64,
        y: &[f64],
        _f_y: &[f64],
        out: &mut [f64],
        _work: &mut [f64],
    ) -> Result<usize, FormulationError> {
        let stop = if y[0] > GAP { STOP } else { 0.0 };
        out.copy_from_slice(&[0.0, 1.0, -OMEGA0 * OMEGA0 - stop, -2.0 * ZETA * OMEGA0]);
        Ok(0)
    }
    fn n_events(&self) -> usize {
        1
    }
    /// The penetration into the stop (m).
    fn events(&self, _t: f64, y: &[f64], g: &mut [f64]) {
        g[0] = y[0] - GAP;
    }
    /// The force law changes at the stop: the integration restarts there (and the shot
    /// records the crossing, an impact when rising).
    fn apply_event(
        &mut self,
        _t: f64,
        _y: &mut [f64],
        _index: usize,
        _crossing: Crossing,
    ) -> EventResponse {
        EventResponse::Restart
    }
}

struct InForce;
impl OrbitFamily for InForce {
    type F = OscillatorAtAStop;
    fn at(&self, force: f64) -> Result<OrbitAt<OscillatorAtAStop>, AnalysisError> {
        Ok(OrbitAt {
            f: OscillatorAtAStop { force },
            t0: 0.0,
            period: std::f64::consts::TAU / W,
        })
    }
    fn contact_events(&self) -> usize {
        1
    }
}

#[test]
fn the_orbit_grazes_the_stop_where_its_amplitude_reaches_the_gap() {
    let solver = SolverOptions::default()
        .method(Method::Dop853)
        .rtol(1e-11)
        .atol(1e-13);
    let f_g = GAP * impedance();
    let b = continue_orbit(
        &InForce,
        &[0.0, 0.0],
        &ContinuationOptions::new(0.3, 0.7, 0.05),
        &solver,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let located = the_one_special_point(&b, SpecialKind::Grazing);
    assert!(
        ((located - f_g) / f_g).abs() < 1e-6,
        "grazing at F = {located}, closed form {f_g}"
    );
    for p in b.points.iter().filter(|p| p.special.is_none()) {
        let force = p.parameter;
        let gap = p.min_gap.unwrap_or(f64::NAN);
        if force < f_g {
            // Clear of the stop: the linear steady state, its gap d − A.
            let amplitude = force / impedance();
            assert!(
                (gap - (GAP - amplitude)).abs() < 1e-9,
                "F = {force}: smallest gap {gap}, closed form {}",
                GAP - amplitude
            );
            assert_eq!(p.impacts_per_period, 0, "F = {force}");
        } else {
            assert!(gap < 0.0, "F = {force}: smallest gap {gap}");
            assert_eq!(p.impacts_per_period, 1, "F = {force}");
        }
        assert!(p.stable, "F = {force}: {:?}", p.multipliers);
    }
}

/// One orbit found by shooting (`linkdyn orbit`'s path) locates its smallest gap the same way:
/// clear of the stop it is d − A, where the gap at the step ends alone is larger; unwatched, no
/// gap is reported.
#[test]
fn a_shot_orbit_locates_its_smallest_gap_inside_the_steps() {
    let solver = SolverOptions::default()
        .method(Method::Dop853)
        .rtol(1e-11)
        .atol(1e-13);
    let force = 0.4;
    let f = OscillatorAtAStop { force };
    let period = std::f64::consts::TAU / W;
    // The steady state at t = 0: x = A cos ϕ, x' = A w sin ϕ, tan ϕ = 2ζω0w/(ω0² − w²).
    let amplitude = force / impedance();
    let phase = (2.0 * ZETA * OMEGA0 * W).atan2(OMEGA0 * OMEGA0 - W * W);
    let guess = [0.9 * amplitude * phase.cos(), amplitude * W * phase.sin()];
    let watched = OrbitOptions {
        watched_gaps: 1,
        ..OrbitOptions::new(period)
    };
    let orbit =
        periodic_orbit(&f, 0.0, &guess, &watched, &solver).unwrap_or_else(|e| panic!("{e}"));
    let gap = orbit.min_gap.unwrap_or(f64::NAN);
    assert!(
        (gap - (GAP - amplitude)).abs() < 1e-9,
        "smallest gap {gap}, closed form {}",
        GAP - amplitude
    );
    assert!(
        (orbit.y0[0] - amplitude * phase.cos()).abs() < 1e-9,
        "x(0) = {}, closed form {}",
        orbit.y0[0],
        amplitude * phase.cos()
    );
    let unwatched = periodic_orbit(&f, 0.0, &guess, &OrbitOptions::new(period), &solver)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(unwatched.min_gap, None);
    assert_eq!(unwatched.y0, orbit.y0, "watching changes nothing else");
}
