//! Integrators: adaptive explicit Runge–Kutta methods with dense output, event location and
//! output on a fixed time grid.
//!
//! The integrators see only the [`Formulation`](crate::formulation::Formulation) trait, never a
//! concrete mechanism. Two hand-written embedded pairs are available ([`Method`]):
//!
//! * **DOPRI5**, the Dormand–Prince 5(4) pair \[1\] with the first-same-as-last (FSAL) property
//!   and Hairer's 4th-order continuous extension \[2, Sec. II.6\], which costs no extra
//!   right-hand-side (RHS) calls;
//! * **DOP853**, Hairer's 8(5,3) pair \[2, Sec. II.10\] with the combined 5th/3rd-order error
//!   estimate and a 7th-order continuous extension that needs 3 extra RHS calls — made only
//!   for steps that are actually interpolated (an output sample or an event root inside).
//!
//! Coefficients of DOP853 are copied digit for digit from SciPy's
//! `scipy/integrate/_ivp/dop853_coefficients.py` \[3\], which transcribes Hairer's `dop853.f`.
//!
//! # Layout
//! | file | job |
//! |---|---|
//! | [`options`] | [`Method`], [`SolverOptions`] and their validation |
//! | [`stats`] | [`SolverStats`], the cost of a run |
//! | [`error`] | [`SolveError`] |
//! | `rk` | kernels shared by both methods: counted RHS calls, stage sums, error scale |
//! | `dopri5`, `dop853` | tableaus, one step, error norm, dense output of each method |
//! | `control` | step-size controller and initial step (Hairer's `hinit`) |
//! | [`stepper`] | [`Stepper`]: one accepted step per call, [`Stop`] says why it stopped |
//! | [`events`] | [`EventRecord`], sign-change detection and root location on the dense output |
//! | [`integrate`](mod@integrate) | [`integrate`](fn@integrate): a whole run with samples on a grid, sent to a [`Sink`] |
//!
//! # Example
//! ```
//! use linkdyn::formulation::{Formulation, FormulationError};
//! use linkdyn::solve::{integrate, Method, SolveError, SolverOptions, Sink};
//!
//! /// x'' = -x as (x, v).
//! struct Oscillator;
//! impl Formulation for Oscillator {
//!     fn n_states(&self) -> usize { 2 }
//!     fn initial_state(&self) -> Vec<f64> { vec![1.0, 0.0] }
//!     fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
//!         dy[0] = y[1];
//!         dy[1] = -y[0];
//!         Ok(())
//!     }
//! }
//!
//! struct Last(f64, Vec<f64>);
//! impl<F> Sink<F> for Last {
//!     fn sample(&mut self, _f: &F, t: f64, y: &[f64]) -> Result<(), SolveError> {
//!         self.0 = t;
//!         self.1 = y.to_vec();
//!         Ok(())
//!     }
//! }
//!
//! let opts = SolverOptions::default().method(Method::Dopri5).rtol(1e-9).build()?;
//! let mut sink = Last(0.0, Vec::new());
//! let stats = integrate(&mut Oscillator, 0.0, &[1.0, 0.0], 1.0, 0.1, &opts, &mut sink)?;
//! assert_eq!(sink.0, 1.0);
//! assert!((sink.1[0] - 1f64.cos()).abs() < 1e-8);
//! assert!(stats.steps > 0);
//! # Ok::<(), SolveError>(())
//! ```
//!
//! # References
//! 1. J. R. Dormand, P. J. Prince, "A family of embedded Runge–Kutta formulae", *Journal of
//!    Computational and Applied Mathematics* 6(1), 19–26, 1980.
//! 2. E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary Differential Equations I:
//!    Nonstiff Problems*, 2nd ed., Springer, 1993 (Sec. II.4 step-size control and `hinit`,
//!    II.6 dense output, II.10 DOP853; codes `dopri5.f`, `dop853.f`).
//! 3. P. Virtanen et al., "SciPy 1.0: fundamental algorithms for scientific computing in
//!    Python", *Nature Methods* 17, 261–272, 2020; files `scipy/integrate/_ivp/rk.py` and
//!    `dop853_coefficients.py`.

mod control;
mod dop853;
mod dopri5;
pub mod error;
pub mod events;
pub mod integrate;
pub mod options;
pub mod radau5;
pub mod record;
mod rk;
pub mod stats;
pub mod stepper;

#[cfg(test)]
mod order_conditions;

pub use error::SolveError;
pub use events::EventRecord;
pub use integrate::{Sink, integrate};
pub use options::{Method, SolverOptions};
pub use record::Recorder;
pub use stats::SolverStats;
pub use stepper::{Stepper, Stop};
