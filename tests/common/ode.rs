//! Reference problems and a recording sink shared by the integration tests.

use linkdyn::formulation::{Formulation, FormulationError, NoStepHooks};
use linkdyn::solve::{EventRecord, Sink, SolveError};

/// Harmonic oscillator x'' = −ω² x as (x, v), x(0) = 1, v(0) = 0: x = cos ωt, v = −ω sin ωt.
pub struct Oscillator {
    /// Angular frequency ω (rad/s).
    pub omega: f64,
}

impl Oscillator {
    /// Exact state at t.
    pub fn exact(&self, t: f64) -> [f64; 2] {
        let w = self.omega;
        [(w * t).cos(), -w * (w * t).sin()]
    }
}

impl NoStepHooks for Oscillator {}

impl Formulation for Oscillator {
    fn n_states(&self) -> usize {
        2
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![1.0, 0.0]
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        dy[0] = y[1];
        dy[1] = -self.omega * self.omega * y[0];
        Ok(())
    }
}

/// Damped linear oscillator under harmonic forcing, x'' + 2ζω0 x' + ω0² x = (F0/m) sin(w t), as
/// (x, v) from rest, with its analytic Jacobian (ω0 = 3 rad/s, ζ = 0.05, F0/m = 2 m/s²): the
/// periodic-orbit tests' reference (`tests/orbit_forced_oscillator.rs`,
/// `tests/continuation_forced_oscillator.rs`, whose headers give the closed forms' sources).
#[derive(Clone)]
pub struct ForcedOscillator {
    /// Forcing frequency w (rad/s).
    pub w: f64,
}

impl ForcedOscillator {
    /// Natural frequency ω0 (rad/s).
    pub const OMEGA0: f64 = 3.0;
    /// Damping ratio ζ.
    pub const ZETA: f64 = 0.05;
    /// Forcing amplitude F0/m (m/s²).
    pub const FORCE: f64 = 2.0;

    /// (x(0), v(0)) of the steady state x(t) = A sin(w t − ϕ), A = (F0/m)/√((ω0² − w²)² +
    /// (2ζω0 w)²), tan ϕ = 2ζω0 w/(ω0² − w²).
    pub fn steady_state(&self) -> (f64, f64) {
        let (w, omega0) = (self.w, Self::OMEGA0);
        let d = omega0 * omega0 - w * w;
        let c = 2.0 * Self::ZETA * omega0 * w;
        let amplitude = Self::FORCE / d.hypot(c);
        let lag = c.atan2(d);
        (-amplitude * lag.sin(), amplitude * w * lag.cos())
    }
}

impl NoStepHooks for ForcedOscillator {}

impl Formulation for ForcedOscillator {
    fn n_states(&self) -> usize {
        2
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![0.0, 0.0]
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        let (omega0, zeta) = (Self::OMEGA0, Self::ZETA);
        dy[0] = y[1];
        dy[1] =
            -omega0 * omega0 * y[0] - 2.0 * zeta * omega0 * y[1] + Self::FORCE * (self.w * t).sin();
        Ok(())
    }
    fn jacobian(
        &self,
        _t: f64,
        _y: &[f64],
        _f_y: &[f64],
        out: &mut [f64],
        _work: &mut [f64],
    ) -> Result<usize, FormulationError> {
        let (omega0, zeta) = (Self::OMEGA0, Self::ZETA);
        out.copy_from_slice(&[0.0, 1.0, -omega0 * omega0, -2.0 * zeta * omega0]);
        Ok(0)
    }
}

/// Non-autonomous, nonlinear in t: y' = y cos t, y(0) = 1, exact y = exp(sin t).
pub struct ExpSin;

impl ExpSin {
    /// Exact solution at t.
    pub fn exact(t: f64) -> f64 {
        t.sin().exp()
    }
}

impl NoStepHooks for ExpSin {}

impl Formulation for ExpSin {
    fn n_states(&self) -> usize {
        1
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![1.0]
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        dy[0] = y[0] * t.cos();
        Ok(())
    }
}

/// Keeps everything it is sent.
#[derive(Default)]
pub struct OdeRecorder {
    pub samples: Vec<(f64, Vec<f64>)>,
    pub events: Vec<(EventRecord, Vec<f64>, Vec<f64>)>,
}

impl<F> Sink<F> for OdeRecorder {
    fn sample(&mut self, _f: &F, t: f64, y: &[f64]) -> Result<(), SolveError> {
        self.samples.push((t, y.to_vec()));
        Ok(())
    }
    fn event(
        &mut self,
        _f: &F,
        ev: &EventRecord,
        before: &[f64],
        after: &[f64],
    ) -> Result<(), SolveError> {
        self.events.push((*ev, before.to_vec(), after.to_vec()));
        Ok(())
    }
}

/// Least-squares slope of log(err) against log(h): the observed order.
pub fn observed_order(h: &[f64], err: &[f64]) -> f64 {
    let x: Vec<f64> = h.iter().map(|v| v.ln()).collect();
    let y: Vec<f64> = err.iter().map(|v| v.ln()).collect();
    let n = x.len() as f64;
    let mx = x.iter().sum::<f64>() / n;
    let my = y.iter().sum::<f64>() / n;
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}
