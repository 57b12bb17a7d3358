//! Integrators: one [`Integrator`] trait that every method implements, a driver ([`Stepper`])
//! that adds events, restarts and limits to any of them, and output on a fixed time grid.
//!
//! The integrators see only the [`Formulation`](crate::formulation::Formulation) trait, never a
//! concrete mechanism; the driver, the event machinery and [`integrate`](fn@integrate) see a
//! method only through [`Integrator`] (stepping, error control and dense output are the
//! method's; `t_end`, `max_step`, events, restarts, sampling and the run limits are the
//! driver's). Two hand-written embedded pairs and one implicit method are available
//! ([`Method`]):
//!
//! * **DOPRI5**, the Dormand–Prince 5(4) pair \[1\] with the first-same-as-last (FSAL) property
//!   and Hairer's 4th-order continuous extension \[2, Sec. II.6\], which costs no extra
//!   right-hand-side (RHS) calls;
//! * **DOP853**, Hairer's 8(5,3) pair \[2, Sec. II.10\] with the combined 5th/3rd-order error
//!   estimate and a 7th-order continuous extension that needs 3 extra RHS calls — made only
//!   for steps that are actually interpolated (an output sample or an event root inside);
//! * **Radau5**, Radau IIA of order 5 after Hairer & Wanner's RADAU5 ([`radau5`]): implicit,
//!   L-stable, for stiff phases (sustained contact), with a cubic dense output.
//!
//! Coefficients of DOP853 are copied digit for digit from SciPy's
//! `scipy/integrate/_ivp/dop853_coefficients.py` \[3\], which transcribes Hairer's `dop853.f`.
//!
//! # Layout
//! | file | job |
//! |---|---|
//! | [`options`] | [`Method`] (the one selector of every method), [`SolverOptions`] (shared options, per-method settings) and their validation |
//! | [`integrator`] | the [`Integrator`] trait, its contract, [`ErrorWeights`] (tolerances, error-controlled components) |
//! | `methods` | the one `match` from a [`Method`] to its [`Integrator`] |
//! | [`stats`] | [`SolverStats`], the cost of a run |
//! | [`error`] | [`SolveError`] |
//! | `explicit` | `ExplicitRk<P>`: any explicit pair with Hairer's controller, FSAL, lazy dense output, stiffness test |
//! | `rk` | kernels shared by the pairs: counted RHS calls, stage sums, error scale |
//! | `dopri5`, `dop853` | tableau, one step, error norm, dense output of each pair |
//! | [`radau5`] | Radau IIA order 5: the method core and its [`Integrator`] adapter |
//! | `ida` | SUNDIALS IDA on the residual form (cargo feature `ida` only): the one `unsafe` wrapper and its [`Integrator`] adapter |
//! | `control` | step-size controller and initial step (Hairer's `hinit`) |
//! | [`stepper`] | [`Stepper`], the driver: one accepted step per call, [`Stop`] says why it stopped |
//! | `progress` | the run limits `max_wall` and the no-progress rule |
//! | [`events`] | [`EventRecord`], sign-change detection and root location on any dense output |
//! | [`dense`] | [`DenseStep`], the dense output of one step as sinks see it |
//! | [`integrate`](mod@integrate) | [`integrate`](fn@integrate): a whole run with samples on a grid, sent to a [`Sink`] (samples, events, a per-step hook) |
//!
//! # Example
//! ```
//! use linkdyn::formulation::{Formulation, FormulationError, NoStepHooks};
//! use linkdyn::solve::{integrate, Method, SolveError, SolverOptions, Sink};
//!
//! /// x'' = -x as (x, v).
//! struct Oscillator;
//! impl NoStepHooks for Oscillator {}
//!
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
pub mod dense;
mod dop853;
mod dopri5;
pub mod error;
pub mod events;
mod explicit;
#[cfg(feature = "ida")]
pub mod ida;
pub mod integrate;
pub mod integrator;
pub mod maximise;
mod methods;
pub mod options;
mod progress;
pub mod radau5;
pub mod record;
mod rk;
pub mod stats;
mod step_cut;
pub mod stepper;

#[cfg(test)]
mod order_conditions;

pub use dense::DenseStep;
pub use error::SolveError;
pub use events::EventRecord;
pub use integrate::{Sink, integrate};
pub use integrator::{Attempt, ErrorWeights, Integrator, Rejection, Start, Trial};
pub use options::{ExplicitRkSettings, IdaSettings, KinkEvents, Method, MethodInfo, SolverOptions};
pub use record::Recorder;
pub use stats::SolverStats;
pub use stepper::{Stepper, Stop};
